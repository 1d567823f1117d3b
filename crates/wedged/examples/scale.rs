//! `cargo run --release -p wedged --example scale -- M MU SEED [pruned|full] [band=B|block=B]`: one
//! timed enumeration of a seeded random problem (dense coupling, local coupling within `B` nodes,
//! or independent blocks of `B` nodes), with the kept-ray counts.
use wedged::examples::{banded_spd_problem, block_spd_problem, random_spd_problem};
use wedged::{enumerate, Method, Settings};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let m: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(10);
    let mu: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let seed: u64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(2024);
    let method = match args.get(4).map(String::as_str) {
        Some("full") => Method::FullDd,
        _ => Method::PrunedDd,
    };
    let family = args.get(5).map(String::as_str).unwrap_or("dense");
    let number = |prefix: &str| family.strip_prefix(prefix).and_then(|s| s.parse().ok());
    let p = if let Some(b) = number("band=") {
        banded_spd_problem(m, b, mu, seed)
    } else if let Some(b) = number("block=") {
        block_spd_problem(m, b, mu, seed)
    } else {
        random_spd_problem(m, mu, seed)
    };
    let e = enumerate(
        &p,
        &Settings {
            method,
            ..Settings::default()
        },
    )
    .expect("enumeration");
    let i = &e.info;
    println!(
        "m = {m}, mu = {mu}, seed = {seed}, {family}, {method}: {} rays, {} cones, {:.3} s, \
         peak {} rays held, {} pairs ({} rejected by pattern, {} by count/combinatorics), \
         {} rank tests, {} rays created",
        e.rays.len(),
        e.cones.len(),
        i.seconds,
        i.peak_rays,
        i.pairs_tested,
        i.pairs_rejected_pattern,
        i.pairs_rejected_combinatorial,
        i.adjacency_tests,
        i.rays_created
    );
    println!("kept after each node: {:?}", i.rays_after_node);
}
