//! The result of `wedged critical` and `wedged sweep`: its JSON (fixed keys) and its summary.
//!
//! ```text
//! { "source": "p.toml", "dim": 2, "nodes": 4, "method": "bnb" | "enumerate" | "faces",
//!   "status": "wedged" | "never" | "incomplete", "complete": true, "stopped": null | "why",
//!   "mu_critical": 1.78 | null, "lower": 1.78 | null, "upper": 1.78 | null,
//!   "tol": 1e-9, "tol_achieved": 1e-7 | null,
//!   "witness": { "u": [..], "r": [..], "status": ["stick", ..], "pattern": ["contact", ..] } | null,
//!   "pattern": ["contact" | "separated" | "grazing", ..] | null,
//!   "thresholds": [ { "pattern": [..], "threshold": 1.9, "lower": 1.9 } ],
//!   "undecided": [ { "contact": [true | false, ..], "reason": ".." } ],
//!   "info": { every field of wedged::CriticalInfo, "peak_rss_bytes": 7340032 | null },
//!   "certified": true | false | null,                  (null without --certify)
//!   "certificate": { "upper": 1.78 | null, "refutations_checked": 148,
//!                    "refutations_failed": 0, "resolved": 0, "failures": [".."] } | null,
//!   "model": { .. },                                   (meshed bodies only, as in `enumerate`)
//!   "version": "0.1.0",
//!   "shard": { .. } }                                  (--shard parts only, as in `enumerate`)
//! ```
//!
//! - `status` `wedged`: `mu_critical` = `upper`, a witness (a solution of the wedged problem at
//!   `mu = upper`, checked) exists there, and no friction coefficient below `lower` wedges the
//!   body (certified by checked Farkas certificates): the true `mu*` is in `[lower, upper]`.
//!   `tol_achieved` = `(upper - lower) / upper`, the width actually certified, which may be wider
//!   than `tol`, the width asked: now and then (in 3D) the certificates stop at about 1e-7.
//! - `never`: certified that no friction coefficient gives a nontrivial wedged configuration;
//!   `mu_critical`, `lower`, `upper`, `tol_achieved`, `witness` and `pattern` are `null`.
//! - `incomplete` (`"complete": false`, `"stopped"` says why): a limit, Ctrl-C, or solver
//!   programs left undecided (listed in `undecided`). `upper` and `witness` may still be there
//!   (checked), but `mu_critical` is `null`; `lower`, when not `null`, is what the passes of
//!   the `bnb` search that finished before the stop proved: no friction coefficient at or
//!   below it wedges the body (`mu* > lower`), not narrowed to `tol`.
//!
//! `thresholds` (method `enumerate`, and so `wedged sweep`) lists each maximal pattern of the
//! enumeration at `info.mu_enumerated` with its own threshold (the least `mu` at which it is
//! realised; `lower` the certified end of its bracket), sorted by threshold; it is empty for the
//! other methods. `info.tol_achieved` is `null` when there is no bracket, like `tol_achieved`.
//! Vectors are in the local node frames, normal first, with `sum r_n = 1`.

use std::fmt::Write;
use std::path::Path;

use serde::Serialize;
use wedged::fe::Model;
use wedged::{Critical, CriticalSettings, CriticalStatus, NodeStatus, PatternThreshold, Problem};

mod info;

use crate::report::answer::fingerprint;
use crate::report::json::{ModelJson, ShardJson, UndecidedJson};
use crate::report::sig4;
use crate::report::summary::{
    codes, pattern_code, plural, seconds_text, status_code, status_legend, wrapped, PATTERN_LEGEND,
};
pub use info::CriticalInfoJson;

/// Witness nodes listed one per line; beyond, one character per node.
const NODE_LINES_UP_TO: usize = 24;
/// Thresholds listed before the rest are left to the JSON.
const THRESHOLD_LIMIT: usize = 50;

