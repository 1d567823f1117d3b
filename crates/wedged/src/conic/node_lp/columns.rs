//! The program's columns (see [`super`]): each node's friction edges, the 3D outer polygon's
//! corners, and the map between a row over the reaction components and a row over the columns
//! ([`spread`], the factors' `expand`) and its transpose ([`gather`]).

/// Columns per node of the 3D program: the edges of a regular polygon's cone that holds the
/// friction cone (an outer relaxation, see the module docs). More sides make the relaxation
/// tighter (`1 / cos(pi / SIDES)` times `mu` at the corners) and each program wider. (Measured
/// on the 3D V-groove plug, m = 20, whole process: 6, 8, 12, 16, 24 sides, `critical` 1.8,
/// 1.6, 1.2, 2.3, 1.6 s, `enumerate` at 1.2 `mu*` 6.9, 6.7, 5.4, 9.0, 9.0 s; `BENCHMARKS.md`.)
pub(crate) const SIDES: usize = 12;

/// Columns per node: the friction cone's edges (2D: 2; 3D: [`SIDES`]).
pub(crate) fn per_node(dim: usize) -> usize {
    if dim == 2 {
        2
    } else {
        SIDES
    }
}

/// The 3D outer polygon's edges: each one's tangent direction times the corner radius per
/// unit `mu` (the polygon's sides touch the circle of radius `mu`). Computed once.
pub(super) fn corners() -> &'static [(f64, f64); SIDES] {
    static CORNERS: std::sync::OnceLock<[(f64, f64); SIDES]> = std::sync::OnceLock::new();
    CORNERS.get_or_init(|| {
        let step = std::f64::consts::PI / SIDES as f64;
        let radius = 1.0 / step.cos();
        std::array::from_fn(|j| {
            let angle = 2.0 * step * j as f64;
            (radius * angle.cos(), radius * angle.sin())
        })
    })
}

/// Writes `row` (over the `d m` reactions, then a floating body's amplitudes) into `out`, a
/// program's row over each node's friction edges ([`per_node`] of them) at `mu` and then the
/// amplitude columns (`amplitude(j)`: rigid mode `j`'s column, if it has one). Both
/// [`put_row`](super::put_row) and the simplex method's row products through the factors
/// ([`Reduced`](crate::conic::simplex::Reduced), at every pivot) call it, so the case is
/// settled once a row, not once a node.
pub(super) fn spread(
    (d, m, mu): (usize, usize, f64),
    amplitude: impl Fn(usize) -> Option<usize>,
    row: &[f64],
    out: &mut [f64],
) {
    let g = per_node(d);
    let reactions = d * m;
    let nodes = row[..reactions].chunks(d).zip(out.chunks_mut(g));
    match (d, mu.is_finite()) {
        (2, true) => nodes.for_each(|(w, o)| {
            o[0] = w[0] + mu * w[1];
            o[1] = w[0] - mu * w[1];
        }),
        (_, true) => {
            // Fixed sizes, so that the inner loop compiles for 12 columns (measured: 10% of
            // the V-groove plug's m = 30 enumeration with sizes known only at run time).
            let corners = corners();
            let nodes = row[..reactions]
                .chunks_exact(3)
                .zip(out.chunks_exact_mut(SIDES));
            for (w, o) in nodes {
                let (t1, t2) = (mu * w[1], mu * w[2]);
                for (o, &(c, s)) in o.iter_mut().zip(corners) {
                    *o = w[0] + c * t1 + s * t2;
                }
            }
        }
        // At mu = infinity: the columns are the reaction components (tangents free), the 3D
        // program's other columns unused (fixed at zero).
        (_, false) => nodes.for_each(|(w, o)| {
            o.iter_mut().for_each(|o| *o = 0.0);
            o[..w.len()].copy_from_slice(w);
        }),
    }
    for (j, &x) in row.get(reactions..).unwrap_or(&[]).iter().enumerate() {
        if let Some(c) = amplitude(j) {
            out[g * m + c] = x;
        }
    }
}

/// The transpose of [`spread`]: the columns' values `x` (each node's friction edges, then the
/// amplitude columns) gathered onto the reaction components and amplitudes, `w = X x`, so that
/// a row's activity is the factor row times `w`
/// ([`Reduced::gather`](crate::conic::simplex::Reduced::gather)).
pub(super) fn gather(
    (d, m, mu): (usize, usize, f64),
    amplitude: impl Fn(usize) -> Option<usize>,
    x: &[f64],
    w: &mut [f64],
) {
    let g = per_node(d);
    let reactions = d * m;
    let nodes = w[..reactions].chunks_mut(d).zip(x.chunks(g));
    match (d, mu.is_finite()) {
        (2, true) => nodes.for_each(|(w, e)| {
            w[0] = e[0] + e[1];
            w[1] = mu * (e[0] - e[1]);
        }),
        (_, true) => {
            let corners = corners();
            let nodes = w[..reactions]
                .chunks_exact_mut(3)
                .zip(x.chunks_exact(SIDES));
            for (w, e) in nodes {
                let (mut n, mut t1, mut t2) = (0.0, 0.0, 0.0);
                for (&v, &(c, s)) in e.iter().zip(corners) {
                    n += v;
                    t1 += c * v;
                    t2 += s * v;
                }
                w[0] = n;
                w[1] = mu * t1;
                w[2] = mu * t2;
            }
        }
        (_, false) => nodes.for_each(|(w, e)| w.copy_from_slice(&e[..w.len()])),
    }
    for (j, v) in w[reactions..].iter_mut().enumerate() {
        *v = amplitude(j).map_or(0.0, |c| x[g * m + c]);
    }
}
