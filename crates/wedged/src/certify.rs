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
//! [`exact_ray_of_status`] exposes checks 1 to 4 alone: from a status vector to its exact ray,
//! or why there is none (the exact brute force of [`crate::exact::brute_force_exact`]).

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use rayon::prelude::*;

use crate::enumerate::{ContactPattern, Enumeration, NodeStatus, Ray};
use crate::problem::Problem;
use crate::verify::status_text;

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
    /// the exact enumeration ([`crate::exact::enumerate_exact`]), so none is missing;
    /// `Some(false)` when they differ (a failure says how); `None` when not checked: more than
    /// [`COMPLETENESS_MAX_NODES`] nodes, an incomplete run, or a ray that failed its own check.
    pub complete: Option<bool>,
}

/// The most nodes for which [`certify_enumeration`] also proves completeness by running the
/// exact enumeration (about 2 s at 8 nodes; beyond, `--exact` gives a complete answer directly).
pub const COMPLETENESS_MAX_NODES: usize = 8;

/// An exactly recomputed ray, normalised to `sum r_n = 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactRay {
    /// Displacements, `2m`, normal first per node.
    pub u: Vec<BigRational>,
    /// Reactions, `2m`, normal first per node.
    pub r: Vec<BigRational>,
}

/// The problem's data as exact rationals.
pub(crate) struct ExactProblem {
    /// `K`, `n x n` (`n = 2m`), row-major.
    pub(crate) k: Vec<Vec<BigRational>>,
    pub(crate) mu: BigRational,
    pub(crate) n: usize,
    /// The `4m` inequality rows in `u` (`r = K u` substituted), row `4 i + k` for inequality `k`
    /// of node `i` in the order of [`INEQUALITIES`], each a primitive integer vector (a positive
    /// multiple of the rational row: same sign, same zero set).
    pub(crate) rows: Vec<Vec<BigInt>>,
    /// `sum_i r_n_i` as a row in `u`, a positive integer multiple.
    pub(crate) sum_rn: Vec<BigInt>,
}

impl ExactProblem {
    pub(crate) fn new(problem: &Problem) -> ExactProblem {
        let stiffness = problem.stiffness();
        let n = stiffness.nrows();
        let k: Vec<Vec<BigRational>> = (0..n)
            .map(|i| (0..n).map(|j| exact(stiffness[(i, j)])).collect())
            .collect();
        let mu = exact(problem.mu());
        let rows = (0..2 * n)
            .map(|id| {
                let (i, kind) = (id / 4, id % 4);
                let (kn, kt) = (&k[2 * i], &k[2 * i + 1]);
                let row: Vec<BigRational> = (0..n)
                    .map(|j| match kind {
                        0 if j == 2 * i => BigRational::one(),
                        0 => BigRational::zero(),
                        1 => kn[j].clone(),
                        2 => &mu * &kn[j] - &kt[j],
                        _ => &mu * &kn[j] + &kt[j],
                    })
                    .collect();
                integer_row(&row)
            })
            .collect();
        let sum: Vec<BigRational> = (0..n)
            .map(|j| {
                (0..n / 2)
                    .map(|i| &k[2 * i][j])
                    .fold(BigRational::zero(), |s, x| s + x)
            })
            .collect();
        ExactProblem {
            sum_rn: integer_row(&sum),
            k,
            mu,
            n,
            rows,
        }
    }

    /// `r = K u`.
    pub(crate) fn reaction(&self, u: &[BigRational]) -> Vec<BigRational> {
        self.k
            .iter()
            .map(|row| {
                row.iter()
                    .zip(u)
                    .filter(|(_, x)| !x.is_zero())
                    .fold(BigRational::zero(), |s, (a, x)| s + a * x)
            })
            .collect()
    }
}

/// The exact rational value of a finite `f64` (the `Problem` admits no other).
fn exact(x: f64) -> BigRational {
    BigRational::from_float(x).expect("a Problem holds finite numbers only")
}

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
        && !matches!(e.outcome, crate::enumerate::Outcome::Incomplete(_))
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
    let exact = crate::exact::enumerate_exact(problem)
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

/// The four inequalities of a node, in the order `u_n`, `r_n`, `mu r_n - r_t`, `mu r_n + r_t`.
const INEQUALITIES: [&str; 4] = ["u_n >= 0", "r_n >= 0", "r_t <= mu r_n", "-mu r_n <= r_t"];

