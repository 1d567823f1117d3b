//! The contact-set search (`Method::Search`, and `PatternMethod::Search` without rays) against
//! the seed's pruned double description on seeded random problems and the triangle plug, and
//! their invariances: renumbered nodes, flipped tangents, nodes rescaled by factors from
//! `2^-20` to `2^20`. (`tests/agreement.rs` also runs the ray method beside every other method
//! on its families, `tests/patterns.rs` the pattern method beside the other pattern methods.)

mod common;

use common::random_spd;
use nalgebra::DMatrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::atomic::AtomicBool;

use wedged::patterns::{
    enumerate_patterns, enumerate_patterns_streaming, Pattern, PatternMethod, PatternSettings,
    Patterns,
};
use wedged::{
    enumerate, ContactPattern, Enumeration, Method, NodeStatus, Outcome, Problem, Settings,
};

fn run(problem: &Problem, method: Method) -> Enumeration {
    let e = enumerate(
        problem,
        &Settings {
            method,
            ..Settings::default()
        },
    )
    .unwrap_or_else(|e| panic!("{method} failed: {e}\nK = {}", problem.stiffness()));
    assert!(
        !matches!(e.outcome, Outcome::Incomplete(_)),
        "{method} incomplete: {:?}",
        e.info.search_undecided_faces
    );
    e
}

fn statuses(e: &Enumeration) -> Vec<Vec<NodeStatus>> {
    e.rays.iter().map(|r| r.status.clone()).collect()
}

#[test]
fn search_agrees_with_pruned_dd_on_300_random_instances() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let (mut wedged, mut rays, mut cones) = (0, 0, 0);
    for trial in 0..300 {
        let m = 2 + trial % 8;
        let mu = [0.5, 1.0, 1.5, 2.0, 3.0][trial % 5] * rng.gen_range(0.8..1.25);
        let p = Problem::new(2, random_spd(&mut rng, 2 * m), mu).unwrap();
        let a = run(&p, Method::PrunedDd);
        let b = run(&p, Method::Search);
        let what = format!("trial {trial} (m = {m}, mu = {mu})");
        assert_eq!(a.outcome, b.outcome, "{what}");
        assert_eq!(statuses(&a), statuses(&b), "{what}: rays differ");
        assert_eq!(a.cones, b.cones, "{what}: cones differ");
        if b.outcome == Outcome::Wedged {
            wedged += 1;
            // Every cone is the face of some leaf, so there are at least as many leaves.
            assert!(b.info.search_leaves as usize >= b.cones.len(), "{what}");
        }
        rays += b.rays.len();
        cones += b.cones.len();
    }
    // The family must exercise both outcomes and many pieces, or the test proves little.
    assert!(wedged > 100 && wedged < 300, "wedged in {wedged} of 300");
    assert!(
        rays > 1000 && cones > 300,
        "{rays} rays, {cones} cones in all"
    );
}

/// A random transformation of `k` ([`transformed`], then scaled as a whole by `2^-30` to
/// `2^30`): the node order, the flipped tangents, the node scales (`2^-20` to `2^20`) and the
/// transformed matrix.
fn random_transform(
    rng: &mut ChaCha8Rng,
    k: &DMatrix<f64>,
) -> (Vec<usize>, Vec<bool>, Vec<f64>, DMatrix<f64>) {
    let m = k.nrows() / 2;
    let mut order: Vec<usize> = (0..m).collect();
    for i in (1..m).rev() {
        order.swap(i, rng.gen_range(0..=i));
    }
    let flip: Vec<bool> = (0..m).map(|_| rng.gen_bool(0.5)).collect();
    let scale: Vec<f64> = (0..m).map(|_| 2f64.powi(rng.gen_range(-20..=20))).collect();
    let whole = 2f64.powi(rng.gen_range(-30..=30));
    let k2 = transformed(k, &order, &flip, &scale) * whole;
    (order, flip, scale, k2)
}

