//! Element stiffness and stress (`wedged::fe::element`) on reference and randomly distorted
//! elements of every type: symmetry, rigid-body null space and rank, patch tests on small
//! distorted meshes, mirrored elements, rotations, and plane strain against plane stress. The
//! hand-computed single elements and rejected inputs are unit tests in `element.rs`.

use nalgebra::{DMatrix, DVector, Matrix3, SymmetricEigen};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wedged::fe::element::{centroid_stress, stiffness};
use wedged::fe::{ElementKind, Material, Plane};

const KINDS: [ElementKind; 8] = [
    ElementKind::Tri3,
    ElementKind::Quad4,
    ElementKind::Tet4,
    ElementKind::Hex8,
    ElementKind::Tri6,
    ElementKind::Quad8,
    ElementKind::Quad9,
    ElementKind::Tet10,
];

/// The corner pairs of each second-order kind's mid-edge nodes, in Gmsh's order (written
/// out here from Gmsh's documentation, not taken from the library).
fn mid_edges(kind: ElementKind) -> &'static [[usize; 2]] {
    match kind {
        ElementKind::Tri6 => &[[0, 1], [1, 2], [2, 0]],
        ElementKind::Quad8 | ElementKind::Quad9 => &[[0, 1], [1, 2], [2, 3], [3, 0]],
        ElementKind::Tet10 => &[[0, 1], [1, 2], [0, 2], [0, 3], [2, 3], [1, 3]],
        _ => &[],
    }
}

/// A straight-sided element of `kind` on `corners`: its mid-edge nodes at the middles of its
/// edges, a `Quad9`'s centre at the mean of its corners.
fn with_midpoints(kind: ElementKind, corners: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut x = corners.to_vec();
    let mid = |p: &[[f64; 3]]| {
        let mut c = [0.0; 3];
        for q in p {
            for k in 0..3 {
                c[k] += q[k] / p.len() as f64;
            }
        }
        c
    };
    for &[a, b] in mid_edges(kind) {
        x.push(mid(&[corners[a], corners[b]]));
    }
    if kind == ElementKind::Quad9 {
        x.push(mid(corners));
    }
    x
}

/// The reference element with unit edges along the axes.
fn reference(kind: ElementKind) -> Vec<[f64; 3]> {
    if kind.linear() != kind {
        return with_midpoints(kind, &reference(kind.linear()));
    }
    match kind {
        ElementKind::Tri3 => vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        ElementKind::Quad4 => vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        ElementKind::Tet4 => vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        ElementKind::Hex8 => vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ],
        _ => unreachable!("the linear kinds"),
    }
}

/// A random rotation: about z in 2D, from a random unit quaternion in 3D.
fn random_rotation(rng: &mut ChaCha8Rng, dim: usize) -> Matrix3<f64> {
    if dim == 2 {
        let t: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
        Matrix3::new(t.cos(), -t.sin(), 0.0, t.sin(), t.cos(), 0.0, 0.0, 0.0, 1.0)
    } else {
        let q = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        ));
        *q.to_rotation_matrix().matrix()
    }
}

fn transform(x: &[[f64; 3]], r: &Matrix3<f64>, shift: [f64; 3]) -> Vec<[f64; 3]> {
    x.iter()
        .map(|p| {
            let q = r * nalgebra::Vector3::from(*p);
            [q[0] + shift[0], q[1] + shift[1], q[2] + shift[2]]
        })
        .collect()
}

/// The reference element with every corner moved by up to `0.2` per coordinate (the other
/// nodes by up to `0.04` from the middles of its edges), then scaled, rotated and shifted at
/// random (positively oriented).
fn distorted(kind: ElementKind, rng: &mut ChaCha8Rng) -> Vec<[f64; 3]> {
    let dim = kind.dim();
    let scale = 10f64.powf(rng.gen_range(-2.0..2.0));
    let mut move_by = |p: &[f64; 3], by: f64| {
        let mut q = [0.0; 3];
        for k in 0..dim {
            q[k] = scale * (p[k] + rng.gen_range(-by..by));
        }
        q
    };
    let corners: Vec<[f64; 3]> = reference(kind.linear())
        .iter()
        .map(|p| move_by(p, 0.2))
        .collect();
    // A second-order element's other nodes near the middles of its (moved) edges: curved
    // edges, but not so curved that `det J` changes sign at a corner.
    let x: Vec<[f64; 3]> = with_midpoints(kind, &corners)
        .iter()
        .enumerate()
        .map(|(a, p)| {
            if a < corners.len() {
                *p
            } else {
                move_by(&p.map(|v| v / scale), 0.04)
            }
        })
        .collect();
    let r = random_rotation(rng, dim);
    let mut shift = [0.0; 3];
    for s in shift.iter_mut().take(dim) {
        *s = scale * rng.gen_range(-5.0..5.0);
    }
    transform(&x, &r, shift)
}

