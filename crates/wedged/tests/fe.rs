//! The finite-element front end against dense computations: condensation equals the dense Schur
//! complement, the condensed stiffness is symmetric positive definite, and a contact
//! displacement mapped back to the mesh is in equilibrium with reactions only where the body is
//! held.

use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wedged::fe::generate::{Frustum, Plug2d, VGroove};
use wedged::fe::{element, BoundarySpec, ContactSpec, FeError, Material, Mesh, Model, Plane};
use wedged::{enumerate, Settings};

fn spec(contact: &[&str], clamp: &[&str], symmetry: &[&str]) -> BoundarySpec {
    BoundarySpec {
        contact: contact
            .iter()
            .map(|g| ContactSpec {
                group: g.to_string(),
                normal: None,
            })
            .collect(),
        clamp: clamp.iter().map(|g| g.to_string()).collect(),
        symmetry: symmetry.iter().map(|g| (g.to_string(), None)).collect(),
    }
}

fn steel(plane: Plane) -> Material {
    Material::new(210e9, 0.3, plane).unwrap()
}

/// The dense global stiffness, assembled without any of the condensation code.
fn dense_k(mesh: &Mesh, material: &Material) -> DMatrix<f64> {
    let dim = mesh.dim();
    let n = dim * mesh.node_count();
    let mut k = DMatrix::zeros(n, n);
    for e in mesh.elements() {
        let ke = element::stiffness(e.kind, &mesh.element_coords(e), material).unwrap();
        for (p, &a) in e.nodes.iter().enumerate() {
            for (q, &b) in e.nodes.iter().enumerate() {
                for i in 0..dim {
                    for j in 0..dim {
                        k[(dim * a + i, dim * b + j)] += ke[(dim * p + i, dim * q + j)];
                    }
                }
            }
        }
    }
    k
}

/// Dense condensation: `T` maps (contact unknowns in frames, then free unknowns) to global
/// dofs; the Schur complement is formed with a dense inverse (fine at this size).
fn dense_condensed(model: &Model) -> DMatrix<f64> {
    let mesh = model.mesh();
    let b = model.boundary();
    let dim = mesh.dim();
    let n = dim * mesh.node_count();
    let mut columns: Vec<DVector<f64>> = Vec::new();
    for (i, &a) in b.contact_nodes.iter().enumerate() {
        for axis in b.frames[i].axes().iter().take(dim) {
            let mut c = DVector::zeros(n);
            for k in 0..dim {
                c[dim * a + k] = axis[k];
            }
            columns.push(c);
        }
    }
    let nc = columns.len();
    for a in 0..mesh.node_count() {
        if b.contact_nodes.contains(&a) || b.clamped.contains(&a) {
            continue;
        }
        // The free directions: the null space of the roller directions.
        let dirs: Vec<[f64; 3]> = b
            .rollers
            .iter()
            .find(|(r, _)| *r == a)
            .map(|(_, d)| d.clone())
            .unwrap_or_default();
        let mut p = DMatrix::<f64>::identity(dim, dim);
        for d in &dirs {
            let v = DVector::from_iterator(dim, d.iter().take(dim).copied());
            p -= &v * v.transpose();
        }
        let svd = p.svd(true, false);
        let u = svd.u.unwrap();
        for s in 0..dim {
            if svd.singular_values[s] > 0.5 {
                let mut c = DVector::zeros(n);
                for k in 0..dim {
                    c[dim * a + k] = u[(k, s)];
                }
                columns.push(c);
            }
        }
    }
    let t = DMatrix::from_columns(&columns);
    let kr = t.transpose() * dense_k(mesh, model.material()) * &t;
    let no = kr.nrows() - nc;
    let kcc = kr.view((0, 0), (nc, nc));
    let koc = kr.view((nc, 0), (no, nc));
    let koo = kr.view((nc, nc), (no, no)).clone_owned();
    let x = koo.cholesky().unwrap().solve(&koc.clone_owned());
    kcc - koc.transpose() * x
}

fn assert_close(a: &DMatrix<f64>, b: &DMatrix<f64>, rel: f64, what: &str) {
    let scale = b.amax();
    let diff = (a - b).amax();
    assert!(
        diff <= rel * scale,
        "{what}: condensed K differs from the dense Schur complement by {diff:e} (scale {scale:e})"
    );
}

