//! The extreme rays of one leaf's face, by double description in the face's own dimension.
//!
//! A leaf of the search fixes every node: contact (`u_n = 0`, friction edges `a_i, b_i >= 0`)
//! or separated (`r = 0`, `u_n >= 0`). Its face is a cone in the friction edges of the contact
//! nodes. The support program ([`ContactLp::support`]) tells which edges and which gaps some
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
    // Inequalities `B N y >= 0`: the edges (identity rows), then the gaps that open.
    let mut labels: Vec<Entry2> = cols.iter().map(|&c| Entry2::Edge(c)).collect();
    let mut b_rows: Vec<Vec<f64>> = (0..nv)
        .map(|c| basis.row(c).iter().copied().collect())
        .collect();
    let mut gaps: Vec<Vec<f64>> = Vec::new();
    for i in (0..m).filter(|&i| classes[i] == Class::Separated && positive(Entry2::Gap(i))) {
        let g = on_edges(form.gap_row(i), mu, &cols);
        let row: Vec<f64> = (0..k)
            .map(|j| (0..nv).map(|c| g[c] * basis[(c, j)]).sum())
            .collect();
        labels.push(Entry2::Gap(i));
        b_rows.push(row);
        gaps.push(g);
    }
    for row in &mut b_rows {
        let s = row.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        if s > 0.0 {
            row.iter_mut().for_each(|x| *x /= s);
        }
    }
    let (ys, zeros, peak) = double_description(&b_rows, k, tol)?;
    let mut out = Vec::with_capacity(ys.len());
    // Per inequality, the largest share of a ray's total pressure it reaches.
    let mut share = vec![0.0f64; nv + gaps.len()];
    for (y, z) in ys.iter().zip(&zeros) {
        let x: Vec<f64> = (0..nv)
            .map(|c| (0..k).map(|j| basis[(c, j)] * y[j]).sum())
            .collect();
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
        let mut edge_zero = vec![true; 2 * m];
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
            edge_zero[col] = z[c];
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
                    let open = labels
                        .iter()
                        .position(|&l| l == Entry2::Gap(i))
                        .is_some_and(|row| !z[row]);
                    if open {
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

/// A bit set over the rows.
#[derive(Clone, PartialEq, Eq)]
struct Bits(Vec<u64>);

impl Bits {
    fn new(n: usize) -> Bits {
        Bits(vec![0; n.div_ceil(64)])
    }
    fn set(&mut self, i: usize) {
        self.0[i / 64] |= 1 << (i % 64);
    }
    fn get(&self, i: usize) -> bool {
        self.0[i / 64] >> (i % 64) & 1 == 1
    }
    fn and(&self, other: &Bits) -> Bits {
        Bits(self.0.iter().zip(&other.0).map(|(a, b)| a & b).collect())
    }
    /// The size of `self & other`.
    fn count_and(&self, other: &Bits) -> usize {
        self.0
            .iter()
            .zip(&other.0)
            .map(|(a, b)| (a & b).count_ones() as usize)
            .sum()
    }
    /// Whether `self` contains `a & b`.
    fn contains_and(&self, a: &Bits, b: &Bits) -> bool {
        self.0
            .iter()
            .zip(a.0.iter().zip(&b.0))
            .all(|(s, (x, y))| s & x & y == x & y)
    }
}

/// The extreme rays of the pointed, full-dimensional cone `{ y in R^k : rows y >= 0 }` (rows
/// scaled to unit max-norm), each with its zero set (one flag per row), and the most rays held
/// at once.
#[allow(clippy::type_complexity)]
fn double_description(
    rows: &[Vec<f64>],
    k: usize,
    tol: f64,
) -> Result<(Vec<Vec<f64>>, Vec<Vec<bool>>, usize), String> {
    let n = rows.len();
    // k independent rows, greedily (modified Gram-Schmidt on unit rows).
    let mut chosen: Vec<usize> = Vec::with_capacity(k);
    let mut ortho: Vec<Vec<f64>> = Vec::with_capacity(k);
    for (i, row) in rows.iter().enumerate() {
        if chosen.len() == k {
            break;
        }
        let norm = row.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            continue;
        }
        let mut v: Vec<f64> = row.iter().map(|x| x / norm).collect();
        for q in &ortho {
            let d: f64 = v.iter().zip(q).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(q).for_each(|(a, b)| *a -= d * b);
        }
        let rest = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if rest > 1e-7 {
            v.iter_mut().for_each(|x| *x /= rest);
            ortho.push(v);
            chosen.push(i);
        }
    }
    if chosen.len() < k {
        return Err(format!(
            "the face's inequalities have rank {} < its dimension {k}: not pointed",
            chosen.len()
        ));
    }
    let b0 = DMatrix::from_fn(k, k, |a, c| rows[chosen[a]][c]);
    let inv = b0
        .try_inverse()
        .ok_or("the face's starting rows are singular")?;
    let mut done = vec![false; n];
    chosen.iter().for_each(|&i| done[i] = true);
    let mut rays: Vec<(Vec<f64>, Bits)> = (0..k)
        .map(|j| {
            let y: Vec<f64> = (0..k).map(|a| inv[(a, j)]).collect();
            let mut z = Bits::new(n);
            for (a, &i) in chosen.iter().enumerate() {
                if a != j {
                    z.set(i);
                }
            }
            (normalised(y), z)
        })
        .collect();
    let mut peak = rays.len();
    for (i, row) in rows.iter().enumerate() {
        if done[i] {
            continue;
        }
        let values: Vec<f64> = rays
            .iter()
            .map(|(y, _)| {
                let v: f64 = row.iter().zip(y).map(|(a, b)| a * b).sum();
                let s: f64 = row.iter().zip(y).map(|(a, b)| (a * b).abs()).sum();
                if v.abs() <= tol * s {
                    0.0
                } else {
                    v
                }
            })
            .collect();
        let plus: Vec<usize> = (0..rays.len()).filter(|&j| values[j] > 0.0).collect();
        let minus: Vec<usize> = (0..rays.len()).filter(|&j| values[j] < 0.0).collect();
        let mut new: Vec<(Vec<f64>, Bits)> = Vec::new();
        for &p in &plus {
            for &q in &minus {
                // The rows common to both, word by word (no set is built for a pair that is
                // not adjacent: most are not).
                let (zp, zq) = (&rays[p].1, &rays[q].1);
                if zp.count_and(zq) + 2 < k {
                    continue;
                }
                let adjacent = !rays
                    .iter()
                    .enumerate()
                    .any(|(j, (_, z))| j != p && j != q && z.contains_and(zp, zq));
                if !adjacent {
                    continue;
                }
                let common = zp.and(zq);
                let (vp, vq) = (values[p], values[q]);
                let y: Vec<f64> = rays[p]
                    .0
                    .iter()
                    .zip(&rays[q].0)
                    .map(|(a, b)| vp * b - vq * a)
                    .collect();
                let mut z = common;
                z.set(i);
                new.push((normalised(y), z));
            }
        }
        let kept: Vec<(Vec<f64>, Bits)> = rays
            .into_iter()
            .zip(&values)
            .filter(|(_, &v)| v >= 0.0)
            .map(|((y, mut z), &v)| {
                if v == 0.0 {
                    z.set(i);
                }
                (y, z)
            })
            .collect();
        peak = peak.max(kept.len() + new.len() + minus.len());
        rays = kept;
        rays.extend(new);
        done[i] = true;
    }
    let zeros = rays
        .iter()
        .map(|(_, z)| (0..n).map(|i| z.get(i)).collect())
        .collect();
    Ok((rays.into_iter().map(|(y, _)| y).collect(), zeros, peak))
}

/// `y` scaled to unit max-norm.
fn normalised(mut y: Vec<f64>) -> Vec<f64> {
    let s = y.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if s > 0.0 {
        y.iter_mut().for_each(|x| *x /= s);
    }
    y
}
