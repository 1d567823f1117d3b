//! A leaf improved by local search over contact sets: the primal heuristic of `critical`'s
//! `bnb`.
//!
//! The search tests its nodes at `min(bar, incumbent (1 - tol))`, so the level it works at is
//! the incumbent's threshold, and a search that starts far above `mu*` pays for the crawl down:
//! on the 3D V-groove plug with m = 40 (`mu*` = 1.4835) a search whose first bar is 2.0 visits
//! 150k nodes, one whose first bar is `mu*` + 1e-4 visits 4k (`BENCHMARKS.md`). So the run's
//! first leaf is improved here before the search goes on with it as its incumbent.
//!
//! **One step**: the contact sets that differ from the current leaf's in one node are each
//! tested at a level below the leaf's threshold `theta` by the search's linear program of the
//! leaf (contact on the set, separated elsewhere, `sum r_n = 1`), in parallel, started from the
//! current leaf's basis. The levels are `theta (1 - s)` for `s` in [`STEPS`], from 0.3 down to
//! 1e-5. Every neighbour is screened at the shallowest (a set with no solution there has none
//! deeper), and those that pass are tried at the levels deepest first: the first level where
//! one is feasible gives the step, so a long step is taken where one exists and the small ones
//! are not missed (on the 2D plug the way down to `mu*` is a chain of single changes of 1e-5 to
//! 1e-2 each). The first neighbour in node order that is feasible there and whose own
//! threshold is below `theta` becomes the current leaf. In 2D that linear program is the leaf's
//! exact program, and the threshold is found by bisection on it (warm-started, a few pivots a
//! probe, between the level and the deeper level that found nothing); the leaf reached is made
//! exact at the end ([`Ctx::leaf_threshold`]). In 3D the linear program is an outer relaxation:
//! a neighbour it does not refute is confirmed by its cone program and its threshold computed
//! exactly.
//!
//! **Block moves**: where no single change improves, the same step over larger changes: a
//! node and its 2, 4, 8, 16 or 32 nearest (by their coupling in `K`, [`nearest`]) all let go,
//! or all pressed ([`blocks`]). A wedge can need a whole run of contact let go at once: on the
//! 2D plug from m = 140 on the single changes stop about 3% above `mu*` ([`BLOCKS`]). The search
//! stops at a leaf that neither improves, after [`MAX_STEPS_PER_NODE`] `m` steps, or when the
//! run is stopped. The order is fixed, so the result does not depend on the threads.
//!
//! The leaf returned is an exact solution of its contact set with its threshold, as every leaf
//! of the search is: it only sets the level; the proof that nothing lies below it is the
//! search's.
//!
//! **The first incumbent** ([`all_contact`]): before the dive, the all-contact set's leaf, which
//! a few programs give. On large problems the search can go long without a leaf (the 2D plug
//! at m = 200: none in ten minutes), and a run stopped then had nothing to report; now it
//! reports at least that leaf's threshold as an upper end, with its checked witness.

use std::collections::HashSet;

use rayon::prelude::*;

use super::{Ctx, Leaf};
use crate::conic::node_lp::{self as lp, LpCounters, Shape, Warm};
use crate::conic::program::{leaf_classes, Decision, Formulation, Goal, Norm};
use crate::run::Control;

/// The levels a step screens the neighbours at, relative distances below the current
/// threshold, deepest first: the first level at which some neighbour improves gives the step.
/// (A single level `1e-4` stopped the 2D plug at m = 80 at 1.7661, 2.4% above `mu*`, where a
/// chain of single changes of 1e-5 to 1e-3 each leads down to it; with these levels it
/// reaches `mu*` = 1.7246526 in 25 steps.)
const STEPS: [f64; 7] = [0.3, 0.1, 3e-2, 1e-2, 1e-3, 1e-4, 1e-5];

/// The block moves' sizes: a node and this many of its nearest ([`blocks`]). (On the 2D plug
/// at m = 140 the single changes stop at 1.7996, 3% above `mu*`, with both walls pressed down
/// from mid-height; `mu*`'s wedge presses one wall over that length and the other only over a
/// short patch. One block move (a run of the second wall let go) at 1.7976 and single changes
/// from there reach `mu*` = 1.7439517.)
const BLOCKS: [usize; 5] = [2, 4, 8, 16, 32];

/// At most this many steps per contact node.
const MAX_STEPS_PER_NODE: usize = 4;

/// The relative width to which a 2D neighbour's threshold is bisected.
const BISECTED: f64 = 1e-7;

