//! `mu*` of uncoupled groups of contact nodes (`critical/groups.rs`): a block-diagonal `K`, its
//! nodes shuffled, is searched group by group, and its `mu*` is the least of the blocks' own,
//! the same as the seed's method (`enumerate`, which searches the whole problem at once) finds;
//! the witness presses one group only; a coupling of 1e-300 is a coupling; a stopped run is
//! incomplete; the closed form of two one-node bodies.

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use nalgebra::DMatrix;
use wedged::examples::random_spd_problem_dim;
use wedged::{
    critical, critical_with_control, enumerate, ContactPattern, Critical, CriticalMethod,
    CriticalSettings, CriticalStatus, Limits, Method, Problem, Settings, Stop,
};

/// The problem whose `K` is the blocks' own on the diagonal, zero elsewhere, its nodes then
/// put in the order `order` (new node `a` is old node `order[a]`).
fn uncoupled(parts: &[Problem], order: &[usize], mu: f64) -> Problem {
    let d = parts[0].dim();
    let n: usize = parts.iter().map(|p| p.stiffness().nrows()).sum();
    let mut k = DMatrix::<f64>::zeros(n, n);
    let mut o = 0;
    for p in parts {
        let s = p.stiffness().nrows();
        k.view_mut((o, o), (s, s)).copy_from(p.stiffness());
        o += s;
    }
    Problem::new(d, k, mu).unwrap().permuted(order)
}

fn settings(method: CriticalMethod, certify: bool) -> CriticalSettings {
    CriticalSettings {
        method,
        certify,
        ..CriticalSettings::default()
    }
}

/// A seeded shuffle of `0..m`.
fn shuffle(m: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..m).collect();
    let mut x = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
    for i in (1..m).rev() {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        order.swap(i, (x >> 33) as usize % (i + 1));
    }
    order
}

fn mu_of(c: &Critical) -> Option<f64> {
    assert!(
        !matches!(c.status, CriticalStatus::Incomplete(_)),
        "{:?}",
        c.status
    );
    c.mu_critical
}

/// Two or three random bodies in 2D and 3D, nodes shuffled: the grouped run (certified
/// exactly) gives the least of the bodies' own `mu*`, as the seed's method on the whole does,
/// and its witness presses the nodes of one body only.
#[test]
fn uncoupled_bodies_give_the_least_of_their_mu_star() {
    let mu = 3.0;
    let mut cases = 0;
    for (dim, sizes) in [
        (2, vec![1, 2]),
        (2, vec![3, 2]),
        (2, vec![2, 2, 2]),
        (2, vec![4, 3]),
        (3, vec![1, 2]),
        (3, vec![2, 2]),
    ] {
        for seed in 0..6u64 {
            let parts: Vec<Problem> = sizes
                .iter()
                .enumerate()
                .map(|(b, &m)| random_spd_problem_dim(dim, m, mu, 100 * seed + b as u64))
                .collect();
            let m: usize = sizes.iter().sum();
            let order = shuffle(m, seed + 7);
            let whole = uncoupled(&parts, &order, mu);
            let what = format!("dim {dim}, sizes {sizes:?}, seed {seed}");
            let grouped = critical(&whole, &settings(CriticalMethod::Bnb, true)).unwrap();
            assert_eq!(grouped.info.groups, sizes.len() as u64, "{what}");
            let certificate = grouped.certificate.as_ref().expect("asked");
            assert!(certificate.certified, "{what}: {:?}", certificate.failures);
            let own: Vec<Option<f64>> = parts
                .iter()
                .map(|p| mu_of(&critical(p, &settings(CriticalMethod::Bnb, false)).unwrap()))
                .collect();
            let least = own.iter().flatten().copied().fold(f64::INFINITY, f64::min);
            let seed_method = critical(&whole, &settings(CriticalMethod::Enumerate, false))
                .expect("the seed's method");
            assert_eq!(seed_method.info.groups, 0, "enumerate searches the whole");
            match mu_of(&grouped) {
                None => {
                    assert!(least.is_infinite(), "{what}: never, but a body wedges");
                    assert_eq!(mu_of(&seed_method), None, "{what}");
                }
                Some(got) => {
                    assert!(
                        (got - least).abs() <= 1e-8 * least,
                        "{what}: {got} vs {least}"
                    );
                    let other = mu_of(&seed_method).expect("the seed's method wedges too");
                    assert!(
                        (got - other).abs() <= 1e-5 * got,
                        "{what}: {got} vs {other}"
                    );
                    let lower = grouped.lower.unwrap();
                    assert!(lower <= got && got - lower <= 1e-6 * got, "{what}");
                    // The pressed nodes belong to one body: old node `order[a]` of block
                    // `b` when `order[a]` lies in its range.
                    let block_of = |old: usize| {
                        let mut start = 0;
                        sizes
                            .iter()
                            .position(|&s| {
                                start += s;
                                old < start
                            })
                            .unwrap()
                    };
                    let w = grouped.witness.as_ref().unwrap();
                    let pressed: std::collections::BTreeSet<usize> = (0..m)
                        .filter(|&a| w.r[dim * a] > 0.0)
                        .map(|a| block_of(order[a]))
                        .collect();
                    assert_eq!(pressed.len(), 1, "{what}: {pressed:?}");
                    let b = *pressed.iter().next().unwrap();
                    for a in (0..m).filter(|&a| block_of(order[a]) != b) {
                        assert_eq!(w.pattern[a], ContactPattern::Grazing, "{what}");
                        assert!((0..dim).all(|c| w.u[dim * a + c] == 0.0), "{what}");
                    }
                }
            }
            cases += 1;
        }
    }
    assert_eq!(cases, 36);
}

