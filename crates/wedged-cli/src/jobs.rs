//! A run of `enumerate` or `critical` as the command and the Python package (`wedged-py`)
//! both make it: the options checked and turned into the library's settings, the run with its
//! progress line and its cancel flag, its errors sorted into bad input and internal failures.
//! Both fronts call these, so that the same options give the same answer and the same message.

use std::fmt;
use std::io::{self, IsTerminal};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use clap::builder::PossibleValue;
use clap::ValueEnum;
use wedged::patterns::{
    enumerate_patterns_streaming, enumerate_patterns_with_control, PatternMethod, PatternSettings,
    PatternSink, DEFAULT_PYRAMID_FACES,
};
use wedged::{
    critical_with_control, enumerate_with_control, Critical, CriticalMethod, CriticalSettings,
    EnumerateError, Limits, Method, Problem, Progress, Settings,
};

use wedged::certify::certify_enumeration;
use wedged::fe::Model;

use crate::progress::{critical_progress_text, progress_text, share, Pace};
use crate::report::answer::{Answer, Certified, Choice};

/// Why a run failed; decides the exit code.
#[derive(Debug)]
pub enum Failure {
    /// Bad input or usage: exit code 2.
    Input(String),
    /// A failure of the program itself: exit code 1.
    Internal(String),
    /// The run stopped at a limit or on Ctrl-C; its results were written, marked incomplete:
    /// exit code 3.
    Incomplete(String),
}

