//! The `wedged` binary end to end: results, JSON, exit codes and one-line error messages.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use nalgebra::DMatrix;
use serde_json::Value;

fn wedged(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wedged"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn fixture(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name)
        .display()
        .to_string()
}

fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8(out.stderr.clone()).unwrap()
}

fn assert_success(out: &Output) {
    assert_eq!(
        out.status.code(),
        Some(0),
        "stdout:\n{}\nstderr:\n{}",
        stdout(out),
        stderr(out)
    );
    assert!(stderr(out).is_empty(), "stderr: {}", stderr(out));
}

/// Exit code 2, stderr one line `error: ...` containing every needle, no panic.
fn assert_bad_input(out: &Output, needles: &[&str]) {
    let err = stderr(out);
    assert_eq!(
        out.status.code(),
        Some(2),
        "stderr: {err}\nstdout: {}",
        stdout(out)
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.starts_with("error: "), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
    assert!(stdout(out).is_empty(), "stdout: {}", stdout(out));
}

/// A temporary directory with `files` written into it.
fn dir_with(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in files {
        fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

fn path_in(dir: &tempfile::TempDir, name: &str) -> String {
    dir.path().join(name).display().to_string()
}

/// Runs `enumerate` on a problem file with the given text; returns the output and the file's path.
fn enumerate_text(toml: &str, extra: &[&str]) -> (Output, String) {
    let dir = dir_with(&[("p.toml", toml)]);
    let path = path_in(&dir, "p.toml");
    let mut args = vec!["enumerate", path.as_str()];
    args.extend_from_slice(extra);
    (wedged(&args), path)
}

fn with_rows(rows: &str) -> String {
    format!("dim = 2\nmu = 1.1\n[stiffness]\nrows = {rows}\n")
}

fn json_stdout(out: &Output) -> Value {
    assert_success(out);
    serde_json::from_str(&stdout(out)).expect("stdout is JSON only")
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// Checks the fixed keys, and `K u = r` for every ray to 1e-9 relative.
fn check_report(report: &Value, k: &DMatrix<f64>) {
    let keys: Vec<&str> = report
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    for key in [
        "dim", "mu", "nodes", "method", "outcome", "complete", "stopped", "rays", "cones", "info",
        "version",
    ] {
        assert!(keys.contains(&key), "missing {key} in {keys:?}");
    }
    // `model` is there for a meshed body only.
    let expected = 11 + usize::from(keys.contains(&"model"));
    assert_eq!(keys.len(), expected, "{keys:?}");
    let info = report["info"].as_object().unwrap();
    for key in [
        "rays_after_node",
        "node_order",
        "pairs_tested",
        "adjacency_tests",
        "seconds",
    ] {
        assert!(info.contains_key(key), "info lacks {key}");
    }
    let n = k.nrows();
    assert_eq!(report["nodes"].as_u64().unwrap() as usize * 2, n);
    let rays = report["rays"].as_array().unwrap();
    assert_eq!(
        report["outcome"],
        if rays.is_empty() {
            "not-wedged"
        } else {
            "wedged"
        }
    );
    for ray in rays {
        let u = DMatrix::from_column_slice(n, 1, &floats(&ray["u"]));
        let r = DMatrix::from_column_slice(n, 1, &floats(&ray["r"]));
        let residual = (k * &u - &r).amax();
        let scale = k.amax() * u.amax() + r.amax();
        assert!(residual <= 1e-9 * scale, "K u - r = {residual:e} for {ray}");
        let r_n_sum: f64 = (0..n / 2).map(|i| r[2 * i]).sum();
        assert!((r_n_sum - 1.0).abs() < 1e-9, "sum r_n = {r_n_sum}");
        assert_eq!(ray["status"].as_array().unwrap().len(), n / 2);
    }
    for cone in report["cones"].as_array().unwrap() {
        for index in cone["rays"].as_array().unwrap() {
            assert!((index.as_u64().unwrap() as usize) < rays.len());
        }
        assert_eq!(cone["status"].as_array().unwrap().len(), n / 2);
    }
}

/// The stiffness of the `coupled_*` fixtures, read back from the array file.
fn coupled_k() -> DMatrix<f64> {
    let text = fs::read_to_string(fixture("coupled_array.mtx")).unwrap();
    let mut numbers = text.lines().filter(|l| !l.starts_with('%'));
    let n: usize = numbers
        .next()
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let values: Vec<f64> = numbers.map(|l| l.trim().parse().unwrap()).collect();
    DMatrix::from_column_slice(n, n, &values)
}

// ---- runs that complete ------------------------------------------------------------------------

#[test]
fn demo_runs_and_explains_itself() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = path_in(&dir, "demo-out");
    let out = wedged(&["demo", "--out", &out_dir]);
    assert_success(&out);
    let text = stdout(&out);
    assert!(text.starts_with("demo: "), "{text}");
    assert!(text.contains("V-notch"), "{text}");
    assert!(text.contains("problem demo: dim 2, 12 nodes"), "{text}");
    assert!(text.contains("wedged configuration"), "{text}");
    assert!(text.contains("info: "), "{text}");
    // It says where the files went, and they are there.
    assert!(text.contains(&out_dir), "{text}");
    let report: Value =
        serde_json::from_str(&fs::read_to_string(dir.path().join("demo-out/result.json")).unwrap())
            .unwrap();
    let (model, _) = wedged::examples::plug2d_demo().unwrap();
    check_report(&report, model.k());
    assert_eq!(report["model"]["contact"].as_array().unwrap().len(), 12);
    let cones = report["cones"].as_array().unwrap().len();
    assert!(cones > 0);
    for ext in ["vtu", "svg"] {
        let n = fs::read_dir(dir.path().join("demo-out"))
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .path()
                    .extension()
                    .is_some_and(|x| x == ext)
            })
            .count();
        assert_eq!(n, cones, "{ext} files");
    }
}

#[test]
fn inline_rows_give_the_known_rays() {
    let out = wedged(&["enumerate", &fixture("two_nodes.toml"), "--json", "-"]);
    let report = json_stdout(&out);
    let k = DMatrix::from_row_slice(
        4,
        4,
        &[
            2.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 1.0, 1.0,
        ],
    );
    check_report(&report, &k);
    assert_eq!(report["dim"], 2);
    assert_eq!(report["mu"], 1.1);
    assert_eq!(report["nodes"], 2);
    assert_eq!(report["outcome"], "wedged");
    let statuses: Vec<&Value> = report["rays"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| &r["status"])
        .collect();
    assert_eq!(
        statuses,
        [
            &serde_json::json!(["stick", "grazing"]),
            &serde_json::json!(["grazing", "stick"])
        ]
    );
    assert_eq!(
        report["cones"],
        serde_json::json!([{"rays": [0, 1], "status": ["contact", "contact"]}])
    );
    assert_eq!(report["version"], env!("CARGO_PKG_VERSION"));
}

#[test]
fn matrix_market_array_and_coordinate_agree() {
    let k = coupled_k();
    let array = json_stdout(&wedged(&[
        "enumerate",
        &fixture("coupled_array.toml"),
        "--json",
        "-",
    ]));
    let coordinate = json_stdout(&wedged(&[
        "enumerate",
        &fixture("coupled_coordinate.toml"),
        "--json",
        "-",
    ]));
    check_report(&array, &k);
    check_report(&coordinate, &k);
    assert_eq!(array["rays"].as_array().unwrap().len(), 7);
    assert_eq!(array["cones"].as_array().unwrap().len(), 4);
    assert_eq!(array["rays"], coordinate["rays"]);
    assert_eq!(array["cones"], coordinate["cones"]);
}

#[test]
fn every_method_gives_the_same_rays() {
    let run = |method: &str| {
        let out = wedged(&[
            "enumerate",
            &fixture("coupled_array.toml"),
            "--method",
            method,
            "--json",
            "-",
        ]);
        let report = json_stdout(&out);
        assert_eq!(report["method"], method);
        let statuses: Vec<Value> = report["rays"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["status"].clone())
            .collect();
        (statuses, report["cones"].clone())
    };
    let pruned = run("pruned-dd");
    assert_eq!(run("full-dd"), pruned);
    assert_eq!(run("faces"), pruned);
}

#[test]
fn one_node_wedges_above_its_critical_mu() {
    // mu* = K_tt / |K_nt| = 1.
    let toml = "dim = 2\nmu = 1.1\n[stiffness]\nrows = [[2, 1], [1, 1]]\n";
    let (out, _) = enumerate_text(toml, &["--json", "-"]);
    let above = json_stdout(&out);
    assert_eq!(above["outcome"], "wedged");
    assert_eq!(above["rays"].as_array().unwrap().len(), 1);
    assert_eq!(above["rays"][0]["status"], serde_json::json!(["stick"]));

    let (out, _) = enumerate_text(toml, &["--mu", "0.9", "--json", "-"]);
    let below = json_stdout(&out);
    assert_eq!(below["outcome"], "not-wedged");
    assert_eq!(below["mu"], 0.9);
    assert_eq!(below["rays"], serde_json::json!([]));
    assert_eq!(below["cones"], serde_json::json!([]));

    let (out, _) = enumerate_text(toml, &["--mu", "0.9"]);
    assert_success(&out);
    assert!(
        stdout(&out).contains(
            "no wedged configuration: only the trivial solution u = r = 0 exists at mu = 0.9"
        ),
        "{}",
        stdout(&out)
    );
}

#[test]
fn summary_lists_rays_and_pieces() {
    let out = wedged(&["enumerate", &fixture("coupled_array.toml")]);
    assert_success(&out);
    let text = stdout(&out);
    assert!(
        text.contains("dim 2, 3 nodes, mu = 1.5, method pruned-dd"),
        "{text}"
    );
    assert!(
        text.contains("7 wedged configurations (complementary extreme rays) in 4 convex pieces"),
        "{text}"
    );
    assert!(
        text.contains("node 1") && text.contains("separated") && text.contains("slip+"),
        "{text}"
    );
    assert!(text.contains("C contact, o separated, g grazing"), "{text}");
}

#[test]
fn json_file_is_written_atomically_next_to_the_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out_path = path_in(&dir, "result.json");
    let out = wedged(&["enumerate", &fixture("two_nodes.toml"), "--json", &out_path]);
    assert_success(&out);
    let text = stdout(&out);
    assert!(text.contains("2 wedged configurations"), "{text}");
    assert!(text.contains("JSON written to"), "{text}");
    let report: Value = serde_json::from_str(&fs::read_to_string(&out_path).unwrap()).unwrap();
    assert_eq!(report["outcome"], "wedged");
    // Only the result is left in the directory: the temporary file was renamed.
    let names: Vec<_> = fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["result.json"]);

    // A second run replaces the file.
    let out = wedged(&[
        "enumerate",
        &fixture("two_nodes.toml"),
        "--mu",
        "0.5",
        "--json",
        &out_path,
    ]);
    assert_success(&out);
    let report: Value = serde_json::from_str(&fs::read_to_string(&out_path).unwrap()).unwrap();
    assert_eq!(report["outcome"], "not-wedged");
}

