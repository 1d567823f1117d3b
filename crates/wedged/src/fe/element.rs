//! Element stiffness matrices and centroid stresses: linear isotropic elasticity, small strain.
//!
//! Every element is isoparametric: reference coordinates `xi`, shape functions `N_a(xi)`, the
//! geometry `x(xi) = sum_a N_a(xi) x_a`. With the Jacobian `J_ij = dx_i/dxi_j` the physical
//! gradients are `grad_x N_a = J^{-T} grad_xi N_a` (computed as `cof(J) grad_xi N_a / det J`), the
//! strain is `eps = B u` with engineering shears, and
//!
//! ```text
//! K = sum_p  w_p |det J(xi_p)|  B(xi_p)^T D B(xi_p),      sigma = D B u.
//! ```
//!
//! | kind  | shape functions                                   | points                          |
//! |-------|---------------------------------------------------|---------------------------------|
//! | Tri3  | `1-r-s, r, s`                                     | `(1/3, 1/3)`, `w = 1/2`         |
//! | Quad4 | `(1 + r r_a)(1 + s s_a)/4`                        | `(±1/√3, ±1/√3)`, `w = 1`       |
//! | Tet4  | `1-r-s-t, r, s, t`                                | `(1/4, 1/4, 1/4)`, `w = 1/6`    |
//! | Hex8  | `(1 + r r_a)(1 + s s_a)(1 + t t_a)/8`             | `(±1/√3, ±1/√3, ±1/√3)`, `w = 1`|
//!
//! | Tri6  | corners `L(2L-1)`, mid-edge `4 L_a L_b` (`L` the barycentrics `1-r-s, r, s`) | `(1/6, 1/6)`, `(2/3, 1/6)`, `(1/6, 2/3)`, `w = 1/6` |
//! | Tet10 | the same with `1-r-s-t, r, s, t`                  | `(a, b, b)` and permutations, `a = (5 + 3√5)/20`, `b = (5 - √5)/20`, `w = 1/24` |
//! | Quad8 | corners `(1 + r r_a)(1 + s s_a)(r r_a + s s_a - 1)/4`, mid-edge `(1 - r²)(1 + s s_a)/2` or `(1 + r r_a)(1 - s²)/2` | 3x3 Gauss: `0, ±√(3/5)`, `w = 8/9, 5/9` each way |
//! | Quad9 | `l_a(r) l_a(s)`, `l` the quadratic Lagrange polynomials on `-1, 0, 1` | 3x3 Gauss |
//!
//! The triangle and the tetrahedron are constant strain (one point is exact); 2x2 (2x2x2) Gauss
//! integrates the bilinear (trilinear) element exactly when it is a parallelogram
//! (parallelepiped); the quadratic triangle's and tetrahedron's points integrate their (linear
//! strain) stiffness exactly when their edges are straight, and 3x3 Gauss the quadratic
//! quadrilaterals' when they are parallelograms. 2D elements have unit thickness and use `x, y` only, with `D` from
//! [`Material::d_matrix`] (plane strain or plane stress already in it).
//!
//! Voigt orders: 2D strain `[xx, yy, xy]`; 3D `[xx, yy, zz, yz, xz, xy]`. For node `a` with
//! gradient `(gx, gy, gz)`, the columns of `B` are
//!
//! ```text
//! 2D: [gx 0; 0 gy; gy gx]      3D: [gx 0 0; 0 gy 0; 0 0 gz; 0 gz gy; gz 0 gx; gy gx 0]
//! ```
//!
//! Validity: `det J` is evaluated at the integration points and the centroid, and (all but
//! Tri3 and Tet4, whose `J` is constant) at the corners. Every value negative (a mirrored element) is accepted and integrated
//! with `|det J|`; values of both signs, or a vanishing value at an integration point or the
//! centroid (`|det J| <= 1e-12 h^dim`, `h` the diagonal of the element's bounding box), are an
//! error. A corner where `det J` merely vanishes (a 180° angle, a collapsed edge) is tolerated.

