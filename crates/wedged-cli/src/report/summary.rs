//! The human-readable summary printed on stdout: header, outcome, rays and cones (ray methods)
//! or maximal sign patterns (pattern methods), diagnostics.
//!
//! Ray, cone and pattern indices are 0-based, as in the JSON; nodes are numbered from 1, as in
//! the library's error messages. In the ray table, up to `FULL_NAMES_UP_TO` nodes the statuses
//! are spelt out in columns; beyond, and always in the pattern table, each node is one
//! character, in groups of ten.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use wedged::fe::{ElementKind, Model, Plane};
use wedged::patterns::{PatternMethod, Patterns};
use wedged::{ContactPattern, Enumeration, Method, NodeStatus, Outcome, Problem, Stop};

use crate::report::answer::{Answer, Certified, Choice};

use crate::report::sig4;
use info::{info_line, pattern_info};
#[cfg(test)]
use info::{power_of_two, pruned_fraction};

/// Contact nodes listed one per line in the model summary; beyond, the JSON has them.
const CONTACT_LIST_LIMIT: usize = 24;

/// Largest number of nodes whose statuses are printed as full names.
const FULL_NAMES_UP_TO: usize = 8;
/// Rays or cones listed before the rest are left to the JSON.
const LIST_LIMIT: usize = 50;

const STATUS_LEGEND: &str = "o separated, s stick, + slip+, - slip-, g grazing";
/// The legend of 3D statuses: slip is on the round friction cone, in no particular direction.
const STATUS_LEGEND_3D: &str = "o separated, s stick, ~ slip, g grazing";
pub const PATTERN_LEGEND: &str = "C contact, o separated, g grazing";

pub fn status_code(s: NodeStatus) -> char {
    match s {
        NodeStatus::Separated => 'o',
        NodeStatus::Stick => 's',
        NodeStatus::SlipPlus => '+',
        NodeStatus::SlipMinus => '-',
        NodeStatus::Slip => '~',
        NodeStatus::Grazing => 'g',
    }
}

/// The legend of the status characters of a `dim`-dimensional problem.
pub fn status_legend(dim: usize) -> &'static str {
    if dim == 3 {
        STATUS_LEGEND_3D
    } else {
        STATUS_LEGEND
    }
}

pub fn pattern_code(p: ContactPattern) -> char {
    match p {
        ContactPattern::Contact => 'C',
        ContactPattern::Separated => 'o',
        ContactPattern::Grazing => 'g',
    }
}

/// One character per node, a space after every ten.
pub fn codes(chars: impl Iterator<Item = char>) -> String {
    let mut s = String::new();
    for (i, c) in chars.enumerate() {
        if i > 0 && i % 10 == 0 {
            s.push(' ');
        }
        s.push(c);
    }
    s
}

/// Lines of the diagnostics are wrapped at this width.
pub const WRAP: usize = 100;

/// Writes `text` as lines of at most [`WRAP`] characters (words are not split), the first
/// indented by `first`, the others by `rest` spaces.
pub fn wrapped(out: &mut String, first: usize, rest: usize, text: &str) {
    let mut line = " ".repeat(first);
    let mut empty = true;
    for word in text.split_whitespace() {
        if !empty && line.len() + 1 + word.len() > WRAP {
            out.push_str(&line);
            out.push('\n');
            line = " ".repeat(rest);
            empty = true;
        }
        if !empty {
            line.push(' ');
        }
        line.push_str(word);
        empty = false;
    }
    out.push_str(&line);
    out.push('\n');
}

/// `", floating (3 free rigid motions)"` for a floating body, nothing for a held one. The
/// pictures and files show the displacement the programs chose among `u + R a` (README,
/// "Floating bodies").
pub fn floating_note(problem: &wedged::Problem) -> String {
    match problem.rigid_modes().ncols() {
        0 => String::new(),
        k => format!(
            ", floating ({})",
            plural(k, "free rigid motion", "free rigid motions")
        ),
    }
}

