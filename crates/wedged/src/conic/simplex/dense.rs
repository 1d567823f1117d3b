//! The dense linear algebra of the simplex method: the basis inverse (Gauss-Jordan), products
//! with it, and dot products on eight partial sums.

use super::{pool, Lp};

/// The inverse of the basis matrix of `head` (Gauss-Jordan with partial pivoting), `None` when
/// it is singular.
pub(super) fn invert(lp: &Lp, head: &[usize]) -> Option<Vec<f64>> {
    let r = lp.rows;
    // [B | I], row-major, 2r wide.
    let w = 2 * r;
    let mut m = pool::zeroed(r * w);
    for (c, &j) in head.iter().enumerate() {
        for k in 0..r {
            m[k * w + c] = lp.entry(k, j);
        }
    }
    for k in 0..r {
        m[k * w + r + k] = 1.0;
    }
    let scale = m.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for c in 0..r {
        let p = (c..r).max_by(|&a, &b| m[a * w + c].abs().total_cmp(&m[b * w + c].abs()))?;
        let pivot = m[p * w + c];
        if pivot.abs() <= 1e-12 * scale {
            return None;
        }
        if p != c {
            for x in 0..w {
                m.swap(p * w + x, c * w + x);
            }
        }
        let inv_p = 1.0 / pivot;
        for x in 0..w {
            m[c * w + x] *= inv_p;
        }
        let pivot_row: Vec<f64> = m[c * w..(c + 1) * w].to_vec();
        for k in (0..r).filter(|&k| k != c) {
            let f = m[k * w + c];
            if f != 0.0 {
                for (a, b) in m[k * w..(k + 1) * w].iter_mut().zip(&pivot_row) {
                    *a -= f * b;
                }
            }
        }
    }
    let mut inv = pool::zeroed(r * r);
    for k in 0..r {
        inv[k * r..(k + 1) * r].copy_from_slice(&m[k * w + r..(k + 1) * w]);
    }
    pool::recycle(m);
    Some(inv)
}

/// The square row-major matrix `inv` times `v`.
pub(super) fn times(inv: &[f64], v: &[f64]) -> Vec<f64> {
    inv.chunks(v.len()).map(|row| dot(row, v)).collect()
}

/// `a . b` with eight partial sums, which the compiler vectorises (a plain sum of products it
/// may not reorder).
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0f64; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    acc.iter().sum::<f64>() + tail
}

/// `a . b` and the sum of its terms' sizes `sum |a_i b_i|`, on eight partial sums each (as
/// [`dot`]).
pub(super) fn dot_terms(a: &[f64], b: &[f64]) -> (f64, f64) {
    let (mut acc, mut size) = ([0.0f64; 8], [0.0f64; 8]);
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let (mut tail, mut tail_size) = (0.0, 0.0);
    for (x, y) in a8.remainder().iter().zip(b8.remainder()) {
        tail += x * y;
        tail_size += (x * y).abs();
    }
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            let t = x[k] * y[k];
            acc[k] += t;
            size[k] += t.abs();
        }
    }
    (
        acc.iter().sum::<f64>() + tail,
        size.iter().sum::<f64>() + tail_size,
    )
}
