//! `wedged enumerate`: the rays and cones (2D) or the sign patterns (2D and 3D) of a problem,
//! the summary, the JSON, the per-piece files.

use std::path::Path;

use wedged::fe::Model;
use wedged::{Problem, Stop};

use super::*;
use crate::args::*;
use crate::draw::export;
use crate::report::answer::{Answer, Choice};
use crate::report::files::{JsonLines, JsonTarget};
use crate::report::summary;
use wedged::PatternSink;
use wedged_cli::input::problem_file;
use wedged_cli::jobs::{enumerate, plan_enumerate, EnumerateOptions};

pub(crate) fn run_enumerate(args: EnumerateArgs) -> Result<(), Failure> {
    let source = args.problem.display().to_string();
    let loaded = problem_file::load(&args.problem, args.mu.is_some())
        .map_err(|e| Failure::Input(e.to_string()))?;
    let problem = match args.mu {
        Some(mu) => loaded
            .problem
            .with_mu(mu)
            .map_err(|e| Failure::Input(format!("--mu: {e}")))?,
        None => loaded.problem,
    };
    let options = EnumerateOptions {
        method: args.method,
        pyramid_faces: args.pyramid_faces,
        zero_tol: args.zero_tol,
        time_limit: args.time_limit,
        max_rays: args.max_rays,
        max_memory: args.max_memory,
        certify: args.certify,
        exact: args.exact,
        shard: args.shard,
        stream: args.jsonl.is_some(),
    };
    let choice = plan_enumerate(&problem, &source, &options)?;
    if let Some(shard) = args.shard {
        if args.json.json.is_none() {
            return Err(Failure::Input(format!(
                "--shard {shard} writes a part for `wedged merge`: give --json PART.json"
            )));
        }
        for (given, option) in [(args.vtk.is_some(), "--vtk"), (args.svg.is_some(), "--svg")] {
            if given {
                return Err(Failure::Input(format!(
                    "{option} draws the whole answer: draw it from a whole run, not from \
                     --shard {shard}"
                )));
            }
        }
    }
    if let (Some(lines), Some(json)) = (&args.jsonl, &args.json.json) {
        if JsonTarget::is_stdout(lines) && JsonTarget::is_stdout(json) {
            return Err(Failure::Input(
                "--json - and --jsonl - would both write to stdout: give one of them a file".into(),
            ));
        }
        if same_file(lines, json) {
            return Err(Failure::Input(format!(
                "--json and --jsonl name the same file, {}: give them two",
                json.display()
            )));
        }
    }
    if args.jsonl.is_some() {
        for (given, option) in [(args.vtk.is_some(), "--vtk"), (args.svg.is_some(), "--svg")] {
            if given {
                return Err(Failure::Input(format!(
                    "{option} draws the pieces, which --jsonl streams to its file and does not \
                     keep: give one of them"
                )));
            }
        }
    }
    if loaded.model.is_none() {
        for (given, option) in [(args.vtk.is_some(), "--vtk"), (args.svg.is_some(), "--svg")] {
            if given {
                return Err(Failure::Input(format!(
                    "{option} needs a meshed body ([mesh] in the problem file); {source} gives \
                     a condensed stiffness only"
                )));
            }
        }
    }
    report(
        &problem,
        &choice,
        &source,
        loaded.model.as_ref(),
        Outputs {
            preface: None,
            json: args.json.json.as_deref(),
            jsonl: args.jsonl.as_deref(),
            vtk: args.vtk.as_deref(),
            svg: args.svg.as_deref(),
            certify: args.certify,
        },
    )
}

/// Where a run's results go besides the summary on stdout.
pub(crate) struct Outputs<'a> {
    pub(crate) preface: Option<&'a str>,
    pub(crate) json: Option<&'a Path>,
    /// `--jsonl`: stream the pieces to this file.
    pub(crate) jsonl: Option<&'a Path>,
    pub(crate) vtk: Option<&'a Path>,
    pub(crate) svg: Option<&'a Path>,
    /// `--certify`: certify a ray method's answer in exact rational arithmetic (a pattern
    /// method certifies during its run, from its settings).
    pub(crate) certify: bool,
}

