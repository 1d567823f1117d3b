//! Tests of `element.rs`.

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
fn box_integral(corners: &[[f64; 3]], dim: usize, a: usize, b: usize, i: usize, j: usize) -> f64 {
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
        let want = isotropic_stiffness(2, 4, &m, |a, b, i, j| box_integral(&SQUARE, 2, a, b, i, j));
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
        let want = isotropic_stiffness(3, 8, &m, |a, b, i, j| box_integral(&CUBE, 3, a, b, i, j));
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
