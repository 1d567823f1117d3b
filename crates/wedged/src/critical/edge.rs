//! A leaf met on the edge of its threshold.
//!
//! `critical`'s `bnb` tests each leaf at the level `min(bar, incumbent (1 - tol))`. The best
//! leaf, met again there, lies within the solver's resolution of the level: the solver calls
//! its program feasible, but the point is feasible only within tolerances and cannot be made an
//! exact solution ([`Ctx::exact_point`]). Such a leaf is decided from a little above instead.

use super::Ctx;
use crate::conic::program::{leaf_classes, Decision, Goal, Norm};

/// An exact point of the leaf of `set` from a little above `level` (`1e-7` to `1e-4`
/// relative), for a leaf whose solver point at `level` could not be made exact: a leaf whose
/// threshold lies within the solver's resolution of the level (the best leaf, met again at
/// `incumbent (1 - tol)`) has a point there that is feasible only within tolerances. Its
/// threshold, computed from the point above, then decides it: refuted at the level
/// (certified), or a leaf with its own bracket. (On the 2D plug at m = 100 with shallower
/// tightening, the best leaf came out undecided this way and the run incomplete.)
pub(super) fn point_above(ctx: &Ctx, set: &[bool], level: f64) -> Option<(f64, Vec<f64>)> {
    let classes = leaf_classes(set);
    (1..=4).find_map(|k| {
        let at = level * (1.0 + 10f64.powi(k - 8));
        match ctx.form.decide_at(&classes, at, Norm::Sum, Goal::Feasible) {
            Decision::Yes { r, .. } => ctx.exact_point(set, &r, at),
            _ => None,
        }
    })
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::AtomicBool;

    use super::*;
    use crate::conic::program::Formulation;
    use crate::critical::improve::tests::{ctx, set, threshold};
    use crate::examples::random_spd_problem_dim;
    use crate::run::{Control, Limits};

    /// Every leaf of small random 2D and 3D problems, met just below its threshold `theta`
    /// (bisection on its cone program): the point from above is an exact solution of the leaf
    /// (contact gaps closed, the rest open, no pull, `sum r_n = 1`) whose ratio lies between
    /// `theta` and the highest level tried, and the threshold computed from it refutes the
    /// leaf at the level or brackets `theta`.
    #[test]
    fn a_leaf_just_below_its_threshold_is_decided_from_above() {
        const CAP: f64 = 20.0;
        let cancel = AtomicBool::new(false);
        let control = Control::new(Limits::default(), &cancel);
        let (mut leaves, mut refuted) = (0, 0);
        for case in 0..16u64 {
            let dim = 2 + (case % 2) as usize;
            let m = 2 + (case % 4) as usize;
            let problem = random_spd_problem_dim(dim, m, 1.0, 700 + case);
            let form = Formulation::new(&problem);
            let ctx = ctx(&form);
            for mask in 1..1usize << m {
                let contact = set(mask, m);
                let Some(theta) = threshold(&form, &contact, CAP) else {
                    continue;
                };
                let what = format!("case {case} (dim {dim}, m {m}), set {mask:b}, theta {theta}");
                let level = theta * (1.0 - 1e-9);
                let Some((t, p)) = point_above(&ctx, &contact, level) else {
                    panic!("{what}: no exact point from above");
                };
                leaves += 1;
                assert!(t >= theta * (1.0 - 1e-6), "{what}: ratio {t} below it");
                assert!(
                    t <= level * (1.0 + 1e-4) * (1.0 + 1e-6),
                    "{what}: ratio {t}"
                );
                let total: f64 = (0..m).map(|i| p[dim * i]).sum();
                assert!((total - 1.0).abs() <= 1e-12, "{what}: sum r_n = {total}");
                for i in 0..m {
                    let gap = form.gap_of(&p, i);
                    if contact[i] {
                        // (A negligible pressure is dropped: `r = 0`, the gap still closed.)
                        assert!(gap.abs() <= 1e-9, "{what}: node {i}'s gap {gap}");
                        assert!(p[dim * i] >= 0.0, "{what}: node {i} pulls");
                    } else {
                        assert!(gap >= -1e-12, "{what}: node {i}'s gap {gap}");
                        assert!(p[dim * i..dim * i + dim].iter().all(|&x| x == 0.0));
                    }
                }
                match ctx.leaf_threshold(&contact, t, p, &control, &|| level) {
                    Ok(None) => refuted += 1,
                    Ok(Some(leaf)) => assert!(
                        leaf.lower <= theta * (1.0 + 1e-6) && leaf.theta >= theta * (1.0 - 1e-6),
                        "{what}: [{}, {}]",
                        leaf.lower,
                        leaf.theta
                    ),
                    Err(why) => panic!("{what}: {why}"),
                }
            }
        }
        // (Seen: 67 of 173 refuted at the level, the others brackets of `tol` holding theta.)
        assert!(
            leaves >= 100 && refuted >= 30,
            "{refuted} of {leaves} refuted"
        );
    }
}