/// Two one-node bodies in 2D: `mu* = K_tt / |K_nt|` each (`tests/critical.rs`), so the pair's
/// is the lesser, 1; with no normal-tangential coupling in either, never.
#[test]
fn two_one_node_bodies_closed_form() {
    let k = DMatrix::from_row_slice(
        4,
        4,
        &[
            2.0, 1.0, 0.0, 0.0, //
            1.0, 1.0, 0.0, 0.0, //
            0.0, 0.0, 3.0, -1.0, //
            0.0, 0.0, -1.0, 2.0,
        ],
    );
    let pair = Problem::new(2, k, 0.5).unwrap();
    for method in [CriticalMethod::Bnb, CriticalMethod::Faces] {
        let c = critical(&pair, &settings(method, true)).unwrap();
        assert_eq!(c.info.groups, 2);
        let mu = mu_of(&c).unwrap();
        assert!((mu - 1.0).abs() <= 1e-8, "{method}: {mu}");
        assert!(c.certificate.unwrap().certified);
    }
    let none = Problem::new(2, DMatrix::from_diagonal_element(4, 4, 2.0), 0.5).unwrap();
    let c = critical(&none, &settings(CriticalMethod::Bnb, true)).unwrap();
    assert_eq!((c.status, c.info.groups), (CriticalStatus::Never, 2));
}

/// A coupling of 1e-300 between two bodies is a coupling: one search, the same `mu*` to the
/// bracket.
#[test]
fn a_tiny_coupling_is_a_coupling() {
    let mu = 3.0;
    for seed in 0..4u64 {
        let parts = [
            random_spd_problem_dim(2, 3, mu, seed),
            random_spd_problem_dim(2, 2, mu, seed + 50),
        ];
        let apart = uncoupled(&parts, &[0, 1, 2, 3, 4], mu);
        let mut k = apart.stiffness().clone();
        k[(0, 6)] = 1e-300;
        k[(6, 0)] = 1e-300;
        let joined = Problem::new(2, k, mu).unwrap();
        let one = critical(&joined, &settings(CriticalMethod::Bnb, false)).unwrap();
        let two = critical(&apart, &settings(CriticalMethod::Bnb, false)).unwrap();
        assert_eq!((one.info.groups, two.info.groups), (0, 2));
        match (mu_of(&one), mu_of(&two)) {
            (Some(a), Some(b)) => assert!((a - b).abs() <= 1e-6 * b, "seed {seed}: {a} {b}"),
            (a, b) => assert_eq!(a, b, "seed {seed}"),
        }
    }
}