/// The whole JSON document of `wedged critical` (and `wedged sweep`).
#[derive(Debug, Serialize)]
pub struct CriticalReport<'a> {
    pub source: &'a str,
    pub dim: usize,
    pub nodes: usize,
    /// A floating body's free rigid motions (0 when it is held).
    pub rigid_modes: usize,
    pub method: &'static str,
    pub status: &'static str,
    pub complete: bool,
    pub stopped: Option<String>,
    pub mu_critical: Option<f64>,
    pub lower: Option<f64>,
    pub upper: Option<f64>,
    pub tol: f64,
    pub tol_achieved: Option<f64>,
    pub witness: Option<WitnessJson<'a>>,
    pub pattern: Option<Vec<&'static str>>,
    pub thresholds: Vec<ThresholdJson>,
    pub undecided: Vec<UndecidedJson<'a>>,
    pub info: CriticalInfoJson,
    /// `true` or `false` with `--certify` (every exact check passed or not), else `null`.
    pub certified: Option<bool>,
    /// The exact checks of `--certify` (`null` without it).
    pub certificate: Option<CertificateJson<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelJson>,
    pub version: &'static str,
    /// A part of a sharded run (`--shard I/N`), as in `enumerate`'s JSON.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shard: Option<ShardJson>,
}

/// The exact checks of `--certify` ([`wedged::critical::certify::CriticalCertificate`]).
#[derive(Debug, Serialize)]
pub struct CertificateJson<'a> {
    /// The least `f64` at which the exactly recomputed witness solves WP.
    pub upper: Option<f64>,
    pub refutations_checked: usize,
    pub refutations_failed: usize,
    /// Certificates that failed at first and passed when solved again at `lower`.
    pub resolved: usize,
    pub failures: &'a [String],
}

/// The solution at `mu = upper`.
#[derive(Debug, Serialize)]
pub struct WitnessJson<'a> {
    pub u: &'a [f64],
    pub r: &'a [f64],
    pub status: Vec<&'static str>,
    pub pattern: Vec<&'static str>,
}

/// A maximal pattern and its own threshold.
#[derive(Debug, Serialize)]
pub struct ThresholdJson {
    pub pattern: Vec<&'static str>,
    pub threshold: f64,
    pub lower: f64,
}

fn pattern_names(pattern: &[wedged::ContactPattern]) -> Vec<&'static str> {
    pattern.iter().map(|p| p.name()).collect()
}

impl<'a> CriticalReport<'a> {
    pub fn new(
        problem: &Problem,
        settings: &CriticalSettings,
        source: &'a str,
        result: &'a Critical,
        model: Option<&Model>,
    ) -> CriticalReport<'a> {
        let bracketed = result.status == CriticalStatus::Wedged && result.lower.is_some();
        CriticalReport {
            source,
            dim: problem.dim(),
            nodes: problem.nodes(),
            rigid_modes: problem.rigid_modes().ncols(),
            method: settings.method.name(),
            status: result.status.name(),
            complete: !matches!(result.status, CriticalStatus::Incomplete(_)),
            stopped: match result.status {
                CriticalStatus::Incomplete(stop) => Some(stop.to_string()),
                _ => None,
            },
            mu_critical: result.mu_critical,
            lower: result.lower,
            upper: result.upper,
            tol: settings.tol,
            tol_achieved: bracketed.then_some(result.info.tol_achieved),
            witness: result.witness.as_ref().map(|w| WitnessJson {
                u: &w.u,
                r: &w.r,
                status: w.status.iter().map(|s| s.name()).collect(),
                pattern: pattern_names(&w.pattern),
            }),
            pattern: result.witness.as_ref().map(|w| pattern_names(&w.pattern)),
            thresholds: result
                .thresholds
                .iter()
                .map(|t| ThresholdJson {
                    pattern: pattern_names(&t.pattern),
                    threshold: t.threshold,
                    lower: t.lower,
                })
                .collect(),
            undecided: result.undecided.iter().map(UndecidedJson::from).collect(),
            info: CriticalInfoJson::new(&result.info, bracketed),
            certified: result.certificate.as_ref().map(|c| c.certified),
            certificate: result.certificate.as_ref().map(|c| CertificateJson {
                upper: c.upper,
                refutations_checked: c.refutations_checked,
                refutations_failed: c.refutations_failed,
                resolved: c.resolved,
                failures: &c.failures,
            }),
            model: model.map(ModelJson::new),
            version: env!("CARGO_PKG_VERSION"),
            shard: result.shard.map(|s| {
                let settings = format!(
                    "critical {} {} {}",
                    settings.method.name(),
                    settings.tol.to_bits(),
                    settings.certify
                );
                ShardJson::new("critical", &s, fingerprint(problem, &settings))
            }),
        }
    }
}