/// `T K T` for `T` = a node permutation (new node `a` is old node `order[a]`), a sign per node
/// on the tangent, and a power of two per node.
fn transformed(k: &DMatrix<f64>, order: &[usize], flip: &[bool], scale: &[f64]) -> DMatrix<f64> {
    let n = k.nrows();
    let mut t = DMatrix::<f64>::zeros(n, n);
    for (new, &old) in order.iter().enumerate() {
        t[(2 * new, 2 * old)] = scale[new];
        t[(2 * new + 1, 2 * old + 1)] = if flip[new] { -scale[new] } else { scale[new] };
    }
    &t * k * t.transpose()
}

#[test]
fn search_is_invariant_under_renumbering_flips_and_node_scales() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    for trial in 0..60 {
        let m = 2 + trial % 6;
        let k = random_spd(&mut rng, 2 * m);
        let mu = rng.gen_range(0.5..3.0);
        let base = run(&Problem::new(2, k.clone(), mu).unwrap(), Method::Search);
        let (order, flip, scale, k2) = random_transform(&mut rng, &k);
        let e = run(&Problem::new(2, k2, mu).unwrap(), Method::Search);
        // Map the transformed answer back: node `new` is old `order[new]`, slips flip with
        // the tangent.
        let mut mapped: Vec<Vec<NodeStatus>> = e
            .rays
            .iter()
            .map(|ray| {
                let mut s = vec![NodeStatus::Grazing; m];
                for (new, &old) in order.iter().enumerate() {
                    s[old] = match (ray.status[new], flip[new]) {
                        (NodeStatus::SlipPlus, true) => NodeStatus::SlipMinus,
                        (NodeStatus::SlipMinus, true) => NodeStatus::SlipPlus,
                        (st, _) => st,
                    };
                }
                s
            })
            .collect();
        mapped.sort();
        assert_eq!(
            statuses(&base),
            mapped,
            "trial {trial}: m = {m}, order {order:?}, flips {flip:?}, scales {scale:?}"
        );
        assert_eq!(base.cones.len(), e.cones.len(), "trial {trial}");
    }
}

/// `pattern-search` through the streaming API (each leaf tested for maximality on its own,
/// with no filter over the whole answer behind it), its streamed patterns sorted into
/// `patterns`; checked against the kept run (`enumerate_patterns`, which filters the maximal
/// ones at the end as well).
fn pattern_search(problem: &Problem) -> Patterns {
    pattern_search_in(problem, None)
}

/// [`pattern_search`] as one shard of one (`Some`): one search over the whole problem even
/// where its nodes fall into uncoupled groups (which a plain run searches apart,
/// `patterns/groups.rs`), so that the block problems below test the search's own maximality.
fn pattern_search_in(problem: &Problem, shard: Option<wedged::Shard>) -> Patterns {
    let settings = PatternSettings {
        method: PatternMethod::Search,
        shard,
        ..PatternSettings::default()
    };
    let streamed = std::sync::Mutex::new(Vec::new());
    let sink = |p: Pattern| streamed.lock().unwrap().push(p);
    let mut p =
        enumerate_patterns_streaming(problem, &settings, &|_| {}, &AtomicBool::new(false), &sink)
            .unwrap_or_else(|e| panic!("pattern-search failed: {e}\nK = {}", problem.stiffness()));
    assert!(
        !matches!(p.outcome, Outcome::Incomplete(_)),
        "pattern-search incomplete: {:?}",
        p.undecided
    );
    assert!(p.patterns.is_empty());
    p.patterns = streamed.into_inner().unwrap();
    p.patterns.sort_by(|a, b| a.pattern.cmp(&b.pattern));
    assert_eq!(p.info.streamed as usize, p.patterns.len());
    let kept = enumerate_patterns(problem, &settings).unwrap();
    assert_eq!(patterns_of(&kept), patterns_of(&p), "streamed and kept");
    assert_eq!(kept.outcome, p.outcome);
    p
}

/// The cones' patterns of a ray enumeration, sorted (the pattern methods sort theirs).
fn cone_patterns(e: &Enumeration) -> Vec<Vec<ContactPattern>> {
    let mut c: Vec<_> = e.cones.iter().map(|c| c.pattern.clone()).collect();
    c.sort();
    c
}