/// A run stopped before or during the groups is incomplete, never a wrong bracket.
#[test]
fn a_stopped_grouped_run_is_incomplete() {
    let mu = 3.0;
    let parts = [
        random_spd_problem_dim(2, 3, mu, 1),
        random_spd_problem_dim(2, 3, mu, 2),
    ];
    let whole = uncoupled(&parts, &shuffle(6, 3), mu);
    let cancelled = AtomicBool::new(true);
    let c =
        critical_with_control(&whole, &CriticalSettings::default(), &|_| {}, &cancelled).unwrap();
    assert_eq!(c.status, CriticalStatus::Incomplete(Stop::Interrupted));
    assert_eq!((c.lower, c.mu_critical), (None, None));
    let timed = CriticalSettings {
        limits: Limits {
            time_limit: Some(Duration::ZERO),
            ..Limits::default()
        },
        ..CriticalSettings::default()
    };
    let c = critical(&whole, &timed).unwrap();
    assert!(matches!(
        c.status,
        CriticalStatus::Incomplete(Stop::TimeLimit(_))
    ));
    assert_eq!(c.mu_critical, None);
}

/// The maximal patterns of two or three random bodies side by side, nodes shuffled (2D by
/// `pattern-search` and `bnb`, 3D by `bnb`): the products of the bodies' own, the same set as
/// one search over the whole problem finds (a run as one shard of one, which is not split into
/// groups), streamed or not; each product's witness checked here on the whole problem.
#[test]
fn uncoupled_bodies_give_the_products_of_their_pieces() {
    use std::collections::BTreeSet;
    use wedged::{enumerate_patterns, enumerate_patterns_streaming, PatternMethod};
    use wedged::{PatternSettings, Shard};
    let mut products = 0;
    for (dim, sizes, method) in [
        (2, vec![2, 3], PatternMethod::Search),
        (2, vec![3, 3], PatternMethod::Search),
        (2, vec![2, 1, 2], PatternMethod::Bnb),
        (3, vec![2, 2], PatternMethod::Bnb),
    ] {
        for seed in 0..5u64 {
            let mu = 3.0;
            let parts: Vec<Problem> = sizes
                .iter()
                .enumerate()
                .map(|(b, &m)| random_spd_problem_dim(dim, m, mu, 300 * seed + b as u64))
                .collect();
            let m: usize = sizes.iter().sum();
            let order = shuffle(m, seed + 11);
            let whole = uncoupled(&parts, &order, mu);
            let what = format!("dim {dim}, sizes {sizes:?}, {method:?}, seed {seed}");
            let settings = PatternSettings {
                method,
                ..PatternSettings::default()
            };
            let grouped = enumerate_patterns(&whole, &settings).unwrap();
            assert_eq!(grouped.info.groups, sizes.len() as u64, "{what}");
            let one_search = enumerate_patterns(
                &whole,
                &PatternSettings {
                    shard: Some(Shard::new(1, 1).unwrap()),
                    ..settings.clone()
                },
            )
            .unwrap();
            assert_eq!(one_search.info.groups, 0, "{what}");
            let set = |p: &wedged::Patterns| -> BTreeSet<Vec<ContactPattern>> {
                p.patterns.iter().map(|q| q.pattern.clone()).collect()
            };
            assert_eq!(grouped.outcome, one_search.outcome, "{what}");
            assert_eq!(set(&grouped), set(&one_search), "{what}");
            // The products of the bodies' own patterns, by hand: old node `order[a]`.
            let own: Vec<Vec<Vec<ContactPattern>>> = parts
                .iter()
                .map(|p| {
                    let e = enumerate_patterns(p, &settings).unwrap();
                    let mut list: Vec<_> = e.patterns.into_iter().map(|q| q.pattern).collect();
                    if list.is_empty() {
                        list.push(vec![ContactPattern::Grazing; p.nodes()]);
                    }
                    list
                })
                .collect();
            let mut by_hand = BTreeSet::new();
            let count: usize = own.iter().map(Vec::len).product();
            for mut k in 0..count {
                let mut old = Vec::new();
                for list in &own {
                    old.extend(list[k % list.len()].iter().copied());
                    k /= list.len();
                }
                if old.iter().any(|&c| c != ContactPattern::Grazing) {
                    by_hand.insert(order.iter().map(|&o| old[o]).collect::<Vec<_>>());
                }
            }
            assert_eq!(set(&grouped), by_hand, "{what}");
            for q in &grouped.patterns {
                wedged::solution::check_solution(&whole, mu, &q.u, &q.r).unwrap();
                let total: f64 = (0..m).map(|a| q.r[dim * a]).sum();
                assert!((total - 1.0).abs() < 1e-9, "{what}");
            }
            let streamed = std::sync::Mutex::new(BTreeSet::new());
            let sink = |p: wedged::Pattern| {
                streamed.lock().unwrap().insert(p.pattern);
            };
            let s = enumerate_patterns_streaming(
                &whole,
                &settings,
                &|_| {},
                &AtomicBool::new(false),
                &sink,
            )
            .unwrap();
            assert_eq!(s.info.streamed as usize, by_hand.len(), "{what}");
            assert_eq!(streamed.into_inner().unwrap(), by_hand, "{what}");
            products += by_hand.len();
        }
    }
    assert!(products >= 60, "{products} products");
}