/// The JSON text of a result, ending with a newline.
pub fn to_json(
    problem: &Problem,
    settings: &CriticalSettings,
    source: &str,
    result: &Critical,
    model: Option<&Model>,
) -> String {
    crate::report::json::layout(&CriticalReport::new(
        problem, settings, source, result, model,
    ))
}

/// Significant digits that show a bracket of relative width `width`: one more than the digits
/// its ends share, from 4 to 15.
pub fn digits_for(width: f64) -> usize {
    if width.is_nan() || width <= 0.0 {
        return 15;
    }
    // A width of 1e-7 in floating point may be just below it: not a digit more.
    ((-width.log10() - 1e-6).ceil() as i64 + 1).clamp(4, 15) as usize
}

/// Which way a printed bound is rounded, so that the printed bracket still holds the value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Round {
    Down,
    Up,
}

/// `v` (positive, finite) with `digits` significant digits, rounded `dir`; plain decimals from
/// 1e-4 to 1e9, else scientific.
pub fn bound(v: f64, digits: usize, dir: Round) -> String {
    if !(v.is_finite() && v > 0.0) {
        return format!("{v}");
    }
    let e = v.log10().floor() as i32;
    let shift = e - digits as i32 + 1;
    let scaled = v / 10f64.powi(shift);
    // Round-off in the scaling is not a digit of the value.
    let near = scaled.round();
    let rounded = if (scaled - near).abs() <= 1e-6 {
        near
    } else {
        match dir {
            Round::Down => scaled.floor(),
            Round::Up => scaled.ceil(),
        }
    };
    let value = rounded * 10f64.powi(shift);
    let s = if (-4..9).contains(&e) {
        let decimals = (-shift).max(0) as usize;
        format!("{value:.decimals$}")
    } else {
        format!("{value:.*e}", digits - 1)
    };
    trim(&s)
}

/// Strips trailing zeros of a decimal fraction (also before an exponent).
fn trim(s: &str) -> String {
    let (mantissa, exponent) = match s.split_once('e') {
        Some((m, x)) => (m, Some(x)),
        None => (s, None),
    };
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.')
    } else {
        mantissa
    };
    match exponent {
        Some(x) => format!("{mantissa}e{x}"),
        None => mantissa.to_string(),
    }
}

/// `mu*` with its bracket, as printed: `(mu*, lower, upper)`, to the digits the bracket's width
/// needs, the lower end rounded down and the upper end (and `mu*`, which is it) up.
pub fn bracket_text(lower: f64, upper: f64) -> (String, String, String) {
    let digits = digits_for((upper - lower) / upper);
    let up = bound(upper, digits, Round::Up);
    (up.clone(), bound(lower, digits, Round::Down), up)
}

/// `mu*` (a bracket's upper end) to the digits its bracket certifies ([`bracket_text`]), or
/// to nine decimals when there is no lower end.
pub fn mu_text(mu: f64, lower: Option<f64>) -> String {
    match lower {
        Some(lower) => bracket_text(lower, mu).0,
        None => format!("{mu:.9}"),
    }
}

