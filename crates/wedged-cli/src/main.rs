//! The `wedged` command: a thin front end over the `wedged` library.
//!
//! `main` calls [`run`] and turns its result into an exit code; every failure is printed as one
//! line, `error: <what went wrong>`, on stderr. The work lives in the library; this binary reads
//! problem files ([`problem_file`], [`mtx`]) and writes results ([`summary`], [`output`]).

mod answer;
mod critical_out;
mod export;
mod output;
mod summary;
mod svg;
mod sweep_svg;
mod vtk;

use std::fmt;
use std::io::{self, IsTerminal, Write};
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::builder::PossibleValue;
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::fs;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;
use wedged::certify::certify_enumeration;
use wedged::fe::Model;
use wedged::patterns::{
    enumerate_patterns_with_control, PatternMethod, PatternSettings, DEFAULT_PYRAMID_FACES,
};
use wedged::{
    critical_with_control, enumerate_with_control, Critical, CriticalMethod, CriticalProgress,
    CriticalSettings, CriticalStatus, EnumerateError, Limits, Method, Problem, Progress, Settings,
    Stop,
};

use crate::answer::{Answer, Choice};
use crate::output::{JsonTarget, PendingFile};
use wedged_cli::{mtx, one_line, problem_file};

const EXIT_CODES: &str = "\
Exit codes:
  0  the run completed, whether or not wedged configurations exist
  1  internal failure (e.g. a computed ray failed verification; a bug)
  2  bad input or usage (unreadable or invalid problem file, bad option, unwritable --json path)
  3  the run is incomplete: it stopped early (--time-limit, --max-rays, --max-memory, Ctrl-C), or
     the conic solver could not decide some contact sets (pattern methods; the summary warns
     about each). The summary and the JSON say so (\"complete\": false); what was not finished
     is neither claimed nor ruled out";

const PROBLEM_FILE: &str = "\
Problem file (TOML), a condensed stiffness:
  dim = 2                      # space dimension, 2 or 3 (3: sign patterns, --method bnb)
  mu = 0.8                     # friction coefficient, > 0
  [stiffness]                  # K on the contact nodes, local frames, normal first
                               #   (2D: n, t per node; 3D: n, t1, t2)
  matrix_market = \"K.mtx\"      # relative to the TOML file's directory, or:
  # rows = [[2.0, 1.0], [1.0, 1.0]]

or a meshed body, condensed onto its contact nodes:
  mu = 0.8
  [mesh]
  gmsh = \"plug.msh\"            # Gmsh MSH 4.1 (ASCII or binary), physical groups by name; or:
  # [mesh.generate]            # a built-in body:
  # kind = \"plug2d\"            #   bottom_width, top_width, height, nx, ny, element = quad|tri
  #                            # 3D: vgroove3d: bottom_width, top_width, height, length, nx,
  #                            #   ny, nz, element = hex|tet;  frustum3d: bottom_width,
  #                            #   top_width, height, n, nz, element = hex|tet
  [material]
  young = 210e9
  poisson = 0.3
  plane = \"strain\"             # 2D: strain | stress
  [[contact]]                  # contact candidates against a rigid obstacle along the surface
  group = \"contact\"            # optional: normal = [nx, ny(, nz)], the body's inward normal
  [[clamp]]                    # zero displacement
  group = \"top\"
  # [[symmetry]]               # roller: zero displacement along the group's normal
  # group = \"axis\"";

const CRITICAL_HELP: &str = "\
The critical friction coefficient mu* is the least friction coefficient at which the body can stay
wedged (a nontrivial equilibrium without load). It is reported as a bracket [lower, upper]: a
wedged configuration exists at upper (checked against the wedged problem; mu* = upper), and none
exists below lower (certified by checked infeasibility certificates of the conic solver). The
width actually certified normally reaches --tol; where it cannot (now and then in 3D), it stops
at about 1e-7 relative (the solver's resolution), and the summary says so. \"never\"
(certified: no friction coefficient wedges the body) is a result, exit code 0. The problem
file's mu is not needed; --method enumerate starts its enumeration there (or at 1) and doubles
it until something wedges.";

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
    /// Condense a meshed body onto its contact nodes and export the stiffness (Matrix Market).
    #[command(after_help = EXIT_CODES, after_long_help = format!("{PROBLEM_FILE}\n\n{EXIT_CODES}"))]
    Condense(CondenseArgs),
    /// Compute the critical friction coefficient mu*: the least mu at which the body can stay
    /// wedged, with a certified bracket and a wedged configuration at its upper end.
    #[command(
        after_help = EXIT_CODES,
        after_long_help = format!("{CRITICAL_HELP}\n\n{PROBLEM_FILE}\n\n{EXIT_CODES}")
    )]
    Critical(CriticalArgs),
    /// Plot how many maximal patterns are realised against mu: each pattern's own threshold
    /// (from the enumeration at a large mu), and mu*, the least of them.
    #[command(
        after_help = EXIT_CODES,
        after_long_help = format!("{CRITICAL_HELP}\n\n{PROBLEM_FILE}\n\n{EXIT_CODES}")
    )]
    Sweep(SweepArgs),
    /// Run the built-in example: a 2D plug wedged in a V-notch, with JSON, VTU and SVG output,
    /// and its critical friction coefficient.
    #[command(after_help = EXIT_CODES)]
    Demo(DemoArgs),
}