fn plug2d(nx: usize, ny: usize, simplices: bool) -> Mesh {
    Plug2d {
        bottom_width: 1.0,
        top_width: 2.0,
        height: 1.0,
        nx,
        ny,
        simplices,
    }
    .mesh()
    .unwrap()
}

fn vgroove(simplices: bool) -> Mesh {
    VGroove {
        bottom_width: 1.0,
        top_width: 1.6,
        height: 1.0,
        length: 1.5,
        nx: 3,
        ny: 2,
        nz: 2,
        simplices,
    }
    .mesh()
    .unwrap()
}

fn frustum(simplices: bool) -> Mesh {
    Frustum {
        bottom_width: 1.0,
        top_width: 1.8,
        height: 1.2,
        n: 3,
        nz: 2,
        simplices,
    }
    .mesh()
    .unwrap()
}

/// Every body family, with clamps and (slanted, so not axis-aligned) rollers.
fn cases() -> Vec<(String, Mesh, Material, BoundarySpec)> {
    let mut cases = Vec::new();
    for simplices in [false, true] {
        let tag = if simplices { "simplices" } else { "bricks" };
        for plane in [Plane::Strain, Plane::Stress] {
            cases.push((
                format!("plug2d {tag} {plane:?}"),
                plug2d(4, 3, simplices),
                steel(plane),
                spec(&["contact"], &["top"], &[]),
            ));
        }
        cases.push((
            format!("plug2d {tag}, roller on the slanted right side"),
            plug2d(4, 3, simplices),
            steel(Plane::Strain),
            spec(&["left"], &["bottom"], &["right"]),
        ));
        cases.push((
            format!("vgroove {tag}"),
            vgroove(simplices),
            steel(Plane::Strain),
            spec(&["contact"], &["top"], &[]),
        ));
        cases.push((
            format!("frustum {tag}, roller on xmax"),
            frustum(simplices),
            Material::new(3.0, 0.25, Plane::Strain).unwrap(),
            spec(&["xmin"], &["top"], &["xmax"]),
        ));
    }
    cases
}

#[test]
fn condensation_equals_the_dense_schur_complement() {
    for (name, mesh, material, spec) in cases() {
        let model = Model::build(mesh, material, &spec).unwrap();
        let dense = dense_condensed(&model);
        assert_close(model.k(), &dense, 1e-10, &name);
        // Symmetric, and positive definite: a clamp exists.
        assert_eq!(model.k(), &model.k().transpose(), "{name}");
        let eig = model.k().clone().symmetric_eigen();
        let min = eig.eigenvalues.min();
        assert!(
            min > 1e-9 * eig.eigenvalues.max(),
            "{name}: min eigenvalue {min:e}"
        );
        model.problem(1.0).unwrap();
    }
}

/// `K u` of a recovered field: zero at free nodes, the frame reaction at contact nodes, along
/// the constrained directions at rollers; total force and moment vanish.
fn check_equilibrium(model: &Model, u_c: &[f64], name: &str) {
    let mesh = model.mesh();
    let b = model.boundary();
    let dim = mesh.dim();
    let state = model.recover(u_c);
    let r = model.k() * DVector::from_column_slice(u_c);
    let scale = state
        .force
        .iter()
        .flat_map(|f| f.iter().map(|v| v.abs()))
        .fold(0.0, f64::max);
    assert!(scale > 0.0);
    let tol = 1e-9 * scale;
    for a in 0..mesh.node_count() {
        let f = state.force[a];
        if let Some(i) = b.contact_nodes.iter().position(|&c| c == a) {
            let expected = b.frames[i].to_global(&r.as_slice()[dim * i..][..dim]);
            for k in 0..3 {
                assert!(
                    (f[k] - expected[k]).abs() <= tol,
                    "{name}: contact node {a}: force {f:?}, reaction {expected:?}"
                );
            }
        } else if b.clamped.contains(&a) {
            // Any reaction.
        } else if let Some((_, dirs)) = b.rollers.iter().find(|(r, _)| *r == a) {
            // The force is along the constrained directions.
            let mut rest = f;
            for d in dirs {
                let p = rest[0] * d[0] + rest[1] * d[1] + rest[2] * d[2];
                for k in 0..3 {
                    rest[k] -= p * d[k];
                }
            }
            assert!(
                rest.iter().all(|v| v.abs() <= tol),
                "{name}: roller {a}: {f:?}"
            );
        } else {
            assert!(
                f.iter().all(|v| v.abs() <= tol),
                "{name}: free node {a} carries a force {f:?} (scale {scale:e})"
            );
        }
    }
    let mut total = [0.0; 3];
    let mut moment = [0.0; 3];
    for (x, f) in mesh.coords().iter().zip(&state.force) {
        for k in 0..3 {
            total[k] += f[k];
        }
        moment[0] += x[1] * f[2] - x[2] * f[1];
        moment[1] += x[2] * f[0] - x[0] * f[2];
        moment[2] += x[0] * f[1] - x[1] * f[0];
    }
    let size = mesh.size();
    assert!(
        total.iter().all(|v| v.abs() <= tol),
        "{name}: total force {total:?}"
    );
    assert!(
        moment.iter().all(|v| v.abs() <= tol * size),
        "{name}: total moment {moment:?}"
    );
    // The recovered contact displacements are the input ones.
    for (i, &a) in b.contact_nodes.iter().enumerate() {
        let local = b.frames[i].to_local(&state.displacement[a], dim);
        for c in 0..dim {
            assert!(
                (local[c] - u_c[dim * i + c]).abs()
                    <= 1e-12 * u_c.iter().map(|v| v.abs()).fold(0.0, f64::max)
            );
        }
    }
    assert_eq!(state.stress.len(), mesh.elements().len());
    assert!(state.von_mises.iter().all(|v| v.is_finite() && *v >= 0.0));
}