/// The answer on one line: `mu* = X (certified bracket [L, U], relative width W)`, with a note
/// when the width certified is wider than asked; or the line of a body that never wedges.
pub fn answer_line(result: &Critical, tol: f64) -> Option<String> {
    match (result.status, result.lower, result.upper) {
        (CriticalStatus::Wedged, Some(lower), Some(upper)) => {
            let (mu, lo, up) = bracket_text(lower, upper);
            let width = result.info.tol_achieved;
            // (The width is a difference of two near numbers: round-off of 1e-7 of it.)
            let note = if width > tol * (1.0 + 1e-6) {
                format!("; asked {tol:e}: the certificates reach no closer")
            } else {
                String::new()
            };
            Some(format!(
                "mu* = {mu} (certified bracket [{lo}, {up}], relative width {width:.1e}{note})"
            ))
        }
        (CriticalStatus::Never, _, _) => Some(
            "No friction coefficient wedges this body (certified: the search is infeasible with \
             friction unlimited)."
                .to_string(),
        ),
        _ => None,
    }
}

/// What an incomplete run proved of `mu*`, as one phrase: the summary's `INCOMPLETE` line and
/// the `incomplete:` line on stderr both say it.
pub fn incomplete_bracket(result: &Critical) -> String {
    match (result.lower, result.upper) {
        (Some(lower), Some(upper)) => format!(
            "{} < mu* <= {} (a checked wedged configuration at the upper end; every contact set \
             refuted at the lower end by the passes of the search that finished)",
            bound(lower, 10, Round::Down),
            bound(upper, 10, Round::Up)
        ),
        (None, Some(upper)) => format!(
            "mu* <= {} (a checked wedged configuration there), but nothing below it is certified",
            super::upper_text(upper)
        ),
        (Some(lower), None) => format!(
            "no wedged configuration found yet; mu* > {} (every contact set refuted there by the \
             passes of the search that finished)",
            bound(lower, 10, Round::Down)
        ),
        (None, None) => "no wedged configuration found yet; nothing is claimed about mu*".into(),
    }
}

/// The human-readable summary; `json` is the JSON file written, if any.
pub fn render(
    problem: &Problem,
    settings: &CriticalSettings,
    source: &str,
    file_mu: Option<f64>,
    result: &Critical,
    json: Option<&Path>,
) -> String {
    let mut out = String::new();
    let start = match (settings.method, result.info.mu_enumerated, file_mu) {
        (wedged::CriticalMethod::Enumerate, _, Some(mu)) => {
            format!(", enumeration from the file's mu = {mu}")
        }
        (wedged::CriticalMethod::Enumerate, _, None) => {
            ", enumeration from mu = 1 (the file gives no mu)".to_string()
        }
        (wedged::CriticalMethod::Bnb, _, Some(mu)) => {
            format!(" (the file's mu = {mu} is only the search's first bar)")
        }
        (_, _, Some(_)) => " (the file's mu is not used)".to_string(),
        _ => String::new(),
    };
    let _ = writeln!(
        out,
        "problem {source}: dim {}, {}{}; critical friction coefficient by {}, tol {:e}{start}",
        problem.dim(),
        plural(problem.nodes(), "node", "nodes"),
        crate::report::summary::floating_note(problem),
        settings.method.name(),
        settings.tol
    );
    if let Some(s) = result.shard {
        let split = if s.units == 0 {
            "stopped before the search was split into units".to_string()
        } else {
            format!(
                "the search split at depth {} into {} units, {} of them here",
                s.split_depth, s.units, s.own_units
            )
        };
        let _ = writeln!(
            out,
            "shard {}/{}: {split}; this is this part's bracket: `wedged merge` the parts for mu*",
            s.index, s.count
        );
    }
    match (result.status, result.upper) {
        (CriticalStatus::Wedged | CriticalStatus::Never, _) => {
            // A shard proves its part of the search only: its lower end rules out that part's
            // contact sets, not the body's.
            let (part, below) = match result.shard {
                Some(_) => (
                    "this part: ",
                    "no contact set of this part of the search wedges",
                ),
                None => ("", "no friction coefficient wedges"),
            };
            if let Some(line) = answer_line(result, settings.tol) {
                let _ = writeln!(out, "{part}{line}");
            }
            if let (CriticalStatus::Wedged, Some(lower), Some(upper)) =
                (result.status, result.lower, result.upper)
            {
                let (_, lo, up) = bracket_text(lower, upper);
                wrapped(
                    &mut out,
                    2,
                    2,
                    &format!(
                        "(below {lo} {below} the body, by checked infeasibility certificates; \
                         at {up} the configuration below does, checked against the wedged \
                         problem)"
                    ),
                );
            }
        }
        (CriticalStatus::Incomplete(stop), _) => {
            let below = if result.witness.is_some() {
                "; the configuration is below"
            } else {
                ""
            };
            let _ = writeln!(
                out,
                "INCOMPLETE: {stop}; {}{below}",
                incomplete_bracket(result)
            );
        }
    }
    for u in &result.undecided {
        let set = crate::report::summary::contact_set(&u.contact);
        let _ = writeln!(
            out,
            "WARNING: the solver could not decide the contact set {{{set}}} ({}); mu* may be \
             below what was found",
            crate::one_line(&u.reason)
        );
    }
    if let (Some(w), Some(upper)) = (&result.witness, result.upper) {
        out.push('\n');
        witness_table(&mut out, problem, w, upper);
    }
    if !result.thresholds.is_empty() {
        out.push('\n');
        thresholds_table(&mut out, problem, result);
    }
    if let Some(c) = &result.certificate {
        certificate_lines(&mut out, c);
    }
    out.push('\n');
    info_lines(&mut out, problem, result);
    if let Some(path) = json {
        let _ = writeln!(out, "JSON written to {}", path.display());
    }
    out
}