/// The leaf reached from `leaf` by changes of its contact set (single nodes, or blocks where
/// none of those improves), each lowering the threshold (see the module docs), and the number
/// of steps taken (`leaf` itself and 0 when none).
pub(super) fn improve(
    ctx: &Ctx,
    counters: &LpCounters,
    control: &Control,
    leaf: Leaf,
) -> (Leaf, usize) {
    let form = ctx.form;
    let m = form.m;
    let mut current = leaf.clone();
    let mut steps = 0;
    let mut near: Option<Vec<Vec<usize>>> = None;
    while steps < MAX_STEPS_PER_NODE * m && !control.must_stop(0) {
        let singles: Vec<Vec<bool>> = (0..m)
            .map(|j| {
                let mut c = current.contact.clone();
                c[j] = !c[j];
                c
            })
            .collect();
        let mut next = step(ctx, counters, control, &current, &singles);
        if next.is_none() && !control.must_stop(0) {
            // A local minimum of the single changes: the block moves.
            let near = near.get_or_insert_with(|| nearest(form));
            next = step(
                ctx,
                counters,
                control,
                &current,
                &blocks(&current.contact, near),
            );
        }
        match next {
            Some(next) => {
                current = next;
                steps += 1;
            }
            None => break,
        }
    }
    if form.dim == 2 && steps > 0 {
        // The bisected threshold made exact, as the search's leaves are.
        let none = || f64::INFINITY;
        let exact = ctx
            .exact_point(&current.contact, &current.r, current.theta)
            .and_then(|(t, p)| {
                ctx.leaf_threshold(&current.contact, t, p, control, &none)
                    .ok()
                    .flatten()
            });
        return match exact {
            Some(exact) => (exact, steps),
            None => (leaf, 0),
        };
    }
    (current, steps)
}

/// The move to take from `current`: among the `candidates` (contact sets near its own), the
/// first in their order that has a solution at the deepest of the levels [`STEPS`] below
/// `current`'s threshold at which any has one, with its own threshold; `None` when none has
/// one at the shallowest level. The candidates are screened at the shallowest level first: a
/// set with no solution there has none deeper (a solution at some `mu` is one at every larger
/// `mu`), so the deeper levels test only the few that pass, and a local minimum costs one
/// program per candidate.
fn step(
    ctx: &Ctx,
    counters: &LpCounters,
    control: &Control,
    current: &Leaf,
    candidates: &[Vec<bool>],
) -> Option<Leaf> {
    let form = ctx.form;
    let theta = current.theta;
    let levels: Vec<f64> = STEPS.iter().map(|s| theta * (1.0 - s)).collect();
    let shallowest = levels[levels.len() - 1];
    // The current leaf's own program at the shallowest level (infeasible there) starts its
    // neighbours'.
    let (_, warm) = leaf_program(ctx, counters, &current.contact, shallowest, None);
    // The candidates the linear program does not refute at `level`, in their order (an empty
    // point when the simplex method was unsure).
    let open_at = |among: &[usize], level: f64| -> Vec<(usize, Vec<f64>)> {
        among
            .par_iter()
            .filter_map(|&j| {
                let contact = &candidates[j];
                if !contact.contains(&true) {
                    return None;
                }
                match leaf_program(ctx, counters, contact, level, warm.as_ref()).0 {
                    Decision::No => None,
                    Decision::Yes { r, .. } => Some((j, r)),
                    Decision::Unsure(_) => Some((j, Vec::new())),
                }
            })
            .collect()
    };
    let all: Vec<usize> = (0..candidates.len()).collect();
    let screened = open_at(&all, shallowest);
    if screened.is_empty() || control.must_stop(0) {
        return None;
    }
    let passed: Vec<usize> = screened.iter().map(|(j, _)| *j).collect();
    // The deepest level first: a long step where one exists, a short one otherwise. A level
    // deeper than the one tried found nothing, which bounds a 2D bisection below.
    (0..levels.len()).find_map(|k| {
        let level = levels[k];
        let floor = if k > 0 { levels[k - 1] } else { 0.0 };
        let open = if k + 1 == levels.len() {
            screened.clone()
        } else {
            open_at(&passed, level)
        };
        open.into_iter().find_map(|(j, r)| {
            let contact = candidates[j].clone();
            if form.dim == 2 && !r.is_empty() {
                let (_, theta, r) = bisect(ctx, counters, &contact, floor, level, r, warm.as_ref());
                return Some(Leaf {
                    contact,
                    theta,
                    r,
                    lower: 0.0,
                });
            }
            confirm(ctx, control, &contact, level, level).filter(|leaf| leaf.theta < current.theta)
        })
    })
}

