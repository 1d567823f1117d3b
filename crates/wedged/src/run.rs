//! What every algorithm's run shares: its [`Limits`], the `Control` it polls between units
//! of work (time, memory, the caller's cancel flag), why it stopped ([`Stop`]), how it ended
//! ([`Outcome`]), and the one [`Error`] type, which keeps bad input (the caller's to fix: exit
//! code 2 in the CLI) apart from internal failures (a failed check of the library's own: a bug,
//! exit code 1).

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// Bounds on a run. A run that reaches one stops cleanly: its outcome is
/// [`Outcome::Incomplete`], with the reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Limits {
    /// Most rays held at once (double description), a proxy for memory: each held ray of an
    /// `m`-node problem takes about `16 m + 3 m / 8` bytes.
    pub max_rays: Option<usize>,
    /// Most wall-clock time.
    pub time_limit: Option<Duration>,
    /// Most bytes for the rays held at once (double description's ray store, the part of
    /// memory that grows; see [`crate::Info::peak_bytes`]).
    pub max_memory: Option<u64>,
}

/// A fault or event that tests inject to see it reported as it would be in use (an internal
/// failure: exit 1 in the CLI; an interruption: exit 3); never set in use. See
/// `CriticalSettings::fault`.
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// Move the `mu*` witness off equilibrium just before its final check.
    CorruptWitness,
    /// Interrupt the `bnb` search of `mu*` (as Ctrl-C would) once its first pass at a bar
    /// has finished without a wedged configuration at or below that bar: at a reproducible
    /// point where an incomplete run has a lower end to report.
    HaltAfterPass,
    /// Not a fault: the `bnb` search of `mu*` settles its root's drive bounds on a problem of
    /// any size (by default from `SETTLE_FROM` nodes on, `critical/bnb/tuning.rs`), so that the
    /// tests see that path on problems small enough to check by brute force.
    SettleRoot,
}

impl Fault {
    /// The fault named `name` (`corrupt-witness`, `halt-after-pass`, `settle-root`), if any.
    pub fn parse(name: &str) -> Option<Fault> {
        match name {
            "corrupt-witness" => Some(Fault::CorruptWitness),
            "halt-after-pass" => Some(Fault::HaltAfterPass),
            "settle-root" => Some(Fault::SettleRoot),
            _ => None,
        }
    }
}

/// Why a run stopped before it was complete.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// More rays would have been held than [`Limits::max_rays`].
    MaxRays(usize),
    /// [`Limits::time_limit`] ran out.
    TimeLimit(Duration),
    /// The rays held would have taken more than [`Limits::max_memory`] bytes.
    MaxMemory(u64),
    /// The caller's cancellation flag was set (Ctrl-C).
    Interrupted,
    /// The conic solver could not decide some programs, even with tighter settings (3D
    /// patterns): the patterns below them may be missing.
    Undecided,
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stop::MaxRays(n) => write!(f, "the limit of {n} rays held was reached"),
            Stop::TimeLimit(d) => write!(f, "the time limit of {} s ran out", d.as_secs_f64()),
            Stop::MaxMemory(b) => write!(
                f,
                "the memory limit of {} for the rays held was reached",
                bytes_text(*b)
            ),
            Stop::Interrupted => write!(f, "the run was interrupted"),
            Stop::Undecided => write!(f, "the solver could not decide some contact sets"),
        }
    }
}

/// Decides when a run must stop: limits and the cancellation flag, checked by the methods
/// between units of work (from any thread). The first reason found is kept.
pub(crate) struct Control<'a> {
    start: Instant,
    limits: Limits,
    cancel: &'a AtomicBool,
    stop: OnceLock<Stop>,
    /// Bytes per held ray, set by the method that holds rays.
    ray_bytes: OnceLock<u64>,
}

/// `1.5 GB`, `320 MB`, `12 kB`, `800 B` (powers of 1000).
pub fn bytes_text(b: u64) -> String {
    let b = b as f64;
    if b >= 1e9 {
        format!("{:.2} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.1} MB", b / 1e6)
    } else if b >= 1e3 {
        format!("{:.0} kB", b / 1e3)
    } else {
        format!("{b} B")
    }
}

