//! The human-readable summary printed on stdout: header, outcome, rays, cones, info.
//!
//! Ray and cone indices are 0-based, as in the JSON; nodes are numbered from 1, as in the
//! library's error messages. Up to [`FULL_NAMES_UP_TO`] nodes the statuses are spelt out in
//! columns; beyond, each node is one character, in groups of ten.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use wedged::fe::{ElementKind, Model, Plane};
use wedged::{ContactPattern, Enumeration, Info, NodeStatus, Outcome, Problem, Settings};

use crate::svg::sig4;

/// Contact nodes listed one per line in the model summary; beyond, the JSON has them.
const CONTACT_LIST_LIMIT: usize = 24;

/// Largest number of nodes whose statuses are printed as full names.
const FULL_NAMES_UP_TO: usize = 8;
/// Rays or cones listed before the rest are left to the JSON.
const LIST_LIMIT: usize = 50;
/// Entries of `rays_after_node` printed on the info line.
const INFO_LIST_LIMIT: usize = 20;

const STATUS_LEGEND: &str = "o separated, s stick, + slip+, - slip-, g grazing";
const PATTERN_LEGEND: &str = "C contact, o separated, g grazing";

fn status_code(s: NodeStatus) -> char {
    match s {
        NodeStatus::Separated => 'o',
        NodeStatus::Stick => 's',
        NodeStatus::SlipPlus => '+',
        NodeStatus::SlipMinus => '-',
        NodeStatus::Grazing => 'g',
    }
}

fn pattern_code(p: ContactPattern) -> char {
    match p {
        ContactPattern::Contact => 'C',
        ContactPattern::Separated => 'o',
        ContactPattern::Grazing => 'g',
    }
}

/// One character per node, a space after every ten.
fn codes(chars: impl Iterator<Item = char>) -> String {
    let mut s = String::new();
    for (i, c) in chars.enumerate() {
        if i > 0 && i % 10 == 0 {
            s.push(' ');
        }
        s.push(c);
    }
    s
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The summary of `result` for `problem` (read from `source`); `json` is the JSON file written,
/// if any.
pub fn render(
    problem: &Problem,
    settings: &Settings,
    source: &str,
    result: &Enumeration,
    json: Option<&Path>,
) -> String {
    let m = problem.nodes();
    let mut out = String::new();
    let _ = writeln!(
        out,
        "problem {source}: dim {}, {}, mu = {}, method {}",
        problem.dim(),
        plural(m, "node", "nodes"),
        problem.mu(),
        settings.method.name()
    );
    match result.outcome {
        Outcome::Incomplete(stop) => {
            let _ = writeln!(
                out,
                "INCOMPLETE: {stop} after {} of {m} nodes ({} rays held at the peak); nothing is \
                 claimed about the wedged configurations",
                result.info.rays_after_node.len(),
                result.info.peak_rays
            );
            if !result.rays.is_empty() {
                let _ = writeln!(
                    out,
                    "the {} found before the stop (checked, but not all of them):",
                    plural(result.rays.len(), "ray", "rays")
                );
                out.push('\n');
                rays_table(&mut out, problem, result);
            }
        }
        Outcome::NotWedged => {
            let _ = writeln!(
                out,
                "no wedged configuration: only the trivial solution u = r = 0 exists at mu = {}",
                problem.mu()
            );
        }
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
            rays_table(&mut out, problem, result);
            out.push('\n');
            cones_table(&mut out, result);
        }
    }
    out.push('\n');
    let _ = writeln!(out, "info: {}", info_line(&result.info));
    if let Some(path) = json {
        let _ = writeln!(out, "JSON written to {}", path.display());
    }
    out
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
pub(crate) fn ranges(indices: &[usize]) -> String {
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

fn seconds_text(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{:.0} us", s * 1e6)
    }
}

/// Diagnostics worth reading, on one line; the zero counters of other methods are left out.
fn info_line(info: &Info) -> String {
    let mut parts = vec![seconds_text(info.seconds)];
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
            wedged::enumerate::bytes_text(info.peak_bytes)
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
    parts.join("; ")
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
    let _ = writeln!(
        out,
        "  {} dofs: {}{clamped_contact}, {}, {}",
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
    result: &Enumeration,
    vtk: Option<&Path>,
    svg: Option<&Path>,
    written: &[PathBuf],
) -> String {
    let mut out = String::new();
    for (dir, ext, what) in [(vtk, "vtu", "ParaView file"), (svg, "svg", "picture")] {
        let Some(dir) = dir else { continue };
        let n = written
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == ext))
            .count();
        if matches!(result.outcome, Outcome::Incomplete(_)) {
            let _ = writeln!(
                out,
                "the run is incomplete, so no .{ext} file was written to {}",
                dir.display()
            );
        } else if result.cones.is_empty() {
            let _ = writeln!(
                out,
                "no wedged cone, so no .{ext} file was written to {}",
                dir.display()
            );
        } else {
            let _ = writeln!(
                out,
                "{} written to {} (cone-N.{ext}, one {what} per cone)",
                plural(n, &format!(".{ext} file"), &format!(".{ext} files")),
                dir.display()
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_shorten_runs() {
        assert_eq!(ranges(&[]), "");
        assert_eq!(ranges(&[4]), "4");
        assert_eq!(ranges(&[0, 1, 2, 3, 7, 9, 10]), "0-3 7 9 10");
    }

    /// A made-up result with many nodes and rays: the layout only, not the mathematics.
    #[test]
    fn many_nodes_and_rays_are_compact_and_cut() {
        use wedged::{Cone, Ray};
        let m = 12;
        let problem = Problem::new(2, nalgebra::DMatrix::identity(2 * m, 2 * m), 1.0).unwrap();
        let all = [
            NodeStatus::Separated,
            NodeStatus::Stick,
            NodeStatus::SlipPlus,
            NodeStatus::SlipMinus,
            NodeStatus::Grazing,
        ];
        let rays: Vec<Ray> = (0..60)
            .map(|k| Ray {
                u: (0..2 * m).map(|i| (i + k) as f64 * 1e-3).collect(),
                r: vec![0.0; 2 * m],
                status: (0..m).map(|i| all[(i + k) % 5]).collect(),
            })
            .collect();
        let cones = vec![Cone {
            rays: vec![0, 1, 2, 7],
            pattern: vec![ContactPattern::Contact; m],
        }];
        let result = Enumeration {
            outcome: Outcome::Wedged,
            rays,
            cones,
            info: Info {
                rays_after_node: (0..30).collect(),
                ..Info::default()
            },
        };
        let text = render(&problem, &Settings::default(), "big.toml", &result, None);
        assert!(text.contains("60 wedged configurations"), "{text}");
        assert!(
            text.contains("\n   0   2.000e-2  os+-gos+-g os\n"),
            "{text}"
        );
        assert!(text.contains("... and 10 more rays"), "{text}");
        assert!(text.contains(STATUS_LEGEND), "{text}");
        assert!(text.contains("  0  CCCCCCCCCC CC  0-2 7"), "{text}");
        assert!(text.contains("(10 more in --json)"), "{text}");
        assert!(text.lines().all(|l| l.len() < 120), "{text}");
    }

    #[test]
    fn codes_group_by_ten() {
        assert_eq!(codes("abcdefghijkl".chars()), "abcdefghij kl");
    }
}