/// What `--certify` found.
fn certificate_lines(out: &mut String, c: &wedged::critical::certify::CriticalCertificate) {
    let checked = plural(
        c.refutations_checked,
        "infeasibility certificate",
        "infeasibility certificates",
    );
    let witness = match c.upper {
        Some(u) => format!("the witness, recomputed exactly, solves WP at mu = {u}"),
        None => "no witness certified".to_string(),
    };
    if c.certified {
        wrapped(
            out,
            0,
            2,
            &format!("certified in exact rational arithmetic: {checked} re-checked; {witness}"),
        );
    } else {
        wrapped(
            out,
            0,
            2,
            &format!(
                "NOT CERTIFIED in exact rational arithmetic ({checked} re-checked, {} failed; \
                 {witness}):",
                c.refutations_failed
            ),
        );
        for f in &c.failures {
            wrapped(out, 2, 4, &format!("- {f}"));
        }
    }
}

/// The witness's nodes: one line each (status, gap, pressure, friction ratio), or for many nodes
/// one character each.
fn witness_table(out: &mut String, problem: &Problem, w: &wedged::CriticalWitness, upper: f64) {
    let (d, m) = (problem.dim(), problem.nodes());
    let _ = writeln!(
        out,
        "the wedged configuration at mu = {upper:.8} (normalised to sum r_n = 1; the slipping \
         nodes have |r_t| / r_n = mu):"
    );
    if m > NODE_LINES_UP_TO {
        let _ = writeln!(
            out,
            "  status of nodes 1-{m}, in groups of ten:  {}",
            codes(w.status.iter().map(|&s| status_code(s)))
        );
        let _ = writeln!(
            out,
            "  pattern:                                  {}",
            codes(w.pattern.iter().map(|&p| pattern_code(p)))
        );
        let _ = writeln!(out, "  ({}; {PATTERN_LEGEND})", status_legend(d));
        return;
    }
    let _ = writeln!(
        out,
        "  {:>4}  {:<9}  {:>10}  {:>10}  {:>11}",
        "node", "status", "u_n", "r_n", "|r_t|/r_n"
    );
    for i in 0..m {
        let (un, rn) = (w.u[d * i], w.r[d * i]);
        let rt = w.r[d * i + 1..d * i + d]
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        // Eight digits: a sticking node's ratio may differ from mu* only far down.
        let ratio = if rn > 0.0 {
            format!("{:.8}", rt / rn)
        } else {
            "-".to_string()
        };
        let status = w.status[i];
        let _ = writeln!(
            out,
            "  {:>4}  {:<9}  {:>10}  {:>10}  {:>11}",
            i + 1,
            status.name(),
            if status == NodeStatus::Separated {
                sig4(un)
            } else {
                "0".to_string()
            },
            sig4(rn),
            ratio
        );
    }
}

