//! Certificates of 2D ray enumerations in exact rational arithmetic.
//!
//! [`certify_enumeration`] re-derives every reported ray of an [`Enumeration`] from its status
//! vector alone, in exact rational arithmetic, and checks it. Every `f64` input (the entries of
//! the problem's stiffness `K` and `mu`) is taken as the exact rational number it represents, so
//! the certificate is about the problem as stored, with no tolerance anywhere except in the
//! comparison with the floating-point ray (check 5).
//!
//! The variables are `(u, r)` in `Q^{4m}` with the equalities `K u - r = 0` and, per node, the
//! inequalities `u_n >= 0`, `r_n >= 0`, `mu r_n - r_t >= 0`, `mu r_n + r_t >= 0`. The status of a
//! node says which of them are tight:
//!
//! | status    | tight                                  | strict                  |
//! |-----------|----------------------------------------|-------------------------|
//! | separated | `r_n`, both friction rows (so `r = 0`) | `u_n`                   |
//! | grazing   | all four                               | none                    |
//! | stick     | `u_n`                                  | `r_n`, both friction    |
//! | slip+     | `u_n`, `mu r_n - r_t`                  | `r_n`, `mu r_n + r_t`   |
//! | slip-     | `u_n`, `mu r_n + r_t`                  | `r_n`, `mu r_n - r_t`   |
//!
//! For each ray, exactly:
//!
//! 1. the null space of the equalities and the tight rows is one-dimensional (the tight set has
//!    rank `4m - 1`: the ray is extreme), found by fraction-free Gaussian elimination. `r = K u`
//!    is substituted, so the elimination runs on `2m` columns, less the gaps fixed at zero;
//! 2. the null vector, oriented and scaled to `sum r_n = 1` (a zero sum is a trivial ray);
//! 3. every inequality holds, the tight ones with equality and the others strictly, so that the
//!    status is exactly right;
//! 4. complementarity `u_n_i r_n_i = 0` at every node;
//! 5. the exact ray, rounded to `f64`, agrees with the reported one within `1e-6` relative to
//!    the largest entry (of `u` and of `r` separately).
//!
//! For each reported cone, its rays are pairwise cross-complementary (exactly: no node where one
//! ray has `u_n > 0` and another `r_n > 0`) and its pattern is the one of its rays.
//!
//! **Completeness** (no complementary extreme ray and no cone missing, the cones maximal) is
//! certified for up to [`COMPLETENESS_MAX_NODES`] nodes by comparison with the exact
//! enumeration of [`crate::exact`], which finds every complementary extreme ray in exact
//! arithmetic ([`Certificate::complete`]); for larger problems `--exact` gives a complete
//! answer directly. Sign patterns (the pattern methods, 3D) are not certified.
//!
//! [`super::exact_ray::exact_ray_of_status`] exposes checks 1 to 4 alone: from a status vector to its exact ray,
//! or why there is none (the exact brute force of [`crate::rays::exact::brute_force_exact`]).

use num_rational::BigRational;
use num_traits::Signed;
use rayon::prelude::*;

use super::exact_ray::{recompute, ExactProblem, ExactRay};
use super::params::Enumeration;
use crate::problem::Problem;
use crate::rational::to_f64;
use crate::solution::{status_text, ContactPattern, NodeStatus, Ray};

/// Relative agreement asked of a floating-point ray with its exact recomputation.
pub const AGREEMENT: f64 = 1e-6;

/// The result of [`certify_enumeration`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Certificate {
    /// True when every check passed.
    pub certified: bool,
    /// Rays checked (all of the enumeration's).
    pub rays_checked: usize,
    /// Cones checked (all of the enumeration's).
    pub cones_checked: usize,
    /// One line per failed check, naming the ray (0-based, as in the tables and the JSON, with
    /// its status vector) or the cone, and the check.
    pub failures: Vec<String>,
    /// Completeness: `Some(true)` when the rays (by status) and the cones are exactly those of
    /// the exact enumeration ([`crate::rays::exact::enumerate_exact`]), so none is missing;
    /// `Some(false)` when they differ (a failure says how); `None` when not checked: more than
    /// [`COMPLETENESS_MAX_NODES`] nodes, an incomplete run, or a ray that failed its own check.
    pub complete: Option<bool>,
}

