//! Built-in example problems (no I/O): the demo and deterministic test families.

use nalgebra::DMatrix;

use crate::problem::Problem;

mod lattice;
pub use lattice::lattice_plug;

/// The demo: four contact nodes of a small elastic block pressed into a notch, modelled as a
/// discrete system. Each node has a normal and a tangential spring, the tangential spring is
/// inclined to the wall (normal-tangential coupling, the source of wedging), and neighbouring
/// nodes are joined by shear springs. At `mu = 1.0` it has wedged configurations.
pub fn demo() -> Problem {
    let m = 4;
    let mut k = DMatrix::<f64>::zeros(2 * m, 2 * m);
    for i in 0..m {
        // A spring of stiffness s at angle theta to the wall adds s d d^T, d = (sin, cos).
        let theta: f64 = if i < m / 2 { 0.9 } else { -0.9 };
        let (s, c) = theta.sin_cos();
        let stiff = 3.0;
        k[(2 * i, 2 * i)] += 1.0 + stiff * s * s;
        k[(2 * i, 2 * i + 1)] += stiff * s * c;
        k[(2 * i + 1, 2 * i)] += stiff * s * c;
        k[(2 * i + 1, 2 * i + 1)] += 0.1 + stiff * c * c;
    }
    for i in 0..m - 1 {
        // Shear springs between neighbouring nodes, on both components.
        for (c, w) in [(0, 0.6), (1, 0.3)] {
            let (a, b) = (2 * i + c, 2 * (i + 1) + c);
            k[(a, a)] += w;
            k[(b, b)] += w;
            k[(a, b)] -= w;
            k[(b, a)] -= w;
        }
    }
    Problem::new(2, k, 1.0).expect("the demo stiffness is symmetric positive definite")
}

/// The demo body: a 2D plug in a V-notch (plane strain, steel), its top edge clamped, its two
/// slanted sides against the notch walls, condensed onto those sides; and a friction coefficient
/// at which it wedges. Bottom width 1, top width 2, height 1 (walls 26.6 degrees off vertical),
/// 8 x 6 quadrilaterals: 12 contact nodes.
pub fn plug2d_demo() -> Result<(crate::fe::Model, f64), crate::fe::FeError> {
    use crate::fe::generate::Plug2d;
    let mesh = Plug2d {
        bottom_width: 1.0,
        top_width: 2.0,
        height: 1.0,
        nx: PLUG2D_DEMO_DIVISIONS.0,
        ny: PLUG2D_DEMO_DIVISIONS.1,
        simplices: false,
    }
    .mesh()?;
    Ok((steel_plug(mesh)?, PLUG2D_DEMO_MU))
}

/// The cork of `wedged demo --cork`: the demo's plug (8 x 6 quadrilaterals, plane strain)
/// with nothing clamped, a floating body held by the notch walls alone (README, "Floating
/// bodies"); a rubbery Young's modulus of 10 MPa (it does not change the answers), Poisson
/// ratio 0.3; 14 contact nodes (its top corners touch too); and a friction coefficient at which
/// it wedges. Its `mu*` is `tan(atan(1/2)) = 0.5`, the equilibrium bound.
pub fn cork2d_demo() -> Result<(crate::fe::Model, f64), crate::fe::FeError> {
    use crate::fe::generate::Plug2d;
    use crate::fe::{Material, Model, Plane};
    let mesh = Plug2d {
        bottom_width: 1.0,
        top_width: 2.0,
        height: 1.0,
        nx: PLUG2D_DEMO_DIVISIONS.0,
        ny: PLUG2D_DEMO_DIVISIONS.1,
        simplices: false,
    }
    .mesh()?;
    let model = Model::build(
        mesh,
        Material::new(10e6, 0.3, Plane::Strain)?,
        &plug_spec(false),
    )?;
    Ok((model, CORK2D_DEMO_MU))
}

/// The 3D cork of `wedged demo --cork` (and `examples/cork3d.toml`): a square frustum (bottom
/// side 1, top side 1.6, height 1: faces at slope 0.3 off vertical) in a pyramidal seat,
/// 2 x 2 x 1 hexahedra, nothing clamped; 16 contact nodes on the four slanted faces. Its `mu*` is
/// 0.35035, between the faces' slope and the corner edges' `0.3 sqrt(2)`.
pub fn cork3d_demo() -> Result<(crate::fe::Model, f64), crate::fe::FeError> {
    use crate::fe::generate::Frustum;
    use crate::fe::{Material, Model, Plane};
    let mesh = Frustum {
        bottom_width: 1.0,
        top_width: 1.6,
        height: 1.0,
        n: 2,
        nz: 1,
        simplices: false,
    }
    .mesh()?;
    let model = Model::build(
        mesh,
        Material::new(10e6, 0.3, Plane::Strain)?,
        &plug_spec(false),
    )?;
    Ok((model, 0.5))
}

