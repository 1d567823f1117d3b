//! Cuts for the searches over contact sets (`critical`'s `bnb`, the enumeration's `rays/search`)
//! from bounds on the drive of the undecided nodes.
//!
//! The relaxation of a search node lets an undecided node press with its gap open, and on a
//! long wall many nodes can each do so: the bound then bites only deep in the tree. These
//! cuts make each undecided node pay for it.
//!
//! Node `j`'s **drive** is the gap that the other reactions open at it:
//! `w_j = u_n_j - c_j r_n_j`, with `c_j = C_{n_j n_j} > 0` its own normal compliance (in the
//! scaled gap units of [`super::program`]). In every solution either `r_n_j = 0`
//! (then `u_n_j = w_j >= 0`) or `u_n_j = 0` (then `c_j r_n_j = -w_j`), so
//!
//! ```text
//! c_j r_n_j = max(0, -w_j).
//! ```
//!
//! The right-hand side is convex in `w_j`, so on an interval `[L s, U s]` that holds `w_j`
//! (`s = sum r_n`) it lies below its secant. With `L < 0 < U` that is the homogeneous cut
//!
//! ```text
//! c_j (U - L) r_n_j <= -L (U s - w_j),
//! ```
//!
//! which forbids pressing hard with a large drive. With `L >= 0` the node cannot press
//! (`r_n_j <= 0`); with `U <= 0` its gap cannot open (`u_n_j <= 0`). The relaxation keeps
//! `u_n_j >= 0` and `r_n_j >= 0`, the convex lower side.
//!
//! `L` and `U` come from **bound tightening**, two linear programs per undecided node over the
//! relaxation of the search node (normalised by `s = 1`, the cuts known so far included), each
//! with the node's own complementarity imposed ([`tighten`]): `L` the least drive with its gap
//! closed (`u_n_j = 0`, so `w_j = -c_j r_n_j <= 0`), `U` the greatest with its pressure zero
//! (`r_n_j = 0`, so `w_j = u_n_j >= 0`), each widened by [`MARGIN`]. In every solution the
//! node is one or the other, and the other side's drives lie on the far side of zero, so `[L,
//! U]` holds every solution's drive; where one side is infeasible, the node is always the
//! other (`L = 0`: it never presses; `U = 0`: its gap never opens). Every solution of a
//! subtree at a friction coefficient up to the node's lies in that relaxation, so the bounds,
//! and the cuts, hold for the whole subtree at every lower level. (Over the relaxation
//! without the node's complementarity, the extremes are often at points that both press the
//! node and open its gap; imposing it settled the 2D plug's root at `mu*` in 40 parts instead
//! of 66 at m = 100.)
//!
//! The cuts are checked in floating point only (the solver's optima behind them are), so a
//! certified run (`--certify`) does not use them: its every prune is a plain refutation that
//! is checked exactly (see [`crate::critical::certify`]).

use rayon::prelude::*;

use crate::conic::program::{Class, Decision, Formulation};

/// Bounds `(L, U)` on each node's drive per unit of total pressure (infinite when unknown).
pub(crate) type Drive = Vec<(f64, f64)>;

/// Each bound from the solver is widened by this much, relative to `1 + sum_k |w_k r_k|` (the
/// terms of the drive at the optimum: drives are of order one in the scaled units, and the
/// optimality check of [`super::socp`] bounds the error of an optimal value by `1e-7` of its
/// terms plus `1e-8` normwise).
const MARGIN: f64 = 1e-5;

/// Node `j`'s drive as a row over the reactions: its scaled gap row without its own normal
/// entry.
fn drive_row(form: &Formulation, j: usize) -> Vec<f64> {
    let mut w = form.gap_row(j).to_vec();
    w[form.dim * j] = 0.0;
    w
}

/// Whether bounds `(lo, hi)` on a drive give a cut ([`row`]): both finite, not crossed.
pub(crate) fn has_row(lo: f64, hi: f64) -> bool {
    lo.is_finite() && hi.is_finite() && lo <= hi
}

