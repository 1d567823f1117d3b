//! The sign patterns (3D, and 2D as a cross-check): branch and bound, the pyramid method and the
//! brute force over the `2^m` contact sets against each other on seeded random problems; against
//! the 2D enumeration (a 2D problem, and a 3D problem built to reduce to one); against the
//! one-node closed forms; and every witness checked here, independently of the library's own
//! check.

mod common;

use common::random_spd;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wedged::patterns::pyramid_candidates;
use wedged::{
    enumerate, enumerate_patterns, ContactPattern, Limits, NodeStatus, Outcome, PatternMethod,
    PatternSettings, Patterns, Problem, Settings,
};

/// Runs a method; `bnb`, `pattern-faces` and `pattern-search` with `--certify`, whose
/// certificate must pass (the pyramid's completeness rests on floating-point double description
/// and is not certified).
fn run(problem: &Problem, method: PatternMethod) -> Patterns {
    let certify = !matches!(method, PatternMethod::Pyramid { .. });
    let settings = PatternSettings {
        method,
        certify,
        ..PatternSettings::default()
    };
    let result = enumerate_patterns(problem, &settings)
        .unwrap_or_else(|e| panic!("{method} failed: {e}\nK = {}", problem.stiffness()));
    assert!(
        !matches!(result.outcome, Outcome::Incomplete(_)),
        "{method} incomplete: {:?}",
        result.undecided
    );
    if certify {
        let c = result.certificate.as_ref().expect("asked for");
        assert!(
            c.certified,
            "{method} not certified: {:?}\nK = {}, mu = {}",
            c.failures,
            problem.stiffness(),
            problem.mu()
        );
        assert_eq!(c.witnesses_checked, result.patterns.len());
        assert!(c.refutations_checked > 0 || result.patterns.is_empty() || problem.nodes() == 1);
    } else {
        assert!(result.certificate.is_none());
    }
    for p in &result.patterns {
        check_witness(problem, p);
    }
    result
}

fn pattern_list(p: &Patterns) -> Vec<Vec<ContactPattern>> {
    p.patterns.iter().map(|p| p.pattern.clone()).collect()
}

/// The witness solves WP, is normalised, and shows its claimed statuses and pattern.
fn check_witness(problem: &Problem, p: &wedged::Pattern) {
    let (d, m, mu) = (problem.dim(), problem.nodes(), problem.mu());
    let k = problem.stiffness();
    let ku = k * nalgebra::DVector::from_column_slice(&p.u);
    let scale = k.abs().max() * p.u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for a in 0..d * m {
        assert!(
            (ku[a] - p.r[a]).abs() <= 1e-8 * scale.max(1e-300) + 1e-12,
            "K u != r in row {a}"
        );
    }
    let total: f64 = (0..m).map(|i| p.r[d * i]).sum();
    assert!((total - 1.0).abs() < 1e-9, "sum r_n = {total}");
    let u_max = p.u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for i in 0..m {
        let (un, rn) = (p.u[d * i], p.r[d * i]);
        let rt = p.r[d * i + 1..d * i + d]
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        let gap_zero = un.abs() <= 1e-7 * u_max;
        assert!(
            rt <= mu * rn * (1.0 + 1e-7) + 1e-12,
            "node {i} outside the cone"
        );
        assert!(un >= -1e-7 * u_max, "node {i} penetrates");
        let expected = match p.status[i] {
            NodeStatus::Separated => {
                assert!(
                    un > 1e-9 * u_max && rn == 0.0 && rt == 0.0,
                    "node {i} not separated"
                );
                ContactPattern::Separated
            }
            NodeStatus::Grazing => {
                assert!(gap_zero && rn == 0.0 && rt == 0.0, "node {i} not grazing");
                ContactPattern::Grazing
            }
            NodeStatus::Stick => {
                assert!(
                    gap_zero && rn > 0.0 && rt < mu * rn,
                    "node {i} not sticking"
                );
                ContactPattern::Contact
            }
            NodeStatus::Slip | NodeStatus::SlipPlus | NodeStatus::SlipMinus => {
                assert!(gap_zero && rn > 0.0, "node {i} not pressed");
                assert!(
                    (rt - mu * rn).abs() <= 1e-6 * rn,
                    "node {i} claimed slip, slack {}",
                    mu * rn - rt
                );
                ContactPattern::Contact
            }
        };
        assert_eq!(
            p.pattern[i], expected,
            "node {i}: status and pattern disagree"
        );
    }
}

