//! `wedged demo`: the built-in plug, end to end.

use wedged::{CriticalSettings, CriticalStatus, Settings};

use super::*;
use crate::args::*;
use crate::report;
use crate::report::answer::Choice;
use wedged_cli::jobs::run_critical_library;

pub(crate) fn run_demo(args: DemoArgs) -> Result<(), Failure> {
    let (model, mu) = if args.cork {
        wedged::examples::cork2d_demo()
    } else {
        wedged::examples::plug2d_demo()
    }
    .map_err(|e| Failure::Internal(format!("the demo model: {e}")))?;
    let problem = model
        .problem(mu)
        .map_err(|e| Failure::Internal(format!("the demo model: {e}")))?;
    let dir = &args.out;
    let preface = if args.cork {
        format!(
            "demo: a 2D elastic cork (plane strain) in a bottle neck, nothing clamped: a floating \
             body held by the walls alone\n(wedged::examples::cork2d_demo, README \"Floating \
             bodies\"); mu = {mu}; its sign patterns by branch and bound. Use `wedged \
             enumerate FILE.toml` for your own problem."
        )
    } else {
        format!(
            "demo: a 2D elastic plug (plane strain) in a V-notch, its top clamped, its slanted \
             sides against the notch walls\n(wedged::examples::plug2d_demo); mu = {mu}. Use \
             `wedged enumerate FILE.toml` for your own problem."
        )
    };
    // A floating body's pieces are sign patterns (the ray methods are for clamped bodies),
    // found by the 2D contact-set search.
    let choice = if problem.is_floating() {
        Choice::Patterns(wedged::PatternSettings {
            method: wedged::PatternMethod::Search,
            ..wedged::PatternSettings::default()
        })
    } else {
        Choice::Rays(Settings::default())
    };
    crate::report::files::create_output_dir(dir, "--out").map_err(Failure::Input)?;
    let json = dir.join("result.json");
    report(
        &problem,
        &choice,
        "demo",
        Some(&model),
        Outputs {
            jsonl: None,
            preface: Some(&preface),
            json: Some(&json),
            vtk: Some(dir),
            svg: Some(dir),
            certify: false,
        },
    )?;
    // The same plug's mu*, by branch and bound.
    let mut line = critical_line(&problem, "critical friction coefficient")?;
    if args.cork {
        // And the 3D cork's (a square frustum in a pyramidal seat, nothing clamped).
        let (model, mu) = wedged::examples::cork3d_demo()
            .map_err(|e| Failure::Internal(format!("the 3D cork: {e}")))?;
        let cork3d = model
            .problem(mu)
            .map_err(|e| Failure::Internal(format!("the 3D cork: {e}")))?;
        line.push_str(&critical_line(
            &cork3d,
            "the 3D cork (wedged::examples::cork3d_demo, walls at slope 0.3, corner edges \
             0.42; examples/cork3d.toml)",
        )?);
    }
    write_stdout(&line)
}

/// `mu*` of `problem` by branch and bound, as one paragraph of the demo's output.
fn critical_line(problem: &wedged::Problem, what: &str) -> Result<String, Failure> {
    let settings = CriticalSettings::default();
    let result = run_critical_library(problem, &settings, "demo", &INTERRUPTED, Show::Terminal)?;
    Ok(match report::critical::answer_line(&result, settings.tol) {
        Some(answer) => format!("\n{what}: {answer}\n"),
        None => format!(
            "\n{what}: not found ({})\n",
            match result.status {
                CriticalStatus::Incomplete(stop) => stop.to_string(),
                _ => "no answer".to_string(),
            }
        ),
    })
}
