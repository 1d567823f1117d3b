//! `wedged demo`: the built-in plug, end to end.

use std::fs;
use wedged::{CriticalSettings, CriticalStatus, Settings};

use super::*;
use crate::args::*;
use crate::report;
use crate::report::answer::Choice;
use wedged_cli::jobs::run_critical_library;

pub(crate) fn run_demo(args: DemoArgs) -> Result<(), Failure> {
    let (model, mu) = wedged::examples::plug2d_demo()
        .map_err(|e| Failure::Internal(format!("the demo model: {e}")))?;
    let problem = model
        .problem(mu)
        .map_err(|e| Failure::Internal(format!("the demo model: {e}")))?;
    let dir = &args.out;
    let preface = format!(
        "demo: a 2D elastic plug (plane strain) in a V-notch, its top clamped, its slanted sides \
         against the notch walls\n(wedged::examples::plug2d_demo); mu = {mu}. Use `wedged \
         enumerate FILE.toml` for your own problem."
    );
    fs::create_dir_all(dir).map_err(|e| {
        Failure::Input(format!(
            "{}: cannot create the demo directory: {e}",
            dir.display()
        ))
    })?;
    let json = dir.join("result.json");
    report(
        &problem,
        &Choice::Rays(Settings::default()),
        "demo",
        Some(&model),
        Outputs {
            preface: Some(&preface),
            json: Some(&json),
            vtk: Some(dir),
            svg: Some(dir),
            certify: false,
        },
    )?;
    // The same plug's mu*, by branch and bound.
    let settings = CriticalSettings::default();
    let result = run_critical_library(&problem, &settings, "demo", &INTERRUPTED, Show::Terminal)?;
    let line = match report::critical::answer_line(&result, settings.tol) {
        Some(answer) => format!("\ncritical friction coefficient: {answer}\n"),
        None => format!(
            "\ncritical friction coefficient: not found ({})\n",
            match result.status {
                CriticalStatus::Incomplete(stop) => stop.to_string(),
                _ => "no answer".to_string(),
            }
        ),
    };
    write_stdout(&line)
}
