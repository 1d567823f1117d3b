//! A large problem given no start begins `bnb` from the answer of the problem condensed onto
//! about half its nodes (`critical/condensed.rs`): the bracket is the one the search finds from
//! scratch, also after the nodes are renumbered, tangents flipped and nodes rescaled (the start
//! may change, the bracket may not), and a time limit is named as given.

use nalgebra::DMatrix;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wedged::examples::{node_scaled, plug2d_tri, plug3d};
use wedged::{critical, Critical, CriticalSettings, CriticalStatus, Problem, Stop};

fn run(problem: &Problem, condense: bool) -> Critical {
    let settings = CriticalSettings {
        condense,
        ..CriticalSettings::default()
    };
    critical(problem, &settings).expect("the run")
}

/// The same `mu*`: each upper end within the other's bracket.
fn assert_same(a: &Critical, b: &Critical, what: &str) {
    assert_eq!(a.status, CriticalStatus::Wedged, "{what}");
    assert_eq!(b.status, CriticalStatus::Wedged, "{what}");
    let (ua, ub) = (a.upper.unwrap(), b.upper.unwrap());
    let width = a.info.tol_achieved.max(b.info.tol_achieved) + 1e-9;
    assert!(
        (ua - ub).abs() <= width * ua.max(ub),
        "{what}: {ua} against {ub}"
    );
}

/// `problem` with its nodes in `order`, the tangents of the nodes in `flip` reversed, and
/// node `i` scaled by `scales[i]`.
fn transformed(problem: &Problem, order: &[usize], flip: &[bool], scales: &[f64]) -> Problem {
    let d = problem.dim();
    let permuted = problem.permuted(order);
    let n = permuted.stiffness().nrows();
    let sign = DMatrix::from_fn(n, n, |i, j| {
        if i != j {
            0.0
        } else if i % d != 0 && flip[i / d] {
            -1.0
        } else {
            1.0
        }
    });
    let flipped = Problem::new(d, &sign * permuted.stiffness() * &sign, problem.mu()).unwrap();
    node_scaled(&flipped, scales)
}

#[test]
fn the_2d_plug_gives_its_bracket_from_the_condensed_start() {
    let problem = plug2d_tri(40).unwrap().problem(2.0).unwrap();
    let m = problem.nodes();
    let started = run(&problem, true);
    let scratch = run(&problem, false);
    assert_same(&started, &scratch, "2D plug, m = 80");
    let nodes = started.info.condensed_nodes as usize;
    assert!(
        (m / 3..=m / 2 + 2).contains(&nodes),
        "{nodes} condensed nodes"
    );
    assert!(started.info.condensed_mu.is_some());
    assert!(started.info.condensed_seconds > 0.0);
    assert_eq!(
        started.info.dive_nodes, 0,
        "the condensed start replaces the dive"
    );
    assert_eq!(scratch.info.condensed_nodes, 0);
    assert!(scratch.info.dive_nodes > 0);

    let mut rng = ChaCha8Rng::seed_from_u64(2080);
    for trial in 0..2 {
        let mut order: Vec<usize> = (0..m).collect();
        order.shuffle(&mut rng);
        let flip: Vec<bool> = (0..m).map(|_| rng.gen_bool(0.5)).collect();
        let scales: Vec<f64> = (0..m).map(|_| 2f64.powi(rng.gen_range(-20..=20))).collect();
        let other = run(&transformed(&problem, &order, &flip, &scales), true);
        assert!(other.info.condensed_nodes > 0, "trial {trial}");
        assert_same(&other, &scratch, &format!("2D plug, transformed {trial}"));
    }
}

#[test]
fn the_3d_plug_gives_its_bracket_from_the_condensed_start() {
    let problem = plug3d(4, 4).unwrap().problem(2.0).unwrap();
    assert_eq!(problem.nodes(), 40);
    let started = run(&problem, true);
    assert!(started.info.condensed_nodes > 0);
    assert_same(&started, &run(&problem, false), "3D V-groove, m = 40");
}

/// A run stopped by its time limit names the limit given, although the condensed run used
/// part of it.
#[test]
fn a_time_limit_is_named_as_given() {
    let problem = plug2d_tri(40).unwrap().problem(2.0).unwrap();
    let limit = std::time::Duration::from_millis(150);
    let mut settings = CriticalSettings::default();
    settings.limits.time_limit = Some(limit);
    let c = critical(&problem, &settings).unwrap();
    assert_eq!(c.status, CriticalStatus::Incomplete(Stop::TimeLimit(limit)));
}