fn random_material(rng: &mut ChaCha8Rng) -> Material {
    let plane = if rng.gen_bool(0.5) {
        Plane::Strain
    } else {
        Plane::Stress
    };
    Material::new(
        10f64.powf(rng.gen_range(-1.0..3.0)),
        rng.gen_range(-0.5..0.45),
        plane,
    )
    .unwrap()
}

/// Reference elements and 20 distorted ones for each kind, each with a random material.
fn samples() -> Vec<(ElementKind, Vec<[f64; 3]>, Material)> {
    let mut rng = ChaCha8Rng::seed_from_u64(0xE1E);
    let mut out = Vec::new();
    for kind in KINDS {
        for i in 0..21 {
            let x = if i == 0 {
                reference(kind)
            } else {
                distorted(kind, &mut rng)
            };
            out.push((kind, x, random_material(&mut rng)));
        }
    }
    out
}

/// The rigid-body modes of the nodes `x`: translations, then rotations (`omega x p`).
fn rigid_modes(dim: usize, x: &[[f64; 3]]) -> Vec<DVector<f64>> {
    let n = x.len();
    let mut modes = Vec::new();
    for k in 0..dim {
        modes.push(DVector::from_fn(n * dim, |r, _| {
            if r % dim == k {
                1.0
            } else {
                0.0
            }
        }));
    }
    let axes: &[[f64; 3]] = if dim == 2 {
        &[[0.0, 0.0, 1.0]]
    } else {
        &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    };
    for w in axes {
        let w = nalgebra::Vector3::from(*w);
        modes.push(DVector::from_fn(n * dim, |r, _| {
            let v = w.cross(&nalgebra::Vector3::from(x[r / dim]));
            v[r % dim]
        }));
    }
    modes
}

fn relative_asymmetry(k: &DMatrix<f64>) -> f64 {
    (k - k.transpose()).amax() / k.amax()
}

#[test]
fn stiffness_is_symmetric() {
    for (kind, x, m) in samples() {
        let k = stiffness(kind, &x, &m).unwrap();
        let nd = kind.node_count() * kind.dim();
        assert_eq!(k.shape(), (nd, nd));
        assert!(
            relative_asymmetry(&k) <= 1e-12,
            "{kind:?} {x:?}: asymmetry {}",
            relative_asymmetry(&k)
        );
    }
}

#[test]
fn rigid_body_modes_are_the_null_space() {
    for (kind, x, m) in samples() {
        let dim = kind.dim();
        let k = stiffness(kind, &x, &m).unwrap();
        let norm = k.norm();
        for mode in rigid_modes(dim, &x) {
            let r = (&k * &mode).norm() / (norm * mode.norm());
            assert!(r <= 1e-13, "{kind:?} {x:?}: |K mode| / |K||mode| = {r:e}");
        }
        // Exactly 3 (2D) or 6 (3D) zero eigenvalues, the rest positive.
        let eig = SymmetricEigen::new(k).eigenvalues;
        let max = eig.max();
        let zero = eig.iter().filter(|l| l.abs() <= 1e-10 * max).count();
        let positive = eig.iter().filter(|&&l| l > 1e-10 * max).count();
        let rigid = if dim == 2 { 3 } else { 6 };
        assert_eq!(zero, rigid, "{kind:?} {x:?}: eigenvalues {eig}");
        assert_eq!(
            positive,
            eig.len() - rigid,
            "{kind:?} {x:?}: eigenvalues {eig}"
        );
    }
}

#[test]
fn stiffness_rotates_with_the_element() {
    // K(R x) = Q K(x) Q^T with Q = diag(R, ..., R).
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (kind, x, m) in samples() {
        let dim = kind.dim();
        let r = random_rotation(&mut rng, dim);
        let k = stiffness(kind, &x, &m).unwrap();
        let kr = stiffness(kind, &transform(&x, &r, [1.0, -2.0, 0.0]), &m).unwrap();
        let nd = k.nrows();
        let q = DMatrix::from_fn(nd, nd, |i, j| {
            if i / dim == j / dim {
                r[(i % dim, j % dim)]
            } else {
                0.0
            }
        });
        let err = (&kr - &q * &k * q.transpose()).amax() / k.amax();
        assert!(err <= 1e-12, "{kind:?}: rotated stiffness off by {err:e}");
    }
}

