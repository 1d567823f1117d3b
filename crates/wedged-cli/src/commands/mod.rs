//! One file per subcommand: `enumerate` (and its report), `critical` and `sweep`, `study`,
//! `condense`, `demo`, `merge`. This file holds what they share: [`Failure`] (which decides the exit code), the
//! dispatch [`run`], the cancel flag set by Ctrl-C, the time limit, and stdout.

mod condense;
mod critical;
mod demo;
mod enumerate;
mod merge;
mod study;

use condense::*;
use critical::*;
use demo::*;
use enumerate::*;
use merge::*;
use study::*;

use std::io::{self, Write};
use std::sync::atomic::AtomicBool;

pub(crate) use wedged_cli::jobs::{Failure, Show};

use crate::args::*;

pub(crate) fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Enumerate(args) => run_enumerate(args),
        Command::Condense(args) => run_condense(args),
        Command::Critical(args) => run_critical(args),
        Command::Sweep(args) => run_sweep(args),
        Command::Study(args) => run_study(args),
        Command::Demo(args) => run_demo(args),
        Command::Merge(args) => run_merge(args),
    }
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
