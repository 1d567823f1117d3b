//! Per-piece output files of a meshed problem, one per convex piece of the solution set, `N`
//! being the piece's 0-based index in the summary and the JSON (zero-padded to a common width, so
//! that files sort in order):
//!
//! - ray methods: `cone-N.vtu` (ParaView) and `cone-N.svg` (a picture) per wedged cone, showing
//!   the cone's centroid (the mean of its rays, a solution in its relative interior, normalised
//!   to `sum r_n = 1`) mapped back to the mesh; the VTU files also carry each ray's displacement;
//! - pattern methods: `pattern-N.vtu` and `pattern-N.svg` per maximal sign pattern, showing the
//!   pattern's witness (`wedged::patterns::Pattern::u`, in the relative interior of its piece)
//!   with the statuses at the witness;
//! - with `--vtk`, also `pieces.pvd`: a ParaView collection of the run's VTU files, piece `N`
//!   at time step `N`, so that ParaView opens the whole answer at once and steps through it.

use std::fs;
use std::path::{Path, PathBuf};

use wedged::fe::{Configuration, Model};
use wedged::patterns::Patterns;
use wedged::{Enumeration, Problem};

use crate::report::answer::Answer;

use crate::draw::svg::svg_string;
use crate::draw::vtk::{vtu_bytes, View};
use crate::report::files::write_atomic;

/// Creates `dir` (and its parents) and removes the `cone-N.<extension>` and
/// `pattern-N.<extension>` files of an earlier run, and with them its collection file, so that
/// the directory holds exactly this run's pieces. Called before the run, so that an unusable directory fails early.
pub fn prepare_dir(dir: &Path, option: &str, extension: &str) -> Result<(), String> {
    crate::report::files::create_output_dir(dir, option)?;
    let entries = fs::read_dir(dir)
        .map_err(|e| format!("{}: cannot read the {option} directory: {e}", dir.display()))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if is_piece_file(&name, extension) || (extension == "vtu" && name == COLLECTION) {
            fs::remove_file(entry.path()).map_err(|e| {
                format!(
                    "{}: cannot remove the old {}: {e}",
                    entry.path().display(),
                    name
                )
            })?;
        }
    }
    Ok(())
}

/// `cone-<digits>.<extension>` or `pattern-<digits>.<extension>`.
fn is_piece_file(name: &str, extension: &str) -> bool {
    name.strip_prefix("cone-")
        .or_else(|| name.strip_prefix("pattern-"))
        .and_then(|rest| rest.strip_suffix(extension))
        .and_then(|rest| rest.strip_suffix('.'))
        .is_some_and(|digits| !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()))
}

/// The collection file of `--vtk` ([`collection`]).
pub const COLLECTION: &str = "pieces.pvd";

/// Writes the files of every piece (cone or pattern) and, with `vtk`, their collection;
/// returns the paths written.
pub fn write_pieces(
    model: &Model,
    problem: &Problem,
    answer: &Answer,
    vtk: Option<&Path>,
    svg: Option<&Path>,
) -> Result<Vec<PathBuf>, String> {
    let mut written = match answer {
        Answer::Rays(result) => write_cones(model, problem, result, vtk, svg),
        Answer::Patterns(result) => write_patterns(model, problem, result, vtk, svg),
    }?;
    if let Some(dir) = vtk {
        let pieces: Vec<(f64, &Path)> = written
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "vtu"))
            .enumerate()
            .map(|(step, p)| (step as f64, p.as_path()))
            .collect();
        if !pieces.is_empty() {
            let path = dir.join(COLLECTION);
            write_atomic(&path, collection(&pieces).as_bytes(), "ParaView collection")
                .map_err(|e| e.to_string())?;
            written.push(path);
        }
    }
    Ok(written)
}

/// A ParaView collection (`.pvd`) of `steps`: each file (in one directory, named relative to
/// it) at its time step (`pieces.pvd` and `study.pvd`: the index; `sweep.pvd`: `mu`).
pub fn collection(steps: &[(f64, &Path)]) -> String {
    let mut out = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
         byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for (step, file) in steps {
        let name = file
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        out.push_str(&format!(
            "    <DataSet timestep=\"{step}\" part=\"0\" file=\"{name}\"/>\n"
        ));
    }
    out.push_str("  </Collection>\n</VTKFile>\n");
    out
}

/// Writes the files of every maximal pattern, from its witness; returns the paths written.
fn write_patterns(
    model: &Model,
    problem: &Problem,
    result: &Patterns,
    vtk: Option<&Path>,
    svg: Option<&Path>,
) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    let count = result.patterns.len();
    let width = count.saturating_sub(1).to_string().len();
    for (c, pattern) in result.patterns.iter().enumerate() {
        let state = model.recover(&pattern.u);
        let status = &pattern.status;
        let pressed = status.iter().filter(|s| s.pressed()).count();
        let sliding = status
            .iter()
            .filter(|s| s.pressed() && **s != wedged::NodeStatus::Stick)
            .count();
        let separated = status.iter().filter(|s| s.gap_open()).count();
        let title = format!(
            "pattern #{c} of {count}, mu = {}: {pressed} of {} contact nodes pressed ({sliding} \
             slip), {separated} separated; witness margin {}",
            problem.mu(),
            status.len(),
            crate::report::sig4(pattern.margin)
        );
        let view = View {
            mesh: model.mesh(),
            boundary: model.boundary(),
            status,
            state: &state,
            rays: &[],
            title,
        };
        let stem = format!("pattern-{c:0width$}");
        write_view(&view, &stem, vtk, svg, &mut written)?;
    }
    Ok(written)
}