#[test]
fn recovered_fields_are_in_equilibrium() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (name, mesh, material, spec) in cases() {
        let model = Model::build(mesh, material, &spec).unwrap();
        for _ in 0..3 {
            let u_c: Vec<f64> = (0..model.k().nrows())
                .map(|_| rng.gen_range(-1e-3..1e-3))
                .collect();
            check_equilibrium(&model, &u_c, &name);
        }
    }
}

#[test]
fn wedged_rays_of_the_plug_map_back_to_equilibria() {
    let model = Model::build(
        plug2d(6, 4, false),
        steel(Plane::Strain),
        &spec(&["contact"], &["top"], &[]),
    )
    .unwrap();
    let problem = model.problem(2.0).unwrap();
    let result = enumerate(&problem, &Settings::default()).unwrap();
    assert!(!result.rays.is_empty(), "the plug should wedge at mu = 2");
    for (k, ray) in result.rays.iter().enumerate() {
        check_equilibrium(&model, &ray.u, &format!("ray {k}"));
    }
}

#[test]
fn rigid_displacements_of_contact_nodes_give_no_stress_without_clamps() {
    // Without a clamp the body floats: the condensed K is singular along rigid motions, and the
    // factorisation of the rest must still succeed (the contact nodes hold it).
    let model = Model::build(
        plug2d(3, 2, false),
        steel(Plane::Strain),
        &spec(&["contact"], &[], &[]),
    )
    .unwrap();
    let b = model.boundary();
    // A translation by (1, 0.5) in local frames.
    let u_c: Vec<f64> = b
        .frames
        .iter()
        .flat_map(|f| f.to_local(&[1.0, 0.5, 0.0], 2))
        .collect();
    let state = model.recover(&u_c);
    for d in &state.displacement {
        assert!(
            (d[0] - 1.0).abs() < 1e-9 && (d[1] - 0.5).abs() < 1e-9,
            "{d:?}"
        );
    }
    assert!(state
        .von_mises
        .iter()
        .all(|v| v.abs() < 1e-3 * 210e9 * 1e-9));
    // Nothing clamps it: a floating body with its three rigid motions (issue 22).
    let p = model.problem(1.0).unwrap();
    assert!(p.is_floating());
    assert_eq!(p.rigid_modes().ncols(), 3);
}

