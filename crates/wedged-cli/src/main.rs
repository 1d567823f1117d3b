//! The `wedged` command: a thin front end over the `wedged` library.
//!
//! `main` calls [`run`] and turns its result into an exit code; every failure is printed as one
//! line, `error: <what went wrong>`, on stderr. The work lives in the library; this binary reads
//! problem files ([`problem_file`], [`mtx`]) and writes results ([`summary`], [`output`]).

#[allow(dead_code)]
mod msh;
mod mtx;
mod output;
mod problem_file;
mod summary;
#[allow(dead_code)]
mod svg;
#[allow(dead_code)]
mod vtk;

use std::fmt;
use std::io::{self, IsTerminal, Write};
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::builder::PossibleValue;
use clap::{Args, Parser, Subcommand, ValueEnum};
use wedged::{
    enumerate_with_progress, EnumerateError, Enumeration, Method, Problem, Progress, Settings,
};

use crate::output::JsonTarget;

const EXIT_CODES: &str = "\
Exit codes:
  0  the run completed, whether or not wedged configurations exist
  1  internal failure (e.g. a computed ray failed verification; a bug)
  2  bad input or usage (unreadable or invalid problem file, bad option, unwritable --json path)";

const PROBLEM_FILE: &str = "\
Problem file (TOML):
  dim = 2                      # space dimension (only 2 can be enumerated so far)
  mu = 0.8                     # friction coefficient, > 0
  [stiffness]                  # K on the contact nodes, local frames, normal first
  matrix_market = \"K.mtx\"      # relative to the TOML file's directory, or:
  # rows = [[2.0, 1.0], [1.0, 1.0]]";

/// Enumerate the wedged configurations of an elastic body in frictional contact with a rigid
/// obstacle: every equilibrium without load in which the body stays deformed.
#[derive(Debug, Parser)]
#[command(name = "wedged", version, after_help = EXIT_CODES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Enumerate the wedged configurations of the problem in a TOML file.
    #[command(after_help = EXIT_CODES, after_long_help = format!("{PROBLEM_FILE}\n\n{EXIT_CODES}"))]
    Enumerate(EnumerateArgs),
    /// Enumerate the wedged configurations of a built-in four-node example.
    #[command(after_help = EXIT_CODES)]
    Demo(DemoArgs),
}

#[derive(Debug, Args)]
struct EnumerateArgs {
    /// The problem file (TOML; see --help for its format).
    problem: PathBuf,
    /// Friction coefficient, overriding the file's `mu`.
    #[arg(long, value_name = "MU", allow_negative_numbers = true)]
    mu: Option<f64>,
    /// Algorithm finding the complementary extreme rays.
    #[arg(long, value_name = "METHOD", default_value = "pruned-dd")]
    method: MethodArg,
    /// Relative zero tolerance of the enumeration [default: 1e-9].
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    zero_tol: Option<f64>,
    #[command(flatten)]
    json: JsonArg,
}

#[derive(Debug, Args)]
struct DemoArgs {
    #[command(flatten)]
    json: JsonArg,
}

#[derive(Debug, Args)]
struct JsonArg {
    /// Also write the full result as JSON to this file (written atomically); `-` writes the JSON
    /// to stdout instead of the summary.
    #[arg(long, value_name = "OUT.json")]
    json: Option<PathBuf>,
}

/// A [`Method`] as a command-line value, named by [`Method::name`].
#[derive(Debug, Clone, Copy)]
struct MethodArg(Method);

impl ValueEnum for MethodArg {
    fn value_variants<'a>() -> &'a [Self] {
        &[
            MethodArg(Method::PrunedDd),
            MethodArg(Method::FullDd),
            MethodArg(Method::Faces),
        ]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let help = match self.0 {
            Method::PrunedDd => "the seed's pruned double description",
            Method::FullDd => "every extreme ray by double description, then a filter",
            Method::Faces => "brute force over the 2^m contact sets (small m only)",
        };
        Some(PossibleValue::new(self.0.name()).help(help))
    }
}

/// Why a run failed; decides the exit code.
#[derive(Debug)]
enum Failure {
    /// Bad input or usage: exit code 2.
    Input(String),
    /// A failure of the program itself: exit code 1.
    Internal(String),
}

impl Failure {
    fn exit_code(&self) -> ExitCode {
        match self {
            Failure::Input(_) => ExitCode::from(2),
            Failure::Internal(_) => ExitCode::from(1),
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Input(m) | Failure::Internal(m) => f.write_str(m),
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // A panic is a bug: report it on one line, as an internal failure, without a backtrace.
    panic::set_hook(Box::new(|info| {
        let what = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".to_string());
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()));
        eprintln!(
            "error: internal failure (a bug in wedged, please report it): {}{}",
            one_line(&what),
            place.unwrap_or_default()
        );
    }));
    match panic::catch_unwind(AssertUnwindSafe(|| run(cli))) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(failure)) => {
            eprintln!("error: {}", one_line(&failure.to_string()));
            failure.exit_code()
        }
        Err(_) => ExitCode::from(1),
    }
}

fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Enumerate(args) => run_enumerate(args),
        Command::Demo(args) => run_demo(args),
    }
}

fn run_enumerate(args: EnumerateArgs) -> Result<(), Failure> {
    let source = args.problem.display().to_string();
    let problem = problem_file::load(&args.problem, args.mu.is_some())
        .map_err(|e| Failure::Input(e.to_string()))?;
    let problem = match args.mu {
        Some(mu) => problem
            .with_mu(mu)
            .map_err(|e| Failure::Input(format!("--mu: {e}")))?,
        None => problem,
    };
    let mut settings = Settings {
        method: args.method.0,
        ..Settings::default()
    };
    if let Some(t) = args.zero_tol {
        settings.zero_tol = t;
    }
    report(
        &problem,
        &settings,
        &source,
        None,
        args.json.json.as_deref(),
    )
}

fn run_demo(args: DemoArgs) -> Result<(), Failure> {
    let problem = wedged::examples::demo();
    let preface = format!(
        "demo: {} contact nodes of a small elastic block pressed into a notch, with inclined \
         springs\n(wedged::examples::demo); mu = {}. Use `wedged enumerate FILE.toml` for your \
         own problem.",
        problem.nodes(),
        problem.mu()
    );
    report(
        &problem,
        &Settings::default(),
        "demo",
        Some(&preface),
        args.json.json.as_deref(),
    )
}

/// Enumerates and writes the summary and the JSON. The JSON target is opened before the run, so
/// that an unwritable path fails before a long computation.
fn report(
    problem: &Problem,
    settings: &Settings,
    source: &str,
    preface: Option<&str>,
    json: Option<&Path>,
) -> Result<(), Failure> {
    let json = json
        .map(JsonTarget::open)
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let result = run_library(problem, settings, source)?;
    let json_text = json
        .as_ref()
        .map(|_| output::to_json(problem, settings, &result));
    let mut stdout_text = String::new();
    match (&json, &json_text) {
        (Some(JsonTarget::Stdout), Some(text)) => stdout_text.push_str(text),
        _ => {
            if let Some(p) = preface {
                stdout_text.push_str(p);
                stdout_text.push('\n');
            }
            let json_path = match &json {
                Some(JsonTarget::File { path, .. }) => Some(path.as_path()),
                _ => None,
            };
            stdout_text.push_str(&summary::render(
                problem, settings, source, &result, json_path,
            ));
        }
    }
    if let (Some(target @ JsonTarget::File { .. }), Some(text)) = (json, &json_text) {
        target
            .commit(text)
            .map_err(|e| Failure::Input(e.to_string()))?;
    }
    write_stdout(&stdout_text)
}

/// Runs the enumeration and sorts its errors into bad input and internal failures.
fn run_library(
    problem: &Problem,
    settings: &Settings,
    source: &str,
) -> Result<Enumeration, Failure> {
    // A live progress line on stderr, only for a person at a terminal and only once the run has
    // lasted a second: pipes, files and CI logs stay clean.
    let start = std::time::Instant::now();
    let live = io::stderr().is_terminal();
    let shown = std::cell::Cell::new(false);
    let progress = |p: Progress| {
        if live && start.elapsed().as_secs_f64() > 1.0 {
            eprint!(
                "\r  node {}/{}: {} rays held, {:.1} s   ",
                p.done,
                p.total,
                p.rays,
                start.elapsed().as_secs_f64()
            );
            shown.set(true);
        }
    };
    let result = enumerate_with_progress(problem, settings, &progress);
    if shown.get() {
        eprintln!();
    }
    result.map_err(|e| match e {
        EnumerateError::UnsupportedDim(d) => Failure::Input(format!(
            "{source}: dim = {d}: enumerating 3D problems (by sign patterns) is not implemented \
             yet; only dim = 2 can be enumerated"
        )),
        EnumerateError::InvalidSettings(m) => Failure::Input(format!("invalid option: {m}")),
        e @ EnumerateError::Verification(_) => Failure::Internal(format!("{source}: {e}")),
    })
}

/// Writes to stdout; a closed pipe (`wedged demo | head`) ends the output quietly.
fn write_stdout(text: &str) -> Result<(), Failure> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Failure::Internal(format!("cannot write to stdout: {e}"))),
    }
}

/// Collapses a possibly multi-line message into one line.
pub(crate) fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn cli_is_well_formed() {
        Cli::command().debug_assert();
    }

    #[test]
    fn method_names_are_the_library_names() {
        let names: Vec<String> = MethodArg::value_variants()
            .iter()
            .map(|m| m.to_possible_value().unwrap().get_name().to_string())
            .collect();
        let library: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        assert_eq!(names, library);
    }

    #[test]
    fn one_line_joins_lines() {
        assert_eq!(one_line("a\n  b\n\nc "), "a; b; c");
    }
}
