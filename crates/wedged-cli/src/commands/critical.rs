//! `wedged critical` and `wedged sweep`: the critical friction coefficient `mu*` with its
//! bracket, and its step plot.

use std::path::Path;

use wedged::fe::Model;
use wedged::{Critical, CriticalMethod, CriticalSettings, CriticalStatus, Problem, Stop};

use super::*;
use crate::args::*;
use crate::draw::export::{collection, write_witness_vtu};
use crate::draw::sweep_svg;
use crate::report::files::write_atomic;
use crate::report::files::{JsonTarget, PendingFile};
use crate::report::{self, summary};
use wedged_cli::input::problem_file;
use wedged_cli::input::start::start_contact;
use wedged_cli::jobs::{
    critical_certification_failure, plan_critical, run_critical_library, CriticalOptions,
};

/// What `critical` and `sweep` read and where they write.
pub(crate) struct CriticalJob<'a> {
    problem: Problem,
    model: Option<Model>,
    file_mu: Option<f64>,
    settings: CriticalSettings,
    source: String,
    json: Option<&'a Path>,
    svg: Option<&'a Path>,
    /// `sweep --vtk`: the directory of the thresholds' configurations.
    vtk: Option<&'a Path>,
}

/// Checks the options (the library checks --tol) and loads the problem of `critical` or
/// `sweep`.
pub(crate) fn critical_job<'a>(
    problem: &Path,
    method: CriticalMethod,
    certify: bool,
    common: &CriticalCommon,
    json: Option<&'a Path>,
    svg: Option<&'a Path>,
) -> Result<CriticalJob<'a>, Failure> {
    let settings = plan_critical(&CriticalOptions {
        method: Some(method),
        tol: common.tol,
        time_limit: common.time_limit,
        certify,
        shard: None,
    })?;
    let input = |e: problem_file::LoadError| Failure::Input(e.to_string());
    let text = problem_file::read_text(problem).map_err(input)?;
    let (loaded, mu_given) = problem_file::parse_str_for_critical(&text, problem).map_err(input)?;
    Ok(CriticalJob {
        file_mu: mu_given.then(|| loaded.problem.mu()),
        problem: loaded.problem,
        model: loaded.model,
        source: problem.display().to_string(),
        json,
        svg,
        vtk: None,
        settings,
    })
}

pub(crate) fn run_critical(args: CriticalArgs) -> Result<(), Failure> {
    if let (Some(shard), None) = (args.shard, &args.json.json) {
        return Err(Failure::Input(format!(
            "--shard {shard} writes a part for `wedged merge`: give --json PART.json"
        )));
    }
    let mut job = critical_job(
        &args.problem,
        args.method.map_or(CriticalMethod::Bnb, |m| m.0),
        args.certify,
        &args.common,
        args.json.json.as_deref(),
        None,
    )?;
    if let Some(shard) = args.shard {
        if job.settings.method != CriticalMethod::Bnb {
            return Err(Failure::Input(format!(
                "--shard {shard} splits the search tree of --method bnb; --method {} has none \
                 to split",
                job.settings.method.name()
            )));
        }
        job.settings.shard = Some(shard);
    }
    if let Some(path) = &args.start {
        let start =
            start_contact(path, job.problem.nodes(), job.model.as_ref()).map_err(Failure::Input)?;
        job.settings.start = Some(start);
    }
    // --no-chain: no condensed problem starts the search.
    job.settings.condense = !args.no_chain;
    report_critical(job)
}

pub(crate) fn run_sweep(args: SweepArgs) -> Result<(), Failure> {
    let mut job = critical_job(
        &args.problem,
        CriticalMethod::Enumerate,
        false,
        &args.common,
        args.json.json.as_deref(),
        Some(&args.svg),
    )?;
    if let Some(dir) = args.vtk.as_deref() {
        if job.model.is_none() {
            return Err(Failure::Input(format!(
                "--vtk needs a meshed body ([mesh] in the problem file); {} gives a condensed \
                 stiffness only",
                job.source
            )));
        }
        prepare_series_dir(dir)?;
        job.vtk = Some(dir);
    }
    report_critical(job)
}

/// The files of `sweep --vtk` in its directory.
const SERIES_COLLECTION: &str = "sweep.pvd";

/// Creates the `sweep --vtk` directory and removes an earlier sweep's `threshold-N.vtu` and
/// `sweep.pvd`, so that it holds exactly this run's series.
fn prepare_series_dir(dir: &Path) -> Result<(), Failure> {
    let fail = |what: String| Failure::Input(format!("{}: {what}", dir.display()));
    crate::report::files::create_output_dir(dir, "--vtk").map_err(Failure::Input)?;
    let entries =
        std::fs::read_dir(dir).map_err(|e| fail(format!("cannot read the directory: {e}")))?;
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let old = name == SERIES_COLLECTION
            || name
                .strip_prefix("threshold-")
                .and_then(|rest| rest.strip_suffix(".vtu"))
                .is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()));
        if old {
            std::fs::remove_file(entry.path())
                .map_err(|e| fail(format!("cannot remove the old {name}: {e}")))?;
        }
    }
    Ok(())
}

