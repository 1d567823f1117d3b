//! Exact certification of a critical friction coefficient (`--certify`).
//!
//! A run with [`super::CriticalSettings::certify`] keeps every infeasibility the solver proved
//! on the way ([`Refutation`]: the classes of a program, its `mu`, its normalisation and the
//! certificate's multipliers `z` of the gap rows). Afterwards, in exact rational arithmetic,
//! with every `f64` of `K` and `mu` taken as the exact rational it represents:
//!
//! **Each refutation.** For any `r` of the program (reactions on the nodes `V` that have one,
//! gaps `u = K^-1 r` with `u_n_j = 0` on contact and grazing nodes, `u_n_j >= 0` on the others),
//! take `z_j >= 0` on the rows `u_n_j >= 0` (the certificate's entries there, negatives set to
//! zero) and any `z_j` on the rows `u_n_j = 0`. Then `0 <= z . u_n`. With `Z` the load of
//! normal components `z` and `w = K^-1 Z` (solved exactly), `z . u_n = w . r`, and friction
//! `||r_t_i|| <= mu r_n_i` gives `w . r <= sum_i c_i r_n_i` with `c_i = w_n_i + mu ||w_t_i||`.
//! So the program is infeasible when
//! - normalised by `sum r_n = 1`: every `c_i < 0`, `i` in `V`;
//! - normalised by `r_n_i >= 1` on the pressed list `P`: every `c_i <= 0` and some `c_i < 0`,
//!   `i` in `P`;
//! - at `mu = infinity` (no friction limit) the same with `w_t_i = 0` required.
//!
//! Signs of `c_i` are decided exactly (`c_i < 0` iff `w_n_i < 0` and `mu^2 ||w_t_i||^2 <
//! w_n_i^2`), so this holds in 3D as in 2D.
//!
//! **The witness.** Its pressed nodes `P` (`r_n > 0`) and closed gaps (pressed or grazing) fix
//! the linear conditions `r_i = 0` off `P` and `u_n_j = 0` on the closed nodes. The solution
//! space of these conditions in `u` is solved exactly, its free coordinates taken from the
//! floating-point witness (the pivots chosen by complete pivoting in floating point, so the
//! exact point stays close). `r = K u` exactly; then `u_n >= 0`, `r_n >= 0`, complementarity
//! and `sum r_n > 0` are checked exactly, and the certified `upper` is the least `f64` `U` with
//! `||r_t_i||^2 <= U^2 r_n_i^2` at every pressed node.
//!
//! The branch-and-bound bookkeeping (which subtree each refutation prunes, the minimum that
//! makes `lower`) is plain comparison of `f64` values and is not redone; what is certified is
//! every infeasibility it rests on and the witness.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use rayon::prelude::*;

use crate::patterns::program::{Class, Cut, Refutation};
use crate::problem::Problem;

/// The outcome of the exact checks of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct CriticalCertificate {
    /// True when every refutation and the witness passed (and the method's lower end rests on
    /// refutations only).
    pub certified: bool,
    /// The least `f64` at which the exactly recomputed witness solves WP (`None` without a
    /// witness or when its check failed).
    pub upper: Option<f64>,
    /// Refutations checked exactly.
    pub refutations_checked: usize,
    /// Refutations that failed their exact check, even solved again.
    pub refutations_failed: usize,
    /// Refutations whose first certificate failed and that passed when solved again at `lower`.
    pub resolved: usize,
    /// One line per failure (the first few refutations, the witness, the method).
    pub failures: Vec<String>,
}

/// Failures listed by name; the rest are counted.
const LISTED: usize = 5;

/// `x` as an exact rational (finite by the problem's validation).
pub(crate) fn rat(x: f64) -> BigRational {
    BigRational::from_float(x).unwrap_or_else(BigRational::zero)
}

/// Fraction-free Gauss-Jordan elimination of the integer matrix `a` in place (Bareiss's rule
/// applied above and below each pivot: every division is exact and every entry stays an
/// integer, a minor of the input). Pivot columns are taken in the order `order`, a column with
/// no nonzero entry left in the unused rows is skipped. At the end the `k`-th row has the
/// `k`-th pivot column's entry equal to `D` (the last pivot, up to sign the same in every pivot
/// row) and zeros in the other pivot columns; rows past the rank are zero and dropped. Returns
/// the pivot columns.
fn eliminate(a: &mut Vec<Vec<BigInt>>, order: &[usize]) -> Vec<usize> {
    let mut prev = BigInt::one();
    let mut pivots = Vec::new();
    for &col in order {
        let k = pivots.len();
        if k == a.len() {
            break;
        }
        let Some(p) = (k..a.len()).find(|&i| !a[i][col].is_zero()) else {
            continue;
        };
        a.swap(k, p);
        let pivot_row = a[k].clone();
        let pivot = pivot_row[col].clone();
        a.par_iter_mut().enumerate().for_each(|(i, row)| {
            if i == k {
                return;
            }
            let f = row[col].clone();
            for (x, p) in row.iter_mut().zip(&pivot_row) {
                let mut v = &pivot * &*x;
                if !f.is_zero() && !p.is_zero() {
                    v -= &f * p;
                }
                *x = v / &prev;
            }
        });
        // The previous pivot rows' pivot entries become the new pivot (their column in the
        // pivot row is zero, so the rule above scaled them by pivot / prev).
        prev = pivot;
        pivots.push(col);
    }
    a.truncate(pivots.len());
    pivots
}