/// For each node, the other nodes by decreasing coupling in the stiffness: the Frobenius norm
/// of their block of `K` over the geometric mean of the two nodes' own blocks' (ties by node
/// number). A condensed stiffness couples neighbours along the contact boundary most and
/// decays with the distance, so a node's first few are the nodes around it on the mesh,
/// whatever their numbering.
fn nearest(form: &Formulation) -> Vec<Vec<usize>> {
    let k = form.problem.stiffness();
    let (d, m) = (form.dim, form.m);
    let block = |i: usize, j: usize| k.view((d * i, d * j), (d, d)).norm();
    let own: Vec<f64> = (0..m).map(|i| block(i, i)).collect();
    (0..m)
        .map(|j| {
            let mut others: Vec<(f64, usize)> = (0..m)
                .filter(|&i| i != j)
                .map(|i| (block(i, j) / (own[i] * own[j]).sqrt(), i))
                .collect();
            others.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
            others.into_iter().map(|(_, i)| i).collect()
        })
        .collect()
}

/// The block moves of `contact` ([`BLOCKS`]): around each node, it and its nearest
/// ([`nearest`]) all separated (around a contact node) or all in contact (around a separated
/// one), in node order and by size; each new set once, and none that is `contact` itself or
/// has no contact.
fn blocks(contact: &[bool], near: &[Vec<usize>]) -> Vec<Vec<bool>> {
    let mut out: Vec<Vec<bool>> = Vec::new();
    let mut seen = HashSet::new();
    seen.insert(contact.to_vec());
    for (j, others) in near.iter().enumerate() {
        for size in BLOCKS {
            let size = size.min(others.len());
            let mut c = contact.to_vec();
            let to = !contact[j];
            c[j] = to;
            for &i in &others[..size] {
                c[i] = to;
            }
            if c.contains(&true) && seen.insert(c.clone()) {
                out.push(c);
            }
        }
    }
    out
}

/// The leaf of `contact` by its cone program: a solution at `level`, made exact, and the
/// set's threshold computed exactly from that point (searched up to `cap`); `None` when the
/// cone program has no solution at `level` or no exact point or threshold came of it.
fn confirm(ctx: &Ctx, control: &Control, contact: &[bool], level: f64, cap: f64) -> Option<Leaf> {
    let classes = leaf_classes(contact);
    let Decision::Yes { r, .. } = ctx
        .form
        .decide_at(&classes, level, Norm::Sum, Goal::Feasible)
    else {
        return None;
    };
    let (t, p) = ctx.exact_point(contact, &r, level)?;
    ctx.leaf_threshold(contact, t, p, control, &|| cap)
        .ok()
        .flatten()
}

/// How many levels above the bar, doubling, [`leaf_of`] tries.
const DOUBLINGS: i32 = 6;

/// A first leaf before the search's: the all-contact set's (every gap closed), by
/// [`leaf_of`]. It costs a few programs, and it is an incumbent (a witness, an upper end of
/// the bracket) where the search may find none for long: on the 2D plug at m = 200 the dive's
/// 2,000 nodes and then ten minutes of the first pass found no leaf, and the run ended with
/// nothing to report. It is not improved by local search here (from the all-contact set that
/// took 66 steps at m = 80 and stopped at a local minimum above the bar at m = 100,
/// `BENCHMARKS.md`); the search's first leaf still is.
pub(super) fn all_contact(
    ctx: &Ctx,
    counters: &LpCounters,
    control: &Control,
    bar: f64,
) -> Option<Leaf> {
    leaf_of(ctx, counters, control, vec![true; ctx.form.m], bar)
}