#[derive(Debug, Args)]
struct CriticalArgs {
    /// The problem file (TOML; see --help for its format; its `mu` is optional).
    problem: PathBuf,
    /// Algorithm [default: bnb].
    #[arg(long, value_name = "METHOD")]
    method: Option<CriticalMethodArg>,
    /// Re-check the answer in exact rational arithmetic: every infeasibility certificate behind
    /// `lower` and the witness at `upper` (bnb and faces; enumerate's lower end rests on a
    /// floating-point enumeration and is reported as not certified). Exit code 1 if a check
    /// fails.
    #[arg(long)]
    certify: bool,
    #[command(flatten)]
    common: CriticalCommon,
    #[command(flatten)]
    json: JsonArg,
}

#[derive(Debug, Args)]
struct SweepArgs {
    /// The problem file (TOML; see --help for its format; its `mu`, when given, is where the
    /// enumeration starts).
    problem: PathBuf,
    /// Write the step plot here (SVG, written atomically).
    #[arg(long, value_name = "PLOT.svg")]
    svg: PathBuf,
    #[command(flatten)]
    common: CriticalCommon,
    #[command(flatten)]
    json: JsonArg,
}

/// The options that `critical` and `sweep` share.
#[derive(Debug, Args)]
struct CriticalCommon {
    /// Relative width asked of the bracket of mu*, from 1e-12 to 0.1 [default: 1e-9].
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    tol: Option<f64>,
    /// Stop after this many seconds (the result is then marked incomplete; exit code 3).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    time_limit: Option<f64>,
}

/// A [`CriticalMethod`] as a command-line value, named by its `name()`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct CriticalMethodArg(CriticalMethod);

impl ValueEnum for CriticalMethodArg {
    fn value_variants<'a>() -> &'a [Self] {
        &[
            CriticalMethodArg(CriticalMethod::Bnb),
            CriticalMethodArg(CriticalMethod::Enumerate),
            CriticalMethodArg(CriticalMethod::Faces),
        ]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let help = match self.0 {
            CriticalMethod::Bnb => "branch and bound over contact sets with an incumbent",
            CriticalMethod::Enumerate => {
                "the maximal patterns at a large mu, then each one's threshold (as `sweep`)"
            }
            CriticalMethod::Faces => "every contact set, each threshold by bisection (m <= 12)",
        };
        Some(PossibleValue::new(self.0.name()).help(help))
    }
}