/// `K^-1` applied to the normal unit loads, exactly and rounded: `cols[j][a] / den = (K^-1
/// e_{n_j})_a` with one positive integer `den` (not kept: only signs are decided), `near[j][a]`
/// the nearest `f64` and `err[j][a]` a bound on its distance from the exact value.
pub(crate) struct Compliance {
    cols: Vec<Vec<BigInt>>,
    near: Vec<Vec<f64>>,
    err: Vec<Vec<f64>>,
}

/// `K` scaled by a power of two to integers (exact).
pub(crate) fn integer_stiffness(problem: &Problem) -> Vec<Vec<BigInt>> {
    let k = problem.stiffness();
    let n = k.nrows();
    let parts: Vec<Vec<(BigInt, i32)>> = (0..n)
        .map(|a| (0..n).map(|b| dyadic(k[(a, b)])).collect())
        .collect();
    let emin = parts
        .iter()
        .flatten()
        .filter(|(x, _)| !x.is_zero())
        .map(|&(_, e)| e)
        .min()
        .unwrap_or(0);
    parts
        .into_iter()
        .map(|row| {
            row.into_iter()
                .map(|(x, e)| x << ((e - emin) as usize))
                .collect()
        })
        .collect()
}

/// Solves `K X = E_n` by fraction-free Gauss-Jordan elimination (Bareiss's rule applied above
/// and below the pivot: every division is exact, every entry an integer minor), on `K` scaled
/// to integers. At the end every diagonal entry is `det K` (scaled) and the right block is
/// `det K * X`. `None` when `K` is singular.
pub(crate) fn compliance(problem: &Problem) -> Option<Compliance> {
    let (d, m) = (problem.dim(), problem.nodes());
    let n = d * m;
    let mut a: Vec<Vec<BigInt>> = integer_stiffness(problem)
        .into_iter()
        .enumerate()
        .map(|(i, mut row)| {
            row.extend((0..m).map(|j| {
                if i == d * j {
                    BigInt::one()
                } else {
                    BigInt::zero()
                }
            }));
            row
        })
        .collect();
    let order: Vec<usize> = (0..n).collect();
    if eliminate(&mut a, &order).len() != n {
        return None;
    }
    let mut cols = Vec::with_capacity(m);
    let mut near = Vec::with_capacity(m);
    let mut err = Vec::with_capacity(m);
    for j in 0..m {
        let (mut c, mut nr, mut er) = (Vec::new(), Vec::new(), Vec::new());
        for (i, row) in a.iter().enumerate() {
            // Row i reads [D e_i | D (K^-1 E_n)_i] (row swaps leave the solution unchanged).
            let (num, diag) = (&row[n + j], &row[i]);
            let x = BigRational::new(num.clone(), diag.clone());
            let f = x.to_f64().unwrap_or(f64::NAN);
            let e = (&x - rat(f)).abs().to_f64().unwrap_or(f64::INFINITY);
            c.push(if diag.is_negative() {
                -num
            } else {
                num.clone()
            });
            nr.push(f);
            er.push(e * 2.0 + f64::MIN_POSITIVE);
        }
        cols.push(c);
        near.push(nr);
        err.push(er);
    }
    Some(Compliance { cols, near, err })
}

/// The sign of `c = w_n + mu ||w_t||` (`mu = None`: infinite, `w_t` must vanish).
fn sign_c(wn: &BigInt, wt: &[BigInt], mu: Option<&BigRational>) -> std::cmp::Ordering {
    use std::cmp::Ordering::*;
    let tangential_zero = wt.iter().all(|x| x.is_zero());
    if tangential_zero {
        return wn.sign_cmp();
    }
    let Some(mu) = mu else {
        return Greater;
    };
    if !wn.is_negative() {
        return Greater;
    }
    // mu^2 |w_t|^2 against w_n^2, with mu = p / q.
    let t2: BigInt = wt.iter().map(|x| x * x).sum();
    let (p, q) = (mu.numer(), mu.denom());
    (p * p * t2).cmp(&(q * q * (wn * wn)))
}

trait SignCmp {
    fn sign_cmp(&self) -> std::cmp::Ordering;
}

impl SignCmp for BigInt {
    fn sign_cmp(&self) -> std::cmp::Ordering {
        self.cmp(&BigInt::zero())
    }
}

/// `x = mantissa * 2^exp`.
fn dyadic(x: f64) -> (BigInt, i32) {
    if x == 0.0 {
        return (BigInt::zero(), 0);
    }
    let bits = x.to_bits();
    let sign = if bits >> 63 == 1 { -1i64 } else { 1 };
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (mant, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i64 << 52), exp - 1075)
    };
    (BigInt::from(sign * mant), e)
}

/// Checks one refutation exactly; `Err` says why it fails. A certificate that fails as it
/// stands is repaired once ([`repair`]) and checked again.
fn check_refutation(problem: &Problem, comp: &Compliance, f: &Refutation) -> Result<(), String> {
    let (d, m) = (problem.dim(), problem.nodes());
    let v: Vec<usize> = (0..m)
        .filter(|&i| matches!(f.classes[i], Class::Contact | Class::Free))
        .collect();
    if v.is_empty() {
        return Ok(());
    }
    if f.z.len() != m || f.z.iter().any(|x| !x.is_finite()) {
        return Err("the solver gave no usable certificate".into());
    }
    // z with the sign conditions of its rows.
    let zf: Vec<f64> = (0..m)
        .map(|j| match f.classes[j] {
            Class::Separated | Class::Free => f.z[j].max(0.0),
            Class::Contact | Class::Grazing => f.z[j],
        })
        .collect();
    if zf.iter().all(|&x| x == 0.0) {
        return Err("the certificate's gap multipliers are all zero".into());
    }
    verdict(comp, f, d, &v, &zf, None).or_else(|e| match repair(comp, f, d, &v, &zf) {
        Some(z) if verdict(comp, f, d, &v, &zf, Some(&z)).is_ok() => Ok(()),
        _ => Err(e),
    })
}

