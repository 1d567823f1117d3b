//! The dense linear algebra of the simplex method: the basis inverse (Gauss-Jordan), products
//! with it, its update at a pivot (with the rows' norms for the dual method's pricing), and dot
//! products on eight partial sums.
//!
//! The kernels that the simplex method spends its time in (a pivot's update of the inverse,
//! `v^T A`, products with the inverse, dot products) are compiled for AVX2 as well, and that
//! version runs when the processor has it (`kernel!`): a default x86-64 build vectorises
//! them two values wide, AVX2 four. (On the 2D plug, `critical`, whole process: m = 60 paired
//! 0.92; see `BENCHMARKS.md`. AVX-512 was no faster there: 1.07 against AVX2.)

use super::{pool, Lp};

/// A kernel: `body` compiled twice, once for AVX2 (run when the processor has it) and once for
/// the build's target. The kernels are elementwise products and sums in a fixed order, which
/// vector width does not change, so both give the same bits.
macro_rules! kernel {
    ($(#[$doc:meta])* $vis:vis fn $name:ident($($arg:ident: $ty:ty),*) $(-> $ret:ty)? $body:block) => {
        $(#[$doc])*
        $vis fn $name($($arg: $ty),*) $(-> $ret)? {
            #[inline(always)]
            fn body($($arg: $ty),*) $(-> $ret)? $body
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2")]
                fn wide($($arg: $ty),*) $(-> $ret)? {
                    body($($arg),*)
                }
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: the processor runs AVX2 (checked just above).
                    return unsafe { wide($($arg),*) };
                }
            }
            body($($arg),*)
        }
    };
}

/// The inverse of the basis matrix of `head` (row `c` of the result for position `c` of the
/// head), `None` when it is singular.
///
/// A basis column `n + k` (row `k`'s activity) is `-e_k`, so only the structural columns need
/// elimination: with `R` the rows no slack of the basis covers and `S` the head's structural
/// columns, `A[R, S] x_S = b_R` gives `x_S`, and each slack covering row `k` is `x = A[k, S] x_S
/// - b_k`. So the inverse is `M^-1` (`M = A[R, S]`, by Gauss-Jordan with partial pivoting) and
/// `A[k, S] M^-1` on the slacks' rows: `2 s^3 + (r - s) s^2` operations for `s` structural
/// columns against `2 r^3` for the whole basis. (A tightening program of the 2D plug at m = 60
/// has 118 active rows, and about 37 of its basis columns are structural; the whole basis's
/// elimination was 28% of `critical` there.)
pub(super) fn invert(lp: &Lp, head: &[usize]) -> Option<Vec<f64>> {
    let r = lp.rows;
    let n = lp.n;
    // The position of the slack that covers each row (`usize::MAX`: none).
    let mut covering = vec![usize::MAX; r];
    let mut structural = Vec::new();
    for (c, &j) in head.iter().enumerate() {
        if j >= n {
            if covering[j - n] != usize::MAX {
                return None;
            }
            covering[j - n] = c;
        } else {
            structural.push(c);
        }
    }
    let open: Vec<usize> = (0..r).filter(|&k| covering[k] == usize::MAX).collect();
    let s = structural.len();
    if open.len() != s {
        return None;
    }
    // The basis's structural columns: on the open rows `M` (row-major, inverted in place
    // below), on the rows its slacks cover `C` (row-major, `r - s` by `s`).
    let covered: Vec<usize> = (0..r).filter(|&k| covering[k] != usize::MAX).collect();
    let gather = |rows: &[usize]| {
        let mut out = pool::zeroed(rows.len() * s);
        for (q, &k) in rows.iter().enumerate() {
            let row = lp.row(k);
            for (p, &c) in structural.iter().enumerate() {
                out[q * s + p] = row[head[c]];
            }
        }
        out
    };
    let mut m = gather(&open);
    let cov = gather(&covered);
    // The scale the pivots are judged against: the basis's entries (its slacks' 1s included).
    let scale = largest_size(&m).max(largest_size(&cov)).max(1.0);
    // M inverted in place: Gauss-Jordan with partial pivoting, each pivot's column taking the
    // inverse's as it goes (`s^3` multiply-adds against `2 s^3` on `[M | I]`), the row swaps
    // undone as column swaps at the end.
    let mut swaps = vec![0usize; s];
    let mut column = vec![0.0; s];
    for c in 0..s {
        let p = (c..s).max_by(|&a, &b| m[a * s + c].abs().total_cmp(&m[b * s + c].abs()))?;
        let pivot = m[p * s + c];
        if pivot.abs() <= 1e-12 * scale {
            pool::recycle(m);
            pool::recycle(cov);
            return None;
        }
        swaps[c] = p;
        if p != c {
            for x in 0..s {
                m.swap(p * s + x, c * s + x);
            }
        }
        // Column `c` becomes the inverse's: `e_c` before the pivot's update, which divides
        // row `c` by the pivot and takes `m_kc` times it from every other row `k`.
        for (k, x) in column.iter_mut().enumerate() {
            *x = m[k * s + c];
            m[k * s + c] = if k == c { 1.0 } else { 0.0 };
        }
        eliminate(&mut m, s, c, &column);
    }
    for c in (0..s).rev() {
        let p = swaps[c];
        if p != c {
            for row in m.chunks_exact_mut(s) {
                row.swap(p, c);
            }
        }
    }
    // Row p of M^-1 is m[p * s..(p + 1) * s]: x_S[p] from b over the open rows.
    let mut inv = pool::zeroed(r * r);
    for (p, &c) in structural.iter().enumerate() {
        let out = &mut inv[c * r..(c + 1) * r];
        for (q, &k) in open.iter().enumerate() {
            out[k] = m[p * s + q];
        }
    }
    // The slacks' rows, `C M^-1`.
    let slack_rows = times_tiled(&cov, &m, s);
    for (g, &k) in covered.iter().enumerate() {
        let out = &mut inv[covering[k] * r..(covering[k] + 1) * r];
        for (q, &kq) in open.iter().enumerate() {
            out[kq] = slack_rows[g * s + q];
        }
        out[k] = -1.0;
    }
    pool::recycle(m);
    pool::recycle(cov);
    pool::recycle(slack_rows);
    Some(inv)
}

