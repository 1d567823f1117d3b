//! Exact arithmetic shared by the certificates and the exact enumeration: `f64`s as the
//! rationals they are ([`rat`]), rows made primitive integer vectors ([`integer_row`]), and the
//! one fraction-free elimination ([`eliminate`], Bareiss's rule) with the null space built on it
//! ([`null_space_int`]).

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use rayon::prelude::*;

/// `x` as an exact rational (a finite `f64` is one; a non-finite one, which a `Problem` never
/// holds, becomes zero).
pub(crate) fn rat(x: f64) -> BigRational {
    BigRational::from_float(x).unwrap_or_else(BigRational::zero)
}

/// The nearest `f64` (or infinity, or NaN if it has none).
pub(crate) fn to_f64(x: &BigRational) -> f64 {
    x.to_f64().unwrap_or(f64::NAN)
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

/// Which rows [`eliminate`] clears in a pivot's column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sweep {
    /// The rows below the pivot row (Gaussian elimination to echelon form; sequential, for the
    /// many small systems of the exact enumeration).
    Below,
    /// Every other row (Gauss-Jordan; rows in parallel, for the certificates' large systems).
    All,
}

/// Fraction-free elimination of the integer matrix `a` in place (Bareiss's rule: every
/// division is exact by Sylvester's identity, and every entry stays an integer, a minor of the
/// input). Pivot columns are taken in the order `order`; a column with no nonzero entry left in
/// the unused rows is skipped. Rows past the rank are zero at the end and dropped. Returns the
/// pivot columns: the `k`-th row has its pivot in the `k`-th of them.
///
/// With [`Sweep::All`], the `k`-th row's entry in the `k`-th pivot column is `D` (the last
/// pivot, up to sign the same in every pivot row) and the other pivot columns are zero there.
pub(crate) fn eliminate(a: &mut Vec<Vec<BigInt>>, order: &[usize], sweep: Sweep) -> Vec<usize> {
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
        let update = |row: &mut Vec<BigInt>| {
            let f = row[col].clone();
            for (x, p) in row.iter_mut().zip(&pivot_row) {
                if x.is_zero() && (f.is_zero() || p.is_zero()) {
                    continue;
                }
                let mut v = &pivot * &*x;
                if !f.is_zero() && !p.is_zero() {
                    v -= &f * p;
                }
                let (q, rem) = v.div_rem(&prev);
                assert!(rem.is_zero(), "Bareiss division is exact");
                *x = q;
            }
        };
        match sweep {
            Sweep::Below => a[k + 1..].iter_mut().for_each(update),
            Sweep::All => a.par_iter_mut().enumerate().for_each(|(i, row)| {
                if i != k {
                    update(row)
                }
            }),
        }
        // With `Sweep::All`, the previous pivot rows' pivot entries become the new pivot (their
        // column in the pivot row is zero, so the rule above scaled them by pivot / prev).
        prev = pivot;
        pivots.push(col);
    }
    a.truncate(pivots.len());
    pivots
}

/// The rank of the integer rows `a` (each of length `ncols`) and, when the rank is `ncols - 1`,
/// a nonzero vector of their null space: [`eliminate`] to echelon form, then back substitution
/// in rationals.
pub(crate) fn null_space_int(
    mut a: Vec<Vec<BigInt>>,
    ncols: usize,
) -> (usize, Option<Vec<BigRational>>) {
    let order: Vec<usize> = (0..ncols).collect();
    let pivots = eliminate(&mut a, &order, Sweep::Below);
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
    let pivots = eliminate(&mut a, &order, Sweep::All);
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

/// Columns in the order complete pivoting in floating point takes them, the rest after, and
/// how many were taken (the numerical rank: a pivot below 1e-10 of its row's original size
/// ends the elimination).
pub(crate) fn float_pivot_order(mut a: Vec<Vec<f64>>, n: usize) -> (Vec<usize>, usize) {
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
pub(crate) fn kernel_point_fast(
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

/// `x` as integers over one common power of two (the same positive factor for all).
pub(crate) fn integers(x: &[f64]) -> Vec<BigInt> {
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

/// `x = mantissa * 2^exp`.
pub(crate) fn dyadic(x: f64) -> (BigInt, i32) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// [`null_space_int`] of rational rows, each scaled to a primitive integer vector first.
    fn null_space(rows: &[Vec<BigRational>], ncols: usize) -> (usize, Option<Vec<BigRational>>) {
        null_space_int(rows.iter().map(|row| integer_row(row)).collect(), ncols)
    }

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