/// A node permutation that reverses the orientation of the element.
fn mirror_permutation(kind: ElementKind) -> &'static [usize] {
    match kind {
        ElementKind::Tri3 => &[0, 2, 1],
        ElementKind::Quad4 => &[0, 3, 2, 1],
        ElementKind::Tet4 => &[0, 2, 1, 3],
        ElementKind::Hex8 => &[4, 5, 6, 7, 0, 1, 2, 3],
        ElementKind::Tri6 => &[0, 2, 1, 5, 4, 3],
        ElementKind::Quad8 => &[0, 3, 2, 1, 7, 6, 5, 4],
        ElementKind::Quad9 => &[0, 3, 2, 1, 7, 6, 5, 4, 8],
        ElementKind::Tet10 => &[0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
    }
}

#[test]
fn mirrored_elements_have_the_same_stiffness() {
    for (kind, x, m) in samples() {
        let dim = kind.dim();
        let k = stiffness(kind, &x, &m).unwrap();
        let scale = k.amax();

        // The same element with its nodes listed in the mirrored order: K permuted.
        let perm = mirror_permutation(kind);
        let xp: Vec<[f64; 3]> = perm.iter().map(|&a| x[a]).collect();
        let kp = stiffness(kind, &xp, &m).unwrap();
        let nd = k.nrows();
        let dof = |r: usize| dim * perm[r / dim] + r % dim;
        let want = DMatrix::from_fn(nd, nd, |i, j| k[(dof(i), dof(j))]);
        let err = (&kp - &want).amax() / scale;
        assert!(err <= 1e-12, "{kind:?} node order {perm:?}: off by {err:e}");

        // The mirror image x -> -x, same node order: every x dof changes sign.
        let xm: Vec<[f64; 3]> = x.iter().map(|p| [-p[0], p[1], p[2]]).collect();
        let km = stiffness(kind, &xm, &m).unwrap();
        let sign = |r: usize| if r % dim == 0 { -1.0 } else { 1.0 };
        let want = DMatrix::from_fn(nd, nd, |i, j| sign(i) * sign(j) * k[(i, j)]);
        let err = (&km - &want).amax() / scale;
        assert!(err <= 1e-12, "{kind:?} reflected: off by {err:e}");

        // Stresses agree too.
        let u: Vec<f64> = (0..nd).map(|r| ((r * 7 % 5) as f64 - 2.0) * 0.1).collect();
        let up: Vec<f64> = (0..nd).map(|r| u[dof(r)]).collect();
        let s = centroid_stress(kind, &x, &m, &u).unwrap();
        let sp = centroid_stress(kind, &xp, &m, &up).unwrap();
        let smax = s.iter().fold(0f64, |a, v| a.max(v.abs()));
        for c in 0..6 {
            assert!(
                (s[c] - sp[c]).abs() <= 1e-12 * smax,
                "{kind:?}: {s:?} vs {sp:?}"
            );
        }
    }
}

/// A linear field `u = a + B x` and its (constant) Voigt stress.
struct LinearField {
    dim: usize,
    a: [f64; 3],
    b: [[f64; 3]; 3],
}

impl LinearField {
    fn random(dim: usize, rng: &mut ChaCha8Rng) -> LinearField {
        let mut a = [0.0; 3];
        let mut b = [[0.0; 3]; 3];
        for (ai, bi) in a.iter_mut().zip(&mut b).take(dim) {
            *ai = rng.gen_range(-1.0..1.0);
            for bij in bi.iter_mut().take(dim) {
                *bij = rng.gen_range(-1.0..1.0);
            }
        }
        LinearField { dim, a, b }
    }

    fn at(&self, p: &[f64; 3]) -> [f64; 3] {
        let mut u = [0.0; 3];
        for ((ui, ai), bi) in u.iter_mut().zip(&self.a).zip(&self.b).take(self.dim) {
            *ui = ai
                + bi.iter()
                    .zip(p)
                    .take(self.dim)
                    .map(|(b, x)| b * x)
                    .sum::<f64>();
        }
        u
    }

    /// Element dofs, node-major.
    fn dofs(&self, x: &[[f64; 3]]) -> Vec<f64> {
        x.iter()
            .flat_map(|p| self.at(p)[..self.dim].to_vec())
            .collect()
    }