pub fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The summary of `answer` for `problem` (read from `source`); `json` is the JSON file written,
/// if any.
pub fn render(
    problem: &Problem,
    choice: &Choice,
    source: &str,
    answer: &Answer,
    json: Option<&Path>,
) -> String {
    let mut out = String::new();
    let faces = match choice.pyramid_faces() {
        Some(k) if problem.dim() == 3 => format!(" ({k} faces)"),
        _ => String::new(),
    };
    let _ = writeln!(
        out,
        "problem {source}: dim {}, {}{}, mu = {}, method {}{faces}",
        problem.dim(),
        plural(problem.nodes(), "node", "nodes"),
        floating_note(problem),
        problem.mu(),
        choice.name()
    );
    if let Some(s) = answer.shard() {
        let _ = writeln!(
            out,
            "shard {}/{}: the search split at depth {} into {} units, {} of them here \
             (finding the split took {} search nodes, as in every shard); these are this \
             part's pieces: `wedged merge` the parts for the answer",
            s.index, s.count, s.split_depth, s.units, s.own_units, s.split_nodes
        );
    }
    match answer {
        Answer::Rays(result) => render_rays(&mut out, problem, choice, result),
        Answer::Patterns(result) => render_patterns(&mut out, problem, choice, result),
    }
    if let Some(path) = json {
        let _ = writeln!(out, "JSON written to {}", path.display());
    }
    out
}

/// The result of `--certify`: one line when every exact check passed, else a WARNING line per
/// failed check.
pub fn certification(c: &Certified) -> String {
    let mut out = String::new();
    if !c.certified() {
        for failure in c.failures() {
            let _ = writeln!(out, "WARNING: exact certification failed: {failure}");
        }
        return out;
    }
    let line = match c {
        Certified::Rays(c) => {
            let complete = match c.complete {
                Some(true) => "; complete: equal to the exact enumeration".to_string(),
                _ => format!(
                    "; completeness not checked (more than {} nodes, or an incomplete run; \
                     --exact gives a complete answer)",
                    wedged::certify::COMPLETENESS_MAX_NODES
                ),
            };
            format!(
                "certified in exact rational arithmetic: {}, {}{complete}",
                plural(c.rays_checked, "ray", "rays"),
                plural(c.cones_checked, "cone", "cones")
            )
        }
        Certified::Patterns(c) => format!(
            "certified in exact rational arithmetic: {} recomputed exactly, {} behind every \
             decision of the search; complete: these are all the maximal patterns",
            plural(c.witnesses_checked, "witness", "witnesses"),
            plural(
                c.refutations_checked,
                "infeasibility certificate",
                "infeasibility certificates"
            )
        ),
    };
    wrapped(&mut out, 0, 2, &line);
    out
}

/// The outcome, the tables and the info line of a ray method.
fn render_rays(out: &mut String, problem: &Problem, choice: &Choice, result: &Enumeration) {
    let m = problem.nodes();
    match result.outcome {
        Outcome::Incomplete(stop) => {
            if by_double_description(choice) {
                let _ = writeln!(
                    out,
                    "INCOMPLETE: {stop} after {} of {m} nodes ({} rays held at the peak); \
                     nothing is claimed about the wedged configurations",
                    result.info.rays_after_node.len(),
                    result.info.peak_rays
                );
            } else {
                let _ = writeln!(
                    out,
                    "INCOMPLETE: {stop}; nothing is claimed about the wedged configurations not \
                     reported"
                );
            }
            if !result.rays.is_empty() {
                let _ = writeln!(
                    out,
                    "the {} found before the stop (checked, but not all of them):",
                    plural(result.rays.len(), "ray", "rays")
                );
                out.push('\n');
                rays_table(out, problem, result);
            }
        }
        Outcome::NotWedged => not_wedged(out, problem),
        Outcome::Wedged => {
            let _ = writeln!(
                out,
                "{} in {}",
                plural(
                    result.rays.len(),
                    "wedged configuration (complementary extreme ray)",
                    "wedged configurations (complementary extreme rays)"
                ),
                plural(result.cones.len(), "convex piece", "convex pieces")
            );
            out.push('\n');
            rays_table(out, problem, result);
            out.push('\n');
            cones_table(out, result);
        }
    }
    out.push('\n');
    wrapped(out, 0, 2, &format!("info: {}", info_line(&result.info)));
}

/// The line of a complete run that found nothing but the trivial solution.
fn not_wedged(out: &mut String, problem: &Problem) {
    let _ = writeln!(
        out,
        "no wedged configuration: only the trivial solution u = r = 0 exists at mu = {}",
        problem.mu()
    );
}