use super::{ElementKind, Material};
use nalgebra::DMatrix;

/// Largest number of nodes of an element (Tet10).
const MAX_NODES: usize = 10;
/// Largest number of integration points (Quad8, Quad9).
const MAX_POINTS: usize = 9;
/// Largest number of dofs of an element.
const MAX_DOFS: usize = 3 * MAX_NODES;
/// Largest number of strain components.
const MAX_STRAINS: usize = 6;
/// The 2-point Gauss abscissa `1/sqrt(3)`.
const GP: f64 = 0.577_350_269_189_625_8;
/// The 3-point Gauss abscissa `sqrt(3/5)`.
const G3: f64 = 0.774_596_669_241_483_4;
/// Relative threshold below which `|det J|` counts as zero.
const DEGENERATE: f64 = 1e-12;

/// Quad4 reference nodes (Gmsh order).
const QUAD_CORNERS: [[f64; 3]; 4] = [
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];
/// Hex8 reference nodes (Gmsh order): bottom face, then top face.
const HEX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];
/// Tri6 reference corners (the Tri3's too).
const TRI_CORNERS: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// Tet10 reference corners.
const TET_CORNERS: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];
/// Quad8 and Quad9 reference nodes (Gmsh order): corners, mid-edges, centre.
const QUAD9_NODES: [[f64; 3]; 9] = [
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 0.0, 0.0],
];
const TRI_POINTS: [[f64; 3]; 1] = [[1.0 / 3.0, 1.0 / 3.0, 0.0]];
const TRI6_POINTS: [[f64; 3]; 3] = [
    [1.0 / 6.0, 1.0 / 6.0, 0.0],
    [2.0 / 3.0, 1.0 / 6.0, 0.0],
    [1.0 / 6.0, 2.0 / 3.0, 0.0],
];
/// `(5 + 3 sqrt 5) / 20` and `(5 - sqrt 5) / 20`: the 4-point rule of the tetrahedron.
const TA: f64 = 0.585_410_196_624_968_5;
const TB: f64 = 0.138_196_601_125_010_5;
const TET10_POINTS: [[f64; 3]; 4] = [[TB, TB, TB], [TA, TB, TB], [TB, TA, TB], [TB, TB, TA]];
const QUAD9_POINTS: [[f64; 3]; 9] = [
    [-G3, -G3, 0.0],
    [0.0, -G3, 0.0],
    [G3, -G3, 0.0],
    [-G3, 0.0, 0.0],
    [0.0, 0.0, 0.0],
    [G3, 0.0, 0.0],
    [-G3, G3, 0.0],
    [0.0, G3, 0.0],
    [G3, G3, 0.0],
];
const QUAD9_WEIGHTS: [f64; 9] = [
    25.0 / 81.0,
    40.0 / 81.0,
    25.0 / 81.0,
    40.0 / 81.0,
    64.0 / 81.0,
    40.0 / 81.0,
    25.0 / 81.0,
    40.0 / 81.0,
    25.0 / 81.0,
];
const TET_POINTS: [[f64; 3]; 1] = [[0.25, 0.25, 0.25]];
const QUAD_POINTS: [[f64; 3]; 4] = [
    [-GP, -GP, 0.0],
    [GP, -GP, 0.0],
    [GP, GP, 0.0],
    [-GP, GP, 0.0],
];
const HEX_POINTS: [[f64; 3]; 8] = [
    [-GP, -GP, -GP],
    [GP, -GP, -GP],
    [GP, GP, -GP],
    [-GP, GP, -GP],
    [-GP, -GP, GP],
    [GP, -GP, GP],
    [GP, GP, GP],
    [-GP, GP, GP],
];

