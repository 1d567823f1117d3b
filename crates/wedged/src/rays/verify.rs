//! Every ray is checked before it is reported.
//!
//! [`polish_and_verify`] recomputes a ray from the constraints that its status says are tight (the
//! null vector of those rows), so that the reported numbers satisfy them to round-off, and then
//! [`verify_ray`] checks, with tolerances relative to the data: `K u = r`, the normalisation, the
//! constraints, complementarity, the claimed status at every node, and extremality (the tight
//! constraints have rank `2m - 1`).

use nalgebra::DMatrix;

use crate::linalg::null_vector;
use crate::problem::Problem;
use crate::solution::{NodeStatus, Ray};

/// A ray that did not pass its check. The status vector names the ray.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VerifyError {
    /// The tight constraints of the status do not determine a single ray.
    #[error(
        "ray [{status}]: its tight constraints have rank {rank}, an extreme ray needs {needed}"
    )]
    NotExtreme {
        status: String,
        rank: usize,
        needed: usize,
    },
    /// The method's ray and the ray recomputed from the tight constraints differ.
    #[error("ray [{status}]: the computed ray and the one recomputed from its tight constraints differ by {difference:e}")]
    Mismatch { status: String, difference: f64 },
    /// A constraint or the claimed status fails at a node (1-based).
    #[error("ray [{status}]: node {node}: {what}")]
    Violated {
        status: String,
        node: usize,
        what: String,
    },
}

/// The status vector as text, for messages.
pub fn status_text(status: &[NodeStatus]) -> String {
    status
        .iter()
        .map(|s| s.name())
        .collect::<Vec<_>>()
        .join(" ")
}

impl From<VerifyError> for crate::run::Error {
    /// A ray that fails its own check is an internal failure, not the input's fault.
    fn from(e: VerifyError) -> Self {
        crate::run::Error::Internal(format!(
            "a computed ray failed verification, so no answer is given: {e}"
        ))
    }
}

/// The rows of the constraints that `status` makes tight, in `r`-space (`u = K^{-1} r`).
fn tight_rows(problem: &Problem, status: &[NodeStatus]) -> DMatrix<f64> {
    let n = problem.stiffness().nrows();
    let g = problem.compliance();
    let mu = problem.mu();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let unit = |k: usize, a: f64, l: usize, b: f64| {
        let mut v = vec![0.0; n];
        v[k] += a;
        v[l] += b;
        v
    };
    for (i, s) in status.iter().enumerate() {
        let (ni, ti) = (2 * i, 2 * i + 1);
        let gap = || g.row(ni).iter().copied().collect::<Vec<f64>>();
        match s {
            NodeStatus::Separated => {
                rows.push(unit(ni, 1.0, ti, 0.0));
                rows.push(unit(ti, 1.0, ni, 0.0));
            }
            // A 3D status has no place in a 2D ray; the check below refuses it.
            NodeStatus::Stick | NodeStatus::Slip => rows.push(gap()),
            NodeStatus::SlipPlus => {
                rows.push(gap());
                rows.push(unit(ni, mu, ti, -1.0));
            }
            NodeStatus::SlipMinus => {
                rows.push(gap());
                rows.push(unit(ni, mu, ti, 1.0));
            }
            NodeStatus::Grazing => {
                rows.push(unit(ni, 1.0, ti, 0.0));
                rows.push(unit(ti, 1.0, ni, 0.0));
                rows.push(gap());
            }
        }
    }
    DMatrix::from_fn(rows.len(), n, |i, j| rows[i][j])
}

