//! Exact rational certificates of 2D ray enumerations: the methods' answers are certified,
//! corrupted answers are caught, and the one-node closed form comes out exactly.

use std::time::{Duration, Instant};

use nalgebra::DMatrix;
use num_rational::BigRational;
use wedged::certify::{certify_enumeration, certify_ray_exact};
use wedged::examples::{block_spd_problem, demo, random_spd_problem};
use wedged::{enumerate, Enumeration, Method, NodeStatus, Outcome, Problem, Settings};

fn run(p: &Problem, method: Method) -> Enumeration {
    enumerate(
        p,
        &Settings {
            method,
            ..Settings::default()
        },
    )
    .unwrap()
}

/// About forty seeded random problems and the demo: every enumeration certifies.
#[test]
fn enumerations_are_certified() {
    let mut problems: Vec<(String, Problem)> = vec![("demo".into(), demo())];
    for m in 2..=8 {
        for (seed, mu) in [(1, 0.4), (2, 0.8), (3, 1.2), (4, 2.0), (5, 3.0), (6, 4.0)] {
            let seed = 100 * m as u64 + seed;
            problems.push((
                format!("random m = {m}, mu = {mu}, seed {seed}"),
                random_spd_problem(m, mu, seed),
            ));
        }
    }
    let (mut rays, mut cones, mut wedged) = (0, 0, 0);
    for (name, p) in &problems {
        for method in [Method::PrunedDd, Method::Faces] {
            if method == Method::Faces && p.nodes() > 6 {
                continue;
            }
            let e = run(p, method);
            let c = certify_enumeration(p, &e);
            assert!(c.certified, "{name}, {}: {:?}", method.name(), c.failures);
            assert!(c.failures.is_empty());
            assert_eq!(c.rays_checked, e.rays.len());
            assert_eq!(c.cones_checked, e.cones.len());
            if method == Method::PrunedDd {
                rays += e.rays.len();
                cones += e.cones.len();
                wedged += usize::from(!e.rays.is_empty());
            }
        }
    }
    // The families must exercise the certificate, not only empty answers.
    assert!(wedged >= 15, "only {wedged} problems wedge");
    println!(
        "{} problems, {wedged} wedged: {rays} rays and {cones} cones certified",
        problems.len()
    );
}

/// The first ray with at least one node of the given kind, and that node.
fn find(e: &Enumeration, pick: impl Fn(NodeStatus) -> bool) -> Option<(usize, usize)> {
    e.rays
        .iter()
        .enumerate()
        .find_map(|(k, ray)| ray.status.iter().position(|&s| pick(s)).map(|i| (k, i)))
}

/// An enumeration with rays of every kind needed below.
fn subject() -> (Problem, Enumeration) {
    let p = demo();
    let e = run(&p, Method::PrunedDd);
    assert!(e.rays.len() >= 3, "the demo must have rays to corrupt");
    assert!(certify_enumeration(&p, &e).certified);
    (p, e)
}

fn assert_caught(p: &Problem, bad: &Enumeration, k: usize, what: &str) {
    let c = certify_enumeration(p, bad);
    assert!(!c.certified, "{what}: not caught");
    let name = format!("ray {k} [");
    assert!(
        c.failures.iter().any(|f| f.starts_with(&name)),
        "{what}: no failure names ray {k}: {:?}",
        c.failures
    );
}

#[test]
fn flipped_status_is_caught() {
    let (p, e) = subject();
    let mut flips = 0;
    for (from, to) in [
        (NodeStatus::Stick, NodeStatus::SlipPlus),
        (NodeStatus::Stick, NodeStatus::SlipMinus),
        (NodeStatus::SlipPlus, NodeStatus::Stick),
        (NodeStatus::SlipMinus, NodeStatus::Stick),
        (NodeStatus::Separated, NodeStatus::Grazing),
        (NodeStatus::Stick, NodeStatus::Separated),
        (NodeStatus::Separated, NodeStatus::Stick),
    ] {
        if let Some((k, i)) = find(&e, |s| s == from) {
            let mut bad = e.clone();
            bad.rays[k].status[i] = to;
            assert_caught(&p, &bad, k, &format!("{} -> {}", from.name(), to.name()));
            flips += 1;
        }
    }
    assert!(flips >= 3, "only {flips} kinds of flip were tried");
}

