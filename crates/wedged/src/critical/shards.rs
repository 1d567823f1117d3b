//! The one-run bracket of `mu*` from the brackets of a sharded `bnb` search
//! ([`crate::shard`]).
//!
//! Every shard runs the passes of [`super::bnb`] (one per bar) over its own units of each
//! pass's tree, with its own incumbent. Let pass `k` be the first in which some shard finds a
//! leaf: every shard ran pass `k` to its end, so the shards' pass-`k` units cover every
//! solution with a ratio up to that bar. A shard that found a leaf certified its units down
//! to its own `lower`; one that found none certified that its units hold nothing up to the
//! bar, which is above every leaf found in the pass. So `mu*` is at least the least `lower`
//! of the shards that found a leaf, and at most their least `upper`, whose witness is a
//! solution. A shard that went on to later passes (none found in pass `k`) may report a leaf
//! of a later pass: its `lower` bounds its own units of that pass, and the least of the
//! `lower`s is still a lower bound. When no shard finds a leaf at any bar, the body never
//! wedges. A shard that stopped early (a limit, undecided sets) leaves the merge incomplete.

use super::{Critical, CriticalInfo, CriticalStatus};
use crate::patterns::every_shard;

/// The one-run result from the results of the shards `1..N` of one `critical` run (each with
/// [`super::CriticalSettings::shard`]); an error when a part is not a shard, or the shards are
/// not `1..N` once each. The counters are the shards' sums, the seconds the longest shard's.
pub fn merge_shards(parts: Vec<Critical>) -> Result<Critical, String> {
    every_shard(parts.iter().map(|p| p.shard))?;
    let stop = parts.iter().find_map(|p| match p.status {
        CriticalStatus::Incomplete(s) => Some(s),
        _ => None,
    });
    let mut info = CriticalInfo {
        method: parts[0].info.method,
        ..CriticalInfo::default()
    };
    for p in &parts {
        add_info(&mut info, &p.info);
    }
    let certified = parts
        .iter()
        .map(|p| p.certificate.as_ref().map(|c| c.certified))
        .collect::<Option<Vec<bool>>>();
    let wedged: Vec<&Critical> = parts
        .iter()
        .filter(|p| p.status == CriticalStatus::Wedged)
        .collect();
    let lower = wedged.iter().filter_map(|p| p.lower).min_by(f64::total_cmp);
    let best = parts.iter().filter(|p| p.upper.is_some()).min_by(|a, b| {
        a.upper
            .unwrap_or(f64::INFINITY)
            .total_cmp(&b.upper.unwrap_or(f64::INFINITY))
    });
    let status = match stop {
        Some(s) => CriticalStatus::Incomplete(s),
        None if best.is_some() => CriticalStatus::Wedged,
        None => CriticalStatus::Never,
    };
    let upper = best.and_then(|b| b.upper);
    let lower = if status == CriticalStatus::Wedged {
        lower
    } else {
        None
    };
    if let (Some(l), Some(u)) = (lower, upper) {
        info.tol_achieved = (u - l) / u;
    }
    let mut undecided = Vec::new();
    for p in &parts {
        undecided.extend(p.undecided.iter().cloned());
    }
    let certificate = match (certified, parts[0].certificate.clone()) {
        (Some(all), Some(mut first)) => {
            first.certified = all.iter().all(|&c| c);
            first.upper = upper;
            for p in &parts[1..] {
                if let Some(c) = &p.certificate {
                    first.refutations_checked += c.refutations_checked;
                    first.refutations_failed += c.refutations_failed;
                    first.resolved += c.resolved;
                    first.failures.extend(c.failures.iter().cloned());
                }
            }
            Some(first)
        }
        _ => None,
    };
    Ok(Critical::of_bracket(
        status,
        (lower, upper),
        best.and_then(|b| b.witness.clone()),
        undecided,
        info,
        certificate,
    ))
}

/// Adds a shard's counters to `sum` (seconds: the longest).
pub(super) fn add_info(sum: &mut CriticalInfo, part: &CriticalInfo) {
    // No `..`: a new counter must be merged here too.
    let CriticalInfo {
        method: _,
        nodes_visited,
        pruned_infeasible,
        leaves_solved,
        bound_tightenings,
        mirrored,
        dive_nodes,
        improvement_steps,
        simplex_solves,
        simplex_fallbacks,
        simplex_relaxed,
        dinkelbach_steps,
        bisection_steps,
        certificates,
        loosened,
        tol_achieved: _,
        mu_enumerated: _,
        patterns_enumerated: _,
        socps,
        retries,
        uncertain,
        groups: _,
        seconds,
        // A shard has no condensed start (its top must be the same in every process).
        condensed_nodes: _,
        condensed_mu: _,
        condensed_seconds: _,
    } = *part;
    sum.nodes_visited += nodes_visited;
    sum.pruned_infeasible += pruned_infeasible;
    sum.leaves_solved += leaves_solved;
    sum.bound_tightenings += bound_tightenings;
    sum.mirrored += mirrored;
    sum.dive_nodes += dive_nodes;
    sum.improvement_steps += improvement_steps;
    sum.simplex_solves += simplex_solves;
    sum.simplex_fallbacks += simplex_fallbacks;
    sum.simplex_relaxed += simplex_relaxed;
    sum.dinkelbach_steps += dinkelbach_steps;
    sum.bisection_steps += bisection_steps;
    sum.certificates += certificates;
    sum.loosened += loosened;
    sum.socps += socps;
    sum.retries += retries;
    sum.uncertain += uncertain;
    sum.seconds = sum.seconds.max(seconds);
}