/// A random 3D problem whose friction coefficient is drawn around the range where random
/// problems start to wedge.
fn random_problem(rng: &mut ChaCha8Rng, dim: usize, m: usize) -> Problem {
    let k = random_spd(rng, dim * m);
    let mu = rng.gen_range(0.3..3.0);
    Problem::new(dim, k, mu).unwrap()
}

#[test]
fn bnb_pyramid_and_brute_force_agree_in_3d() {
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let (mut wedged, mut several, mut grazing) = (0, 0, 0);
    for case in 0..60 {
        let m = 1 + case % 6;
        let problem = random_problem(&mut rng, 3, m);
        let brute = run(&problem, PatternMethod::Faces);
        let bnb = run(&problem, PatternMethod::Bnb);
        // The approximation's rays grow fast with k and m (BENCHMARKS.md): k = 4 for the
        // larger cases keeps the test short, and still exercises spurious candidates.
        let faces = if m <= 4 { 8 } else { 4 };
        let pyramid = run(&problem, PatternMethod::Pyramid { faces });
        let what = format!("case {case}, m = {m}, mu = {}", problem.mu());
        assert_eq!(pattern_list(&bnb), pattern_list(&brute), "bnb, {what}");
        assert_eq!(
            pattern_list(&pyramid),
            pattern_list(&brute),
            "pyramid, {what}"
        );
        assert_eq!(bnb.outcome, brute.outcome, "{what}");
        wedged += (brute.outcome == Outcome::Wedged) as usize;
        several += (brute.patterns.len() >= 2) as usize;
        grazing += brute
            .patterns
            .iter()
            .any(|p| p.pattern.contains(&ContactPattern::Grazing)) as usize;
    }
    // The family is not trivial: it has wedged and unwedged cases and several pieces.
    assert!((10..60).contains(&wedged), "{wedged} wedged");
    assert!(several >= 5, "{several} with several patterns");
    eprintln!("{wedged} wedged, {several} with several patterns, {grazing} with grazing");
}

/// Without `--certify` the `bnb` decides its inner nodes by the warm-started simplex method
/// (`conic::node_lp`; in 3D an outer polyhedral relaxation of the friction cone), with drive
/// cuts near the root, and its leaves by the cone program: on 300 seeded random 3D problems with
/// up to 5 nodes and 100 2D ones with up to 7 its patterns are the brute force's over all
/// contact sets, and a certified run (every node by the cone program) gives them too.
#[test]
fn bnb_on_the_simplex_method_agrees_with_the_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let (mut wedged, mut several, mut tightenings) = (0, 0, 0);
    let cases = (0..300).map(|c| (3, c)).chain((0..100).map(|c| (2, c)));
    for (dim, case) in cases {
        let m = 1 + case % if dim == 3 { 5 } else { 7 };
        let problem = random_problem(&mut rng, dim, m);
        let plain = |method, certify| {
            let settings = PatternSettings {
                method,
                certify,
                ..PatternSettings::default()
            };
            enumerate_patterns(&problem, &settings).unwrap()
        };
        let brute = plain(PatternMethod::Faces, false);
        let bnb = plain(PatternMethod::Bnb, false);
        let what = format!("{dim}D case {case}, m = {m}, mu = {}", problem.mu());
        tightenings += bnb.info.bound_tightenings;
        assert!(
            bnb.info.lp_solves > 0 || m == 1,
            "no linear program, {what}"
        );
        assert!(bnb.undecided.is_empty(), "{what}: {:?}", bnb.undecided);
        for p in &bnb.patterns {
            check_witness(&problem, p);
        }
        assert_eq!(pattern_list(&bnb), pattern_list(&brute), "{what}");
        assert_eq!(bnb.outcome, brute.outcome, "{what}");
        if case % 10 == 0 {
            // Certified: every node by the cone program, each prune checked exactly.
            let certified = plain(PatternMethod::Bnb, true);
            assert!(
                certified.certificate.as_ref().is_some_and(|c| c.certified),
                "{what}"
            );
            assert_eq!(certified.info.lp_solves, 0, "{what}");
            assert_eq!(
                pattern_list(&certified),
                pattern_list(&brute),
                "certified, {what}"
            );
        }
        wedged += (brute.outcome == Outcome::Wedged) as usize;
        several += (brute.patterns.len() >= 2) as usize;
    }
    assert!((50..350).contains(&wedged), "{wedged} wedged");
    assert!(several >= 20, "{several} with several patterns");
    assert!(tightenings > 300, "{tightenings} bound tightenings");
    eprintln!("{wedged} wedged, {several} with several patterns, {tightenings} tightenings");
}

