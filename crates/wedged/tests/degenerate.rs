//! Highly degenerate 2D problems, where a floating-point tolerance decides things: symmetric
//! stiffnesses, repeated nodes with identical stiffness blocks, and friction coefficients at
//! which rays lie exactly on a friction-cone edge or on a gap constraint. On each, three answers
//! agree exactly:
//!
//! - floating `pruned-dd`, certified ray by ray with `certify_enumeration`;
//! - the exact double description (`wedged::exact::enumerate_exact`, and `Method::Exact` through
//!   `enumerate`), and its plain unpruned form (`enumerate_exact_full`);
//! - the exact brute force over all `5^m` status vectors (`wedged::exact::brute_force_exact`),
//!   which shares no enumeration code with either.
//!
//! Every `K` has small integer (or dyadic) entries and every `mu` is dyadic, so the `f64` data
//! are exactly the intended problem: the degeneracies are exact, not approximate.

use std::time::Duration;

use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wedged::certify::certify_enumeration;
use wedged::exact::{brute_force_exact, enumerate_exact, enumerate_exact_full, ExactEnumeration};
use wedged::{
    enumerate, Enumeration, Limits, Method, NodeStatus, Outcome, Problem, Settings, Stop,
};

fn run(p: &Problem, method: Method) -> Enumeration {
    let settings = Settings {
        method,
        ..Settings::default()
    };
    enumerate(p, &settings)
        .unwrap_or_else(|e| panic!("{method} failed: {e}\nK = {}", p.stiffness()))
}

/// Rays within `1e-9` of each other, relative to the largest entry (`u` and `r` separately).
fn close(a: &[f64], b: &[f64]) -> bool {
    let scale = a
        .iter()
        .chain(b)
        .fold(0.0f64, |s, x| s.max(x.abs()))
        .max(1e-300);
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-9 * scale)
}

/// The floating answer equals the exact one: same statuses, same cones, rays within 1e-9.
fn assert_matches(e: &Enumeration, x: &ExactEnumeration, what: &str) {
    let sf: Vec<&Vec<NodeStatus>> = e.rays.iter().map(|r| &r.status).collect();
    let sx: Vec<&Vec<NodeStatus>> = x.rays.iter().map(|r| &r.status).collect();
    assert_eq!(sf, sx, "{what}: statuses differ");
    for (ray, exact) in e.rays.iter().zip(x.rounded_rays()) {
        assert!(
            close(&ray.r, &exact.r),
            "{what}: r {:?} vs {:?}",
            ray.r,
            exact.r
        );
        assert!(
            close(&ray.u, &exact.u),
            "{what}: u {:?} vs {:?}",
            ray.u,
            exact.u
        );
    }
    assert_eq!(e.cones, x.cones, "{what}: cones differ");
}

/// The three answers agree; with `brute`, the exact brute force is the third. Returns the number
/// of rays.
fn check(p: &Problem, what: &str, brute: bool) -> usize {
    let exact = enumerate_exact(p).unwrap();
    if brute {
        let b = brute_force_exact(p).unwrap();
        assert_eq!(exact, b, "{what}: exact dd and exact brute force differ");
        let full = enumerate_exact_full(p).unwrap();
        assert_eq!(exact, full, "{what}: exact pruned and full dd differ");
    }
    // Method::Exact through the ordinary API gives the same, rounded.
    let e = run(p, Method::Exact);
    assert_eq!(e.rays, exact.rounded_rays(), "{what}: Method::Exact");
    assert_eq!(e.cones, exact.cones, "{what}: Method::Exact cones");
    let expected = if exact.rays.is_empty() {
        Outcome::NotWedged
    } else {
        Outcome::Wedged
    };
    assert_eq!(e.outcome, expected, "{what}");
    // Floating pruned-dd, certified, and equal to the exact answer.
    let f = run(p, Method::PrunedDd);
    let c = certify_enumeration(p, &f);
    assert!(
        c.certified,
        "{what}: pruned-dd not certified: {:?}",
        c.failures
    );
    assert_matches(&f, &exact, &format!("{what}: pruned-dd vs exact"));
    exact.rays.len()
}

