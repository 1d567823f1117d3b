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
//! The triangle and the tetrahedron are constant strain (one point is exact); 2x2 (2x2x2) Gauss
//! integrates the bilinear (trilinear) element exactly when it is a parallelogram
//! (parallelepiped). 2D elements have unit thickness and use `x, y` only, with `D` from
//! [`Material::d_matrix`] (plane strain or plane stress already in it).
//!
//! Voigt orders: 2D strain `[xx, yy, xy]`; 3D `[xx, yy, zz, yz, xz, xy]`. For node `a` with
//! gradient `(gx, gy, gz)`, the columns of `B` are
//!
//! ```text
//! 2D: [gx 0; 0 gy; gy gx]      3D: [gx 0 0; 0 gy 0; 0 0 gz; 0 gz gy; gz 0 gx; gy gx 0]
//! ```
//!
//! Validity: `det J` is evaluated at the integration points and, for Quad4 and Hex8, also at the
//! corners and the centroid. Every value negative (a mirrored element) is accepted and integrated
//! with `|det J|`; values of both signs, or a vanishing value at an integration point or the
//! centroid (`|det J| <= 1e-12 h^dim`, `h` the diagonal of the element's bounding box), are an
//! error. A corner where `det J` merely vanishes (a 180° angle, a collapsed edge) is tolerated.

use super::{ElementKind, Material};
use nalgebra::DMatrix;

/// Largest number of nodes of an element (Hex8).
const MAX_NODES: usize = 8;
/// Largest number of integration points (Hex8).
const MAX_POINTS: usize = 8;
/// Largest number of dofs of an element.
const MAX_DOFS: usize = 3 * MAX_NODES;
/// Largest number of strain components.
const MAX_STRAINS: usize = 6;
/// The 2-point Gauss abscissa `1/sqrt(3)`.
const GP: f64 = 0.577_350_269_189_625_8;
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
const TRI_POINTS: [[f64; 3]; 1] = [[1.0 / 3.0, 1.0 / 3.0, 0.0]];
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

/// The integration points of an element (reference coordinates) and their common weight.
fn integration_points(kind: ElementKind) -> (&'static [[f64; 3]], f64) {
    match kind {
        ElementKind::Tri3 => (&TRI_POINTS, 0.5),
        ElementKind::Quad4 => (&QUAD_POINTS, 1.0),
        ElementKind::Tet4 => (&TET_POINTS, 1.0 / 6.0),
        ElementKind::Hex8 => (&HEX_POINTS, 1.0),
    }
}

