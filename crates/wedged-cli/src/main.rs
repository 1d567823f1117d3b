//! The `wedged` command: a thin front end over the `wedged` library.
//!
//! `main` runs the command ([`commands::run`]) and maps its result to an exit code (0 done, 1
//! an internal failure, 2 bad input, 3 incomplete); every failure is printed as one line,
//! `error: <what went wrong>`, on stderr. The command line is in [`args`], one file per
//! subcommand in [`commands`], the readers in the library `wedged_cli::input`, the reports in
//! [`report`] and the pictures and ParaView files in [`draw`].

mod args;
mod commands;
mod draw;

use std::panic::{self, AssertUnwindSafe};
use std::process::ExitCode;

use clap::Parser;
use std::sync::atomic::Ordering;

use crate::args::*;
use crate::commands::*;
use wedged_cli::{one_line, report};

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