/// Recomputes the ray with status `status` from its tight constraints, compares it with `r`, and
/// verifies it. `tol` is the relative zero tolerance of the run.
pub fn polish_and_verify(
    problem: &Problem,
    r: &[f64],
    status: Vec<NodeStatus>,
    tol: f64,
) -> Result<Ray, VerifyError> {
    let n = problem.stiffness().nrows();
    let a = tight_rows(problem, &status);
    let (sigma, v) = null_vector(&a);
    // Rows have unit norm, so the largest singular value is at least 1: `tol` is relative.
    let rank = sigma.iter().filter(|&&s| s > tol * sigma[n - 1]).count();
    if rank != n - 1 || sigma[0] > tol.sqrt() {
        return Err(VerifyError::NotExtreme {
            status: status_text(&status),
            rank: rank.min(n - 1),
            needed: n - 1,
        });
    }
    let sum_n = |x: &[f64]| x.iter().step_by(2).sum::<f64>();
    let scale = sum_n(&v);
    let mut polished: Vec<f64> = v.iter().map(|x| x / scale).collect();
    // Put the tight friction constraints exactly in place: they are part of the status.
    let mu = problem.mu();
    for (i, s) in status.iter().enumerate() {
        match s {
            NodeStatus::Separated | NodeStatus::Grazing => {
                polished[2 * i] = 0.0;
                polished[2 * i + 1] = 0.0;
            }
            NodeStatus::SlipPlus => polished[2 * i + 1] = mu * polished[2 * i],
            NodeStatus::SlipMinus => polished[2 * i + 1] = -mu * polished[2 * i],
            NodeStatus::Stick | NodeStatus::Slip => {}
        }
    }
    let raw_scale = sum_n(r);
    let difference = polished
        .iter()
        .zip(r)
        .map(|(p, q)| (p - q / raw_scale).abs())
        .fold(0.0f64, f64::max);
    // Both are approximations of the null vector of the tight rows, whose accuracy degrades like
    // 1 / sigma_{2m-1} (the gap to the next singular value, rows of unit norm). The raw ray comes
    // out of repeated combinations: it must agree to 1e-6, loosened by that conditioning only.
    // (Written so that a NaN fails too.)
    let conditioning = (sigma[n - 1] / sigma[1]).max(1.0);
    let bound = 1e-6 * conditioning * polished.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let agrees = raw_scale > 0.0 && difference <= bound;
    if !agrees {
        return Err(VerifyError::Mismatch {
            status: status_text(&status),
            difference,
        });
    }
    let u = problem.displacement(&polished);
    let ray = Ray {
        u,
        r: polished,
        status,
    };
    verify_ray(problem, &ray, tol)?;
    Ok(ray)
}

/// Strict inequalities must hold by this much, relative to the ray's scale: about 4500 units of
/// round-off, well above the error of a ray recomputed from its tight constraints.
pub const STRICT_MARGIN: f64 = 1e-12;

