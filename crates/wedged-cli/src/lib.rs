//! The input side of the `wedged` command as a library: the readers of the problem file
//! ([`input::problem_file`]), of Matrix Market stiffness files ([`input::mtx`]) and of Gmsh
//! meshes ([`input::msh`]).
//!
//! The binary uses them from here; the fuzz targets (`fuzz/` at the repository root) and the
//! corpus regression test (`tests/fuzz_corpus.rs`) call their in-memory entry points
//! ([`input::mtx::parse_bytes`], [`input::msh::parse`], [`input::problem_file::parse_str`]) directly. On any input
//! these return an error, one line that names the source, and never panic.
//!
//! Besides the readers: [`jobs`] (a run made from options, as the command and the Python
//! bindings both make it), [`progress`] (its live progress lines), [`report`] (the summaries, the JSON and the output files) and
//! [`study`] (the grid, CSV and extrapolation of `wedged study`).

pub mod input;
pub mod jobs;
pub mod progress;
pub mod report;
pub mod study;

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};

thread_local! {
    static CONTAINED_PANIC: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f`, catching a panic without the internal-failure report: for third-party code on
/// hostile input (the MSH parser), whose panic the caller reports as bad input.
///
/// A panic hook should stay quiet while [`panic_is_contained`] is true.
pub fn contain_panic<T>(f: impl FnOnce() -> T) -> Option<T> {
    CONTAINED_PANIC.with(|c| c.set(true));
    let result = panic::catch_unwind(AssertUnwindSafe(f)).ok();
    CONTAINED_PANIC.with(|c| c.set(false));
    result
}

/// Whether the current thread is inside [`contain_panic`]: a panic now is caught and reported
/// as bad input by the caller, not a bug.
pub fn panic_is_contained() -> bool {
    CONTAINED_PANIC.with(Cell::get)
}

/// Collapses a possibly multi-line message into one line.
pub fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}