/// A floating body's rigid modes are the null space of its condensed stiffness: `K R = 0` to
/// round-off, and `K` is definite off them (`Problem::floating` checks both). A roller on the
/// right side (its normal) stops every rigid motion but the slide along that side, the one mode
/// left when the left side is the contact; in 3D an unclamped body keeps all six.
#[test]
fn the_rigid_modes_of_a_floating_body_are_its_null_space() {
    let free = Model::build(
        plug2d(4, 3, false),
        steel(Plane::Strain),
        &spec(&["contact"], &[], &[]),
    )
    .unwrap();
    let rolled = Model::build(
        plug2d(4, 3, false),
        steel(Plane::Strain),
        &spec(&["left"], &[], &["right"]),
    )
    .unwrap();
    for (model, modes) in [(&free, 3), (&rolled, 1)] {
        let r = model.rigid_modes();
        assert_eq!(r.ncols(), modes);
        let kr = model.k() * r;
        assert!(
            kr.amax() <= 1e-9 * model.k().amax() * r.amax(),
            "{}",
            kr.amax()
        );
        let p = model.problem(1.0).unwrap();
        assert_eq!(p.rigid_modes().ncols(), modes);
    }
    // The slide along the right side, (0.5, 1) from its bottom to its top, at every node.
    let b = rolled.boundary();
    let r = rolled.rigid_modes();
    for (i, f) in b.frames.iter().enumerate() {
        let v = f.to_global(&[r[(2 * i, 0)], r[(2 * i + 1, 0)]]);
        let along = (v[0] * 1.0 - v[1] * 0.5).abs();
        assert!(along <= 1e-12 * r.amax(), "node {i}: {v:?}");
        assert!(v[0].abs() + v[1].abs() > 0.1 * r.amax(), "node {i}: {v:?}");
    }
    let cone = Model::build(
        frustum(false),
        steel(Plane::Strain),
        &spec(&["contact"], &[], &[]),
    )
    .unwrap();
    assert_eq!(cone.rigid_modes().ncols(), 6);
    let kr = cone.k() * cone.rigid_modes();
    assert!(kr.amax() <= 1e-9 * cone.k().amax() * cone.rigid_modes().amax());
    assert_eq!(cone.problem(1.0).unwrap().rigid_modes().ncols(), 6);
}

/// Two bodies that nothing clamps could each move on their own: refused, naming a node of each.
#[test]
fn two_floating_parts_are_refused() {
    let mesh = plug2d(2, 1, false);
    let count = mesh.coords().len();
    let mut coords = mesh.coords().to_vec();
    coords.extend(mesh.coords().iter().map(|x| [x[0] + 10.0, x[1], x[2]]));
    let mut elements = mesh.elements().to_vec();
    elements.extend(mesh.elements().iter().map(|e| wedged::fe::Element {
        kind: e.kind,
        nodes: e.nodes.iter().map(|a| a + count).collect(),
    }));
    let groups = mesh
        .groups()
        .iter()
        .map(|g| {
            let mut g = g.clone();
            let shifted: Vec<Vec<usize>> = g
                .entities
                .iter()
                .map(|e| e.iter().map(|a| a + count).collect())
                .collect();
            g.entities.extend(shifted);
            g
        })
        .collect();
    let mesh = Mesh::new(2, coords, elements, groups).unwrap();
    let e = Model::build(mesh, steel(Plane::Strain), &spec(&["contact"], &[], &[])).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("disconnected parts"), "{text}");
    assert!(
        text.contains("node 1 ") && text.contains(&format!("node {}", count + 1)),
        "{text}"
    );
}

#[test]
fn boundary_errors_are_named() {
    let err = |spec: BoundarySpec| {
        Model::build(plug2d(3, 2, false), steel(Plane::Strain), &spec)
            .unwrap_err()
            .to_string()
    };
    let e = err(spec(&["wall"], &["top"], &[]));
    assert!(
        e.contains("contact group 'wall' does not exist") && e.contains("'contact'"),
        "{e}"
    );
    let e = err(spec(&["contact"], &["lid"], &[]));
    assert!(e.contains("clamp group 'lid'"), "{e}");
    let e = err(spec(&["contact"], &["top"], &["bottom"]));
    assert!(
        e.contains("both a contact node") && e.contains("'bottom'"),
        "{e}"
    );
    let e = err(spec(&[], &["top"], &[]));
    assert!(e.contains("no contact group"), "{e}");
    let e = err(spec(&["body"], &["top"], &[]));
    assert!(e.contains("2D elements"), "{e}");
    let e = err(spec(&["top"], &["top"], &[]));
    assert!(e.contains("no contact node left"), "{e}");
    // Contact nodes that are clamped are clamped, and counted.
    let model = Model::build(
        plug2d(3, 2, false),
        steel(Plane::Strain),
        &spec(&["contact"], &["top"], &[]),
    )
    .unwrap();
    assert_eq!(model.boundary().clamped_contact, 2);
    assert_eq!(model.boundary().contact_nodes.len(), 4);
}