/// Checks a reported ray against WP: equilibrium (to round-off of `|K| |u|`), the normalisation
/// `sum r_n = 1`, every constraint, and the claimed status at every node (which includes
/// complementarity). Scales are the ray's own: a computed ray is accurate relative to its largest
/// entries, not relative to a tiny reaction at one node. So an equality holds when it is within
/// `tol` of that scale, and a strict inequality when it holds by more than [`STRICT_MARGIN`] of it.
/// Extremality is checked by [`polish_and_verify`], which recomputes the ray from its tight
/// constraints.
pub fn verify_ray(problem: &Problem, ray: &Ray, tol: f64) -> Result<(), VerifyError> {
    let k = problem.stiffness();
    let g = problem.compliance();
    let n = k.nrows();
    let mu = problem.mu();
    let fail = |node: usize, what: String| VerifyError::Violated {
        status: status_text(&ray.status),
        node: node + 1,
        what,
    };
    if ray.u.len() != n || ray.r.len() != n || ray.status.len() * 2 != n {
        return Err(fail(0, "wrong vector lengths".into()));
    }
    if ray.u.iter().chain(&ray.r).any(|x| !x.is_finite()) {
        return Err(fail(0, "non-finite entry".into()));
    }
    for i in 0..n {
        let ku: f64 = (0..n).map(|j| k[(i, j)] * ray.u[j]).sum();
        let scale: f64 = (0..n).map(|j| (k[(i, j)] * ray.u[j]).abs()).sum::<f64>() + ray.r[i].abs();
        if (ku - ray.r[i]).abs() > 1e3 * f64::EPSILON * n as f64 * scale.max(f64::MIN_POSITIVE) {
            return Err(fail(
                i / 2,
                format!("equilibrium fails: (K u - r) = {:e}", ku - ray.r[i]),
            ));
        }
    }
    let total: f64 = ray.r.iter().step_by(2).sum();
    if (total - 1.0).abs() > 1e-12 {
        return Err(fail(0, format!("sum of r_n is {total}, not 1")));
    }
    let r_max = ray.r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (i, &s) in ray.status.iter().enumerate() {
        let (un, rn, rt) = (ray.u[2 * i], ray.r[2 * i], ray.r[2 * i + 1]);
        // How far u_n moves when r moves by its own largest entry.
        let u_scale: f64 = (0..n).map(|j| g[(2 * i, j)].abs()).sum::<f64>() * r_max;
        let gap_zero = un.abs() <= tol * u_scale;
        let gap_open = un > STRICT_MARGIN * u_scale;
        let r_zero = rn == 0.0 && rt == 0.0;
        let pressed = rn > STRICT_MARGIN * r_max;
        let slack_plus = mu * rn - rt;
        let slack_minus = mu * rn + rt;
        let f_scale = (mu + 1.0) * r_max;
        let tight = |x: f64| x.abs() <= tol * f_scale;
        let strict = |x: f64| x > STRICT_MARGIN * f_scale;
        let ok = match s {
            NodeStatus::Separated => gap_open && r_zero,
            NodeStatus::Grazing => gap_zero && r_zero,
            NodeStatus::Stick => gap_zero && pressed && strict(slack_plus) && strict(slack_minus),
            NodeStatus::SlipPlus => gap_zero && pressed && tight(slack_plus) && strict(slack_minus),
            NodeStatus::SlipMinus => {
                gap_zero && pressed && strict(slack_plus) && tight(slack_minus)
            }
            // The 3D status, which a 2D ray cannot have.
            NodeStatus::Slip => false,
        };
        if !ok {
            return Err(fail(
                i,
                format!(
                    "claimed {} but u_n = {un:e}, r_n = {rn:e}, r_t = {rt:e}",
                    s.name()
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::demo;
    use crate::rays::enumerate;
    use crate::rays::Settings;

    /// The demo's rays pass; every kind of corruption is caught.
    #[test]
    fn corrupted_rays_are_caught() {
        let p = demo();
        let tol = Settings::default().zero_tol;
        let e = enumerate(&p, &Settings::default()).unwrap();
        assert!(e.rays.len() >= 3, "the demo must have rays to corrupt");
        for ray in &e.rays {
            verify_ray(&p, ray, tol).unwrap();
            // Recomputing from the status gives the same ray back.
            let again = polish_and_verify(&p, &ray.r, ray.status.clone(), tol).unwrap();
            assert_eq!(again.status, ray.status);

            // A perturbed reaction breaks equilibrium with the reported u.
            let mut bad = ray.clone();
            bad.r[1] += 1e-6;
            assert!(matches!(
                verify_ray(&p, &bad, tol),
                Err(VerifyError::Violated { .. })
            ));

            // A displaced u (still K u = r after recomputing r) breaks the gap or the status.
            let mut bad = ray.clone();
            let i = bad.status.iter().position(|s| s.pressed()).unwrap();
            bad.u[2 * i] -= 1e-3;
            bad.r = (0..bad.u.len())
                .map(|row| {
                    (0..bad.u.len())
                        .map(|c| p.stiffness()[(row, c)] * bad.u[c])
                        .sum()
                })
                .collect();
            assert!(verify_ray(&p, &bad, tol).is_err());

            // Claiming another status at one node is caught, by the recomputation or the check.
            for other in [
                NodeStatus::Separated,
                NodeStatus::Stick,
                NodeStatus::SlipPlus,
            ] {
                if other == ray.status[0] {
                    continue;
                }
                let mut status = ray.status.clone();
                status[0] = other;
                assert!(polish_and_verify(&p, &ray.r, status, tol).is_err());
            }
        }
    }

    /// A status whose tight constraints leave a 2D face is not an extreme ray.
    #[test]
    fn non_extreme_status_is_rejected() {
        let p = demo();
        let r = vec![0.25, 0.0, 0.25, 0.0, 0.25, 0.0, 0.25, 0.0];
        let status = vec![NodeStatus::Stick; 4];
        assert!(matches!(
            polish_and_verify(&p, &r, status, 1e-9),
            Err(VerifyError::NotExtreme {
                rank: 4,
                needed: 7,
                ..
            })
        ));
    }
}