/// The outcome, the warnings, the table and the diagnostics of a pattern method.
fn render_patterns(out: &mut String, problem: &Problem, choice: &Choice, result: &Patterns) {
    // Streamed patterns (`--jsonl`) are counted, not kept.
    let n = result.patterns.len() + result.info.streamed as usize;
    match result.outcome {
        Outcome::Incomplete(Stop::Undecided) => {
            let _ = writeln!(
                out,
                "INCOMPLETE: {} (see the warnings); {} found, but patterns below the undecided \
                 contact sets may be missing",
                Stop::Undecided,
                plural(n, "maximal sign pattern was", "maximal sign patterns were")
            );
        }
        Outcome::Incomplete(stop) if n > 0 && is_search(choice) => {
            // pattern-search tests each leaf's pattern for maximality on its own.
            let _ = writeln!(
                out,
                "INCOMPLETE: {stop}; nothing is claimed about the patterns not reported, and the \
                 {} found before the stop were each realised, checked and tested maximal",
                plural(n, "pattern", "patterns")
            );
        }
        Outcome::Incomplete(stop) => {
            let _ = writeln!(
                out,
                "INCOMPLETE: {stop}; nothing is claimed about the patterns not reported{}",
                if n > 0 {
                    format!(
                        ", and the {} found before the stop (realised and checked) may not all \
                         be maximal",
                        plural(n, "pattern", "patterns")
                    )
                } else {
                    String::new()
                }
            );
        }
        Outcome::NotWedged => not_wedged(out, problem),
        Outcome::Wedged => {
            let _ = writeln!(
                out,
                "{} (the convex pieces of the set of wedged configurations)",
                plural(n, "maximal sign pattern", "maximal sign patterns")
            );
        }
    }
    for u in &result.undecided {
        let set = contact_set(&u.contact);
        let _ = writeln!(
            out,
            "WARNING: the solver could not decide the contact set {{{set}}} ({}); the patterns \
             below it may be missing",
            crate::one_line(&u.reason)
        );
    }
    if !result.patterns.is_empty() {
        out.push('\n');
        patterns_table(out, problem, result);
    }
    out.push('\n');
    pattern_info(out, problem, choice, result);
}

/// Whether the rays come from a double description that adds the nodes one by one (its
/// progress is "after k of m nodes").
pub fn by_double_description(choice: &Choice) -> bool {
    matches!(choice, Choice::Rays(s) if matches!(s.method, Method::PrunedDd | Method::FullDd))
}

fn is_search(choice: &Choice) -> bool {
    matches!(choice, Choice::Patterns(s) if s.method == PatternMethod::Search)
}

/// The line that says where `--jsonl` wrote the pieces.
pub fn streamed(result: &Patterns, path: &Path) -> String {
    format!(
        "{} written to {} as found (one JSON object per line)\n",
        plural(
            result.info.streamed as usize,
            "maximal sign pattern",
            "maximal sign patterns"
        ),
        path.display()
    )
}

/// One row per maximal pattern: the widest gap and the margin of its witness, and one status
/// character per node.
fn patterns_table(out: &mut String, problem: &Problem, result: &Patterns) {
    let m = problem.nodes();
    let d = problem.dim();
    wrapped(
        out,
        0,
        2,
        "maximal sign patterns (a witness in each piece, normalised to sum r_n = 1; max u_n is \
         its widest gap, margin its smallest positive entry):",
    );
    let width = result
        .patterns
        .len()
        .saturating_sub(1)
        .to_string()
        .len()
        .max(1);
    let _ = writeln!(
        out,
        "  {:>width$}  {:>9}  {:>9}  status at the witness of nodes 1-{m}{}",
        "#",
        "max u_n",
        "margin",
        if m > 10 { ", in groups of ten" } else { "" }
    );
    for (index, pattern) in result.patterns.iter().enumerate().take(LIST_LIMIT) {
        let max_gap = (0..m)
            .filter(|&i| pattern.status[i] == NodeStatus::Separated)
            .map(|i| pattern.u[d * i])
            .fold(0.0_f64, f64::max);
        let gap = if max_gap > 0.0 {
            format!("{max_gap:.3e}")
        } else {
            "0".to_string()
        };
        let _ = writeln!(
            out,
            "  {index:>width$}  {gap:>9}  {:>9.3e}  {}",
            pattern.margin,
            codes(pattern.status.iter().map(|&s| status_code(s)))
        );
    }
    more(out, result.patterns.len(), "patterns");
    wrapped(
        out,
        2,
        3,
        &format!(
            "({}; a pattern's contact nodes are the pressed ones: {})",
            status_legend(d),
            if d == 3 { "s and ~" } else { "s, + and -" }
        ),
    );
}

