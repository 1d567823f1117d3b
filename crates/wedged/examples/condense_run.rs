//! One timed condensation of a benchmark body (see BENCHMARKS.md):
//!
//! ```text
//! cargo run --release -p wedged --example condense_run -- 2d 989 100      # 200,000 dofs
//! cargo run --release -p wedged --example condense_run -- 3d 332 24 3     # 99,900 dofs
//! ```

use std::time::Instant;
use wedged::examples::{wide_plug2d, wide_vgroove};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n = |i: usize| -> usize { args[i].parse().expect("a number of divisions") };
    let start = Instant::now();
    let model = match args.first().map(String::as_str) {
        Some("2d") => wide_plug2d(n(1), n(2)),
        Some("3d") => wide_vgroove(n(1), n(2), n(3)),
        _ => {
            eprintln!("usage: condense_run 2d NX NY | 3d NX NY NZ");
            std::process::exit(2);
        }
    }
    .unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(2)
    });
    let total = start.elapsed().as_secs_f64();
    let s = model.stats();
    println!(
        "{} dofs, {} eliminated, {} contact nodes; K_oo nnz (lower) {}",
        s.dofs, s.eliminated, s.contact_nodes, s.nnz_oo
    );
    println!(
        "mesh + assembly {:.2} s (assembly {:.2} s), sparse Cholesky {:.2} s, Schur complement {:.2} s; total {total:.2} s",
        total - s.seconds_factor - s.seconds_schur,
        s.seconds_assembly,
        s.seconds_factor,
        s.seconds_schur
    );
    let t = Instant::now();
    let u: Vec<f64> = (0..model.k().nrows())
        .map(|i| 1e-6 * (i % 7) as f64)
        .collect();
    let state = model.recover(&u);
    println!(
        "recovery of one state (displacement, forces, stresses): {:.2} s; max von Mises {:.3e}",
        t.elapsed().as_secs_f64(),
        state.von_mises.iter().cloned().fold(0.0, f64::max)
    );
}