/// Friction coefficient of the cork demo (above its `mu* = 0.5`).
pub const CORK2D_DEMO_MU: f64 = 0.8;

/// The 2D plug of the demo with `nx x ny` quadrilaterals (bottom width 1, top width 2, height 1,
/// steel, plane strain, nu = 0.3; top clamped, both slanted sides in contact): `2 ny` contact
/// nodes. `plug2d(10, 8)` (m = 16) and `plug2d(38, 30)` (m = 60) are the critical-coefficient
/// benchmarks; the mesh study refines it.
pub fn plug2d(nx: usize, ny: usize) -> Result<crate::fe::Model, crate::fe::FeError> {
    use crate::fe::generate::Plug2d;
    let mesh = Plug2d {
        bottom_width: 1.0,
        top_width: 2.0,
        height: 1.0,
        nx,
        ny,
        simplices: false,
    }
    .mesh()?;
    steel_plug(mesh)
}

/// The plug of issue 20's scale study: the plug of [`plug2d`] on an `n x n` triangle mesh (each
/// quadrilateral cut in two), `m = 2n` contact nodes. (Its units do not matter: scaling `K` does
/// not change the rays, pieces or `mu*`.)
pub fn plug2d_tri(n: usize) -> Result<crate::fe::Model, crate::fe::FeError> {
    use crate::fe::generate::Plug2d;
    let mesh = Plug2d {
        bottom_width: 1.0,
        top_width: 2.0,
        height: 1.0,
        nx: n,
        ny: n,
        simplices: true,
    }
    .mesh()?;
    steel_plug(mesh)
}

/// The condensation benchmark bodies: a wide, shallow 2D plug (bottom width 10, top width 12,
/// height 1, nearly square elements) and a wide 3D V-groove plug (bottom width 30, top width 32,
/// height 1, length 8), each steel, top clamped, both slanted sides in contact. Sizes in
/// BENCHMARKS.md: `wide_plug2d(989, 100)` has 200,000 dofs and 200 contact nodes;
/// `wide_vgroove(332, 24, 3)` has 99,900 dofs and 150 contact nodes.
pub fn wide_plug2d(nx: usize, ny: usize) -> Result<crate::fe::Model, crate::fe::FeError> {
    use crate::fe::generate::Plug2d;
    let mesh = Plug2d {
        bottom_width: 10.0,
        top_width: 12.0,
        height: 1.0,
        nx,
        ny,
        simplices: false,
    }
    .mesh()?;
    steel_plug(mesh)
}

/// See [`wide_plug2d`].
pub fn wide_vgroove(
    nx: usize,
    ny: usize,
    nz: usize,
) -> Result<crate::fe::Model, crate::fe::FeError> {
    use crate::fe::generate::VGroove;
    let mesh = VGroove {
        bottom_width: 30.0,
        top_width: 32.0,
        height: 1.0,
        length: 8.0,
        nx,
        ny,
        nz,
        simplices: false,
    }
    .mesh()?;
    steel_plug(mesh)
}

/// The 3D plug: the demo's V-notch plug extruded into a V-groove (bottom width 1, top width 2,
/// height 1, length 1; steel), its top face clamped, both slanted faces in contact, meshed with
/// `4 x ny x nz` hexahedra. It has `2 nz (ny + 1)` contact nodes (the top row is clamped):
/// `plug3d(4, 2)` has 20, the size of the branch-and-bound benchmark.
pub fn plug3d(ny: usize, nz: usize) -> Result<crate::fe::Model, crate::fe::FeError> {
    use crate::fe::generate::VGroove;
    let mesh = VGroove {
        bottom_width: 1.0,
        top_width: 2.0,
        height: 1.0,
        length: 1.0,
        nx: 4,
        ny,
        nz,
        simplices: false,
    }
    .mesh()?;
    steel_plug(mesh)
}