fn rays_table(out: &mut String, problem: &Problem, result: &Enumeration) {
    let m = problem.nodes();
    let d = problem.dim();
    let _ = writeln!(
        out,
        "rays (wedged configurations normalised to sum r_n = 1; max u_n is the widest gap):"
    );
    let width = result.rays.len().saturating_sub(1).to_string().len().max(1);
    let full = m <= FULL_NAMES_UP_TO;
    let mut header = format!("  {:>width$}  {:>9}  ", "#", "max u_n");
    if full {
        for i in 1..=m {
            let _ = write!(header, "{:<9}  ", format!("node {i}"));
        }
    } else {
        let _ = write!(header, "status of nodes 1-{m}, in groups of ten");
    }
    let _ = writeln!(out, "{}", header.trim_end());
    for (index, ray) in result.rays.iter().enumerate().take(LIST_LIMIT) {
        let max_gap = (0..m)
            .filter(|&i| ray.status[i] == NodeStatus::Separated)
            .map(|i| ray.u[d * i])
            .fold(0.0_f64, f64::max);
        let gap = if max_gap > 0.0 {
            format!("{max_gap:.3e}")
        } else {
            "0".to_string()
        };
        let mut line = format!("  {index:>width$}  {gap:>9}  ");
        if full {
            for s in &ray.status {
                let _ = write!(line, "{:<9}  ", s.name());
            }
        } else {
            line.push_str(&codes(ray.status.iter().map(|&s| status_code(s))));
        }
        let _ = writeln!(out, "{}", line.trim_end());
    }
    more(out, result.rays.len(), "rays");
    if !full {
        let _ = writeln!(out, "  ({STATUS_LEGEND})");
    }
}

fn cones_table(out: &mut String, result: &Enumeration) {
    let _ = writeln!(
        out,
        "convex pieces (every nonnegative combination of a piece's rays is a wedged configuration):"
    );
    let width = result
        .cones
        .len()
        .saturating_sub(1)
        .to_string()
        .len()
        .max(1);
    let pattern_width = result
        .cones
        .first()
        .map_or(0, |c| {
            codes(c.pattern.iter().map(|&p| pattern_code(p))).len()
        })
        .max("pattern".len());
    let _ = writeln!(
        out,
        "  {:>width$}  {:<pattern_width$}  rays",
        "#", "pattern"
    );
    for (index, cone) in result.cones.iter().enumerate().take(LIST_LIMIT) {
        let pattern = codes(cone.pattern.iter().map(|&p| pattern_code(p)));
        let _ = writeln!(
            out,
            "  {index:>width$}  {pattern:<pattern_width$}  {}",
            ranges(&cone.rays)
        );
    }
    more(out, result.cones.len(), "pieces");
    let _ = writeln!(out, "  ({PATTERN_LEGEND})");
}

fn more(out: &mut String, total: usize, what: &str) {
    if total > LIST_LIMIT {
        let _ = writeln!(
            out,
            "  ... and {} more {what} (the first {LIST_LIMIT} are shown; --json writes them all)",
            total - LIST_LIMIT
        );
    }
}

/// Increasing indices with runs of three or more shortened: `0-3 7 9 10`.
/// A contact set (one flag per node) as text: "no node", "node 3", "nodes 1-4, 7".
pub fn contact_set(contact: &[bool]) -> String {
    let nodes: Vec<usize> = (0..contact.len())
        .filter(|&i| contact[i])
        .map(|i| i + 1)
        .collect();
    match nodes.len() {
        0 => "no node".to_string(),
        1 => format!("node {}", ranges(&nodes)),
        _ => format!("nodes {}", ranges(&nodes)),
    }
}

pub fn ranges(indices: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let mut j = i;
        while j + 1 < indices.len() && indices[j + 1] == indices[j] + 1 {
            j += 1;
        }
        parts.push(if j > i + 1 {
            format!("{}-{}", indices[i], indices[j])
        } else if j == i + 1 {
            format!("{} {}", indices[i], indices[j])
        } else {
            indices[i].to_string()
        });
        i = j + 1;
    }
    parts.join(" ")
}

pub fn seconds_text(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.0} us", s * 1e6)
    }
}

fn vector(v: &[f64]) -> String {
    format!(
        "({})",
        v.iter().map(|&x| sig4(x)).collect::<Vec<_>>().join(", ")
    )
}

