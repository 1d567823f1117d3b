//! The extreme rays of one leaf's face, by double description in the face's own dimension.
//!
//! A leaf of the search fixes every node: contact (`u_n = 0`, friction edges `a_i, b_i >= 0`)
//! or separated (`r = 0`, `u_n >= 0`). Its face is a cone in the friction edges of the contact
//! nodes. The support program ([`crate::conic::contact_lp::ContactLp::support`]) tells which edges and which gaps some
//! solution makes positive; every other one is zero throughout the face, an equality. So the
//! face is `{ x : E x = 0, B x >= 0 }` with `E` the contact gaps and the entries that are always
//! zero, `B` the entries that are not. With `N` a basis of the null space of `E` (`k`
//! columns, `k` the face's dimension), the face is `{ N y : (B N) y >= 0 }`, a pointed cone
//! that is full-dimensional in `R^k`, and its extreme rays come from a plain double
//! description there: start from `k` independent rows (a simplicial cone), add the other rows
//! one at a time, combine the pairs of opposite sign that are adjacent. Every ray of the
//! current cone is held, so the combinatorial adjacency test (no other held ray is tight on
//! every row common to the pair) is exact.
//!
//! A ray's status follows from the rows it is tight on: an edge at zero is a slip direction
//! (`a_i = 0`: `r_t = -mu r_n`, slip-; `b_i = 0`: slip+; both: grazing), a gap at zero is
//! grazing. The finishing step recomputes each ray from its status and checks it.

use nalgebra::DMatrix;

use crate::conic::contact_lp::{Entry2, LeafSupport};
use crate::conic::program::{Class, Formulation};
use crate::linalg::null_space;
use crate::rays::dd::{bit, set_bit, NOISE};
use crate::solution::NodeStatus;

/// A ray of a face in the search's (equilibrated) units: reactions, `sum r_n = 1`, and status.
pub(super) struct FaceRay {
    pub r: Vec<f64>,
    pub status: Vec<NodeStatus>,
}

/// What a face's double description cost.
#[derive(Debug, Default, Clone, Copy)]
pub(super) struct FaceStats {
    /// The face's dimension.
    pub dim: usize,
    /// Most rays held at once.
    pub peak: usize,
    /// The face was described without its support (neither solver settled it).
    pub close: bool,
    /// The least, over the face's inequalities (its positive edges and opening gaps), of the
    /// largest share of the total pressure that one of its rays gives it (`0` for no rays).
    pub least_share: f64,
}

/// The row of the friction edge `col` (`2i` for `a_i`, `2i + 1` for `b_i`) of a gap row over
/// the reaction components: `r_n = a + b`, `r_t = mu (a - b)`.
fn on_edges(gap: &[f64], mu: f64, cols: &[usize]) -> Vec<f64> {
    cols.iter()
        .map(|&c| {
            let (gn, gt) = (gap[c & !1], gap[c | 1]);
            if c % 2 == 0 {
                gn + mu * gt
            } else {
                gn - mu * gt
            }
        })
        .collect()
}