/// Writes `threshold-N.vtu` for each pattern with a witness (in the order of the summary's
/// thresholds table, by threshold) and `sweep.pvd` with each file at its threshold as the time;
/// returns the line for the summary.
fn write_series(
    dir: &Path,
    model: &Model,
    source: &str,
    result: &Critical,
) -> Result<String, Failure> {
    let fail = |e: String| Failure::Input(e);
    let count = result.thresholds.len();
    let width = count.saturating_sub(1).to_string().len();
    let mut entries = Vec::new();
    for (k, t) in result.thresholds.iter().enumerate() {
        let Some(witness) = &t.witness else { continue };
        let path = dir.join(format!("threshold-{k:0width$}.vtu"));
        let title = format!(
            "{source}: pattern {k} of {count} at its threshold mu = {}",
            report::sig4(t.threshold)
        );
        write_witness_vtu(model, &witness.u, &witness.status, title, &path)?;
        entries.push((t.threshold, path));
    }
    let steps: Vec<(f64, &Path)> = entries.iter().map(|(mu, p)| (*mu, p.as_path())).collect();
    let pvd = collection(&steps);
    let pvd_path = dir.join(SERIES_COLLECTION);
    write_atomic(&pvd_path, pvd.as_bytes(), "ParaView collection")
        .map_err(|e| fail(e.to_string()))?;
    let missing = count - entries.len();
    let note = if missing > 0 {
        format!(" ({missing} without a checked configuration at their threshold, left out)")
    } else {
        String::new()
    };
    Ok(format!(
        "{} threshold-N.vtu files (each pattern at its own threshold) and their collection {} \
         (time = mu) written{note}\n",
        entries.len(),
        pvd_path.display()
    ))
}

/// Computes `mu*` and writes the summary, the JSON and (sweep) the plot. The JSON and SVG targets
/// are opened before the run, so that an unwritable path fails before a long computation.
pub(crate) fn report_critical(job: CriticalJob) -> Result<(), Failure> {
    let CriticalJob {
        problem,
        model,
        file_mu,
        settings,
        source,
        json,
        svg,
        vtk,
    } = job;
    let json = json
        .map(JsonTarget::open)
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let svg = svg
        .map(|path| PendingFile::open(path, "SVG file"))
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let result = run_critical_library(&problem, &settings, &source, &INTERRUPTED, Show::Terminal)?;
    let json_text = json
        .as_ref()
        .map(|_| report::critical::to_json(&problem, &settings, &source, &result, model.as_ref()));
    let incomplete = match result.status {
        CriticalStatus::Incomplete(stop) => Some(stop),
        _ => None,
    };
    let mut stdout_text = String::new();
    let mut svg_line = String::new();
    let mut series_line = String::new();
    if let (Some(dir), Some(model)) = (vtk, &model) {
        if incomplete.is_none() {
            series_line = write_series(dir, model, &source, &result)?;
        }
    }
    if let Some(target) = svg {
        let path = target.path().display().to_string();
        if incomplete.is_some() {
            // Dropped uncommitted: its temporary file goes, and no plot claims anything.
            svg_line = format!("the run is incomplete, so no plot was written to {path}\n");
        } else {
            target
                .commit(sweep_svg::sweep_svg(&source, &result).as_bytes())
                .map_err(|e| Failure::Input(e.to_string()))?;
            svg_line = match result.status {
                CriticalStatus::Never => format!(
                    "the body never wedges, so the plot written to {path} says so instead of \
                     plotting\n"
                ),
                _ if result.thresholds.is_empty() => {
                    format!("no pattern thresholds to plot; {path} says why\n")
                }
                _ => format!("plot of the patterns realised against mu written to {path}\n"),
            };
        }
    }
    match (&json, &json_text) {
        (Some(JsonTarget::Stdout), Some(text)) => stdout_text.push_str(text),
        _ => {
            let json_path = match &json {
                Some(JsonTarget::File { path, .. }) => Some(path.as_path()),
                _ => None,
            };
            if let Some(model) = &model {
                stdout_text.push_str(&summary::model(&source, model));
            }
            stdout_text.push_str(&report::critical::render(
                &problem, &settings, &source, file_mu, &result, json_path,
            ));
            stdout_text.push_str(&svg_line);
            stdout_text.push_str(&series_line);
        }
    }
    if let (Some(target @ JsonTarget::File { .. }), Some(text)) = (json, &json_text) {
        target
            .commit(text)
            .map_err(|e| Failure::Input(e.to_string()))?;
    }
    write_stdout(&stdout_text)?;
    if let Some(failure) = critical_certification_failure(&source, &result) {
        return Err(failure);
    }
    match incomplete {
        Some(stop) => Err(Failure::Incomplete(critical_incomplete_text(
            &source, &result, stop,
        ))),
        None => Ok(()),
    }
}

/// The `incomplete: ...` line of an incomplete `critical` or `sweep` run.
pub(crate) fn critical_incomplete_text(source: &str, result: &Critical, stop: Stop) -> String {
    let found = report::critical::incomplete_bracket(result);
    if stop == Stop::Undecided {
        format!(
            "{source}: {stop} ({} undecided, listed in the summary and the JSON); {found}; the \
             result is incomplete",
            result.undecided.len()
        )
    } else {
        format!("{source}: {stop}; {found}; the result is incomplete")
    }
}