/// The finite-element model: mesh, material, boundary, condensation.
pub fn model(source: &str, model: &Model) -> String {
    let mesh = model.mesh();
    let dim = mesh.dim();
    let b = model.boundary();
    let stats = model.stats();
    let mut out = String::new();
    let mut kinds: Vec<(ElementKind, usize)> = Vec::new();
    for e in mesh.elements() {
        match kinds.iter_mut().find(|(k, _)| *k == e.kind) {
            Some((_, n)) => *n += 1,
            None => kinds.push((e.kind, 1)),
        }
    }
    let kinds = kinds
        .iter()
        .map(|(k, n)| format!("{n} {}{}", k.name(), if *n == 1 { "" } else { "s" }))
        .collect::<Vec<_>>()
        .join(", ");
    let material = model.material();
    let plane = match (dim, material.plane()) {
        (3, _) => "3D",
        (_, Plane::Strain) => "plane strain",
        (_, Plane::Stress) => "plane stress",
    };
    let _ = writeln!(
        out,
        "model {source}: {dim}D mesh, {}, {kinds}; {plane}, E = {}, nu = {}",
        plural(mesh.node_count(), "node", "nodes"),
        sig4(material.young()),
        sig4(material.poisson())
    );
    let clamped_contact = if b.clamped_contact > 0 {
        format!(
            " ({} of the contact groups clamped, so not contact nodes)",
            plural(b.clamped_contact, "node", "nodes")
        )
    } else {
        String::new()
    };
    // A floating body: the rigid motions that nothing stops (README, "Floating bodies").
    let floating = match model.rigid_modes().ncols() {
        0 => String::new(),
        k => format!(
            "; the body floats: {} free",
            plural(k, "rigid motion", "rigid motions")
        ),
    };
    let _ = writeln!(
        out,
        "  {} dofs: {}{clamped_contact}, {}, {}{floating}",
        stats.dofs,
        plural(b.contact_nodes.len(), "contact node", "contact nodes"),
        plural(b.clamped.len(), "clamped node", "clamped nodes"),
        plural(b.rollers.len(), "roller node", "roller nodes"),
    );
    let _ = writeln!(
        out,
        "  condensed {} unknowns onto {} in {} (assembly {}, sparse Cholesky {} with {} \
         nonzeros in K_oo, Schur complement {})",
        stats.eliminated,
        dim * stats.contact_nodes,
        seconds_text(stats.seconds_assembly + stats.seconds_factor + stats.seconds_schur),
        seconds_text(stats.seconds_assembly),
        seconds_text(stats.seconds_factor),
        stats.nnz_oo,
        seconds_text(stats.seconds_schur),
    );
    let m = b.contact_nodes.len();
    let _ = writeln!(
        out,
        "  contact nodes (WP node: mesh node at position, inward normal n{}):",
        if dim == 2 {
            ", tangent t = n turned +90 degrees"
        } else {
            "; t1, t2 in the JSON"
        }
    );
    for (i, (&a, f)) in b
        .contact_nodes
        .iter()
        .zip(&b.frames)
        .enumerate()
        .take(CONTACT_LIST_LIMIT)
    {
        let x = &mesh.coords()[a];
        let _ = writeln!(
            out,
            "    {:>4}: mesh node {} at {}, n = {}",
            i + 1,
            a + 1,
            vector(&x[..dim]),
            vector(&f.n[..dim])
        );
    }
    if m > CONTACT_LIST_LIMIT {
        let _ = writeln!(out, "    ... {} more in the JSON", m - CONTACT_LIST_LIMIT);
    }
    out.push('\n');
    out
}

/// Which VTU and SVG files were written.
pub fn files(
    answer: &Answer,
    vtk: Option<&Path>,
    svg: Option<&Path>,
    written: &[PathBuf],
) -> String {
    let mut out = String::new();
    let (none, stem, each) = match answer {
        Answer::Rays(_) => ("no wedged cone", "cone", "cone"),
        Answer::Patterns(_) => ("no wedged pattern", "pattern", "maximal pattern"),
    };
    for (dir, ext, what) in [(vtk, "vtu", "ParaView file"), (svg, "svg", "picture")] {
        let Some(dir) = dir else { continue };
        let n = written
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == ext))
            .count();
        if matches!(answer.outcome(), Outcome::Incomplete(_)) {
            let _ = writeln!(
                out,
                "the run is incomplete, so no .{ext} file was written to {}",
                dir.display()
            );
        } else if n == 0 {
            let _ = writeln!(
                out,
                "{none}, so no .{ext} file was written to {}",
                dir.display()
            );
        } else {
            let collection = if ext == "vtu" {
                "; pieces.pvd opens them all in ParaView, piece N at time step N"
            } else {
                ""
            };
            let _ = writeln!(
                out,
                "{} written to {} ({stem}-N.{ext}, one {what} per {each}{collection})",
                plural(n, &format!(".{ext} file"), &format!(".{ext} files")),
                dir.display()
            );
        }
    }
    out
}

mod info;
#[cfg(test)]
mod tests;