impl Failure {
    pub fn exit_code(&self) -> ExitCode {
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

/// The limits of `--time-limit`.
pub fn time_limits(time_limit: Option<f64>) -> Result<Limits, Failure> {
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

/// When the live progress line is drawn on stderr.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Show {
    /// Only for a person at a terminal (stderr is one), once the run has lasted a second:
    /// pipes, files and CI logs stay clean. The command's choice.
    Terminal,
    /// Whatever stderr is, once the run has lasted a second (Python's `progress=True`).
    Always,
    /// Never.
    Never,
}

impl Show {
    fn live(self) -> bool {
        match self {
            Show::Terminal => io::stderr().is_terminal(),
            Show::Always => true,
            Show::Never => false,
        }
    }
}

/// The options of `wedged enumerate` that choose and tune the method.
#[derive(Debug, Clone, Default)]
pub struct EnumerateOptions {
    /// `--method` (none: pruned-dd in 2D, bnb in 3D; exact with `exact`).
    pub method: Option<MethodArg>,
    /// `--pyramid-faces`.
    pub pyramid_faces: Option<i64>,
    /// `--zero-tol`.
    pub zero_tol: Option<f64>,
    /// `--time-limit`, seconds.
    pub time_limit: Option<f64>,
    /// `--max-rays`.
    pub max_rays: Option<usize>,
    /// `--max-memory`, bytes.
    pub max_memory: Option<u64>,
    /// `--certify`.
    pub certify: bool,
    /// `--exact`.
    pub exact: bool,
    /// `--shard I/N`: one shard of the search (pattern methods with a tree: `bnb`,
    /// `pattern-search`, the default with a shard).
    pub shard: Option<wedged::Shard>,
    /// `--jsonl`: the pieces are streamed (a pattern method; `pattern-search` by default in
    /// 2D).
    pub stream: bool,
}

/// The most contact nodes of a 2D problem (clamped, not sharded or streamed) for which
/// `enumerate` lists the extreme rays by default; above it the default is `pattern-search`
/// (the pieces with a witness each; `bnb` with `--certify`). Measured on the triangle plug
/// (whole process, pruned-dd against pattern-search): m = 12 0.02 s against 0.01 s, m = 14
/// 0.11 s against 0.01 s, m = 16 0.99 s against 0.02 s, m = 18 7.1 s against 0.03 s, m = 20
/// 264 s against 0.04 s: the rays' double description grows about 7x per two nodes there, the
/// search with the pieces. The rays by `search` (the pieces, then each one's rays) reach
/// further on the plug (m = 20 in 0.2 s) but not far (m = 30 not in 120 s: the rays of its
/// pieces multiply), and a random m = 12 problem already has thousands of rays (4,934 in
/// 2.4 s).
pub const RAYS_DEFAULT_MAX_NODES: usize = 12;

/// The method and settings that `options` ask for on `problem` (`source` names the problem in
/// messages), or why they cannot run.
pub fn plan_enumerate(
    problem: &Problem,
    source: &str,
    options: &EnumerateOptions,
) -> Result<Choice, Failure> {
    let faces = match options.pyramid_faces {
        None => None,
        Some(k) if (3..=64).contains(&k) => Some(k as usize),
        Some(k) => {
            return Err(Failure::Input(format!(
                "--pyramid-faces must be from 3 to 64, got {k}"
            )))
        }
    };
    let mut limits = time_limits(options.time_limit)?;
    limits.max_rays = options.max_rays;
    limits.max_memory = options.max_memory;
    if options.exact {
        if let Some(other) = options
            .method
            .filter(|&m| m != MethodArg::Rays(Method::Exact))
        {
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
    let method = match options.method {
        Some(m) => m,
        None if options.exact => MethodArg::Rays(Method::Exact),
        // Shards split a search tree, and a floating body's pieces are sign patterns (the ray
        // methods are for clamped bodies): the contact-set search of the pieces in 2D.
        // With --certify, bnb: its decisions are kept for the exact check.
        // Above RAYS_DEFAULT_MAX_NODES the extreme rays are out of reach (pruned-dd's
        // intermediate rays explode) and the pieces are what a run can give.
        None if problem.dim() == 2
            && (options.shard.is_some()
                || problem.is_floating()
                || options.stream
                || (problem.nodes() > RAYS_DEFAULT_MAX_NODES
                    // A bound on the rays held asks for a ray method.
                    && options.max_rays.is_none()
                    && options.max_memory.is_none())) =>
        {
            MethodArg::Patterns(if options.certify {
                PatternMethod::Bnb
            } else {
                PatternMethod::Search
            })
        }
        // The rays: by `search` (the contact sets some solution presses, then each piece's
        // rays in its own dimension), faster than the seed's pruned double description on
        // every problem measured (BENCHMARKS.md, "The default ray method": random m = 9,
        // whole process, 0.46x to 0.80x; random m = 12 0.33 s against 1.00 s); `pruned-dd`
        // when the rays held are bounded (`--max-rays`, `--max-memory`: its ray store).
        None if problem.dim() == 2
            && (options.max_rays.is_some() || options.max_memory.is_some()) =>
        {
            MethodArg::Rays(Method::PrunedDd)
        }
        None if problem.dim() == 2 => MethodArg::Rays(Method::Search),
        None => MethodArg::Patterns(PatternMethod::Bnb),
    };
    if problem.is_floating() {
        let why = match method {
            MethodArg::Rays(_) => Some(wedged::rays::FLOATING_RAYS.to_string()),
            MethodArg::Patterns(m) => wedged::patterns::floating_refusal(m),
        };
        if let Some(why) = why {
            return Err(Failure::Input(format!("{source}: {why}")));
        }
    }
    if options.certify {
        // Their answers' completeness rests on floating-point decisions that are not kept for
        // an exact check: refused here rather than reported as a failed certification (exit
        // 1, "a bug") after the run.
        let why = match method {
            MethodArg::Patterns(PatternMethod::Pyramid { .. }) => {
                Some("its candidates come from a floating-point double description on the pyramid")
            }
            _ => None,
        };
        if let Some(why) = why {
            return Err(Failure::Input(format!(
                "--certify cannot prove the answer of --method {} complete ({why}); use \
                 --method bnb, pattern-search (2D) or pattern-faces for certified patterns, or \
                 drop --certify",
                method.name()
            )));
        }
    }
    if let Some(shard) = options.shard {
        if !matches!(
            method,
            MethodArg::Patterns(PatternMethod::Bnb | PatternMethod::Search)
        ) {
            return Err(Failure::Input(format!(
                "--shard {shard} splits the search tree of --method bnb or pattern-search (the \
                 default with --shard); --method {} has none to split",
                method.name()
            )));
        }
    }
    if options.stream {
        if let MethodArg::Rays(m) = method {
            return Err(Failure::Input(format!(
                "--jsonl streams sign patterns, and --method {} lists rays: use --json, or a \
                 pattern method (pattern-search, the default with --jsonl in 2D)",
                m.name()
            )));
        }
        if let Some(shard) = options.shard {
            return Err(Failure::Input(format!(
                "--jsonl streams a whole run's pieces; --shard {shard} writes a part for \
                 `wedged merge` with --json: give one of them"
            )));
        }
    }
    // `--max-rays` and `--max-memory` bound a double description's store of rays; a method
    // without one would run unbounded while the user believes it bounded.
    let holds_rays = matches!(
        method,
        MethodArg::Rays(Method::PrunedDd | Method::FullDd | Method::Faces | Method::Exact)
            | MethodArg::Patterns(PatternMethod::Pyramid { .. })
    );
    if !holds_rays {
        for (given, option) in [
            (options.max_rays.is_some(), "--max-rays"),
            (options.max_memory.is_some(), "--max-memory"),
        ] {
            if given {
                return Err(Failure::Input(format!(
                    "{option} bounds the store of rays of a double description (pruned-dd, \
                     full-dd, faces, exact, pyramid); --method {} has no such bound: limit its \
                     run with --time-limit",
                    method.name()
                )));
            }
        }
    }
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
            certify: options.certify,
            ..PatternSettings::default()
        }),
        MethodArg::Patterns(method) => Choice::Patterns(PatternSettings {
            method,
            limits,
            certify: options.certify,
            shard: options.shard,
            ..PatternSettings::default()
        }),
    };
    if let Some(t) = options.zero_tol {
        match &mut choice {
            Choice::Rays(s) => s.zero_tol = t,
            Choice::Patterns(s) => s.zero_tol = t,
        }
    }
    Ok(choice)
}

/// A finished enumeration and, with `--certify` on a ray method, its exact certificate (a
/// pattern method's is part of its answer).
pub struct Enumerated {
    pub answer: Answer,
    rays_certificate: Option<wedged::certify::Certificate>,
}

impl Enumerated {
    /// The exact certificate of the run, when `--certify` asked for one.
    pub fn certificate(&self) -> Option<Certified<'_>> {
        match &self.answer {
            Answer::Rays(_) => self.rays_certificate.as_ref().map(Certified::Rays),
            Answer::Patterns(p) => p.certificate.as_ref().map(Certified::Patterns),
        }
    }

