//! `mu*` of a body whose contact nodes fall into groups that `K` does not couple (separate
//! bodies condensed into one problem, or a matrix assembled so): each group is searched on its
//! own, and `mu*` is the least of the groups'.
//!
//! **Why it holds.** With `K` block diagonal over the groups (every entry between two groups
//! exactly zero), so is its inverse, and a group's reactions open no gap at another's nodes. A
//! solution of WP restricted to one group is a solution of that group's problem, and a group's
//! solution padded with zeros (no pressure, no gap: grazing) is one of the whole. So the whole
//! is wedged at `mu` exactly when some group is, and its `mu*` is the least of the groups'
//! (never when no group is ever wedged). The bracket is the least upper end (its group's
//! witness, padded and checked against the whole problem) over the least lower end.
//!
//! **Why it pays.** One search over all the nodes proves its lower end for every group at
//! once, and its relaxations share one normalisation (`sum r_n = 1`) across the groups, so a
//! group that cannot wedge below the incumbent is refuted only together with the others. Two
//! uncoupled copies of the 2D plug's stiffness at m = 50 (m = 100 in all) took 44 s and
//! 515k search nodes and reached only 1.3e-7 of the bracket; grouped, 0.23 s (one copy: 0.11 s)
//! (`BENCHMARKS.md`).
//!
//! The groups ([`crate::groups::uncoupled_groups`]) are found from exact zeros only. Every
//! problem is one group for the `enumerate` method (its per-pattern thresholds are the whole
//! problem's patterns) and for a shard (every process must split the same tree).

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::certify::CriticalCertificate;
use super::{Critical, CriticalInfo, CriticalProgress, CriticalSettings, CriticalStatus};
use crate::groups::{restricted, spread_contact, time_for_next};
use crate::problem::Problem;
use crate::run::{EnumerateError, Stop};
use crate::solution::{check_solution, ContactPattern, NodeStatus};

