//! The three methods against each other on seeded random problems, with degenerate families, and
//! against the one-node closed form.
//!
//! `faces` (brute force over contact sets and tight sets) shares no enumeration code with the two
//! double descriptions; `full-dd` decides adjacency combinatorially, `pruned-dd` algebraically.

mod common;

use common::random_spd;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wedged::{enumerate, Enumeration, Method, NodeStatus, Outcome, Problem, Settings};

/// Mirror symmetry: node `i` and node `m-1-i` are images with the tangent flipped.
fn mirrored(k: &DMatrix<f64>) -> DMatrix<f64> {
    let n = k.nrows();
    let m = n / 2;
    let mut p = DMatrix::<f64>::zeros(n, n);
    for i in 0..m {
        let j = m - 1 - i;
        p[(2 * j, 2 * i)] = 1.0;
        p[(2 * j + 1, 2 * i + 1)] = -1.0;
    }
    (k + &p * k * p.transpose()) * 0.5
}

fn run(problem: &Problem, method: Method) -> Enumeration {
    let settings = Settings {
        method,
        ..Settings::default()
    };
    enumerate(problem, &settings)
        .unwrap_or_else(|e| panic!("{method} failed: {e}\nK = {}", problem.stiffness()))
}

/// Same rays (status vectors and values) and the same cones.
fn assert_same(a: &Enumeration, b: &Enumeration, what: &str) {
    let sa: Vec<_> = a.rays.iter().map(|r| r.status.clone()).collect();
    let sb: Vec<_> = b.rays.iter().map(|r| r.status.clone()).collect();
    assert_eq!(sa, sb, "{what}: ray sets differ");
    for (x, y) in a.rays.iter().zip(&b.rays) {
        let d =
            x.r.iter()
                .zip(&y.r)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
        assert!(d < 1e-9, "{what}: ray values differ by {d}");
    }
    assert_eq!(a.cones, b.cones, "{what}: cones differ");
}

fn check_all_methods(problem: &Problem, what: &str) -> Enumeration {
    let pruned = run(problem, Method::PrunedDd);
    let full = run(problem, Method::FullDd);
    let faces = run(problem, Method::Faces);
    let search = run(problem, Method::Search);
    assert_same(&pruned, &full, &format!("{what}: pruned-dd vs full-dd"));
    assert_same(&pruned, &faces, &format!("{what}: pruned-dd vs faces"));
    assert_same(&pruned, &search, &format!("{what}: pruned-dd vs search"));
    pruned
}

#[test]
fn methods_agree_on_random_problems() {
    let mut rng = ChaCha8Rng::seed_from_u64(20081);
    let mut wedged = 0;
    let mut total_rays = 0;
    for trial in 0..280 {
        let m = 1 + trial % 7;
        let mu = [0.5, 1.0, 2.0, 3.0, 5.0][trial % 5] * rng.gen_range(0.8..1.25);
        let k = random_spd(&mut rng, 2 * m);
        let p = Problem::new(2, k, mu).unwrap();
        let e = check_all_methods(&p, &format!("trial {trial} (m = {m}, mu = {mu})"));
        wedged += (e.outcome == Outcome::Wedged) as usize;
        total_rays += e.rays.len();
    }
    // The family must exercise both outcomes and non-trivial ray sets, or the test proves little.
    assert!(wedged > 100 && wedged < 280, "wedged in {wedged} of 280");
    assert!(total_rays > 500, "only {total_rays} rays in all");
}

#[test]
fn methods_agree_on_mirror_symmetric_problems() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for trial in 0..60 {
        let m = 2 + trial % 5;
        let k = mirrored(&random_spd(&mut rng, 2 * m));
        let p = Problem::new(2, k, rng.gen_range(0.4..2.5)).unwrap();
        let e = check_all_methods(&p, &format!("mirror trial {trial}"));
        // The mirror image of every ray is a ray: statuses reversed with slip+ and slip- swapped.
        for ray in &e.rays {
            let image: Vec<NodeStatus> = ray
                .status
                .iter()
                .rev()
                .map(|s| match s {
                    NodeStatus::SlipPlus => NodeStatus::SlipMinus,
                    NodeStatus::SlipMinus => NodeStatus::SlipPlus,
                    s => *s,
                })
                .collect();
            assert!(
                e.rays.iter().any(|q| q.status == image),
                "mirror trial {trial}"
            );
        }
    }
}

