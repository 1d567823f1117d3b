//! `cargo bench -p wedged --bench patterns`: the 3D sign patterns.
//!
//! - `bnb_plug3d_m20_1.2mu*`: branch and bound on the 3D plug ([`plug3d`]`(4, 2)`, 20 contact
//!   nodes) at 1.2 times its critical friction coefficient, the target (under 60 s on
//!   the 2-core machine). `mu* in [1.49023, 1.49121]` was bracketed by
//!   `cargo run --release -p wedged --example plug3d_run -- 4 2`; the run uses 1.2 times the
//!   upper end. Each sample is one whole enumeration, so the group takes several minutes.
//! - `random3d_m6_*`: a seeded random 3D problem with 6 nodes, by branch and bound and by the
//!   pyramid method with 4 and 8 faces (how the approximation's cost grows with `k`).

use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Duration;
use wedged::examples::{plug3d, random_spd_problem_dim};
use wedged::patterns::{enumerate_patterns, PatternMethod, PatternSettings};
use wedged::{Outcome, Problem};

/// The upper end of the bracket of the plug's `mu*` (see the module docs).
const PLUG3D_M20_MU_STAR: f64 = 1.49121;

fn run(problem: &Problem, method: PatternMethod) -> usize {
    let settings = PatternSettings {
        method,
        ..PatternSettings::default()
    };
    let r = enumerate_patterns(problem, &settings).unwrap();
    assert_eq!(r.outcome, Outcome::Wedged);
    r.patterns.len()
}

fn patterns(c: &mut Criterion) {
    let mut small = c.benchmark_group("patterns_small");
    small.sample_size(10);
    small.measurement_time(Duration::from_secs(20));
    let problem = random_spd_problem_dim(3, 6, 2.0, 7);
    small.bench_function("random3d_m6_bnb", |b| {
        b.iter(|| run(&problem, PatternMethod::Bnb))
    });
    for faces in [4, 8] {
        small.bench_function(format!("random3d_m6_pyramid{faces}"), |b| {
            b.iter(|| run(&problem, PatternMethod::Pyramid { faces }))
        });
    }
    small.finish();

    let mut plug = c.benchmark_group("patterns_plug3d");
    plug.sample_size(10);
    plug.warm_up_time(Duration::from_secs(1));
    plug.measurement_time(Duration::from_secs(300));
    let model = plug3d(4, 2).unwrap();
    let problem = model.problem(1.2 * PLUG3D_M20_MU_STAR).unwrap();
    assert_eq!(problem.nodes(), 20);
    plug.bench_function("bnb_plug3d_m20_1.2mu*", |b| {
        b.iter(|| run(&problem, PatternMethod::Bnb))
    });
    plug.finish();
}

criterion_group!(benches, patterns);
criterion_main!(benches);
