//! `critical`'s start on a fine mesh: the same body with half the divisions (a generated body)
//! or with every mesh size doubled (a Gmsh script, its `size_factor`), solved first, its wedge
//! mapped onto the fine mesh as the search's first leaf, as `critical --start` maps an earlier
//! result ([`Earlier::onto`]). The coarse body is itself started from a coarser one while it
//! has [`COARSE_FROM`] contact nodes or more. A mesh file has no coarser mesh.
//!
//! On a Gmsh script's unstructured mesh the start matters more than on the generated plug,
//! whose settled root refutes the whole tree at `mu*` (`BENCHMARKS.md`).
//!
//! The search's own first leaf comes from its rounded root and a local search over contact
//! sets, which on a fine mesh can stop far above `mu*` (the 2D plug at m = 400: at 2.28, where
//! `mu*` is 1.77, and the run did not finish in 25 minutes); the coarse mesh's wedge lies in
//! the right basin, and the local search goes from its image to `mu*` in a few steps. The
//! bracket does not depend on the start (the proof is the search's): only the time does.
//!
//! Only where a start is used (`bnb` without `--certify` or `--shard`, no `--start` given);
//! `critical --no-chain` computes from scratch.

use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use wedged::fe::Model;
use wedged::{CriticalMethod, CriticalSettings, CriticalStatus, Problem, Stop};

use crate::input::problem_file;
use crate::input::start::Earlier;
use crate::jobs::{run_critical_library, Failure, Show};
use crate::report::critical::mu_text;
use crate::report::upper_text;
use crate::study;

/// 2D problems of this many contact nodes or more start from the same body with half the
/// divisions. (Measured on the 2D plug, `wedged critical` against the coarse run plus
/// `critical --start` with its answer, 2026-11-29: m = 50 0.118 s against 0.026 + 0.091 s, no
/// gain; m = 100 1.07 s against 0.11 + 0.84 s; m = 140 3.85 s against 0.34 + 3.19 s; m = 200
/// 19.8 s against 0.95 + 15.95 s; m = 400 not finished in 15 minutes (the local search stops
/// at 2.28) against 17 + 338 s.)
pub const COARSE_FROM: usize = 80;

/// The same for 3D problems. (Measured on the 3D V-groove plug, `examples/plug3d.toml` with
/// `mu = 2`, 2026-11-29: m = 40 (`ny = nz = 4`) 2.37 s against 0.035 + 1.96 s (paired 0.82 for
/// the second, `-n 3`); m = 80 (`ny = 9, nz = 4`) 224.7 s against 0.52 + 161.4 s, one run each.)
pub const COARSE_FROM_3D: usize = 40;

/// How the problem file (text `text`) is made coarser ([`start`]), for the summary's line.
pub fn how(text: &str) -> &'static str {
    let table = text.parse::<toml::Table>().unwrap_or_default();
    if study::is_script(&table) {
        "every mesh size of its Gmsh script doubled"
    } else {
        "half the divisions"
    }
}

/// The answers of the coarser meshes, coarsest first, and the start they give.
#[derive(Debug, Clone)]
pub struct Coarse {
    /// The start: whether each of the fine problem's contact nodes is in contact.
    pub start: Vec<bool>,
    /// One line per coarse mesh, coarsest first (its contact nodes, its answer, the time of
    /// its own run).
    pub levels: Vec<String>,
}

/// Whether a run of `settings` on `problem` starts from a coarser mesh's answer (when its
/// problem file can be coarsened, [`start`]).
pub fn chains(settings: &CriticalSettings, problem: &Problem) -> bool {
    settings.method == CriticalMethod::Bnb
        && !settings.certify
        && settings.shard.is_none()
        && settings.start.is_none()
        && problem.nodes()
            >= match problem.dim() {
                2 => COARSE_FROM,
                _ => COARSE_FROM_3D,
            }
}

/// Where [`chains`] allows, starts `settings` from the coarser meshes' answer ([`start`]) of
/// the problem of the file `path` (text `text`) and `model`, and takes the time they took
/// from the time limit (the whole run's); returns their lines for the summary (none where
/// nothing was chained). The one entry for the command and the Python package.
#[allow(clippy::too_many_arguments)]
pub fn chain(
    text: &str,
    path: &Path,
    problem: &Problem,
    model: Option<&Model>,
    settings: &mut CriticalSettings,
    cancel: &AtomicBool,
    show: Show,
) -> Result<Vec<String>, Failure> {
    if !chains(settings, problem) {
        return Ok(Vec::new());
    }
    let began = Instant::now();
    let found = start(text, path, problem.nodes(), model, settings, cancel, show)?;
    let limits = &mut settings.limits;
    limits.time_limit = limits
        .time_limit
        .map(|limit| limit.saturating_sub(began.elapsed()));
    Ok(found.map_or_else(Vec::new, |found| {
        settings.start = Some(found.start);
        found.levels
    }))
}