/// `--certify` of a grouped enumeration: every group's search certified exactly.
#[test]
fn a_grouped_enumeration_is_certified() {
    use wedged::{enumerate_patterns, PatternMethod, PatternSettings};
    let mu = 4.0;
    let parts = [
        random_spd_problem_dim(2, 3, mu, 5),
        random_spd_problem_dim(2, 2, mu, 6),
    ];
    let whole = uncoupled(&parts, &shuffle(5, 1), mu);
    for method in [PatternMethod::Search, PatternMethod::Bnb] {
        let e = enumerate_patterns(
            &whole,
            &PatternSettings {
                method,
                certify: true,
                ..PatternSettings::default()
            },
        )
        .unwrap();
        let c = e.certificate.clone().expect("asked");
        assert!(c.certified, "{method:?}: {:?}", c.failures);
        assert!(
            c.witnesses_checked > 0 && e.patterns.len() > 1,
            "{method:?}: {e:?}"
        );
    }
}
/// The contact-set search (`enumerate`'s 2D default) lists the same extreme rays of
/// uncoupled bodies as the seed's pruned double description: each ray lies on one body. (A
/// ray of one body had met another body's rows in round-off only, whose sum passed for a
/// sign; the search then combined rays of two bodies and failed its own check, on 5 of these
/// 24 problems.)
#[test]
fn the_search_lists_the_rays_of_uncoupled_bodies() {
    let mu = 3.0;
    let mut rays = 0;
    for sizes in [vec![1, 2], vec![3, 2], vec![2, 2, 2], vec![4, 3]] {
        for seed in 0..6u64 {
            let parts: Vec<Problem> = sizes
                .iter()
                .enumerate()
                .map(|(b, &m)| random_spd_problem_dim(2, m, mu, 100 * seed + b as u64))
                .collect();
            let m: usize = sizes.iter().sum();
            let whole = uncoupled(&parts, &shuffle(m, seed + 7), mu);
            let what = format!("sizes {sizes:?}, seed {seed}");
            let statuses = |method| {
                let settings = Settings {
                    method,
                    ..Settings::default()
                };
                let e = enumerate(&whole, &settings).unwrap_or_else(|e| panic!("{what}: {e}"));
                let mut s: Vec<String> = e.rays.iter().map(|r| format!("{:?}", r.status)).collect();
                s.sort();
                s
            };
            let (search, dd) = (statuses(Method::Search), statuses(Method::PrunedDd));
            assert_eq!(search, dd, "{what}");
            rays += search.len();
        }
    }
    assert!(rays >= 60, "{rays} rays");
}