/// `x` as integers over one common power of two (the same positive factor for all).
fn integers(x: &[f64]) -> Vec<BigInt> {
    let parts: Vec<(BigInt, i32)> = x.iter().map(|&x| dyadic(x)).collect();
    let emin = parts
        .iter()
        .filter(|(x, _)| !x.is_zero())
        .map(|&(_, e)| e)
        .min()
        .unwrap_or(0);
    parts
        .iter()
        .map(|(x, e)| x << ((e - emin) as usize))
        .collect()
}

/// The exact check of a refutation's multipliers: `exact` (integers up to one positive
/// factor), or when `None` the floats `zf` themselves, whose signs of `c_i` are first tried by
/// the floating-point [`filter`].
fn verdict(
    comp: &Compliance,
    f: &Refutation,
    d: usize,
    v: &[usize],
    zf: &[f64],
    exact: Option<&[BigInt]>,
) -> Result<(), String> {
    let m = zf.len();
    // The exact multipliers, made when first needed.
    let made = std::cell::OnceCell::new();
    let zi = || -> &[BigInt] { exact.unwrap_or_else(|| made.get_or_init(|| integers(zf))) };
    if let Some(z) = exact {
        if z.iter().all(|x| x.is_zero()) {
            return Err("the repaired multipliers are all zero".into());
        }
        if let Some(j) = (0..m)
            .find(|&j| matches!(f.classes[j], Class::Separated | Class::Free) && z[j].is_negative())
        {
            return Err(format!(
                "the repaired multiplier of node {}'s gap is negative",
                j + 1
            ));
        }
    }
    // w (times a positive factor), exactly.
    let w = |a: usize| -> BigInt {
        let zi = zi();
        (0..m)
            .filter(|&j| !zi[j].is_zero())
            .map(|j| &comp.cols[j][a] * &zi[j])
            .sum()
    };
    let mu = f.mu.is_finite().then(|| rat(f.mu));
    let mut some_negative_pressed = false;
    let strict_needed = f.cut == Cut::Sum;
    for &i in v {
        let s = exact
            .is_none()
            .then(|| filter(comp, zf, d, i, f.mu))
            .flatten()
            .unwrap_or_else(|| {
                let wn = w(d * i);
                let wt: Vec<BigInt> = (1..d).map(|c| w(d * i + c)).collect();
                sign_c(&wn, &wt, mu.as_ref())
            });
        match s {
            std::cmp::Ordering::Less => {
                if matches!(&f.cut, Cut::Pressed(p) if p.contains(&i)) {
                    some_negative_pressed = true;
                }
            }
            std::cmp::Ordering::Equal if !strict_needed => {}
            _ => {
                return Err(format!(
                    "node {}: w_n + mu ||w_t|| is {} (needs < 0{})",
                    i + 1,
                    if s == std::cmp::Ordering::Equal {
                        "0"
                    } else {
                        "positive"
                    },
                    if strict_needed { "" } else { " or = 0" }
                ))
            }
        }
    }
    match f.cut {
        Cut::Pressed(_) if !some_negative_pressed => {
            Err("no pressed node has w_n + mu ||w_t|| < 0".into())
        }
        Cut::Gap(j) if !zi()[j].is_positive() => Err(format!(
            "the multiplier of node {}'s gap, the one claimed shut, is not positive",
            j + 1
        )),
        _ => Ok(()),
    }
}