#[derive(Debug, Args)]
struct EnumerateArgs {
    /// The problem file (TOML; see --help for its format).
    problem: PathBuf,
    /// Friction coefficient, overriding the file's `mu`.
    #[arg(long, value_name = "MU", allow_negative_numbers = true)]
    mu: Option<f64>,
    /// Algorithm [default: pruned-dd for a 2D problem, bnb for a 3D one]. The ray methods
    /// (pruned-dd, full-dd, faces, exact) list the complementary extreme rays and the cones of a
    /// 2D problem; the pattern methods (bnb, pyramid, pattern-faces) list the maximal sign patterns
    /// (the convex pieces, each with a witness) of a 2D or 3D problem.
    #[arg(long, value_name = "METHOD")]
    method: Option<MethodArg>,
    /// Faces of the pyramid that replaces the round friction cone in --method pyramid, 3 to 64
    /// [default: 8]. Only --method pyramid uses it (and only in 3D).
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    pyramid_faces: Option<i64>,
    /// Relative zero tolerance of the enumeration [default: 1e-9].
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    zero_tol: Option<f64>,
    /// Stop after this many seconds (the result is then marked incomplete; exit code 3).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    time_limit: Option<f64>,
    /// Stop when more than this many rays would be held at once (a memory bound: a ray of an
    /// m-node problem takes about 16 m bytes; ray methods and pyramid); the result is then
    /// marked incomplete.
    #[arg(long, value_name = "N")]
    max_rays: Option<usize>,
    /// Stop when the rays held would take more than this much memory: bytes, or with a unit
    /// (500M, 2G, 1.5GB; powers of 1000; ray methods and pyramid); the result is then marked
    /// incomplete.
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    max_memory: Option<u64>,
    #[command(flatten)]
    json: JsonArg,
    /// For a meshed body: write one ParaView file per wedged cone, DIR/cone-N.vtu, or with a
    /// pattern method per maximal pattern, DIR/pattern-N.vtu (old cone-N.vtu and pattern-N.vtu
    /// files in DIR are removed).
    #[arg(long, value_name = "DIR")]
    vtk: Option<PathBuf>,
    /// For a meshed body: write one picture per wedged cone, DIR/cone-N.svg, or with a pattern
    /// method per maximal pattern, DIR/pattern-N.svg (old cone-N.svg and pattern-N.svg files in
    /// DIR are removed).
    #[arg(long, value_name = "DIR")]
    svg: Option<PathBuf>,
    /// Certify the answer in exact rational arithmetic. A 2D ray method (pruned-dd, full-dd,
    /// faces, exact): each ray recomputed from its status, checked extreme, feasible with
    /// exactly its status and complementary, and compared with the floating-point ray; each
    /// cone's rays checked cross-complementary (completeness checked up to 8 nodes; --exact
    /// gives a provably complete answer). A pattern method (bnb, pattern-faces; 2D or 3D): each
    /// pattern's witness recomputed exactly and checked, and every decision of the search
    /// backed by an infeasibility certificate checked exactly, which proves the patterns are
    /// all the maximal ones (the pyramid method's candidates are not certified). A failure is
    /// reported and the exit code is 1.
    #[arg(long)]
    certify: bool,
    /// Run the whole 2D enumeration in exact rational arithmetic (the same as --method exact):
    /// K and mu taken as the rationals their f64s are, every sign decided exactly, so the rays,
    /// their statuses and the cones are provably all of them. Slower than pruned-dd.
    #[arg(long)]
    exact: bool,
}

#[derive(Debug, Args)]
struct CondenseArgs {
    /// The problem file (TOML with a [mesh]; see --help).
    problem: PathBuf,
    /// Write the condensed stiffness here (Matrix Market, coordinate real symmetric; written
    /// atomically). Its comment lines name each contact node's mesh node and frame.
    #[arg(long, value_name = "K.mtx")]
    mtx: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct DemoArgs {
    /// Directory for the demo's JSON, VTU and SVG files.
    #[arg(long, value_name = "DIR", default_value = "wedged-demo")]
    out: PathBuf,
}

#[derive(Debug, Args)]
struct JsonArg {
    /// Also write the full result as JSON to this file (written atomically); `-` writes the JSON
    /// to stdout instead of the summary.
    #[arg(long, value_name = "OUT.json")]
    json: Option<PathBuf>,
}

/// A ray [`Method`] or a [`PatternMethod`] as a command-line value, named by their `name()`.
/// The pyramid's number of faces comes from `--pyramid-faces`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MethodArg {
    Rays(Method),
    Patterns(PatternMethod),
}

impl MethodArg {
    fn name(self) -> &'static str {
        match self {
            MethodArg::Rays(m) => m.name(),
            MethodArg::Patterns(m) => m.name(),
        }
    }
}

impl ValueEnum for MethodArg {
    fn value_variants<'a>() -> &'a [Self] {
        &[
            MethodArg::Rays(Method::PrunedDd),
            MethodArg::Rays(Method::FullDd),
            MethodArg::Rays(Method::Faces),
            MethodArg::Rays(Method::Exact),
            MethodArg::Patterns(PatternMethod::Bnb),
            MethodArg::Patterns(PatternMethod::Pyramid {
                faces: DEFAULT_PYRAMID_FACES,
            }),
            MethodArg::Patterns(PatternMethod::Faces),
        ]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let help = match self {
            MethodArg::Rays(Method::PrunedDd) => "2D rays: the seed's pruned double description",
            MethodArg::Rays(Method::FullDd) => {
                "2D rays: every extreme ray by double description, then a filter"
            }
            MethodArg::Rays(Method::Faces) => {
                "2D rays: brute force over the 2^m contact sets (small m only)"
            }
            MethodArg::Rays(Method::Exact) => {
                "2D rays: double description in exact rational arithmetic (as --exact)"
            }
            MethodArg::Patterns(PatternMethod::Bnb) => {
                "patterns (2D, 3D): branch and bound with conic relaxations"
            }
            MethodArg::Patterns(PatternMethod::Pyramid { .. }) => {
                "patterns (2D, 3D): the 2D algorithm on a pyramid around the friction cone, \
                 candidates checked exactly"
            }
            MethodArg::Patterns(PatternMethod::Faces) => {
                "patterns (2D, 3D): brute force over the 2^m contact sets (m <= 12)"
            }
        };
        Some(PossibleValue::new(self.name()).help(help))
    }
}

