//! `wedged enumerate --jsonl FILE` (issue 20): each maximal sign pattern as one line of JSON as
//! soon as it is found. The lines are the pieces of `--json` (same patterns, statuses, witnesses
//! and margins, in the order found) in 2D (`pattern-search`, the default with `--jsonl`) and 3D
//! (`bnb`); a run stopped by its time limit has written the pieces it reports (exit 3); the
//! combinations that cannot stream are refused (exit 2, one line).

mod common;

use std::path::Path;

use common::{assert_bad_input, assert_code, example, example_with, text, wedged};
use serde_json::Value;

fn lines(path: &Path) -> Vec<Value> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).expect("each line is one JSON object"))
        .collect()
}

/// The patterns, sorted by pattern (the JSON's order).
fn sorted(mut v: Vec<Value>) -> Vec<Value> {
    v.sort_by_key(|p| p["pattern"].to_string());
    v
}

/// `--jsonl` writes the pieces of `--json`, and `--json` beside it counts them.
fn streams_the_pieces_of_json(problem: &str, method: &[&str], expected_method: &str) {
    let dir = tempfile::tempdir().unwrap();
    let (jsonl, json, whole) = (
        dir.path().join("pieces.jsonl"),
        dir.path().join("streamed.json"),
        dir.path().join("whole.json"),
    );
    let mut args = vec!["enumerate", problem, "--jsonl", jsonl.to_str().unwrap()];
    args.extend(["--json", json.to_str().unwrap()]);
    let out = wedged(&args);
    assert_code(&out, 0);
    let mut args = vec!["enumerate", problem, "--json", whole.to_str().unwrap()];
    args.extend(method);
    assert_code(&wedged(&args), 0);
    let streamed = lines(&jsonl);
    let whole: Value = serde_json::from_str(&std::fs::read_to_string(&whole).unwrap()).unwrap();
    let pieces = whole["patterns"].as_array().unwrap().clone();
    assert!(!pieces.is_empty());
    assert_eq!(sorted(streamed.clone()), sorted(pieces), "{problem}");
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(doc["info"]["method"], expected_method);
    assert_eq!(doc["patterns"].as_array().unwrap().len(), 0);
    assert_eq!(doc["info"]["streamed"], streamed.len());
    assert_eq!(doc["outcome"], "wedged");
    let summary = text(&out.stdout);
    let said = format!(
        "{} maximal sign patterns written to {}",
        streamed.len(),
        jsonl.display()
    );
    assert!(summary.contains(&said), "{summary}");
}

#[test]
fn a_2d_mesh_streams_the_pieces_of_pattern_search() {
    streams_the_pieces_of_json(
        &example("plug2d.toml"),
        &["--method", "pattern-search"],
        "pattern-search",
    );
}

#[test]
fn a_3d_mesh_streams_the_pieces_of_bnb() {
    streams_the_pieces_of_json(&example("plug3d.toml"), &[], "bnb");
}

/// `--jsonl -` streams to stdout, which then holds the pieces' lines only (the same as the
/// file's; it had written a file named `-`); a reader that stops early is no failure.
#[test]
fn the_pieces_stream_to_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("pieces.jsonl");
    let problem = example("plug3d.toml");
    assert_code(
        &wedged(&["enumerate", &problem, "--jsonl", file.to_str().unwrap()]),
        0,
    );
    let out = wedged(&["enumerate", &problem, "--jsonl", "-"]);
    assert_code(&out, 0);
    let piped: Vec<Value> = text(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("each line of stdout is one JSON object"))
        .collect();
    assert!(!piped.is_empty());
    assert_eq!(sorted(piped), sorted(lines(&file)));
    assert!(!Path::new("-").exists());
    // Both to stdout, or both to one file: refused.
    assert_bad_input(
        &wedged(&["enumerate", &problem, "--jsonl", "-", "--json", "-"]),
        &["--json -", "--jsonl -", "stdout"],
    );
    let f = file.to_str().unwrap();
    assert_bad_input(
        &wedged(&["enumerate", &problem, "--jsonl", f, "--json", f]),
        &["--json and --jsonl name the same file"],
    );
}