/// The integration points of an element (reference coordinates) and their weights.
fn integration_points(kind: ElementKind) -> (&'static [[f64; 3]], &'static [f64]) {
    match kind {
        ElementKind::Tri3 => (&TRI_POINTS, &[0.5]),
        ElementKind::Quad4 => (&QUAD_POINTS, &[1.0; 4]),
        ElementKind::Tet4 => (&TET_POINTS, &[1.0 / 6.0]),
        ElementKind::Hex8 => (&HEX_POINTS, &[1.0; 8]),
        ElementKind::Tri6 => (&TRI6_POINTS, &[1.0 / 6.0; 3]),
        ElementKind::Tet10 => (&TET10_POINTS, &[1.0 / 24.0; 4]),
        ElementKind::Quad8 | ElementKind::Quad9 => (&QUAD9_POINTS, &QUAD9_WEIGHTS),
    }
}

/// The reference centroid.
fn centroid(kind: ElementKind) -> [f64; 3] {
    match kind.linear() {
        ElementKind::Tri3 => TRI_POINTS[0],
        ElementKind::Tet4 => TET_POINTS[0],
        _ => [0.0; 3],
    }
}

/// The barycentric coordinates of a simplex's reference point, with their gradients.
fn barycentric(dim: usize, xi: [f64; 3]) -> ([f64; 4], [[f64; 3]; 4]) {
    let l0 = 1.0 - xi[..dim].iter().sum::<f64>();
    let mut l = [l0, xi[0], xi[1], 0.0];
    let mut g = [
        [-1.0, -1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0; 3],
    ];
    if dim == 3 {
        l[3] = xi[2];
        g = [
            [-1.0, -1.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
    }
    (l, g)
}

/// The quadratic Lagrange polynomial on `-1, 0, 1` that is 1 at `at` and its derivative, at `x`.
fn lagrange(at: f64, x: f64) -> (f64, f64) {
    if at == 0.0 {
        (1.0 - x * x, -2.0 * x)
    } else {
        (0.5 * x * (x + at), x + 0.5 * at)
    }
}

/// Gradients of the shape functions in reference coordinates at `xi`: `g[a][j] = dN_a/dxi_j`.
fn reference_gradients(kind: ElementKind, xi: [f64; 3]) -> [[f64; 3]; MAX_NODES] {
    let mut g = [[0.0; 3]; MAX_NODES];
    match kind {
        ElementKind::Tri3 => {
            g[0] = [-1.0, -1.0, 0.0];
            g[1] = [1.0, 0.0, 0.0];
            g[2] = [0.0, 1.0, 0.0];
        }
        ElementKind::Tet4 => {
            g[0] = [-1.0, -1.0, -1.0];
            g[1] = [1.0, 0.0, 0.0];
            g[2] = [0.0, 1.0, 0.0];
            g[3] = [0.0, 0.0, 1.0];
        }
        ElementKind::Quad4 => {
            // N_a = (1 + r r_a)(1 + s s_a) / 4.
            for (ga, c) in g.iter_mut().zip(&QUAD_CORNERS) {
                let f = [1.0 + xi[0] * c[0], 1.0 + xi[1] * c[1]];
                *ga = [c[0] * f[1] / 4.0, c[1] * f[0] / 4.0, 0.0];
            }
        }
        ElementKind::Tri6 | ElementKind::Tet10 => {
            // Corners L_a (2 L_a - 1), mid-edge nodes 4 L_a L_b.
            let dim = kind.dim();
            let (l, gl) = barycentric(dim, xi);
            for a in 0..=dim {
                g[a] = gl[a].map(|d| (4.0 * l[a] - 1.0) * d);
            }
            for (ga, &[a, b]) in g[dim + 1..].iter_mut().zip(kind.mid_edges()) {
                for j in 0..3 {
                    ga[j] = 4.0 * (gl[a][j] * l[b] + l[a] * gl[b][j]);
                }
            }
        }
        ElementKind::Quad8 => {
            for (ga, c) in g.iter_mut().zip(&QUAD9_NODES[..8]) {
                let (r, s) = (xi[0], xi[1]);
                *ga = if c[0] != 0.0 && c[1] != 0.0 {
                    // (1 + r r_a)(1 + s s_a)(r r_a + s s_a - 1) / 4.
                    let (fr, fs) = (1.0 + r * c[0], 1.0 + s * c[1]);
                    let q = r * c[0] + s * c[1] - 1.0;
                    [c[0] * fs * (q + fr) / 4.0, c[1] * fr * (q + fs) / 4.0, 0.0]
                } else if c[0] == 0.0 {
                    // (1 - r^2)(1 + s s_a) / 2.
                    [-r * (1.0 + s * c[1]), c[1] * (1.0 - r * r) / 2.0, 0.0]
                } else {
                    // (1 + r r_a)(1 - s^2) / 2.
                    [c[0] * (1.0 - s * s) / 2.0, -s * (1.0 + r * c[0]), 0.0]
                };
            }
        }
        ElementKind::Quad9 => {
            for (ga, c) in g.iter_mut().zip(&QUAD9_NODES) {
                let ((lr, dr), (ls, ds)) = (lagrange(c[0], xi[0]), lagrange(c[1], xi[1]));
                *ga = [dr * ls, lr * ds, 0.0];
            }
        }
        ElementKind::Hex8 => {
            // N_a = (1 + r r_a)(1 + s s_a)(1 + t t_a) / 8.
            for (ga, c) in g.iter_mut().zip(&HEX_CORNERS) {
                let f = [1.0 + xi[0] * c[0], 1.0 + xi[1] * c[1], 1.0 + xi[2] * c[2]];
                *ga = [
                    c[0] * f[1] * f[2] / 8.0,
                    c[1] * f[0] * f[2] / 8.0,
                    c[2] * f[0] * f[1] / 8.0,
                ];
            }
        }
    }
    g
}

/// The geometric map evaluated at one reference point.
#[derive(Debug, Clone, Copy)]
struct Mapped {
    /// Physical gradients `grad[a] = grad_x N_a` (`z` component 0 in 2D).
    grad: [[f64; 3]; MAX_NODES],
    /// `det J` (signed).
    det: f64,
}

/// Maps reference point `xi` of an element with `x.len() == kind.node_count()` nodes: `J`, its
/// determinant, and `grad_x N_a = cof(J) grad_xi N_a / det J` (`J^{-T} = cof(J) / det J`). When
/// `det J` is zero the gradients are not finite; the callers check `det` first.
fn map_point(kind: ElementKind, x: &[[f64; 3]], xi: [f64; 3]) -> Mapped {
    let dim = kind.dim();
    let g = reference_gradients(kind, xi);
    // J_ij = sum_a x_a[i] g_a[j].
    let mut j = [[0.0; 3]; 3];
    for (xa, ga) in x.iter().zip(&g) {
        for (row, &xai) in j.iter_mut().zip(xa).take(dim) {
            for (jij, &gaj) in row.iter_mut().zip(ga).take(dim) {
                *jij += xai * gaj;
            }
        }
    }
    let (det, cof) = if dim == 2 {
        (
            j[0][0] * j[1][1] - j[0][1] * j[1][0],
            [[j[1][1], -j[1][0], 0.0], [-j[0][1], j[0][0], 0.0], [0.0; 3]],
        )
    } else {
        let mut cof = [[0.0; 3]; 3];
        for (i, row) in cof.iter_mut().enumerate() {
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            for (k, c) in row.iter_mut().enumerate() {
                let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
                *c = j[i1][k1] * j[i2][k2] - j[i1][k2] * j[i2][k1];
            }
        }
        let det = j[0][0] * cof[0][0] + j[0][1] * cof[0][1] + j[0][2] * cof[0][2];
        (det, cof)
    };
    let mut grad = [[0.0; 3]; MAX_NODES];
    for (gx, gr) in grad.iter_mut().zip(&g).take(x.len()) {
        for (gxi, c) in gx.iter_mut().zip(&cof) {
            *gxi = (c[0] * gr[0] + c[1] * gr[1] + c[2] * gr[2]) / det;
        }
    }
    Mapped { grad, det }
}

/// An element checked and mapped at its integration points and centroid.
struct Prepared {
    /// The mapping at each integration point (the first `count`).
    points: [Mapped; MAX_POINTS],
    /// Number of integration points.
    count: usize,
    /// Integration weight times `|det J|` at each point.
    weights: [f64; MAX_POINTS],
    /// The mapping at the centroid.
    centroid: Mapped,
}

/// Checks the number and finiteness of the coordinates and the sign of `det J`, and maps the
/// integration points and the centroid.
fn prepare(kind: ElementKind, x: &[[f64; 3]]) -> Result<Prepared, String> {
    let (n, dim) = (kind.node_count(), kind.dim());
    if x.len() != n {
        return Err(format!(
            "a {} needs {n} node coordinates, got {}",
            kind.name(),
            x.len()
        ));
    }
    if let Some(v) = x.iter().flat_map(|xa| &xa[..dim]).find(|v| !v.is_finite()) {
        return Err(format!("non-finite node coordinate {v}"));
    }
    // Size: diagonal of the bounding box.
    let size = (0..dim)
        .map(|k| {
            let (lo, hi) = x
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), xa| {
                    (lo.min(xa[k]), hi.max(xa[k]))
                });
            (hi - lo).powi(2)
        })
        .sum::<f64>()
        .sqrt();
    let tol = DEGENERATE * size.powi(dim as i32);

    let (xis, w) = integration_points(kind);
    let mut points = [Mapped {
        grad: [[0.0; 3]; MAX_NODES],
        det: 0.0,
    }; MAX_POINTS];
    for (p, &xi) in points.iter_mut().zip(xis) {
        *p = map_point(kind, x, xi);
    }
    let points_used = &points[..xis.len()];
    let centroid = map_point(kind, x, centroid(kind));
    let corners: &[[f64; 3]] = match kind {
        ElementKind::Quad4 | ElementKind::Quad8 | ElementKind::Quad9 => &QUAD_CORNERS,
        ElementKind::Hex8 => &HEX_CORNERS,
        ElementKind::Tri6 => &TRI_CORNERS,
        ElementKind::Tet10 => &TET_CORNERS,
        ElementKind::Tri3 | ElementKind::Tet4 => &[],
    };
    let corner_dets = corners.iter().map(|&xi| map_point(kind, x, xi).det);
    let all_dets = points_used
        .iter()
        .map(|p| p.det)
        .chain([centroid.det])
        .chain(corner_dets);
    let (lo, hi) = all_dets.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
        (lo.min(d), hi.max(d))
    });
    if lo < -tol && hi > tol {
        return Err(format!(
            "Jacobian changes sign (det J from {lo:.3e} to {hi:.3e})"
        ));
    }
    // NaN: coordinates so large that `det J` overflows.
    if let Some(bad) = points_used
        .iter()
        .chain([&centroid])
        .find(|p| p.det.is_nan() || p.det.abs() <= tol)
    {
        let what = if dim == 2 { "area" } else { "volume" };
        return Err(format!(
            "zero {what} (det J = {:.3e}, element size {size:.3e})",
            bad.det
        ));
    }
    let mut weights = [0.0; MAX_POINTS];
    for ((wp, p), w) in weights.iter_mut().zip(points_used).zip(w) {
        *wp = w * p.det.abs();
    }
    Ok(Prepared {
        points,
        count: xis.len(),
        weights,
        centroid,
    })
}