fn patterns_of(p: &Patterns) -> Vec<Vec<ContactPattern>> {
    p.patterns.iter().map(|q| q.pattern.clone()).collect()
}

/// The pieces of `pattern-search` are the cones of pruned-dd (which shares no code with it),
/// with the statuses of the cones' relative interiors, on 300 seeded instances up to m = 9.
#[test]
fn pattern_search_finds_the_cones_of_pruned_dd_on_300_random_instances() {
    let mut rng = ChaCha8Rng::seed_from_u64(4096);
    let (mut wedged, mut pieces, mut below) = (0, 0, 0);
    for trial in 0..300 {
        let m = 2 + trial % 8;
        let mu = [0.5, 1.0, 1.5, 2.0, 3.0][trial % 5] * rng.gen_range(0.8..1.25);
        let p = Problem::new(2, random_spd(&mut rng, 2 * m), mu).unwrap();
        let rays = run(&p, Method::PrunedDd);
        let found = pattern_search(&p);
        let what = format!("trial {trial} (m = {m}, mu = {mu})");
        assert_eq!(rays.outcome, found.outcome, "{what}");
        assert_eq!(cone_patterns(&rays), patterns_of(&found), "{what}");
        for q in &found.patterns {
            let cone = rays.cones.iter().find(|c| c.pattern == q.pattern).unwrap();
            assert_eq!(q.status, rays.cone_status(cone), "{what}");
        }
        wedged += (found.outcome == Outcome::Wedged) as usize;
        pieces += found.patterns.len();
        below += found.info.realised - found.info.streamed;
    }
    assert!(wedged > 100 && wedged < 300, "wedged in {wedged} of 300");
    assert!(pieces > 300, "{pieces} pieces in all");
    // Generic problems have no grazing node, so every leaf's piece is maximal.
    assert_eq!(below, 0);
}

/// Problems of independent blocks (separate bodies or contact patches), where a leaf that
/// presses nodes of some blocks only leaves the other blocks' nodes grazing (their gaps follow
/// their own block's reactions, all zero): its piece lies in a larger leaf's whenever another
/// block can wedge on its own, and the maximality test of each leaf must drop it. The streamed
/// pieces equal pruned-dd's cones.
#[test]
fn pattern_search_tests_each_leaf_for_maximality_on_block_problems() {
    let (mut below, mut pieces, mut kept_grazing) = (0, 0, 0);
    for trial in 0..40u64 {
        let b = 1 + (trial % 3) as usize;
        let m = b * (2 + (trial % 2) as usize);
        let mu = [1.0, 1.5, 2.0, 3.0][(trial % 4) as usize];
        let p = wedged::examples::block_spd_problem(m, b, mu, 100 + trial);
        let rays = run(&p, Method::PrunedDd);
        let found = pattern_search_in(&p, Some(wedged::Shard::new(1, 1).unwrap()));
        // Searched apart, the groups give the same pieces.
        assert_eq!(patterns_of(&found), patterns_of(&pattern_search(&p)));
        let what = format!("trial {trial} (m = {m}, blocks of {b}, mu = {mu})");
        assert_eq!(cone_patterns(&rays), patterns_of(&found), "{what}");
        below += found.info.realised - found.info.streamed;
        pieces += found.patterns.len();
        kept_grazing += found
            .patterns
            .iter()
            .filter(|q| q.pattern.contains(&ContactPattern::Grazing))
            .count();
    }
    eprintln!("blocks: {pieces} pieces, {kept_grazing} with a grazing node, {below} leaves below another's piece");
    assert!(below > 20, "{below} leaves below another's piece");
    assert!(pieces > 40, "{pieces} pieces");
}