/// Each maximal pattern of the enumeration with its own threshold, by threshold.
fn thresholds_table(out: &mut String, problem: &Problem, result: &Critical) {
    let m = problem.nodes();
    let rows: &[PatternThreshold] = &result.thresholds;
    let mu_enumerated = result
        .info
        .mu_enumerated
        .map_or_else(|| "?".to_string(), sig4);
    wrapped(
        out,
        0,
        2,
        &format!(
            "{} at mu = {mu_enumerated}, each with its own threshold (the least mu at which it \
             is realised; below lower it is certified not to be), by threshold:",
            plural(rows.len(), "maximal pattern", "maximal patterns")
        ),
    );
    let width = rows
        .iter()
        .map(|t| (t.threshold - t.lower) / t.threshold)
        .fold(0.0f64, f64::max);
    let digits = digits_for(width);
    let index_width = rows.len().saturating_sub(1).to_string().len().max(1);
    let number_width = (digits + 3).max(9);
    let _ = writeln!(
        out,
        "  {:>index_width$}  {:<number_width$}  {:<number_width$}  pattern of nodes 1-{m}{}",
        "#",
        "threshold",
        "lower",
        if m > 10 { ", in groups of ten" } else { "" }
    );
    for (k, t) in rows.iter().enumerate().take(THRESHOLD_LIMIT) {
        let _ = writeln!(
            out,
            "  {k:>index_width$}  {:<number_width$}  {:<number_width$}  {}",
            bound(t.threshold, digits, Round::Up),
            bound(t.lower, digits, Round::Down),
            codes(t.pattern.iter().map(|&p| pattern_code(p)))
        );
    }
    if rows.len() > THRESHOLD_LIMIT {
        let _ = writeln!(
            out,
            "  ... and {} more (the first {THRESHOLD_LIMIT} are shown; --json writes them all)",
            rows.len() - THRESHOLD_LIMIT
        );
    }
    let _ = writeln!(out, "  ({PATTERN_LEGEND})");
}

