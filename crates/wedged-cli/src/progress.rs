//! The live progress lines of `enumerate` ([`progress_text`]) and of `critical` and `sweep`
//! ([`critical_progress_text`]), as text: [`crate::jobs`] draws them on stderr.
//!
//! A search's explored share counts each finished subtree at depth `d` as `2^-d` of the tree
//! (Knuth's measure), so the line's size of the tree and time left are estimates. On the
//! contact-set search they are hopeful: the subtrees left for the end are often the largest (on
//! the 2D plug at m = 100 the share passed 95% at 33 s of a 67 s run). [`Pace`] notices
//! that: once the share has stood still for longer than the time the line says is left, the
//! estimate is refuted, and the line says so instead of repeating it.

use wedged::patterns::{PatternMethod, PatternSettings};
use wedged::{CriticalProgress, Method, Progress, Settings};

use crate::report::answer::Choice;

/// When the explored share last moved, for [`progress_text`]'s time left.
#[derive(Debug, Default)]
pub struct Pace {
    share: std::cell::Cell<f64>,
    since: std::cell::Cell<f64>,
}

impl Pace {
    /// How long the share has stood at `share`, at `seconds` into the run.
    pub fn still(&self, share: f64, seconds: f64) -> f64 {
        if share != self.share.get() {
            self.share.set(share);
            self.since.set(seconds);
        }
        seconds - self.since.get()
    }
}

/// The explored share of an `enumerate` run's report, in `[0, 1]`.
pub fn share(p: &Progress) -> f64 {
    p.done as f64 / p.total.max(1) as f64
}

/// The live progress line of `enumerate` (without its carriage return); `still` is how long
/// the explored share has not moved ([`Pace::still`]).
pub fn progress_text(choice: &Choice, p: Progress, seconds: f64, still: f64) -> String {
    let share = share(&p);
    let count = |n: usize, one: &str, many: &str| {
        if n == 1 {
            format!("1 {one}")
        } else {
            format!("{n} {many}")
        }
    };
    let tree = |found: String| {
        format!(
            "explored {} of the search tree{}, {found} found, {seconds:.1} s{}",
            percent(share),
            tree_size(p.nodes, share),
            time_left(share, seconds, still)
        )
    };
    match choice {
        Choice::Patterns(PatternSettings {
            method: PatternMethod::Bnb | PatternMethod::Search,
            ..
        }) => tree(count(p.rays, "pattern", "patterns")),
        Choice::Rays(Settings {
            method: Method::Search,
            ..
        }) => tree(count(p.rays, "contact set", "contact sets")),
        Choice::Patterns(_) => format!(
            "pyramid approximation, node {}/{}: {} rays held, {seconds:.1} s",
            p.done, p.total, p.rays
        ),
        Choice::Rays(_) => format!(
            "node {}/{}: {} rays held, {seconds:.1} s",
            p.done, p.total, p.rays
        ),
    }
}

/// A share as a percentage with one decimal, rounded down: `100.0%` only when all is explored.
fn percent(share: f64) -> String {
    let tenths = (share.clamp(0.0, 1.0) * 1000.0).floor();
    format!("{:.1}%", tenths / 10.0)
}

/// `" (N nodes of about T)"`: the nodes visited and the estimated size of the whole tree,
/// `nodes / share` (see [`Progress::nodes`]), once a thousandth of it is explored; empty
/// before any node.
fn tree_size(nodes: u64, share: f64) -> String {
    tree_counts(nodes, share).map_or(String::new(), |t| format!(" ({t})"))
}

/// What [`tree_size`] puts in its parentheses, `None` before any node.
fn tree_counts(nodes: u64, share: f64) -> Option<String> {
    if nodes == 0 {
        return None;
    }
    let visited = format!("{nodes} nodes");
    if !(1e-3..1.0).contains(&share) {
        return Some(visited);
    }
    let total = nodes as f64 / share;
    let about = if total < 1e4 {
        format!("{total:.0}")
    } else if total < 1e7 {
        format!("{:.0}k", total / 1e3)
    } else {
        format!("{:.1e}", total)
    };
    Some(format!("{visited} of about {about}"))
}

/// `", about T left"` for a search that has explored `share` of its tree in `seconds`, at the
/// same pace; empty before 0.1% is explored. When the share has stood still (`still` seconds)
/// for longer than that, the pace is not the same, and it says `", time left unknown"`: a
/// subtree larger than the measure says is being searched (see the module's docs).
fn time_left(share: f64, seconds: f64, still: f64) -> String {
    if !(1e-3..1.0).contains(&share) {
        return String::new();
    }
    let left = seconds * (1.0 - share) / share;
    if still > left.max(1.0) {
        return ", time left unknown".to_string();
    }
    let text = if left < 1.0 {
        "under 1 s".to_string()
    } else if left < 90.0 {
        format!("about {left:.0} s")
    } else if left < 90.0 * 60.0 {
        format!("about {:.0} min", left / 60.0)
    } else {
        format!("about {:.1} h", left / 3600.0)
    };
    format!(", {text} left")
}

/// The live progress line of `critical` and `sweep` (without its carriage return).
pub fn critical_progress_text(p: CriticalProgress, seconds: f64) -> String {
    let sig4 = crate::report::sig4;
    let best = match (p.lower, p.upper) {
        (Some(lo), Some(up)) => format!("mu* in ({}, {}]", sig4(lo), sig4(up)),
        (None, Some(up)) => format!("best mu {}", sig4(up)),
        (Some(lo), None) => format!("no wedged configuration yet, mu* > {}", sig4(lo)),
        (None, None) => "no wedged configuration yet".to_string(),
    };
    let share = p.explored.clamp(0.0, 1.0);
    let pass = match p.bar {
        Some(bar) => format!("pass at mu <= {}: ", crate::report::sig4(bar)),
        None => String::new(),
    };
    // The start's run on the condensed problem: its numbers are that problem's, not yet mu*'s.
    let start = match p.condensed {
        Some(n) => format!("start, condensed onto {n} nodes: "),
        None => String::new(),
    };
    // The programs go inside the tree's parentheses: `(7065 nodes of about 19k, 15468 linear
    // programs)`.
    let programs = (p.programs > 0).then(|| format!("{} linear programs", p.programs));
    let counts: Vec<String> = tree_counts(p.nodes, share)
        .into_iter()
        .chain(programs)
        .collect();
    let tree = if counts.is_empty() {
        String::new()
    } else {
        format!(" ({})", counts.join(", "))
    };
    format!(
        "{start}{pass}explored {}{tree}, {best}, {seconds:.1} s",
        percent(share)
    )
}
