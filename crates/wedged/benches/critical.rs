//! `cargo bench -p wedged --bench critical`: the critical friction coefficient.
//!
//! - `plug2d_m16_bnb` / `plug2d_m16_enumerate`: the 2D plug ([`plug2d`]`(10, 8)`, 16 contact
//!   nodes), `mu*` by branch and bound and by the seed's method (enumeration at `mu = 2`, then
//!   each cone's threshold). The issue asks for bnb to be at least 10x faster.
//! - `plug2d_m16_bnb_certify`: the same bnb run with `certify` (every refutation and the
//!   witness re-checked in exact arithmetic); the difference is the price of `--certify`.
//! - `plug2d_m60_bnb`: the 2D plug with 60 contact nodes ([`plug2d`]`(38, 30)`), problem `mu`
//!   2 (target: under 30 s).
//! - `plug3d_m20_bnb`: the 3D plug ([`plug3d`]`(4, 2)`, 20 contact nodes) by branch and bound
//!   (target: under 60 s). Its problem `mu` (the first bar of the search) is 2.
//!
//! Every run asserts that it found `mu*` (status wedged).

use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Duration;
use wedged::examples::{plug2d, plug3d};
use wedged::{critical, CriticalMethod, CriticalSettings, CriticalStatus, Problem};

fn run(problem: &Problem, method: CriticalMethod) -> f64 {
    run_with(problem, method, false)
}

fn run_with(problem: &Problem, method: CriticalMethod, certify: bool) -> f64 {
    let settings = CriticalSettings {
        method,
        certify,
        ..CriticalSettings::default()
    };
    let c = critical(problem, &settings).unwrap();
    assert_eq!(c.status, CriticalStatus::Wedged);
    if certify {
        let cert = c.certificate.as_ref().unwrap();
        assert!(cert.certified, "{:?}", cert.failures);
    }
    c.mu_critical.unwrap()
}

fn bench(c: &mut Criterion) {
    let mut two = c.benchmark_group("critical_plug2d");
    two.sample_size(10);
    two.measurement_time(Duration::from_secs(60));
    let model = plug2d(10, 8).unwrap();
    let problem = model.problem(2.0).unwrap();
    assert_eq!(problem.nodes(), 16);
    for method in [CriticalMethod::Bnb, CriticalMethod::Enumerate] {
        two.bench_function(format!("plug2d_m16_{method}"), |b| {
            b.iter(|| run(&problem, method))
        });
    }
    two.bench_function("plug2d_m16_bnb_certify", |b| {
        b.iter(|| run_with(&problem, CriticalMethod::Bnb, true))
    });
    two.finish();

    let model = plug2d(38, 30).unwrap();
    let problem = model.problem(2.0).unwrap();
    one_run_group(
        c,
        "critical_plug2d_large",
        "plug2d_m60_bnb",
        &problem,
        60,
        120,
    );
    let model = plug3d(4, 2).unwrap();
    let problem = model.problem(2.0).unwrap();
    one_run_group(c, "critical_plug3d", "plug3d_m20_bnb", &problem, 20, 40);
}

/// A group of its own for one long `bnb` run of `problem` (`m` contact nodes): 10 samples in
/// about `secs` seconds.
fn one_run_group(
    c: &mut Criterion,
    group: &str,
    name: &str,
    problem: &Problem,
    m: usize,
    secs: u64,
) {
    assert_eq!(problem.nodes(), m);
    let mut g = c.benchmark_group(group);
    g.sample_size(10);
    g.warm_up_time(Duration::from_secs(1));
    g.measurement_time(Duration::from_secs(secs));
    g.bench_function(name, |b| b.iter(|| run(problem, CriticalMethod::Bnb)));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
