//! The brute force for `mu*`: every nonempty contact set in turn, each threshold by plain
//! bisection. It shares with the other methods only the conic program of a leaf and the exact
//! projection of a solver point, not the Dinkelbach descent nor any search, which makes it
//! their check.
//!
//! A contact set is skipped when no solution presses all of its nodes even with unlimited
//! friction (certified infeasible; its solutions belong to smaller sets), or when its leaf is
//! infeasible at the best value so far (certified). Otherwise the bracket `[lo, hi]` starts at
//! `[0, min(best, ratio of a pressing solution)]` and is halved until it is `tol` wide; every
//! infeasible midpoint is certified, so `lo` is.

use std::sync::atomic::Ordering;

use super::{loosest, CriticalInfo, CriticalProgress, Ctx, Found, Leaf};
use crate::conic::program::{leaf_classes, Decision, Goal, Norm};
use crate::patterns::Undecided;
use crate::run::Control;

pub(super) fn run(
    ctx: &Ctx,
    info: &mut CriticalInfo,
    progress: &dyn Fn(CriticalProgress),
    control: &Control,
) -> Found {
    let m = ctx.form.m;
    let mut found = Found {
        lower: f64::INFINITY,
        ..Found::default()
    };
    let total = (1u64 << m) - 1;
    for mask in 1..=total {
        if control.must_stop(0) {
            break;
        }
        progress(CriticalProgress {
            explored: (mask - 1) as f64 / total as f64,
            upper: found.best.as_ref().map(|b| b.theta),
            ..CriticalProgress::default()
        });
        let contact: Vec<bool> = (0..m).map(|i| mask >> i & 1 == 1).collect();
        let nodes: Vec<usize> = (0..m).filter(|&i| contact[i]).collect();
        let classes = leaf_classes(&contact);
        let mut undecided = |why: String| {
            found.undecided.push(Undecided {
                contact: contact.clone(),
                reason: why,
            })
        };
        // A solution pressing every node, with unlimited friction; when the solver cannot
        // settle that, any nontrivial solution of the leaf (the question bnb asks of an unsure
        // leaf: its infeasibility is the stronger certificate, and a point of it belongs to
        // this leaf's closure all the same).
        let mut decision = ctx.form.decide_at(
            &classes,
            f64::INFINITY,
            Norm::Pressed(&nodes),
            Goal::Feasible,
        );
        if matches!(decision, Decision::Unsure(_)) {
            decision = ctx
                .form
                .decide_at(&classes, f64::INFINITY, Norm::Sum, Goal::Feasible);
        }
        let start = match decision {
            Decision::No => {
                info.pruned_infeasible += 1;
                ctx.tally.certificates.fetch_add(1, Ordering::Relaxed);
                continue;
            }
            // With a best threshold already, the test at it below decides this leaf instead.
            Decision::Unsure(_) if found.best.is_some() => None,
            Decision::Unsure(why) => {
                undecided(why);
                continue;
            }
            Decision::Yes { r, .. } => Some(r),
        };
        let (mut hi, mut witness) = match start {
            Some(r) => match ctx.exact_point(&contact, &r, f64::INFINITY) {
                Some(point) => point,
                None => {
                    undecided("the solver's point could not be made an exact solution".into());
                    continue;
                }
            },
            None => (f64::INFINITY, Vec::new()),
        };
        if let Some(best) = &found.best {
            if best.theta < hi {
                match ctx
                    .form
                    .decide_at(&classes, best.theta, Norm::Sum, Goal::Feasible)
                {
                    Decision::No => {
                        info.pruned_infeasible += 1;
                        ctx.tally.certificates.fetch_add(1, Ordering::Relaxed);
                        continue;
                    }
                    Decision::Unsure(why) => {
                        undecided(why);
                        continue;
                    }
                    Decision::Yes { r, .. } => match ctx.exact_point(&contact, &r, best.theta) {
                        Some((t, p)) => (hi, witness) = (t, p),
                        None => {
                            undecided("the solver's point could not be made exact".into());
                            continue;
                        }
                    },
                }
            }
        }
        info.leaves_solved += 1;
        let mut lo = 0.0f64;
        let mut unsure = None;
        // A probe the solver cannot settle is moved once or twice (to 0.3 and 0.7 of the
        // bracket) before the bisection gives up with the bracket it has.
        let mut moves = 0;
        while hi - lo > ctx.tol * hi && !control.must_stop(0) {
            let mid = lo + [0.5, 0.3, 0.7][moves.min(2)] * (hi - lo);
            ctx.tally.bisection.fetch_add(1, Ordering::Relaxed);
            match ctx.form.decide_at(&classes, mid, Norm::Sum, Goal::Feasible) {
                Decision::No => {
                    ctx.tally.certificates.fetch_add(1, Ordering::Relaxed);
                    lo = mid;
                }
                Decision::Yes { r, .. } => match ctx.exact_point(&contact, &r, mid) {
                    // The exact point's ratio may sit a little above mid (solver accuracy);
                    // then the bracket cannot be narrowed further from this side.
                    Some((t, p)) if t < hi && t >= lo => (hi, witness) = (t, p),
                    _ => {
                        unsure = Some(format!(
                            "feasible at {mid} by the solver, but no exact solution below {hi}"
                        ));
                        moves += 1;
                    }
                },
                Decision::Unsure(why) => {
                    unsure = Some(why);
                    moves += 1;
                }
            }
            if moves > 2 {
                break;
            }
        }
        if hi - lo > loosest(ctx.tol) * hi {
            undecided(unsure.unwrap_or_else(|| "stopped".into()));
            continue;
        }
        if hi - lo > ctx.tol * hi * 1.000001 {
            ctx.tally.loosened.fetch_add(1, Ordering::Relaxed);
        }
        found.lower = found.lower.min(lo);
        if found.best.as_ref().is_none_or(|b| hi < b.theta) {
            found.best = Some(Leaf {
                contact: contact.clone(),
                theta: hi,
                r: witness,
                lower: lo,
            });
        }
    }
    found
}
