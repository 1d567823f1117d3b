//! `cargo bench -p wedged --bench enumerate`: pruned-dd against full-dd, and pruned-dd's growth.
//!
//! Problems: `K = A A^T + diag` with `A` a seeded uniform `2m x 2m` matrix, `mu = 1`
//! ([`random_spd_problem`]). The kept-ray counts per node are printed once per size (they are
//! deterministic). m = 18 takes minutes per run on this family, so it is measured once with
//! `cargo run --release -p wedged --example scale -- 18 1 2024` instead (see BENCHMARKS.md).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use wedged::examples::random_spd_problem;
use wedged::{enumerate, Method, Settings};

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

criterion_group!(benches, pruned_vs_full, pruned_growth);
criterion_main!(benches);