/// The cut (a row `a` of `a . r >= 0` over all reaction components) that bounds `(lo, hi)` on
/// node `j`'s drive give, `None` when they give none (not both finite, or crossed).
pub(crate) fn row(form: &Formulation, j: usize, lo: f64, hi: f64) -> Option<Vec<f64>> {
    if !has_row(lo, hi) {
        return None;
    }
    let d = form.dim;
    let mut row = vec![0.0; d * form.m];
    if lo >= 0.0 {
        // -r_n_j >= 0.
        row[d * j] = -1.0;
    } else if hi <= 0.0 {
        // -u_n_j >= 0.
        row.iter_mut()
            .zip(form.gap_row(j))
            .for_each(|(a, g)| *a = -g);
    } else {
        // -L U s + L w_j - c_j (U - L) r_n_j >= 0.
        let c = form.gap_row(j)[d * j];
        for (a, w) in row.iter_mut().zip(drive_row(form, j)) {
            *a = lo * w;
        }
        for k in 0..form.m {
            row[d * k] -= lo * hi;
        }
        row[d * j] -= c * (hi - lo);
    }
    Some(row)
}

/// The depth down to which the 3D searches' nodes tighten the drive bounds (nodes at depths
/// below it, or at it for `critical`'s `bnb`): deeper than in 2D, since a 3D tree is far wider
/// (measured on the 3D V-groove plug with the 12-gon relaxation, whole process: m = 20,
/// `enumerate` at 1.2 `mu*`, depths 3, 5, 7, 9: 6.5, 3.6, 3.7, 4.7 s (42k, 26k, 16k, 11k
/// nodes); `critical` (8-gon) depths 4, 6, 8, 10: 1.7, 1.5, 1.9, 2.5 s; m = 40, `critical`,
/// 8-gon, depth 4: 2.0M nodes, 635 s, depth 10: 525k nodes, 533 s; 12-gon, depth 8: 235k
/// nodes, 514 s, depth 10 with leaves screened: not finished in 900 s; all four on a machine
/// shared with other runs for part of the time).
pub(crate) fn tighten_depth_3d(m: usize) -> usize {
    (m / 5).max(5)
}

/// The depth down to which the patterns' 3D `bnb` tightens the drive bounds: twice
/// [`tighten_depth_3d`] (`critical`'s), since its nodes' programs have grown cheaper while a
/// tightened node's subtree shrinks as before. (Measured on the 3D V-groove plug at 1.2 `mu*`,
/// `enumerate`, whole process: m = 20, depths 5, 6, 8, 10, 12: 0.66, 0.55, 0.50, 0.57, 0.88 s
/// (12.8k, 10.2k, 6.8k, 5.3k, 4.9k nodes); m = 30, depths 3, 6, 9, 12, 15, 18, 22: 16.7, 12.8,
/// 10.0, 9.1, 9.5, 11.2, 13.6 s (246k, 163k, 116k, 82k, 69k, 65k, 63k nodes); m = 40, depths 8,
/// 16, 20: 283, 181 to 197, 201 s (2.11M, 1.12M, 1.03M nodes); BENCHMARKS.md.)
pub(crate) fn enumeration_depth_3d(m: usize) -> usize {
    (2 * m / 5).max(5)
}

/// The solver of [`tighten`]'s programs: `(key, classes, objective)` to the least value.
pub(crate) type Minimise<'a> = dyn Fn(usize, &[Class], &[f64]) -> Decision + Sync + 'a;

/// Whether bounds `(lo, hi)` decide the sign of a drive ([`tighten`]).
fn decided((lo, hi): (f64, f64)) -> bool {
    lo >= 0.0 || hi <= 0.0
}

/// The cuts (rows [`row`]) that the bounds `drive` give the free nodes of `classes`.
pub(crate) fn rows(form: &Formulation, classes: &[Class], drive: &[(f64, f64)]) -> Vec<Vec<f64>> {
    drive
        .iter()
        .enumerate()
        .filter(|&(j, _)| classes[j] == Class::Free)
        .filter_map(|(j, &(lo, hi))| row(form, j, lo, hi))
        .collect()
}