    /// `D eps` in the output Voigt order `[xx, yy, zz, yz, xz, xy]`, from the material formulas.
    fn stress(&self, m: &Material) -> [f64; 6] {
        let b = &self.b;
        if self.dim == 2 {
            let eps = DVector::from_vec(vec![b[0][0], b[1][1], b[0][1] + b[1][0]]);
            let s = m.d_matrix(2) * eps;
            [s[0], s[1], m.sigma_zz(s[0], s[1]), 0.0, 0.0, s[2]]
        } else {
            let eps = DVector::from_vec(vec![
                b[0][0],
                b[1][1],
                b[2][2],
                b[1][2] + b[2][1],
                b[0][2] + b[2][0],
                b[0][1] + b[1][0],
            ]);
            let s = m.d_matrix(3) * eps;
            [s[0], s[1], s[2], s[3], s[4], s[5]]
        }
    }
}

/// A structured patch on `[0, m]^dim`: node coordinates (perturbed by up to `jitter` per
/// coordinate), whether each node is on the boundary, and the elements.
struct Patch {
    kind: ElementKind,
    coords: Vec<[f64; 3]>,
    boundary: Vec<bool>,
    elements: Vec<Vec<usize>>,
}

impl Patch {
    fn new(kind: ElementKind, m: usize, jitter: f64, rng: &mut ChaCha8Rng) -> Patch {
        let dim = kind.dim();
        let side = m + 1;
        let count = side.pow(dim as u32);
        let index = |i: usize, j: usize, k: usize| i + side * (j + side * k);
        let mut coords = Vec::with_capacity(count);
        let mut boundary = Vec::with_capacity(count);
        for k in 0..if dim == 3 { side } else { 1 } {
            for j in 0..side {
                for i in 0..side {
                    let grid = [i, j, k];
                    let mut p = [0.0; 3];
                    for c in 0..dim {
                        p[c] = grid[c] as f64 + rng.gen_range(-jitter..jitter);
                    }
                    coords.push(p);
                    boundary.push(grid[..dim].iter().any(|&g| g == 0 || g == m));
                }
            }
        }
        let mut elements = Vec::new();
        for k in 0..if dim == 3 { m } else { 1 } {
            for j in 0..m {
                for i in 0..m {
                    // The cell's corners in Gmsh quad / hex order.
                    let quad = [
                        index(i, j, k),
                        index(i + 1, j, k),
                        index(i + 1, j + 1, k),
                        index(i, j + 1, k),
                    ];
                    let up = |a: usize| a + side * side;
                    match kind {
                        ElementKind::Quad4 => elements.push(quad.to_vec()),
                        ElementKind::Tri3 => {
                            // Alternate the diagonal.
                            if (i + j) % 2 == 0 {
                                elements.push(vec![quad[0], quad[1], quad[2]]);
                                elements.push(vec![quad[0], quad[2], quad[3]]);
                            } else {
                                elements.push(vec![quad[0], quad[1], quad[3]]);
                                elements.push(vec![quad[1], quad[2], quad[3]]);
                            }
                        }
                        ElementKind::Hex8 => {
                            let mut hex = quad.to_vec();
                            hex.extend(quad.iter().map(|&a| up(a)));
                            elements.push(hex);
                        }
                        ElementKind::Tet4 => {
                            // Kuhn split: 6 tetrahedra along the diagonal (0,0,0)-(1,1,1), one
                            // per order of the axes; conforming between cells.
                            let corner = |d: [usize; 3]| index(i + d[0], j + d[1], k + d[2]);
                            for axes in [
                                [0, 1, 2],
                                [0, 2, 1],
                                [1, 0, 2],
                                [1, 2, 0],
                                [2, 0, 1],
                                [2, 1, 0],
                            ] {
                                let mut d = [0usize; 3];
                                let mut tet = vec![corner(d)];
                                for &ax in &axes {
                                    d[ax] = 1;
                                    tet.push(corner(d));
                                }
                                // Odd orders are negatively oriented: swap two nodes.
                                let odd =
                                    axes == [0, 2, 1] || axes == [1, 0, 2] || axes == [2, 1, 0];
                                if odd {
                                    tet.swap(1, 2);
                                }
                                elements.push(tet);
                            }
                        }
                        _ => unreachable!("patches of linear elements"),
                    }
                }
            }
        }
        Patch {
            kind,
            coords,
            boundary,
            elements,
        }
    }

    fn element_coords(&self, e: &[usize]) -> Vec<[f64; 3]> {
        e.iter().map(|&a| self.coords[a]).collect()
    }

    fn assemble(&self, m: &Material) -> DMatrix<f64> {
        let dim = self.kind.dim();
        let nd = dim * self.coords.len();
        let mut k = DMatrix::zeros(nd, nd);
        for e in &self.elements {
            let ke = stiffness(self.kind, &self.element_coords(e), m).unwrap();
            for (r, &a) in e.iter().enumerate() {
                for (c, &b) in e.iter().enumerate() {
                    for i in 0..dim {
                        for j in 0..dim {
                            k[(dim * a + i, dim * b + j)] += ke[(dim * r + i, dim * c + j)];
                        }
                    }
                }
            }
        }
        k
    }
}