/// The triangle plug of issue 20 at m = 16 (`n = 8`): the same pieces as pruned-dd's cones, from
/// both search methods. (m = 20 was compared once by hand: 5 pieces, 527 rays, equal.)
#[test]
fn both_searches_agree_with_pruned_dd_on_the_triangle_plug() {
    let model = wedged::examples::plug2d_tri(8).unwrap();
    let p = model.problem(2.0).unwrap();
    assert_eq!(p.nodes(), 16);
    let truth = run(&p, Method::PrunedDd);
    let rays = run(&p, Method::Search);
    assert_eq!(statuses(&truth), statuses(&rays));
    assert_eq!(truth.cones, rays.cones);
    assert!(truth.cones.len() >= 2, "{} cones", truth.cones.len());
    assert_eq!(cone_patterns(&truth), patterns_of(&pattern_search(&p)));
}

/// The demo plug (m = 12) at the ray methods' largest friction coefficient, `RAYS_MU_MAX`:
/// both ray methods finish with the same rays and pieces, thousands of them. (The search's
/// check compared a ray with its recomputation entry by entry, and a pressure's round-off,
/// repeated `mu` times in a slipping node's `r_t`, failed it: an internal failure at `1e4`.)
#[test]
fn the_ray_methods_agree_at_their_largest_mu() {
    let (model, _) = wedged::examples::plug2d_demo().unwrap();
    let p = model.problem(wedged::RAYS_MU_MAX).unwrap();
    let truth = run(&p, Method::PrunedDd);
    let rays = run(&p, Method::Search);
    assert_eq!(statuses(&truth), statuses(&rays));
    assert_eq!(truth.cones, rays.cones);
    assert!(truth.rays.len() > 10_000, "{} rays", truth.rays.len());
}

/// Renumbered nodes, flipped tangents, node scales from `2^-20` to `2^20` and a scaled `K` do
/// not change the pieces of `pattern-search`.
#[test]
fn pattern_search_is_invariant_under_renumbering_flips_and_node_scales() {
    let mut rng = ChaCha8Rng::seed_from_u64(78);
    let mut nonempty = 0;
    for trial in 0..60 {
        let m = 2 + trial % 7;
        let k = random_spd(&mut rng, 2 * m);
        let mu = rng.gen_range(0.5..3.0);
        let base = pattern_search(&Problem::new(2, k.clone(), mu).unwrap());
        let (order, _, scale, k2) = random_transform(&mut rng, &k);
        let e = pattern_search(&Problem::new(2, k2, mu).unwrap());
        let mut mapped: Vec<Vec<ContactPattern>> = e
            .patterns
            .iter()
            .map(|q| {
                let mut s = vec![ContactPattern::Grazing; m];
                for (new, &old) in order.iter().enumerate() {
                    s[old] = q.pattern[new];
                }
                s
            })
            .collect();
        mapped.sort();
        assert_eq!(
            patterns_of(&base),
            mapped,
            "trial {trial}: order {order:?}, scales {scale:?}"
        );
        nonempty += !mapped.is_empty() as usize;
    }
    assert!(nonempty > 15, "{nonempty}");
}

