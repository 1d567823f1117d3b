//! Which method `wedged enumerate` runs when none is named (issue 20: the fastest complete
//! method for the problem, named in the summary and the JSON): in 2D `search` (the extreme
//! rays, by the contact-set search) up to 12 contact nodes and `pattern-search` (the pieces)
//! above, `bnb` above with `--certify`, `pruned-dd` with a bound on the rays held; `bnb` in
//! 3D. The default's rays are pruned-dd's, and its pieces above 12 nodes pruned-dd's cones.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_code, example, text, wedged};
use serde_json::Value;

/// The example plug with an `n x n` triangle mesh: `m = 2n` contact nodes.
fn plug(dir: &Path, n: usize) -> PathBuf {
    let text = std::fs::read_to_string(example("plug2d.toml"))
        .unwrap()
        .replace("nx = 8 ", &format!("nx = {n} "))
        .replace("ny = 6 ", &format!("ny = {n} "))
        .replace("element = \"quad\"", "element = \"tri\"")
        .replace("mu = 1.8", "mu = 2.0");
    let path = dir.join(format!("plug_{n}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// The JSON of `wedged enumerate PROBLEM EXTRA...`.
fn run(problem: &Path, extra: &[&str]) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("out.json");
    let mut args = vec![
        "enumerate",
        problem.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ];
    args.extend(extra);
    let out = wedged(&args);
    assert_code(&out, 0);
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let first = text(&out.stdout);
    let method = doc["method"].as_str().unwrap();
    assert!(first.contains(&format!("method {method}")), "{first}");
    doc
}

fn pieces(doc: &Value) -> Vec<String> {
    let mut p: Vec<String> = doc["patterns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["pattern"].to_string())
        .collect();
    p.sort();
    p
}

#[test]
fn small_2d_problems_list_their_rays() {
    let dir = tempfile::tempdir().unwrap();
    let doc = run(&plug(dir.path(), 6), &[]);
    assert_eq!(doc["nodes"], 12);
    assert_eq!(doc["method"], "search");
    assert!(!doc["rays"].as_array().unwrap().is_empty());
    // The same rays (in the same order) and pieces as the seed's pruned double description,
    // which a bound on the rays held asks for.
    let dd = run(&plug(dir.path(), 6), &["--max-rays", "10000000"]);
    assert_eq!(dd["method"], "pruned-dd");
    let statuses = |d: &Value| -> Vec<String> {
        d["rays"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["status"].to_string())
            .collect()
    };
    assert_eq!(statuses(&doc), statuses(&dd));
    assert_eq!(pieces(&doc), pieces(&dd));
}

#[test]
fn larger_2d_problems_list_their_pieces() {
    let dir = tempfile::tempdir().unwrap();
    let problem = plug(dir.path(), 7);
    let doc = run(&problem, &[]);
    assert_eq!(doc["nodes"], 14);
    assert_eq!(doc["method"], "pattern-search");
    assert!(doc["rays"].as_array().unwrap().is_empty());
    // The same pieces as the rays' cones.
    let rays = run(&problem, &["--method", "pruned-dd"]);
    assert!(!pieces(&doc).is_empty());
    assert_eq!(pieces(&doc), pieces(&rays));
    // Certified: bnb, with the same pieces.
    let certified = run(&problem, &["--certify"]);
    assert_eq!(certified["method"], "bnb");
    assert_eq!(certified["certified"], true);
    assert_eq!(pieces(&certified), pieces(&doc));
    // A bound on the rays held asks for the rays.
    let bounded = run(&problem, &["--max-rays", "10000000"]);
    assert_eq!(bounded["method"], "pruned-dd");
}

#[test]
fn a_3d_problem_gets_bnb() {
    let doc = run(Path::new(&example("plug3d.toml")), &[]);
    assert_eq!(doc["method"], "bnb");
}