/// Why a run failed; decides the exit code.
#[derive(Debug)]
enum Failure {
    /// Bad input or usage: exit code 2.
    Input(String),
    /// A failure of the program itself: exit code 1.
    Internal(String),
    /// The run stopped at a limit or on Ctrl-C; its results were written, marked incomplete:
    /// exit code 3.
    Incomplete(String),
}

impl Failure {
    fn exit_code(&self) -> ExitCode {
        match self {
            Failure::Input(_) => ExitCode::from(2),
            Failure::Internal(_) => ExitCode::from(1),
            Failure::Incomplete(_) => ExitCode::from(3),
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Input(m) | Failure::Internal(m) | Failure::Incomplete(m) => f.write_str(m),
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Ctrl-C asks the run to stop cleanly; a second Ctrl-C ends the process at once.
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::Relaxed) {
            std::process::exit(130);
        }
    });
    // A panic is a bug: report it on one line, as an internal failure, without a backtrace.
    panic::set_hook(Box::new(|info| {
        if wedged_cli::panic_is_contained() {
            // A third-party parser's panic that the caller turns into an input error.
            return;
        }
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
        Ok(Err(failure @ Failure::Incomplete(_))) => {
            eprintln!("incomplete: {}", one_line(&failure.to_string()));
            failure.exit_code()
        }
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
        Command::Condense(args) => run_condense(args),
        Command::Critical(args) => run_critical(args),
        Command::Sweep(args) => run_sweep(args),
        Command::Demo(args) => run_demo(args),
    }
}

/// The limits of `--time-limit`.
fn time_limits(time_limit: Option<f64>) -> Result<Limits, Failure> {
    let mut limits = Limits::default();
    if let Some(t) = time_limit {
        if !(t.is_finite() && t >= 0.0) {
            return Err(Failure::Input(format!(
                "--time-limit must be a finite number of seconds >= 0, got {t}"
            )));
        }
        limits.time_limit = Some(Duration::from_secs_f64(t));
    }
    Ok(limits)
}

fn run_enumerate(args: EnumerateArgs) -> Result<(), Failure> {
    let source = args.problem.display().to_string();
    let faces = match args.pyramid_faces {
        None => None,
        Some(k) if (3..=64).contains(&k) => Some(k as usize),
        Some(k) => {
            return Err(Failure::Input(format!(
                "--pyramid-faces must be from 3 to 64, got {k}"
            )))
        }
    };
    let loaded = problem_file::load(&args.problem, args.mu.is_some())
        .map_err(|e| Failure::Input(e.to_string()))?;
    let problem = match args.mu {
        Some(mu) => loaded
            .problem
            .with_mu(mu)
            .map_err(|e| Failure::Input(format!("--mu: {e}")))?,
        None => loaded.problem,
    };
    let mut limits = time_limits(args.time_limit)?;
    limits.max_rays = args.max_rays;
    limits.max_memory = args.max_memory;
    if args.exact {
        if let Some(other) = args.method.filter(|&m| m != MethodArg::Rays(Method::Exact)) {
            return Err(Failure::Input(format!(
                "--exact runs the exact 2D ray enumeration (--method exact); it cannot be \
                 combined with --method {}",
                other.name()
            )));
        }
        if problem.dim() != 2 {
            return Err(Failure::Input(format!(
                "{source}: dim = {}: --exact enumerates the rays of a 2D problem; a 3D problem \
                 has sign patterns instead (--method bnb or pyramid)",
                problem.dim()
            )));
        }
    }
    let method = match args.method {
        Some(m) => m,
        None if args.exact => MethodArg::Rays(Method::Exact),
        None if problem.dim() == 2 => MethodArg::Rays(Method::PrunedDd),
        None => MethodArg::Patterns(PatternMethod::Bnb),
    };
    if faces.is_some() && !matches!(method, MethodArg::Patterns(PatternMethod::Pyramid { .. })) {
        return Err(Failure::Input(format!(
            "--pyramid-faces is used by --method pyramid only, and the method is {}",
            method.name()
        )));
    }
    let mut choice = match method {
        MethodArg::Rays(m) if problem.dim() != 2 => {
            return Err(Failure::Input(format!(
                "{source}: dim = {}: --method {} lists rays, which only a 2D problem has; use \
                 --method bnb (the default in 3D) or --method pyramid",
                problem.dim(),
                m.name()
            )))
        }
        MethodArg::Rays(method) => Choice::Rays(Settings {
            method,
            limits,
            ..Settings::default()
        }),
        MethodArg::Patterns(PatternMethod::Pyramid { .. }) => Choice::Patterns(PatternSettings {
            method: PatternMethod::Pyramid {
                faces: faces.unwrap_or(DEFAULT_PYRAMID_FACES),
            },
            limits,
            certify: args.certify,
            ..PatternSettings::default()
        }),
        MethodArg::Patterns(method) => Choice::Patterns(PatternSettings {
            method,
            limits,
            certify: args.certify,
            ..PatternSettings::default()
        }),
    };
    if let Some(t) = args.zero_tol {
        match &mut choice {
            Choice::Rays(s) => s.zero_tol = t,
            Choice::Patterns(s) => s.zero_tol = t,
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
            vtk: args.vtk.as_deref(),
            svg: args.svg.as_deref(),
            certify: args.certify,
        },
    )
}

fn run_condense(args: CondenseArgs) -> Result<(), Failure> {
    let source = args.problem.display().to_string();
    let model =
        problem_file::load_model(&args.problem).map_err(|e| Failure::Input(e.to_string()))?;
    let mut text = summary::model(&source, &model);
    if let Some(path) = &args.mtx {
        let bytes = mtx::write_condensed(&model, &source);
        output::write_atomic(path, bytes.as_bytes(), "Matrix Market file")
            .map_err(|e| Failure::Input(e.to_string()))?;
        text.push_str(&format!(
            "condensed stiffness ({n} x {n}) written to {}\n",
            path.display(),
            n = model.k().nrows()
        ));
    }
    write_stdout(&text)
}

fn run_demo(args: DemoArgs) -> Result<(), Failure> {
    let (model, mu) = wedged::examples::plug2d_demo()
        .map_err(|e| Failure::Internal(format!("the demo model: {e}")))?;
    let problem = Problem::new(2, model.k().clone(), mu)
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
    let result = run_critical_library(&problem, &settings, "demo")?;
    let line = match critical_out::answer_line(&result, settings.tol) {
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

/// What `critical` and `sweep` read and where they write.
struct CriticalJob<'a> {
    problem: Problem,
    model: Option<Model>,
    file_mu: Option<f64>,
    settings: CriticalSettings,
    source: String,
    json: Option<&'a Path>,
    svg: Option<&'a Path>,
}

/// Loads the problem of `critical` or `sweep` and checks the options (the library checks --tol).
fn critical_job<'a>(
    problem: &Path,
    method: CriticalMethod,
    certify: bool,
    common: &CriticalCommon,
    json: Option<&'a Path>,
    svg: Option<&'a Path>,
) -> Result<CriticalJob<'a>, Failure> {
    let limits = time_limits(common.time_limit)?;
    let (loaded, mu_given) =
        problem_file::load_for_critical(problem).map_err(|e| Failure::Input(e.to_string()))?;
    Ok(CriticalJob {
        file_mu: mu_given.then(|| loaded.problem.mu()),
        problem: loaded.problem,
        model: loaded.model,
        settings: CriticalSettings {
            method,
            tol: common.tol.unwrap_or(wedged::critical::DEFAULT_TOL),
            limits,
            certify,
        },
        source: problem.display().to_string(),
        json,
        svg,
    })
}

