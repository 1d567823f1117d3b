//! Enumeration of the 2D solution set: the complementary extreme rays of `C` and the maximal
//! cross-complementary sets of them (MISSION sections 3 and 4).
//!
//! Several methods find the rays; they share the finishing step in this file, which recomputes
//! each ray from its tight constraints, checks it ([`crate::verify`]), puts the rays in canonical
//! order and finds the maximal cliques ([`crate::cliques`]). (The search calls the same check
//! itself, on the thread that described each face: `search::run`.)
//!
//! - [`Method::PrunedDd`] (`dd.rs`, pruned variant): the seed's algorithm, the default.
//! - [`Method::FullDd`] (`dd.rs`, full variant): all extreme rays of `C` by double description,
//!   then a complementarity filter.
//! - [`Method::Faces`] (`faces.rs`): brute force over the `2^m` contact sets.
//! - [`Method::Search`] (`search/`): depth-first search over the contact sets that some
//!   solution presses (warm-started simplex), then the rays of each face in its own dimension.
//! - [`Method::Exact`] ([`crate::exact`]): double description in exact integer arithmetic, no
//!   tolerance anywhere; its rays are exact (rounded to `f64` only for output), so they skip the
//!   floating-point check of the finishing step.

pub mod certify;
pub(crate) mod dd;
pub mod exact;
pub mod exact_ray;
mod faces;
pub(crate) mod params;
pub(crate) mod search;
pub mod verify;

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use rayon::prelude::*;

pub use params::{Enumeration, Info, Method, Progress, Settings, FACES_MAX_NODES};

use crate::problem::Problem;
use crate::run::{check_zero_tol, Control, EnumerateError, Outcome};
use crate::solution::{pieces, Cone, NodeStatus, Ray};
use verify::polish_and_verify;

/// Enumerates the complementary extreme rays and the maximal cross-complementary sets of a 2D
/// problem.
pub fn enumerate(problem: &Problem, settings: &Settings) -> Result<Enumeration, EnumerateError> {
    enumerate_with_control(problem, settings, &|_| {}, &AtomicBool::new(false))
}

/// Why the ray methods refuse a floating body.
pub const FLOATING_RAYS: &str = "the ray methods (pruned-dd, full-dd, faces, search, exact) \
     are written for a clamped body (u = K^-1 r); this body floats, so its pieces are found as \
     sign patterns: use --method bnb or pattern-faces";

/// The largest friction coefficient the floating-point ray methods take. A slipping node's
/// `r_t` is `mu` times its pressure, and on a ray with such a node a pressure's round-off
/// comes back `mu` times larger in the friction constraints; past this the rays no longer
/// pass their own checks. (The 2D plug of `examples/plug2d.toml`: `search` and `pruned-dd`
/// agree at `mu = 1e4`, 44,690 rays; at `1e5` both stop with a ray that fails its check. Real
/// friction coefficients are below 10; the pieces at `1e4` are, within the resolution, those of
/// unlimited friction.) `Method::Exact` has no such limit.
pub const RAYS_MU_MAX: f64 = 1e4;