/// The diagnostics: the search, the thresholds, the conic programs, the time.
fn info_lines(out: &mut String, problem: &Problem, result: &Critical) {
    let info = &result.info;
    let m = problem.nodes();
    let memory = crate::report::json::peak_memory_text();
    let _ = writeln!(
        out,
        "info: {}, {}{memory}",
        info.method,
        seconds_text(info.seconds)
    );
    let mut search = Vec::new();
    if info.groups > 1 {
        search.push(format!(
            "the contact nodes fall into {} groups that K does not couple, each searched on \
             its own (mu* is the least of theirs; the counts below are their sums)",
            info.groups
        ));
    }
    if let Some(mu) = info.mu_enumerated {
        search.push(format!(
            "{} enumerated at mu = {}",
            plural(
                info.patterns_enumerated as usize,
                "maximal pattern",
                "maximal patterns"
            ),
            sig4(mu)
        ));
    }
    if info.nodes_visited > 0 {
        let sets = if info.groups > 1 {
            "each group's contact sets".to_string()
        } else {
            format!("the 2^{m} contact sets")
        };
        search.push(format!(
            "branch and bound over {sets}: {} visited, {} pruned (certified infeasible)",
            plural(info.nodes_visited as usize, "node", "nodes"),
            plural(info.pruned_infeasible as usize, "subtree", "subtrees")
        ));
        if info.bound_tightenings > 0 {
            search.push(format!(
                "drive cuts from bounds tightened at {} (checked in floating point; \
                 --certify proves every prune exactly without them)",
                plural(info.bound_tightenings as usize, "node", "nodes")
            ));
        }
        if info.dive_nodes > 0 {
            search.push(format!(
                "a first leaf looked for by a dive of {}, leaves improved in {} of \
                 local search over contact sets",
                plural(info.dive_nodes as usize, "node", "nodes"),
                plural(info.improvement_steps as usize, "step", "steps")
            ));
        } else if info.condensed_nodes > 0 {
            // No dive: the run started from its condensed problem's answer.
            search.push(format!(
                "the first leaf from the answer of the problem condensed onto {} of its {m} \
                 nodes (mu* = {} there, {}; no dive), improved in {} of local search over \
                 contact sets",
                info.condensed_nodes,
                info.condensed_mu.map_or_else(|| "?".to_string(), sig4),
                seconds_text(info.condensed_seconds),
                plural(info.improvement_steps as usize, "step", "steps")
            ));
        } else if info.improvement_steps > 0 {
            // No dive: the run started from the caller's contact set (`--start`).
            search.push(format!(
                "the first leaf from the start's contact set (no dive), improved in {} of \
                 local search over contact sets",
                plural(info.improvement_steps as usize, "step", "steps")
            ));
        }
        if info.simplex_solves + info.simplex_fallbacks > 0 {
            search.push(format!(
                "{} by the warm-started simplex method, {} left to Clarabel",
                plural(
                    info.simplex_solves as usize,
                    "linear program",
                    "linear programs"
                ),
                info.simplex_fallbacks
            ));
            if info.simplex_relaxed > 0 {
                search.push(format!(
                    "{} decided normalised by the sum where their pressed program was undecided",
                    plural(info.simplex_relaxed as usize, "inner node", "inner nodes")
                ));
            }
        }
    } else if info.method == "faces" {
        let sets = if info.groups > 1 {
            "all of each group's contact sets".to_string()
        } else {
            format!("all 2^{m} contact sets")
        };
        search.push(format!(
            "{sets}, {} certified infeasible",
            info.pruned_infeasible
        ));
    }
    search.push(format!(
        "{} computed",
        plural(info.leaves_solved as usize, "threshold", "thresholds")
    ));
    wrapped(out, 2, 4, &format!("search: {}", search.join("; ")));
    let mut steps = Vec::new();
    if info.dinkelbach_steps > 0 {
        steps.push(plural(
            info.dinkelbach_steps as usize,
            "Dinkelbach step",
            "Dinkelbach steps",
        ));
    }
    if info.bisection_steps > 0 {
        steps.push(plural(
            info.bisection_steps as usize,
            "bisection step",
            "bisection steps",
        ));
    }
    steps.push(format!(
        "{} checked{}",
        plural(
            info.certificates as usize,
            "infeasibility certificate",
            "infeasibility certificates"
        ),
        if info.loosened > 0 {
            format!(
                " ({} taken further below a threshold than --tol asked)",
                info.loosened
            )
        } else {
            String::new()
        }
    ));
    wrapped(out, 2, 4, &format!("thresholds: {}", steps.join(", ")));
    let unsure = match (info.uncertain, result.status) {
        (0, _) => String::new(),
        (n, CriticalStatus::Incomplete(_)) => format!(", {n} undecided"),
        (n, _) => format!(", {n} undecided but not needed for the answer"),
    };
    wrapped(
        out,
        2,
        4,
        &format!(
            "{} solved ({} retried{unsure})",
            plural(info.socps as usize, "SOCP", "SOCPs"),
            info.retries
        ),
    );
}

#[cfg(test)]
mod tests;