/// The extreme rays of the face of the leaf `classes` (contact or separated at every node)
/// whose support is `support`. `tol` is the relative zero tolerance of the sign decisions.
pub(super) fn rays(
    form: &Formulation,
    classes: &[Class],
    support: &LeafSupport,
    tol: f64,
) -> Result<(Vec<FaceRay>, FaceStats), String> {
    let (m, mu) = (form.m, form.mu);
    let positive = |e: Entry2| support.positive.contains(&e);
    // The variables: the edges some solution makes positive.
    let cols: Vec<usize> = (0..2 * m)
        .filter(|&c| classes[c / 2] == Class::Contact && positive(Entry2::Edge(c)))
        .collect();
    let nv = cols.len();
    if nv == 0 {
        return Ok((Vec::new(), FaceStats::default()));
    }
    // Equalities: contact gaps, and the gaps of separated nodes that never open.
    let eq_nodes: Vec<usize> = (0..m)
        .filter(|&i| classes[i] == Class::Contact || !positive(Entry2::Gap(i)))
        .collect();
    let mut e = DMatrix::<f64>::zeros(eq_nodes.len(), nv);
    for (k, &i) in eq_nodes.iter().enumerate() {
        for (c, v) in on_edges(form.gap_row(i), mu, &cols).into_iter().enumerate() {
            e[(k, c)] = v;
        }
    }
    // The gap rows are scaled to unit largest entry over all `2m` reaction components, so an
    // entry on the edges is at most `1 + mu`: that is the scale of the zero threshold.
    let basis = if eq_nodes.is_empty() {
        DMatrix::<f64>::identity(nv, nv)
    } else {
        null_space(&e, tol * (1.0 + mu) * (nv as f64).sqrt())
    };
    let k = basis.ncols();
    if k == 0 {
        return Err(format!(
            "the face has dimension 0 although {nv} friction edges are positive in it"
        ));
    }
    // Inequalities `B N y >= 0`: the edges (identity rows), then the gaps that open; row
    // after row, `k` values each.
    let mut labels: Vec<Entry2> = cols.iter().map(|&c| Entry2::Edge(c)).collect();
    let mut b_rows: Vec<f64> = Vec::with_capacity((nv + m) * k);
    for c in 0..nv {
        b_rows.extend(basis.row(c).iter());
    }
    let mut gaps: Vec<Vec<f64>> = Vec::new();
    for i in (0..m).filter(|&i| classes[i] == Class::Separated && positive(Entry2::Gap(i))) {
        let g = on_edges(form.gap_row(i), mu, &cols);
        b_rows.extend((0..k).map(|j| (0..nv).map(|c| g[c] * basis[(c, j)]).sum::<f64>()));
        labels.push(Entry2::Gap(i));
        gaps.push(g);
    }
    for row in b_rows.chunks_exact_mut(k) {
        let s = row.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        if s > 0.0 {
            row.iter_mut().for_each(|x| *x /= s);
        }
    }
    // The row of each separated node's gap among the inequalities, if it opens.
    let gap_row: Vec<Option<usize>> = (0..m)
        .map(|i| labels.iter().position(|&l| l == Entry2::Gap(i)))
        .collect();
    let (held, peak) = double_description(&b_rows, k, tol)?;
    let mut out = Vec::with_capacity(held.len());
    // Per inequality, the largest share of a ray's total pressure it reaches.
    let mut share = vec![0.0f64; nv + gaps.len()];
    let mut x = vec![0.0; nv];
    let mut edge_zero = vec![true; 2 * m];
    for ray in 0..held.len() {
        let y = held.y(ray);
        for (c, xc) in x.iter_mut().enumerate() {
            *xc = (0..k).map(|j| basis[(c, j)] * y[j]).sum();
        }
        let pressure: f64 = x.iter().sum();
        if pressure > 0.0 {
            let values = x.iter().copied().chain(
                gaps.iter()
                    .map(|g| g.iter().zip(&x).map(|(a, b)| a * b).sum::<f64>()),
            );
            for (s, v) in share.iter_mut().zip(values) {
                *s = s.max(v / pressure);
            }
        }
        let mut r = vec![0.0; 2 * m];
        edge_zero.iter_mut().for_each(|z| *z = true);
        for (c, &col) in cols.iter().enumerate() {
            let v = x[c].max(0.0);
            let i = col / 2;
            if col % 2 == 0 {
                r[2 * i] += v;
                r[2 * i + 1] += mu * v;
            } else {
                r[2 * i] += v;
                r[2 * i + 1] -= mu * v;
            }
            edge_zero[col] = held.zero(ray, c);
        }
        let total: f64 = r.iter().step_by(2).sum();
        if total <= 0.0 {
            return Err("a ray of the face has no pressure".into());
        }
        r.iter_mut().for_each(|v| *v /= total);
        let status = (0..m)
            .map(|i| match classes[i] {
                Class::Contact => match (edge_zero[2 * i], edge_zero[2 * i + 1]) {
                    (true, true) => NodeStatus::Grazing,
                    (true, false) => NodeStatus::SlipMinus,
                    (false, true) => NodeStatus::SlipPlus,
                    (false, false) => NodeStatus::Stick,
                },
                _ => {
                    if gap_row[i].is_some_and(|row| !held.zero(ray, row)) {
                        NodeStatus::Separated
                    } else {
                        NodeStatus::Grazing
                    }
                }
            })
            .collect();
        out.push(FaceRay { r, status });
    }
    Ok((
        out,
        FaceStats {
            dim: k,
            peak,
            close: false,
            least_share: share.iter().copied().fold(f64::INFINITY, f64::min),
        },
    ))
}

