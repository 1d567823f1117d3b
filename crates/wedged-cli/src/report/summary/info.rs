//! The diagnostics of a summary: a ray method's line ([`info_line`]) and a pattern method's
//! lines ([`pattern_info`]).

use std::fmt::Write;

use wedged::patterns::{PatternMethod, Patterns};
use wedged::{Info, Outcome, Problem, Stop};

use super::{plural, seconds_text, wrapped};
use crate::report::answer::Choice;

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

/// `2^m - minus` as an exact integer while it is short, else in floating point.
pub(super) fn power_of_two(m: usize, minus: u64) -> String {
    if m <= 40 {
        ((1u64 << m) - minus).to_string()
    } else {
        format!("{:.3e}", 2f64.powi(m as i32))
    }
}

/// The share of the full binary tree over the `m` nodes (`2^(m+1) - 1` search nodes) that the
/// branch and bound never visited: `1 - (nodes_visited + leaves) / (2^(m+1) - 1)`.
pub(super) fn pruned_fraction(m: usize, nodes_visited: u64, leaves: u64) -> f64 {
    let tree = 2f64.powi(m as i32 + 1) - 1.0;
    (1.0 - (nodes_visited + leaves) as f64 / tree).clamp(0.0, 1.0)
}

/// The diagnostics of a pattern method: the search, the conic programs, the time.
pub(super) fn pattern_info(
    out: &mut String,
    problem: &Problem,
    choice: &Choice,
    result: &Patterns,
) {
    let m = problem.nodes();
    let info = &result.info;
    let maximal = result.patterns.len() + info.streamed as usize;
    let _ = writeln!(
        out,
        "info: {}{}; {}",
        seconds_text(info.seconds),
        crate::report::json::peak_memory_text(),
        if info.groups > 1 {
            format!(
                "{} realised in the groups, {maximal} maximal (their products)",
                plural(info.realised as usize, "pattern", "patterns"),
            )
        } else {
            format!(
                "{} realised, {maximal} of them maximal",
                plural(info.realised as usize, "pattern", "patterns"),
            )
        }
    );
    let search = match choice {
        Choice::Patterns(s) if s.method == PatternMethod::Bnb => {
            let fraction = match result.outcome {
                // A search stopped early has not pruned what it did not reach.
                Outcome::Incomplete(stop) if stop != Stop::Undecided => {
                    "the search stopped before the end".to_string()
                }
                _ => format!(
                    "pruned fraction {:.4} (the share of the 2^{} - 1 = {} nodes of the full \
                     tree never visited)",
                    pruned_fraction(m, info.nodes_visited, info.leaves),
                    m + 1,
                    power_of_two(m + 1, 1)
                ),
            };
            // Inner nodes by the simplex method (not in a certified run; in 3D on a polygon's
            // cone that holds the friction cone), leaves by the cone program.
            let programs = match info.lp_solves {
                0 => String::new(),
                _ => format!(
                    "; inner nodes by {}",
                    linear_programs(info.lp_solves, info.lp_pivots, info.lp_fallbacks)
                ),
            };
            // Orbital branching (a symmetry of the problem): the regions it skipped are filled
            // with images of the patterns found.
            let mirrored = match info.mirrored {
                0 => String::new(),
                n => format!(
                    "; {} separated a node's mirror image too, {} made as images",
                    plural(n as usize, "branching", "branchings"),
                    plural(info.images as usize, "pattern", "patterns")
                ),
            };
            // Leaves and witnesses taken from their orbits' least pattern (3D).
            let mapped = match info.mapped {
                0 => String::new(),
                n => format!("; {n} leaves and witnesses mapped from their orbits' least"),
            };
            format!(
                "branch and bound: {} visited, {} pruned (infeasible) + {} pruned (a contact node \
                 could not be pressed), {} reached of 2^{m} = {}; {fraction}{programs}{mirrored}\
                 {mapped}",
                plural(info.nodes_visited as usize, "node", "nodes"),
                info.pruned_infeasible,
                info.pruned_unpressed,
                plural(info.leaves as usize, "leaf", "leaves"),
                power_of_two(m, 0),
            )
        }
        Choice::Patterns(s) if matches!(s.method, PatternMethod::Pyramid { .. }) => {
            let faces = match s.method {
                PatternMethod::Pyramid { faces } if problem.dim() == 3 => {
                    format!("{faces} faces")
                }
                _ => "2D: exact, the friction law is already polyhedral".to_string(),
            };
            format!(
                "pyramid approximation ({faces}): {} of the approximation, {} (its maximal \
                 patterns), {} spurious (not realised as they stood)",
                plural(info.pyramid_rays as usize, "ray", "rays"),
                plural(info.candidates as usize, "candidate", "candidates"),
                info.spurious
            )
        }
        Choice::Patterns(s) if s.method == PatternMethod::Search => format!(
            "contact-set search: {} visited, {} pruned (no solution presses the contact nodes \
             at once), {} inherited their parent's solution, {} bounded the drives of their \
             free nodes, {} (contact sets pressed exactly) of 2^{m} = {}; {}",
            plural(info.nodes_visited as usize, "node", "nodes"),
            info.pruned_infeasible,
            info.nodes_inherited,
            info.bound_tightenings,
            plural(info.leaves as usize, "leaf", "leaves"),
            power_of_two(m, 0),
            linear_programs(info.lp_solves, info.lp_pivots, info.lp_fallbacks),
        ),
        _ => format!(
            "brute force: {} of the 2^{m} - 1 = {} nonempty contact sets have a nontrivial cone",
            info.candidates,
            power_of_two(m, 1)
        ),
    };
    let search = if info.groups > 1 {
        format!(
            "the contact nodes fall into {} groups that K does not couple, each searched on its \
             own, the pieces the products of theirs (the counts below are their sums); {search}",
            info.groups
        )
    } else {
        search
    };
    wrapped(out, 2, 4, &search);
    wrapped(
        out,
        2,
        4,
        &format!(
            "{} solved ({} retried, {} undecided, {} near-degenerate {})",
            plural(info.socps as usize, "SOCP", "SOCPs"),
            info.retries,
            info.uncertain,
            info.near_degenerate,
            if info.near_degenerate == 1 {
                "decision"
            } else {
                "decisions"
            }
        ),
    );
}