/// `status` with the time limit the caller was given where [`chain`] shortened it: a run
/// stopped by its limit names the limit asked for, not what the coarser meshes left of it.
pub fn given_limit(status: CriticalStatus, given: Option<Duration>) -> CriticalStatus {
    match (status, given) {
        (CriticalStatus::Incomplete(Stop::TimeLimit(_)), Some(limit)) => {
            CriticalStatus::Incomplete(Stop::TimeLimit(limit))
        }
        _ => status,
    }
}

/// The start of the problem of the file `path` (text `text`, `nodes` contact nodes on `model`)
/// from its body with half the divisions (see the module docs), computed with `settings` (its
/// start replaced); `None` where the file has no division counts to halve, the coarse body
/// does not load, has no fewer contact nodes, or found no wedge. A failure of the program
/// itself in a coarse run is an error.
pub fn start(
    text: &str,
    path: &Path,
    nodes: usize,
    model: Option<&Model>,
    settings: &CriticalSettings,
    cancel: &AtomicBool,
    show: Show,
) -> Result<Option<Coarse>, Failure> {
    let Ok(table) = text.parse::<toml::Table>() else {
        return Ok(None);
    };
    let Some(coarse) = study::coarsened(&table) else {
        return Ok(None);
    };
    let Ok(coarse_text) = toml::to_string(&coarse) else {
        return Ok(None);
    };
    let Ok((loaded, _)) = problem_file::parse_str_for_critical(&coarse_text, path) else {
        return Ok(None);
    };
    let m = loaded.problem.nodes();
    if m >= nodes || m == 0 {
        return Ok(None);
    }
    let mut settings = settings.clone();
    settings.start = None;
    // The coarse body from a coarser one, while it is large enough.
    let below = if chains(&settings, &loaded.problem) {
        start(
            &coarse_text,
            path,
            m,
            loaded.model.as_ref(),
            &settings,
            cancel,
            show,
        )?
    } else {
        None
    };
    let mut levels = Vec::new();
    if let Some(below) = below {
        settings.start = Some(below.start);
        levels = below.levels;
    }
    let source = format!("{} [{m} contact nodes]", path.display());
    // Each line's time is its own mesh's run, not its coarser meshes' (nor its loading).
    let began = Instant::now();
    let result = match run_critical_library(&loaded.problem, &settings, &source, cancel, show) {
        Ok(result) => result,
        Err(failure @ Failure::Internal(_)) => return Err(failure),
        Err(_) => return Ok(None),
    };
    let Some(witness) = &result.witness else {
        return Ok(None);
    };
    let answer = match (&result.status, result.mu_critical, result.upper) {
        (CriticalStatus::Incomplete(_), _, Some(upper)) => {
            format!("incomplete, mu* <= {}", upper_text(upper))
        }
        // As many digits as the bracket certifies (`critical`'s answer line).
        (_, Some(mu), _) => format!("mu* = {}", mu_text(mu, result.lower)),
        _ => return Ok(None),
    };
    levels.push(format!(
        "m = {m}: {answer} ({:.2} s)",
        began.elapsed().as_secs_f64()
    ));
    let earlier = Earlier::of(&witness.pattern, loaded.model.as_ref());
    match earlier.onto(nodes, model, &source) {
        Ok(start) if start.contains(&true) => Ok(Some(Coarse { start, levels })),
        _ => Ok(None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wedged::examples::random_spd_problem;

    /// A start from coarser meshes only where the search uses one, from [`COARSE_FROM`]
    /// nodes in 2D and [`COARSE_FROM_3D`] in 3D.
    #[test]
    fn chains_only_where_a_start_is_used() {
        let large = random_spd_problem(COARSE_FROM, 2.0, 1);
        let small = random_spd_problem(COARSE_FROM - 1, 2.0, 1);
        let plain = CriticalSettings::default();
        assert_eq!(plain.method, CriticalMethod::Bnb);
        assert!(chains(&plain, &large));
        assert!(!chains(&plain, &small));
        let certify = CriticalSettings {
            certify: true,
            ..plain.clone()
        };
        let faces = CriticalSettings {
            method: CriticalMethod::Faces,
            ..plain.clone()
        };
        let started = CriticalSettings {
            start: Some(vec![true; COARSE_FROM]),
            ..plain.clone()
        };
        let shard = CriticalSettings {
            shard: Some(wedged::Shard::parse("1/2").unwrap()),
            ..plain.clone()
        };
        for settings in [certify, faces, started, shard] {
            assert!(!chains(&settings, &large), "{settings:?}");
        }
        let three = |m| wedged::examples::random_spd_problem_dim(3, m, 2.0, 1);
        assert!(chains(&plain, &three(COARSE_FROM_3D)));
        assert!(!chains(&plain, &three(COARSE_FROM_3D - 1)));
    }
}