/// Which of the four inequalities `status` makes tight; `None` for a status a 2D ray cannot have.
pub(crate) fn tight_set(status: NodeStatus) -> Option<[bool; 4]> {
    match status {
        NodeStatus::Separated => Some([false, true, true, true]),
        NodeStatus::Grazing => Some([true, true, true, true]),
        NodeStatus::Stick => Some([true, false, false, false]),
        NodeStatus::SlipPlus => Some([true, false, true, false]),
        NodeStatus::SlipMinus => Some([true, false, false, true]),
        NodeStatus::Slip => None,
    }
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

/// The ray that a status vector determines, exactly, normalised to `sum r_n = 1`, when it is an
/// extreme ray of `C` with exactly that status (checks 1 to 4 of the module documentation:
/// extreme, nontrivial, feasible with the tight and strict inequalities exactly as the status
/// says, complementary); otherwise one line per failed check. No floating-point ray is involved.
///
/// This is how the exact brute force ([`crate::exact::brute_force_exact`]) finds its rays.
pub fn exact_ray_of_status(
    problem: &Problem,
    status: &[NodeStatus],
) -> Result<ExactRay, Vec<String>> {
    if problem.dim() != 2 {
        return Err(vec!["exact rays need a 2D problem".into()]);
    }
    ray_of_status(&ExactProblem::new(problem), status)
}

/// [`exact_ray_of_status`] on data already converted.
pub(crate) fn ray_of_status(
    p: &ExactProblem,
    status: &[NodeStatus],
) -> Result<ExactRay, Vec<String>> {
    match recompute(p, status, true)? {
        (x, failures) if failures.is_empty() => Ok(x),
        (_, failures) => Err(failures),
    }
}

/// The ray of `status` if it is an extreme ray of `C` with exactly that status, without saying
/// why not otherwise (the exact brute force's inner loop: most candidates fail, cheaply).
pub(crate) fn ray_of_status_quiet(p: &ExactProblem, status: &[NodeStatus]) -> Option<ExactRay> {
    match recompute(p, status, false) {
        Ok((x, failures)) if failures.is_empty() => Some(x),
        _ => None,
    }
}

/// Checks 1 and 2 (an error ends there: there is no ray), then the ray with the failures of
/// checks 3 and 4. The signs are decided on integer rows; without `detail`, a failure of check 3
/// or 4 ends the computation at once with no message (and no rational arithmetic).
fn recompute(
    p: &ExactProblem,
    status: &[NodeStatus],
    detail: bool,
) -> Result<(ExactRay, Vec<String>), Vec<String>> {
    let n = p.n;
    let m = n / 2;
    if status.len() != m {
        return Err(vec![format!(
            "wrong length: {} statuses for {m} nodes",
            status.len()
        )]);
    }
    let mut tight = Vec::with_capacity(m);
    for (i, &s) in status.iter().enumerate() {
        match tight_set(s) {
            Some(t) => tight.push(t),
            None => {
                return Err(vec![format!(
                    "node {}: status {} has no place in a 2D ray",
                    i + 1,
                    s.name()
                )])
            }
        }
    }
    // 1. The null space. With r = K u substituted, the variables are u; a tight gap u_n_i = 0
    // removes its column, and the other tight rows are rows of K (or mu K_n -/+ K_t) on the
    // remaining columns.
    let columns: Vec<usize> = (0..n)
        .filter(|&j| !(j % 2 == 0 && tight[j / 2][0]))
        .collect();
    // Fewer tight rows than 4m - 1 cannot have that rank: no elimination needed.
    let tight_rows: usize = tight.iter().map(|t| t.iter().filter(|&&x| x).count()).sum();
    if tight_rows + n < 2 * n - 1 {
        return Err(vec![format!(
            "not extreme: only {} constraints are tight with the equalities, an extreme ray \
             needs rank {}",
            tight_rows + n,
            2 * n - 1
        )]);
    }
    // The tight rows other than gaps, on the remaining columns (dropping columns whose variable
    // is fixed at zero keeps the null space).
    let rows: Vec<Vec<BigInt>> = tight
        .iter()
        .enumerate()
        .flat_map(|(i, t)| (1..4).filter(|&k| t[k]).map(move |k| 4 * i + k))
        .map(|id| columns.iter().map(|&j| p.rows[id][j].clone()).collect())
        .collect();
    let (rank, null) = null_space_int(rows, columns.len());
    // The tight gaps add one independent row each.
    let total_rank = rank + (n - columns.len()) + n;
    if total_rank != 2 * n - 1 {
        return Err(vec![format!(
            "not extreme: the equalities and the tight constraints have rank {total_rank}, an \
             extreme ray needs {}",
            2 * n - 1
        )]);
    }
    let Some(null) = null else {
        return Err(vec!["internal: no null vector at rank 4m - 1".into()]);
    };
    let mut x = vec![BigInt::zero(); n];
    for (&j, v) in columns.iter().zip(integer_row(&null)) {
        x[j] = v;
    }
    // 2. Orientation (sum r_n > 0).
    let dot = |row: &[BigInt]| {
        row.iter()
            .zip(&x)
            .filter(|(a, b)| !a.is_zero() && !b.is_zero())
            .fold(BigInt::zero(), |s, (a, b)| s + a * b)
    };
    let total = dot(&p.sum_rn);
    if total.is_zero() {
        return Err(vec![
            "trivial: the ray of its tight constraints has sum r_n = 0".into(),
        ]);
    }
    let flip = total.is_negative();
    // 3 and 4 on integers first: each row is a positive multiple of its inequality.
    let signs_right = tight.iter().enumerate().all(|(i, t)| {
        let values: Vec<BigInt> = (0..4)
            .map(|k| {
                let v = dot(&p.rows[4 * i + k]);
                if flip {
                    -v
                } else {
                    v
                }
            })
            .collect();
        let right = values
            .iter()
            .zip(t)
            .all(|(v, &tight)| if tight { v.is_zero() } else { v.is_positive() });
        right && !(values[0].is_positive() && values[1].is_positive())
    });
    if !signs_right && !detail {
        return Err(Vec::new());
    }
    let mut u: Vec<BigRational> = x
        .into_iter()
        .map(|v| BigRational::from_integer(if flip { -v } else { v }))
        .collect();
    let mut r = p.reaction(&u);
    let total = r.iter().step_by(2).fold(BigRational::zero(), |s, x| s + x);
    let scale = total.recip();
    for x in u.iter_mut().chain(r.iter_mut()) {
        *x = &*x * &scale;
    }
    let mut failures = Vec::new();
    // 3. Feasibility, with the status exactly right; 4. complementarity.
    for (i, t) in tight.iter().enumerate() {
        let (un, rn, rt) = (&u[2 * i], &r[2 * i], &r[2 * i + 1]);
        let values = [un.clone(), rn.clone(), &p.mu * rn - rt, &p.mu * rn + rt];
        for (k, v) in values.iter().enumerate() {
            if v.is_negative() {
                failures.push(format!(
                    "node {}: {} fails ({} = {:e})",
                    i + 1,
                    INEQUALITIES[k],
                    ["u_n", "r_n", "mu r_n - r_t", "mu r_n + r_t"][k],
                    to_f64(v)
                ));
            } else if t[k] && !v.is_zero() {
                failures.push(format!(
                    "node {}: {} should be tight for {} but holds strictly",
                    i + 1,
                    INEQUALITIES[k],
                    status[i].name()
                ));
            } else if !t[k] && v.is_zero() {
                failures.push(format!(
                    "node {}: {} should hold strictly for {} but is tight",
                    i + 1,
                    INEQUALITIES[k],
                    status[i].name()
                ));
            }
        }
        if !(un * rn).is_zero() {
            failures.push(format!(
                "node {}: complementarity fails: u_n r_n = {:e}",
                i + 1,
                to_f64(&(un * rn))
            ));
        }
    }
    Ok((ExactRay { u, r }, failures))
}

/// The nearest `f64` (or infinity, or NaN if it has none).
pub(crate) fn to_f64(x: &BigRational) -> f64 {
    x.to_f64().unwrap_or(f64::NAN)
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

/// [`null_space_int`] of rational rows, each scaled to a primitive integer vector first.
#[cfg(test)]
fn null_space(rows: &[Vec<BigRational>], ncols: usize) -> (usize, Option<Vec<BigRational>>) {
    null_space_int(rows.iter().map(|row| integer_row(row)).collect(), ncols)
}

/// The rank of the integer rows `a` (each of length `ncols`) and, when the rank is `ncols - 1`,
/// a nonzero vector of their null space. Eliminated fraction-free (Bareiss), so that every
/// intermediate entry is a minor of the integer matrix; the null vector comes from back
/// substitution in rationals.
pub(crate) fn null_space_int(
    mut a: Vec<Vec<BigInt>>,
    ncols: usize,
) -> (usize, Option<Vec<BigRational>>) {
    let nrows = a.len();
    let mut pivots: Vec<usize> = Vec::new();
    let mut prev = BigInt::one();
    let mut r = 0;
    for c in 0..ncols {
        if r == nrows {
            break;
        }
        let Some(p) = (r..nrows).find(|&i| !a[i][c].is_zero()) else {
            continue;
        };
        a.swap(r, p);
        let (top, below) = a.split_at_mut(r + 1);
        let pivot_row = &top[r];
        let pivot = &pivot_row[c];
        for row in below.iter_mut() {
            let factor = row[c].clone();
            for j in c + 1..ncols {
                let value = pivot * &row[j] - &factor * &pivot_row[j];
                // Exact by Sylvester's identity.
                let (q, rem) = value.div_rem(&prev);
                assert!(rem.is_zero(), "Bareiss division is exact");
                row[j] = q;
            }
            row[c] = BigInt::zero();
        }
        prev = top[r][c].clone();
        pivots.push(c);
        r += 1;
    }
    let rank = pivots.len();
    if rank + 1 != ncols {
        return (rank, None);
    }
    let free = (0..ncols)
        .find(|c| !pivots.contains(c))
        .expect("one column has no pivot");
    let mut x = vec![BigRational::zero(); ncols];
    x[free] = BigRational::one();
    for (i, &c) in pivots.iter().enumerate().rev() {
        let s = (c + 1..ncols)
            .filter(|&j| !x[j].is_zero() && !a[i][j].is_zero())
            .fold(BigRational::zero(), |s, j| {
                s + BigRational::from_integer(a[i][j].clone()) * &x[j]
            });
        x[c] = -s / BigRational::from_integer(a[i][c].clone());
    }
    (rank, Some(x))
}

/// A rational row scaled to a primitive integer row (the same null space).
pub(crate) fn integer_row(row: &[BigRational]) -> Vec<BigInt> {
    let denominator = row.iter().fold(BigInt::one(), |l, x| l.lcm(x.denom()));
    let ints: Vec<BigInt> = row
        .iter()
        .map(|x| x.numer() * (&denominator / x.denom()))
        .collect();
    let content = ints.iter().fold(BigInt::zero(), |g, x| g.gcd(x));
    if content.is_zero() || content.is_one() {
        ints
    } else {
        ints.into_iter().map(|x| x / &content).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(a: i64, b: i64) -> BigRational {
        BigRational::new(a.into(), b.into())
    }

    #[test]
    fn null_space_of_small_matrices() {
        // x + 2y + 3z = 0, y - z = 0: null vector (-5, 1, 1).
        let rows = vec![
            vec![q(1, 1), q(2, 1), q(3, 1)],
            vec![q(0, 1), q(1, 2), q(-1, 2)],
        ];
        let (rank, x) = null_space(&rows, 3);
        assert_eq!(rank, 2);
        let x = x.unwrap();
        assert_eq!(x[0].clone() / &x[2], q(-5, 1));
        assert_eq!(x[1].clone() / &x[2], q(1, 1));
        // A repeated row does not add to the rank.
        let rows = vec![rows[0].clone(), rows[0].clone()];
        assert_eq!(null_space(&rows, 3).0, 1);
        // The first column empty: its unit vector is the null vector.
        let rows = vec![
            vec![q(0, 1), q(1, 1), q(1, 1)],
            vec![q(0, 1), q(1, 3), q(2, 1)],
        ];
        let (rank, x) = null_space(&rows, 3);
        assert_eq!(rank, 2);
        let x = x.unwrap();
        assert!(x[1].is_zero() && x[2].is_zero() && !x[0].is_zero());
    }
}