/// The strain-displacement matrix `B` (rows: Voigt strains, columns: node-major dofs) from the
/// physical gradients of `n` nodes. Only the first `3` (2D) or `6` (3D) rows and `n*dim` columns
/// are set.
fn b_matrix(dim: usize, n: usize, grad: &[[f64; 3]; MAX_NODES]) -> [[f64; MAX_DOFS]; MAX_STRAINS] {
    let mut b = [[0.0; MAX_DOFS]; MAX_STRAINS];
    for (a, &[gx, gy, gz]) in grad.iter().enumerate().take(n) {
        let c = dim * a;
        if dim == 2 {
            b[0][c] = gx;
            b[1][c + 1] = gy;
            b[2][c] = gy;
            b[2][c + 1] = gx;
        } else {
            b[0][c] = gx;
            b[1][c + 1] = gy;
            b[2][c + 2] = gz;
            b[3][c + 1] = gz;
            b[3][c + 2] = gy;
            b[4][c] = gz;
            b[4][c + 2] = gx;
            b[5][c] = gy;
            b[5][c + 1] = gx;
        }
    }
    b
}

/// The number of Voigt strain components in `dim` dimensions.
fn strain_count(dim: usize) -> usize {
    if dim == 2 {
        3
    } else {
        6
    }
}

