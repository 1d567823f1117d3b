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

    #[test]
    fn null_vector_of_wide_matrix() {
        let a = DMatrix::from_row_slice(1, 2, &[1.0, -1.0]);
        let (sigma, v) = null_vector(&a);
        assert!(sigma[0] < 1e-15 && (sigma[1] - 1.0).abs() < 1e-15);
        assert!((v[0] - v[1]).abs() < 1e-15 && (v[0].abs() - 0.5f64.sqrt()).abs() < 1e-15);
    }
}