#[test]
fn a_disconnected_piece_is_not_held() {
    let mesh = plug2d(2, 1, false);
    let mut coords = mesh.coords().to_vec();
    let mut elements = mesh.elements().to_vec();
    // A loose square far away.
    let base = coords.len();
    for p in [[5.0, 0.0], [6.0, 0.0], [6.0, 1.0], [5.0, 1.0]] {
        coords.push([p[0], p[1], 0.0]);
    }
    elements.push(wedged::fe::Element {
        kind: wedged::fe::ElementKind::Quad4,
        nodes: (base..base + 4).collect(),
    });
    let mesh = Mesh::new(2, coords, elements, mesh.groups().to_vec()).unwrap();
    let e = Model::build(
        mesh,
        steel(Plane::Strain),
        &spec(&["contact"], &["top"], &[]),
    )
    .unwrap_err();
    assert!(matches!(e, FeError::NotHeld(_)), "{e}");
    assert!(e.to_string().contains(&format!("node {}", base + 1)), "{e}");
}

#[test]
fn normals_point_into_the_body_and_frames_are_right_handed() {
    let model = Model::build(
        plug2d(2, 2, false),
        steel(Plane::Strain),
        &spec(&["contact"], &["top"], &[]),
    )
    .unwrap();
    let mesh = model.mesh();
    for (i, &a) in model.boundary().contact_nodes.iter().enumerate() {
        let f = model.boundary().frames[i];
        let x = mesh.coords()[a];
        // Left wall: the inward normal points right (+x), and up, since the wall leans out.
        let expected: [f64; 2] = if x[0] < 0.0 { [1.0, 0.5] } else { [-1.0, 0.5] };
        let l = (expected[0] * expected[0] + expected[1] * expected[1]).sqrt();
        assert!(
            (f.n[0] - expected[0] / l).abs() < 1e-12 && (f.n[1] - expected[1] / l).abs() < 1e-12
        );
        assert_eq!(f.t1, [-f.n[1], f.n[0], 0.0]);
    }
    let model = Model::build(
        frustum(false),
        steel(Plane::Strain),
        &spec(&["contact"], &["top"], &[]),
    )
    .unwrap();
    for f in &model.boundary().frames {
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        assert!((dot(f.n, f.n) - 1.0).abs() < 1e-12 && dot(f.n, f.t1).abs() < 1e-12);
        let c = [
            f.n[1] * f.t1[2] - f.n[2] * f.t1[1],
            f.n[2] * f.t1[0] - f.n[0] * f.t1[2],
            f.n[0] * f.t1[1] - f.n[1] * f.t1[0],
        ];
        assert!((0..3).all(|k| (c[k] - f.t2[k]).abs() < 1e-12));
        // The pyramid's walls lean out: every inward normal has an upward component.
        assert!(f.n[2] > 0.0);
    }
}

#[test]
fn the_mean_of_states_is_the_state_of_the_mean() {
    let model = Model::build(
        plug2d(4, 3, true),
        steel(Plane::Strain),
        &spec(&["contact"], &["top"], &[]),
    )
    .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let n = model.k().nrows();
    let us: Vec<Vec<f64>> = (0..3)
        .map(|_| (0..n).map(|_| rng.gen_range(-1e-3..1e-3)).collect())
        .collect();
    let mean_u: Vec<f64> = (0..n)
        .map(|i| us.iter().map(|u| u[i]).sum::<f64>() / 3.0)
        .collect();
    let states: Vec<_> = us.iter().map(|u| model.recover(u)).collect();
    let mean = wedged::fe::Configuration::mean(&states.iter().collect::<Vec<_>>());
    let direct = model.recover(&mean_u);
    let close = |a: &[f64], b: &[f64]| {
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-12 * scale)
    };
    let flat3 = |v: &[[f64; 3]]| v.iter().flatten().copied().collect::<Vec<_>>();
    let flat6 = |v: &[[f64; 6]]| v.iter().flatten().copied().collect::<Vec<_>>();
    assert!(close(
        &flat3(&mean.displacement),
        &flat3(&direct.displacement)
    ));
    assert!(close(&flat3(&mean.force), &flat3(&direct.force)));
    assert!(close(&flat6(&mean.stress), &flat6(&direct.stress)));
    assert!(close(&mean.von_mises, &direct.von_mises));
}