/// `pattern-search --certify` (no drive cuts; every prune solved again by the cone solver and
/// checked exactly; each leaf's pattern from its cone program; the maximal ones by comparison):
/// the same pieces and statuses as the plain run on 300 seeded random instances and on block
/// problems (grazing nodes, leaves below another's piece), the certificate passing every time,
/// with a refutation behind every prune of the search.
#[test]
fn certified_pattern_search_agrees_with_the_plain_run() {
    // Block problems as one shard of one: one search, not one per uncoupled group.
    let certified = |p: &Problem, shard: Option<wedged::Shard>| {
        let settings = PatternSettings {
            method: PatternMethod::Search,
            certify: true,
            shard,
            ..PatternSettings::default()
        };
        let c = enumerate_patterns(p, &settings)
            .unwrap_or_else(|e| panic!("certified pattern-search failed: {e}"));
        let cert = c.certificate.as_ref().expect("asked for");
        assert!(cert.certified, "{:?}\nK = {}", cert.failures, p.stiffness());
        assert_eq!(cert.witnesses_checked, c.patterns.len());
        // Every prune but the all-separated node's (r = 0 there) has its refutation.
        assert!(cert.refutations_checked as u64 + 1 >= c.info.pruned_infeasible);
        c
    };
    let mut rng = ChaCha8Rng::seed_from_u64(4097);
    let (mut refuted, mut pieces) = (0, 0);
    for trial in 0..300 {
        let m = 2 + trial % 8;
        let mu = [0.5, 1.0, 1.5, 2.0, 3.0][trial % 5] * rng.gen_range(0.8..1.25);
        let p = Problem::new(2, random_spd(&mut rng, 2 * m), mu).unwrap();
        let plain = pattern_search(&p);
        let c = certified(&p, None);
        let what = format!("trial {trial} (m = {m}, mu = {mu})");
        assert_eq!(plain.outcome, c.outcome, "{what}");
        assert_eq!(patterns_of(&plain), patterns_of(&c), "{what}");
        for (a, b) in plain.patterns.iter().zip(&c.patterns) {
            assert_eq!(a.status, b.status, "{what}");
        }
        assert_eq!(c.info.bound_tightenings, 0, "{what}: no drive cuts");
        refuted += c.certificate.unwrap().refutations_checked;
        pieces += c.patterns.len();
    }
    assert!(
        pieces > 300 && refuted > 3000,
        "{pieces} pieces, {refuted} refutations"
    );
    for trial in 0..40u64 {
        let b = 1 + (trial % 3) as usize;
        let m = b * (2 + (trial % 2) as usize);
        let mu = [1.0, 1.5, 2.0, 3.0][(trial % 4) as usize];
        let p = wedged::examples::block_spd_problem(m, b, mu, 100 + trial);
        let what = format!("block trial {trial} (m = {m}, blocks of {b}, mu = {mu})");
        let whole = Some(wedged::Shard::new(1, 1).unwrap());
        assert_eq!(
            patterns_of(&pattern_search(&p)),
            patterns_of(&certified(&p, whole)),
            "{what}"
        );
    }
}

/// A limit that stops the search run (in its tree, in the rays of its pieces, or while they are
/// checked) leaves an incomplete result whose rays are checked rays of the complete answer and
/// no cones: at a tenth, three tenths and six tenths of the complete run's time, on a random
/// m = 12 problem with thousands of rays. (Where the stop lands depends on the machine; each
/// run is checked wherever it lands, and one that finished must equal the complete answer.)
#[test]
fn a_stopped_search_reports_checked_rays_of_the_answer_and_no_cones() {
    let mut rng = ChaCha8Rng::seed_from_u64(4934);
    let p = Problem::new(2, random_spd(&mut rng, 24), 1.5).unwrap();
    let start = std::time::Instant::now();
    let full = run(&p, Method::Search);
    let seconds = start.elapsed().as_secs_f64();
    let all: std::collections::HashSet<Vec<NodeStatus>> = statuses(&full).into_iter().collect();
    assert!(all.len() > 100, "{} rays", all.len());
    let mut stopped = 0;
    for share in [0.1, 0.3, 0.6] {
        let limit = std::time::Duration::from_secs_f64(seconds * share);
        let e = enumerate(
            &p,
            &Settings {
                method: Method::Search,
                limits: wedged::Limits {
                    time_limit: Some(limit),
                    ..wedged::Limits::default()
                },
                ..Settings::default()
            },
        )
        .unwrap();
        match e.outcome {
            Outcome::Incomplete(wedged::Stop::TimeLimit(_)) => {
                stopped += 1;
                assert!(e.cones.is_empty(), "{share}: cones of an incomplete run");
                for ray in &e.rays {
                    assert!(
                        all.contains(&ray.status),
                        "{share}: a ray not in the answer"
                    );
                }
            }
            _ => {
                assert_eq!(statuses(&e), statuses(&full), "{share}");
                assert_eq!(e.cones, full.cones, "{share}");
            }
        }
    }
    println!(
        "{} rays in {seconds:.2} s; {stopped} of 3 limited runs stopped",
        all.len()
    );
}
