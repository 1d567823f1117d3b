//! `cargo run --release -p wedged --example scale -- M MU SEED [full]`: one timed enumeration of a
//! seeded random problem, with the kept-ray counts.
use wedged::examples::random_spd_problem;
use wedged::{enumerate, Method, Settings};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let m: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(10);
    let mu: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let seed: u64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(2024);
    let method = if args.get(4).map(String::as_str) == Some("full") {
        Method::FullDd
    } else {
        Method::PrunedDd
    };
    let p = random_spd_problem(m, mu, seed);
    let e = enumerate(
        &p,
        &Settings {
            method,
            ..Settings::default()
        },
    )
    .expect("enumeration");
    println!(
        "m = {m}, mu = {mu}, seed = {seed}, {method}: {} rays, {} cones, {:.3} s, peak {}, pairs {} (pattern-rejected {}, comb-rejected {}), rank tests {}, created {}\nkept after each node: {:?}",
        e.rays.len(), e.cones.len(), e.info.seconds, e.info.peak_rays, e.info.pairs_tested, e.info.pairs_rejected_pattern, e.info.pairs_rejected_combinatorial, e.info.adjacency_tests, e.info.rays_created, e.info.rays_after_node
    );
}