/// `A A^T + diag`, `A` with integer entries in `[-2, 2]`: integer, symmetric, positive definite.
fn integer_spd(rng: &mut ChaCha8Rng, m: usize) -> DMatrix<f64> {
    let n = 2 * m;
    let cols = rng.gen_range(1..=n + 1);
    let a = DMatrix::from_fn(n, cols, |_, _| rng.gen_range(-2..=2) as f64);
    let d = DMatrix::from_diagonal(&nalgebra::DVector::from_fn(n, |_, _| {
        rng.gen_range(1..=3) as f64
    }));
    &a * a.transpose() + d
}

/// `K + P K P^T` for the signed permutation `P` of a node map and tangent signs: invariant under
/// it exactly (integers stay integers).
fn symmetrised(k: &DMatrix<f64>, image: &[usize], flip: bool) -> DMatrix<f64> {
    let n = k.nrows();
    let mut p = DMatrix::<f64>::zeros(n, n);
    for (i, &j) in image.iter().enumerate() {
        p[(2 * j, 2 * i)] = 1.0;
        p[(2 * j + 1, 2 * i + 1)] = if flip { -1.0 } else { 1.0 };
    }
    k + &p * k * p.transpose()
}

/// The mirror image of a status vector: nodes reversed, slip+ and slip- swapped.
fn mirror(status: &[NodeStatus]) -> Vec<NodeStatus> {
    status
        .iter()
        .rev()
        .map(|s| match s {
            NodeStatus::SlipPlus => NodeStatus::SlipMinus,
            NodeStatus::SlipMinus => NodeStatus::SlipPlus,
            s => *s,
        })
        .collect()
}

const MUS: [f64; 6] = [0.5, 1.0, 1.5, 2.0, 3.0, 4.0];

/// (a) Mirror-symmetric problems: node `i` is the image of node `m-1-i` with its tangent flipped
/// (a symmetric plug in a symmetric notch), and the exact answer is mirror-symmetric too.
#[test]
fn mirror_symmetric_problems() {
    let mut rng = ChaCha8Rng::seed_from_u64(2008);
    let (mut rays, mut wedged) = (0, 0);
    for trial in 0..36 {
        let m = 2 + trial % 4;
        let image: Vec<usize> = (0..m).rev().collect();
        let k = symmetrised(&integer_spd(&mut rng, m), &image, true);
        let mu = MUS[trial % MUS.len()];
        let p = Problem::new(2, k, mu).unwrap();
        let what = format!("mirror trial {trial} (m = {m}, mu = {mu})");
        let found = check(&p, &what, m <= 5);
        rays += found;
        wedged += usize::from(found > 0);
        let x = enumerate_exact(&p).unwrap();
        for ray in &x.rays {
            let image = mirror(&ray.status);
            assert!(x.rays.iter().any(|q| q.status == image), "{what}");
        }
    }
    eprintln!("mirror: 36 problems, {wedged} wedged, {rays} rays");
    assert!(wedged >= 10 && rays >= 40, "{wedged} wedged, {rays} rays");
}

/// (a) The demo's spring-lattice plug, symmetric by construction, at a few `mu`.
#[test]
fn the_lattice_plug() {
    use wedged::examples::lattice_plug;
    for (per_side, mu) in [(1, 2.5), (1, 3.0), (2, 2.5), (2, 3.0), (2, 5.0)] {
        let p = lattice_plug(per_side, mu);
        check(&p, &format!("lattice {per_side}, mu {mu}"), true);
    }
}