#[test]
fn patterns_of_2d_problems_are_the_cones_of_the_2d_enumeration() {
    let mut rng = ChaCha8Rng::seed_from_u64(20);
    let mut nonempty = 0;
    for case in 0..40 {
        let m = 1 + case % 6;
        let problem = random_problem(&mut rng, 2, m);
        let rays = enumerate(&problem, &Settings::default()).unwrap();
        let mut cones: Vec<Vec<ContactPattern>> =
            rays.cones.iter().map(|c| c.pattern.clone()).collect();
        cones.sort();
        for method in [
            PatternMethod::Bnb,
            PatternMethod::Faces,
            PatternMethod::Pyramid { faces: 8 },
            PatternMethod::Search,
        ] {
            let patterns = run(&problem, method);
            assert_eq!(pattern_list(&patterns), cones, "{method}, case {case}");
            // The witness's statuses are those of its cone's relative interior.
            for p in &patterns.patterns {
                let cone = rays.cones.iter().find(|c| c.pattern == p.pattern).unwrap();
                assert_eq!(p.status, rays.cone_status(cone), "{method}, case {case}");
            }
        }
        nonempty += !cones.is_empty() as usize;
    }
    assert!(nonempty >= 10, "{nonempty}");
}

#[test]
fn a_3d_problem_with_a_decoupled_second_tangent_has_the_2d_patterns() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut nonempty = 0;
    for case in 0..30 {
        let m = 1 + case % 5;
        let k2 = random_spd(&mut rng, 2 * m);
        let k22 = random_spd(&mut rng, m);
        let mu = rng.gen_range(0.3..3.0);
        let mut k3 = DMatrix::<f64>::zeros(3 * m, 3 * m);
        for i in 0..m {
            for j in 0..m {
                for a in 0..2 {
                    for b in 0..2 {
                        k3[(3 * i + a, 3 * j + b)] = k2[(2 * i + a, 2 * j + b)];
                    }
                }
                k3[(3 * i + 2, 3 * j + 2)] = k22[(i, j)];
            }
        }
        let p2 = Problem::new(2, k2, mu).unwrap();
        let p3 = Problem::new(3, k3, mu).unwrap();
        let mut cones: Vec<_> = enumerate(&p2, &Settings::default())
            .unwrap()
            .cones
            .iter()
            .map(|c| c.pattern.clone())
            .collect();
        cones.sort();
        assert_eq!(
            pattern_list(&run(&p3, PatternMethod::Bnb)),
            cones,
            "case {case}"
        );
        nonempty += !cones.is_empty() as usize;
    }
    assert!(nonempty >= 8, "{nonempty}");
}

/// One node in 3D: `u = (0, u_t)`, `r_n = k_nt . u_t`, `r_t = K_tt u_t`, so wedging needs
/// `||K_tt u_t|| <= mu k_nt . u_t` for some `u_t`: `mu* = 1 / ||K_tt^-1 k_nt||`.
#[test]
fn one_node_closed_form_in_3d() {
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for case in 0..20 {
        let k = random_spd(&mut rng, 3);
        let ktt = k.view((1, 1), (2, 2)).clone_owned();
        let knt = nalgebra::DVector::from_vec(vec![k[(1, 0)], k[(2, 0)]]);
        let mu_star = 1.0 / (ktt.try_inverse().unwrap() * knt).norm();
        for (factor, wedges) in [(0.97, false), (1.03, true)] {
            let problem = Problem::new(3, k.clone(), factor * mu_star).unwrap();
            for method in [PatternMethod::Bnb, PatternMethod::Pyramid { faces: 16 }] {
                let p = run(&problem, method);
                assert_eq!(
                    p.outcome == Outcome::Wedged,
                    wedges,
                    "case {case}, {method}, mu = {factor} mu*"
                );
                if wedges {
                    assert_eq!(p.patterns.len(), 1);
                    assert_eq!(p.patterns[0].status, vec![NodeStatus::Stick]);
                }
            }
        }
    }
}

