//! The `info` object of `critical`'s JSON: every counter of [`wedged::CriticalInfo`].

use serde::Serialize;
use wedged::CriticalInfo;

/// Every field of [`wedged::CriticalInfo`], under the same names (`tol_achieved` is `null`
/// without a bracket).
#[derive(Debug, Serialize)]
pub struct CriticalInfoJson {
    pub method: &'static str,
    pub nodes_visited: u64,
    pub pruned_infeasible: u64,
    pub leaves_solved: u64,
    pub bound_tightenings: u64,
    pub mirrored: u64,
    pub dive_nodes: u64,
    pub improvement_steps: u64,
    pub simplex_solves: u64,
    pub simplex_fallbacks: u64,
    pub simplex_relaxed: u64,
    pub dinkelbach_steps: u64,
    pub bisection_steps: u64,
    pub certificates: u64,
    pub loosened: u64,
    pub tol_achieved: Option<f64>,
    pub mu_enumerated: Option<f64>,
    pub patterns_enumerated: u64,
    pub socps: u64,
    pub retries: u64,
    pub uncertain: u64,
    pub groups: u64,
    pub seconds: f64,
    pub condensed_nodes: u64,
    pub condensed_mu: Option<f64>,
    pub condensed_seconds: f64,
    /// The process's peak resident memory ([`crate::report::json::peak_rss_bytes`]).
    pub peak_rss_bytes: Option<u64>,
}

impl CriticalInfoJson {
    pub(super) fn new(info: &CriticalInfo, bracketed: bool) -> CriticalInfoJson {
        // No `..`: a new field of CriticalInfo must be added here too.
        let CriticalInfo {
            method,
            nodes_visited,
            pruned_infeasible,
            leaves_solved,
            bound_tightenings,
            mirrored,
            dive_nodes,
            improvement_steps,
            simplex_solves,
            simplex_fallbacks,
            simplex_relaxed,
            dinkelbach_steps,
            bisection_steps,
            certificates,
            loosened,
            tol_achieved,
            mu_enumerated,
            patterns_enumerated,
            socps,
            retries,
            uncertain,
            groups,
            seconds,
            condensed_nodes,
            condensed_mu,
            condensed_seconds,
        } = *info;
        CriticalInfoJson {
            method,
            nodes_visited,
            pruned_infeasible,
            leaves_solved,
            bound_tightenings,
            mirrored,
            dive_nodes,
            improvement_steps,
            simplex_solves,
            simplex_fallbacks,
            simplex_relaxed,
            dinkelbach_steps,
            bisection_steps,
            certificates,
            loosened,
            tol_achieved: bracketed.then_some(tol_achieved),
            mu_enumerated,
            patterns_enumerated,
            socps,
            retries,
            uncertain,
            groups,
            seconds,
            condensed_nodes,
            condensed_mu,
            condensed_seconds,
            peak_rss_bytes: crate::report::json::peak_rss_bytes(),
        }
    }
}