/// A repaired certificate, for a claim that some node cannot be pressed or some gap cannot
/// open (cut [`Cut::Pressed`] or [`Cut::Gap`]), or a claim at `mu = infinity`. Such claims are
/// degenerate: every valid certificate has `w_i = K^-1 Z` exactly zero at the nodes that some
/// solution presses while sticking (`w_i . r_i = c_i r_n_i` must vanish on an open set of
/// `r_i`), `c_i = 0` exactly (2D: `w_n + sigma mu w_t = 0`, `sigma` the sign of `w_t`) at those
/// that only slip, and `w_t = 0` at infinite `mu`; floating point leaves a hair there, on
/// either side. The repair makes them exact: these linear conditions on `z` (chosen where the
/// floating-point `w` is within 1e-6 of them, relative to its scale), together with `z_j = 0`
/// on the gap rows whose multiplier is negligible, are solved exactly with the other entries of
/// `z` kept as they are (complete pivoting in floating point picks which are solved for).
/// `None` when there is nothing to repair.
fn repair(
    comp: &Compliance,
    f: &Refutation,
    d: usize,
    v: &[usize],
    zf: &[f64],
) -> Option<Vec<BigInt>> {
    if f.cut == Cut::Sum && f.mu.is_finite() {
        return None;
    }
    let m = zf.len();
    let wf = |a: usize| -> f64 { (0..m).map(|j| comp.near[j][a] * zf[j]).sum() };
    let w: Vec<Vec<f64>> = v
        .iter()
        .map(|&i| (0..d).map(|c| wf(d * i + c)).collect())
        .collect();
    let norm = |x: &[f64]| x.iter().map(|y| y * y).sum::<f64>().sqrt();
    let big_w = w.iter().fold(0.0f64, |a, x| a.max(norm(x)));
    let big_z = zf.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let row = |a: usize| -> (Vec<BigInt>, Vec<f64>) {
        (
            (0..m).map(|j| comp.cols[j][a].clone()).collect(),
            (0..m).map(|j| comp.near[j][a]).collect(),
        )
    };
    let (mut exact, mut float) = (Vec::new(), Vec::new());
    for (&i, wi) in v.iter().zip(&w) {
        let wt = norm(&wi[1..]);
        let components: Vec<usize> = if norm(wi) <= 1e-6 * big_w {
            (0..d).collect()
        } else if !f.mu.is_finite() {
            (1..d).collect()
        } else {
            Vec::new()
        };
        for c in components {
            let (e, x) = row(d * i + c);
            exact.push(e);
            float.push(x);
        }
        if d == 2
            && f.mu.is_finite()
            && norm(wi) > 1e-6 * big_w
            && (wi[0] + f.mu * wt).abs() <= 1e-6 * (wi[0].abs() + f.mu * wt)
        {
            // q w_n + sigma p w_t = 0, mu = p / q.
            let mu = rat(f.mu);
            let sigma = if wi[1] < 0.0 { -1 } else { 1 };
            let (p, q) = (mu.numer() * BigInt::from(sigma), mu.denom().clone());
            let (en, xn) = row(d * i);
            let (et, xt) = row(d * i + 1);
            exact.push(en.iter().zip(&et).map(|(a, b)| &q * a + &p * b).collect());
            float.push(
                xn.iter()
                    .zip(&xt)
                    .map(|(a, b)| a + sigma as f64 * f.mu * b)
                    .collect(),
            );
        }
    }
    if exact.is_empty() {
        return None;
    }
    for j in 0..m {
        if matches!(f.classes[j], Class::Separated | Class::Free) && zf[j] <= 1e-9 * big_z {
            let mut e = vec![BigInt::zero(); m];
            e[j] = BigInt::one();
            let mut x = vec![0.0; m];
            x[j] = 1.0;
            exact.push(e);
            float.push(x);
        }
    }
    Some(kernel_point(exact, float, zf))
}

/// An exact state near the floating-point `u`: the unknowns `cols` a [`kernel_point`] of the
/// linear conditions `exact` (rows over `cols`; `float` the same in floating point) with the
/// free ones taken from `u`, the others zero, and `r = K u` (`k` the integer stiffness). Both
/// are integers, times the same positive factor.
pub(crate) fn exact_state(
    k: &[Vec<BigInt>],
    cols: &[usize],
    exact: Vec<Vec<BigInt>>,
    float: Vec<Vec<f64>>,
    u: &[f64],
) -> (Vec<BigInt>, Vec<BigInt>) {
    let n = u.len();
    let start: Vec<f64> = cols.iter().map(|&c| u[c]).collect();
    let mut ux = vec![BigInt::zero(); n];
    for (&c, x) in cols.iter().zip(kernel_point(exact, float, &start)) {
        ux[c] = x;
    }
    let rx = (0..n)
        .map(|a| {
            (0..n)
                .filter(|&b| !ux[b].is_zero() && !k[a][b].is_zero())
                .map(|b| &k[a][b] * &ux[b])
                .sum()
        })
        .collect();
    (ux, rx)
}

/// A point of the null space of the integer matrix `a` (rows over `x.len()` unknowns) close to
/// `x`: the pivot columns chosen by complete pivoting on `af` (`a` in floating point, scaled
/// as it likes), the free unknowns given `x`'s own values (as integers over a common power of
/// two), the pivot unknowns solved for exactly. Returned times one positive integer.
pub(crate) fn kernel_point(mut a: Vec<Vec<BigInt>>, af: Vec<Vec<f64>>, x: &[f64]) -> Vec<BigInt> {
    let n = x.len();
    let (order, rank) = float_pivot_order(af, n);
    // Each row divided by the power of two common to its entries (the kernel is the same):
    // rows of K made integers by one power of two for the whole matrix carry many trailing
    // zeros, and elimination grows every entry with the size of the rows.
    for row in a.iter_mut() {
        if let Some(t) = row.iter().filter_map(|x| x.trailing_zeros()).min() {
            if t > 0 {
                row.iter_mut().for_each(|x| *x >>= t);
            }
        }
    }
    let free = integers(x);
    if let Some(point) = kernel_point_fast(&a, &order, rank, &free) {
        return point;
    }
    let pivots = eliminate(&mut a, &order);
    // Pivot row k: D u_{p_k} + sum_f a_kf u_f = 0, D the same up to sign in every row. Scaled
    // by |D| (positive), the free unknowns are |D| u_f and the pivots -sign(D) sum_f a_kf u_f.
    let scale = a.first().map_or(BigInt::one(), |row| row[pivots[0]].abs());
    let is_pivot: Vec<bool> = (0..n).map(|q| pivots.contains(&q)).collect();
    let mut out: Vec<BigInt> = (0..n)
        .map(|q| {
            if is_pivot[q] {
                BigInt::zero()
            } else {
                &scale * &free[q]
            }
        })
        .collect();
    for (row, &p) in a.iter().zip(&pivots) {
        let mut v = BigInt::zero();
        for (q, y) in row.iter().enumerate() {
            if !is_pivot[q] && !y.is_zero() && !free[q].is_zero() {
                v -= y * &free[q];
            }
        }
        out[p] = if row[p].is_negative() { -v } else { v };
    }
    out
}