/// The most nodes for which [`certify_enumeration`] also proves completeness by running the
/// exact enumeration (about 2 s at 8 nodes; beyond, `--exact` gives a complete answer directly).
pub const COMPLETENESS_MAX_NODES: usize = 8;

/// Certifies the rays and cones of a 2D ray enumeration of `problem` (see the module
/// documentation for what is checked and what is not).
pub fn certify_enumeration(problem: &Problem, e: &Enumeration) -> Certificate {
    let mut failures = Vec::new();
    if problem.dim() != 2 {
        failures.push(format!(
            "exact certification needs a 2D problem, this one has dim = {}",
            problem.dim()
        ));
        return Certificate {
            certified: false,
            rays_checked: 0,
            cones_checked: 0,
            failures,
            complete: None,
        };
    }
    let p = ExactProblem::new(problem);
    let results: Vec<Result<ExactRay, Vec<String>>> = e
        .rays
        .par_iter()
        .enumerate()
        .map(|(index, ray)| {
            certify_ray(&p, ray).map_err(|what| {
                what.into_iter()
                    .map(|w| format!("ray {index} [{}]: {w}", status_text(&ray.status)))
                    .collect()
            })
        })
        .collect();
    let mut exact_rays: Vec<Option<ExactRay>> = Vec::with_capacity(results.len());
    for result in results {
        match result {
            Ok(x) => exact_rays.push(Some(x)),
            Err(lines) => {
                failures.extend(lines);
                exact_rays.push(None);
            }
        }
    }
    for (c, cone) in e.cones.iter().enumerate() {
        failures.extend(
            check_cone(&exact_rays, &cone.rays, &cone.pattern)
                .into_iter()
                .map(|w| format!("cone {c}: {w}")),
        );
    }
    let complete = (failures.is_empty()
        && !matches!(e.outcome, crate::run::Outcome::Incomplete(_))
        && problem.nodes() <= COMPLETENESS_MAX_NODES)
        .then(|| match compare_with_exact(problem, e) {
            Ok(()) => true,
            Err(why) => {
                failures.push(format!("completeness: {why}"));
                false
            }
        });
    Certificate {
        certified: failures.is_empty(),
        rays_checked: e.rays.len(),
        cones_checked: e.cones.len(),
        failures,
        complete,
    }
}

/// The rays (by status, in canonical order) and the cones of `e` against the exact enumeration.
fn compare_with_exact(problem: &Problem, e: &Enumeration) -> Result<(), String> {
    let exact = crate::rays::exact::enumerate_exact(problem)
        .map_err(|err| format!("the exact enumeration failed: {err}"))?;
    let ours: Vec<&Vec<NodeStatus>> = e.rays.iter().map(|r| &r.status).collect();
    let theirs: Vec<&Vec<NodeStatus>> = exact.rays.iter().map(|r| &r.status).collect();
    if ours != theirs {
        let missing = theirs.iter().find(|s| !ours.contains(s));
        let extra = ours.iter().find(|s| !theirs.contains(s));
        return Err(format!(
            "the exact enumeration has {} rays, this answer {}{}{}",
            theirs.len(),
            ours.len(),
            missing.map_or(String::new(), |s| format!("; missing [{}]", status_text(s))),
            extra.map_or(String::new(), |s| format!(
                "; not extreme [{}]",
                status_text(s)
            ))
        ));
    }
    let cones: Vec<(&Vec<usize>, &Vec<ContactPattern>)> =
        e.cones.iter().map(|c| (&c.rays, &c.pattern)).collect();
    let exact_cones: Vec<(&Vec<usize>, &Vec<ContactPattern>)> =
        exact.cones.iter().map(|c| (&c.rays, &c.pattern)).collect();
    if cones != exact_cones {
        return Err(format!(
            "the exact enumeration has {} cones, this answer {} (or they differ)",
            exact_cones.len(),
            cones.len()
        ));
    }
    Ok(())
}

/// Recomputes one ray exactly from its status and checks it; the failed checks otherwise.
pub fn certify_ray_exact(problem: &Problem, ray: &Ray) -> Result<ExactRay, Vec<String>> {
    if problem.dim() != 2 {
        return Err(vec!["exact certification needs a 2D problem".into()]);
    }
    certify_ray(&ExactProblem::new(problem), ray)
}