/// The stiffness matrix of one element, `(n*dim) x (n*dim)`, dofs node-major in the element's
/// node order: `K = sum_p w_p |det J_p| B_p^T D B_p` over the integration points (see the module
/// documentation). `Err` carries a one-line reason for a degenerate or inverted element or a
/// wrong number of coordinates.
pub fn stiffness(
    kind: ElementKind,
    x: &[[f64; 3]],
    material: &Material,
) -> Result<DMatrix<f64>, String> {
    let prepared = prepare(kind, x)?;
    let (n, dim) = (kind.node_count(), kind.dim());
    let (ns, nd) = (strain_count(dim), n * dim);
    let d = material.d_matrix(dim);
    let mut k = [[0.0; MAX_DOFS]; MAX_DOFS];
    let points = prepared.points.iter().zip(&prepared.weights);
    for (p, &w) in points.take(prepared.count) {
        let b = b_matrix(dim, n, &p.grad);
        // db = w D B
        let mut db = [[0.0; MAX_DOFS]; MAX_STRAINS];
        for (r, dbr) in db.iter_mut().enumerate().take(ns) {
            for (s, bs) in b.iter().enumerate().take(ns) {
                let drs = w * d[(r, s)];
                if drs != 0.0 {
                    for (v, &bsc) in dbr.iter_mut().zip(bs).take(nd) {
                        *v += drs * bsc;
                    }
                }
            }
        }
        // K += B^T (w D B), upper triangle.
        for i in 0..nd {
            for (j, kij) in k[i].iter_mut().enumerate().take(nd).skip(i) {
                *kij += (0..ns).map(|r| b[r][i] * db[r][j]).sum::<f64>();
            }
        }
    }
    Ok(DMatrix::from_fn(nd, nd, |i, j| {
        if i <= j {
            k[i][j]
        } else {
            k[j][i]
        }
    }))
}

