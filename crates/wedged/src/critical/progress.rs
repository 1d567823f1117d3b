//! What a running computation of `mu*` reports as it goes ([`CriticalProgress`]).

/// Where a running search is (`Default`: nothing explored, nothing found yet).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CriticalProgress {
    /// The explored fraction of the search, in `[0, 1]` (of the present pass, for `bnb`).
    pub explored: f64,
    /// The best friction coefficient with a witness so far.
    pub upper: Option<f64>,
    /// `bnb`: the search nodes visited in the present pass (0 for the other methods); with
    /// `explored` an estimate of the pass's tree, as in [`crate::Progress::nodes`].
    pub nodes: u64,
    /// `bnb`: the bar of the present pass, when it is finite (the pass tests every node at
    /// `min(bar, best (1 - tol))`).
    pub bar: Option<f64>,
    /// `bnb`: the lower end proved by the passes finished so far (`mu*` lies above it), as an
    /// incomplete run reports it ([`super::Critical::lower`]).
    pub lower: Option<f64>,
    /// `bnb` on a large problem: `Some(n)` while the run looks for its start on the problem
    /// condensed onto `n` nodes (the other fields are then that run's, on the condensed
    /// problem; the smallest where the condensed problem starts from its own), `None` in the
    /// run proper.
    pub condensed: Option<usize>,
    /// `bnb`: the linear programs the simplex method has decided so far in the run (all its
    /// passes; 0 for the other methods). It moves while a node takes long, as the root of a
    /// large problem does while it settles its bounds (minutes at m = 400).
    pub programs: u64,
}
