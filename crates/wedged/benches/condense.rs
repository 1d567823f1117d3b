//! `cargo bench -p wedged --bench condense`: condensation of large meshes onto their contact
//! nodes (assembly, sparse Cholesky of the eliminated block, Schur complement), the targets of
//! the FE front end: a 2D mesh of 200,000 dofs onto 200 contact nodes and a 3D mesh of 100,000
//! dofs onto 150, each under 20 s on the 2-core machine. Bodies: [`wide_plug2d`] and
//! [`wide_vgroove`]. Each sample is one whole condensation, so 10 samples take minutes.

use criterion::{criterion_group, criterion_main, Criterion};
use std::time::Duration;
use wedged::examples::{wide_plug2d, wide_vgroove};

fn condense(c: &mut Criterion) {
    let mut group = c.benchmark_group("condense");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(60));
    let model = wide_plug2d(989, 100).unwrap();
    eprintln!("2D: {:?}", model.stats());
    drop(model);
    group.bench_function("2d_200k_dofs_200_contact", |b| {
        b.iter(|| wide_plug2d(989, 100).unwrap())
    });
    let model = wide_vgroove(332, 24, 3).unwrap();
    eprintln!("3D: {:?}", model.stats());
    drop(model);
    group.bench_function("3d_100k_dofs_150_contact", |b| {
        b.iter(|| wide_vgroove(332, 24, 3).unwrap())
    });
    group.finish();
}

criterion_group!(benches, condense);
criterion_main!(benches);