/// The leaf of `contact` from the first of the levels `bar`, `2 bar`, ..., `64 bar` at which
/// its linear program has a solution; in 2D bisected on that program to [`BISECTED`] and the
/// point there made exact (its ratio is the leaf's `theta`, within `1e-7` above the set's
/// threshold; its `lower` is the bisection's last refuted level, a floating-point one), in 3D
/// confirmed by its cone program and its threshold computed exactly. `None` when it has none
/// there.
pub(super) fn leaf_of(
    ctx: &Ctx,
    counters: &LpCounters,
    control: &Control,
    contact: Vec<bool>,
    bar: f64,
) -> Option<Leaf> {
    let form = ctx.form;
    let mut warm = None;
    let mut floor = 0.0;
    for k in 0..=DOUBLINGS {
        if control.must_stop(0) {
            return None;
        }
        let level = bar * 2f64.powi(k);
        let (decision, next) = leaf_program(ctx, counters, &contact, level, warm.as_ref());
        warm = next.or(warm);
        let r = match decision {
            Decision::Yes { r, .. } => r,
            Decision::No => {
                floor = level;
                continue;
            }
            Decision::Unsure(_) => continue,
        };
        if form.dim == 2 {
            // In 2D the linear program is the leaf's own: its threshold by bisection on it
            // (the solution at a level far above need not survive being made exact; on the 2D
            // plug it did not), the bisection's last refuted level its lower end, and the
            // point there made exact. (The leaf's threshold by `leaf_threshold` would need
            // cone programs: 23 of them and 5 to 8 s on the plug at m = 80.)
            let (lower, theta, r) = bisect(ctx, counters, &contact, floor, level, r, warm.as_ref());
            let (t, p) = ctx.exact_point(&contact, &r, theta)?;
            return Some(Leaf {
                contact,
                theta: t,
                r: p,
                lower: lower.min(t),
            });
        }
        // (A level whose cone program fails to confirm the linear program's solution is
        // passed over for the next.)
        if let Some(leaf) = confirm(ctx, control, &contact, level, f64::INFINITY) {
            return Some(leaf);
        }
    }
    None
}

/// The search's linear program of the leaf of `contact` at `mu` (`sum r_n = 1`, no cuts), from
/// `warm`: its decision and final basis.
fn leaf_program(
    ctx: &Ctx,
    counters: &LpCounters,
    contact: &[bool],
    mu: f64,
    warm: Option<&Warm>,
) -> (Decision, Option<Warm>) {
    let shape = Shape { mu, drive: None };
    let classes = leaf_classes(contact);
    lp::decide(ctx.form, counters, &classes, shape, Norm::Sum, None, warm)
}

/// A 2D leaf's threshold by bisection on its linear program between `floor` (a level where no
/// neighbour was feasible, or 0) and `level` (where it has the solution `r`), to [`BISECTED`]:
/// the lower end (`floor` or a level the program refuted), the upper end and its solution.
fn bisect(
    ctx: &Ctx,
    counters: &LpCounters,
    contact: &[bool],
    floor: f64,
    level: f64,
    r: Vec<f64>,
    warm: Option<&Warm>,
) -> (f64, f64, Vec<f64>) {
    let (mut lo, mut hi, mut r) = (floor, level, r);
    let mut warm = warm.cloned();
    while hi - lo > BISECTED * hi {
        let mid = 0.5 * (lo + hi);
        let (decision, next) = leaf_program(ctx, counters, contact, mid, warm.as_ref());
        warm = next.or(warm);
        match decision {
            Decision::Yes { r: at, .. } => (hi, r) = (mid, at),
            Decision::No => lo = mid,
            Decision::Unsure(_) => break,
        }
    }
    (lo, hi, r)
}

#[cfg(test)]
pub(super) mod tests {
    use std::sync::atomic::AtomicBool;

    use super::*;
    use crate::conic::program::Formulation;
    use crate::critical::Tally;
    use crate::examples::random_spd_problem_dim;
    use crate::run::Limits;