/// Unit round-off of `f64`.
const U: f64 = f64::EPSILON / 2.0;

/// The sign of `c_i = w_n_i + mu ||w_t_i||` (`w = K^-1 Z`) from floating point with a rigorous
/// error bound, when that bound decides it (`Less` or `Greater`; `None`: evaluate exactly).
///
/// `w_a = sum_j X_aj z_j` with `X` rounded (`near`, off by at most `err`): the sum is off by at
/// most `sum_j err_aj |z_j|` from the data and `(m + 2) u sum_j |near_aj z_j|` from its
/// rounding (the standard bound `gamma_m`, `u` the unit round-off, with room to spare). The
/// tangential norm moves by at most the norm of its entries' bounds, and the last few
/// operations by a few `u` of their magnitudes; the bound used is twice all that.
fn filter(comp: &Compliance, z: &[f64], d: usize, i: usize, mu: f64) -> Option<std::cmp::Ordering> {
    let m = z.len();
    let gamma = (m as f64 + 2.0) * U;
    let entry = |a: usize| -> (f64, f64) {
        let (mut w, mut abs, mut data) = (0.0f64, 0.0f64, 0.0f64);
        for j in (0..m).filter(|&j| z[j] != 0.0) {
            let t = comp.near[j][a] * z[j];
            w += t;
            abs += t.abs();
            data += comp.err[j][a] * z[j].abs();
        }
        (
            w,
            2.0 * (data + gamma * abs) + f64::MIN_POSITIVE * 4.0 * m as f64,
        )
    };
    let (wn, en) = entry(d * i);
    let tangential: Vec<(f64, f64)> = (1..d).map(|c| entry(d * i + c)).collect();
    let norm = tangential.iter().map(|(w, _)| w * w).sum::<f64>().sqrt();
    let spread = tangential.iter().map(|(_, e)| e * e).sum::<f64>().sqrt();
    let norm_hi = (norm + spread) * (1.0 + 8.0 * U);
    let norm_lo = ((norm - spread) * (1.0 - 8.0 * U)).max(0.0);
    if !mu.is_finite() {
        // c = +infinity unless w_t = 0 exactly, which floating point cannot show.
        return (norm_lo > 0.0).then_some(std::cmp::Ordering::Greater);
    }
    let slack = 8.0 * U * (wn.abs() + en + mu * norm_hi) + f64::MIN_POSITIVE;
    let hi = wn + en + mu * norm_hi + slack;
    let lo = wn - en + mu * norm_lo - slack;
    if hi < 0.0 {
        Some(std::cmp::Ordering::Less)
    } else if lo > 0.0 {
        Some(std::cmp::Ordering::Greater)
    } else {
        None
    }
}

/// Names a refutation in a failure line.
fn describe(f: &Refutation) -> String {
    let classes = crate::patterns::program::describe(&f.classes);
    let norm = match &f.cut {
        Cut::Sum => "sum r_n = 1".to_string(),
        Cut::Pressed(p) => format!("{} nodes pressed", p.len()),
        Cut::Gap(j) => format!("the gap of node {} open", j + 1),
    };
    format!("infeasibility at mu = {} of [{classes}] ({norm})", f.mu)
}

/// The witness recomputed exactly; returns the least `f64` `U` at which it solves WP.
fn check_witness(
    problem: &Problem,
    u: &[f64],
    r: &[f64],
    closed: &[bool],
    upper: f64,
) -> Result<f64, String> {
    let (d, m) = (problem.dim(), problem.nodes());
    let n = d * m;
    let pressed: Vec<bool> = (0..m).map(|i| r[d * i] > 0.0).collect();
    if !pressed.iter().any(|&p| p) {
        return Err("the witness presses no node".into());
    }
    let shut = |c: usize| c % d == 0 && (closed[c / d] || pressed[c / d]);
    // Unknowns: u off the closed normals (those are zero). Rows: (K u)_a = 0 for every
    // component a of a node that is not pressed.
    let cols: Vec<usize> = (0..n).filter(|&c| !shut(c)).collect();
    let k = integer_stiffness(problem);
    let kf = problem.stiffness();
    let rows: Vec<usize> = (0..n).filter(|&a| !pressed[a / d]).collect();
    let float: Vec<Vec<f64>> = rows
        .iter()
        .map(|&a| cols.iter().map(|&c| kf[(a, c)]).collect())
        .collect();
    let a: Vec<Vec<BigInt>> = rows
        .iter()
        .map(|&a| cols.iter().map(|&c| k[a][c].clone()).collect())
        .collect();
    let (ux, rx) = exact_state(&k, &cols, a, float, u);
    let mut total = BigInt::zero();
    for i in 0..m {
        let (un, rn) = (&ux[d * i], &rx[d * i]);
        let node = i + 1;
        if un.is_negative() {
            return Err(format!("exact witness: node {node} penetrates (u_n < 0)"));
        }
        if rn.is_negative() {
            return Err(format!("exact witness: node {node} pulls (r_n < 0)"));
        }
        if !un.is_zero() && !rn.is_zero() {
            return Err(format!(
                "exact witness: node {node} is pressed with an open gap"
            ));
        }
        if rn.is_zero() && (1..d).any(|c| !rx[d * i + c].is_zero()) {
            return Err(format!(
                "exact witness: node {node} has friction without pressure"
            ));
        }
        total += rn;
    }
    if !total.is_positive() {
        return Err("exact witness: no pressure (trivial)".into());
    }
    // The least f64 U with ||r_t||^2 <= U^2 r_n^2 everywhere.
    let mut best = 0.0f64;
    for i in (0..m).filter(|&i| rx[d * i].is_positive()) {
        let t2 = BigRational::from_integer((1..d).map(|c| &rx[d * i + c] * &rx[d * i + c]).sum());
        let n2 = BigRational::from_integer(&rx[d * i] * &rx[d * i]);
        let holds = |x: f64| {
            let x = rat(x);
            &x * &x * &n2 >= t2
        };
        let ratio2 = (&t2 / &n2).to_f64().unwrap_or(f64::INFINITY);
        let mut x = ratio2.sqrt().max(0.0);
        let mut steps = 0;
        while !holds(x) {
            x = next_up(x);
            steps += 1;
            if steps > 1000 || !x.is_finite() {
                return Err(format!(
                    "exact witness: no f64 bounds the ratio of node {}",
                    i + 1
                ));
            }
        }
        // Step down while it still holds (the float estimate may be above the least).
        while x > 0.0 && holds(next_down(x)) && steps < 2000 {
            x = next_down(x);
            steps += 1;
        }
        best = best.max(x);
    }
    if best > upper * (1.0 + 1e-9) {
        return Err(format!(
            "exact witness: its ratio {best} exceeds the reported upper {upper}"
        ));
    }
    Ok(best)
}

