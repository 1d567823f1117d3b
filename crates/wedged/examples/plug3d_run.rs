//! The 3D plug benchmark as a one-shot run (see BENCHMARKS.md):
//!
//! ```text
//! cargo run --release -p wedged --example plug3d_run -- 4 2            # m = 20: bracket mu* in [1, 2], then 1.2 mu*
//! cargo run --release -p wedged --example plug3d_run -- 4 2 --mu 2.5   # one run at a given mu
//! cargo run --release -p wedged --example plug3d_run -- 4 2 --mu 1.7895 --certify
//! ```
//!
//! Without `--mu` it brackets the critical friction coefficient by bisection on "branch and
//! bound finds a pattern", from `[--lo, --hi]` (default `[1, 2]`) to a relative width of 1e-3, then enumerates at 1.2 times its upper
//! end and prints the search's statistics, with the pruned share of the `2^(m+1) - 1` nodes of
//! the full tree.

use std::time::Instant;
use wedged::patterns::{enumerate_patterns, PatternMethod, PatternSettings};
use wedged::Outcome;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n = |i: usize| -> usize {
        args.get(i).and_then(|a| a.parse().ok()).unwrap_or_else(|| {
            eprintln!("usage: plug3d_run NY NZ [--mu MU] [--pyramid K]");
            std::process::exit(2)
        })
    };
    let flag = |name: &str| -> Option<f64> {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
    };
    let model = wedged::examples::plug3d(n(0), n(1)).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(2)
    });
    let base = model.problem(1.0).expect("the plug is definite");
    let m = base.nodes();
    let method = match flag("--pyramid") {
        Some(k) => PatternMethod::Pyramid { faces: k as usize },
        None => PatternMethod::Bnb,
    };
    let settings = PatternSettings {
        method,
        ..PatternSettings::default()
    };
    let certify = args.iter().any(|a| a == "--certify");
    let solve = |mu: f64| {
        let problem = base.with_mu(mu).expect("mu > 0");
        enumerate_patterns(&problem, &settings).expect("valid settings")
    };
    let mu = match flag("--mu") {
        Some(mu) => mu,
        None => {
            let (mut lo, mut hi) = (flag("--lo").unwrap_or(1.0), flag("--hi").unwrap_or(2.0));
            assert!(
                solve(hi).outcome == Outcome::Wedged,
                "no wedging at mu = {hi}"
            );
            let start = Instant::now();
            while hi - lo > 1e-3 * hi {
                let mid = 0.5 * (lo + hi);
                let r = solve(mid);
                match r.outcome {
                    Outcome::Wedged => hi = mid,
                    Outcome::NotWedged => lo = mid,
                    Outcome::Incomplete(s) => panic!("incomplete at mu = {mid}: {s}"),
                }
            }
            println!(
                "m = {m}: mu* in [{lo:.5}, {hi:.5}] (bisection, {:.1} s)",
                start.elapsed().as_secs_f64()
            );
            1.2 * hi
        }
    };
    let start = Instant::now();
    let r = if certify {
        let problem = base.with_mu(mu).expect("mu > 0");
        let settings = PatternSettings {
            certify: true,
            ..settings.clone()
        };
        enumerate_patterns(&problem, &settings).expect("valid settings")
    } else {
        solve(mu)
    };
    let seconds = start.elapsed().as_secs_f64();
    if let Some(c) = &r.certificate {
        println!(
            "certified {}: {} witnesses, {} refutations ({} failed), {} doubts; {:?}",
            c.certified,
            c.witnesses_checked,
            c.refutations_checked,
            c.refutations_failed,
            c.doubts,
            c.failures
        );
    }
    let i = &r.info;
    let tree = 2f64.powi(m as i32 + 1) - 1.0;
    println!(
        "{method} at mu = {mu:.5}: {:?}, {} maximal patterns ({} realised), {seconds:.2} s",
        r.outcome,
        r.patterns.len(),
        i.realised
    );
    println!(
        "  nodes visited {} ({} of them inherited), leaves {}, pruned {} infeasible + {} unpressed; visited share of \
         the full tree {:.3e}, leaves reached / 2^m = {:.3e}",
        i.nodes_visited,
        i.nodes_inherited,
        i.leaves,
        i.pruned_infeasible,
        i.pruned_unpressed,
        (i.nodes_visited + i.leaves) as f64 / tree,
        i.leaves as f64 / 2f64.powi(m as i32)
    );
    println!(
        "  SOCPs {} ({} retried, {} undecided, {} near-degenerate); pyramid rays {}, candidates \
         {}, spurious {}",
        i.socps,
        i.retries,
        i.uncertain,
        i.near_degenerate,
        i.pyramid_rays,
        i.candidates,
        i.spurious
    );
    for p in &r.patterns {
        let s: String = p
            .status
            .iter()
            .map(|s| match s.name() {
                "separated" => 'o',
                "grazing" => '.',
                "stick" => 'S',
                _ => 's',
            })
            .collect();
        println!("  {s}  margin {:.2e}", p.margin);
    }
}
