//! The tests of `condensed.rs`.

use super::*;
use crate::examples::{plug2d_tri, random_spd_problem};

/// On the 2D plug the strongest couplings are a node's neighbours along its side: about every
/// other node is kept, no two neighbours, and every dropped node has a kept neighbour.
#[test]
fn the_plug_keeps_about_every_other_node_of_each_side() {
    let model = plug2d_tri(40).unwrap();
    let problem = model.problem(2.0).unwrap();
    let m = problem.nodes();
    assert_eq!(m, 80);
    let kept = keep(&problem);
    assert!(kept.windows(2).all(|w| w[0] < w[1]));
    assert!((m / 3..=m / 2 + 2).contains(&kept.len()), "{}", kept.len());
    let mesh = model.mesh();
    let nodes = &model.boundary().contact_nodes;
    let at = |i: usize| mesh.coords()[nodes[i]];
    let distance = |i: usize, j: usize| {
        let (a, b) = (at(i), at(j));
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
    };
    // The spacing along a side: the plug's side is sqrt(1.25) long, in 40 divisions.
    let h = 1.25f64.sqrt() / 40.0;
    for i in (0..m).filter(|i| kept.binary_search(i).is_err()) {
        let nearest = kept
            .iter()
            .map(|&j| distance(i, j))
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1.01 * h,
            "node {i}: the nearest kept node at {nearest}"
        );
    }
    for (a, &i) in kept.iter().enumerate() {
        for &j in &kept[a + 1..] {
            assert!(distance(i, j) > 1.5 * h, "kept {i} and {j}");
        }
    }
}

/// The condensed stiffness is that of the kept nodes with the others free: the inverse of the
/// compliance's block on them (a different route to the same matrix).
#[test]
fn the_condensed_stiffness_inverts_the_compliance_block() {
    for seed in 0..5 {
        let problem = random_spd_problem(12, 1.0, seed);
        let kept = [0, 3, 4, 7, 11];
        let (s, _) = condense(&problem, &kept).unwrap();
        let g = problem.compliance();
        let dofs: Vec<usize> = kept.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect();
        let block = DMatrix::from_fn(dofs.len(), dofs.len(), |i, j| g[(dofs[i], dofs[j])]);
        let inverse = block.try_inverse().unwrap();
        let scale = inverse.norm();
        assert!((&s - &inverse).norm() <= 1e-10 * scale, "seed {seed}");
        assert_eq!(s, s.transpose());
    }
    let problem = random_spd_problem(4, 1.0, 0);
    assert!(condense(&problem, &[0, 1, 2, 3]).is_none());
}

/// A kept node takes the condensed answer; a dropped one is in contact where the condensed
/// wedge moves it onto the obstacle or into it (`u_d = -K_dd^-1 K_dk u_k`, normal part <= 0).
#[test]
fn the_start_spreads_by_the_dropped_nodes_displacements() {
    let kept = [0, 2];
    // Kept nodes 0 and 2 (u_k = (1, 0), (2, 0)); dropped node 1 follows their mean into the
    // obstacle (-1.5), node 3 moves away (+1) and node 4 stays on it (0, within round-off).
    let follow = DMatrix::from_row_slice(
        6,
        4,
        &[
            0.5, 0.0, 0.5, 0.0, //
            0.0, 0.0, 0.0, 0.0, //
            -1.0, 0.0, 0.0, 0.0, //
            0.0, 0.0, 0.0, 0.0, //
            1e-12, 0.0, 0.0, 0.0, //
            0.0, 0.0, 0.0, 0.0,
        ],
    );
    let u_k = [1.0, 0.3, 2.0, -0.7];
    let start = spread(2, &kept, &[true, false], &u_k, &follow);
    assert_eq!(start, [true, true, false, false, true]);
}

/// Only `bnb` with no start, not certified, not a shard, from the sizes named.
#[test]
fn it_applies_to_large_searches_with_no_start() {
    let large = random_spd_problem(CONDENSE_FROM, 2.0, 1);
    let small = random_spd_problem(CONDENSE_FROM - 1, 2.0, 1);
    let plain = CriticalSettings::default();
    assert!(applies(&large, &plain));
    assert!(!applies(&small, &plain));
    let three = crate::examples::random_spd_problem_dim(3, CONDENSE_FROM_3D, 2.0, 1);
    assert!(applies(&three, &plain));
    let off = [
        CriticalSettings {
            condense: false,
            ..plain.clone()
        },
        CriticalSettings {
            certify: true,
            ..plain.clone()
        },
        CriticalSettings {
            method: CriticalMethod::Faces,
            ..plain.clone()
        },
        CriticalSettings {
            start: Some(vec![true; CONDENSE_FROM]),
            ..plain.clone()
        },
        CriticalSettings {
            shard: Some(crate::Shard::parse("1/2").unwrap()),
            ..plain.clone()
        },
    ];
    for settings in off {
        assert!(!applies(&large, &settings), "{settings:?}");
    }
}

/// The condensed run's progress reaches the caller marked with the condensed problem's nodes,
/// all of it before the run proper's (unmarked) reports, which end the run. The run proper's
/// programs grow to the count its summary gives.
#[test]
fn the_start_reports_its_progress_marked() {
    let problem = plug2d_tri(40).unwrap().problem(2.0).unwrap();
    let kept = keep(&problem).len();
    let seen = std::sync::Mutex::new(Vec::new());
    let programs = std::sync::Mutex::new(Vec::new());
    let record = |p: CriticalProgress| {
        seen.lock().unwrap().push(p.condensed);
        if p.condensed.is_none() {
            programs.lock().unwrap().push(p.programs);
        }
    };
    let result = critical_with_control(
        &problem,
        &CriticalSettings::default(),
        &record,
        &AtomicBool::new(false),
    )
    .unwrap();
    assert!(result.mu_critical.is_some());
    let seen = seen.into_inner().unwrap();
    let marked = seen.iter().take_while(|c| c.is_some()).count();
    assert!(marked > 0, "{seen:?}");
    assert!(seen[..marked].iter().all(|&c| c == Some(kept)), "{seen:?}");
    assert!(marked < seen.len(), "{seen:?}");
    assert!(seen[marked..].iter().all(Option::is_none), "{seen:?}");
    let programs = programs.into_inner().unwrap();
    assert!(programs.windows(2).all(|w| w[0] <= w[1]), "{programs:?}");
    assert_eq!(programs.last(), Some(&result.info.simplex_solves));
    assert!(result.info.simplex_solves > 0);
}