#[test]
fn help_documents_exit_codes() {
    for args in [&["--help"][..], &["enumerate", "--help"], &["demo", "-h"]] {
        let out = wedged(args);
        assert_success(&out);
        let text = stdout(&out);
        assert!(
            text.contains("Exit codes:") && text.contains("2  bad input"),
            "{text}"
        );
    }
    assert!(stdout(&wedged(&["enumerate", "--help"])).contains("matrix_market"));
}

// ---- bad input: exit code 2 and one line naming the problem -----------------------------------

#[test]
fn missing_problem_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = path_in(&dir, "nothere.toml");
    assert_bad_input(&wedged(&["enumerate", &path]), &[&path, "cannot read"]);
}

#[test]
fn malformed_toml() {
    let (out, path) = enumerate_text("dim = 2\nmu = = 1\n", &[]);
    assert_bad_input(&out, &[&path, "TOML error at line 2"]);
}

#[test]
fn unknown_key() {
    let (out, path) = enumerate_text(
        &format!("friction = 3\n{}", with_rows("[[2, 1], [1, 1]]")),
        &[],
    );
    assert_bad_input(&out, &[&path, "line 1", "unknown field `friction`"]);
    let text = "dim = 2\nmu = 1\n[stiffness]\nrows = [[2, 1], [1, 1]]\nmatrix = 'K.mtx'\n";
    let (out, path) = enumerate_text(text, &[]);
    assert_bad_input(&out, &[&path, "line 5", "unknown field `matrix`"]);
}