/// Decoupled nodes and zero normal-tangential couplings: many rays lie exactly on constraints.
#[test]
fn methods_agree_on_degenerate_problems() {
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    for trial in 0..80 {
        let m = 2 + trial % 5;
        let mut k = random_spd(&mut rng, 2 * m);
        let n = 2 * m;
        match trial % 4 {
            // Block diagonal in two groups of nodes: exact zeros in K^{-1}.
            0 => {
                let split = 1 + trial % (m - 1).max(1);
                for i in 0..n {
                    for j in 0..n {
                        if (i / 2 < split) != (j / 2 < split) {
                            k[(i, j)] = 0.0;
                        }
                    }
                }
            }
            // A node with no coupling at all: its gap is exactly zero in rays elsewhere.
            1 => {
                let c = 2 * (trial % m);
                for j in 0..n {
                    if j != c && j != c + 1 {
                        for i in [c, c + 1] {
                            k[(i, j)] = 0.0;
                            k[(j, i)] = 0.0;
                        }
                    }
                }
            }
            // Identical nodes: repeated stiffness blocks.
            2 => {
                let (d, o) = (k.view((0, 0), (2, 2)).clone_owned(), 0.1 * k[(0, 2)]);
                for i in 0..m {
                    for j in 0..m {
                        for a in 0..2 {
                            for b in 0..2 {
                                k[(2 * i + a, 2 * j + b)] = if i == j {
                                    d[(a, b)]
                                } else if a == b {
                                    o
                                } else {
                                    0.0
                                };
                            }
                        }
                    }
                }
                k += DMatrix::identity(n, n) * 0.5 * d.min().abs();
            }
            // Integer entries: many exact ties.
            _ => {
                k = k.map(|x| (x * 4.0).round());
                k += DMatrix::identity(n, n) * (n as f64 * 4.0);
            }
        }
        let mu = [0.25, 0.5, 1.0, 2.0][trial % 4];
        let p = Problem::new(2, k, mu).expect("family stays SPD");
        check_all_methods(
            &p,
            &format!("degenerate trial {trial} (kind {})", trial % 4),
        );
    }
}

/// Rays that sit exactly on the unilateral constraint: one node at exactly its critical `mu`
/// coupled to nodes that do not feel it.
#[test]
fn methods_agree_when_a_ray_lies_on_a_constraint() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for trial in 0..40 {
        let m = 1 + trial % 4;
        let k = random_spd(&mut rng, 2 * m);
        let g = k.clone().try_inverse().unwrap();
        // At mu = G_nn / |G_nt| of node 0, the ray e_n -/+ mu e_t of node 0 has u_n_0 = 0.
        let mu = g[(0, 0)] / g[(0, 1)].abs();
        let p = Problem::new(2, k, mu).unwrap();
        check_all_methods(&p, &format!("on-constraint trial {trial}"));
    }
}

#[test]
fn scale_does_not_change_the_answer() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for trial in 0..60 {
        let m = 1 + trial % 6;
        let k = random_spd(&mut rng, 2 * m);
        let mu = rng.gen_range(0.3..2.0);
        let base = run(&Problem::new(2, k.clone(), mu).unwrap(), Method::PrunedDd);
        for s in [1e-6, 1e6] {
            let p = Problem::new(2, &k * s, mu).unwrap();
            for method in Method::ALL {
                let e = run(&p, method);
                let sa: Vec<_> = base.rays.iter().map(|r| &r.status).collect();
                let sb: Vec<_> = e.rays.iter().map(|r| &r.status).collect();
                assert_eq!(sa, sb, "trial {trial}, scale {s}, {method}");
                for (x, y) in base.rays.iter().zip(&e.rays) {
                    // Reactions are scale-free; displacements scale by 1/s.
                    for (p, q) in x.r.iter().zip(&y.r) {
                        assert!((p - q).abs() < 1e-9);
                    }
                    for (p, q) in x.u.iter().zip(&y.u) {
                        assert!((p - q * s).abs() <= 1e-8 * p.abs().max(1e-300) + 1e-12);
                    }
                }
                assert_eq!(base.cones, e.cones);
            }
        }
    }
}