/// [`enumerate`], calling `progress` as the run goes (from the calling thread) and stopping
/// cleanly ([`Outcome::Incomplete`]) as soon as `cancel` is set (by a Ctrl-C handler, say) or
/// a limit of `settings.limits` is reached. Every algorithm has this pair of entry points: the
/// plain call, and `_with_control` with a progress callback and a cancellation flag
/// ([`crate::enumerate_patterns_with_control`], [`crate::critical_with_control`]).
pub fn enumerate_with_control(
    problem: &Problem,
    settings: &Settings,
    progress: &dyn Fn(Progress),
    cancel: &AtomicBool,
) -> Result<Enumeration, EnumerateError> {
    if problem.dim() != 2 {
        return Err(EnumerateError::UnsupportedDim(problem.dim()));
    }
    check_zero_tol(settings.zero_tol)?;
    if problem.is_floating() {
        return Err(EnumerateError::InvalidSettings(FLOATING_RAYS.into()));
    }
    if settings.method != Method::Exact && problem.mu() > RAYS_MU_MAX {
        return Err(EnumerateError::InvalidSettings(format!(
            "mu = {} is above {RAYS_MU_MAX:e}, the largest friction coefficient the \
             floating-point ray methods resolve (a slipping node's r_t is mu times its \
             pressure); use --exact (up to about 10 nodes), or --method pattern-search \
             (which names the contact sets it cannot decide)",
            problem.mu()
        )));
    }
    if settings.method == Method::Faces && problem.nodes() > FACES_MAX_NODES {
        return Err(EnumerateError::InvalidSettings(format!(
            "the faces method tries every one of the 2^m contact sets; m = {} is more than its \
             limit of {FACES_MAX_NODES} (use pruned-dd)",
            problem.nodes()
        )));
    }
    let start = Instant::now();
    let control = Control::new(settings.limits, cancel);
    let mut info = Info::default();
    let mut exact_rays: Vec<Ray> = Vec::new();
    let mut undecided = None;
    // Rays are polished and verified in equilibrated units (node scales by powers of two, so
    // exact): the rank and sign decisions of the check then do not depend on the units of
    // each node, as the answer must not. They are reported in the problem's own units.
    let (scaled, t) = problem.equilibrated();
    let check = |r: &[f64], status: Vec<NodeStatus>| {
        polish_and_verify(&scaled, r, status, settings.zero_tol).map(|ray| in_units_of(ray, &t))
    };
    // The search checks its rays itself, on the thread that found each face.
    let mut checked_by_search = Vec::new();
    let raw = if control.must_stop(0) {
        Vec::new()
    } else {
        match settings.method {
            // Exact rays need no floating-point check: they go straight to the finishing step.
            Method::Exact => {
                exact_rays = crate::rays::exact::run(
                    problem,
                    crate::rays::exact::Variant::Pruned,
                    &mut info,
                    progress,
                    &control,
                )?
                .iter()
                .map(crate::rays::exact::ExactSolution::rounded)
                .collect();
                Vec::new()
            }
            Method::PrunedDd => dd::run(
                problem,
                &dd::Friction::planar(problem.mu()),
                settings,
                &mut info,
                dd::Variant::Pruned,
                progress,
                &control,
            ),
            Method::FullDd => dd::run(
                problem,
                &dd::Friction::planar(problem.mu()),
                settings,
                &mut info,
                dd::Variant::Full,
                progress,
                &control,
            ),
            Method::Faces => faces::run(problem, settings, &mut info, &control),
            Method::Search => {
                let (checked, stop) =
                    search::run(&scaled, settings, &mut info, progress, &control, &check);
                checked_by_search = checked;
                undecided = stop;
                Vec::new()
            }
        }
    };
    let mut rays = exact_rays;
    // Each ray on its own, in parallel (a QR factorisation each, a singular value decomposition
    // where its bounds do not decide: `verify::quick`), in order, so that a failure reported
    // is the first one.
    // A run that must stop while they are checked (a limit, Ctrl-C) reports the rays checked
    // so far, incomplete. (A method that stopped before hands back the rays it finished, as
    // `faces` does: they are its answer, and all of them are checked.)
    let stopped = control.stopped().is_some();
    let checked: Vec<Option<Result<Ray, verify::VerifyError>>> = raw
        .into_par_iter()
        .map(|raw_ray| {
            if !stopped && control.must_stop(0) {
                return None;
            }
            // The raw ray's own vector, in the equilibrated units.
            let mut r = raw_ray.r;
            for (a, x) in r.iter_mut().enumerate() {
                *x *= t[a / 2];
            }
            Some(check(&r, raw_ray.status))
        })
        .collect();
    rays.reserve(checked.len() + checked_by_search.len());
    for ray in checked.into_iter().flatten().chain(checked_by_search) {
        rays.push(ray?);
    }
    rays.sort_by(|a, b| a.status.cmp(&b.status));
    rays.dedup_by(|a, b| a.status == b.status);
    let (outcome, cones) = match control.stopped().or(undecided) {
        Some(stop) => (Outcome::Incomplete(stop), Vec::new()),
        None if rays.is_empty() => (Outcome::NotWedged, Vec::new()),
        None => (Outcome::Wedged, cones_of(&rays)),
    };
    // The pieces are part of the run's time: with tens of thousands of rays their cliques
    // can take as long as the search.
    info.seconds = start.elapsed().as_secs_f64();
    Ok(Enumeration {
        outcome,
        rays,
        cones,
        info,
    })
}

/// A ray of the equilibrated problem (node scales `t`) in the problem's own units: `r = T^-1 r'`,
/// `u = T u'`, renormalised to `sum r_n = 1`.
fn in_units_of(mut ray: Ray, t: &[f64]) -> Ray {
    if t.iter().all(|&x| x == 1.0) {
        return ray;
    }
    // In place: the ray's own vectors hold the new values.
    for (a, x) in ray.r.iter_mut().enumerate() {
        *x /= t[a / 2];
    }
    for (a, x) in ray.u.iter_mut().enumerate() {
        *x *= t[a / 2];
    }
    let total: f64 = ray.r.iter().step_by(2).sum();
    ray.r.iter_mut().for_each(|x| *x /= total);
    ray.u.iter_mut().for_each(|x| *x /= total);
    ray
}

/// The maximal cross-complementary sets of `rays`, each with its pattern, in canonical order.
fn cones_of(rays: &[Ray]) -> Vec<Cone> {
    let statuses: Vec<&[NodeStatus]> = rays.iter().map(|r| r.status.as_slice()).collect();
    pieces(&statuses)
}
