//! Every ray is checked before it is reported.
//!
//! [`polish_and_verify`] recomputes a ray from the constraints that its status says are tight (the
//! null vector of those rows), so that the reported numbers satisfy them to round-off, and then
//! [`verify_ray`] checks, with tolerances relative to the data: `K u = r`, the normalisation, the
//! constraints, complementarity, the claimed status at every node, and extremality (the tight
//! constraints have rank `2m - 1`).

use nalgebra::DMatrix;

use crate::linalg::{one_row_short, smallest_singular};
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

/// The constraints that `status` makes tight, in `r`-space (`u = K^{-1} r`), reduced to the
/// reactions they leave free.
///
/// The tight rows of a status are of two kinds: the reactions it fixes (`r = 0` at a separated
/// or grazing node, `r_t = +-mu r_n` at a slipping one) and the closed gaps (`(G r)_n = 0` at a
/// node in contact). The first kind are orthonormal rows on coordinates of their own, so with
/// `Q = [P, P_perp]` orthogonal (`P`: one column per reaction left free, `e_n` and `e_t` at a
/// node that sticks, `(e_n +- mu e_t) / sqrt(1 + mu^2)` at one that slips) the tight matrix is
/// `[[0, C], [G P, G P_perp]]` with `C` square and orthogonal: its null vectors are exactly
/// `P y` with `(G P) y = 0`. So the rank test and the null vector come from `G P`, a matrix of
/// (nodes in contact) x (free reactions), not from the whole `2m x 2m` one: on a random problem
/// with 9 nodes the SVD of the whole matrix was about 40% of the run. Each gap row is scaled
/// by the norm of its whole row `G_n`, as the whole matrix's rows were.
struct Tight {
    /// `G P`, one row per closed gap (scaled), one column per free reaction.
    rows: DMatrix<f64>,
    /// The columns of `P`: `(node, weight of r_n, weight of r_t)`.
    free: Vec<(usize, f64, f64)>,
}

fn tight(problem: &Problem, status: &[NodeStatus]) -> Tight {
    let g = problem.compliance();
    let mu = problem.mu();
    let slip = 1.0 / (1.0 + mu * mu).sqrt();
    let mut free: Vec<(usize, f64, f64)> = Vec::new();
    for (i, s) in status.iter().enumerate() {
        match s {
            NodeStatus::Separated | NodeStatus::Grazing => {}
            // A 3D status has no place in a 2D ray; the check below refuses it.
            NodeStatus::Stick | NodeStatus::Slip => free.extend([(i, 1.0, 0.0), (i, 0.0, 1.0)]),
            NodeStatus::SlipPlus => free.push((i, slip, mu * slip)),
            NodeStatus::SlipMinus => free.push((i, slip, -mu * slip)),
        }
    }
    let closed = || (0..status.len()).filter(|&i| status[i] != NodeStatus::Separated);
    let mut rows = DMatrix::<f64>::zeros(closed().count(), free.len());
    for (row, i) in closed().enumerate() {
        let norm = g.row(2 * i).norm();
        if norm > 0.0 {
            for (col, &(j, a, b)) in free.iter().enumerate() {
                rows[(row, col)] = (a * g[(2 * i, 2 * j)] + b * g[(2 * i, 2 * j + 1)]) / norm;
            }
        }
    }
    Tight { rows, free }
}

