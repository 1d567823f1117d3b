//! `cargo run --release -p wedged --example lattice_run -- N MU`: pruned-dd on the lattice plug
//! with `N` contact nodes per side.
use wedged::examples::lattice_plug;
use wedged::{enumerate, Settings};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(5);
    let mu: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(3.0);
    let p = lattice_plug(n, mu);
    match enumerate(&p, &Settings::default()) {
        Ok(e) => println!(
            "lattice plug, m = {}, mu = {mu}: {} rays, {} cones, {:.3} s, peak {} rays held\nkept after each node: {:?}",
            p.nodes(),
            e.rays.len(),
            e.cones.len(),
            e.info.seconds,
            e.info.peak_rays,
            e.info.rays_after_node
        ),
        Err(err) => println!("lattice plug, m = {}, mu = {mu}: error: {err}", p.nodes()),
    }
}