/// (b) Repeated nodes: every node has the same stiffness block `D` and every pair the same
/// coupling `O` (`K = I (x) (D - O) + J (x) O`), so `K` is invariant under every permutation of
/// the nodes; and pairs of twin nodes inside an otherwise random `K`.
#[test]
fn repeated_nodes_with_identical_blocks() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let (mut rays, mut wedged) = (0, 0);
    for trial in 0..30 {
        let m = 2 + trial % 4;
        let n = 2 * m;
        let k = if trial % 2 == 0 {
            // D = [[a, b], [b, c]], O = [[o, q], [q, s]] with small integers; D - O and
            // D + (m - 1) O positive definite makes K positive definite.
            loop {
                let d = [
                    rng.gen_range(4..=8),
                    rng.gen_range(-3..=3),
                    rng.gen_range(2..=6),
                ];
                let o = [
                    rng.gen_range(-2..=2),
                    rng.gen_range(-2..=2),
                    rng.gen_range(-1..=1),
                ];
                let block = |x: [i32; 3]| DMatrix::from_row_slice(2, 2, &[x[0], x[1], x[1], x[2]]);
                let (d, o) = (block(d).map(f64::from), block(o).map(f64::from));
                let k = DMatrix::from_fn(n, n, |r, c| {
                    let (i, j) = (r / 2, c / 2);
                    if i == j {
                        d[(r % 2, c % 2)]
                    } else {
                        o[(r % 2, c % 2)]
                    }
                });
                if k.clone().cholesky().is_some() {
                    break k;
                }
            }
        } else {
            // Twins: nodes 0 and 1 swapped leave K unchanged (tangents not flipped).
            let mut image: Vec<usize> = (0..m).collect();
            image.swap(0, 1);
            symmetrised(&integer_spd(&mut rng, m), &image, false)
        };
        let mu = MUS[(trial / 2) % MUS.len()];
        let p = Problem::new(2, k, mu).unwrap();
        let found = check(
            &p,
            &format!("repeated trial {trial} (m = {m}, mu = {mu})"),
            m <= 5,
        );
        rays += found;
        wedged += usize::from(found > 0);
    }
    eprintln!("repeated: 30 problems, {wedged} wedged, {rays} rays");
    assert!(wedged >= 8 && rays >= 30, "{wedged} wedged, {rays} rays");
}

/// (c) `mu` exactly at a node's critical value `K_tt / |K_nt|` in a block-diagonal `K` (that
/// node decoupled from the rest): below it the node alone never wedges, at it the node's ray is
/// on its friction-cone edge (slip), above it the node sticks. The exact answer changes exactly
/// there, and the floating methods follow it.
#[test]
fn mu_at_a_decoupled_nodes_critical_value() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let mut slips = 0;
    for trial in 0..24 {
        let m = 1 + trial % 4;
        let n = 2 * m;
        // Node 0: K_nn = a, K_nt = b = +/- 1, 2 or 4, K_tt = c; mu* = c / |b| is dyadic.
        let b = [1.0, -1.0, 2.0, -2.0, 4.0, -4.0][trial % 6];
        let c: f64 = rng.gen_range(1..=6) as f64;
        let a = (b * b / c).ceil() + rng.gen_range(1..=3) as f64;
        let mut k = DMatrix::<f64>::zeros(n, n);
        k[(0, 0)] = a;
        k[(0, 1)] = b;
        k[(1, 0)] = b;
        k[(1, 1)] = c;
        if m > 1 {
            let rest = integer_spd(&mut rng, m - 1);
            k.view_mut((2, 2), (n - 2, n - 2)).copy_from(&rest);
        }
        let critical = c / b.abs();
        for (mu, label) in [
            (critical * (1.0 - 1.0 / 64.0), "below"),
            (critical, "at"),
            (critical * (1.0 + 1.0 / 64.0), "above"),
        ] {
            let p = Problem::new(2, k.clone(), mu).unwrap();
            let what = format!("critical trial {trial} (m = {m}, mu {label} {critical})");
            check(&p, &what, m <= 4);
            let x = enumerate_exact(&p).unwrap();
            // Node 0 pressed, the others grazing: the node's own ray.
            let own: Vec<NodeStatus> = x
                .rays
                .iter()
                .filter(|r| r.status[1..].iter().all(|&s| s == NodeStatus::Grazing))
                .map(|r| r.status[0])
                .filter(|s| s.pressed())
                .collect();
            let expected = match label {
                "below" => vec![],
                "at" if b > 0.0 => vec![NodeStatus::SlipPlus],
                "at" => vec![NodeStatus::SlipMinus],
                _ => vec![NodeStatus::Stick],
            };
            assert_eq!(own, expected, "{what}");
            slips += usize::from(label == "at");
        }
    }
    assert_eq!(slips, 24);
}