impl<'a> Control<'a> {
    /// A control starting now.
    pub(crate) fn new(limits: Limits, cancel: &'a AtomicBool) -> Control<'a> {
        Control {
            start: Instant::now(),
            limits,
            cancel,
            stop: OnceLock::new(),
            ray_bytes: OnceLock::new(),
        }
    }

    /// Declares the memory of one held ray, for the memory limit.
    pub(crate) fn set_ray_bytes(&self, bytes: u64) {
        let _ = self.ray_bytes.set(bytes);
    }

    /// Whether the run must stop, with `held` rays in memory now.
    pub(crate) fn must_stop(&self, held: usize) -> bool {
        if self.stop.get().is_some() {
            return true;
        }
        let reason = if self.cancel.load(Ordering::Relaxed) {
            Some(Stop::Interrupted)
        } else if self
            .limits
            .time_limit
            .is_some_and(|t| self.start.elapsed() >= t)
        {
            self.limits.time_limit.map(Stop::TimeLimit)
        } else if let Some(n) = self.limits.max_rays.filter(|&n| held > n) {
            Some(Stop::MaxRays(n))
        } else {
            let bytes = held as u64 * self.ray_bytes.get().copied().unwrap_or(0);
            self.limits
                .max_memory
                .filter(|&b| bytes > b)
                .map(Stop::MaxMemory)
        };
        match reason {
            Some(r) => {
                let _ = self.stop.set(r);
                true
            }
            None => false,
        }
    }

    pub(crate) fn stopped(&self) -> Option<Stop> {
        self.stop.get().copied()
    }

    /// Stops the run for `why` (unless it stopped already): the injected interruption
    /// [`Fault::HaltAfterPass`].
    pub(crate) fn halt(&self, why: Stop) {
        let _ = self.stop.set(why);
    }
}

/// How the run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Complete; at least one wedged configuration exists.
    Wedged,
    /// Complete; only the trivial solution `(0, 0)` exists.
    NotWedged,
    /// Stopped before the end: nothing is claimed about the rays not reported. The double
    /// descriptions have final rays only once every node is processed, so they report none;
    /// `faces` reports the (checked) rays of the contact sets it finished. Cones are not formed.
    Incomplete(Stop),
}

/// Why a run could not give an answer.
///
/// [`Error::UnsupportedDim`] and [`Error::InvalidSettings`] are bad input: the caller can fix
/// them. [`Error::Internal`] is a failed internal check (a computed ray or witness that does not
/// pass its own verification): a bug, or floating point that could not be trusted; no answer is
/// given rather than a wrong one.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// The enumeration of patterns by rays is the 2D algorithm; 3D goes through sign patterns.
    #[error("enumeration of rays needs dim = 2, the problem has dim = {0}")]
    UnsupportedDim(usize),
    /// A setting is out of range.
    #[error("invalid setting: {0}")]
    InvalidSettings(String),
    /// An internal check failed (not the input's fault): what failed.
    #[error("internal failure (a bug in wedged; please report it): {0}")]
    Internal(String),
}

/// The name the enumeration API has always used for [`Error`].
pub type EnumerateError = Error;

/// The range of a relative zero tolerance (`Settings::zero_tol`, `PatternSettings::zero_tol`).
pub(crate) fn check_zero_tol(zero_tol: f64) -> Result<(), Error> {
    if zero_tol > 0.0 && zero_tol < 1e-2 {
        Ok(())
    } else {
        Err(Error::InvalidSettings(format!(
            "zero_tol must be in (0, 0.01), got {zero_tol}"
        )))
    }
}

/// Runs `work` on a scoped thread while the calling thread calls `report` every 200 ms, and
/// once more at the end; returns what `work` returns. (The progress callbacks of the searches
/// run on the caller's thread, which may not be `Sync`-friendly code such as a terminal line.)
pub(crate) fn with_progress<T: Send>(work: impl FnOnce() -> T + Send, report: impl Fn()) -> T {
    let (finished, wait) = std::sync::mpsc::channel::<()>();
    let out = std::thread::scope(|scope| {
        let handle = scope.spawn(|| {
            let out = work();
            let _ = finished.send(());
            out
        });
        // Until the work sends its end (or its thread is gone).
        while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
            wait.recv_timeout(std::time::Duration::from_millis(200))
        {
            report();
        }
        handle.join()
    });
    report();
    match out {
        Ok(out) => out,
        Err(panic) => std::panic::resume_unwind(panic),
    }
}