/// The largest share of its width by which a bound interval of `old` shrank in `new` (1 when
/// an infinite end became finite; 0 for an empty or a point interval).
pub(crate) fn largest_shrink(old: &[(f64, f64)], new: &[(f64, f64)]) -> f64 {
    old.iter()
        .zip(new)
        .map(|(&(lo, hi), &(new_lo, new_hi))| {
            let width = hi - lo;
            if (!lo.is_finite() && new_lo.is_finite()) || (!hi.is_finite() && new_hi.is_finite()) {
                1.0
            } else if !width.is_finite() || width <= 0.0 {
                0.0
            } else {
                ((new_lo - lo) + (hi - new_hi)) / width
            }
        })
        .fold(0.0, f64::max)
}

/// Bound tightening at a search node: for every free node `j` of `classes`, the least drive
/// with `j` in contact and the greatest with `j` separated (the module docs), over its
/// relaxation at a finite `mu` with `sum r_n = 1` and the cuts of `drive`, intersected with
/// `drive`. `minimise(key, fixed, objective)` solves the relaxation of the classes `fixed`
/// (`classes` with `j` fixed) with a linear objective over the reaction components, by
/// Clarabel (`clarabel_relaxation`, in the tests) or by the simplex method ([`super::node_lp`]); `key`
/// names the program (`2 j` the least drive of node `j`, `2 j + 1` the greatest), so that a
/// solver may start each from where the same program ended before. `None` when both of a
/// node's programs are infeasible (certified by the solver: the subtree has no solution at
/// `mu` or below); one infeasible program decides the node. A bound the solver cannot
/// decide stays as it was, and so do the bounds not yet tightened once `stop()` (the run's
/// limit or Ctrl-C: at m = 200 one node's programs take seconds).
///
/// A node whose bounds already decide its drive's sign (`L >= 0`: it cannot press; `U <= 0`:
/// its gap cannot open) is left as it is: its cut ([`row`]) is the same for any tighter bounds.
/// (Settling at `mu*`, where the relaxation is infeasible, more and more nodes are decided
/// before it is refuted: on the 2D plug at m = 100, a third of the root's last rounds.)
///
/// Only a part of the free nodes with `part = (k, parts)`: those whose position among the free
/// nodes is `k` modulo `parts`; the others keep their bounds (`(0, 1)`: every free node). (A
/// settled tightening, [`super::node_lp::tighten_node`], takes the parts in turn, each with the
/// cuts the one before it gave.)
pub(crate) fn tighten(
    form: &Formulation,
    classes: &[Class],
    drive: Option<&Drive>,
    part: (usize, usize),
    minimise: &Minimise,
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<Drive> {
    let m = form.m;
    let mut out = drive
        .cloned()
        .unwrap_or_else(|| vec![(f64::NEG_INFINITY, f64::INFINITY); m]);
    let (k, parts) = part;
    let free: Vec<usize> = (0..m)
        .filter(|&j| classes[j] == Class::Free)
        .enumerate()
        .filter(|&(n, _)| n % parts.max(1) == k)
        .map(|(_, j)| j)
        // A decided node's cut no longer depends on its bounds: no programs.
        .filter(|&j| !decided(out[j]))
        .collect();
    // Each free node's two programs: the node and its new bounds, each `None` when the solver
    // was unsure; `None` for the whole when neither program is feasible. (Starting each
    // program from the basis the previous one left, the least drives of a run of neighbours
    // first, took as many pivots as starting each from the node's basis.)
    type NewBounds = (usize, Option<f64>, Option<f64>);
    let found: Option<Vec<NewBounds>> = free
        .par_iter()
        .map(|&j| {
            if stop() {
                // The run is stopping: this node's bounds stay as they were (valid, looser).
                return Some((j, None, None));
            }
            let w = drive_row(form, j);
            // The least drive with the node in contact, the greatest with it separated:
            // `Some(None)` unsure, `None` infeasible.
            let extreme = |sign: f64| -> Option<Option<f64>> {
                let objective: Vec<f64> = w.iter().map(|x| sign * x).collect();
                let key = 2 * j + usize::from(sign < 0.0);
                let mut fixed = classes.to_vec();
                fixed[j] = if sign > 0.0 {
                    Class::Contact
                } else {
                    Class::Separated
                };
                match minimise(key, &fixed, &objective) {
                    Decision::No => None,
                    Decision::Unsure(_) => Some(None),
                    Decision::Yes { r, .. } => {
                        let v: f64 = w.iter().zip(&r).map(|(a, b)| a * b).sum();
                        let terms: f64 = w.iter().zip(&r).map(|(a, b)| (a * b).abs()).sum();
                        Some(Some(v - sign * MARGIN * (1.0 + terms)))
                    }
                }
            };
            // The two programs as two tasks: the parts' last nodes share the threads.
            match rayon::join(|| extreme(1.0), || extreme(-1.0)) {
                // Neither pressed nor separated: no solution at all.
                (None, None) => None,
                // Never in contact: it never presses, and its drive is its open gap.
                (None, Some(hi)) => Some((j, Some(0.0), hi)),
                // Never separated: its gap stays closed, and its drive presses it.
                (Some(lo), None) => Some((j, lo, Some(0.0))),
                (Some(lo), Some(hi)) => Some((j, lo, hi)),
            }
        })
        .collect();
    for (j, lo, hi) in found? {
        let (old_lo, old_hi) = out[j];
        out[j] = (
            lo.map_or(old_lo, |x| x.max(old_lo)),
            hi.map_or(old_hi, |x| x.min(old_hi)),
        );
    }
    Some(out)
}

/// The relaxation of [`tighten`] solved by Clarabel: the node of `classes` at `mu` (finite)
/// with `sum r_n = 1` and the cuts of `drive`. (The search uses the simplex method; the tests
/// check the cuts of both.)
#[cfg(test)]
pub(crate) fn clarabel_relaxation<'a>(
    form: &'a Formulation,
    classes: &'a [Class],
    mu: f64,
    drive: Option<&Drive>,
) -> impl Fn(usize, &[Class], &[f64]) -> Decision + Sync + 'a {
    use crate::conic::program::{Goal, Norm};
    debug_assert!(mu.is_finite());
    let cuts = drive.map(|d| rows(form, classes, d)).unwrap_or_default();
    move |_key: usize, fixed: &[Class], objective: &[f64]| {
        form.decide_cut(fixed, mu, Norm::Sum, Goal::Minimise(objective), &cuts)
            .0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conic::node_lp::{self as lp, LpCounters, Shape};
    use crate::examples::random_spd_problem;
    use crate::rays::{enumerate, Settings};
    use std::sync::atomic::Ordering;
    use std::sync::Arc;

    /// Every extreme ray of the solution set of a random 2D problem (enumerated independently,
    /// by double description) satisfies the cuts (bounds tightened by Clarabel or by the
    /// simplex method) of the root and of random subtrees it belongs
    /// to; a cut is linear, so every solution, a combination of rays of one cone, does too.
    /// Some cuts hold a ray tightly: a cut any stronger would cut off a solution.
    #[test]
    fn cuts_keep_every_solution() {
        let (mut checked, mut tight, mut rows_seen, mut simplex_solves) = (0, 0, 0, 0);
        for seed in 0..40u64 {
            let m = 2 + (seed % 5) as usize;
            let problem = random_spd_problem(m, 2.5, 7000 + seed);
            let rays = enumerate(&problem, &Settings::default()).unwrap().rays;
            let form = Formulation::new(&problem);
            let mut lcg = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            for round in 0..4 {
                // Round 0 is the root; the others fix some nodes at random.
                let classes: Vec<Class> = (0..m)
                    .map(|_| {
                        lcg = lcg
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        match (round, lcg >> 61) {
                            (0, _) | (_, 0..=3) => Class::Free,
                            (_, 4 | 5) => Class::Contact,
                            _ => Class::Separated,
                        }
                    })
                    .collect();
                // Tightened twice, by Clarabel in even rounds and by the simplex method
                // in odd ones.
                let mu = problem.mu();
                let by_simplex = round % 2 == 1;
                let counters = LpCounters::default();
                let twice = |d: Option<&Drive>| -> Option<Drive> {
                    if by_simplex {
                        let arc = d.cloned().map(Arc::new);
                        let shape = Shape {
                            mu,
                            drive: arc.as_ref(),
                        };
                        let minimise = lp::relaxation(&form, &counters, shape, None, None, None);
                        tighten(&form, &classes, d, (0, 1), &minimise, &|| false)
                    } else {
                        let minimise = clarabel_relaxation(&form, &classes, mu, d);
                        tighten(&form, &classes, d, (0, 1), &minimise, &|| false)
                    }
                };
                let again = twice(None).and_then(|d| twice(Some(&d)));
                simplex_solves += counters.solves.load(Ordering::Relaxed);
                let Some(drive) = again else {
                    // Certified infeasible: then no ray may belong to the subtree.
                    assert!(
                        !rays.iter().any(|ray| belongs(&form, &classes, &ray.r)),
                        "seed {seed}: a subtree with a solution was found infeasible"
                    );
                    continue;
                };
                let rows = rows(&form, &classes, &drive);
                rows_seen += rows.len();
                for ray in rays.iter().filter(|ray| belongs(&form, &classes, &ray.r)) {
                    for row in &rows {
                        let v: f64 = row.iter().zip(&ray.r).map(|(a, b)| a * b).sum();
                        let scale: f64 = row.iter().zip(&ray.r).map(|(a, b)| (a * b).abs()).sum();
                        assert!(v >= -1e-9 * scale, "seed {seed}: a cut {v:e} at a ray");
                        tight += usize::from(v <= 1e-4 * scale);
                        checked += 1;
                    }
                }
            }
        }
        assert!(
            rows_seen > 100 && checked > 100 && tight > 10 && simplex_solves > 100,
            "{rows_seen} {checked} {tight} {simplex_solves}"
        );
    }

    /// Once `stop()` holds, [`tighten`] solves no more programs and the bounds not yet
    /// tightened stay as they were: with a stop from the start, none is solved and the bounds
    /// come back unchanged; with a stop after a few programs, each bound is either the one it
    /// had or the one a whole tightening gives. A tightening of a part of the nodes is the
    /// whole one's on them.
    #[test]
    fn a_stop_leaves_the_bounds_as_they_were() {
        use std::sync::atomic::AtomicUsize;
        let mut partial_seen = 0;
        for seed in 0..6u64 {
            let m = 4 + (seed % 3) as usize;
            let problem = random_spd_problem(m, 2.5, 9100 + seed);
            let form = Formulation::new(&problem);
            let classes = vec![Class::Free; m];
            let counters = LpCounters::default();
            let shape = Shape {
                mu: problem.mu(),
                drive: None,
            };
            let solved = AtomicUsize::new(0);
            let minimise = lp::relaxation(&form, &counters, shape, None, None, None);
            let counted = |key: usize, fixed: &[Class], objective: &[f64]| {
                solved.fetch_add(1, Ordering::Relaxed);
                minimise(key, fixed, objective)
            };
            let Some(whole) = tighten(&form, &classes, None, (0, 1), &counted, &|| false) else {
                continue;
            };
            let unbounded = vec![(f64::NEG_INFINITY, f64::INFINITY); m];
            solved.store(0, Ordering::Relaxed);
            let none =
                tighten(&form, &classes, None, (0, 1), &counted, &|| true).expect("not refuted");
            assert_eq!(solved.load(Ordering::Relaxed), 0, "seed {seed}");
            assert_eq!(none, unbounded, "seed {seed}");
            let kept = tighten(&form, &classes, Some(&whole), (0, 1), &counted, &|| true).unwrap();
            assert_eq!(kept, whole, "seed {seed}");
            solved.store(0, Ordering::Relaxed);
            let few = || solved.load(Ordering::Relaxed) >= 3;
            let partial =
                tighten(&form, &classes, None, (0, 1), &counted, &few).expect("not refuted");
            for j in 0..m {
                let (lo, hi) = partial[j];
                assert!(
                    lo == f64::NEG_INFINITY || lo == whole[j].0,
                    "seed {seed}: {lo}"
                );
                assert!(hi == f64::INFINITY || hi == whole[j].1, "seed {seed}: {hi}");
            }
            if partial != whole && partial != unbounded {
                partial_seen += 1;
            }
            // A part's nodes (every third free one) get the whole tightening's bounds, the
            // others keep theirs.
            for k in 0..3 {
                let part = tighten(&form, &classes, None, (k, 3), &counted, &|| false)
                    .expect("not refuted");
                for j in 0..m {
                    let expected = if j % 3 == k { whole[j] } else { unbounded[j] };
                    assert_eq!(part[j], expected, "seed {seed}: part {k}, node {j}");
                }
            }
        }
        assert!(partial_seen >= 3, "only {partial_seen} partial tightenings");
    }

    /// A settled root ([`lp::tighten_node`], in one part or three) bounds every extreme ray's
    /// drive (so, the cone being their combinations, every solution's) and is at least as
    /// tight as one round; on some problems it is tighter.
    #[test]
    fn settled_bounds_keep_every_solution_and_tighten() {
        let (mut checked, mut tighter) = (0, [0, 0]);
        // Settled in one part (a round's programs all with the last round's cuts) and in
        // three (each part with the cuts of those before it).
        for (kind, settle) in [1, 3]
            .map(|parts| lp::Settle::InParts {
                parts,
                until: lp::SETTLED,
            })
            .into_iter()
            .enumerate()
        {
            for seed in 0..30u64 {
                let m = 3 + (seed % 4) as usize;
                let problem = random_spd_problem(m, 2.5, 9100 + seed);
                let rays = enumerate(&problem, &Settings::default()).unwrap().rays;
                let form = Formulation::new(&problem);
                let classes = vec![Class::Free; m];
                let counters = LpCounters::default();
                let shape = Shape {
                    mu: problem.mu(),
                    drive: None,
                };
                let never = || false;
                let once = lp::tighten_node(
                    &form,
                    &counters,
                    &classes,
                    shape,
                    Default::default(),
                    lp::Settle::Once,
                    &never,
                );
                let settled = lp::tighten_node(
                    &form,
                    &counters,
                    &classes,
                    shape,
                    Default::default(),
                    settle,
                    &never,
                );
                let (Some((once, _, _)), Some((settled, _, _))) = (once, settled) else {
                    assert!(rays.is_empty(), "seed {seed}: a root with solutions pruned");
                    continue;
                };
                for j in 0..m {
                    let (lo, hi) = settled[j];
                    // (Within rounding: a part's first programs are the single round's,
                    // solved from other bases.)
                    let slack = |x: f64| 1e-12 * (1.0 + x.abs());
                    assert!(
                        lo >= once[j].0 - slack(once[j].0) && hi <= once[j].1 + slack(once[j].1),
                        "seed {seed}: node {j} looser: {:?} against {:?}",
                        settled[j],
                        once[j]
                    );
                    tighter[kind] += usize::from(lo > once[j].0 + 1e-9 || hi < once[j].1 - 1e-9);
                    let w = drive_row(&form, j);
                    for ray in &rays {
                        let s: f64 = (0..m).map(|i| ray.r[2 * i]).sum();
                        let v: f64 = w.iter().zip(&ray.r).map(|(a, b)| a * b).sum::<f64>() / s;
                        assert!(
                            v >= lo - 1e-9 && v <= hi + 1e-9,
                            "seed {seed}: node {j}'s drive {v} outside [{lo}, {hi}]"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(
            checked > 200 && tighter.iter().all(|&t| t > 0),
            "{checked} {tighter:?}"
        );
    }

    #[test]
    fn largest_shrink_measures_the_intervals() {
        let old = [(f64::NEG_INFINITY, f64::INFINITY), (0.0, 4.0), (1.0, 1.0)];
        assert_eq!(largest_shrink(&old[1..], &[(1.0, 4.0), (1.0, 1.0)]), 0.25);
        assert_eq!(largest_shrink(&old[1..], &old[1..]), 0.0);
        assert_eq!(
            largest_shrink(&old, &[(-1.0, f64::INFINITY), old[1], old[2]]),
            1.0
        );
    }

    /// Whether the solution `r` lies in the subtree of `classes`: `r = 0` on its separated
    /// nodes, closed gaps on its contact nodes.
    fn belongs(form: &Formulation, classes: &[Class], r: &[f64]) -> bool {
        (0..form.m).all(|i| match classes[i] {
            Class::Separated => r[2 * i] == 0.0 && r[2 * i + 1] == 0.0,
            Class::Contact => form.gap_of(r, i).abs() <= 1e-9,
            _ => true,
        })
    }
}