/// Imposes a random linear field on the boundary nodes of a distorted patch, solves for the
/// interior nodes, and checks that they and every element's centroid stress reproduce the field.
fn patch_test(kind: ElementKind, m: usize, jitter: f64, seed: u64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let dim = kind.dim();
    let patch = Patch::new(kind, m, jitter, &mut rng);
    let material = random_material(&mut rng);
    let field = LinearField::random(dim, &mut rng);
    let k = patch.assemble(&material);
    let nd = k.nrows();

    let (interior, fixed): (Vec<usize>, Vec<usize>) =
        (0..nd).partition(|&r| !patch.boundary[r / dim]);
    assert!(!interior.is_empty());
    let exact = field.dofs(&patch.coords);
    let u_b = DVector::from_iterator(fixed.len(), fixed.iter().map(|&r| exact[r]));
    let k_ii = k.select_rows(&interior).select_columns(&interior);
    let k_ib = k.select_rows(&interior).select_columns(&fixed);
    let rhs = -(k_ib * u_b);
    let u_i = k_ii
        .cholesky()
        .expect("interior stiffness is positive definite")
        .solve(&rhs);
    let scale = exact.iter().fold(0f64, |a, v| a.max(v.abs()));
    for (q, &r) in interior.iter().enumerate() {
        assert!(
            (u_i[q] - exact[r]).abs() <= 1e-10 * scale,
            "{kind:?} patch, dof {r}: {} != {}",
            u_i[q],
            exact[r]
        );
    }

    let mut u = exact.clone();
    for (q, &r) in interior.iter().enumerate() {
        u[r] = u_i[q];
    }
    let want = field.stress(&material);
    let smax = want.iter().fold(0f64, |a, v| a.max(v.abs()));
    for e in &patch.elements {
        let ue: Vec<f64> = e
            .iter()
            .flat_map(|&a| u[dim * a..dim * a + dim].to_vec())
            .collect();
        let s = centroid_stress(kind, &patch.element_coords(e), &material, &ue).unwrap();
        for c in 0..6 {
            assert!(
                (s[c] - want[c]).abs() <= 1e-10 * smax,
                "{kind:?} patch element {e:?}: stress {s:?} != {want:?}"
            );
        }
    }
    // Interior nodes are in equilibrium: (K u)_interior = 0.
    let f = &k * DVector::from_vec(u);
    let fmax = k.amax() * scale;
    for &r in &interior {
        assert!(f[r].abs() <= 1e-10 * fmax);
    }
}

#[test]
fn patch_test_tri3() {
    for seed in 0..5 {
        patch_test(ElementKind::Tri3, 2, 0.15, seed);
        patch_test(ElementKind::Tri3, 3, 0.15, 100 + seed);
    }
}

#[test]
fn patch_test_quad4() {
    // m = 2: four distorted quadrilaterals around one interior node.
    for seed in 0..5 {
        patch_test(ElementKind::Quad4, 2, 0.3, seed);
        patch_test(ElementKind::Quad4, 3, 0.25, 100 + seed);
    }
}

#[test]
fn patch_test_tet4() {
    // m = 2: 8 cubes, 48 tetrahedra, one interior node.
    for seed in 0..3 {
        patch_test(ElementKind::Tet4, 2, 0.1, seed);
    }
    patch_test(ElementKind::Tet4, 3, 0.1, 100);
}

#[test]
fn patch_test_hex8() {
    // m = 2: 8 hexahedra around a perturbed interior node; m = 3: 8 interior nodes.
    for seed in 0..3 {
        patch_test(ElementKind::Hex8, 2, 0.25, seed);
    }
    patch_test(ElementKind::Hex8, 3, 0.2, 100);
}

/// A linear field on element `x` given by `b` (`u = b x`), as element dofs.
fn linear_dofs(dim: usize, x: &[[f64; 3]], b: [[f64; 3]; 3]) -> Vec<f64> {
    LinearField {
        dim,
        a: [0.0; 3],
        b,
    }
    .dofs(x)
}

fn assert_stress(got: [f64; 6], want: [f64; 6], what: &str) {
    let scale = want.iter().fold(0f64, |a, v| a.max(v.abs()));
    for c in 0..6 {
        assert!(
            (got[c] - want[c]).abs() <= 1e-12 * scale,
            "{what}: {got:?} != {want:?}"
        );
    }
}