/// The stress at the element's centroid (reference point `(1/3, 1/3)`, `0`, `(1/4, 1/4, 1/4)` or
/// `0`), Voigt `[xx, yy, zz, yz, xz, xy]`, for element displacements `u` (node-major, `dim` per
/// node): `sigma = D B(centroid) u`. In 2D `zz` is [`Material::sigma_zz`] of the in-plane
/// stresses and `yz = xz = 0`.
pub fn centroid_stress(
    kind: ElementKind,
    x: &[[f64; 3]],
    material: &Material,
    u: &[f64],
) -> Result<[f64; 6], String> {
    let (n, dim) = (kind.node_count(), kind.dim());
    let (ns, nd) = (strain_count(dim), n * dim);
    if u.len() != nd {
        return Err(format!(
            "a {} needs {nd} displacement components, got {}",
            kind.name(),
            u.len()
        ));
    }
    let prepared = prepare(kind, x)?;
    let b = b_matrix(dim, n, &prepared.centroid.grad);
    let mut eps = [0.0; MAX_STRAINS];
    for (e, br) in eps.iter_mut().zip(&b).take(ns) {
        *e = br.iter().zip(u).map(|(b, u)| b * u).sum();
    }
    let d = material.d_matrix(dim);
    let mut s = [0.0; MAX_STRAINS];
    for (r, sr) in s.iter_mut().enumerate().take(ns) {
        *sr = (0..ns).map(|c| d[(r, c)] * eps[c]).sum();
    }
    Ok(if dim == 2 {
        [s[0], s[1], material.sigma_zz(s[0], s[1]), 0.0, 0.0, s[2]]
    } else {
        s
    })
}

#[cfg(test)]
mod tests;
