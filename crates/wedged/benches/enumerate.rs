//! `cargo bench -p wedged --bench enumerate`: pruned-dd against full-dd, pruned-dd's growth,
//! and the contact-set searches: `search` (rays) against pruned-dd on random m = 9 at mu = 1.5
//! and the triangle plug of issue 20 ([`plug2d_tri`], mu = 2), `pattern-search` (pieces)
//! against bnb on the plug.
//!
//! Problems: `K = A A^T + diag` with `A` a seeded uniform `2m x 2m` matrix, `mu = 1`
//! ([`random_spd_problem`]). The kept-ray counts per node are printed once per size (they are
//! deterministic). m = 18 takes minutes per run on this family, so it is measured once with
//! `cargo run --release -p wedged --example scale -- 18 1 2024` instead (see BENCHMARKS.md).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use wedged::examples::{plug2d_tri, random_spd_problem};
use wedged::patterns::{enumerate_patterns, PatternMethod, PatternSettings};
use wedged::{enumerate, Method, Problem, Settings};

fn settings(method: Method) -> Settings {
    Settings {
        method,
        ..Settings::default()
    }
}

fn pruned_vs_full(c: &mut Criterion) {
    let mut group = c.benchmark_group("m10");
    group.sample_size(10);
    let p = random_spd_problem(10, 1.0, 2024);
    for method in [Method::PrunedDd, Method::FullDd] {
        let e = enumerate(&p, &settings(method)).unwrap();
        eprintln!(
            "m = 10, {method}: {} rays, peak {} held, after each node {:?}",
            e.rays.len(),
            e.info.peak_rays,
            e.info.rays_after_node
        );
        group.bench_function(BenchmarkId::new(method.name(), 10), |b| {
            b.iter(|| enumerate(&p, &settings(method)).unwrap())
        });
    }
    group.finish();
}

fn pruned_growth(c: &mut Criterion) {
    let mut group = c.benchmark_group("pruned-dd");
    group.sample_size(10);
    for m in [10, 12, 14] {
        let p = random_spd_problem(m, 1.0, 2024);
        let e = enumerate(&p, &settings(Method::PrunedDd)).unwrap();
        eprintln!(
            "m = {m}: {} rays, {} cones, peak {} held, after each node {:?}",
            e.rays.len(),
            e.cones.len(),
            e.info.peak_rays,
            e.info.rays_after_node
        );
        group.bench_function(BenchmarkId::from_parameter(m), |b| {
            b.iter(|| enumerate(&p, &settings(Method::PrunedDd)).unwrap())
        });
    }
    group.finish();
}

fn search_vs_pruned(c: &mut Criterion) {
    let mut group = c.benchmark_group("search");
    group.sample_size(10);
    let random = random_spd_problem(9, 1.5, 2024);
    let plug = |n: usize| {
        let model = plug2d_tri(n).unwrap();
        model.problem(2.0).unwrap()
    };
    // Rays: (name, problem, whether pruned-dd is run too: at m = 20 it takes about 40 s).
    // Beyond m = 20 the rays themselves explode (29,720 at m = 30), so pieces only.
    let cases = [
        ("random_m9", random, true),
        ("plug_tri_m16", plug(8), true),
        ("plug_tri_m20", plug(10), false),
    ];
    for (name, p, with_pruned) in &cases {
        let e = enumerate(p, &settings(Method::Search)).unwrap();
        eprintln!(
            "{name}: {} rays, {} cones, {} search nodes, {} leaves",
            e.rays.len(),
            e.cones.len(),
            e.info.search_nodes,
            e.info.search_leaves
        );
        let methods: &[Method] = if *with_pruned {
            &[Method::Search, Method::PrunedDd]
        } else {
            &[Method::Search]
        };
        for &method in methods {
            group.bench_function(BenchmarkId::new(method.name(), name), |b| {
                b.iter(|| enumerate(p, &settings(method)).unwrap())
            });
        }
    }
    // Pieces: pattern-search against bnb.
    let pieces = |p: &Problem, method: PatternMethod| {
        let settings = PatternSettings {
            method,
            ..PatternSettings::default()
        };
        enumerate_patterns(p, &settings).unwrap()
    };
    for (name, p, with_bnb) in [
        ("plug_tri_m20", plug(10), true),
        ("plug_tri_m30", plug(15), false),
    ] {
        let methods: &[PatternMethod] = if with_bnb {
            &[PatternMethod::Search, PatternMethod::Bnb]
        } else {
            &[PatternMethod::Search]
        };
        for &method in methods {
            group.bench_function(BenchmarkId::new(method.name(), name), |b| {
                b.iter(|| pieces(&p, method))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, pruned_vs_full, pruned_growth, search_vs_pruned);
criterion_main!(benches);
