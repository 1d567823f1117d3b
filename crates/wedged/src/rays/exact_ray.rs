//! A 2D ray of `C` from its status vector, in exact arithmetic: the problem's data as
//! rationals (`ExactProblem`, inequality rows as primitive integer rows), and the ray that a
//! status determines, with the checks 1 to 4 of [`super::certify`] ([`exact_ray_of_status`]).
//! Shared by the certificate and the exact enumeration.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

use crate::problem::Problem;
use crate::rational::{integer_row, null_space_int, rat, to_f64};
use crate::solution::NodeStatus;

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
            .map(|i| (0..n).map(|j| rat(stiffness[(i, j)])).collect())
            .collect();
        let mu = rat(problem.mu());
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

/// The ray that a status vector determines, exactly, normalised to `sum r_n = 1`, when it is an
/// extreme ray of `C` with exactly that status (checks 1 to 4 of the module documentation:
/// extreme, nontrivial, feasible with the tight and strict inequalities exactly as the status
/// says, complementary); otherwise one line per failed check. No floating-point ray is involved.
///
/// This is how the exact brute force ([`crate::rays::exact::brute_force_exact`]) finds its rays.
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
pub(crate) fn recompute(
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
