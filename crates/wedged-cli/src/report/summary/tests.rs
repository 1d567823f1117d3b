//! Tests of `summary.rs`.

use super::*;
use wedged::Info;

#[test]
fn ranges_shorten_runs() {
    assert_eq!(ranges(&[]), "");
    assert_eq!(ranges(&[4]), "4");
    assert_eq!(ranges(&[0, 1, 2, 3, 7, 9, 10]), "0-3 7 9 10");
}

/// A made-up result with many nodes and rays: the layout only, not the mathematics.
#[test]
fn many_nodes_and_rays_are_compact_and_cut() {
    use wedged::{Cone, Ray};
    let m = 12;
    let problem = Problem::new(2, nalgebra::DMatrix::identity(2 * m, 2 * m), 1.0).unwrap();
    let all = [
        NodeStatus::Separated,
        NodeStatus::Stick,
        NodeStatus::SlipPlus,
        NodeStatus::SlipMinus,
        NodeStatus::Grazing,
    ];
    let rays: Vec<Ray> = (0..60)
        .map(|k| Ray {
            u: (0..2 * m).map(|i| (i + k) as f64 * 1e-3).collect(),
            r: vec![0.0; 2 * m],
            status: (0..m).map(|i| all[(i + k) % 5]).collect(),
        })
        .collect();
    let cones = vec![Cone {
        rays: vec![0, 1, 2, 7],
        pattern: vec![ContactPattern::Contact; m],
    }];
    let result = Enumeration {
        outcome: Outcome::Wedged,
        rays,
        cones,
        info: Info {
            rays_after_node: (0..30).collect(),
            ..Info::default()
        },
    };
    let text = render(
        &problem,
        &Choice::Rays(wedged::Settings::default()),
        "big.toml",
        &Answer::Rays(result),
        None,
    );
    assert!(text.contains("60 wedged configurations"), "{text}");
    assert!(
        text.contains("\n   0   2.000e-2  os+-gos+-g os\n"),
        "{text}"
    );
    assert!(text.contains("... and 10 more rays"), "{text}");
    assert!(text.contains(STATUS_LEGEND), "{text}");
    assert!(text.contains("  0  CCCCCCCCCC CC  0-2 7"), "{text}");
    assert!(text.contains("(10 more in --json)"), "{text}");
    assert!(text.lines().all(|l| l.len() < 120), "{text}");
}

#[test]
fn codes_group_by_ten() {
    assert_eq!(codes("abcdefghijkl".chars()), "abcdefghij kl");
}

/// A made-up 3D pattern run with undecided contact sets: the layout only.
fn undecided_run() -> (Problem, Patterns) {
    use wedged::patterns::{Pattern, PatternInfo, Undecided};
    let m = 12;
    let problem = Problem::new(3, nalgebra::DMatrix::identity(3 * m, 3 * m), 1.0).unwrap();
    let mut status = vec![NodeStatus::Stick; m];
    status[1] = NodeStatus::Slip;
    status[2] = NodeStatus::Separated;
    status[11] = NodeStatus::Grazing;
    let pattern = status.iter().map(|&s| ContactPattern::of(s)).collect();
    let mut u = vec![0.0; 3 * m];
    u[6] = 0.25;
    let result = Patterns {
        outcome: Outcome::Incomplete(Stop::Undecided),
        patterns: vec![Pattern {
            pattern,
            status,
            u,
            r: vec![0.0; 3 * m],
            margin: 0.0125,
        }],
        undecided: vec![
            Undecided {
                contact: (0..m).map(|i| i < 3 || i == 7).collect(),
                reason: "the solver stalled\ntwice".to_string(),
            },
            Undecided {
                contact: vec![false; m],
                reason: "no progress".to_string(),
            },
        ],
        info: PatternInfo {
            nodes_visited: 100,
            pruned_infeasible: 20,
            pruned_unpressed: 30,
            leaves: 27,
            socps: 400,
            retries: 3,
            uncertain: 2,
            near_degenerate: 1,
            realised: 5,
            seconds: 1.5,
            ..PatternInfo::default()
        },
        certificate: None,
        shard: None,
    };
    (problem, result)
}

#[test]
fn undecided_contact_sets_are_warned_about() {
    let (problem, result) = undecided_run();
    let choice = Choice::Patterns(wedged::patterns::PatternSettings::default());
    let text = render(&problem, &choice, "p.toml", &Answer::Patterns(result), None);
    assert!(
        text.contains("INCOMPLETE: the solver could not decide some contact sets"),
        "{text}"
    );
    assert!(
        text.contains(
            "WARNING: the solver could not decide the contact set {nodes 1-3 8} (the solver \
             stalled; twice); the patterns below it may be missing\n"
        ),
        "{text}"
    );
    assert!(text.contains("{no node} (no progress)"), "{text}");
    // The row: index, widest gap, margin, statuses in groups of ten; the 3D legend.
    assert!(
        text.contains("  0   2.500e-1   1.250e-2  s~osssssss sg\n"),
        "{text}"
    );
    assert!(text.contains(STATUS_LEGEND_3D), "{text}");
    assert!(text.contains("nodes 1-12, in groups of ten"), "{text}");
    // The diagnostics: 1 - (100 + 27) / (2^13 - 1).
    assert!(text.contains("pruned fraction 0.9845"), "{text}");
    assert!(text.contains("8191 nodes of the full tree"), "{text}");
    assert!(text.contains("27 leaves reached of 2^12 = 4096"), "{text}");
    assert!(
        text.contains("400 SOCPs solved (3 retried, 2 undecided, 1 near-degenerate decision)"),
        "{text}"
    );
    // Only the outcome and the warnings are long lines (one each, for grep).
    assert!(
        text.lines()
            .all(|l| l.len() <= WRAP || l.starts_with("WARNING") || l.starts_with("INCOMPLETE")),
        "{text}"
    );
}

#[test]
fn a_stopped_pattern_run_claims_no_pruning() {
    let (problem, mut result) = undecided_run();
    result.outcome = Outcome::Incomplete(Stop::Interrupted);
    result.undecided.clear();
    let choice = Choice::Patterns(wedged::patterns::PatternSettings::default());
    let answer = Answer::Patterns(result);
    let text = render(&problem, &choice, "p.toml", &answer, None);
    assert!(
        text.contains("INCOMPLETE: the run was interrupted"),
        "{text}"
    );
    assert!(text.contains("may not all be maximal"), "{text}");
    assert!(text.contains("the search stopped before the end"), "{text}");
    assert!(!text.contains("pruned fraction"), "{text}");
    let dir = Path::new("/tmp/out");
    let files = files(&answer, Some(dir), None, &[]);
    assert!(
        files.contains("the run is incomplete, so no .vtu file"),
        "{files}"
    );
}

#[test]
fn pruned_fraction_and_powers() {
    assert_eq!(pruned_fraction(2, 3, 4), 0.0);
    assert!((pruned_fraction(3, 3, 1) - (1.0 - 4.0 / 15.0)).abs() < 1e-15);
    assert_eq!(power_of_two(6, 0), "64");
    assert_eq!(power_of_two(7, 1), "127");
    assert_eq!(power_of_two(49, 1), "5.629e14");
}

#[test]
fn wrapping_keeps_words_and_indents() {
    let mut out = String::new();
    let long = "word ".repeat(40);
    wrapped(&mut out, 2, 4, &long);
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines.len() > 1);
    assert!(lines[0].starts_with("  word") && lines[1].starts_with("    word"));
    assert!(lines.iter().all(|l| l.len() <= WRAP));
    assert_eq!(out.split_whitespace().count(), 40);
}