fn run_critical(args: CriticalArgs) -> Result<(), Failure> {
    let method = args.method.map_or(CriticalMethod::Bnb, |m| m.0);
    if args.certify && method == CriticalMethod::Enumerate {
        return Err(Failure::Input(
            "--certify needs --method bnb or faces: the enumerate method's lower end rests on \
             a floating-point enumeration of patterns, which is not certified"
                .to_string(),
        ));
    }
    let job = critical_job(
        &args.problem,
        method,
        args.certify,
        &args.common,
        args.json.json.as_deref(),
        None,
    )?;
    report_critical(job)
}

fn run_sweep(args: SweepArgs) -> Result<(), Failure> {
    let job = critical_job(
        &args.problem,
        CriticalMethod::Enumerate,
        false,
        &args.common,
        args.json.json.as_deref(),
        Some(&args.svg),
    )?;
    report_critical(job)
}

/// Computes `mu*` and writes the summary, the JSON and (sweep) the plot. The JSON and SVG targets
/// are opened before the run, so that an unwritable path fails before a long computation.
fn report_critical(job: CriticalJob) -> Result<(), Failure> {
    let CriticalJob {
        problem,
        model,
        file_mu,
        settings,
        source,
        json,
        svg,
    } = job;
    let json = json
        .map(JsonTarget::open)
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let svg = svg
        .map(|path| PendingFile::open(path, "SVG file"))
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let result = run_critical_library(&problem, &settings, &source)?;
    let json_text = json
        .as_ref()
        .map(|_| critical_out::to_json(&problem, &settings, &source, &result, model.as_ref()));
    let incomplete = match result.status {
        CriticalStatus::Incomplete(stop) => Some(stop),
        _ => None,
    };
    let mut stdout_text = String::new();
    let mut svg_line = String::new();
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
            stdout_text.push_str(&critical_out::render(
                &problem, &settings, &source, file_mu, &result, json_path,
            ));
            stdout_text.push_str(&svg_line);
        }
    }
    if let (Some(target @ JsonTarget::File { .. }), Some(text)) = (json, &json_text) {
        target
            .commit(text)
            .map_err(|e| Failure::Input(e.to_string()))?;
    }
    write_stdout(&stdout_text)?;
    if let Some(c) = result.certificate.as_ref().filter(|c| !c.certified) {
        return Err(Failure::Internal(format!(
            "{source}: exact certification of mu* failed ({}; first: {})",
            match c.failures.len() {
                1 => "1 check".to_string(),
                n => format!("{n} checks"),
            },
            c.failures.first().map_or("", String::as_str)
        )));
    }
    match incomplete {
        Some(stop) => Err(Failure::Incomplete(critical_incomplete_text(
            &source, &result, stop,
        ))),
        None => Ok(()),
    }
}

