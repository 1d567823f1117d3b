//! The diagnostics line of a ray method's summary ([`info_line`]).

use wedged::Info;

use super::{plural, seconds_text};

/// Entries of `rays_after_node` printed on the info line.
const INFO_LIST_LIMIT: usize = 20;

/// Diagnostics worth reading, on one line; the zero counters of other methods are left out.
pub(super) fn info_line(info: &Info) -> String {
    let mut parts = vec![format!(
        "{}{}",
        seconds_text(info.seconds),
        crate::report::json::peak_memory_text()
    )];
    if !info.rays_after_node.is_empty() {
        let shown: Vec<String> = info
            .rays_after_node
            .iter()
            .take(INFO_LIST_LIMIT)
            .map(|n| n.to_string())
            .collect();
        let rest = info.rays_after_node.len().saturating_sub(INFO_LIST_LIMIT);
        let tail = if rest > 0 {
            format!(" ... ({rest} more in --json)")
        } else {
            String::new()
        };
        parts.push(format!(
            "rays kept after each node: {}{tail}",
            shown.join(" ")
        ));
    }
    if info.peak_rays > 0 {
        parts.push(format!(
            "peak {} ({})",
            plural(info.peak_rays, "ray", "rays"),
            wedged::run::bytes_text(info.peak_bytes)
        ));
    }
    if info.pairs_tested > 0 {
        parts.push(format!(
            "{} tested ({} rejected by pattern, {} combinatorially)",
            plural(info.pairs_tested as usize, "pair", "pairs"),
            info.pairs_rejected_pattern,
            info.pairs_rejected_combinatorial
        ));
    }
    if info.adjacency_tests > 0 {
        parts.push(plural(
            info.adjacency_tests as usize,
            "adjacency test",
            "adjacency tests",
        ));
    }
    if info.rays_created > 0 {
        parts.push(plural(
            info.rays_created as usize,
            "ray created",
            "rays created",
        ));
    }
    if info.near_degenerate > 0 {
        parts.push(plural(
            info.near_degenerate as usize,
            "near-degenerate sign decision",
            "near-degenerate sign decisions",
        ));
    }
    if info.extreme_rays_total > 0 {
        parts.push(plural(
            info.extreme_rays_total,
            "extreme ray of C",
            "extreme rays of C",
        ));
    }
    if info.candidates > 0 {
        parts.push(plural(
            info.candidates as usize,
            "candidate tight set",
            "candidate tight sets",
        ));
    }
    if info.search_nodes > 0 {
        parts.push(format!(
            "search tree: {} ({} pruned, {} inherited, {} bounded the drives), {} (faces up to \
             dimension {}); {}",
            plural(info.search_nodes as usize, "node", "nodes"),
            info.search_pruned,
            info.search_inherited,
            info.search_tightenings,
            plural(info.search_leaves as usize, "leaf", "leaves"),
            info.largest_face,
            linear_programs(info.lp_solves, info.lp_pivots, info.lp_fallbacks)
        ));
    }
    parts.join("; ")
}

/// The simplex method's share of a search: "N linear programs (P pivots, F passed to
/// Clarabel)".
pub(super) fn linear_programs(solves: u64, pivots: u64, fallbacks: u64) -> String {
    format!(
        "{} ({pivots} pivots, {fallbacks} passed to Clarabel)",
        plural(solves as usize, "linear program", "linear programs"),
    )
}