/// The reference centroid.
fn centroid(kind: ElementKind) -> [f64; 3] {
    match kind {
        ElementKind::Tri3 => TRI_POINTS[0],
        ElementKind::Tet4 => TET_POINTS[0],
        ElementKind::Quad4 | ElementKind::Hex8 => [0.0; 3],
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
        ElementKind::Quad4 => &QUAD_CORNERS,
        ElementKind::Hex8 => &HEX_CORNERS,
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
    for (wp, p) in weights.iter_mut().zip(points_used) {
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
mod tests {
    //! Hand computations of single elements, and rejected inputs. Properties on random
    //! distorted elements and patch tests are in `tests/elements.rs`.

    use super::*;
    use crate::fe::Plane;

    const TRI: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    const SQUARE: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    const TET: [[f64; 3]; 4] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    const CUBE: [[f64; 3]; 8] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];

    fn material(young: f64, poisson: f64, plane: Plane) -> Material {
        Material::new(young, poisson, plane).unwrap()
    }

    fn assert_matrix_close(got: &DMatrix<f64>, want: &DMatrix<f64>, rel: f64) {
        assert_eq!(got.shape(), want.shape());
        let scale = want.amax();
        let err = (got - want).amax();
        assert!(
            err <= rel * scale,
            "error {err:e} (scale {scale:e})\ngot {got}\nwant {want}"
        );
    }

    /// `lambda'` of the in-plane (2D) or 3D isotropic law `sigma = lambda' tr(eps) I + 2 G eps`:
    /// plane strain and 3D use Lamé's `lambda`; plane stress `2 lambda G / (lambda + 2 G)`
    /// (so that `lambda' + 2G = E/(1-nu^2)`, `lambda' = E nu/(1-nu^2)`).
    fn lambda_eff(m: &Material, dim: usize) -> f64 {
        let (lambda, g) = m.lame();
        if dim == 2 && m.plane() == Plane::Stress {
            2.0 * lambda * g / (lambda + 2.0 * g)
        } else {
            lambda
        }
    }

    /// The isotropic stiffness from the gradient integrals
    /// `I[a][b][i][j] = integral of dN_a/dx_i dN_b/dx_j`:
    /// `K_(a i)(b j) = lambda' I_abij + G (delta_ij sum_k I_abkk + I_abji)`,
    /// which is `B_a^T D B_b` written out for isotropic `D`.
    fn isotropic_stiffness(
        dim: usize,
        n: usize,
        m: &Material,
        integral: impl Fn(usize, usize, usize, usize) -> f64,
    ) -> DMatrix<f64> {
        let (lambda, g) = (lambda_eff(m, dim), m.lame().1);
        DMatrix::from_fn(n * dim, n * dim, |r, c| {
            let (a, i, b, j) = (r / dim, r % dim, c / dim, c % dim);
            let trace: f64 = if i == j {
                (0..dim).map(|k| integral(a, b, k, k)).sum()
            } else {
                0.0
            };
            lambda * integral(a, b, i, j) + g * (trace + integral(a, b, j, i))
        })
    }

    /// `I[a][b][i][j]` for the unit square or cube `[0,1]^dim` with (bi/tri)linear shape
    /// functions. Node `a` at corner `c_a in {0,1}^dim` has `N_a = prod_k phi_ak(x_k)`,
    /// `phi = x` if `c = 1` else `1 - x`, `phi' = s = +-1`. With `int phi = 1/2`,
    /// `int phi_a phi_b = 1/3` (same corner coordinate) or `1/6` (different):
    /// - `i == j`: `s_ai s_bi prod_{k != i} int phi_ak phi_bk`;
    /// - `i != j`: `s_ai s_bj (int phi_aj)(int phi_bi) prod_{k != i,j} int phi_ak phi_bk`
    ///   `= s_ai s_bj / 4 prod_{k != i,j} ...`.
    fn box_integral(
        corners: &[[f64; 3]],
        dim: usize,
        a: usize,
        b: usize,
        i: usize,
        j: usize,
    ) -> f64 {
        let c = |node: usize, k: usize| corners[node][k];
        let s = |node: usize, k: usize| if c(node, k) == 1.0 { 1.0 } else { -1.0 };
        let m = |k: usize| {
            if c(a, k) == c(b, k) {
                1.0 / 3.0
            } else {
                1.0 / 6.0
            }
        };
        let rest: f64 = (0..dim).filter(|&k| k != i && k != j).map(m).product();
        if i == j {
            s(a, i) * s(b, i) * rest
        } else {
            s(a, i) * s(b, j) / 4.0 * rest
        }
    }

    #[test]
    fn tri3_unit_right_triangle_by_hand() {
        // Gradients: N0 = 1-x-y -> (-1,-1), N1 = x -> (1,0), N2 = y -> (0,1); area 1/2.
        // E = 1, nu = 0, plane strain: D = diag(1, 1, 1/2). Rows of B (dofs u0x u0y u1x u1y
        // u2x u2y): xx = [-1 0 1 0 0 0], yy = [0 -1 0 0 0 1], xy = [-1 -1 0 1 1 0].
        // K = 1/2 (xx^T xx + yy^T yy + 1/2 xy^T xy):
        #[rustfmt::skip]
        let want = DMatrix::from_row_slice(6, 6, &[
             0.75,  0.25, -0.5,  -0.25, -0.25,  0.0,
             0.25,  0.75,  0.0,  -0.25, -0.25, -0.5,
            -0.5,   0.0,   0.5,   0.0,   0.0,   0.0,
            -0.25, -0.25,  0.0,   0.25,  0.25,  0.0,
            -0.25, -0.25,  0.0,   0.25,  0.25,  0.0,
             0.0,  -0.5,   0.0,   0.0,   0.0,   0.5,
        ]);
        let k = stiffness(ElementKind::Tri3, &TRI, &material(1.0, 0.0, Plane::Strain)).unwrap();
        assert_matrix_close(&k, &want, 1e-15);

        // General D (d11, d12, d33) with gradients (b_a, c_a):
        // K_ab = A [d11 b_a b_b + d33 c_a c_b,  d12 b_a c_b + d33 c_a b_b;
        //           d12 c_a b_b + d33 b_a c_b,  d11 c_a c_b + d33 b_a b_b].
        let (bx, cy) = ([-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]);
        for plane in [Plane::Strain, Plane::Stress] {
            let m = material(3.0, 0.3, plane);
            let d = m.d_matrix(2);
            let (d11, d12, d33) = (d[(0, 0)], d[(0, 1)], d[(2, 2)]);
            let want = DMatrix::from_fn(6, 6, |r, c| {
                let (a, i, b, j) = (r / 2, r % 2, c / 2, c % 2);
                0.5 * match (i, j) {
                    (0, 0) => d11 * bx[a] * bx[b] + d33 * cy[a] * cy[b],
                    (0, 1) => d12 * bx[a] * cy[b] + d33 * cy[a] * bx[b],
                    (1, 0) => d12 * cy[a] * bx[b] + d33 * bx[a] * cy[b],
                    _ => d11 * cy[a] * cy[b] + d33 * bx[a] * bx[b],
                }
            });
            let k = stiffness(ElementKind::Tri3, &TRI, &m).unwrap();
            assert_matrix_close(&k, &want, 1e-14);
        }
    }

    #[test]
    fn quad4_unit_square_by_hand() {
        // The classical plane-stress stiffness of the bilinear square (any size, unit
        // thickness), as in Andreassen et al.'s "88-line topology optimisation code", in the
        // node order (0,0), (1,0), (1,1), (0,1): K = E/(1-nu^2) [k_(perm)] with
        // k1 = 1/2 - nu/6, k2 = 1/8 + nu/8, k3 = -1/4 - nu/12, k4 = -1/8 + 3nu/8,
        // k5 = -1/4 + nu/12, k6 = -1/8 - nu/8, k7 = nu/6, k8 = 1/8 - 3nu/8.
        // (Row 0 checked by hand with the integrals of `box_integral`, e.g.
        // K_00 = c (1/3 + (1-nu)/2 1/3) = c (1/2 - nu/6).)
        for (young, nu) in [(1.0, 0.0), (2.0, 0.3), (7.0, -0.4)] {
            let c = young / (1.0 - nu * nu);
            let k = [
                0.5 - nu / 6.0,
                0.125 + nu / 8.0,
                -0.25 - nu / 12.0,
                -0.125 + 3.0 * nu / 8.0,
                -0.25 + nu / 12.0,
                -0.125 - nu / 8.0,
                nu / 6.0,
                0.125 - 3.0 * nu / 8.0,
            ];
            #[rustfmt::skip]
            let pattern: [[usize; 8]; 8] = [
                [1, 2, 3, 4, 5, 6, 7, 8],
                [2, 1, 8, 7, 6, 5, 4, 3],
                [3, 8, 1, 6, 7, 4, 5, 2],
                [4, 7, 6, 1, 8, 3, 2, 5],
                [5, 6, 7, 8, 1, 2, 3, 4],
                [6, 5, 4, 3, 2, 1, 8, 7],
                [7, 4, 5, 2, 3, 8, 1, 6],
                [8, 3, 2, 5, 4, 7, 6, 1],
            ];
            let want = DMatrix::from_fn(8, 8, |r, s| c * k[pattern[r][s] - 1]);
            let m = material(young, nu, Plane::Stress);
            let got = stiffness(ElementKind::Quad4, &SQUARE, &m).unwrap();
            assert_matrix_close(&got, &want, 1e-14);
            // In 2D the square's stiffness does not depend on its size.
            let big: Vec<[f64; 3]> = SQUARE
                .iter()
                .map(|p| [3.0 * p[0], 3.0 * p[1], 0.0])
                .collect();
            assert_matrix_close(
                &stiffness(ElementKind::Quad4, &big, &m).unwrap(),
                &want,
                1e-14,
            );
        }
        // Plane strain (and stress) from the exact integrals of the gradient products.
        for plane in [Plane::Strain, Plane::Stress] {
            let m = material(5.0, 0.35, plane);
            let want =
                isotropic_stiffness(2, 4, &m, |a, b, i, j| box_integral(&SQUARE, 2, a, b, i, j));
            let got = stiffness(ElementKind::Quad4, &SQUARE, &m).unwrap();
            assert_matrix_close(&got, &want, 1e-14);
        }
    }

    #[test]
    fn tet4_unit_corner_by_hand() {
        // Gradients g0 = (-1,-1,-1), g1 = (1,0,0), g2 = (0,1,0), g3 = (0,0,1); volume 1/6.
        // Rows [xx yy zz yz xz xy]; a node's columns are [gx 0 0; 0 gy 0; 0 0 gz; 0 gz gy;
        // gz 0 gx; gy gx 0].
        #[rustfmt::skip]
        let b = DMatrix::from_row_slice(6, 12, &[
            -1.0,  0.0,  0.0,   1.0, 0.0, 0.0,   0.0, 0.0, 0.0,   0.0, 0.0, 0.0,
             0.0, -1.0,  0.0,   0.0, 0.0, 0.0,   0.0, 1.0, 0.0,   0.0, 0.0, 0.0,
             0.0,  0.0, -1.0,   0.0, 0.0, 0.0,   0.0, 0.0, 0.0,   0.0, 0.0, 1.0,
             0.0, -1.0, -1.0,   0.0, 0.0, 0.0,   0.0, 0.0, 1.0,   0.0, 1.0, 0.0,
            -1.0,  0.0, -1.0,   0.0, 0.0, 1.0,   0.0, 0.0, 0.0,   1.0, 0.0, 0.0,
            -1.0, -1.0,  0.0,   0.0, 1.0, 0.0,   1.0, 0.0, 0.0,   0.0, 0.0, 0.0,
        ]);
        let m = material(1.0, 0.25, Plane::Strain);
        let want = b.transpose() * m.d_matrix(3) * &b / 6.0;
        let k = stiffness(ElementKind::Tet4, &TET, &m).unwrap();
        assert_matrix_close(&k, &want, 1e-15);
        // E = 1, nu = 1/4: lambda = G = 2/5. K_ab = V [lambda g_a g_b^T + G (g_a.g_b) I + G g_b g_a^T].
        // K_(0x)(0x) = (lambda + 3G + G)/6 = 1/3; K_(0x)(0y) = (lambda + G)/6 = 2/15;
        // K_(1x)(1x) = (lambda + 2G)/6 = 1/5; K_(1y)(1y) = G/6 = 1/15;
        // K_(1x)(2y) = lambda/6 = 1/15; K_(1y)(2x) = G/6 = 1/15; K_(1x)(2x) = 0.
        let close = |r: usize, c: usize, v: f64| {
            assert!(
                (k[(r, c)] - v).abs() < 1e-15,
                "K[{r},{c}] = {} != {v}",
                k[(r, c)]
            );
        };
        close(0, 0, 1.0 / 3.0);
        close(0, 1, 2.0 / 15.0);
        close(3, 3, 0.2);
        close(4, 4, 1.0 / 15.0);
        close(3, 7, 1.0 / 15.0);
        close(4, 6, 1.0 / 15.0);
        close(3, 6, 0.0);
        let grads = [
            [-1.0, -1.0, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let m = material(4.0, 0.3, Plane::Strain);
        let want = isotropic_stiffness(3, 4, &m, |a, b, i, j| grads[a][i] * grads[b][j] / 6.0);
        assert_matrix_close(
            &stiffness(ElementKind::Tet4, &TET, &m).unwrap(),
            &want,
            1e-15,
        );
    }

    #[test]
    fn hex8_unit_cube_by_hand() {
        // On the unit cube every integrand dN_a/dx_i dN_b/dx_j is a polynomial of degree <= 2 in
        // each coordinate, so 2x2x2 Gauss (exact to degree 3) gives the exact integrals of
        // `box_integral`. E = 1, nu = 0: lambda = 0, G = 1/2.
        // K_(0x)(0x) = int (E N0x^2 + G N0y^2 + G N0z^2) = 1/9 + 1/18 + 1/18 = 2/9;
        // K_(0x)(0y) = (lambda + G) int N0x N0y = 1/2 (1/4)(1/3) = 1/24;
        // node 6 is opposite node 0: int N0x N6x = -(1/6)^2 = -1/36 and likewise for y, z, so
        // K_(0x)(6x) = -(1 + 1/2 + 1/2)/36 = -1/18; K_(0x)(6y) = (lambda + G) (-1)(1)/4 (1/6)
        // = -1/48.
        let k = stiffness(ElementKind::Hex8, &CUBE, &material(1.0, 0.0, Plane::Strain)).unwrap();
        let close = |r: usize, c: usize, v: f64| {
            assert!(
                (k[(r, c)] - v).abs() < 1e-15,
                "K[{r},{c}] = {} != {v}",
                k[(r, c)]
            );
        };
        close(0, 0, 2.0 / 9.0);
        close(0, 1, 1.0 / 24.0);
        close(0, 18, -1.0 / 18.0);
        close(0, 19, -1.0 / 48.0);
        for dof in 0..24 {
            close(dof, dof, 2.0 / 9.0);
        }
        for (young, nu) in [(1.0, 0.0), (2.5, 0.3), (1.0, 0.49), (3.0, -0.5)] {
            let m = material(young, nu, Plane::Strain);
            let want =
                isotropic_stiffness(3, 8, &m, |a, b, i, j| box_integral(&CUBE, 3, a, b, i, j));
            let got = stiffness(ElementKind::Hex8, &CUBE, &m).unwrap();
            assert_matrix_close(&got, &want, 1e-14);
        }
    }

    #[test]
    fn degenerate_elements_are_errors() {
        let m = material(1.0, 0.3, Plane::Strain);
        let cases: Vec<(ElementKind, Vec<[f64; 3]>, &str)> = vec![
            (
                ElementKind::Tri3,
                vec![[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 2.0, 0.0]],
                "zero area",
            ),
            (ElementKind::Tri3, vec![[1.0, 2.0, 0.0]; 3], "zero area"),
            (
                ElementKind::Tet4,
                vec![
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                    [0.3, 0.4, 0.0],
                ],
                "zero volume",
            ),
            (
                // Bow-tie: edges 0-1 and 2-3 cross.
                ElementKind::Quad4,
                vec![
                    [0.0, 0.0, 0.0],
                    [1.0, 1.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0],
                ],
                "changes sign",
            ),
            (
                // Arrowhead: node 2 is a reflex corner, det J < 0 there.
                ElementKind::Quad4,
                vec![
                    [0.0, 0.0, 0.0],
                    [2.0, 0.0, 0.0],
                    [0.4, 0.4, 0.0],
                    [0.0, 2.0, 0.0],
                ],
                "changes sign",
            ),
            (
                // Slightly non-convex: det J > 0 at the Gauss points, < 0 at corner 2 only.
                ElementKind::Quad4,
                vec![
                    [0.0, 0.0, 0.0],
                    [2.0, 0.0, 0.0],
                    [0.9, 0.9, 0.0],
                    [0.0, 2.0, 0.0],
                ],
                "changes sign",
            ),
            (
                ElementKind::Quad4,
                vec![
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [2.0, 0.0, 0.0],
                    [3.0, 0.0, 0.0],
                ],
                "zero area",
            ),
            (
                // Flat hexahedron.
                ElementKind::Hex8,
                CUBE.iter().map(|p| [p[0], p[1], 0.0]).collect(),
                "zero volume",
            ),
            (
                // Node 6 pushed through the bottom face.
                ElementKind::Hex8,
                CUBE.iter()
                    .enumerate()
                    .map(|(a, &p)| if a == 6 { [1.0, 1.0, -1.5] } else { p })
                    .collect(),
                "changes sign",
            ),
            (
                // Node 6 pulled inside, past the plane of its neighbours 2, 5, 7: det J < 0 at
                // corner 6 only.
                ElementKind::Hex8,
                CUBE.iter()
                    .enumerate()
                    .map(|(a, &p)| if a == 6 { [0.6, 0.6, 0.6] } else { p })
                    .collect(),
                "changes sign",
            ),
            (
                // Top face twisted by 180 degrees: det J > 0 at the corners, 0 at the centroid.
                ElementKind::Hex8,
                [0, 1, 2, 3, 6, 7, 4, 5].iter().map(|&a| CUBE[a]).collect(),
                "zero volume",
            ),
        ];
        for (kind, x, reason) in cases {
            let err = stiffness(kind, &x, &m)
                .err()
                .unwrap_or_else(|| panic!("{kind:?} {x:?} was accepted"));
            assert!(err.contains(reason), "{kind:?} {x:?}: {err}");
            assert!(!err.contains('\n'));
            let u = vec![0.0; kind.node_count() * kind.dim()];
            assert!(centroid_stress(kind, &x, &m, &u).is_err());
        }
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let m = material(1.0, 0.3, Plane::Stress);
        assert!(stiffness(ElementKind::Tri3, &TRI[..2], &m)
            .unwrap_err()
            .contains("needs 3"));
        assert!(stiffness(ElementKind::Quad4, &CUBE[..5], &m).is_err());
        assert!(stiffness(ElementKind::Hex8, &TET, &m).is_err());
        assert!(stiffness(ElementKind::Tet4, &[], &m).is_err());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut x = CUBE;
            x[3][1] = bad;
            assert!(stiffness(ElementKind::Hex8, &x, &m)
                .unwrap_err()
                .contains("non-finite"));
            let mut x = TRI;
            x[0][0] = bad;
            assert!(stiffness(ElementKind::Tri3, &x, &m).is_err());
            assert!(centroid_stress(ElementKind::Tri3, &x, &m, &[0.0; 6]).is_err());
        }
        // Huge or tiny but finite coordinates: no panic either way.
        for scale in [1e300, 1e-300, 1e150] {
            let x: Vec<[f64; 3]> = CUBE.iter().map(|p| p.map(|v| v * scale)).collect();
            let _ = stiffness(ElementKind::Hex8, &x, &m);
            let _ = centroid_stress(ElementKind::Hex8, &x, &m, &[1.0; 24]);
        }
        // The z coordinate of a 2D element is ignored.
        let mut x = SQUARE;
        x[2][2] = f64::NAN;
        assert!(stiffness(ElementKind::Quad4, &x, &m).is_ok());
        // Wrong displacement length.
        let err = centroid_stress(ElementKind::Quad4, &SQUARE, &m, &[0.0; 7]).unwrap_err();
        assert!(err.contains("needs 8 displacement"), "{err}");
        assert!(centroid_stress(ElementKind::Tet4, &TET, &m, &[0.0; 13]).is_err());
    }

    #[test]
    fn vanishing_corner_jacobian_is_tolerated() {
        // A quadrilateral with a 180-degree angle at node 3 (it is the triangle 0-1-2):
        // det J = 0 at that corner only, positive at the Gauss points.
        let m = material(1.0, 0.3, Plane::Strain);
        let x = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.5, 0.5, 0.0],
        ];
        let k = stiffness(ElementKind::Quad4, &x, &m).unwrap();
        assert!(k.iter().all(|v| v.is_finite()));
        // A hexahedron collapsed to a prism (node 3 = node 2, node 7 = node 6).
        let mut x = CUBE;
        x[3] = x[2];
        x[7] = x[6];
        let k = stiffness(ElementKind::Hex8, &x, &m).unwrap();
        assert!(k.iter().all(|v| v.is_finite()));
    }

    #[test]
    fn centroid_is_where_the_stress_is_taken() {
        // u = (x y, 0) on the unit square: eps_xx = y, gamma_xy = x; at the centroid (1/2, 1/2)
        // eps = (1/2, 0, 1/2). E = 1, nu = 0 plane stress: sigma = (1/2, 0, 1/4).
        let m = material(1.0, 0.0, Plane::Stress);
        let u: Vec<f64> = SQUARE.iter().flat_map(|p| [p[0] * p[1], 0.0]).collect();
        let s = centroid_stress(ElementKind::Quad4, &SQUARE, &m, &u).unwrap();
        let want = [0.5, 0.0, 0.0, 0.0, 0.0, 0.25];
        assert!(
            s.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-15),
            "{s:?}"
        );
        // Same on the cube with u = (x y z, 0, 0): at (1/2,1/2,1/2) eps_xx = 1/4,
        // gamma_xy = x z = 1/4, gamma_xz = x y = 1/4; G = 1/2.
        let u: Vec<f64> = CUBE
            .iter()
            .flat_map(|p| [p[0] * p[1] * p[2], 0.0, 0.0])
            .collect();
        let s = centroid_stress(ElementKind::Hex8, &CUBE, &m, &u).unwrap();
        let want = [0.25, 0.0, 0.0, 0.0, 0.125, 0.125];
        assert!(
            s.iter().zip(&want).all(|(a, b)| (a - b).abs() < 1e-15),
            "{s:?}"
        );
    }
}