#[test]
fn uniaxial_and_shear_stresses_match_material_formulas() {
    let (young, nu, e) = (210.0, 0.3, 1e-3);
    let (lambda, g) = Material::new(young, nu, Plane::Strain).unwrap().lame();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for kind in KINDS {
        for x in [reference(kind), distorted(kind, &mut rng)] {
            let dim = kind.dim();
            let run = |plane: Plane, b: [[f64; 3]; 3]| {
                let m = Material::new(young, nu, plane).unwrap();
                centroid_stress(kind, &x, &m, &linear_dofs(dim, &x, b)).unwrap()
            };
            let diag = |d: [f64; 3]| [[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]];
            let gamma = 2e-3;
            if dim == 2 {
                // Uniaxial strain eps_xx = e.
                let c = young / ((1.0 + nu) * (1.0 - 2.0 * nu));
                let s = run(Plane::Strain, diag([e, 0.0, 0.0]));
                let want = [c * (1.0 - nu) * e, c * nu * e, c * nu * e, 0.0, 0.0, 0.0];
                assert_stress(s, want, "plane strain, uniaxial strain");
                let s = run(Plane::Stress, diag([e, 0.0, 0.0]));
                let c = young / (1.0 - nu * nu);
                assert_stress(
                    s,
                    [c * e, c * nu * e, 0.0, 0.0, 0.0, 0.0],
                    "plane stress, uniaxial strain",
                );
                // Uniaxial stress: plane stress eps_yy = -nu eps_xx gives sigma_xx = E eps_xx;
                // plane strain eps_yy = -nu/(1-nu) eps_xx gives E/(1-nu^2) and sigma_zz = nu sigma_xx.
                let s = run(Plane::Stress, diag([e, -nu * e, 0.0]));
                assert_stress(
                    s,
                    [young * e, 0.0, 0.0, 0.0, 0.0, 0.0],
                    "plane stress, uniaxial stress",
                );
                let s = run(Plane::Strain, diag([e, -nu / (1.0 - nu) * e, 0.0]));
                let sxx = young / (1.0 - nu * nu) * e;
                assert_stress(
                    s,
                    [sxx, 0.0, nu * sxx, 0.0, 0.0, 0.0],
                    "plane strain, uniaxial stress",
                );
                // Simple shear u_x = gamma y: sigma_xy = G gamma in both.
                for plane in [Plane::Strain, Plane::Stress] {
                    let b = [[0.0, gamma, 0.0], [0.0; 3], [0.0; 3]];
                    assert_stress(run(plane, b), [0.0, 0.0, 0.0, 0.0, 0.0, g * gamma], "shear");
                }
            } else {
                let s = run(Plane::Strain, diag([e, 0.0, 0.0]));
                let want = [
                    (lambda + 2.0 * g) * e,
                    lambda * e,
                    lambda * e,
                    0.0,
                    0.0,
                    0.0,
                ];
                assert_stress(s, want, "3D uniaxial strain");
                let s = run(Plane::Stress, diag([e, -nu * e, -nu * e]));
                assert_stress(
                    s,
                    [young * e, 0.0, 0.0, 0.0, 0.0, 0.0],
                    "3D uniaxial stress",
                );
                // Simple shears: u_y = gamma z -> yz; u_x = gamma z -> xz; u_x = gamma y -> xy.
                for (i, j, voigt) in [(1, 2, 3), (0, 2, 4), (0, 1, 5)] {
                    let mut b = [[0.0; 3]; 3];
                    b[i][j] = gamma;
                    let mut want = [0.0; 6];
                    want[voigt] = g * gamma;
                    assert_stress(run(Plane::Strain, b), want, "3D shear");
                }
            }
        }
    }
}

#[test]
fn plane_stress_is_softer_than_plane_strain() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for kind in [ElementKind::Tri3, ElementKind::Quad4] {
        for x in [reference(kind), distorted(kind, &mut rng)] {
            let k = |nu: f64, plane: Plane| {
                stiffness(kind, &x, &Material::new(2.0, nu, plane).unwrap()).unwrap()
            };
            // nu = 0: the same.
            let (strain, stress) = (k(0.0, Plane::Strain), k(0.0, Plane::Stress));
            assert!((&strain - &stress).amax() <= 1e-14 * strain.amax());

            let nu = 0.3;
            let (strain, stress) = (k(nu, Plane::Strain), k(nu, Plane::Stress));
            // D_strain - D_stress = (lambda - lambda*) [1 1; 1 1] (+ 0 shear): K_strain - K_stress
            // is positive semidefinite and nonzero.
            let diff = &strain - &stress;
            assert!(diff.amax() > 0.1 * strain.amax());
            let eig = SymmetricEigen::new(diff).eigenvalues;
            assert!(eig.min() >= -1e-12 * strain.amax(), "{eig}");
            // A deviatoric field (eps_xx + eps_yy = 0) stores the same energy in both; a
            // dilatation (e, e) stores E/((1+nu)(1-2nu)) against E/(1-nu) per unit volume.
            let energy = |k: &DMatrix<f64>, b: [[f64; 3]; 3]| {
                let u = DVector::from_vec(linear_dofs(2, &x, b));
                u.dot(&(k * &u))
            };
            let dev = [[1.0, 0.4, 0.0], [0.2, -1.0, 0.0], [0.0; 3]];
            let (a, b) = (energy(&strain, dev), energy(&stress, dev));
            assert!((a - b).abs() <= 1e-12 * a, "{a} vs {b}");
            let dil = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0; 3]];
            let ratio = energy(&strain, dil) / energy(&stress, dil);
            let want = (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
            assert!((ratio - want).abs() <= 1e-12 * want, "{ratio} vs {want}");
        }
    }
}