/// A generated plug body in steel (plane strain in 2D), contact on its group `contact`,
/// clamped on `top`, condensed.
fn steel_plug(mesh: crate::fe::Mesh) -> Result<crate::fe::Model, crate::fe::FeError> {
    use crate::fe::{Material, Model, Plane};
    Model::build(
        mesh,
        Material::new(210e9, 0.3, Plane::Strain)?,
        &plug_spec(true),
    )
}

/// Contact on the generated group `contact`, and with `clamp` a clamp on `top` (without, the
/// body floats: the corks).
fn plug_spec(clamp: bool) -> crate::fe::BoundarySpec {
    crate::fe::BoundarySpec {
        contact: vec![crate::fe::ContactSpec {
            group: "contact".to_string(),
            normal: None,
        }],
        clamp: if clamp {
            vec!["top".to_string()]
        } else {
            vec![]
        },
        symmetry: vec![],
    }
}

/// Divisions (across, up) of the demo plug.
pub const PLUG2D_DEMO_DIVISIONS: (usize, usize) = (8, 6);
/// Friction coefficient of the demo.
pub const PLUG2D_DEMO_MU: f64 = 1.8;

/// A seeded random 2D problem with `K = A A^T + diag(d)`: `A` is `2m x 2m` with entries uniform
/// in `[-1, 1)`, `d` uniform in `[0.05, 1)`. The generator is a fixed 64-bit LCG, so the problem
/// depends on `seed` only (benchmarks and the CLI can name it).
pub fn random_spd_problem(m: usize, mu: f64, seed: u64) -> Problem {
    // Every pair of nodes is within m of each other: the band keeps every entry.
    banded_spd_problem(m, m, mu, seed)
}

/// A seeded random 2D problem with local coupling, like a condensed finite-element contact
/// boundary: `K = A A^T + diag(d)` where `A[i][j]` is nonzero only when the nodes of `i` and `j`
/// are at most `band` apart along the boundary (every entry is drawn, so `band >= m - 1` gives
/// [`random_spd_problem`]).
pub fn banded_spd_problem(m: usize, band: usize, mu: f64, seed: u64) -> Problem {
    seeded_spd_problem(2, m, band, mu, seed)
}

/// `K = A A^T + diag(d)` in dimension `dim`, `A[i][j]` kept when the nodes of `i` and `j` are at
/// most `band` apart; entries drawn in column order from a fixed 64-bit LCG seeded by `seed`.
fn seeded_spd_problem(dim: usize, m: usize, band: usize, mu: f64, seed: u64) -> Problem {
    let n = dim * m;
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut uniform = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let a = DMatrix::from_fn(n, n, |i, j| {
        let x = 2.0 * uniform() - 1.0;
        if (i / dim).abs_diff(j / dim) <= band {
            x
        } else {
            0.0
        }
    });
    let d = nalgebra::DVector::from_fn(n, |_, _| 0.05 + 0.95 * uniform());
    let k = &a * a.transpose() + DMatrix::from_diagonal(&d);
    Problem::new(dim, k, mu).expect("A A^T + diag(d) with d > 0 is positive definite")
}

/// Several independent bodies (or contact patches that do not interact), each a seeded random
/// [`random_spd_problem`] of `block` nodes: `K` is block diagonal, `m` must be a multiple of
/// `block`. Its wedged configurations are those of each block with the other blocks grazing.
pub fn block_spd_problem(m: usize, block: usize, mu: f64, seed: u64) -> Problem {
    assert!(block > 0 && m % block == 0, "m must be a multiple of block");
    let n = 2 * m;
    let mut k = DMatrix::<f64>::zeros(n, n);
    for b in 0..m / block {
        let part = random_spd_problem(block, mu, seed.wrapping_add(b as u64));
        let o = 2 * block * b;
        k.view_mut((o, o), (2 * block, 2 * block))
            .copy_from(part.stiffness());
    }
    Problem::new(2, k, mu).expect("a block diagonal of SPD blocks is SPD")
}

/// `p` in other units per node: `S K S`, node `i`'s block scaled by `s[i % s.len()]` (`u_i / s_i`,
/// `r_i s_i`). The same wedged problem (signs, complementarity and friction cones are per node),
/// so every answer must be the same; a mesh whose stiffness varies by orders of magnitude looks
/// like this. Panics if the result is not a valid problem (a scale of zero or not finite).
pub fn node_scaled(p: &Problem, s: &[f64]) -> Problem {
    let d = p.dim();
    let k = p.stiffness();
    let n = k.nrows();
    let f = |a: usize| s[(a / d) % s.len()];
    Problem::new(
        d,
        DMatrix::from_fn(n, n, |a, b| f(a) * k[(a, b)] * f(b)),
        p.mu(),
    )
    .expect("positive finite scales keep K definite")
}