/// The rays a double description holds: each one's direction (`k` values) and zero set (a
/// bit per row, `words` words), in two flat arrays, so that a round allocates nothing per ray
/// (one `Vec` per direction and per zero set had been a fifth of a random m = 9 enumeration's
/// allocations).
struct Held {
    k: usize,
    words: usize,
    ys: Vec<f64>,
    zs: Vec<u64>,
}

impl Held {
    fn new(k: usize, rows: usize) -> Held {
        Held {
            k,
            words: rows.div_ceil(64),
            ys: Vec::new(),
            zs: Vec::new(),
        }
    }
    fn len(&self) -> usize {
        self.ys.len() / self.k
    }
    fn y(&self, j: usize) -> &[f64] {
        &self.ys[j * self.k..(j + 1) * self.k]
    }
    fn z(&self, j: usize) -> &[u64] {
        &self.zs[j * self.words..(j + 1) * self.words]
    }
    /// Whether ray `j` is tight on row `i`.
    fn zero(&self, j: usize, i: usize) -> bool {
        bit(self.z(j), i)
    }
    /// A new ray: `y` scaled to unit max-norm, zero on the rows of `z`.
    fn push(&mut self, y: impl Iterator<Item = f64>, z: impl Iterator<Item = u64>) {
        let from = self.ys.len();
        self.ys.extend(y);
        let y = &mut self.ys[from..];
        let s = y.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        if s > 0.0 {
            y.iter_mut().for_each(|x| *x /= s);
        }
        self.zs.extend(z);
    }
    /// The last ray made tight on row `i` too.
    fn tight_last(&mut self, i: usize) {
        let from = self.zs.len() - self.words;
        set_bit(&mut self.zs[from..], i);
    }
    fn clear(&mut self) {
        self.ys.clear();
        self.zs.clear();
    }
}

/// The size of `a & b`.
fn count_and(a: &[u64], b: &[u64]) -> usize {
    a.iter()
        .zip(b)
        .map(|(a, b)| (a & b).count_ones() as usize)
        .sum()
}

/// Whether `s` contains `a & b`.
fn contains_and(s: &[u64], a: &[u64], b: &[u64]) -> bool {
    s.iter()
        .zip(a.iter().zip(b))
        .all(|(s, (x, y))| s & x & y == x & y)
}