#[test]
fn mu_from_the_command_line_alone() {
    let text = "dim = 2\n[stiffness]\nrows = [[2, 1], [1, 1]]\n";
    let (out, _) = enumerate_text(text, &["--mu", "1.1", "--json", "-"]);
    let json = json_stdout(&out);
    assert_eq!(json["mu"], 1.1);
    assert_eq!(json["rays"].as_array().unwrap().len(), 1);
}

#[test]
fn missing_keys() {
    let (out, path) = enumerate_text("dim = 2\n[stiffness]\nrows = [[2, 1], [1, 1]]\n", &[]);
    assert_bad_input(&out, &[&path, "missing `mu`"]);
    let (out, path) = enumerate_text("mu = 1\n[stiffness]\nrows = [[2, 1], [1, 1]]\n", &[]);
    assert_bad_input(&out, &[&path, "missing `dim`"]);
    let (out, path) = enumerate_text("dim = 2\nmu = 1\n", &[]);
    assert_bad_input(&out, &[&path, "missing the [stiffness] table"]);
}

#[test]
fn stiffness_needs_exactly_one_source() {
    let both = "dim = 2\nmu = 1\n[stiffness]\nrows = [[2, 1], [1, 1]]\nmatrix_market = 'K.mtx'\n";
    let (out, path) = enumerate_text(both, &[]);
    assert_bad_input(&out, &[&path, "both `matrix_market` and `rows`"]);
    let (out, path) = enumerate_text("dim = 2\nmu = 1\n[stiffness]\n", &[]);
    assert_bad_input(&out, &[&path, "[stiffness] needs"]);
}