/// Writes `path`, the VTU file of one wedged configuration of `model` given by its contact
/// displacement `u` and statuses (a witness of `critical`, `sweep` or `study`). A view that
/// fails its own check is a bug (exit 1); a file that cannot be written, bad input (exit 2).
pub fn write_witness_vtu(
    model: &Model,
    u: &[f64],
    status: &[wedged::NodeStatus],
    title: String,
    path: &Path,
) -> Result<(), wedged_cli::jobs::Failure> {
    use wedged_cli::jobs::Failure;
    let state = model.recover(u);
    let view = View {
        mesh: model.mesh(),
        boundary: model.boundary(),
        status,
        state: &state,
        rays: &[],
        title,
    };
    let bytes =
        vtu_bytes(&view).map_err(|e| Failure::Internal(format!("{}: {e}", path.display())))?;
    write_atomic(path, &bytes, "VTU file").map_err(|e| Failure::Input(e.to_string()))
}

/// Writes `DIR/<stem>.vtu` and `DIR/<stem>.svg` of one view, for the directories given.
fn write_view(
    view: &View,
    stem: &str,
    vtk: Option<&Path>,
    svg: Option<&Path>,
    written: &mut Vec<PathBuf>,
) -> Result<(), String> {
    if let Some(dir) = vtk {
        let path = dir.join(format!("{stem}.vtu"));
        let bytes = vtu_bytes(view).map_err(|e| format!("{}: {e}", path.display()))?;
        write_atomic(&path, &bytes, "VTU file").map_err(|e| e.to_string())?;
        written.push(path);
    }
    if let Some(dir) = svg {
        let path = dir.join(format!("{stem}.svg"));
        write_atomic(&path, svg_string(view).as_bytes(), "SVG file").map_err(|e| e.to_string())?;
        written.push(path);
    }
    Ok(())
}

/// Writes the files of every cone; returns the paths written.
fn write_cones(
    model: &Model,
    problem: &Problem,
    result: &Enumeration,
    vtk: Option<&Path>,
    svg: Option<&Path>,
) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    let count = result.cones.len();
    let width = count.saturating_sub(1).to_string().len();
    for (c, cone) in result.cones.iter().enumerate() {
        let status = result.cone_status(cone);
        let ray_states: Vec<(usize, Configuration)> = cone
            .rays
            .iter()
            .map(|&k| (k, model.recover(&result.rays[k].u)))
            .collect();
        let rays: Vec<(usize, &Configuration)> = ray_states.iter().map(|(k, s)| (*k, s)).collect();
        // The centroid's state from its rays' (the fields are linear), not one more solve.
        let state = Configuration::mean(&rays.iter().map(|(_, s)| *s).collect::<Vec<_>>());
        let pressed = status.iter().filter(|s| s.pressed()).count();
        let separated = status.iter().filter(|s| s.gap_open()).count();
        // Indices are 0-based, as in the summary's tables and the JSON.
        let title = format!(
            "cone #{c} of {count}, mu = {}: {} #{}; {pressed} of {} contact nodes pressed, \
             {separated} separated",
            problem.mu(),
            if cone.rays.len() == 1 { "ray" } else { "rays" },
            crate::report::summary::ranges(&cone.rays),
            status.len()
        );
        let view = View {
            mesh: model.mesh(),
            boundary: model.boundary(),
            status: &status,
            state: &state,
            rays: &rays,
            title,
        };
        let stem = format!("cone-{c:0width$}");
        write_view(&view, &stem, vtk, svg, &mut written)?;
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_piece_files_are_recognised() {
        assert!(is_piece_file("cone-1.vtu", "vtu"));
        assert!(is_piece_file("cone-012.svg", "svg"));
        assert!(is_piece_file("pattern-0.vtu", "vtu"));
        assert!(is_piece_file("pattern-07.svg", "svg"));
        assert!(!is_piece_file("cone-.vtu", "vtu"));
        assert!(!is_piece_file("pattern-.vtu", "vtu"));
        assert!(!is_piece_file("cone-1.svg", "vtu"));
        assert!(!is_piece_file("pattern-1.svg", "vtu"));
        assert!(!is_piece_file("mycone-1.vtu", "vtu"));
        assert!(!is_piece_file("patterns-1.vtu", "vtu"));
        assert!(!is_piece_file("cone-1a.vtu", "vtu"));
        assert!(!is_piece_file("result.json", "vtu"));
    }
}