/// The `incomplete: ...` line of an incomplete `critical` or `sweep` run.
fn critical_incomplete_text(source: &str, result: &Critical, stop: Stop) -> String {
    let found = match result.upper {
        Some(upper) => format!(
            "mu* <= {} (a checked wedged configuration), not certified from below",
            critical_out::bound(upper, 10, critical_out::Round::Up)
        ),
        None => "no wedged configuration found, nothing claimed about mu*".to_string(),
    };
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

/// Runs the computation of `mu*` with the live progress line and sorts its errors into bad input
/// and internal failures.
fn run_critical_library(
    problem: &Problem,
    settings: &CriticalSettings,
    source: &str,
) -> Result<Critical, Failure> {
    let start = std::time::Instant::now();
    let live = io::stderr().is_terminal();
    let shown = std::cell::Cell::new(false);
    let progress = |p: CriticalProgress| {
        if live && start.elapsed().as_secs_f64() > 1.0 {
            eprint!(
                "\r  {}   ",
                critical_progress_text(p, start.elapsed().as_secs_f64())
            );
            shown.set(true);
        }
    };
    let result = critical_with_control(problem, settings, &progress, &INTERRUPTED);
    if shown.get() {
        eprintln!();
    }
    result.map_err(|e| match e {
        EnumerateError::InvalidSettings(m) => Failure::Input(format!("invalid option: {m}")),
        e @ EnumerateError::UnsupportedDim(_) => Failure::Input(format!("{source}: {e}")),
        e @ EnumerateError::Internal(_) => Failure::Internal(format!("{source}: {e}")),
    })
}

/// The live progress line of `critical` and `sweep` (without its carriage return).
fn critical_progress_text(p: CriticalProgress, seconds: f64) -> String {
    let best = match p.upper {
        Some(mu) => format!("best mu {}", svg::sig4(mu)),
        None => "no wedged configuration yet".to_string(),
    };
    format!(
        "explored {:.1}%, {best}, {seconds:.1} s",
        100.0 * p.explored.clamp(0.0, 1.0)
    )
}

/// Where a run's results go besides the summary on stdout.
struct Outputs<'a> {
    preface: Option<&'a str>,
    json: Option<&'a Path>,
    vtk: Option<&'a Path>,
    svg: Option<&'a Path>,
    /// `--certify`: certify a ray method's answer in exact rational arithmetic (a pattern
    /// method certifies during its run, from its settings).
    certify: bool,
}