#[test]
fn mu_zero() {
    let (out, path) = enumerate_text(
        "dim = 2\nmu = 0\n[stiffness]\nrows = [[2, 1], [1, 1]]\n",
        &[],
    );
    assert_bad_input(
        &out,
        &[
            &path,
            "friction coefficient mu must be finite and > 0, got 0",
        ],
    );
}

#[test]
fn mu_negative() {
    let (out, path) = enumerate_text(
        "dim = 2\nmu = -0.5\n[stiffness]\nrows = [[2, 1], [1, 1]]\n",
        &[],
    );
    assert_bad_input(&out, &[&path, "got -0.5"]);
    let (out, _) = enumerate_text(&with_rows("[[2, 1], [1, 1]]"), &["--mu", "-1"]);
    assert_bad_input(&out, &["--mu", "got -1"]);
}

#[test]
fn mu_nan_on_the_command_line() {
    let (out, _) = enumerate_text(&with_rows("[[2, 1], [1, 1]]"), &["--mu", "nan"]);
    assert_bad_input(&out, &["--mu", "got NaN"]);
}

#[test]
fn non_square_rows() {
    let (out, path) = enumerate_text(&with_rows("[[1, 0, 0], [0, 1, 0]]"), &[]);
    assert_bad_input(&out, &[&path, "not square: 2 rows, 3 columns"]);
}

#[test]
fn ragged_rows() {
    let rows = "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0], [0, 0, 0, 1]]";
    let (out, path) = enumerate_text(&with_rows(rows), &[]);
    assert_bad_input(&out, &[&path, "row 3 has 2 entries, row 1 has 4 entries"]);
}

#[test]
fn size_not_a_multiple_of_dim() {
    let (out, path) = enumerate_text(&with_rows("[[1, 0, 0], [0, 1, 0], [0, 0, 1]]"), &[]);
    assert_bad_input(&out, &[&path, "size 3, which is not a multiple of dim = 2"]);
}

#[test]
fn non_symmetric() {
    let (out, path) = enumerate_text(&with_rows("[[2, 1], [0.5, 1]]"), &[]);
    assert_bad_input(&out, &[&path, "not symmetric", "K[1,2]"]);
}

#[test]
fn indefinite() {
    let (out, path) = enumerate_text(&with_rows("[[1, 2], [2, 1]]"), &[]);
    assert_bad_input(&out, &[&path, "not positive definite", "pivot 2"]);
}

#[test]
fn nan_entry_in_matrix_market() {
    let mtx = "%%MatrixMarket matrix array real general\n2 2\n2\nnan\n1\n1\n";
    let toml = "dim = 2\nmu = 1\n[stiffness]\nmatrix_market = \"K.mtx\"\n";
    let dir = dir_with(&[("p.toml", toml), ("K.mtx", mtx)]);
    let out = wedged(&["enumerate", &path_in(&dir, "p.toml")]);
    assert_bad_input(
        &out,
        &[&path_in(&dir, "K.mtx"), "non-finite", "row 2, column 1"],
    );
}