/// A seeded random problem of dimension `dim` (2 or 3) with `K = A A^T + diag(d)`, `A` square
/// with entries uniform in `[-1, 1)`, `d` uniform in `[0.05, 1)` (the 2D one is
/// [`random_spd_problem`]'s matrix).
pub fn random_spd_problem_dim(dim: usize, m: usize, mu: f64, seed: u64) -> Problem {
    // Every pair of nodes is within m of each other: the band keeps every entry.
    seeded_spd_problem(dim, m, m, mu, seed)
}

/// A seeded random floating body in a rigid V-notch (2D) or conical seat (3D) with half angle
/// `half_angle` (radians, between each wall and the vertical axis): `m` contact nodes at random
/// distances from the apex (in 2D alternately on the left and the right wall, in 3D at random
/// angles around the axis), the body's rigid motions at them in the nodes' frames (normal into
/// the body, then the tangents), and `K = P A A^T P` with `A` random and `P` the projection off
/// the rigid motions, so that `K` is positive semidefinite with exactly those null vectors.
///
/// Equilibrium along the axis (the walls push the body up with `sin(half_angle) r_n` per node,
/// friction holds it back with at most `mu cos(half_angle) r_n`) makes `tan(half_angle)` a lower
/// bound of `mu*`.
pub fn floating_notch(dim: usize, m: usize, half_angle: f64, mu: f64, seed: u64) -> Problem {
    assert!(dim == 2 || dim == 3, "dim must be 2 or 3");
    let n = dim * m;
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut uniform = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (s, c) = half_angle.sin_cos();
    let modes = if dim == 2 { 3 } else { 6 };
    let mut rigid = DMatrix::<f64>::zeros(n, modes);
    for i in 0..m {
        let dist = 1.0 + uniform();
        // Position, normal into the body, tangent(s); 2D vectors padded with z = 0.
        let (x, frame): ([f64; 3], Vec<[f64; 3]>) = if dim == 2 {
            let side = if i % 2 == 0 { -1.0 } else { 1.0 };
            let x = [side * s * dist, c * dist, 0.0];
            let normal = [-side * c, s, 0.0];
            (x, vec![normal, [normal[1], -normal[0], 0.0]])
        } else {
            let phi = 2.0 * std::f64::consts::PI * uniform();
            let (sp, cp) = phi.sin_cos();
            let x = [s * cp * dist, s * sp * dist, c * dist];
            let normal = [-c * cp, -c * sp, s];
            let t1 = [-sp, cp, 0.0];
            let t2 = [
                normal[1] * t1[2] - normal[2] * t1[1],
                normal[2] * t1[0] - normal[0] * t1[2],
                normal[0] * t1[1] - normal[1] * t1[0],
            ];
            (x, vec![normal, t1, t2])
        };
        // Rigid velocities at x: translations, then rotations w x X (2D: about z only).
        let mut motions: Vec<[f64; 3]> = (0..dim)
            .map(|a| {
                let mut e = [0.0; 3];
                e[a] = 1.0;
                e
            })
            .collect();
        let axes: &[usize] = if dim == 2 { &[2] } else { &[0, 1, 2] };
        for &a in axes {
            let mut w = [0.0; 3];
            w[a] = 1.0;
            motions.push([
                w[1] * x[2] - w[2] * x[1],
                w[2] * x[0] - w[0] * x[2],
                w[0] * x[1] - w[1] * x[0],
            ]);
        }
        for (j, v) in motions.iter().enumerate() {
            for (cpt, e) in frame.iter().enumerate() {
                rigid[(dim * i + cpt, j)] = e[0] * v[0] + e[1] * v[1] + e[2] * v[2];
            }
        }
    }
    let a = DMatrix::from_fn(n, n, |_, _| 2.0 * uniform() - 1.0);
    let q = rigid.clone().qr().q();
    let p = DMatrix::identity(n, n) - &q * q.transpose();
    let k = &p * (&a * a.transpose()) * &p;
    Problem::floating(dim, k, rigid, mu).expect("P A A^T P is semidefinite with null space R")
}