/// A run stopped by its time limit: exit 3, and the file holds exactly the pieces the summary
/// counts, each one whole.
#[test]
fn a_stopped_run_has_written_what_it_found() {
    let dir = tempfile::tempdir().unwrap();
    // The 2D plug with m = 60 takes about 2 to 2.5 s on the 2-core machine (m = 50, 1 s, came
    // in under a limit of 1 s once the search was faster): stopped at 0.5 s, well before its
    // end.
    let plug = example_with(
        "plug2d.toml",
        &[
            ("nx", "30".into()),
            ("ny", "30".into()),
            ("element", "\"tri\"".into()),
            ("mu", "2.0".into()),
        ],
    );
    assert!(
        plug.contains("nx = 30") && plug.contains("ny = 30"),
        "{plug}"
    );
    let problem = dir.path().join("plug.toml");
    std::fs::write(&problem, plug).unwrap();
    let jsonl = dir.path().join("pieces.jsonl");
    let out = wedged(&[
        "enumerate",
        problem.to_str().unwrap(),
        "--jsonl",
        jsonl.to_str().unwrap(),
        "--time-limit",
        "0.5",
    ]);
    assert_code(&out, 3);
    let streamed = lines(&jsonl);
    let summary = text(&out.stdout);
    assert!(summary.contains("INCOMPLETE"), "{summary}");
    let said = format!("{} maximal sign pattern", streamed.len());
    assert!(summary.contains(&said), "{said:?} not in {summary}");
    assert!(text(&out.stderr).contains("incomplete"));
}

/// A 3D run (`bnb`, which writes each orbit of pieces as its search meets the orbit's first
/// leaf) stopped by its time limit: exit 3, and every line it wrote is one line of the
/// complete run's, to the bit (the witnesses do not depend on where the search stopped).
#[test]
fn a_stopped_3d_run_has_written_pieces_of_the_whole_answer() {
    let dir = tempfile::tempdir().unwrap();
    // The V-groove plug with m = 20 at 1.2 mu*: 592 pieces in about 0.6 to 1.1 s on the
    // 2-core machine; stopped at 0.15 s.
    let plug = example_with(
        "plug3d.toml",
        &[
            ("mu", "1.7895".into()),
            ("ny", "4".into()),
            ("nz", "2".into()),
        ],
    );
    assert!(
        plug.contains("mu = 1.7895\n") && plug.contains("ny = 4\n") && plug.contains("nz = 2\n"),
        "{plug}"
    );
    let problem = dir.path().join("plug.toml");
    std::fs::write(&problem, plug).unwrap();
    let (part, whole) = (
        dir.path().join("part.jsonl"),
        dir.path().join("whole.jsonl"),
    );
    let run = |file: &Path, limit: &[&str]| {
        let mut args = vec!["enumerate", problem.to_str().unwrap(), "--jsonl"];
        args.push(file.to_str().unwrap());
        args.extend(limit);
        wedged(&args)
    };
    let out = run(&part, &["--time-limit", "0.15"]);
    assert_code(&out, 3);
    assert_code(&run(&whole, &[]), 0);
    let read = |f: &Path| std::fs::read_to_string(f).unwrap();
    let (part, whole) = (read(&part), read(&whole));
    let all: std::collections::HashSet<&str> = whole.lines().collect();
    assert_eq!(all.len(), 592);
    let written: Vec<&str> = part.lines().collect();
    assert!(written.len() < 592, "{} lines", written.len());
    for line in &written {
        assert!(
            all.contains(line),
            "not a piece of the whole answer: {line}"
        );
    }
    let said = format!("{} maximal sign pattern", written.len());
    assert!(
        text(&out.stdout).contains(&said),
        "{said:?} not in the summary"
    );
}

#[test]
fn what_cannot_stream_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.jsonl");
    let (problem, out) = (example("plug2d.toml"), out.to_str().unwrap().to_string());
    let run = |extra: &[&str]| {
        let mut args = vec!["enumerate", &problem, "--jsonl", &out];
        args.extend(extra);
        wedged(&args)
    };
    assert_bad_input(
        &run(&["--method", "pruned-dd"]),
        &["--jsonl", "pruned-dd", "rays"],
    );
    let vtk = dir.path().join("vtk");
    assert_bad_input(
        &run(&["--vtk", vtk.to_str().unwrap()]),
        &["--vtk", "--jsonl"],
    );
    let part = dir.path().join("part.json");
    assert_bad_input(
        &run(&["--shard", "1/2", "--json", part.to_str().unwrap()]),
        &["--jsonl", "--shard 1/2"],
    );
    let here = dir.path().to_str().unwrap();
    assert_bad_input(
        &wedged(&["enumerate", &problem, "--jsonl", here]),
        &["is a directory", "--jsonl"],
    );
    let missing = dir.path().join("no/such/dir/x.jsonl");
    assert_bad_input(
        &wedged(&["enumerate", &problem, "--jsonl", missing.to_str().unwrap()]),
        &["cannot write the --jsonl file"],
    );
}