/// Enumerates and writes the summary and the JSON. The JSON target is opened before the run, so
/// that an unwritable path fails before a long computation.
pub(crate) fn report(
    problem: &Problem,
    choice: &Choice,
    source: &str,
    model: Option<&Model>,
    outputs: Outputs,
) -> Result<(), Failure> {
    let Outputs {
        preface,
        json,
        jsonl,
        vtk,
        svg,
        certify,
    } = outputs;
    let json = json
        .map(JsonTarget::open)
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let lines = jsonl
        .map(JsonLines::create)
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let write_line = |p: wedged::Pattern| lines.iter().for_each(|l| l.write_pattern(&p));
    if let Some(dir) = vtk {
        export::prepare_dir(dir, "--vtk", "vtu").map_err(Failure::Input)?;
    }
    if let Some(dir) = svg {
        export::prepare_dir(dir, "--svg", "svg").map_err(Failure::Input)?;
    }
    let run = enumerate(
        problem,
        choice,
        source,
        certify,
        &INTERRUPTED,
        Show::Terminal,
        lines.is_some().then_some(&write_line as PatternSink),
    )?;
    if let Some(lines) = lines {
        lines.finish().map_err(|e| Failure::Input(e.to_string()))?;
    }
    let answer = &run.answer;
    let certificate = run.certificate();
    // A file is written as the document is made (below); only stdout's is held as text.
    let json_text = match &json {
        Some(JsonTarget::Stdout) => Some(run.json(problem, choice, model)),
        _ => None,
    };
    let incomplete = answer.stopped();
    let written = match model {
        Some(model) if (vtk.is_some() || svg.is_some()) && incomplete.is_none() => {
            export::write_pieces(model, problem, answer, vtk, svg).map_err(Failure::Input)?
        }
        _ => Vec::new(),
    };
    let mut stdout_text = String::new();
    match (&json, &json_text) {
        (Some(JsonTarget::Stdout), Some(text)) => stdout_text.push_str(text),
        // `--jsonl -`: stdout holds the pieces' lines only (as `--json -` holds its JSON).
        _ if jsonl.is_some_and(JsonTarget::is_stdout) => {}
        _ => {
            if let Some(p) = preface {
                stdout_text.push_str(p);
                stdout_text.push('\n');
            }
            let json_path = match &json {
                Some(JsonTarget::File { path, .. }) => Some(path.as_path()),
                _ => None,
            };
            if let Some(model) = model {
                stdout_text.push_str(&summary::model(source, model));
            }
            stdout_text.push_str(&summary::render(problem, choice, source, answer, json_path));
            if let (Some(path), Answer::Patterns(p)) = (jsonl, answer) {
                stdout_text.push_str(&summary::streamed(p, path));
            }
            if let Some(c) = &certificate {
                stdout_text.push_str(&summary::certification(c));
            }
            stdout_text.push_str(&summary::files(answer, vtk, svg, &written));
        }
    }
    if let Some(target @ JsonTarget::File { .. }) = json {
        target
            .commit_with(|out| run.write_json(problem, choice, model, out))
            .map_err(|e| Failure::Input(e.to_string()))?;
    }
    write_stdout(&stdout_text)?;
    if let Some(failure) = run.certification_failure(source) {
        return Err(failure);
    }
    match incomplete {
        Some(stop) => Err(Failure::Incomplete(incomplete_text(
            source, problem, choice, answer, stop,
        ))),
        None => Ok(()),
    }
}

/// The `incomplete: ...` line of an incomplete run.
pub(crate) fn incomplete_text(
    source: &str,
    problem: &Problem,
    choice: &Choice,
    answer: &Answer,
    stop: Stop,
) -> String {
    match answer {
        // Double description: how far through the nodes it came (as the summary says).
        Answer::Rays(result) if summary::by_double_description(choice) => format!(
            "{source}: {stop} after {} of {} nodes; the result is incomplete",
            result.info.rays_after_node.len(),
            problem.nodes()
        ),
        // The others: the checked rays they report.
        Answer::Rays(result) => format!(
            "{source}: {stop} with {} found so far (checked); the result is incomplete",
            match result.rays.len() {
                1 => "1 wedged configuration".to_string(),
                n => format!("{n} wedged configurations"),
            }
        ),
        Answer::Patterns(result) if stop == Stop::Undecided => format!(
            "{source}: {stop} ({} undecided, listed in the summary and the JSON); the patterns \
             below them may be missing, so the result is incomplete",
            result.undecided.len()
        ),
        Answer::Patterns(result) => format!(
            "{source}: {stop} with {} found so far; the result is incomplete",
            match result.patterns.len() + result.info.streamed as usize {
                1 => "1 maximal pattern".to_string(),
                n => format!("{n} maximal patterns"),
            }
        ),
    }
}

/// Whether two output paths name the same file (as given, or once made absolute).
fn same_file(a: &Path, b: &Path) -> bool {
    a == b
        || matches!(
            (std::path::absolute(a), std::path::absolute(b)),
            (Ok(x), Ok(y)) if x == y
        )
}
