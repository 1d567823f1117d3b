//! Tests of the command line and the commands' texts.

use super::*;
use crate::report::answer::{Answer, Choice};
use clap::{CommandFactory, ValueEnum};
use std::time::Duration;
use wedged::patterns::{PatternMethod, PatternSettings};
use wedged::{CriticalProgress, Method, Problem, Progress, Settings, Stop};
use wedged_cli::one_line;
use wedged_cli::progress::{critical_progress_text, progress_text, Pace};

#[test]
fn sizes_parse() {
    assert_eq!(parse_size("500M"), Ok(500_000_000));
    assert_eq!(parse_size("1.5GB"), Ok(1_500_000_000));
    assert_eq!(parse_size("2g"), Ok(2_000_000_000));
    assert_eq!(parse_size("1234"), Ok(1234));
    assert_eq!(parse_size("64kB"), Ok(64_000));
    for bad in ["", "G", "-1G", "lots", "0", "nanM", "1e30T"] {
        assert!(parse_size(bad).is_err(), "{bad}");
    }
}

#[test]
fn cli_is_well_formed() {
    Cli::command().debug_assert();
}

#[test]
fn method_names_are_the_library_names() {
    let names: Vec<String> = MethodArg::value_variants()
        .iter()
        .map(|m| m.to_possible_value().unwrap().get_name().to_string())
        .collect();
    let mut library: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
    library.extend(
        [
            PatternMethod::Bnb,
            PatternMethod::Pyramid { faces: 8 },
            PatternMethod::Faces,
            PatternMethod::Search,
        ]
        .map(PatternMethod::name),
    );
    assert_eq!(names, library);
}

#[test]
fn progress_lines_name_what_they_count() {
    let p = Progress {
        done: 372,
        total: 1000,
        rays: 5,
        nodes: 7065,
    };
    let bnb = Choice::Patterns(PatternSettings::default());
    assert_eq!(
        progress_text(&bnb, p, 3.42, 0.0),
        "explored 37.2% of the search tree (7065 nodes of about 19k), 5 patterns found, \
         3.4 s, about 6 s left"
    );
    let p = Progress { nodes: 70650, ..p };
    assert!(progress_text(&bnb, p, 3.42, 0.0).contains("(70650 nodes of about 190k)"));
    let search = Choice::Rays(Settings {
        method: Method::Search,
        ..Settings::default()
    });
    assert_eq!(
        progress_text(
            &search,
            Progress {
                done: 1,
                total: 1000,
                rays: 1,
                nodes: 20,
            },
            360.0,
            0.0
        ),
        "explored 0.1% of the search tree (20 nodes of about 20k), 1 contact set found, \
         360.0 s, about 99.9 h left"
    );
    assert_eq!(
        progress_text(
            &search,
            Progress {
                done: 0,
                total: 1000,
                rays: 0,
                nodes: 3,
            },
            2.0,
            0.0
        ),
        "explored 0.0% of the search tree (3 nodes), 0 contact sets found, 2.0 s"
    );
    let rays = Choice::Rays(Settings::default());
    let p = Progress {
        done: 3,
        total: 12,
        rays: 40,
        nodes: 0,
    };
    assert_eq!(
        progress_text(&rays, p, 1.0, 0.0),
        "node 3/12: 40 rays held, 1.0 s"
    );
}

/// The 2D plug at m = 100: the share stood at 95.7% from 26.6 s to 31.4 s, and then at 97.7%,
/// while the run took 62 s. The line's "about 1 s left" is refuted once the share stands still
/// for longer, and it never says 100% while the search runs.
#[test]
fn a_refuted_time_left_is_not_repeated() {
    let search = Choice::Rays(Settings {
        method: Method::Search,
        ..Settings::default()
    });
    let pace = Pace::default();
    let line = |done: usize, seconds: f64| {
        let p = Progress {
            done,
            total: 1000,
            rays: 134,
            nodes: 250795,
        };
        progress_text(
            &search,
            p,
            seconds,
            pace.still(done as f64 / 1000.0, seconds),
        )
    };
    assert!(line(957, 26.6).ends_with("26.6 s, about 1 s left"));
    assert!(line(957, 27.4).ends_with("27.4 s, about 1 s left"));
    assert!(line(957, 28.2).ends_with("28.2 s, time left unknown"));
    assert!(line(957, 31.4).ends_with("31.4 s, time left unknown"));
    // The share moves: a new estimate, until it too has stood still too long.
    assert!(line(977, 34.6).ends_with("34.6 s, under 1 s left"));
    assert!(line(977, 36.2).ends_with("36.2 s, time left unknown"));
    // 99.96% is not shown as 100.0%.
    let p = Progress {
        done: 9996,
        total: 10000,
        rays: 645,
        nodes: 436792,
    };
    let text = progress_text(&search, p, 47.5, 0.0);
    assert!(
        text.starts_with("explored 99.9% of the search tree"),
        "{text}"
    );
    let critical = CriticalProgress {
        explored: 0.99996,
        ..CriticalProgress::default()
    };
    assert!(critical_progress_text(critical, 3.0).starts_with("explored 99.9%,"));
}

