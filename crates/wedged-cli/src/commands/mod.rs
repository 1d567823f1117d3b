//! One file per subcommand: `enumerate` (and its report), `critical` and `sweep`, `condense`,
//! `demo`. This file holds what they share: [`Failure`] (which decides the exit code), the
//! dispatch [`run`], the cancel flag set by Ctrl-C, the time limit, and stdout.

mod condense;
mod critical;
mod demo;
mod enumerate;

use condense::*;
use critical::*;
use demo::*;
use enumerate::*;

use std::fmt;
use std::io::{self, Write};
use std::process::ExitCode;

use std::sync::atomic::AtomicBool;
use std::time::Duration;
use wedged::Limits;

use crate::args::*;

/// Why a run failed; decides the exit code.
#[derive(Debug)]
pub(crate) enum Failure {
    /// Bad input or usage: exit code 2.
    Input(String),
    /// A failure of the program itself: exit code 1.
    Internal(String),
    /// The run stopped at a limit or on Ctrl-C; its results were written, marked incomplete:
    /// exit code 3.
    Incomplete(String),
}

impl Failure {
    pub(crate) fn exit_code(&self) -> ExitCode {
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

pub(crate) fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Enumerate(args) => run_enumerate(args),
        Command::Condense(args) => run_condense(args),
        Command::Critical(args) => run_critical(args),
        Command::Sweep(args) => run_sweep(args),
        Command::Demo(args) => run_demo(args),
    }
}

/// The limits of `--time-limit`.
pub(crate) fn time_limits(time_limit: Option<f64>) -> Result<Limits, Failure> {
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

/// Writes to stdout; a closed pipe (`wedged demo | head`) ends the output quietly.
pub(crate) fn write_stdout(text: &str) -> Result<(), Failure> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Failure::Internal(format!("cannot write to stdout: {e}"))),
    }
}

/// Set by Ctrl-C; the enumeration polls it.
pub(crate) static INTERRUPTED: AtomicBool = AtomicBool::new(false);

#[cfg(test)]
mod tests;