    /// The JSON document of `--json`.
    pub fn json(&self, problem: &Problem, choice: &Choice, model: Option<&Model>) -> String {
        crate::report::json::to_json(
            problem,
            choice,
            &self.answer,
            model,
            self.certificate().as_ref(),
        )
    }

    /// [`Enumerated::json`] written to `out` as it is made.
    pub fn write_json(
        &self,
        problem: &Problem,
        choice: &Choice,
        model: Option<&Model>,
        out: &mut dyn std::io::Write,
    ) -> std::io::Result<()> {
        crate::report::json::write_json(
            problem,
            choice,
            &self.answer,
            model,
            self.certificate().as_ref(),
            out,
        )
    }

    /// The internal failure that a failed exact certification is (the answer cannot be
    /// trusted), `None` when it passed or was not asked for.
    pub fn certification_failure(&self, source: &str) -> Option<Failure> {
        let c = self.certificate().filter(|c| !c.certified())?;
        let failures = c.failures();
        Some(Failure::Internal(format!(
            "{source}: exact certification failed ({}; first: {}): the floating-point answer \
             cannot be trusted",
            match failures.len() {
                1 => "1 check".to_string(),
                n => format!("{n} checks"),
            },
            failures.first().map_or("", String::as_str)
        )))
    }
}

/// Runs the enumeration ([`run_library`]) and, when `certify` is set and the method lists
/// rays, certifies its answer in exact arithmetic.
pub fn enumerate(
    problem: &Problem,
    choice: &Choice,
    source: &str,
    certify: bool,
    cancel: &AtomicBool,
    show: Show,
    sink: Option<PatternSink>,
) -> Result<Enumerated, Failure> {
    let answer = run_library(problem, choice, source, cancel, show, sink)?;
    let rays_certificate = match (&answer, certify) {
        (Answer::Rays(result), true) => Some(certify_enumeration(problem, result)),
        _ => None,
    };
    Ok(Enumerated {
        answer,
        rays_certificate,
    })
}