#[test]
fn constant_strain_energy_is_area_times_density() {
    // For u = B x the strain is constant, and u^T K u = |element| eps^T D eps exactly (det J is
    // integrated exactly by the rules used). Areas by the shoelace formula, volumes of
    // tetrahedra by the triple product.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for kind in [ElementKind::Tri3, ElementKind::Quad4, ElementKind::Tet4] {
        for _ in 0..10 {
            let x = distorted(kind, &mut rng);
            let m = random_material(&mut rng);
            let field = LinearField::random(kind.dim(), &mut rng);
            let k = stiffness(kind, &x, &m).unwrap();
            let u = DVector::from_vec(field.dofs(&x));
            let size = if kind == ElementKind::Tet4 {
                let v = |a: usize| nalgebra::Vector3::from(x[a]) - nalgebra::Vector3::from(x[0]);
                v(1).cross(&v(2)).dot(&v(3)).abs() / 6.0
            } else {
                let n = x.len();
                (0..n)
                    .map(|a| x[a][0] * x[(a + 1) % n][1] - x[(a + 1) % n][0] * x[a][1])
                    .sum::<f64>()
                    .abs()
                    / 2.0
            };
            let dim = kind.dim();
            let want = size * energy_density(&field.b, dim, &m.d_matrix(dim));
            let got = u.dot(&(&k * &u));
            assert!(
                (got - want).abs() <= 1e-11 * want,
                "{kind:?}: {got} vs {want}"
            );
        }
    }
}

/// A random quadratic displacement field: each component a full quadratic polynomial.
fn quadratic_field(dim: usize, rng: &mut ChaCha8Rng) -> Vec<Vec<f64>> {
    // Coefficients per component of 1, x_j, x_j x_k (j <= k).
    let terms = 1 + dim + dim * (dim + 1) / 2;
    (0..dim)
        .map(|_| (0..terms).map(|_| rng.gen_range(-1.0..1.0)).collect())
        .collect()
}

/// The field's value and gradient (`grad[i][j] = du_i/dx_j`) at `p`.
fn quadratic_at(c: &[Vec<f64>], dim: usize, p: &[f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let (mut u, mut g) = ([0.0; 3], [[0.0; 3]; 3]);
    for i in 0..dim {
        let ci = &c[i];
        u[i] = ci[0];
        for j in 0..dim {
            u[i] += ci[1 + j] * p[j];
            g[i][j] += ci[1 + j];
        }
        let mut t = 1 + dim;
        for j in 0..dim {
            for k in j..dim {
                u[i] += ci[t] * p[j] * p[k];
                g[i][j] += ci[t] * p[k];
                g[i][k] += ci[t] * p[j];
                t += 1;
            }
        }
    }
    (u, g)
}

/// The strain energy density `eps^T D eps` (Voigt, engineering shears) of a gradient.
fn energy_density(g: &[[f64; 3]; 3], dim: usize, d: &DMatrix<f64>) -> f64 {
    let eps = if dim == 2 {
        DVector::from_vec(vec![g[0][0], g[1][1], g[0][1] + g[1][0]])
    } else {
        DVector::from_vec(vec![
            g[0][0],
            g[1][1],
            g[2][2],
            g[1][2] + g[2][1],
            g[0][2] + g[2][0],
            g[0][1] + g[1][0],
        ])
    };
    eps.dot(&(d * &eps))
}

/// The integral of a quadratic polynomial `f` over a straight-sided triangle or tetrahedron
/// with corners `c`, exactly, by rules that are not the library's: the triangle's edge
/// midpoints (`A/3` each), the tetrahedron's corners (`-V/20`) and edge midpoints (`V/5`).
fn simplex_integral(c: &[[f64; 3]], f: &dyn Fn(&[f64; 3]) -> f64) -> f64 {
    let mid = |a: usize, b: usize| -> [f64; 3] { [0, 1, 2].map(|k| (c[a][k] + c[b][k]) / 2.0) };
    let v = |a: usize| nalgebra::Vector3::from(c[a]) - nalgebra::Vector3::from(c[0]);
    if c.len() == 3 {
        let area = v(1).cross(&v(2)).norm() / 2.0;
        area / 3.0 * (f(&mid(0, 1)) + f(&mid(1, 2)) + f(&mid(2, 0)))
    } else {
        let volume = v(1).cross(&v(2)).dot(&v(3)).abs() / 6.0;
        let corners: f64 = (0..4).map(|a| f(&c[a])).sum();
        let mids: f64 = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)]
            .iter()
            .map(|&(a, b)| f(&mid(a, b)))
            .sum();
        volume * (-corners / 20.0 + mids / 5.0)
    }
}