/// The largest `|x|` of `values` (0 for none), on four running maxima.
fn largest_size(values: &[f64]) -> f64 {
    let mut most = [0.0f64; 4];
    let chunks = values.chunks_exact(4);
    let tail = chunks
        .remainder()
        .iter()
        .fold(0.0f64, |a, x| a.max(x.abs()));
    for c in chunks {
        for k in 0..4 {
            most[k] = most[k].max(c[k].abs());
        }
    }
    most.iter().fold(tail, |a, &x| a.max(x))
}

kernel! {
    /// `C B` for `C` row-major with `s` columns and `B` row-major `s` by `s`: each entry summed
    /// over `p` in order from `+0` (the bits of one `axpy` per term, row by row), in tiles of
    /// four rows by eight columns held in registers across the sum.
    fn times_tiled(c: &[f64], b: &[f64], s: usize) -> Vec<f64> {
        let rows = c.len() / s.max(1);
        let mut out = pool::zeroed(rows * s);
        let whole = s / 8 * 8;
        let mut i0 = 0;
        while i0 < rows {
            let h = (rows - i0).min(4);
            let mut q0 = 0;
            while q0 < whole {
                let mut acc = [[0.0f64; 8]; 4];
                for p in 0..s {
                    let bp: &[f64; 8] = b[p * s + q0..p * s + q0 + 8].try_into().expect("eight");
                    for (i, row) in acc.iter_mut().enumerate().take(h) {
                        let f = c[(i0 + i) * s + p];
                        for j in 0..8 {
                            row[j] += f * bp[j];
                        }
                    }
                }
                for (i, row) in acc.iter().enumerate().take(h) {
                    out[(i0 + i) * s + q0..(i0 + i) * s + q0 + 8].copy_from_slice(row);
                }
                q0 += 8;
            }
            if whole < s {
                // The last columns, fewer than eight: the same tile, partly used.
                let w = s - whole;
                let mut acc = [[0.0f64; 8]; 4];
                for p in 0..s {
                    let bp = &b[p * s + whole..(p + 1) * s];
                    for (i, row) in acc.iter_mut().enumerate().take(h) {
                        let f = c[(i0 + i) * s + p];
                        for j in 0..w {
                            row[j] += f * bp[j];
                        }
                    }
                }
                for (i, row) in acc.iter().enumerate().take(h) {
                    out[(i0 + i) * s + whole..(i0 + i + 1) * s].copy_from_slice(&row[..w]);
                }
            }
            i0 += h;
        }
        out
    }
}