#[test]
fn three_dimensional_problems_are_not_enumerated_yet() {
    let toml = "dim = 3\nmu = 1\n[stiffness]\nrows = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n";
    let (out, path) = enumerate_text(toml, &[]);
    assert_bad_input(&out, &[&path, "dim = 3", "not implemented"]);
}

#[test]
fn bad_method() {
    let out = wedged(&[
        "enumerate",
        &fixture("two_nodes.toml"),
        "--method",
        "simplex",
    ]);
    // clap's own usage error: exit 2, several lines, the first naming the option.
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    let first = err.lines().next().unwrap();
    assert!(
        first.starts_with("error: ") && first.contains("simplex") && first.contains("--method"),
        "{err}"
    );
    assert!(
        err.contains("pruned-dd") && !err.contains("panicked"),
        "{err}"
    );
}

#[test]
fn bad_zero_tolerance() {
    let out = wedged(&["enumerate", &fixture("two_nodes.toml"), "--zero-tol", "0.5"]);
    assert_bad_input(&out, &["zero_tol"]);
}

#[test]
fn malformed_matrix_market() {
    let toml = "dim = 2\nmu = 1\n[stiffness]\nmatrix_market = \"K.mtx\"\n";
    let dir = dir_with(&[
        ("p.toml", toml),
        (
            "K.mtx",
            "%%MatrixMarket matrix array real general\n2 2\n1\nx\n",
        ),
    ]);
    let out = wedged(&["enumerate", &path_in(&dir, "p.toml")]);
    assert_bad_input(&out, &[&format!("{}:4", path_in(&dir, "K.mtx"))]);
}

#[test]
fn missing_matrix_market_file() {
    let toml = "dim = 2\nmu = 1\n[stiffness]\nmatrix_market = \"sub/K.mtx\"\n";
    let dir = dir_with(&[("p.toml", toml)]);
    let out = wedged(&["enumerate", &path_in(&dir, "p.toml")]);
    let expected: PathBuf = dir.path().join("sub").join("K.mtx");
    assert_bad_input(&out, &[&expected.display().to_string(), "cannot read"]);
}

#[test]
fn unwritable_json_path() {
    let dir = tempfile::tempdir().unwrap();
    let out_path = path_in(&dir, "no/such/dir/out.json");
    let out = wedged(&["enumerate", &fixture("two_nodes.toml"), "--json", &out_path]);
    assert_bad_input(&out, &[&out_path, "cannot write"]);
}

// ---- limits ------------------------------------------------------------------------------------

#[test]
fn a_run_stopped_by_the_time_limit_is_marked_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let json = path_in(&dir, "out.json");
    let out = wedged(&[
        "enumerate",
        &fixture("coupled_array.toml"),
        "--time-limit",
        "0",
        "--json",
        &json,
    ]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.starts_with("incomplete: ") && err.contains("time limit"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(stdout(&out).contains("INCOMPLETE"), "{}", stdout(&out));
    // The JSON is whole, valid and says it is incomplete.
    let report: Value = serde_json::from_str(&fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["complete"], false);
    assert_eq!(report["outcome"], "incomplete");
    assert!(report["stopped"].as_str().unwrap().contains("time limit"));
    assert!(report["rays"].as_array().unwrap().is_empty());
}

#[test]
fn max_rays_stops_the_run() {
    let out = wedged(&[
        "enumerate",
        &fixture("coupled_array.toml"),
        "--max-rays",
        "3",
        "--json",
        "-",
    ]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let report = json_stdout_any(&out);
    assert_eq!(report["complete"], false);
    assert!(report["stopped"].as_str().unwrap().contains("3 rays"));
    // A complete run says so.
    let report = json_stdout(&wedged(&[
        "enumerate",
        &fixture("coupled_array.toml"),
        "--json",
        "-",
    ]));
    assert_eq!(report["complete"], true);
    assert_eq!(report["stopped"], Value::Null);
}

#[test]
fn bad_time_limit() {
    let out = wedged(&[
        "enumerate",
        &fixture("coupled_array.toml"),
        "--time-limit",
        "-1",
    ]);
    assert_bad_input(&out, &["--time-limit"]);
}

fn json_stdout_any(out: &Output) -> Value {
    serde_json::from_slice(&out.stdout).expect("valid JSON on stdout")
}