/// [`super::critical_with_control`] on each group of `groups` (more than one), combined (see
/// the module docs). A stop (time limit, Ctrl-C) leaves the groups not yet searched without a
/// lower end, and the result incomplete unless the groups done already decide it.
pub(super) fn by_groups(
    problem: &Problem,
    settings: &CriticalSettings,
    groups: &[Vec<usize>],
    progress: &dyn Fn(CriticalProgress),
    cancel: &AtomicBool,
) -> Result<Critical, EnumerateError> {
    let clock = Instant::now();
    let (d, m) = (problem.dim(), problem.nodes());
    // Each group's result, `None` for a group not searched (the run stopped first).
    let mut parts: Vec<Option<Critical>> = Vec::with_capacity(groups.len());
    let mut stopped: Option<Stop> = None;
    for nodes in groups {
        let left = match time_for_next(&settings.limits, &clock, cancel) {
            Ok(left) if stopped.is_none() => left,
            Ok(_) => {
                parts.push(None);
                continue;
            }
            Err(stop) => {
                stopped = stopped.or(Some(stop));
                parts.push(None);
                continue;
            }
        };
        let sub = restricted(problem, nodes)?;
        let mut own = settings.clone();
        own.limits.time_limit = left;
        own.start = settings
            .start
            .as_ref()
            .map(|start| nodes.iter().map(|&i| start[i]).collect::<Vec<bool>>())
            .filter(|start| start.contains(&true));
        parts.push(Some(super::critical_with_control(
            &sub, &own, progress, cancel,
        )?));
    }

    // The least upper end, and the group it is in.
    let best = parts
        .iter()
        .enumerate()
        .filter_map(|(g, p)| Some((g, p.as_ref()?.upper?)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let upper = best.map(|b| b.1);
    // What each group proves of its own mu*: wedged, its lower end; never, nothing below
    // infinity; incomplete, what its finished passes proved (`None`: nothing).
    let proved = |p: &Option<Critical>| -> Option<f64> {
        let p = p.as_ref()?;
        match p.status {
            CriticalStatus::Wedged => p.lower,
            CriticalStatus::Never => Some(f64::INFINITY),
            CriticalStatus::Incomplete(_) => p.lower,
        }
    };
    // A group left incomplete decides nothing only if it might still wedge below `upper`.
    let open = parts.iter().find_map(|p| {
        let stop = match p {
            None => stopped.unwrap_or(Stop::Interrupted),
            Some(c) => match c.status {
                CriticalStatus::Incomplete(s) => s,
                _ => return None,
            },
        };
        let settled = proved(p).zip(upper).is_some_and(|(l, u)| l >= u);
        (!settled).then_some(stop)
    });
    let lower = parts
        .iter()
        .map(proved)
        .try_fold(f64::INFINITY, |least, l| l.map(|l| least.min(l)));
    let (status, lower) = match (open, upper) {
        (Some(stop), _) => (
            CriticalStatus::Incomplete(stop),
            lower.filter(|l| l.is_finite()),
        ),
        (None, None) => (CriticalStatus::Never, None),
        (None, Some(u)) => (CriticalStatus::Wedged, lower.map(|l| l.min(u))),
    };

    // The best group's witness on the whole problem: the other nodes unpressed, gaps closed.
    let witness = match best {
        Some((g, up)) => match parts[g].as_ref().and_then(|p| p.witness.as_ref()) {
            Some(w) => {
                let mut whole = super::CriticalWitness {
                    u: vec![0.0; d * m],
                    r: vec![0.0; d * m],
                    status: vec![NodeStatus::Grazing; m],
                    pattern: vec![ContactPattern::Grazing; m],
                };
                for (a, &i) in groups[g].iter().enumerate() {
                    for c in 0..d {
                        whole.u[d * i + c] = w.u[d * a + c];
                        whole.r[d * i + c] = w.r[d * a + c];
                    }
                    whole.status[i] = w.status[a];
                    whole.pattern[i] = w.pattern[a];
                }
                check_solution(problem, up, &whole.u, &whole.r).map_err(|why| {
                    EnumerateError::Internal(format!(
                        "the witness of mu* = {up} of a group of uncoupled contact nodes failed \
                         its check on the whole problem: {why}"
                    ))
                })?;
                Some(whole)
            }
            None => None,
        },
        None => None,
    };

    let mut info = CriticalInfo {
        method: settings.method.name(),
        groups: groups.len() as u64,
        ..CriticalInfo::default()
    };
    let mut undecided = Vec::new();
    let mut certificate: Option<CriticalCertificate> = None;
    for (g, part) in parts.iter().enumerate() {
        let Some(part) = part else { continue };
        super::shards::add_info(&mut info, &part.info);
        undecided.extend(part.undecided.iter().map(|u| crate::patterns::Undecided {
            contact: spread_contact(&groups[g], m, &u.contact),
            reason: u.reason.clone(),
        }));
        if let Some(c) = &part.certificate {
            let sum = certificate.get_or_insert_with(|| CriticalCertificate {
                certified: true,
                upper: None,
                refutations_checked: 0,
                refutations_failed: 0,
                resolved: 0,
                failures: Vec::new(),
            });
            sum.certified &= c.certified;
            sum.refutations_checked += c.refutations_checked;
            sum.refutations_failed += c.refutations_failed;
            sum.resolved += c.resolved;
            let first = groups[g][0] + 1;
            sum.failures.extend(
                c.failures
                    .iter()
                    .map(|f| format!("the group of node {first}: {f}")),
            );
            if best.is_some_and(|b| b.0 == g) {
                sum.upper = c.upper;
            }
        }
    }
    if let (Some(l), Some(u)) = (lower, upper) {
        info.tol_achieved = (u - l) / u;
    }
    info.seconds = clock.elapsed().as_secs_f64();
    Ok(Critical::of_bracket(
        status,
        (lower, upper),
        witness,
        undecided,
        info,
        certificate,
    ))
}