kernel! {
    /// The square row-major matrix `inv` times `v`, into `out` (its storage reused).
    pub(super) fn times_into(inv: &[f64], v: &[f64], out: &mut Vec<f64>) {
        out.clear();
        // A plain loop rather than `extend(map(..))`: the iterator's `fold` was compiled as a
        // function of its own, outside the AVX2 body, and ran the dot products two values
        // wide (15% of `critical` on the 2D plug at m = 100).
        for row in inv.chunks(v.len()) {
            out.push(dot8(row, v));
        }
    }
}

kernel! {
    /// `a . b` with eight partial sums, which the compiler vectorises (a plain sum of products
    /// it may not reorder).
    pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
        dot8(a, b)
    }
}

kernel! {
    /// `y += f x`.
    pub(super) fn axpy(y: &mut [f64], f: f64, x: &[f64]) {
        for (a, b) in y.iter_mut().zip(x) {
            *a += f * b;
        }
    }
}

kernel! {
    /// The pivot's update of a square row-major inverse `inv` (`r` wide): row `p` divided by
    /// `alpha_p`, then every other row `k` less `alpha_k` times it.
    pub(super) fn eliminate(inv: &mut [f64], r: usize, p: usize, alpha: &[f64]) {
        let f = 1.0 / alpha[p];
        for a in &mut inv[p * r..(p + 1) * r] {
            *a *= f;
        }
        // Row `p` borrowed beside the others rather than copied (a copy a pivot).
        let (before, rest) = inv.split_at_mut(p * r);
        let (prow, after) = rest.split_at_mut(r);
        let others = before.chunks_exact_mut(r).zip(&alpha[..p]);
        for (row, &ak) in others.chain(after.chunks_exact_mut(r).zip(&alpha[p + 1..])) {
            if ak != 0.0 {
                for (a, b) in row.iter_mut().zip(prow.iter()) {
                    *a -= ak * b;
                }
            }
        }
    }
}

kernel! {
    /// [`eliminate`] (the same bits), and the squared norm of every row it changed into
    /// `norms` (the bits of [`dot`] of the row with itself): the dual method's steepest-edge
    /// weights, kept exact at the cost of a sum in the pass that writes the rows anyway.
    pub(super) fn eliminate_norms(
        inv: &mut [f64],
        r: usize,
        p: usize,
        alpha: &[f64],
        norms: &mut [f64]
    ) {
        let f = 1.0 / alpha[p];
        for a in &mut inv[p * r..(p + 1) * r] {
            *a *= f;
        }
        let (before, rest) = inv.split_at_mut(p * r);
        let (prow, after) = rest.split_at_mut(r);
        norms[p] = dot8(prow, prow);
        let others = before.chunks_exact_mut(r).zip(&alpha[..p]).enumerate();
        let later = after.chunks_exact_mut(r).zip(&alpha[p + 1..]);
        let later = later.enumerate().map(|(k, pair)| (k + p + 1, pair));
        for (k, (row, &ak)) in others.chain(later) {
            if ak == 0.0 {
                continue;
            }
            // Eight values at a time through registers: written back, then squared into
            // the partial sums (updated in place and read again, the loop stayed scalar).
            let mut acc = [0.0f64; 8];
            let mut rows = row.chunks_exact_mut(8);
            let mut pivots = prow.chunks_exact(8);
            for (c, b) in (&mut rows).zip(&mut pivots) {
                let c: &mut [f64; 8] = c.try_into().expect("eight");
                let b: &[f64; 8] = b.try_into().expect("eight");
                let mut v = [0.0f64; 8];
                for j in 0..8 {
                    v[j] = c[j] - ak * b[j];
                }
                *c = v;
                for j in 0..8 {
                    acc[j] += v[j] * v[j];
                }
            }
            let mut tail = 0.0;
            for (a, b) in rows.into_remainder().iter_mut().zip(pivots.remainder()) {
                *a -= ak * b;
                tail += *a * *a;
            }
            norms[k] = acc.iter().sum::<f64>() + tail;
        }
    }
}