/// Enumerates and writes the summary and the JSON. The JSON target is opened before the run, so
/// that an unwritable path fails before a long computation.
fn report(
    problem: &Problem,
    choice: &Choice,
    source: &str,
    model: Option<&Model>,
    outputs: Outputs,
) -> Result<(), Failure> {
    let Outputs {
        preface,
        json,
        vtk,
        svg,
        certify,
    } = outputs;
    let json = json
        .map(JsonTarget::open)
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    if let Some(dir) = vtk {
        export::prepare_dir(dir, "--vtk", "vtu").map_err(Failure::Input)?;
    }
    if let Some(dir) = svg {
        export::prepare_dir(dir, "--svg", "svg").map_err(Failure::Input)?;
    }
    let answer = run_library(problem, choice, source)?;
    let rays_certificate = match (&answer, certify) {
        (Answer::Rays(result), true) => Some(certify_enumeration(problem, result)),
        _ => None,
    };
    let certificate = match &answer {
        Answer::Rays(_) => rays_certificate.as_ref().map(summary::Certified::Rays),
        Answer::Patterns(p) => p.certificate.as_ref().map(summary::Certified::Patterns),
    };
    let json_text = json
        .as_ref()
        .map(|_| output::to_json(problem, choice, &answer, model, certificate.as_ref()));
    let incomplete = answer.stopped();
    let written = match model {
        Some(model) if (vtk.is_some() || svg.is_some()) && incomplete.is_none() => {
            export::write_pieces(model, problem, &answer, vtk, svg).map_err(Failure::Input)?
        }
        _ => Vec::new(),
    };
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
            if let Some(model) = model {
                stdout_text.push_str(&summary::model(source, model));
            }
            stdout_text.push_str(&summary::render(
                problem, choice, source, &answer, json_path,
            ));
            if let Some(c) = &certificate {
                stdout_text.push_str(&summary::certification(c));
            }
            stdout_text.push_str(&summary::files(&answer, vtk, svg, &written));
        }
    }
    if let (Some(target @ JsonTarget::File { .. }), Some(text)) = (json, &json_text) {
        target
            .commit(text)
            .map_err(|e| Failure::Input(e.to_string()))?;
    }
    write_stdout(&stdout_text)?;
    if let Some(c) = certificate.as_ref().filter(|c| !c.certified()) {
        let failures = c.failures();
        return Err(Failure::Internal(format!(
            "{source}: exact certification failed ({}; first: {}): the floating-point answer \
             cannot be trusted",
            match failures.len() {
                1 => "1 check".to_string(),
                n => format!("{n} checks"),
            },
            failures.first().map_or("", String::as_str)
        )));
    }
    match incomplete {
        Some(stop) => Err(Failure::Incomplete(incomplete_text(
            source, problem, &answer, stop,
        ))),
        None => Ok(()),
    }
}

/// The `incomplete: ...` line of an incomplete run.
fn incomplete_text(source: &str, problem: &Problem, answer: &Answer, stop: Stop) -> String {
    match answer {
        Answer::Rays(result) => format!(
            "{source}: {stop} after {} of {} nodes; the result is incomplete",
            result.info.rays_after_node.len(),
            problem.nodes()
        ),
        Answer::Patterns(result) if stop == Stop::Undecided => format!(
            "{source}: {stop} ({} undecided, listed in the summary and the JSON); the patterns \
             below them may be missing, so the result is incomplete",
            result.undecided.len()
        ),
        Answer::Patterns(result) => format!(
            "{source}: {stop} with {} found so far; the result is incomplete",
            match result.patterns.len() {
                1 => "1 maximal pattern".to_string(),
                n => format!("{n} maximal patterns"),
            }
        ),
    }
}

/// Runs the enumeration and sorts its errors into bad input and internal failures.
fn run_library(problem: &Problem, choice: &Choice, source: &str) -> Result<Answer, Failure> {
    // A live progress line on stderr, only for a person at a terminal and only once the run has
    // lasted a second: pipes, files and CI logs stay clean.
    let start = std::time::Instant::now();
    let live = io::stderr().is_terminal();
    let shown = std::cell::Cell::new(false);
    let progress = |p: Progress| {
        if live && start.elapsed().as_secs_f64() > 1.0 {
            eprint!(
                "\r  {}   ",
                progress_text(choice, p, start.elapsed().as_secs_f64())
            );
            shown.set(true);
        }
    };
    let result = match choice {
        Choice::Rays(settings) => {
            enumerate_with_control(problem, settings, &progress, &INTERRUPTED).map(Answer::Rays)
        }
        Choice::Patterns(settings) => {
            enumerate_patterns_with_control(problem, settings, &progress, &INTERRUPTED)
                .map(Answer::Patterns)
        }
    };
    if shown.get() {
        eprintln!();
    }
    result.map_err(|e| match e {
        EnumerateError::UnsupportedDim(d) => Failure::Input(format!(
            "{source}: dim = {d}: --method {} needs a 2D problem; use --method bnb or pyramid",
            choice.name()
        )),
        EnumerateError::InvalidSettings(m) => Failure::Input(format!("invalid option: {m}")),
        e @ EnumerateError::Internal(_) => Failure::Internal(format!("{source}: {e}")),
    })
}