/// Problems with a friction-cone edge ray exactly on its gap constraint, in a fully coupled `K`:
/// `K = (L L^T)^{-1}` with `L` unit lower triangular and integer, so `K` and its compliance
/// `G = L L^T` are integer, `G_nn = 1` and `G_nt = L_10` at node 0; at `mu = G_nn / |G_nt|`
/// (1 or 1/2) the edge ray `r = e_n -/+ mu e_t` of node 0 has `u_n = G_nn -/+ mu G_nt = 0`
/// exactly. `count` problems from `seed`, `m = 1..4`.
fn edge_family(seed: u64, count: usize) -> Vec<(String, Problem)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::new();
    let mut trial = 0;
    while out.len() < count {
        trial += 1;
        let m = 1 + out.len() % 4;
        let n = 2 * m;
        let mut l = DMatrix::<f64>::identity(n, n);
        for i in 1..n {
            for j in 0..i {
                l[(i, j)] = rng.gen_range(-1..=1) as f64;
            }
        }
        l[(1, 0)] = [1.0, -1.0, 2.0, -2.0][out.len() % 4];
        let g = &l * l.transpose();
        // Forward substitution with a unit diagonal: integer operations only, exact.
        let li = l
            .solve_lower_triangular(&DMatrix::identity(n, n))
            .expect("unit diagonal");
        let k = li.transpose() * li;
        // Keep K small (so exactly integer).
        if k.iter().any(|x| x.abs() > 1e6) {
            continue;
        }
        assert!(k.iter().all(|x| x.fract() == 0.0));
        let mu = g[(0, 0)] / g[(0, 1)].abs();
        assert!(mu == 1.0 || mu == 0.5, "mu = {mu}");
        out.push((
            format!("edge trial {trial} (m = {m}, mu = {mu})"),
            Problem::new(2, k, mu).unwrap(),
        ));
    }
    out
}

/// (c) The edge family: the exact double description, `Method::Exact` and the exact brute force
/// agree on every instance. The floating methods are held to what they promise today: whatever
/// they report certifies and is among the exact rays (no wrong ray, no wrong status), or they
/// refuse with a verification error. Rays they miss are counted, not failed: see
/// `floating_pruned_dd_finds_every_edge_ray` (ignored) for the strict comparison.
#[test]
fn an_edge_ray_exactly_on_its_gap_constraint() {
    let (mut missed, mut refused) = (0, 0);
    for (what, p) in edge_family(31, 30) {
        let exact = enumerate_exact(&p).unwrap();
        assert_eq!(exact, brute_force_exact(&p).unwrap(), "{what}");
        assert_eq!(exact, enumerate_exact_full(&p).unwrap(), "{what}");
        let e = run(&p, Method::Exact);
        assert_eq!(e.rays, exact.rounded_rays(), "{what}: Method::Exact");
        assert_eq!(e.cones, exact.cones, "{what}: Method::Exact cones");
        for method in [Method::PrunedDd, Method::FullDd, Method::Faces] {
            let settings = Settings {
                method,
                ..Settings::default()
            };
            let Ok(f) = enumerate(&p, &settings) else {
                refused += 1;
                continue;
            };
            let c = certify_enumeration(&p, &f);
            for ray in &f.rays {
                let x = exact.rays.iter().find(|x| x.status == ray.status);
                let x = x.unwrap_or_else(|| panic!("{what}: {method} ray {:?}", ray.status));
                assert!(close(&ray.r, &x.rounded().r), "{what}: {method}");
            }
            let lost = exact.rays.len() - f.rays.len();
            missed += lost;
            // Every ray reported checks; a missing one is caught by the completeness check of
            // --certify (m <= 8 here), never passed as certified.
            if lost == 0 {
                assert!(c.certified, "{what}: {method}: {:?}", c.failures);
                assert_eq!(c.complete, Some(true), "{what}: {method}");
            } else {
                assert!(
                    !c.certified,
                    "{what}: {method} lost {lost} rays, yet certified"
                );
                assert_eq!(c.complete, Some(false), "{what}: {method}");
                assert!(
                    c.failures.iter().all(|f| f.starts_with("completeness:")),
                    "{what}: {method}: {:?}",
                    c.failures
                );
            }
        }
    }
    eprintln!(
        "edge family: the floating methods missed {missed} exact rays and refused {refused} \
         answers (verification errors)"
    );
    // None since the round-off floors of dd.rs and faces.rs (before: trial 14 missed by
    // pruned-dd, trial 4 refused by pruned-dd and full-dd and missed by faces).
    assert!(
        missed == 0 && refused == 0,
        "{missed} missed, {refused} refused"
    );
}