    /// The least `mu` at which the leaf of `contact` has a solution, by bisection on its cone
    /// program (neither the simplex method nor Dinkelbach's steps); `None` when it has none at
    /// `cap`.
    pub(in crate::critical) fn threshold(
        form: &Formulation,
        contact: &[bool],
        cap: f64,
    ) -> Option<f64> {
        let classes = leaf_classes(contact);
        let feasible = |mu: f64| {
            matches!(
                form.decide_at(&classes, mu, Norm::Sum, Goal::Feasible),
                Decision::Yes { .. }
            )
        };
        if !feasible(cap) {
            return None;
        }
        let (mut lo, mut hi) = (0.0, cap);
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if feasible(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Some(hi)
    }

    /// On a chain (a stiffness coupling each node to its neighbours, more weakly to the next
    /// ones, numbered out of order) a node's nearest are its neighbours along the chain, and
    /// a block move lets go of (or presses) a run of the chain around a node.
    #[test]
    fn blocks_are_runs_of_the_chain() {
        let m = 12;
        // Chain position of node i: a shuffled numbering.
        let at: Vec<usize> = (0..m).map(|i| (5 * i + 3) % m).collect();
        let mut k = nalgebra::DMatrix::<f64>::zeros(2 * m, 2 * m);
        for i in 0..m {
            for j in 0..m {
                let dist = at[i].abs_diff(at[j]);
                let c = match dist {
                    0 => 4.0,
                    _ => -1.0 / (dist * dist * dist) as f64,
                };
                k[(2 * i, 2 * j)] = c;
                k[(2 * i + 1, 2 * j + 1)] = 0.5 * c;
            }
        }
        let problem = crate::Problem::new(2, k, 1.0).expect("a diagonally dominant stiffness");
        let form = Formulation::new(&problem);
        let near = nearest(&form);
        for (j, others) in near.iter().enumerate() {
            let first: Vec<usize> = others[..2].iter().map(|&i| at[i]).collect();
            let expect = match at[j] {
                0 => vec![1, 2],
                p if p == m - 1 => vec![m - 2, m - 3],
                p => vec![p - 1, p + 1],
            };
            let mut sorted = first.clone();
            sorted.sort();
            let mut expect_sorted = expect.clone();
            expect_sorted.sort();
            assert_eq!(sorted, expect_sorted, "node {j} at {}", at[j]);
        }
        // Contact on chain positions 2 to 9: around position 5, the run of 3 let go.
        let contact: Vec<bool> = (0..m).map(|i| (2..=9).contains(&at[i])).collect();
        let moves = blocks(&contact, &near);
        assert!(!moves.contains(&contact));
        let centre = (0..m).find(|&i| at[i] == 5).unwrap();
        let run: Vec<bool> = (0..m)
            .map(|i| contact[i] && !(4..=6).contains(&at[i]))
            .collect();
        assert!(
            moves.contains(&run),
            "no move lets go of 4..=6 around {centre}"
        );
        // Every move changes the set one way around its node: only let go, or only pressed.
        for c in &moves {
            let off = (0..m).filter(|&i| contact[i] && !c[i]).count();
            let on = (0..m).filter(|&i| !contact[i] && c[i]).count();
            assert!(off == 0 || on == 0, "{c:?}");
            assert!(off + on >= 1 && c.contains(&true));
        }
        let unique: HashSet<&Vec<bool>> = moves.iter().collect();
        assert_eq!(unique.len(), moves.len());
    }

    /// The context of the tests' runs: `tol` 1e-9, a fresh tally.
    pub(in crate::critical) fn ctx<'a, 'b>(form: &'a Formulation<'b>) -> Ctx<'a, 'b> {
        Ctx {
            form,
            tol: 1e-9,
            tally: Tally::default(),
        }
    }

    pub(in crate::critical) fn set(mask: usize, m: usize) -> Vec<bool> {
        (0..m).map(|i| mask >> i & 1 == 1).collect()
    }

    /// The leaf of a contact set ([`leaf_of`]: the all-contact set's, [`all_contact`], and a
    /// second set per problem, as the rounded root gives) of small random problems (2D and 3D)
    /// has the threshold that bisection on the set's cone program gives, never below the brute
    /// force's `mu*`; where that threshold is at most `64 bar` the leaf is found.
    #[test]
    fn a_sets_leaf_has_the_sets_threshold() {
        const BAR: f64 = 0.5;
        let cancel = AtomicBool::new(false);
        let control = Control::new(Limits::default(), &cancel);
        let (mut found, mut reachable) = (0, 0);
        for case in 0..24u64 {
            let dim = 2 + (case % 2) as usize;
            let m = 2 + (case % 5) as usize;
            let problem = random_spd_problem_dim(dim, m, 1.0, 500 + case);
            let form = Formulation::new(&problem);
            let ctx = ctx(&form);
            let mu_star = (1..1usize << m)
                .filter_map(|mask| threshold(&form, &set(mask, m), 64.0 * BAR))
                .fold(f64::INFINITY, f64::min);
            // A nonempty set (masks 1 to `2^m - 1`: now and then the all-contact set again).
            let other = set(1 + (case as usize * 7) % ((1 << m) - 1), m);
            for contact in [vec![true; m], other] {
                let own = threshold(&form, &contact, 64.0 * BAR);
                let leaf = if contact.iter().all(|&c| c) {
                    all_contact(&ctx, &LpCounters::default(), &control, BAR)
                } else {
                    leaf_of(&ctx, &LpCounters::default(), &control, contact.clone(), BAR)
                };
                let what = format!("case {case} (dim {dim}, m {m}), set {contact:?}");
                match (own, leaf) {
                    (Some(t), Some(leaf)) => {
                        found += 1;
                        reachable += 1;
                        assert_eq!(leaf.contact, contact, "{what}");
                        assert!(
                            (leaf.theta - t).abs() <= 1e-6 * t,
                            "{what}: {} against {t}",
                            leaf.theta
                        );
                        assert!(leaf.theta >= mu_star * (1.0 - 1e-6), "{what}: below mu*");
                        assert!(leaf.lower <= leaf.theta, "{what}");
                    }
                    (Some(t), None) => {
                        reachable += 1;
                        eprintln!("{what}: the set's threshold {t} not found");
                    }
                    (None, Some(leaf)) => {
                        panic!("{what}: a leaf at {} beyond the levels", leaf.theta)
                    }
                    (None, None) => {}
                }
            }
        }
        assert!(
            reachable >= 16 && found >= reachable - 2,
            "{found} of {reachable}"
        );
    }

    /// From the worst leaf of small random problems (2D and 3D), the improvement lowers the
    /// threshold, never below the brute force's `mu*`, to the leaf's own threshold (checked by
    /// bisection), and stops where no single-node change and no block move lowers it by more
    /// than 1e-5 (the shallowest level, with a margin for the solvers).
    #[test]
    fn improvement_reaches_a_local_minimum_above_mu_star() {
        const CAP: f64 = 50.0;
        let cancel = AtomicBool::new(false);
        let control = Control::new(Limits::default(), &cancel);
        let mut improved = 0;
        for case in 0..20u64 {
            let dim = 2 + (case % 2) as usize;
            let m = 3 + (case % 4) as usize;
            let problem = random_spd_problem_dim(dim, m, 1.0, 300 + case);
            let form = Formulation::new(&problem);
            let ctx = ctx(&form);
            let thresholds: Vec<Option<f64>> = (0..1usize << m)
                .map(|mask| {
                    (mask > 0)
                        .then(|| threshold(&form, &set(mask, m), CAP))
                        .flatten()
                })
                .collect();
            let Some((worst, &Some(t))) = thresholds
                .iter()
                .enumerate()
                .filter(|(_, t)| t.is_some_and(|t| t < CAP / 2.0))
                .max_by(|a, b| a.1.unwrap().total_cmp(&b.1.unwrap()))
            else {
                continue;
            };
            let mu_star = thresholds
                .iter()
                .flatten()
                .fold(f64::INFINITY, |a, &b| a.min(b));
            let contact = set(worst, m);
            let classes = leaf_classes(&contact);
            let hi = t * (1.0 + 1e-3);
            let Decision::Yes { r, .. } = form.decide_at(&classes, hi, Norm::Sum, Goal::Feasible)
            else {
                panic!("case {case}: the worst leaf is feasible above its threshold");
            };
            let (theta, p) = ctx.exact_point(&contact, &r, hi).expect("an exact point");
            let start = ctx
                .leaf_threshold(&contact, theta, p, &control, &|| f64::INFINITY)
                .unwrap()
                .expect("the worst leaf's threshold");
            let (leaf, steps) = improve(&ctx, &LpCounters::default(), &control, start.clone());
            let what = format!("case {case} (dim {dim}, m {m}, {steps} steps)");
            assert!(leaf.theta <= start.theta * (1.0 + 1e-9), "{what}");
            assert!(leaf.theta >= mu_star * (1.0 - 1e-6), "{what}: below mu*");
            let mask: usize = (0..m).filter(|&i| leaf.contact[i]).map(|i| 1 << i).sum();
            let own = thresholds[mask].expect("the leaf reached has a threshold");
            assert!(
                (own - leaf.theta).abs() <= 1e-6 * own,
                "{what}: {own} against {}",
                leaf.theta
            );
            for j in 0..m {
                if let Some(t) = thresholds[mask ^ (1 << j)] {
                    assert!(
                        t >= leaf.theta * (1.0 - 3e-5),
                        "{what}: node {j} lowers it to {t}"
                    );
                }
            }
            for block in blocks(&leaf.contact, &nearest(&form)) {
                let other: usize = (0..m).filter(|&i| block[i]).map(|i| 1 << i).sum();
                if let Some(t) = thresholds[other] {
                    assert!(
                        t >= leaf.theta * (1.0 - 3e-5),
                        "{what}: the block move to {block:?} lowers it to {t}"
                    );
                }
            }
            if steps > 0 {
                improved += 1;
            }
        }
        assert!(improved >= 8, "only {improved} of 20 improved");
    }
}