/// The live progress line (without its carriage return).
fn progress_text(choice: &Choice, p: Progress, seconds: f64) -> String {
    match choice {
        Choice::Patterns(PatternSettings {
            method: PatternMethod::Bnb,
            ..
        }) => format!(
            "explored {:.1}% of the search tree, {} found, {seconds:.1} s",
            100.0 * p.done as f64 / p.total.max(1) as f64,
            if p.rays == 1 {
                "1 pattern".to_string()
            } else {
                format!("{} patterns", p.rays)
            }
        ),
        Choice::Patterns(_) => format!(
            "pyramid approximation, node {}/{}: {} rays held, {seconds:.1} s",
            p.done, p.total, p.rays
        ),
        Choice::Rays(_) => format!(
            "node {}/{}: {} rays held, {seconds:.1} s",
            p.done, p.total, p.rays
        ),
    }
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

/// Set by Ctrl-C; the enumeration polls it.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// A memory size: a number of bytes, or a number with `k`, `M`, `G` or `T` (powers of 1000),
/// optionally followed by `B`: `500M`, `2G`, `1.5GB`.
fn parse_size(text: &str) -> Result<u64, String> {
    let t = text.trim();
    let t = t.strip_suffix(['B', 'b']).unwrap_or(t);
    let (number, factor) = match t.chars().last() {
        Some('k' | 'K') => (&t[..t.len() - 1], 1e3),
        Some('m' | 'M') => (&t[..t.len() - 1], 1e6),
        Some('g' | 'G') => (&t[..t.len() - 1], 1e9),
        Some('t' | 'T') => (&t[..t.len() - 1], 1e12),
        _ => (t, 1.0),
    };
    match number.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 && x * factor < 1.8e19 => Ok((x * factor) as u64),
        _ => Err(format!(
            "expected a positive size such as 500M, 2G or 1500000000, got {text:?}"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_size("500M"), Ok(500_000_000));
        assert_eq!(parse_size("1.5GB"), Ok(1_500_000_000));
        assert_eq!(parse_size("2g"), Ok(2_000_000_000));
        assert_eq!(parse_size("1234"), Ok(1234));
        assert_eq!(parse_size("64kB"), Ok(64_000));
        for bad in ["", "G", "-1G", "lots", "0", "nanM", "1e30T"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }

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
        let mut library: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        library.extend(
            [
                PatternMethod::Bnb,
                PatternMethod::Pyramid { faces: 8 },
                PatternMethod::Faces,
            ]
            .map(PatternMethod::name),
        );
        assert_eq!(names, library);
    }

    #[test]
    fn progress_lines_name_what_they_count() {
        let p = Progress {
            done: 372,
            total: 1000,
            rays: 5,
        };
        let bnb = Choice::Patterns(PatternSettings::default());
        assert_eq!(
            progress_text(&bnb, p, 3.42),
            "explored 37.2% of the search tree, 5 patterns found, 3.4 s"
        );
        let rays = Choice::Rays(Settings::default());
        let p = Progress {
            done: 3,
            total: 12,
            rays: 40,
        };
        assert_eq!(
            progress_text(&rays, p, 1.0),
            "node 3/12: 40 rays held, 1.0 s"
        );
    }

    #[test]
    fn incomplete_pattern_runs_say_why_without_node_counts() {
        use wedged::patterns::{PatternInfo, Patterns, Undecided};
        let problem = Problem::new(3, nalgebra::DMatrix::identity(6, 6), 1.0).unwrap();
        let mut result = Patterns {
            outcome: wedged::Outcome::Incomplete(Stop::Undecided),
            patterns: Vec::new(),
            undecided: vec![Undecided {
                contact: vec![true, false],
                reason: "stalled".to_string(),
            }],
            info: PatternInfo::default(),
            certificate: None,
        };
        let text = incomplete_text(
            "p.toml",
            &problem,
            &Answer::Patterns(result.clone()),
            Stop::Undecided,
        );
        assert_eq!(
            text,
            "p.toml: the solver could not decide some contact sets (1 undecided, listed in the \
             summary and the JSON); the patterns below them may be missing, so the result is \
             incomplete"
        );
        result.undecided.clear();
        let stop = Stop::TimeLimit(Duration::from_secs(2));
        let text = incomplete_text("p.toml", &problem, &Answer::Patterns(result), stop);
        assert_eq!(
            text,
            "p.toml: the time limit of 2 s ran out with 0 maximal patterns found so far; the \
             result is incomplete"
        );
    }

    #[test]
    fn critical_progress_names_the_best_mu() {
        let p = CriticalProgress {
            explored: 0.372,
            upper: Some(1.23456),
        };
        assert_eq!(
            critical_progress_text(p, 3.42),
            "explored 37.2%, best mu 1.235, 3.4 s"
        );
        let p = CriticalProgress {
            explored: 0.0,
            upper: None,
        };
        assert_eq!(
            critical_progress_text(p, 1.0),
            "explored 0.0%, no wedged configuration yet, 1.0 s"
        );
    }

    #[test]
    fn critical_method_names_are_the_library_names() {
        let names: Vec<String> = CriticalMethodArg::value_variants()
            .iter()
            .map(|m| m.to_possible_value().unwrap().get_name().to_string())
            .collect();
        assert_eq!(names, ["bnb", "enumerate", "faces"]);
    }

    #[test]
    fn one_line_joins_lines() {
        assert_eq!(one_line("a\n  b\n\nc "), "a; b; c");
    }
}