#[test]
fn permuting_nodes_permutes_the_answer() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for trial in 0..40 {
        let m = 2 + trial % 5;
        let p = Problem::new(2, random_spd(&mut rng, 2 * m), rng.gen_range(0.3..2.0)).unwrap();
        let mut order: Vec<usize> = (0..m).collect();
        order.reverse();
        order.rotate_left(trial % m);
        let a = run(&p, Method::PrunedDd);
        let b = run(&p.permuted(&order), Method::PrunedDd);
        let mut mapped: Vec<Vec<NodeStatus>> = b
            .rays
            .iter()
            .map(|ray| {
                let mut s = vec![NodeStatus::Grazing; m];
                for (new, &old) in order.iter().enumerate() {
                    s[old] = ray.status[new];
                }
                s
            })
            .collect();
        mapped.sort();
        let orig: Vec<_> = a.rays.iter().map(|r| r.status.clone()).collect();
        assert_eq!(orig, mapped, "trial {trial}");
        assert_eq!(a.cones.len(), b.cones.len());
    }
}

/// MISSION section 6: one node has a nontrivial solution iff `mu >= K_tt / |K_nt|`.
#[test]
fn one_node_closed_form() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for trial in 0..200 {
        let knn: f64 = rng.gen_range(0.5..3.0);
        let ktt: f64 = rng.gen_range(0.5..3.0);
        let knt: f64 = rng.gen_range(-0.95..0.95) * (knn * ktt).sqrt();
        let k = DMatrix::from_row_slice(2, 2, &[knn, knt, knt, ktt]);
        let critical = ktt / knt.abs();
        for (factor, expect) in [(0.99, false), (1.01, true), (1.5, true)] {
            let p = Problem::new(2, k.clone(), critical * factor).unwrap();
            for method in Method::ALL {
                let e = run(&p, method);
                assert_eq!(
                    e.outcome == Outcome::Wedged,
                    expect,
                    "trial {trial}, {method}"
                );
                if expect {
                    assert_eq!(e.rays.len(), 1);
                    // u = (0, u_t) gives r = (K_nt, K_tt) u_t: |r_t| / r_n = K_tt / |K_nt| < mu.
                    assert_eq!(e.rays[0].status, vec![NodeStatus::Stick]);
                    let r = &e.rays[0].r;
                    assert!((r[1] / r[0] - ktt / knt).abs() < 1e-9 * (ktt / knt).abs());
                    assert_eq!(e.cones.len(), 1);
                }
            }
        }
    }
    // No coupling: never wedged, however large mu is; above `RAYS_MU_MAX` only the exact
    // method takes the problem, and the others refuse it as bad input.
    let k = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
    let p = Problem::new(2, k.clone(), wedged::RAYS_MU_MAX).unwrap();
    for method in Method::ALL {
        assert_eq!(run(&p, method).outcome, Outcome::NotWedged);
    }
    let p = Problem::new(2, k, 1e6).unwrap();
    for method in Method::ALL {
        let settings = Settings {
            method,
            ..Settings::default()
        };
        match (method, enumerate(&p, &settings)) {
            (Method::Exact, Ok(e)) => assert_eq!(e.outcome, Outcome::NotWedged),
            (Method::Exact, Err(e)) => panic!("exact at mu = 1e6: {e}"),
            (_, Err(wedged::Error::InvalidSettings(why))) => {
                assert!(why.contains("mu = 1000000 is above 1e4"), "{why}")
            }
            (_, other) => panic!("{method} at mu = 1e6: {other:?}"),
        }
    }
}

/// Ill-conditioned stiffness (low-rank `A A^T` plus a diagonal down to 1e-6; condition numbers up
/// to about 1e7): every ray still verifies and the methods still agree.
#[test]
fn methods_agree_on_ill_conditioned_problems() {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    for trial in 0..150 {
        let m = 3 + trial % 5;
        let n = 2 * m;
        let cols = rng.gen_range(1..=n);
        let a = DMatrix::from_fn(n, cols, |_, _| rng.gen_range(-1.0..1.0));
        let dmin = [1e-2, 1e-4, 1e-6][trial % 3];
        let d = nalgebra::DVector::from_fn(n, |_, _| dmin * rng.gen_range(1.0..10.0));
        let k = &a * a.transpose() + DMatrix::from_diagonal(&d);
        let p = Problem::new(2, k, rng.gen_range(0.3..4.0)).unwrap();
        check_all_methods(
            &p,
            &format!("ill-conditioned trial {trial} (diagonal {dmin})"),
        );
    }
}