/// Every true pattern lies below a candidate of the pyramid, and the candidates of a finer
/// pyramid (contained in the coarser one: its faces include the coarser's) lie below those of
/// the coarser; the spurious candidates become fewer.
#[test]
fn pyramid_candidates_shrink_towards_the_true_patterns() {
    let mut rng = ChaCha8Rng::seed_from_u64(32);
    let below = |a: &[ContactPattern], b: &[ContactPattern]| {
        a.iter()
            .zip(b)
            .all(|(&x, &y)| x == ContactPattern::Grazing || x == y)
    };
    let mut spurious = [0usize; 3];
    for case in 0..30 {
        let m = 2 + case % 3;
        let problem = random_problem(&mut rng, 3, m);
        let truth = pattern_list(&run(&problem, PatternMethod::Bnb));
        let mut coarser: Option<Vec<Vec<ContactPattern>>> = None;
        for (level, faces) in [4, 8, 16].into_iter().enumerate() {
            let candidates = pyramid_candidates(&problem, faces, 1e-9).unwrap();
            for q in &truth {
                assert!(
                    candidates.iter().any(|c| below(q, c)),
                    "case {case}, k = {faces}: a true pattern is below no candidate"
                );
            }
            if let Some(coarse) = &coarser {
                for c in &candidates {
                    assert!(
                        coarse.iter().any(|d| below(c, d)),
                        "case {case}, k = {faces}: a candidate is below no coarser one"
                    );
                }
            }
            spurious[level] += candidates.iter().filter(|c| !truth.contains(c)).count();
            coarser = Some(candidates);
        }
    }
    eprintln!("spurious candidates for k = 4, 8, 16: {spurious:?}");
    assert!(
        spurious[0] > 0,
        "the family does not exercise the approximation"
    );
    assert!(spurious[2] < spurious[0], "{spurious:?}");
}

#[test]
fn a_time_limit_of_zero_gives_an_incomplete_run() {
    let problem = wedged::examples::random_spd_problem_dim(3, 6, 2.0, 1);
    let settings = PatternSettings {
        limits: Limits {
            time_limit: Some(std::time::Duration::ZERO),
            ..Limits::default()
        },
        ..PatternSettings::default()
    };
    let p = enumerate_patterns(&problem, &settings).unwrap();
    assert!(matches!(p.outcome, Outcome::Incomplete(_)));
}

#[test]
fn the_3d_plug_wedges_and_every_piece_is_checked() {
    let model = wedged::examples::plug3d(1, 1).unwrap();
    let problem = model.problem(3.0).unwrap();
    let p = run(&problem, PatternMethod::Bnb);
    assert_eq!(p.outcome, Outcome::Wedged);
    let q = run(&problem, PatternMethod::Pyramid { faces: 8 });
    assert_eq!(pattern_list(&p), pattern_list(&q));
}

/// Other units per node (`S K S`, node `i`'s block scaled by `s_i` from 1e-3 to 1e3): the same
/// problem, so the same patterns, with every witness checked against the scaled problem.
#[test]
fn per_node_units_do_not_change_the_patterns() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let scales = [1e-3, 1e3, 1.0, 31.6, 0.0316];
    let mut compared = 0;
    for case in 0..12 {
        let dim = 2 + case % 2;
        let m = 2 + case % 4;
        let base = random_problem(&mut rng, dim, m);
        let scaled = wedged::examples::node_scaled(&base, &scales);
        let (a, b) = (
            run(&base, PatternMethod::Bnb),
            run(&scaled, PatternMethod::Bnb),
        );
        assert_eq!(pattern_list(&a), pattern_list(&b), "case {case}");
        for p in &b.patterns {
            check_witness(&scaled, p);
        }
        compared += 1;
    }
    assert_eq!(compared, 12);
}