/// Runs `work` with the live progress line on stderr: `text` makes the line of a progress
/// report and the seconds so far; it is drawn when `show` says, once the run has lasted a
/// second, and ended with a newline when it was drawn.
fn with_line<P, T>(
    show: Show,
    text: impl Fn(P, f64) -> String,
    work: impl FnOnce(&dyn Fn(P)) -> T,
) -> T {
    let start = std::time::Instant::now();
    let live = show.live();
    let shown = std::cell::Cell::new(false);
    let progress = |p: P| {
        let seconds = start.elapsed().as_secs_f64();
        if live && seconds > 1.0 {
            eprint!("\r  {}   ", text(p, seconds));
            shown.set(true);
        }
    };
    let result = work(&progress);
    if shown.get() {
        eprintln!();
    }
    result
}

/// Runs the enumeration and sorts its errors into bad input and internal failures.
/// `cancel` stops the run (it then returns what it found, marked incomplete); `show` says when
/// the live progress line is drawn; a pattern method hands its patterns to `sink` when one is
/// given ([`wedged::enumerate_patterns_streaming`]).
pub fn run_library(
    problem: &Problem,
    choice: &Choice,
    source: &str,
    cancel: &AtomicBool,
    show: Show,
    sink: Option<PatternSink>,
) -> Result<Answer, Failure> {
    let pace = Pace::default();
    let text = |p: Progress, seconds: f64| {
        let still = pace.still(share(&p), seconds);
        progress_text(choice, p, seconds, still)
    };
    let result = with_line(show, text, |progress| match choice {
        Choice::Rays(settings) => {
            enumerate_with_control(problem, settings, progress, cancel).map(Answer::Rays)
        }
        Choice::Patterns(settings) => match sink {
            Some(sink) => enumerate_patterns_streaming(problem, settings, progress, cancel, sink),
            None => enumerate_patterns_with_control(problem, settings, progress, cancel),
        }
        .map(Answer::Patterns),
    });
    result.map_err(|e| match e {
        EnumerateError::UnsupportedDim(d) => Failure::Input(format!(
            "{source}: dim = {d}: --method {} needs a 2D problem; use --method bnb or pyramid",
            choice.name()
        )),
        EnumerateError::InvalidSettings(m) => {
            Failure::Input(format!("{source}: invalid option: {m}"))
        }
        e @ EnumerateError::Internal(_) => Failure::Internal(format!("{source}: {e}")),
    })
}

/// The test hook `WEDGED_INJECT_FAULT` (see `wedged::Fault`): tests set it to see an internal
/// failure exit 1, or an interrupted search report what it proved. An unknown name is an input error, so that a typo cannot pass unnoticed.
pub fn injected_fault() -> Result<Option<wedged::Fault>, Failure> {
    match std::env::var("WEDGED_INJECT_FAULT") {
        Err(_) => Ok(None),
        Ok(name) => wedged::Fault::parse(&name).map(Some).ok_or_else(|| {
            Failure::Input(format!(
                "WEDGED_INJECT_FAULT={name:?} is not a known fault (corrupt-witness, halt-after-pass, settle-root)"
            ))
        }),
    }
}

/// The options of `wedged critical` that choose and tune the method.
#[derive(Debug, Clone, Default)]
pub struct CriticalOptions {
    /// `--method` (none: bnb).
    pub method: Option<CriticalMethod>,
    /// `--tol` (none: [`wedged::critical::DEFAULT_TOL`]; the library checks its range).
    pub tol: Option<f64>,
    /// `--time-limit`, seconds.
    pub time_limit: Option<f64>,
    /// `--certify`.
    pub certify: bool,
    /// `--shard I/N`: one shard of the bnb search.
    pub shard: Option<wedged::Shard>,
}

