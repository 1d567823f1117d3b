//! Small dense helpers: numerical rank and null vectors with tolerances relative to the data.

use nalgebra::DMatrix;

/// Numerical rank of the `rows x cols` row-major matrix `a` (overwritten), by Gaussian elimination
/// with complete pivoting after scaling every row to unit max-norm. A pivot is zero when it is
/// `<= tol` times the largest entry of the scaled matrix (which is 1). All-zero rows are ignored.
pub(crate) fn rank(a: &mut [f64], rows: usize, cols: usize, tol: f64) -> usize {
    debug_assert_eq!(a.len(), rows * cols);
    for i in 0..rows {
        let row = &mut a[i * cols..(i + 1) * cols];
        let m = row.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if m > 0.0 {
            row.iter_mut().for_each(|x| *x /= m);
        }
    }
    let mut col_perm: Vec<usize> = (0..cols).collect();
    let mut rank = 0;
    while rank < rows.min(cols) {
        // Complete pivot search over the remaining block.
        let (mut bi, mut bj, mut best) = (rank, rank, 0.0f64);
        for i in rank..rows {
            for (jj, &j) in col_perm.iter().enumerate().skip(rank) {
                let v = a[i * cols + j].abs();
                if v > best {
                    best = v;
                    bi = i;
                    bj = jj;
                }
            }
        }
        if best <= tol {
            break;
        }
        if bi != rank {
            for c in 0..cols {
                a.swap(bi * cols + c, rank * cols + c);
            }
        }
        col_perm.swap(rank, bj);
        let pc = col_perm[rank];
        let pivot = a[rank * cols + pc];
        for i in (rank + 1)..rows {
            let f = a[i * cols + pc] / pivot;
            if f != 0.0 {
                for &j in &col_perm[rank..] {
                    a[i * cols + j] -= f * a[rank * cols + j];
                }
            }
        }
        rank += 1;
    }
    rank
}

/// The singular values (ascending) of `a` with its rows scaled to unit 2-norm, and the right
/// singular vector of the smallest one. `a` may have fewer rows than columns.
pub(crate) fn null_vector(a: &DMatrix<f64>) -> (Vec<f64>, Vec<f64>) {
    let mut b = a.clone();
    for i in 0..a.nrows() {
        let norm = a.row(i).norm();
        if norm > 0.0 {
            b.set_row(i, &(a.row(i) / norm));
        }
    }
    smallest_singular(&b)
}

/// The singular values (ascending) of `a` as it is, and the right singular vector of the
/// smallest one. `a` may have fewer rows than columns.
pub(crate) fn smallest_singular(a: &DMatrix<f64>) -> (Vec<f64>, Vec<f64>) {
    let n = a.ncols();
    let rows = a.nrows().max(n);
    let mut b = DMatrix::<f64>::zeros(rows, n);
    b.rows_mut(0, a.nrows()).copy_from(a);
    let svd = b.svd(false, true);
    let vt = svd.v_t.expect("requested V^T");
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&x, &y| svd.singular_values[x].total_cmp(&svd.singular_values[y]));
    let sigma = order.iter().map(|&k| svd.singular_values[k]).collect();
    let v = vt.row(order[0]).iter().copied().collect();
    (sigma, v)
}

/// What a QR factorisation tells of a matrix `a` with one row fewer than columns (`k - 1` x
/// `k`, the usual tight matrix of an extreme ray) without its singular value decomposition:
/// bounds on its singular values and a null vector. With `a^T = Q R` (Householder; `Q` has
/// orthonormal columns, `R` is square and triangular) the singular values of `a` are those of
/// `R`, so the least of them, `s`, satisfies `1 / |R^-1|_F <= s <= min_i |R_ii|` (the diagonal
/// holds `R`'s eigenvalues), and the largest lies between `a`'s largest row norm and its
/// Frobenius norm. A null vector is orthogonal to `Q`'s columns: `e_j` minus its projections
/// on them, normalised, for the `j` that they cover least (what is left then has norm at least
/// `1 / sqrt(k)`), projected twice so that the first projection's round-off does not stay. The
/// bounds are what a caller can decide from without the decomposition (and decide the rest by
/// [`smallest_singular`]); `None` when `a` is not of that shape or `R` is singular.
pub(crate) struct OneShort {
    /// A unit null vector of `a`.
    pub null: Vec<f64>,
    /// `1 / |R^-1|_F`: at most the least singular value.
    pub least_at_least: f64,
    /// `min_i |R_ii|`: at least the least singular value.
    pub least_at_most: f64,
    /// The largest row norm: at most the largest singular value.
    pub top_at_least: f64,
    /// The Frobenius norm: at least the largest singular value.
    pub top_at_most: f64,
}