#[test]
fn incomplete_pattern_runs_say_why_without_node_counts() {
    use wedged::patterns::{PatternInfo, Patterns, Undecided};
    let problem = Problem::new(3, nalgebra::DMatrix::identity(6, 6), 1.0).unwrap();
    let mut result = Patterns {
        outcome: wedged::Outcome::Incomplete(Stop::Undecided),
        patterns: Vec::new(),
        undecided: vec![Undecided {
            contact: vec![true, false],
            reason: "stalled".to_string(),
        }],
        info: PatternInfo::default(),
        certificate: None,
        shard: None,
    };
    let choice = Choice::Patterns(PatternSettings::default());
    let text = incomplete_text(
        "p.toml",
        &problem,
        &choice,
        &Answer::Patterns(result.clone()),
        Stop::Undecided,
    );
    assert_eq!(
        text,
        "p.toml: the solver could not decide some contact sets (1 undecided, listed in the \
         summary and the JSON); the patterns below them may be missing, so the result is \
         incomplete"
    );
    result.undecided.clear();
    let stop = Stop::TimeLimit(Duration::from_secs(2));
    let text = incomplete_text("p.toml", &problem, &choice, &Answer::Patterns(result), stop);
    assert_eq!(
        text,
        "p.toml: the time limit of 2 s ran out with 0 maximal patterns found so far; the \
         result is incomplete"
    );
}

#[test]
fn critical_progress_names_the_best_mu() {
    let p = CriticalProgress {
        explored: 0.372,
        upper: Some(1.23456),
        nodes: 0,
        bar: None,
        lower: None,
        condensed: None,
        programs: 0,
    };
    assert_eq!(
        critical_progress_text(p, 3.42),
        "explored 37.2%, best mu 1.235, 3.4 s"
    );
    let p = CriticalProgress {
        nodes: 7065,
        bar: Some(2.5),
        ..p
    };
    assert_eq!(
        critical_progress_text(p, 3.42),
        "pass at mu <= 2.5: explored 37.2% (7065 nodes of about 19k), best mu 1.235, 3.4 s"
    );
    // After a finished pass: the bracket proved so far (sig4 rounds to nearest: a progress
    // line, not the certified answer).
    let p = CriticalProgress {
        lower: Some(1.2),
        ..p
    };
    assert_eq!(
        critical_progress_text(p, 3.42),
        "pass at mu <= 2.5: explored 37.2% (7065 nodes of about 19k), mu* in (1.2, 1.235], 3.4 s"
    );
    let p = CriticalProgress::default();
    assert_eq!(
        critical_progress_text(p, 1.0),
        "explored 0.0%, no wedged configuration yet, 1.0 s"
    );
    let p = CriticalProgress {
        lower: Some(0.5),
        ..p
    };
    assert_eq!(
        critical_progress_text(p, 1.0),
        "explored 0.0%, no wedged configuration yet, mu* > 0.5, 1.0 s"
    );
    // The start's run on the condensed problem says so.
    let p = CriticalProgress {
        explored: 0.5,
        upper: Some(1.8),
        nodes: 40,
        bar: Some(2.0),
        lower: None,
        condensed: Some(200),
        programs: 0,
    };
    assert_eq!(
        critical_progress_text(p, 2.0),
        "start, condensed onto 200 nodes: pass at mu <= 2: explored 50.0% (40 nodes of about \
         80), best mu 1.8, 2.0 s"
    );
    // The programs solved so far, which move while the root settles its bounds.
    let p = CriticalProgress {
        explored: 0.0,
        nodes: 1,
        condensed: None,
        programs: 15468,
        ..p
    };
    assert_eq!(
        critical_progress_text(p, 9.0),
        "pass at mu <= 2: explored 0.0% (1 nodes, 15468 linear programs), best mu 1.8, 9.0 s"
    );
    let p = CriticalProgress { nodes: 0, ..p };
    assert_eq!(
        critical_progress_text(p, 9.0),
        "pass at mu <= 2: explored 0.0% (15468 linear programs), best mu 1.8, 9.0 s"
    );
}

#[test]
fn critical_method_names_are_the_library_names() {
    let names: Vec<String> = CriticalMethodArg::value_variants()
        .iter()
        .map(|m| m.to_possible_value().unwrap().get_name().to_string())
        .collect();
    assert_eq!(names, ["bnb", "enumerate", "faces"]);
}

#[test]
fn one_line_joins_lines() {
    assert_eq!(one_line("a\n  b\n\nc "), "a; b; c");
}

#[test]
fn the_incomplete_line_of_a_ray_method_follows_the_method_as_the_summary_does() {
    use wedged::rays::{Enumeration, Info};
    let problem = Problem::new(2, nalgebra::DMatrix::identity(6, 6), 1.0).unwrap();
    let stop = Stop::TimeLimit(Duration::from_secs(2));
    // Stopped before its first node: a double description still says how far it came, and a
    // method that does not go node by node says what it checked.
    let result = Enumeration {
        outcome: wedged::Outcome::Incomplete(stop),
        rays: Vec::new(),
        cones: Vec::new(),
        info: Info::default(),
    };
    let answer = Answer::Rays(result);
    let dd = Choice::Rays(Settings {
        method: Method::PrunedDd,
        ..Settings::default()
    });
    let search = Choice::Rays(Settings {
        method: Method::Search,
        ..Settings::default()
    });
    assert_eq!(
        incomplete_text("p.toml", &problem, &dd, &answer, stop),
        "p.toml: the time limit of 2 s ran out after 0 of 3 nodes; the result is incomplete"
    );
    assert_eq!(
        incomplete_text("p.toml", &problem, &search, &answer, stop),
        "p.toml: the time limit of 2 s ran out with 0 wedged configurations found so far \
         (checked); the result is incomplete"
    );
}