/// Columns in the order complete pivoting in floating point takes them, the rest after, and
/// how many were taken (the numerical rank: a pivot below 1e-10 of its row's original size
/// ends the elimination).
fn float_pivot_order(mut a: Vec<Vec<f64>>, n: usize) -> (Vec<usize>, usize) {
    let mut order = Vec::with_capacity(n);
    let mut used = vec![false; n];
    let mut live: Vec<bool> = vec![true; a.len()];
    let sizes: Vec<f64> = a
        .iter()
        .map(|row| row.iter().fold(0.0f64, |s, x| s.max(x.abs())))
        .collect();
    loop {
        let mut best = (0.0f64, usize::MAX, usize::MAX);
        for (i, row) in a.iter().enumerate().filter(|(i, _)| live[*i]) {
            if sizes[i] == 0.0 {
                continue;
            }
            for (c, x) in row.iter().enumerate().filter(|(c, _)| !used[*c]) {
                if x.abs() / sizes[i] > best.0 {
                    best = (x.abs() / sizes[i], i, c);
                }
            }
        }
        if best.1 == usize::MAX || best.0 < 1e-10 {
            break;
        }
        let (_, pr, pc) = best;
        used[pc] = true;
        live[pr] = false;
        order.push(pc);
        let prow = a[pr].clone();
        for (i, row) in a.iter_mut().enumerate() {
            if live[i] && row[pc] != 0.0 {
                let f = row[pc] / prow[pc];
                for (x, p) in row.iter_mut().zip(&prow) {
                    *x -= f * p;
                }
                row[pc] = 0.0;
            }
        }
    }
    let rank = order.len();
    order.extend((0..n).filter(|&c| !used[c]));
    (order, rank)
}

/// The fast path of [`kernel_point`]: the free unknowns (`order[rank..]`) substituted, the
/// square system of the pivots (`order[..rank]`) solved by fraction-free Gaussian elimination
/// (Bareiss) and back substitution. `None` when the exact rank differs from the floating-point
/// one (a pivot vanishes exactly, or a row past the rank is not exactly zero).
fn kernel_point_fast(
    a: &[Vec<BigInt>],
    order: &[usize],
    rank: usize,
    free: &[BigInt],
) -> Option<Vec<BigInt>> {
    let n = free.len();
    let (piv, rest) = order.split_at(rank);
    // Rows [A_p | -A_f x_f].
    let mut m: Vec<Vec<BigInt>> = a
        .iter()
        .map(|row| {
            let mut out: Vec<BigInt> = piv.iter().map(|&c| row[c].clone()).collect();
            let mut b = BigInt::zero();
            for &c in rest {
                if !row[c].is_zero() && !free[c].is_zero() {
                    b -= &row[c] * &free[c];
                }
            }
            out.push(b);
            out
        })
        .collect();
    let mut prev = BigInt::one();
    for s in 0..rank {
        let p = (s..m.len()).find(|&i| !m[i][s].is_zero())?;
        m.swap(s, p);
        let (top, below) = m.split_at_mut(s + 1);
        let pivot_row = &top[s];
        for row in below.iter_mut() {
            let f = row[s].clone();
            for j in s + 1..=rank {
                let mut v = &pivot_row[s] * &row[j];
                if !f.is_zero() && !pivot_row[j].is_zero() {
                    v -= &f * &pivot_row[j];
                }
                row[j] = v / &prev;
            }
            row[s] = BigInt::zero();
        }
        prev = m[s][s].clone();
    }
    if m[rank..].iter().any(|row| row.iter().any(|x| !x.is_zero())) {
        return None;
    }
    // y = D x_p, D the last pivot (the determinant of the pivots' rows), by Cramer integers.
    let det = if rank == 0 { BigInt::one() } else { prev };
    let mut y = vec![BigInt::zero(); rank];
    for i in (0..rank).rev() {
        let mut v = &det * &m[i][rank];
        for j in i + 1..rank {
            v -= &m[i][j] * &y[j];
        }
        y[i] = v / &m[i][i];
    }
    let (scale, sign) = (det.abs(), det.is_negative());
    let mut out = vec![BigInt::zero(); n];
    for &c in rest {
        out[c] = &scale * &free[c];
    }
    for (k, &c) in piv.iter().enumerate() {
        out[c] = if sign { -&y[k] } else { y[k].clone() };
    }
    Some(out)
}