#[inline(always)]
fn dot8(a: &[f64], b: &[f64]) -> f64 {
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

kernel! {
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
}

kernel! {
/// The least and the greatest of `a . x` over the box `lo <= x <= hi` (all of them finite), on
/// eight partial sums each (as [`dot`]): the interval a row's columns imply for its activity.
pub(super) fn implied(a: &[f64], lo: &[f64], hi: &[f64]) -> (f64, f64) {
    let (mut least, mut most) = ([0.0f64; 8], [0.0f64; 8]);
    let (a8, lo8, hi8) = (a.chunks_exact(8), lo.chunks_exact(8), hi.chunks_exact(8));
    let (mut tail_least, mut tail_most) = (0.0, 0.0);
    for ((&x, &l), &h) in a8.remainder().iter().zip(lo8.remainder()).zip(hi8.remainder()) {
        let (at_least, at_most) = if x > 0.0 { (l, h) } else { (h, l) };
        tail_least += x * at_least;
        tail_most += x * at_most;
    }
    for ((x, l), h) in a8.zip(lo8).zip(hi8) {
        for k in 0..8 {
            let (at_least, at_most) = if x[k] > 0.0 { (l[k], h[k]) } else { (h[k], l[k]) };
            least[k] += x[k] * at_least;
            most[k] += x[k] * at_most;
        }
    }
    (
        least.iter().sum::<f64>() + tail_least,
        most.iter().sum::<f64>() + tail_most,
    )
}
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values of many sizes and signs (a fixed linear congruential sequence).
    fn values(len: usize, seed: u64) -> Vec<f64> {
        let mut x = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (0..len)
            .map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let unit = (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                unit * 2f64.powi(((x >> 3) % 40) as i32 - 20)
            })
            .collect()
    }

    /// The kernels (the AVX2 version where the processor has it) give exactly the bits of the
    /// same operations done one value at a time in the same order: eight partial sums for a
    /// dot product, elementwise for the rest.
    #[test]
    fn kernels_give_the_bits_of_scalar_code() {
        for len in [0, 1, 7, 8, 9, 31, 64, 301] {
            let (a, b) = (values(len, 1 + len as u64), values(len, 1000 + len as u64));
            let mut acc = [0.0f64; 8];
            let mut size = [0.0f64; 8];
            let whole = len / 8 * 8;
            for i in 0..whole {
                acc[i % 8] += a[i] * b[i];
                size[i % 8] += (a[i] * b[i]).abs();
            }
            let mut tail = 0.0;
            let mut tail_size = 0.0;
            for i in whole..len {
                tail += a[i] * b[i];
                tail_size += (a[i] * b[i]).abs();
            }
            // `Iterator::sum` of floats starts from -0.0; the partial sums are added in order.
            let reference = acc.iter().fold(-0.0, |s, x| s + x) + tail;
            assert_eq!(dot(&a, &b).to_bits(), reference.to_bits(), "dot, {len}");
            let (d, t) = dot_terms(&a, &b);
            assert_eq!(d.to_bits(), reference.to_bits(), "dot_terms, {len}");
            let size_ref = size.iter().fold(-0.0, |s, x| s + x) + tail_size;
            assert_eq!(t.to_bits(), size_ref.to_bits(), "dot_terms size, {len}");

            // The implied interval over a box: each term at the bound its sign picks.
            let c = values(len, 2000 + len as u64);
            let (lo, hi): (Vec<f64>, Vec<f64>) = b
                .iter()
                .zip(&c)
                .map(|(&p, &q)| (p.min(q), p.max(q)))
                .unzip();
            let (mut least, mut most) = ([0.0f64; 8], [0.0f64; 8]);
            let (mut tail_least, mut tail_most) = (0.0, 0.0);
            for i in 0..len {
                let (l, h) = if a[i] > 0.0 {
                    (lo[i], hi[i])
                } else {
                    (hi[i], lo[i])
                };
                if i < whole {
                    least[i % 8] += a[i] * l;
                    most[i % 8] += a[i] * h;
                } else {
                    tail_least += a[i] * l;
                    tail_most += a[i] * h;
                }
            }
            let (il, ih) = implied(&a, &lo, &hi);
            let least_ref = least.iter().fold(-0.0, |s, x| s + x) + tail_least;
            let most_ref = most.iter().fold(-0.0, |s, x| s + x) + tail_most;
            assert_eq!(il.to_bits(), least_ref.to_bits(), "implied least, {len}");
            assert_eq!(ih.to_bits(), most_ref.to_bits(), "implied most, {len}");
            assert!(il <= ih, "implied, {len}");

            let mut y = a.clone();
            axpy(&mut y, -0.375, &b);
            for i in 0..len {
                assert_eq!(y[i].to_bits(), (a[i] + -0.375 * b[i]).to_bits(), "axpy");
            }
        }
        let r = 13;
        let inv = values(r * r, 7);
        let v = values(r, 8);
        let mut product = vec![1.0; 3];
        times_into(&inv, &v, &mut product);
        assert_eq!(product.len(), r);
        for k in 0..r {
            assert_eq!(
                product[k].to_bits(),
                dot(&inv[k * r..(k + 1) * r], &v).to_bits()
            );
        }
        // `C B` in tiles: the bits of one `axpy` per term, row by row, for every shape of
        // the tiles' edges (rows not a multiple of four, columns not of eight), zeros in `C`.
        for (rows, s) in [(1, 1), (3, 7), (4, 8), (5, 9), (9, 17), (12, 30)] {
            let mut c = values(rows * s, 20 + s as u64);
            c.iter_mut().step_by(3).for_each(|x| *x = 0.0);
            let b = values(s * s, 40 + rows as u64);
            let tiled = times_tiled(&c, &b, s);
            for i in 0..rows {
                let mut row = vec![0.0; s];
                for p in 0..s {
                    if c[i * s + p] != 0.0 {
                        axpy(&mut row, c[i * s + p], &b[p * s..(p + 1) * s]);
                    }
                }
                for q in 0..s {
                    assert_eq!(tiled[i * s + q].to_bits(), row[q].to_bits(), "times_tiled");
                }
            }
        }
        let mut alpha = values(r, 9);
        alpha[2] = 0.0;
        let p = 4;
        let mut updated = inv.clone();
        eliminate(&mut updated, r, p, &alpha);
        // The same update with the rows' squared norms: the same bits, and each changed
        // row's norm that of `dot` (a row left alone, `alpha_k = 0`, keeps its old norm).
        for wide in [r, 16, 9] {
            let inv = values(wide * wide, 7 + wide as u64);
            let mut alpha = values(wide, 9);
            alpha[2] = 0.0;
            let mut plain = inv.clone();
            eliminate(&mut plain, wide, p, &alpha);
            let mut with = inv.clone();
            let mut norms = vec![-1.0; wide];
            eliminate_norms(&mut with, wide, p, &alpha, &mut norms);
            for k in 0..wide {
                let row = &with[k * wide..(k + 1) * wide];
                let expected = if k == 2 { -1.0 } else { dot(row, row) };
                assert_eq!(norms[k].to_bits(), expected.to_bits(), "norm {k} of {wide}");
                for (a, b) in row.iter().zip(&plain[k * wide..(k + 1) * wide]) {
                    assert_eq!(a.to_bits(), b.to_bits(), "eliminate_norms");
                }
            }
        }
        let f = 1.0 / alpha[p];
        let prow: Vec<f64> = inv[p * r..(p + 1) * r].iter().map(|x| x * f).collect();
        for k in 0..r {
            for c in 0..r {
                let expected = if k == p {
                    prow[c]
                } else {
                    inv[k * r + c] - alpha[k] * prow[c]
                };
                assert_eq!(
                    updated[k * r + c].to_bits(),
                    expected.to_bits(),
                    "eliminate"
                );
            }
        }
    }
}
