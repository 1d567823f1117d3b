//! The contact-set search (`Method::Search`) against the seed's pruned double description on
//! seeded random problems, and its invariances: renumbered nodes, flipped tangents, nodes
//! rescaled by factors from `2^-20` to `2^20`. (`tests/agreement.rs` also runs it beside
//! every other method on its families.)

mod common;

use common::random_spd;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wedged::{enumerate, Enumeration, Method, NodeStatus, Outcome, Problem, Settings};

fn run(problem: &Problem, method: Method) -> Enumeration {
    let e = enumerate(
        problem,
        &Settings {
            method,
            ..Settings::default()
        },
    )
    .unwrap_or_else(|e| panic!("{method} failed: {e}\nK = {}", problem.stiffness()));
    assert!(
        !matches!(e.outcome, Outcome::Incomplete(_)),
        "{method} incomplete: {:?}",
        e.info.search_undecided_faces
    );
    e
}

fn statuses(e: &Enumeration) -> Vec<Vec<NodeStatus>> {
    e.rays.iter().map(|r| r.status.clone()).collect()
}

#[test]
fn search_agrees_with_pruned_dd_on_300_random_instances() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let (mut wedged, mut rays, mut cones) = (0, 0, 0);
    for trial in 0..300 {
        let m = 2 + trial % 8;
        let mu = [0.5, 1.0, 1.5, 2.0, 3.0][trial % 5] * rng.gen_range(0.8..1.25);
        let p = Problem::new(2, random_spd(&mut rng, 2 * m), mu).unwrap();
        let a = run(&p, Method::PrunedDd);
        let b = run(&p, Method::Search);
        let what = format!("trial {trial} (m = {m}, mu = {mu})");
        assert_eq!(a.outcome, b.outcome, "{what}");
        assert_eq!(statuses(&a), statuses(&b), "{what}: rays differ");
        assert_eq!(a.cones, b.cones, "{what}: cones differ");
        if b.outcome == Outcome::Wedged {
            wedged += 1;
            // Every cone is the face of some leaf, so there are at least as many leaves.
            assert!(b.info.search_leaves as usize >= b.cones.len(), "{what}");
        }
        rays += b.rays.len();
        cones += b.cones.len();
    }
    // The family must exercise both outcomes and many pieces, or the test proves little.
    assert!(wedged > 100 && wedged < 300, "wedged in {wedged} of 300");
    assert!(
        rays > 1000 && cones > 300,
        "{rays} rays, {cones} cones in all"
    );
}

/// `T K T` for `T` = a node permutation (new node `a` is old node `order[a]`), a sign per node
/// on the tangent, and a power of two per node.
fn transformed(k: &DMatrix<f64>, order: &[usize], flip: &[bool], scale: &[f64]) -> DMatrix<f64> {
    let n = k.nrows();
    let mut t = DMatrix::<f64>::zeros(n, n);
    for (new, &old) in order.iter().enumerate() {
        t[(2 * new, 2 * old)] = scale[new];
        t[(2 * new + 1, 2 * old + 1)] = if flip[new] { -scale[new] } else { scale[new] };
    }
    &t * k * t.transpose()
}

#[test]
fn search_is_invariant_under_renumbering_flips_and_node_scales() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    for trial in 0..60 {
        let m = 2 + trial % 6;
        let k = random_spd(&mut rng, 2 * m);
        let mu = rng.gen_range(0.5..3.0);
        let base = run(&Problem::new(2, k.clone(), mu).unwrap(), Method::Search);
        let mut order: Vec<usize> = (0..m).collect();
        for i in (1..m).rev() {
            order.swap(i, rng.gen_range(0..=i));
        }
        let flip: Vec<bool> = (0..m).map(|_| rng.gen_bool(0.5)).collect();
        let scale: Vec<f64> = (0..m).map(|_| 2f64.powi(rng.gen_range(-20..=20))).collect();
        let whole = 2f64.powi(rng.gen_range(-30..=30));
        let k2 = transformed(&k, &order, &flip, &scale) * whole;
        let e = run(&Problem::new(2, k2, mu).unwrap(), Method::Search);
        // Map the transformed answer back: node `new` is old `order[new]`, slips flip with
        // the tangent.
        let mut mapped: Vec<Vec<NodeStatus>> = e
            .rays
            .iter()
            .map(|ray| {
                let mut s = vec![NodeStatus::Grazing; m];
                for (new, &old) in order.iter().enumerate() {
                    s[old] = match (ray.status[new], flip[new]) {
                        (NodeStatus::SlipPlus, true) => NodeStatus::SlipMinus,
                        (NodeStatus::SlipMinus, true) => NodeStatus::SlipPlus,
                        (st, _) => st,
                    };
                }
                s
            })
            .collect();
        mapped.sort();
        assert_eq!(
            statuses(&base),
            mapped,
            "trial {trial}: m = {m}, order {order:?}, flips {flip:?}, scales {scale:?}"
        );
        assert_eq!(base.cones.len(), e.cones.len(), "trial {trial}");
    }
}