fn next_up(x: f64) -> f64 {
    if x == 0.0 {
        return f64::from_bits(1);
    }
    if x > 0.0 {
        f64::from_bits(x.to_bits() + 1)
    } else {
        f64::from_bits(x.to_bits() - 1)
    }
}

fn next_down(x: f64) -> f64 {
    if x > 0.0 {
        f64::from_bits(x.to_bits() - 1)
    } else {
        -next_up(-x)
    }
}

/// The exact check of refutations of one problem, as they are made (a search that relies on
/// a decision only when its certificate passes). Holds the exact compliance.
pub(crate) struct Checker {
    problem: Problem,
    comp: Option<Compliance>,
}

impl Checker {
    pub(crate) fn new(problem: &Problem) -> Checker {
        Checker {
            problem: problem.clone(),
            comp: compliance(problem),
        }
    }

    pub(crate) fn check(&self, f: &Refutation) -> Result<(), String> {
        match &self.comp {
            None => Err("K is singular in exact arithmetic".into()),
            Some(comp) => check_refutation(&self.problem, comp, f),
        }
    }
}

/// A witness to check: `u`, `r`, its closed gaps (pressed or grazing nodes) and the `upper` it
/// claims.
pub(crate) type Witness<'a> = (&'a [f64], &'a [f64], &'a [bool], f64);