/// On straight-sided second-order elements (random corners; a quadrilateral a random
/// parallelogram, split into two triangles for the reference integral), a random quadratic
/// field at the nodes has the strain energy `u^T K u` of the field itself: the shape functions
/// reproduce it, their gradients are right, and the rule integrates the energy exactly.
#[test]
fn quadratic_fields_have_their_exact_energy() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for kind in [
        ElementKind::Tri6,
        ElementKind::Quad8,
        ElementKind::Quad9,
        ElementKind::Tet10,
    ] {
        let dim = kind.dim();
        for _ in 0..10 {
            let corners = transform(
                &distorted(kind.linear(), &mut rng),
                &Matrix3::identity(),
                [0.0; 3],
            );
            let corners = if kind.linear() == ElementKind::Quad4 {
                // A parallelogram: the fourth corner from the other three.
                let mut c = corners;
                c[3] = [0, 1, 2].map(|k| c[0][k] + c[2][k] - c[1][k]);
                c
            } else {
                corners
            };
            let x = with_midpoints(kind, &corners);
            let m = random_material(&mut rng);
            let d = m.d_matrix(dim);
            let field = quadratic_field(dim, &mut rng);
            let u = DVector::from_iterator(
                x.len() * dim,
                x.iter()
                    .flat_map(|p| quadratic_at(&field, dim, p).0.into_iter().take(dim)),
            );
            let k = stiffness(kind, &x, &m).unwrap();
            let got = u.dot(&(&k * &u));
            let density = |p: &[f64; 3]| energy_density(&quadratic_at(&field, dim, p).1, dim, &d);
            let want = if kind.linear() == ElementKind::Quad4 {
                simplex_integral(&[corners[0], corners[1], corners[2]], &density)
                    + simplex_integral(&[corners[0], corners[2], corners[3]], &density)
            } else {
                simplex_integral(&corners, &density)
            };
            assert!(
                (got - want).abs() <= 1e-10 * want.abs(),
                "{kind:?}: u^T K u = {got}, the field's energy {want}"
            );
        }
    }
}

/// `ElementKind::vtk_order` gives VTK's node order (VTK's documentation: a quadratic
/// triangle's and quadrilateral's middles on `0-1, 1-2, 2-0 (3-0)`, a biquadratic
/// quadrilateral's centre last, a quadratic tetrahedron's on `0-1, 1-2, 2-0, 0-3, 1-3, 2-3`).
#[test]
fn vtk_order_puts_the_middles_where_vtk_wants_them() {
    let vtk: [(ElementKind, &[[usize; 2]]); 4] = [
        (ElementKind::Tri6, &[[0, 1], [1, 2], [2, 0]]),
        (ElementKind::Quad8, &[[0, 1], [1, 2], [2, 3], [3, 0]]),
        (ElementKind::Quad9, &[[0, 1], [1, 2], [2, 3], [3, 0]]),
        (
            ElementKind::Tet10,
            &[[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]],
        ),
    ];
    for (kind, pairs) in vtk {
        let x = reference(kind);
        let order = kind.vtk_order(&(0..x.len()).collect::<Vec<_>>());
        let corners = kind.corner_count();
        assert_eq!(order[..corners], (0..corners).collect::<Vec<_>>()[..]);
        for (&node, &[a, b]) in order[corners..].iter().zip(pairs) {
            let middle = [0, 1, 2].map(|k| (x[a][k] + x[b][k]) / 2.0);
            assert_eq!(x[node], middle, "{kind:?}: VTK node between {a} and {b}");
        }
    }
    assert_eq!(ElementKind::Tri3.vtk_order(&[4, 5, 6]), [4, 5, 6]);
}
