//! The critical friction coefficient of a built-in problem as a one-shot run (see
//! BENCHMARKS.md):
//!
//! ```text
//! cargo run --release -p wedged --example critical_run -- plug2d 10 8 [bnb|enumerate|faces] [TOL]
//! cargo run --release -p wedged --example critical_run -- plug3d 4 2 [METHOD] [TOL]
//! cargo run --release -p wedged --example critical_run -- random DIM M SEED [METHOD] [TOL]
//! ```
//!
//! It prints the bracket, the witness's statuses and the search statistics, and each new
//! incumbent on stderr as it comes; with the environment variable `CERTIFY` set, also the exact
//! certification. The plugs' `mu` (the first bar of `bnb`) is 2, or the environment variable
//! `MU`.

use std::sync::atomic::AtomicBool;

use wedged::{critical_with_control, CriticalMethod, CriticalProgress, CriticalSettings};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = || -> ! {
        eprintln!(
            "usage: critical_run (plug2d NX NY | plug3d NY NZ | random DIM M SEED) [METHOD] [TOL]"
        );
        std::process::exit(2)
    };
    let n = |i: usize| -> usize {
        args.get(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or_else(|| usage())
    };
    let mu: f64 = std::env::var("MU")
        .ok()
        .and_then(|m| m.parse().ok())
        .unwrap_or(2.0);
    let (problem, rest) = match args.first().map(String::as_str) {
        Some("plug2d") => {
            let model = wedged::examples::plug2d(n(1), n(2)).expect("the plug builds");
            (model.problem(mu).expect("definite"), 3)
        }
        Some("plug3d") => {
            let model = wedged::examples::plug3d(n(1), n(2)).expect("the plug builds");
            (model.problem(mu).expect("definite"), 3)
        }
        Some("random") => (
            wedged::examples::random_spd_problem_dim(n(1), n(2), 2.0, n(3) as u64),
            4,
        ),
        _ => usage(),
    };
    let method = match args.get(rest).map(String::as_str) {
        None | Some("bnb") => CriticalMethod::Bnb,
        Some("enumerate") => CriticalMethod::Enumerate,
        Some("faces") => CriticalMethod::Faces,
        Some(_) => usage(),
    };
    let tol = args
        .get(rest + 1)
        .and_then(|t| t.parse().ok())
        .unwrap_or(wedged::critical::DEFAULT_TOL);
    let settings = CriticalSettings {
        method,
        tol,
        certify: std::env::var_os("CERTIFY").is_some(),
        ..CriticalSettings::default()
    };
    // Each new incumbent (upper end) on stderr, with the time and the share of the tree explored.
    let start = std::time::Instant::now();
    let last = std::cell::Cell::new(f64::INFINITY);
    let progress = |p: CriticalProgress| {
        if let Some(upper) = p.upper.filter(|&u| u < last.get()) {
            last.set(upper);
            eprintln!(
                "{:8.2} s  upper {upper:.10}  explored {:.4}",
                start.elapsed().as_secs_f64(),
                p.explored
            );
        }
    };
    let c = critical_with_control(&problem, &settings, &progress, &AtomicBool::new(false))
        .expect("valid settings");
    println!(
        "m = {}, dim = {}, method {}: {} mu* = {:?} in [{:?}, {:?}]",
        problem.nodes(),
        problem.dim(),
        method,
        c.status.name(),
        c.mu_critical,
        c.lower,
        c.upper
    );
    if let Some(w) = &c.witness {
        let s: Vec<&str> = w.status.iter().map(|s| s.name()).collect();
        println!("witness: {}", s.join(" "));
    }
    println!("{:#?}", c.info);
    if let Some(cert) = &c.certificate {
        println!("{cert:#?}");
    }
    for u in &c.undecided {
        println!("undecided: {:?}: {}", u.contact, u.reason);
    }
}