/// The settings that `options` ask for, or why they cannot run.
pub fn plan_critical(options: &CriticalOptions) -> Result<CriticalSettings, Failure> {
    let method = options.method.unwrap_or(CriticalMethod::Bnb);
    if options.certify && method == CriticalMethod::Enumerate {
        return Err(Failure::Input(
            "--certify needs --method bnb or faces: the enumerate method's lower end rests on \
             a floating-point enumeration of patterns, which is not certified"
                .to_string(),
        ));
    }
    if let (Some(shard), true) = (options.shard, method != CriticalMethod::Bnb) {
        return Err(Failure::Input(format!(
            "--shard {shard} splits the search tree of --method bnb; --method {} has none to \
             split",
            method.name()
        )));
    }
    Ok(CriticalSettings {
        method,
        tol: options.tol.unwrap_or(wedged::critical::DEFAULT_TOL),
        limits: time_limits(options.time_limit)?,
        certify: options.certify,
        fault: injected_fault()?,
        shard: options.shard,
        start: None,
        // The callers' `--no-chain` turns it off.
        condense: true,
    })
}

/// The internal failure that a failed exact certification of `mu*` is, `None` when it passed
/// or was not asked for.
pub fn critical_certification_failure(source: &str, result: &Critical) -> Option<Failure> {
    let c = result.certificate.as_ref().filter(|c| !c.certified)?;
    Some(Failure::Internal(format!(
        "{source}: exact certification of mu* failed ({}; first: {})",
        match c.failures.len() {
            1 => "1 check".to_string(),
            n => format!("{n} checks"),
        },
        c.failures.first().map_or("", String::as_str)
    )))
}

/// Runs the computation of `mu*` with the live progress line and sorts its errors into bad input
/// and internal failures; `cancel` and `show` as in [`run_library`].
pub fn run_critical_library(
    problem: &Problem,
    settings: &CriticalSettings,
    source: &str,
    cancel: &AtomicBool,
    show: Show,
) -> Result<Critical, Failure> {
    let result = with_line(show, critical_progress_text, |progress| {
        critical_with_control(problem, settings, progress, cancel)
    });
    result.map_err(|e| match e {
        EnumerateError::InvalidSettings(m) => {
            Failure::Input(format!("{source}: invalid option: {m}"))
        }
        e @ EnumerateError::UnsupportedDim(_) => Failure::Input(format!("{source}: {e}")),
        e @ EnumerateError::Internal(_) => Failure::Internal(format!("{source}: {e}")),
    })
}

/// A ray [`Method`] or a [`PatternMethod`] as a command-line value, named by their `name()`.
/// The pyramid's number of faces comes from `--pyramid-faces`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MethodArg {
    Rays(Method),
    Patterns(PatternMethod),
}

impl MethodArg {
    /// The method of this name (`pruned-dd`, `bnb`, ...), as `--method` takes it.
    pub fn named(name: &str) -> Option<MethodArg> {
        MethodArg::value_variants()
            .iter()
            .copied()
            .find(|m| m.name() == name)
    }

    pub fn name(self) -> &'static str {
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
            MethodArg::Rays(Method::Search),
            MethodArg::Patterns(PatternMethod::Bnb),
            MethodArg::Patterns(PatternMethod::Pyramid {
                faces: DEFAULT_PYRAMID_FACES,
            }),
            MethodArg::Patterns(PatternMethod::Faces),
            MethodArg::Patterns(PatternMethod::Search),
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
            MethodArg::Rays(Method::Search) => {
                "2D rays: depth-first search over contact sets (warm-started simplex), then the \
                 rays of each face in its own dimension"
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
            MethodArg::Patterns(PatternMethod::Search) => {
                "patterns (2D): depth-first search over contact sets (warm-started simplex), \
                 no rays; for large meshes"
            }
        };
        Some(PossibleValue::new(self.name()).help(help))
    }
}

/// A [`CriticalMethod`] as a command-line value, named by its `name()`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CriticalMethodArg(pub CriticalMethod);

impl CriticalMethodArg {
    /// The method of this name (`bnb`, `enumerate`, `faces`), as `--method` takes it.
    pub fn named(name: &str) -> Option<CriticalMethod> {
        CriticalMethodArg::value_variants()
            .iter()
            .map(|m| m.0)
            .find(|m| m.name() == name)
    }
}

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