/// The strict form of the edge family: floating `pruned-dd`, certified, equals the exact answer.
/// (It failed on `edge trial 14`, `m = 2`, `mu = 1`, where `pruned-dd` printed "no wedged
/// configuration" although `[slip+, slip+]` exists: a projected gap row of pure round-off
/// counted in the adjacency rank; and on `edge trial 4`, `m = 4`, `mu = 1/2`, where an entry of
/// `K^-1` that is zero exactly came out as round-off and decided a sign, so `pruned-dd` and
/// `full-dd` stopped with a verification error and `faces` missed the only ray.)
#[test]
fn floating_pruned_dd_finds_every_edge_ray() {
    for (what, p) in edge_family(31, 30) {
        check(&p, &what, false);
    }
}

/// The exact double description equals the exact brute force on seeded random problems with
/// generic `f64` data (every entry a long dyadic rational), `m = 1..5`; floating pruned-dd agrees.
#[test]
fn exact_equals_brute_force_on_random_problems() {
    use wedged::examples::random_spd_problem;
    let (mut rays, mut wedged) = (0, 0);
    for trial in 0..50u64 {
        let m = 1 + (trial % 5) as usize;
        let mu = [0.5, 1.0, 2.0, 3.0, 5.0][(trial / 5 % 5) as usize];
        let p = random_spd_problem(m, mu, 9000 + trial);
        let found = check(
            &p,
            &format!("random trial {trial} (m = {m}, mu = {mu})"),
            true,
        );
        rays += found;
        wedged += usize::from(found > 0);
    }
    eprintln!("random: 50 problems, {wedged} wedged, {rays} rays");
    assert!(wedged >= 15 && rays >= 50, "{wedged} wedged, {rays} rays");
}

/// `Method::Exact` honours the limits: it stops cleanly, incomplete, with no ray.
#[test]
fn exact_runs_stop_cleanly_at_a_limit() {
    let p = wedged::examples::random_spd_problem(8, 1.0, 3);
    for (limits, stop) in [
        (
            Limits {
                time_limit: Some(Duration::ZERO),
                ..Limits::default()
            },
            Stop::TimeLimit(Duration::ZERO),
        ),
        (
            Limits {
                max_rays: Some(20),
                ..Limits::default()
            },
            Stop::MaxRays(20),
        ),
    ] {
        let settings = Settings {
            method: Method::Exact,
            limits,
            ..Settings::default()
        };
        let e = enumerate(&p, &settings).unwrap();
        assert_eq!(e.outcome, Outcome::Incomplete(stop));
        assert!(e.rays.is_empty() && e.cones.is_empty());
    }
    // A 3D problem is refused, like the other ray methods.
    let p3 = wedged::examples::random_spd_problem_dim(3, 2, 1.0, 1);
    assert!(enumerate_exact(&p3).is_err() && brute_force_exact(&p3).is_err());
}