/// The extreme rays of the pointed, full-dimensional cone `{ y in R^k : rows y >= 0 }` (`rows`
/// row after row, `k` values each, scaled to unit max-norm), each scaled to unit max-norm and
/// with its zero set (a bit per row), and the most rays held at once.
fn double_description(rows: &[f64], k: usize, tol: f64) -> Result<(Held, usize), String> {
    let n = rows.len() / k;
    let row = |i: usize| &rows[i * k..(i + 1) * k];
    // k independent rows, greedily (modified Gram-Schmidt on unit rows).
    let mut chosen: Vec<usize> = Vec::with_capacity(k);
    let mut ortho: Vec<f64> = Vec::with_capacity(k * k);
    let mut v = vec![0.0; k];
    for i in 0..n {
        if chosen.len() == k {
            break;
        }
        let norm = row(i).iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            continue;
        }
        v.iter_mut().zip(row(i)).for_each(|(a, x)| *a = x / norm);
        for q in ortho.chunks_exact(k) {
            let d: f64 = v.iter().zip(q).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(q).for_each(|(a, b)| *a -= d * b);
        }
        let rest = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rest > 1e-7 {
            ortho.extend(v.iter().map(|x| x / rest));
            chosen.push(i);
        }
    }
    if chosen.len() < k {
        return Err(format!(
            "the face's inequalities have rank {} < its dimension {k}: not pointed",
            chosen.len()
        ));
    }
    let b0 = DMatrix::from_fn(k, k, |a, c| row(chosen[a])[c]);
    let inv = b0
        .try_inverse()
        .ok_or("the face's starting rows are singular")?;
    let mut starting = vec![false; n];
    chosen.iter().for_each(|&i| starting[i] = true);
    let mut rays = Held::new(k, n);
    let mut zero = vec![0u64; rays.words];
    chosen.iter().for_each(|&c| set_bit(&mut zero, c));
    for (j, &i) in chosen.iter().enumerate() {
        // Tight on every starting row but its own.
        let own = |(w, &x): (usize, &u64)| if w == i / 64 { x & !(1 << (i % 64)) } else { x };
        rays.push(
            (0..k).map(|a| inv[(a, j)]),
            zero.iter().enumerate().map(own),
        );
    }
    let mut peak = rays.len();
    let mut next = Held::new(k, n);
    let (mut values, mut plus, mut minus) = (Vec::new(), Vec::new(), Vec::new());
    for (i, &start) in starting.iter().enumerate() {
        // (The starting rows are in every ray's zero set already.)
        if start {
            continue;
        }
        let r = row(i);
        let row_max = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        values.clear();
        values.extend((0..rays.len()).map(|j| {
            let y = rays.y(j);
            let v: f64 = r.iter().zip(y).map(|(a, b)| a * b).sum();
            let s: f64 = r.iter().zip(y).map(|(a, b)| (a * b).abs()).sum();
            let size: f64 = y.iter().map(|x| x.abs()).sum();
            // Zero against its terms, or below the round-off floor of the row and the ray
            // whatever its terms, as the double description's `classify` judges: on uncoupled
            // bodies a ray of one body meets another body's row only in entries of order
            // 1e-17, whose sum had passed for a sign, and the pair made a "ray" spanning both.
            if v.abs() <= tol * s || v.abs() <= NOISE * row_max * size {
                0.0
            } else {
                v
            }
        }));
        plus.clear();
        plus.extend((0..rays.len()).filter(|&j| values[j] > 0.0));
        minus.clear();
        minus.extend((0..rays.len()).filter(|&j| values[j] < 0.0));
        // The rays kept (tight on row `i` where their value is zero), then the new ones.
        next.clear();
        for (j, &v) in values.iter().enumerate() {
            if v >= 0.0 {
                next.ys.extend_from_slice(rays.y(j));
                next.zs.extend_from_slice(rays.z(j));
                if v == 0.0 {
                    next.tight_last(i);
                }
            }
        }
        let kept = next.len();
        for &p in &plus {
            for &q in &minus {
                // The rows common to both, word by word (no set is built for a pair that is
                // not adjacent: most are not).
                let (zp, zq) = (rays.z(p), rays.z(q));
                if count_and(zp, zq) + 2 < k {
                    continue;
                }
                let adjacent =
                    !(0..rays.len()).any(|j| j != p && j != q && contains_and(rays.z(j), zp, zq));
                if !adjacent {
                    continue;
                }
                let (vp, vq) = (values[p], values[q]);
                let y = rays
                    .y(p)
                    .iter()
                    .zip(rays.y(q))
                    .map(|(a, b)| vp * b - vq * a);
                next.push(y, zp.iter().zip(zq).map(|(a, b)| a & b));
                next.tight_last(i);
            }
        }
        peak = peak.max(next.len() + minus.len());
        debug_assert!(next.len() >= kept);
        std::mem::swap(&mut rays, &mut next);
    }
    Ok((rays, peak))
}