#[test]
fn perturbed_ray_is_caught() {
    let (p, e) = subject();
    for k in 0..e.rays.len() {
        let ray = &e.rays[k];
        let largest = ray.r.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let j = (0..ray.r.len())
            .max_by(|&a, &b| ray.r[a].abs().total_cmp(&ray.r[b].abs()))
            .unwrap();
        let mut bad = e.clone();
        bad.rays[k].r[j] += 1e-3 * largest;
        assert_caught(&p, &bad, k, "r perturbed by 1e-3");
        // A perturbation of u alone is caught too.
        let mut bad = e.clone();
        let largest = ray.u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        bad.rays[k].u[0] -= 1e-3 * largest;
        assert_caught(&p, &bad, k, "u perturbed by 1e-3");
    }
}

#[test]
fn corrupted_cone_is_caught() {
    // Two rays that are not cross-complementary put into one cone.
    let (p, e) = subject();
    let pair = (0..e.rays.len()).find_map(|a| {
        (a + 1..e.rays.len())
            .find(|&b| {
                e.rays[a]
                    .status
                    .iter()
                    .zip(&e.rays[b].status)
                    .any(|(x, y)| (x.gap_open() && y.pressed()) || (y.gap_open() && x.pressed()))
            })
            .map(|b| (a, b))
    });
    let (a, b) = pair.expect("the demo has incompatible rays");
    let mut bad = e.clone();
    bad.cones[0].rays = vec![a, b];
    let c = certify_enumeration(&p, &bad);
    assert!(!c.certified);
    assert!(
        c.failures.iter().any(|f| f.starts_with("cone 0: ")),
        "{:?}",
        c.failures
    );
}

/// One node, K = [[2, 1], [1, 1]], mu = 1.1: the single ray u = (0, 1), r = (1, 1), exactly.
#[test]
fn one_node_closed_form_is_exact() {
    let k = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 1.0]);
    let p = Problem::new(2, k, 1.1).unwrap();
    let e = run(&p, Method::PrunedDd);
    assert_eq!(e.rays.len(), 1);
    let c = certify_enumeration(&p, &e);
    assert!(c.certified, "{:?}", c.failures);
    assert_eq!((c.rays_checked, c.cones_checked), (1, 1));
    let x = certify_ray_exact(&p, &e.rays[0]).unwrap();
    let int = |v: i64| BigRational::from_integer(v.into());
    assert_eq!(x.r[1].clone() / &x.r[0], int(1));
    assert_eq!(x.u, vec![int(0), int(1)]);
    assert_eq!(x.r, vec![int(1), int(1)]);
}

/// Sixteen nodes certify in well under a second (the enumeration is bounded in time; a stopped
/// one is skipped).
#[test]
fn sixteen_nodes_certify_quickly() {
    let mut certified = 0;
    for (band, mu, seed) in [(2, 1.5, 7), (4, 1.5, 8), (1, 2.0, 9)] {
        // Blocks of `band` coupled nodes: many rays, a fast enumeration.
        let p = block_spd_problem(16, band, mu, seed);
        let start = Instant::now();
        let mut settings = Settings::default();
        settings.limits.time_limit = Some(Duration::from_secs(8));
        let e = enumerate(&p, &settings).unwrap();
        let enumerated = start.elapsed().as_secs_f64();
        if matches!(e.outcome, Outcome::Incomplete(_)) {
            eprintln!("m = 16, band {band}, mu = {mu}: enumeration stopped, skipped");
            continue;
        }
        let start = Instant::now();
        let c = certify_enumeration(&p, &e);
        let seconds = start.elapsed().as_secs_f64();
        assert!(c.certified, "{:?}", c.failures);
        eprintln!(
            "m = 16, band {band}, mu = {mu}: enumerated in {enumerated:.3} s; {} rays, {} cones \
             certified in {seconds:.3} s",
            c.rays_checked, c.cones_checked
        );
        assert!(seconds < 5.0, "{seconds} s");
        certified += usize::from(c.rays_checked > 0);
    }
    assert!(
        certified >= 1,
        "no sixteen-node problem with rays was certified"
    );
}
