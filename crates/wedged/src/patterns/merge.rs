//! The one-run answer from the answers of a sharded search ([`crate::shard`]).
//!
//! The shards' trees and the top that they share make up the one-run tree node for node, so
//! the realised patterns of all of them are the one run's; each shard keeps the maximal ones of
//! its part, and a pattern maximal in its shard may lie below another shard's. The merge keeps
//! the maximal patterns of the union (the first of equal ones: a leaf above the split is found
//! by every shard) and sorts them by pattern, as one run does. A maximal pattern's witness
//! depends on the pattern alone, so each is the one run's witness.

use super::{keep_maximal, PatternCertificate, PatternInfo, Patterns, Undecided};
use crate::run::{Outcome, Stop};

/// Checks that `shards` (each part's `(index, count)`) are shards of one split into `N`, none
/// twice (the error names the repeated or foreign ones), and returns the missing indices.
pub fn check_shards(shards: &[(usize, usize)]) -> Result<Vec<usize>, String> {
    let Some(&(_, count)) = shards.first() else {
        return Err("no parts to merge".to_string());
    };
    if let Some(&(i, n)) = shards.iter().find(|&&(_, n)| n != count) {
        return Err(format!(
            "shard {i}/{n} is of a split into {n}, the first part's into {count}"
        ));
    }
    let mut seen = vec![0usize; count];
    for &(i, n) in shards {
        if i == 0 || i > n {
            return Err(format!("shard {i}/{n}: no such shard"));
        }
        seen[i - 1] += 1;
    }
    let list = |f: &dyn Fn(usize) -> bool| -> Vec<String> {
        (1..=count)
            .filter(|&i| f(seen[i - 1]))
            .map(|i| i.to_string())
            .collect()
    };
    let repeated = list(&|k| k > 1);
    if !repeated.is_empty() {
        return Err(format!(
            "shard {} of {count} given more than once",
            repeated.join(", ")
        ));
    }
    Ok((1..=count).filter(|&i| seen[i - 1] == 0).collect())
}

/// Checks that the parts whose shard reports are `shards` are the shards `1..N` of one split,
/// each once: the error names a part that is a whole run, and the missing or repeated shards.
/// (The library's merges need every shard; `wedged merge` also merges what is there.)
pub(crate) fn every_shard(
    shards: impl Iterator<Item = Option<crate::shard::ShardReport>>,
) -> Result<(), String> {
    let shards = shards
        .map(|s| {
            s.map(|s| (s.index, s.count))
                .ok_or_else(|| "a part is a whole run, not a shard".to_string())
        })
        .collect::<Result<Vec<_>, _>>()?;
    let missing = check_shards(&shards)?;
    if missing.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{}: the merge of the others is not the whole answer",
            missing_text(&missing, shards[0].1)
        ))
    }
}

/// `"shard 3 of 16 missing"`, `"shards 3, 7 of 16 missing"`.
pub fn missing_text(missing: &[usize], count: usize) -> String {
    let list: Vec<String> = missing.iter().map(|i| i.to_string()).collect();
    let s = if missing.len() == 1 { "" } else { "s" };
    format!("shard{s} {} of {count} missing", list.join(", "))
}

/// The one-run answer of the shards `parts` of one search (each a run with
/// [`super::PatternSettings::shard`]): an error when a part is not a shard or the shards are
/// not `1..N` once each. The counters are the shards' sums (the top of the tree, which every
/// shard solves, counted once per shard), the seconds the longest shard's.
pub fn merge_shards(parts: Vec<Patterns>) -> Result<Patterns, String> {
    every_shard(parts.iter().map(|p| p.shard))?;
    let mut stopped = None;
    let mut info = PatternInfo::default();
    let mut certificate: Option<PatternCertificate> = None;
    let mut all = Vec::new();
    let mut undecided: Vec<Undecided> = Vec::new();
    for part in parts {
        if let Outcome::Incomplete(stop) = part.outcome {
            if stop != Stop::Undecided {
                stopped.get_or_insert(stop);
            }
        }
        add_info(&mut info, &part.info);
        if let Some(c) = part.certificate {
            certificate = Some(match certificate {
                None => c,
                Some(mut m) => {
                    m.certified &= c.certified;
                    m.witnesses_checked += c.witnesses_checked;
                    m.witnesses_failed += c.witnesses_failed;
                    m.refutations_checked += c.refutations_checked;
                    m.refutations_failed += c.refutations_failed;
                    m.doubts += c.doubts;
                    m.failures.extend(c.failures);
                    m
                }
            });
        }
        all.extend(part.patterns);
        for u in part.undecided {
            if !undecided.iter().any(|v| v.contact == u.contact) {
                undecided.push(u);
            }
        }
    }
    let keep = keep_maximal(&all.iter().map(|p| &p.pattern[..]).collect::<Vec<_>>());
    let mut patterns: Vec<_> = all
        .into_iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(p))
        .collect();
    patterns.sort_by(|a, b| a.pattern.cmp(&b.pattern));
    let outcome = super::outcome_of(stopped, !undecided.is_empty(), !patterns.is_empty());
    Ok(Patterns {
        outcome,
        patterns,
        undecided,
        info,
        certificate,
        shard: None,
    })
}

/// Adds a shard's counters to `sum` (seconds: the longest).
pub(super) fn add_info(sum: &mut PatternInfo, part: &PatternInfo) {
    // No `..`: a new counter must be merged here too.
    let PatternInfo {
        nodes_visited,
        nodes_inherited,
        pruned_infeasible,
        pruned_unpressed,
        leaves,
        candidates,
        spurious,
        pyramid_rays,
        socps,
        retries,
        uncertain,
        near_degenerate,
        realised,
        streamed,
        bound_tightenings,
        lp_solves,
        lp_pivots,
        lp_fallbacks,
        mirrored,
        images,
        mapped,
        groups: _,
        seconds,
    } = *part;
    sum.nodes_visited += nodes_visited;
    sum.nodes_inherited += nodes_inherited;
    sum.pruned_infeasible += pruned_infeasible;
    sum.pruned_unpressed += pruned_unpressed;
    sum.leaves += leaves;
    sum.candidates += candidates;
    sum.spurious += spurious;
    sum.pyramid_rays += pyramid_rays;
    sum.socps += socps;
    sum.retries += retries;
    sum.uncertain += uncertain;
    sum.near_degenerate += near_degenerate;
    sum.realised += realised;
    sum.streamed += streamed;
    sum.bound_tightenings += bound_tightenings;
    sum.lp_solves += lp_solves;
    sum.lp_pivots += lp_pivots;
    sum.lp_fallbacks += lp_fallbacks;
    sum.mirrored += mirrored;
    sum.images += images;
    sum.mapped += mapped;
    sum.seconds = sum.seconds.max(seconds);
}
