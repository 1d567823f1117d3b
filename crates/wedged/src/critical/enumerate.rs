//! The seed's method for `mu*` (MISSION section 6): enumerate the maximal patterns at a large
//! `mu`, find each one's threshold, take the least.
//!
//! Every solution at some `mu' <= mu` is a solution at `mu`, so it lies in the closed piece of a
//! maximal pattern `q` there, and so in the leaf of `q`'s zero-gap nodes (contact and grazing).
//! The least of those leaves' thresholds is therefore `mu*`, provided that `mu >= mu*`: the
//! enumeration starts at the problem's own `mu` and doubles it while nothing wedges, up to
//! `2^MAX_DOUBLINGS` times. When even that finds nothing, the branch and bound decides (it
//! certifies "never" or finds `mu*` above).
//!
//! The 2D enumeration is the contact-set search (`search`; each cone's centroid starts its
//! threshold); 3D uses the pattern branch and bound (each pattern's witness).

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::{CriticalInfo, CriticalProgress, Ctx, Found, PatternThreshold};
use crate::patterns::{enumerate_patterns_with_control, PatternSettings, Undecided};
use crate::rays::{enumerate_with_control, Method, Settings};
use crate::run::{Control, EnumerateError, Limits, Outcome, Stop};
use crate::solution::ContactPattern;

/// How many times the enumeration's `mu` may double before the branch and bound takes over.
const MAX_DOUBLINGS: usize = 10;

pub(super) fn run(
    ctx: &Ctx,
    info: &mut CriticalInfo,
    progress: &dyn Fn(CriticalProgress),
    limits: Limits,
    cancel: &AtomicBool,
    control: &Control,
) -> Result<Found, EnumerateError> {
    let start = Instant::now();
    let problem = ctx.form.problem;
    let mut mu = problem.mu();
    // Pieces as (pattern, a solution in it).
    let mut pieces: Vec<(Vec<ContactPattern>, Vec<f64>)> = Vec::new();
    for _ in 0..=MAX_DOUBLINGS {
        let at = problem
            .with_mu(mu)
            .map_err(|e| EnumerateError::Internal(format!("cannot enumerate at mu = {mu}: {e}")))?;
        // The enumeration gets what is left of the time limit.
        let left = Limits {
            time_limit: limits.time_limit.map(|t| t.saturating_sub(start.elapsed())),
            ..limits
        };
        progress(CriticalProgress::default());
        // (Above the ray methods' largest `mu` the sign patterns go on.)
        let (outcome, found) =
            if problem.dim() == 2 && !problem.is_floating() && mu <= crate::rays::RAYS_MU_MAX {
                // The contact-set search, as `enumerate` takes by default in 2D: the seed's
                // pruned double description (the library's default method) held 2 GB of rays and
                // took 17 s for the 5 pieces of the 2D plug at m = 20 (`wedged sweep`), where the
                // search takes milliseconds.
                let e = enumerate_with_control(
                    &at,
                    &Settings {
                        method: Method::Search,
                        limits: left,
                        ..Settings::default()
                    },
                    &|_| {},
                    cancel,
                )?;
                let pieces = e
                    .cones
                    .iter()
                    .map(|c| {
                        let q = e
                            .cone_status(c)
                            .iter()
                            .map(|&s| ContactPattern::of(s))
                            .collect();
                        (q, e.cone_centroid(c).1)
                    })
                    .collect::<Vec<_>>();
                (e.outcome, pieces)
            } else {
                let p = enumerate_patterns_with_control(
                    &at,
                    &PatternSettings {
                        limits: left,
                        ..PatternSettings::default()
                    },
                    &|_| {},
                    cancel,
                )?;
                if !p.undecided.is_empty() {
                    return Ok(Found {
                        undecided: p.undecided,
                        ..Found::default()
                    });
                }
                // A floating body's point carries its rigid amplitudes, read off the witness.
                let pieces = p
                    .patterns
                    .into_iter()
                    .map(|q| (q.pattern, at.point_of(&q.u, &q.r)))
                    .collect();
                (p.outcome, pieces)
            };
        info.mu_enumerated = Some(mu);
        match outcome {
            Outcome::Incomplete(stop) => {
                // The run's own limit, not what the enumeration was left of it.
                let stop = match (stop, limits.time_limit) {
                    (Stop::TimeLimit(_), Some(limit)) => Stop::TimeLimit(limit),
                    _ => stop,
                };
                return Ok(Found {
                    stop: Some(stop),
                    ..Found::default()
                });
            }
            Outcome::NotWedged => mu *= 2.0,
            Outcome::Wedged => {
                pieces = found;
                break;
            }
        }
    }
    info.patterns_enumerated = pieces.len() as u64;
    if pieces.is_empty() {
        info.mu_enumerated = None;
        return Ok(super::bnb::run(
            ctx,
            info,
            (None, None),
            progress,
            control,
            Default::default(),
        ));
    }
    let mut found = Found {
        lower: f64::INFINITY,
        ..Found::default()
    };
    let total = pieces.len();
    for (k, (q, r)) in pieces.into_iter().enumerate() {
        if control.must_stop(0) {
            break;
        }
        progress(CriticalProgress {
            explored: k as f64 / total as f64,
            upper: found.best.as_ref().map(|b| b.theta),
            ..CriticalProgress::default()
        });
        // The leaf of the zero-gap nodes.
        let contact: Vec<bool> = q.iter().map(|&c| c != ContactPattern::Separated).collect();
        let Some((theta, r)) = ctx.exact_point(&contact, &r, mu) else {
            found.undecided.push(Undecided {
                contact,
                reason: "the piece's solution could not be made exact".into(),
            });
            continue;
        };
        info.leaves_solved += 1;
        match ctx.leaf_threshold(&contact, theta, r, control, &|| f64::INFINITY) {
            Ok(None) => unreachable!("no cap"),
            Ok(Some(leaf)) => {
                found.thresholds.push(PatternThreshold {
                    pattern: q,
                    threshold: leaf.theta,
                    lower: leaf.lower,
                    witness: super::witness_of(ctx.form, &leaf).ok(),
                });
                found.lower = found.lower.min(leaf.lower);
                if found.best.as_ref().is_none_or(|b| leaf.theta < b.theta) {
                    found.best = Some(leaf);
                }
            }
            Err(_) if control.stopped().is_some() => {}
            Err(reason) => found.undecided.push(Undecided { contact, reason }),
        }
    }
    Ok(found)
}