fn certify_ray(p: &ExactProblem, ray: &Ray) -> Result<ExactRay, Vec<String>> {
    let n = p.n;
    let m = n / 2;
    if ray.status.len() != m || ray.u.len() != n || ray.r.len() != n {
        return Err(vec![format!(
            "wrong lengths: {} statuses, {} entries of u, {} of r, for {m} nodes",
            ray.status.len(),
            ray.u.len(),
            ray.r.len()
        )]);
    }
    // Checks 1 to 4; a failure of 1 or 2 leaves no ray to compare.
    let (exact_ray, mut failures) = recompute(p, &ray.status, true)?;
    let ExactRay { u, r } = &exact_ray;
    // 5. Agreement with the floating-point ray.
    for (name, exact, reported) in [("u", u, &ray.u), ("r", r, &ray.r)] {
        let rounded: Vec<f64> = exact.iter().map(to_f64).collect();
        let largest = rounded.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        for (j, (x, y)) in rounded.iter().zip(reported.iter()).enumerate() {
            // Written so that a NaN fails.
            let agrees = (x - y).abs() <= AGREEMENT * largest;
            if !agrees {
                failures.push(format!(
                    "{name}[{j}] (node {}, {}) is {y:e}, the exact ray has {x:e} (difference \
                     {:e}, allowed {:e})",
                    j / 2 + 1,
                    if j % 2 == 0 { "normal" } else { "tangent" },
                    (x - y).abs(),
                    AGREEMENT * largest
                ));
                break;
            }
        }
    }
    if failures.is_empty() {
        Ok(exact_ray)
    } else {
        Err(failures)
    }
}

/// The cone's checks: its rays exist and were certified, are pairwise cross-complementary, and
/// its pattern is theirs.
fn check_cone(
    rays: &[Option<ExactRay>],
    members: &[usize],
    pattern: &[ContactPattern],
) -> Vec<String> {
    let mut failures = Vec::new();
    let mut exact: Vec<(usize, &ExactRay)> = Vec::new();
    for &k in members {
        match rays.get(k) {
            None => failures.push(format!("ray {k} does not exist")),
            Some(None) => failures.push(format!("ray {k} is not certified")),
            Some(Some(x)) => exact.push((k, x)),
        }
    }
    if !failures.is_empty() {
        return failures;
    }
    let positive = |x: &BigRational| x.is_positive();
    for (a, (ka, xa)) in exact.iter().enumerate() {
        for (kb, xb) in &exact[a + 1..] {
            for i in 0..xa.u.len() / 2 {
                let (gap_a, gap_b) = (positive(&xa.u[2 * i]), positive(&xb.u[2 * i]));
                let (press_a, press_b) = (positive(&xa.r[2 * i]), positive(&xb.r[2 * i]));
                if (gap_a && press_b) || (gap_b && press_a) {
                    failures.push(format!(
                        "rays {ka} and {kb} are not cross-complementary at node {}",
                        i + 1
                    ));
                }
            }
        }
    }
    if let Some((_, first)) = exact.first() {
        let m = first.u.len() / 2;
        if pattern.len() != m {
            failures.push(format!("pattern has {} nodes, not {m}", pattern.len()));
            return failures;
        }
        for (i, &claimed) in pattern.iter().enumerate() {
            let gap = exact.iter().any(|(_, x)| positive(&x.u[2 * i]));
            let pressed = exact.iter().any(|(_, x)| positive(&x.r[2 * i]));
            let actual = match (gap, pressed) {
                (true, false) => Some(ContactPattern::Separated),
                (false, true) => Some(ContactPattern::Contact),
                (false, false) => Some(ContactPattern::Grazing),
                (true, true) => None, // reported above as not cross-complementary
            };
            if actual.is_some_and(|a| a != claimed) {
                failures.push(format!(
                    "node {}: pattern {} but its rays make it {}",
                    i + 1,
                    claimed.name(),
                    actual.map_or("", |a| a.name())
                ));
            }
        }
    } else {
        failures.push("no rays".into());
    }
    failures
}