#[cfg(test)]
thread_local! {
    /// How many of this thread's checks the quick path finished.
    static QUICK_DONE: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// The tight rows' null vector where the rank test of [`polish_and_verify`] is clear without
/// the singular value decomposition, and a lower bound on the conditioning it compares with.
struct Quick {
    null: Vec<f64>,
    conditioning_at_least: f64,
}

/// The rank test of [`polish_and_verify`] decided by [`one_row_short`]'s bounds, where they
/// are clear: the tight rows are `k - 1` x `k` (an extreme ray's, when no more constraints are
/// tight than it needs) and the least singular value is surely above twice the tolerance, so
/// that the decomposition would find rank `k - 1` too (its round-off is about `1e-16` of the
/// largest; from `tol >= 1e-13` on that is far below the tolerance). `None` leaves the test to
/// the decomposition: another shape, a singular triangle, a least singular value that may lie
/// near the tolerance. (The decomposition was four fifths of a ray's check; on the random
/// m = 9 problems every ray's test is clear this way.)
fn quick(rows: &DMatrix<f64>, tol: f64) -> Option<Quick> {
    if tol < 1e-13 {
        return None;
    }
    let bounds = one_row_short(rows)?;
    let top_at_most = bounds.top_at_most.max(1.0);
    // (A NaN bound declines too.)
    let clear = bounds.least_at_least > 2.0 * tol * top_at_most;
    if !clear {
        return None;
    }
    // `top / least` with `top >= top_at_least` and `least <= least_at_most`.
    let conditioning_at_least = (bounds.top_at_least.max(1.0) / bounds.least_at_most).max(1.0);
    conditioning_at_least.is_finite().then_some(Quick {
        null: bounds.null,
        conditioning_at_least,
    })
}

/// Recomputes the ray with status `status` from its tight constraints, compares it with `r`, and
/// verifies it. `tol` is the relative zero tolerance of the run.
pub fn polish_and_verify(
    problem: &Problem,
    r: &[f64],
    status: Vec<NodeStatus>,
    tol: f64,
) -> Result<Ray, VerifyError> {
    polish_and_check(problem, r, status, tol, true)
}

/// [`polish_and_verify`]; with `quick_ok` the tests of rank and agreement are decided from
/// bounds where they are clear ([`quick`]), without it always by the singular value
/// decomposition.
fn polish_and_check(
    problem: &Problem,
    r: &[f64],
    status: Vec<NodeStatus>,
    tol: f64,
    quick_ok: bool,
) -> Result<Ray, VerifyError> {
    let n = problem.stiffness().nrows();
    let not_extreme = |rank: usize| VerifyError::NotExtreme {
        status: status_text(&status),
        rank: rank.min(n - 1),
        needed: n - 1,
    };
    let Tight { rows, free } = tight(problem, &status);
    let k = free.len();
    // The fixed reactions' rows have rank `n - k` between them.
    if k == 0 {
        return Err(not_extreme(n));
    }
    let sum_n = |x: &[f64]| x.iter().step_by(2).sum::<f64>();
    // The two rays are compared with each tangential entry divided by `1 + mu`, the scale a
    // slipping node's `r_t = +-mu r_n` gives it: a ray's error is an error in its pressures,
    // which a slipping node's `r_t` repeats `mu` times over. (Compared entry by entry, the 2D
    // plug of `examples/plug2d.toml` failed at `mu = 1e4`: a pressure of 1.94e-5 off by 1.7e-9
    // made its `r_t` differ by 1.7e-5 of a ray of size 1.)
    let weight: Vec<f64> = (0..n)
        .map(|a| {
            if a % 2 == 1 {
                1.0 / (1.0 + problem.mu())
            } else {
                1.0
            }
        })
        .collect();
    let raw_scale = sum_n(r);
    // The ray from a null vector `y` of the tight rows (one entry per free reaction), and how
    // far `r` is from it.
    let polish = |y: &[f64]| -> (Vec<f64>, f64) {
        let mut v = vec![0.0; n];
        for (&(i, a, b), &x) in free.iter().zip(y) {
            v[2 * i] += a * x;
            v[2 * i + 1] += b * x;
        }
        let scale = sum_n(&v);
        let mut polished = v;
        polished.iter_mut().for_each(|x| *x /= scale);
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
        let difference = polished
            .iter()
            .zip(r)
            .zip(&weight)
            .map(|((p, q), w)| w * (p - q / raw_scale).abs())
            .fold(0.0f64, f64::max);
        (polished, difference)
    };
    let size = |x: &[f64]| {
        x.iter()
            .zip(&weight)
            .fold(0.0f64, |m, (x, w)| m.max(w * x.abs()))
    };
    // Both checks below decided from bounds where they are clear (`quick`), by the singular
    // value decomposition otherwise.
    let polished = match quick_ok.then(|| quick(&rows, tol)).flatten() {
        Some(q) => {
            let (polished, difference) = polish(&q.null);
            // The conditioning below is at least `q.conditioning_at_least`; half of that bound
            // leaves room for the last bits in which the two null vectors differ.
            let clear = 0.5e-6 * q.conditioning_at_least * size(&polished);
            // (`f64::max` passes over a NaN: a ray that is not finite goes to the decomposition.)
            let done =
                raw_scale > 0.0 && difference <= clear && polished.iter().all(|x| x.is_finite());
            #[cfg(test)]
            QUICK_DONE.with(|c| c.set(c.get() + usize::from(done)));
            done.then_some(polished)
        }
        None => None,
    };
    let polished = match polished {
        Some(polished) => polished,
        None => {
            let (sigma, y) = smallest_singular(&rows);
            // The whole matrix has rows of unit norm, so its largest singular value is at
            // least 1: `tol` is relative to that.
            let top = sigma[k - 1].max(1.0);
            let rank = sigma.iter().filter(|&&s| s > tol * top).count();
            if rank != k - 1 || sigma[0] > tol.sqrt() {
                return Err(not_extreme(n - k + rank));
            }
            let (polished, difference) = polish(&y);
            // Both are approximations of the null vector of the tight rows, whose accuracy
            // degrades like 1 / sigma_{2m-1} (the gap to the next singular value, rows of unit
            // norm). The raw ray comes out of repeated combinations: it must agree to 1e-6,
            // loosened by that conditioning only. (Written so that a NaN fails too.)
            let conditioning = if k > 1 {
                (top / sigma[1]).max(1.0)
            } else {
                1.0
            };
            let bound = 1e-6 * conditioning * size(&polished);
            let agrees = raw_scale > 0.0 && difference <= bound;
            if !agrees {
                return Err(VerifyError::Mismatch {
                    status: status_text(&status),
                    difference,
                });
            }
            polished
        }
    };
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
    // `K u`, `|K| |u|` and (below) the normal rows' sums of `|G|`, in one buffer, column by
    // column (the storage order), each entry summed over `j` in order as a row's sum would be:
    // the same values, without striding across the columns (the row sums had been a sixth of
    // a ray's check).
    let mut sums = vec![0.0; 2 * n + n / 2];
    let (ku, rest) = sums.split_at_mut(n);
    let (sizes, g_sizes) = rest.split_at_mut(n);
    for (column, &uj) in k.as_slice().chunks_exact(n).zip(&ray.u) {
        for ((o, s), a) in ku.iter_mut().zip(sizes.iter_mut()).zip(column) {
            *o += a * uj;
            *s += (a * uj).abs();
        }
    }
    for i in 0..n {
        let ku = ku[i];
        let scale = sizes[i] + ray.r[i].abs();
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
    // Row `2i` of `|G|` summed for node `i` (its normal gap), column by column as above.
    for column in g.as_slice().chunks_exact(n) {
        for (s, a) in g_sizes.iter_mut().zip(column.iter().step_by(2)) {
            *s += a.abs();
        }
    }
    for (i, &s) in ray.status.iter().enumerate() {
        let (un, rn, rt) = (ray.u[2 * i], ray.r[2 * i], ray.r[2 * i + 1]);
        // How far u_n moves when r moves by its own largest entry.
        let u_scale: f64 = g_sizes[i] * r_max;
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

    /// The quick check ([`quick`]) and the singular value decomposition give the same verdict on
    /// every ray, and the same ray to round-off of its conditioning: the rays of 60 random
    /// problems (m = 3 to 9), 30 banded ones (m = 4 to 9, band 1 or 2), the demo and the plug
    /// at m = 12 and 16, each also with one node's status changed (a wrong status, which both
    /// must refuse alike). The quick path finishes most of the checks (the test
    /// would pass vacuously if it declined them all).
    #[test]
    fn the_quick_check_agrees_with_the_decomposition() {
        use crate::examples::{banded_spd_problem, plug2d_tri, random_spd_problem};
        let mut problems: Vec<Problem> = Vec::new();
        for seed in 0..60 {
            problems.push(random_spd_problem(3 + (seed as usize % 7), 1.5, seed));
        }
        for seed in 0..30 {
            let m = 4 + (seed as usize % 6);
            problems.push(banded_spd_problem(
                m,
                1 + seed as usize % 2,
                0.9,
                100 + seed,
            ));
        }
        problems.push(demo());
        for n in [6, 8] {
            problems.push(plug2d_tri(n).unwrap().problem(2.0).unwrap());
        }
        let tol = Settings::default().zero_tol;
        let (mut rays, mut refused) = (0, 0);
        for p in &problems {
            let Ok(e) = enumerate(p, &Settings::default()) else {
                continue;
            };
            for ray in &e.rays {
                let mut statuses = vec![ray.status.clone()];
                let mut other = ray.status.clone();
                other[0] = match other[0] {
                    NodeStatus::Separated => NodeStatus::Stick,
                    _ => NodeStatus::Separated,
                };
                statuses.push(other);
                for status in statuses {
                    let fast = polish_and_check(p, &ray.r, status.clone(), tol, true);
                    let slow = polish_and_check(p, &ray.r, status.clone(), tol, false);
                    match (&fast, &slow) {
                        (Ok(a), Ok(b)) => {
                            rays += 1;
                            assert_eq!(a.status, b.status);
                            let scale = b.r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                            for (x, y) in a.r.iter().zip(&b.r) {
                                assert!((x - y).abs() <= 1e-9 * scale, "{x} against {y}");
                            }
                        }
                        (Err(a), Err(b)) => {
                            refused += 1;
                            assert_eq!(
                                std::mem::discriminant(a),
                                std::mem::discriminant(b),
                                "{a:?} against {b:?}"
                            );
                        }
                        _ => panic!("the two checks disagree: {fast:?} against {slow:?}"),
                    }
                }
            }
        }
        let quick_ones = QUICK_DONE.with(|c| c.get());
        eprintln!("{rays} rays, {refused} refused, {quick_ones} checked quickly");
        assert!(
            rays > 1000 && refused > 100,
            "{rays} rays, {refused} refused"
        );
        assert!(
            quick_ones > rays / 2,
            "{quick_ones} of {rays} checked quickly"
        );
    }

    /// The quick check declines where its bounds do not decide: a least singular value near
    /// the tolerance, another shape than `k - 1` x `k`, a tolerance below the decomposition's
    /// round-off.
    #[test]
    fn the_quick_check_declines_near_the_tolerance() {
        let tol = 1e-9;
        // Rows of unit norm, the second the first turned by `angle`.
        let rows = |angle: f64| {
            DMatrix::from_row_slice(2, 3, &[1.0, 0.0, 0.0, angle.cos(), angle.sin(), 0.0])
        };
        assert!(quick(&rows(0.5), tol).is_some());
        // The least singular value about `angle / sqrt 2`.
        assert!(quick(&rows(1e-9), tol).is_none());
        assert!(quick(&rows(1e-12), tol).is_none());
        assert!(quick(&rows(0.5), 1e-14).is_none());
        assert!(quick(&DMatrix::identity(3, 3), tol).is_none());
        assert!(quick(&DMatrix::from_row_slice(1, 3, &[1.0, 0.0, 0.0]), tol).is_none());
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