/// The exact checks of a finished run: `refutations` (all the run kept), and the witness
/// `(u, r)` with its closed gaps at `upper`. `note` names a reason the method's lower end
/// does not rest on refutations alone (the enumerate method).
///
/// A refutation whose certificate fails exactly (a floating-point certificate can leave a
/// coefficient `c_i` that must be zero a hair above it; at `mu = infinity` every tangential
/// term must vanish exactly) is solved again at `lower`, the least `mu` the answer needs it at
/// (for an incomplete run, which claims nothing below, at the witness's `upper`), by `again(refutation, mu, sum)`: with its own normalisation,
/// then normalised by `sum r_n = 1` (a stronger claim whose certificate needs every `c_i < 0`).
/// A new certificate that passes replaces it; the count of such is `resolved`.
pub(crate) fn certify(
    problem: &Problem,
    refutations: &[Refutation],
    witness: Option<Witness>,
    lower: Option<f64>,
    again: &(dyn Fn(&Refutation, f64, bool) -> Option<Refutation> + Sync),
    note: Option<String>,
) -> CriticalCertificate {
    let mut failures = Vec::new();
    let resolved = std::sync::atomic::AtomicUsize::new(0);
    if let Some(note) = note {
        failures.push(note);
    }
    let comp = compliance(problem);
    let results: Vec<Result<(), String>> = match &comp {
        None => {
            failures.push("K is singular in exact arithmetic".into());
            Vec::new()
        }
        Some(comp) => refutations
            .par_iter()
            .map(|f| {
                check_refutation(problem, comp, f).or_else(|e| {
                    let retry = lower.filter(|&l| l <= f.mu && l.is_finite());
                    for sum in [false, true] {
                        let Some(mu) = retry else { break };
                        if let Some(g) = again(f, mu, sum) {
                            if check_refutation(problem, comp, &g).is_ok() {
                                resolved.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                                return Ok(());
                            }
                        }
                    }
                    Err(format!("{}: {e}", describe(f)))
                })
            })
            .collect(),
    };
    let failed: Vec<String> = results.into_iter().filter_map(Result::err).collect();
    let refutations_failed = failed.len();
    if refutations_failed > 0 {
        failures.push(format!(
            "{refutations_failed} of {} infeasibility certificates failed their exact check",
            refutations.len()
        ));
        failures.extend(failed.into_iter().take(LISTED));
    }
    let upper = match witness {
        None => None,
        Some((u, r, closed, upper)) => match check_witness(problem, u, r, closed, upper) {
            Ok(x) => Some(x),
            Err(e) => {
                failures.push(e);
                None
            }
        },
    };
    CriticalCertificate {
        certified: failures.is_empty() && comp.is_some(),
        upper,
        refutations_checked: refutations.len(),
        refutations_failed,
        resolved: resolved.into_inner(),
        failures,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::random_spd_problem_dim;
    use crate::patterns::program::{Decision, Formulation, Goal, Norm};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The floating-point filter never contradicts the exact sign, and decides most cases.
    #[test]
    fn filter_agrees_with_exact_signs() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut decided, mut total) = (0, 0);
        for case in 0..40 {
            let dim = 2 + case % 2;
            let m = 1 + case % 5;
            let p = random_spd_problem_dim(dim, m, 1.0, case as u64);
            let comp = compliance(&p).expect("definite");
            for _ in 0..20 {
                let z: Vec<f64> = (0..m).map(|_| rng.gen_range(-1.0..1.0)).collect();
                let mu = match rng.gen_range(0..4) {
                    0 => f64::INFINITY,
                    _ => rng.gen_range(0.1..3.0),
                };
                let zi: Vec<BigInt> = {
                    let parts: Vec<(BigInt, i32)> = z.iter().map(|&x| dyadic(x)).collect();
                    let emin = parts.iter().map(|&(_, e)| e).min().unwrap();
                    parts
                        .iter()
                        .map(|(x, e)| x << ((e - emin) as usize))
                        .collect()
                };
                let w = |a: usize| -> BigInt { (0..m).map(|j| &comp.cols[j][a] * &zi[j]).sum() };
                let exact_mu = mu.is_finite().then(|| rat(mu));
                for i in 0..m {
                    let wt: Vec<BigInt> = (1..dim).map(|c| w(dim * i + c)).collect();
                    let exact = sign_c(&w(dim * i), &wt, exact_mu.as_ref());
                    total += 1;
                    if let Some(s) = filter(&comp, &z, dim, i, mu) {
                        decided += 1;
                        assert_eq!(s, exact, "case {case} node {i} mu {mu}");
                    }
                }
            }
        }
        assert!(decided * 10 > total * 7, "{decided} of {total} decided");
    }

    /// A solver's refutation passes exactly; the same certificate negated, or claimed at a
    /// friction coefficient where the program is feasible, fails.
    #[test]
    fn refutations_pass_and_corrupted_ones_fail() {
        let mut checked = 0;
        for case in 0..30u64 {
            let dim = 2 + (case % 2) as usize;
            let m = 2 + (case % 4) as usize;
            let p = random_spd_problem_dim(dim, m, 1.0, 100 + case);
            let comp = compliance(&p).unwrap();
            let mut form = Formulation::new(&p);
            form.refutations = Some(std::sync::Mutex::new(Vec::new()));
            // Every gap closed: at mu = 0 only r = 0 fits (K^-1_nn is definite), nor at 1e-3.
            let classes = vec![Class::Contact; m];
            let Decision::No = form.decide_at(&classes, 1e-3, Norm::Sum, Goal::Feasible) else {
                continue;
            };
            let f = form
                .refutations
                .take()
                .unwrap()
                .into_inner()
                .unwrap()
                .pop()
                .unwrap();
            assert_eq!(check_refutation(&p, &comp, &f), Ok(()), "case {case}");
            let negated = Refutation {
                z: f.z.iter().map(|x| -x).collect(),
                ..f.clone()
            };
            assert!(
                check_refutation(&p, &comp, &negated).is_err(),
                "case {case}"
            );
            let far = Refutation { mu: 1e6, ..f };
            assert!(check_refutation(&p, &comp, &far).is_err(), "case {case}");
            checked += 1;
        }
        assert!(checked >= 25, "{checked}");
    }

    /// A witness of `critical` passes exactly at its own `upper`; claimed at a `upper` a
    /// millionth lower, it is caught; with its pressures spread to every node it no longer
    /// solves WP and is caught too.
    #[test]
    fn witnesses_pass_and_corrupted_ones_fail() {
        use crate::critical::{critical, CriticalSettings};
        let mut checked = 0;
        for case in 0..12u64 {
            let dim = 2 + (case % 2) as usize;
            let p = random_spd_problem_dim(dim, 2 + (case % 3) as usize, 1.0, 300 + case);
            let c = critical(&p, &CriticalSettings::default()).unwrap();
            let (Some(w), Some(upper)) = (&c.witness, c.upper) else {
                continue;
            };
            let closed: Vec<bool> = w
                .pattern
                .iter()
                .map(|&q| q != crate::enumerate::ContactPattern::Separated)
                .collect();
            let exact = check_witness(&p, &w.u, &w.r, &closed, upper);
            assert!(
                exact
                    .as_ref()
                    .is_ok_and(|&x| (x - upper).abs() <= 1e-12 * upper),
                "case {case}: {exact:?}"
            );
            let lowered = check_witness(&p, &w.u, &w.r, &closed, upper * (1.0 - 1e-6));
            assert!(lowered.is_err(), "case {case}: a lowered upper passed");
            // Every node pressed and closed: the leaf of all nodes, whose only point with the
            // witness's free coordinates is not this one (or not a solution at all).
            let m = p.nodes();
            let mut r = w.r.clone();
            for i in 0..m {
                r[dim * i] = r[dim * i].max(1.0);
            }
            let spread = check_witness(&p, &w.u, &r, &vec![true; m], upper);
            if closed.iter().all(|&x| x) && w.r.iter().step_by(dim).all(|&x| x > 0.0) {
                // The witness already pressed every node: nothing was corrupted.
                continue;
            }
            assert!(
                spread.is_err(),
                "case {case}: a spread witness passed: {spread:?}"
            );
            checked += 1;
        }
        assert!(checked >= 5, "{checked}");
    }

    #[test]
    fn dyadic_is_exact() {
        for x in [1.0, -0.75, 1e-300, 5e-324, 0.1 + 0.2, -1e300] {
            let (mant, e) = dyadic(x);
            let back = BigRational::from_integer(mant)
                * if e >= 0 {
                    BigRational::from_integer(BigInt::one() << e as usize)
                } else {
                    BigRational::new(BigInt::one(), BigInt::one() << (-e) as usize)
                };
            assert_eq!(back, rat(x), "{x}");
        }
    }

    #[test]
    fn steps_are_one_ulp() {
        for x in [1.0, 0.3, 1e-310, 7e200] {
            assert!(next_up(x) > x && next_down(next_up(x)) == x);
        }
    }
}