pub(crate) fn one_row_short(a: &DMatrix<f64>) -> Option<OneShort> {
    let (rows, n) = a.shape();
    if rows == 0 || rows + 1 != n {
        return None;
    }
    let qr = a.transpose().qr();
    let r = qr.r();
    // `R^-1` in place of the identity (one matrix, not a copy; `false` when `R` is singular).
    let mut inverse = DMatrix::identity(rows, rows);
    if !r.solve_upper_triangular_mut(&mut inverse) {
        return None;
    }
    let inverse_norm = inverse.norm();
    if !inverse_norm.is_finite() || inverse_norm == 0.0 {
        return None;
    }
    let q = qr.q();
    let covered = |j: usize| q.row(j).norm_squared();
    let j = (0..n).min_by(|&x, &y| covered(x).total_cmp(&covered(y)))?;
    let mut v = nalgebra::DVector::<f64>::zeros(n);
    v[j] = 1.0;
    // `v -= Q (Q^T v)` twice, the products into two vectors made once.
    let mut c = nalgebra::DVector::<f64>::zeros(rows);
    let mut qc = nalgebra::DVector::<f64>::zeros(n);
    for _ in 0..2 {
        q.tr_mul_to(&v, &mut c);
        q.mul_to(&c, &mut qc);
        v -= &qc;
    }
    let norm = v.norm();
    let mut null: Vec<f64> = v.data.into();
    null.iter_mut().for_each(|x| *x /= norm);
    Some(OneShort {
        null,
        least_at_least: 1.0 / inverse_norm,
        least_at_most: (0..rows).fold(f64::INFINITY, |m, i| m.min(r[(i, i)].abs())),
        top_at_least: a.row_iter().fold(0.0f64, |m, row| m.max(row.norm())),
        top_at_most: a.norm(),
    })
}

/// An orthonormal basis (columns) of the numerical null space of `a`: the right singular
/// vectors of `a` whose singular value is at most `zero` (an absolute threshold: the caller
/// knows the scale of the rows, which may be parts of longer rows that set it).
pub(crate) fn null_space(a: &DMatrix<f64>, zero: f64) -> DMatrix<f64> {
    let n = a.ncols();
    let rows = a.nrows().max(n);
    let mut b = DMatrix::<f64>::zeros(rows, n);
    b.rows_mut(0, a.nrows()).copy_from(a);
    let svd = b.svd(false, true);
    let vt = svd.v_t.expect("requested V^T");
    let null: Vec<usize> = (0..n).filter(|&k| svd.singular_values[k] <= zero).collect();
    DMatrix::from_fn(n, null.len(), |r, c| vt[(null[c], r)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rank_of_known_matrices() {
        let mut a = vec![1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 1.0, 0.0, 1.0];
        assert_eq!(rank(&mut a, 3, 3, 1e-12), 2);
        let mut b = vec![1e-20, 0.0, 0.0, 5e8];
        assert_eq!(
            rank(&mut b, 2, 2, 1e-12),
            2,
            "row scaling makes tiny rows count"
        );
        let mut c = vec![0.0; 6];
        assert_eq!(rank(&mut c, 2, 3, 1e-12), 0);
        let mut d = vec![1.0, 1.0, 1.0, 1.0 + 1e-14];
        assert_eq!(rank(&mut d, 2, 2, 1e-12), 1);
    }

    /// [`one_row_short`]'s bounds hold against the singular value decomposition and its null
    /// vector is one, on 600 seeded matrices of 1 x 2 to 9 x 10: plain, with rows and columns
    /// scaled over twelve orders of magnitude, and with the last row within `1e-14` to `1` of a
    /// combination of the others.
    #[test]
    fn one_row_short_bounds_the_singular_values() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut checked = 0;
        for case in 0..600 {
            let n = 2 + case % 9;
            let mut a = DMatrix::<f64>::from_fn(n - 1, n, |_, _| rng.gen_range(-1.0..1.0));
            match case % 3 {
                1 => {
                    for i in 0..n - 1 {
                        let f = 10f64.powf(rng.gen_range(-6.0..6.0));
                        a.row_mut(i).iter_mut().for_each(|x| *x *= f);
                    }
                    for j in 0..n {
                        let f = 10f64.powf(rng.gen_range(-6.0..6.0));
                        a.column_mut(j).iter_mut().for_each(|x| *x *= f);
                    }
                }
                2 if n > 2 => {
                    let eps = 10f64.powf(rng.gen_range(-14.0..0.0));
                    let mut last = a.row(0) * rng.gen_range(-1.0..1.0);
                    for i in 1..n - 2 {
                        last += a.row(i) * rng.gen_range(-1.0..1.0);
                    }
                    for x in last.iter_mut() {
                        *x += eps * rng.gen_range(-1.0..1.0);
                    }
                    a.set_row(n - 2, &last);
                }
                _ => {}
            }
            let (sigma, _) = smallest_singular(&a);
            let (least, top) = (sigma[1], sigma[n - 1]);
            // `nalgebra`'s decomposition of the scaled matrices is only good to about 1e-10
            // of the largest singular value (its largest came out 8e-11 above the Frobenius
            // norm on one of them).
            let slack = 1e-9 * top;
            let Some(b) = one_row_short(&a) else {
                continue;
            };
            checked += 1;
            assert!(
                b.least_at_least <= least + slack,
                "{} > {least}",
                b.least_at_least
            );
            assert!(
                least <= b.least_at_most + slack,
                "{least} > {}",
                b.least_at_most
            );
            assert!(
                b.top_at_least <= top + slack && top <= b.top_at_most + slack,
                "case {case}: {} {top} {} {slack}",
                b.top_at_least,
                b.top_at_most
            );
            let v = DMatrix::from_column_slice(n, 1, &b.null);
            assert!(((v.norm()) - 1.0).abs() < 1e-14);
            assert!((&a * &v).norm() <= 1e-13 * a.norm(), "case {case}");
        }
        assert!(checked > 550, "{checked}");
    }

    #[test]
    fn null_vector_of_wide_matrix() {
        let a = DMatrix::from_row_slice(1, 2, &[1.0, -1.0]);
        let (sigma, v) = null_vector(&a);
        assert!(sigma[0] < 1e-15 && (sigma[1] - 1.0).abs() < 1e-15);
        assert!((v[0] - v[1]).abs() < 1e-15 && (v[0].abs() - 0.5f64.sqrt()).abs() < 1e-15);
    }
}