/// The spring-lattice plug: physical compliance, mirror symmetry, near-grazing rays.
#[test]
fn methods_agree_on_the_lattice_plug() {
    use wedged::examples::lattice_plug;
    for per_side in 1..=3 {
        for mu in [0.5, 2.2, 2.5, 3.0, 5.0] {
            check_all_methods(
                &lattice_plug(per_side, mu),
                &format!("lattice {per_side}, mu {mu}"),
            );
        }
    }
    // m = 8: faces is slow here, the two double descriptions are compared.
    for mu in [2.5, 3.0, 6.0] {
        let p = lattice_plug(4, mu);
        let what = format!("lattice 4, mu {mu}");
        assert_same(&run(&p, Method::PrunedDd), &run(&p, Method::FullDd), &what);
    }
}

/// The status of a cone's centroid, decided numerically from its values, equals the
/// combinatorial `cone_status`; and the centroid is a solution (`K u = r`, `sum r_n = 1`).
#[test]
fn cone_status_is_the_status_of_the_centroid() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let mut cones_seen = 0;
    let mut multi_ray = 0;
    for trial in 0..120 {
        let m = 2 + trial % 5;
        let mu = [1.0, 2.0, 3.0][trial % 3] * rng.gen_range(0.8..1.25);
        let p = Problem::new(2, random_spd(&mut rng, 2 * m), mu).unwrap();
        let e = run(&p, Method::PrunedDd);
        for cone in &e.cones {
            cones_seen += 1;
            multi_ray += usize::from(cone.rays.len() > 1);
            let (u, r) = e.cone_centroid(cone);
            let ku = p.stiffness() * nalgebra::DVector::from_column_slice(&u);
            let scale = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for i in 0..2 * m {
                assert!((ku[i] - r[i]).abs() <= 1e-9 * scale.max(1.0), "K u != r");
            }
            let sum_rn: f64 = (0..m).map(|i| r[2 * i]).sum();
            assert!((sum_rn - 1.0).abs() < 1e-12);
            let umax = u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let expected: Vec<NodeStatus> = (0..m)
                .map(|i| {
                    let (un, rn, rt) = (u[2 * i], r[2 * i], r[2 * i + 1]);
                    if un > 1e-9 * umax {
                        NodeStatus::Separated
                    } else if rn <= 1e-12 {
                        NodeStatus::Grazing
                    } else if (rt.abs() - mu * rn).abs() <= 1e-9 * rn {
                        if rt > 0.0 {
                            NodeStatus::SlipPlus
                        } else {
                            NodeStatus::SlipMinus
                        }
                    } else {
                        NodeStatus::Stick
                    }
                })
                .collect();
            assert_eq!(
                e.cone_status(cone),
                expected,
                "trial {trial}, cone {:?}",
                cone.rays
            );
        }
    }
    assert!(
        cones_seen > 100 && multi_ray > 30,
        "{cones_seen} cones, {multi_ray} with several rays"
    );
}

/// Close calls are counted: with compliance `G = [[1, 1/2], [1/2, 1]]` the friction edge
/// `r = (1, -mu)` has `u_n = 1 - mu / 2`, which at `mu = 2 (1 - 1e-8)` is `1e-8` against terms
/// summing to about 2: five times the zero threshold (`1e-9` relative), a near-degenerate sign
/// decision. At `mu = 1` no decision is close.
#[test]
fn near_degenerate_sign_decisions_are_counted() {
    let k = nalgebra::DMatrix::from_row_slice(2, 2, &[1.0, -0.5, -0.5, 1.0]) / 0.75;
    let count = |mu: f64| {
        let problem = Problem::new(2, k.clone(), mu).unwrap();
        enumerate(&problem, &Settings::default())
            .unwrap()
            .info
            .near_degenerate
    };
    assert_eq!(count(1.0), 0);
    assert!(count(2.0 * (1.0 - 1e-8)) >= 1);
}
