//! The `wedged` binary end to end: results, JSON, exit codes and one-line error messages.

mod common;

use common::{example, example_with, fixture};
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

/// `K u - r` relative to the terms, and `sum r_n`, of a solution `(u, r)` of a `dim`-D problem.
fn residual_and_normal_sum(k: &DMatrix<f64>, dim: usize, u: &[f64], r: &[f64]) -> (f64, f64) {
    let n = k.nrows();
    let u = DMatrix::from_column_slice(n, 1, u);
    let r = DMatrix::from_column_slice(n, 1, r);
    let residual = (k * &u - &r).amax();
    let scale = k.amax() * u.amax() + r.amax();
    let r_n_sum: f64 = (0..n / dim).map(|i| r[dim * i]).sum();
    (residual / scale, r_n_sum)
}

/// Checks the fixed keys, `K u = r` for every ray to 1e-9 relative and for every pattern's
/// witness to 1e-8 relative, and `sum r_n = 1`.
fn check_report(report: &Value, k: &DMatrix<f64>) {
    let keys: Vec<&str> = report
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    for key in [
        "dim",
        "mu",
        "nodes",
        "rigid_modes",
        "method",
        "outcome",
        "complete",
        "stopped",
        "certified",
        "certified_complete",
        "rays",
        "cones",
        "patterns",
        "undecided",
        "info",
        "version",
    ] {
        assert!(keys.contains(&key), "missing {key} in {keys:?}");
    }
    // `model` is there for a meshed body only.
    let expected = 16 + usize::from(keys.contains(&"model"));
    assert_eq!(keys.len(), expected, "{keys:?}");
    let info = report["info"].as_object().unwrap();
    let ray_method =
        ["pruned-dd", "full-dd", "faces", "search"].contains(&report["method"].as_str().unwrap());
    let info_keys: &[&str] = if ray_method {
        &[
            "rays_after_node",
            "node_order",
            "pairs_tested",
            "adjacency_tests",
            "seconds",
            "peak_rss_bytes",
        ]
    } else {
        &[
            "method",
            "pyramid_faces",
            "nodes_visited",
            "nodes_inherited",
            "pruned_infeasible",
            "pruned_unpressed",
            "leaves",
            "candidates",
            "spurious",
            "pyramid_rays",
            "socps",
            "retries",
            "uncertain",
            "near_degenerate",
            "realised",
            "streamed",
            "bound_tightenings",
            "lp_solves",
            "lp_pivots",
            "lp_fallbacks",
            "mirrored",
            "images",
            "mapped",
            "groups",
            "seconds",
            "peak_rss_bytes",
        ]
    };
    for key in info_keys {
        assert!(info.contains_key(*key), "info lacks {key}");
    }
    if !ray_method {
        assert_eq!(info.len(), info_keys.len(), "{info:?}");
        assert_eq!(report["info"]["method"], report["method"]);
    }
    let n = k.nrows();
    let dim = report["dim"].as_u64().unwrap() as usize;
    let m = report["nodes"].as_u64().unwrap() as usize;
    assert_eq!(m * dim, n);
    let rays = report["rays"].as_array().unwrap();
    let patterns = report["patterns"].as_array().unwrap();
    if report["complete"] == true {
        assert_eq!(
            report["outcome"],
            if patterns.is_empty() {
                "not-wedged"
            } else {
                "wedged"
            }
        );
        assert!(report["undecided"].as_array().unwrap().is_empty());
    }
    for ray in rays {
        let (residual, r_n_sum) =
            residual_and_normal_sum(k, dim, &floats(&ray["u"]), &floats(&ray["r"]));
        assert!(residual <= 1e-9, "K u - r = {residual:e} for {ray}");
        assert!((r_n_sum - 1.0).abs() < 1e-9, "sum r_n = {r_n_sum}");
        assert_eq!(ray["status"].as_array().unwrap().len(), m);
    }
    for cone in report["cones"].as_array().unwrap() {
        for index in cone["rays"].as_array().unwrap() {
            assert!((index.as_u64().unwrap() as usize) < rays.len());
        }
        assert_eq!(cone["status"].as_array().unwrap().len(), m);
    }
    if ray_method {
        // One pattern per cone, in the same order; the margin is null.
        let cones = report["cones"].as_array().unwrap();
        assert_eq!(patterns.len(), cones.len());
        for (p, c) in patterns.iter().zip(cones) {
            assert_eq!(p["pattern"], c["status"]);
            assert_eq!(p["margin"], Value::Null);
        }
    } else {
        assert!(rays.is_empty() && report["cones"].as_array().unwrap().is_empty());
    }
    for p in patterns {
        let keys: Vec<&str> = p.as_object().unwrap().keys().map(String::as_str).collect();
        // (in the document's order: serde_json keeps it, `preserve_order`)
        assert_eq!(keys, ["pattern", "status", "u", "r", "margin"]);
        let (residual, r_n_sum) =
            residual_and_normal_sum(k, dim, &floats(&p["u"]), &floats(&p["r"]));
        assert!(residual <= 1e-8, "K u - r = {residual:e} for {p}");
        assert!((r_n_sum - 1.0).abs() < 1e-8, "sum r_n = {r_n_sum}");
        let pattern = p["pattern"].as_array().unwrap();
        let status = p["status"].as_array().unwrap();
        assert_eq!((pattern.len(), status.len()), (m, m));
        // The status at the witness agrees with the pattern.
        for (q, s) in pattern.iter().zip(status) {
            let (q, s) = (q.as_str().unwrap(), s.as_str().unwrap());
            let expected: &[&str] = match q {
                "contact" => &["stick", "slip", "slip+", "slip-"],
                "separated" => &["separated"],
                "grazing" => &["grazing"],
                other => panic!("pattern {other}"),
            };
            assert!(expected.contains(&s), "{q} with {s}");
        }
        if !ray_method {
            assert!(p["margin"].as_f64().unwrap() > 0.0, "{p}");
        }
    }
}

/// The (pattern, status) pairs of a report, sorted.
fn pattern_set(report: &Value) -> Vec<(Value, Value)> {
    let mut set: Vec<(Value, Value)> = report["patterns"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p["pattern"].clone(), p["status"].clone()))
        .collect();
    set.sort_by_key(|(p, s)| format!("{p}{s}"));
    set
}

/// A seeded random 3D problem with 4 nodes, written as `rows = [...]` into a temporary
/// directory; returns its stiffness and the file (kept alive by the directory).
fn random_3d(mu: f64, seed: u64) -> (DMatrix<f64>, tempfile::TempDir, String) {
    let problem = wedged::examples::random_spd_problem_dim(3, 4, mu, seed);
    let k = problem.stiffness().clone();
    let rows: Vec<String> = (0..k.nrows())
        .map(|i| {
            let row: Vec<String> = (0..k.ncols()).map(|j| format!("{:e}", k[(i, j)])).collect();
            format!("[{}]", row.join(", "))
        })
        .collect();
    let toml = format!(
        "dim = 3\nmu = {mu}\n[stiffness]\nrows = [\n  {}\n]\n",
        rows.join(",\n  ")
    );
    let dir = dir_with(&[("p3.toml", &toml)]);
    let path = path_in(&dir, "p3.toml");
    (k, dir, path)
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
    // And the plug's critical friction coefficient, last.
    assert!(
        text.contains("\ncritical friction coefficient: mu* = "),
        "{text}"
    );
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

/// `value` without the entries that change from run to run (times and memory), recursively.
fn without_timings(value: &Value) -> Value {
    match value {
        Value::Object(map) => Value::Object(
            map.iter()
                .filter(|(k, _)| !["seconds", "peak", "time"].iter().any(|w| k.contains(w)))
                .map(|(k, v)| (k.clone(), without_timings(v)))
                .collect(),
        ),
        Value::Array(items) => Value::Array(items.iter().map(without_timings).collect()),
        other => other.clone(),
    }
}

/// `--json FILE` is written as the document is made, `--json -` from its text: the same
/// document (but its times), for a ray method (pieces from the cones) and a pattern method,
/// 2D and 3D.
#[test]
fn a_json_file_holds_the_document_of_stdout() {
    let dir = tempfile::tempdir().unwrap();
    let runs: [(&str, &[&str]); 3] = [
        (&fixture("coupled_array.toml"), &[]),
        (&fixture("coupled_array.toml"), &["--method", "bnb"]),
        (&example("plug3d.toml"), &[]),
    ];
    for (k, (file, extra)) in runs.iter().enumerate() {
        let path = path_in(&dir, &format!("run{k}.json"));
        let mut args = vec!["enumerate", file];
        args.extend_from_slice(extra);
        let mut to_file = args.clone();
        to_file.extend(["--json", &path]);
        assert_success(&wedged(&to_file));
        args.extend(["--json", "-"]);
        let stdout = json_stdout(&wedged(&args));
        let written: Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
        let pieces = written["patterns"].as_array().unwrap().len();
        assert!(pieces > 0, "{file}: no pieces");
        assert_eq!(
            without_timings(&written),
            without_timings(&stdout),
            "{file} {extra:?}"
        );
    }
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
        text.contains("dim 2, 3 nodes, mu = 1.5, method search"),
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
    let help = stdout(&wedged(&["enumerate", "--help"]));
    assert!(help.contains("matrix_market"), "{help}");
    assert!(!help.contains("only 2 can be enumerated"), "{help}");
    for needle in [
        "bnb",
        "pyramid",
        "pattern-faces",
        "--pyramid-faces",
        "could not decide",
    ] {
        assert!(help.contains(needle), "{needle:?} not in {help}");
    }
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

/// Above the ray methods' largest friction coefficient, the floating-point ray methods refuse
/// the problem as bad input (they had failed as a bug, exit 1); `--exact` and the sign
/// patterns take it.
#[test]
fn mu_beyond_the_ray_methods_resolution() {
    let text = with_rows("[[2, 1], [1, 1]]");
    let (out, path) = enumerate_text(&text, &["--mu", "1e5"]);
    assert_bad_input(&out, &[&path, "mu = 100000 is above 1e4", "--exact"]);
    for method in [&["--exact"][..], &["--method", "pattern-search"]] {
        let (out, _) = enumerate_text(&text, &[&["--mu", "1e5"][..], method].concat());
        assert_eq!(out.status.code(), Some(0), "{method:?}: {out:?}");
    }
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

// ---- 3D problems and the pattern methods ------------------------------------------------------

#[test]
fn a_3d_problem_gives_the_same_patterns_by_bnb_and_pyramid() {
    // Seed 1 at mu = 1.5: six maximal patterns (none at mu = 0.9).
    let (k, _dir, path) = random_3d(1.5, 1);
    let run = |extra: &[&str]| {
        let mut args = vec!["enumerate", path.as_str(), "--json", "-"];
        args.extend_from_slice(extra);
        let report = json_stdout(&wedged(&args));
        check_report(&report, &k);
        assert_eq!(report["dim"], 3);
        assert_eq!(report["complete"], true);
        report
    };
    // bnb is the default in 3D.
    let default = run(&[]);
    assert_eq!(default["method"], "bnb");
    let bnb = run(&["--method", "bnb"]);
    let pyramid = run(&["--method", "pyramid"]);
    let faces = run(&["--method", "pattern-faces"]);
    assert_eq!(pyramid["method"], "pyramid");
    assert_eq!(pyramid["info"]["pyramid_faces"], 8);
    assert!(pyramid["info"]["pyramid_rays"].as_u64().unwrap() > 0);
    assert_eq!(bnb["info"]["pyramid_faces"], Value::Null);
    assert!(bnb["info"]["nodes_visited"].as_u64().unwrap() > 0);
    let set = pattern_set(&bnb);
    assert_eq!(bnb["outcome"], "wedged");
    assert_eq!(set.len(), 6, "{set:?}");
    assert_eq!(pattern_set(&default), set);
    assert_eq!(pattern_set(&pyramid), set);
    assert_eq!(pattern_set(&faces), set);
    // Another number of faces gives the same answer.
    let pyramid16 = run(&["--method", "pyramid", "--pyramid-faces", "16"]);
    assert_eq!(pyramid16["info"]["pyramid_faces"], 16);
    assert_eq!(pattern_set(&pyramid16), set);

    // Below its critical mu it does not wedge.
    let below = run(&["--mu", "0.9"]);
    assert_eq!(below["outcome"], "not-wedged");
    assert_eq!(below["patterns"], serde_json::json!([]));
}

#[test]
fn the_summary_of_a_pattern_run_explains_itself() {
    let (_, _dir, path) = random_3d(1.5, 1);
    let out = wedged(&["enumerate", &path]);
    assert_success(&out);
    let text = stdout(&out);
    for needle in [
        "dim 3, 4 nodes, mu = 1.5, method bnb",
        "6 maximal sign patterns",
        "status at the witness of nodes 1-4",
        "o separated, s stick, ~ slip, g grazing",
        "branch and bound: ",
        "pruned (infeasible)",
        "pruned fraction ",
        "SOCPs solved (",
        "near-degenerate",
    ] {
        assert!(text.contains(needle), "{needle:?} not in\n{text}");
    }
    assert!(!text.contains("WARNING"), "{text}");
    // One row per pattern: index, max u_n, margin, one character per node.
    let rows = text
        .lines()
        .filter(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            w.len() == 4 && w[0].parse::<usize>().is_ok() && w[3].len() == 4
        })
        .count();
    assert_eq!(rows, 6, "{text}");

    let out = wedged(&["enumerate", &path, "--method", "pyramid"]);
    assert_success(&out);
    let text = stdout(&out);
    assert!(text.contains("method pyramid (8 faces)"), "{text}");
    assert!(
        text.contains("pyramid approximation (8 faces): ") && text.contains("spurious"),
        "{text}"
    );
}

#[test]
fn a_ray_method_on_a_3d_problem_is_a_usage_error() {
    let (_, _dir, path) = random_3d(1.5, 1);
    for method in ["pruned-dd", "full-dd", "faces"] {
        let out = wedged(&["enumerate", &path, "--method", method]);
        assert_bad_input(&out, &[&path, "dim = 3", method, "--method bnb", "pyramid"]);
    }
}

#[test]
fn pyramid_faces_out_of_range_or_without_the_pyramid() {
    let (_, _dir, path) = random_3d(1.5, 1);
    for k in ["2", "100", "-3"] {
        let out = wedged(&[
            "enumerate",
            &path,
            "--method",
            "pyramid",
            "--pyramid-faces",
            k,
        ]);
        assert_bad_input(&out, &["--pyramid-faces", "3 to 64", k]);
    }
    let out = wedged(&["enumerate", &path, "--pyramid-faces", "12"]);
    assert_bad_input(&out, &["--pyramid-faces", "pyramid only", "bnb"]);
}

#[test]
fn a_2d_problem_gives_the_same_patterns_by_rays_and_by_patterns() {
    let k = coupled_k();
    let rays = json_stdout(&wedged(&[
        "enumerate",
        &fixture("coupled_array.toml"),
        "--json",
        "-",
    ]));
    check_report(&rays, &k);
    assert_eq!(rays["method"], "search");
    let set = pattern_set(&rays);
    assert_eq!(set.len(), 4);
    for method in ["bnb", "pyramid", "pattern-faces"] {
        let report = json_stdout(&wedged(&[
            "enumerate",
            &fixture("coupled_array.toml"),
            "--method",
            method,
            "--json",
            "-",
        ]));
        check_report(&report, &k);
        assert_eq!(report["method"], method);
        assert_eq!(pattern_set(&report), set, "{method}");
    }
    // The summary of a 2D pattern run uses the 2D legend.
    let out = wedged(&[
        "enumerate",
        &fixture("coupled_array.toml"),
        "--method",
        "bnb",
    ]);
    assert_success(&out);
    assert!(
        stdout(&out).contains("o separated, s stick, + slip+, - slip-, g grazing"),
        "{}",
        stdout(&out)
    );
}

#[test]
fn a_3d_run_stopped_by_the_time_limit_is_marked_incomplete() {
    let (_, dir, path) = random_3d(1.5, 1);
    let json = path_in(&dir, "out.json");
    let out = wedged(&["enumerate", &path, "--time-limit", "0", "--json", &json]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.starts_with("incomplete: ") && err.contains("time limit") && err.contains(&path),
        "{err}"
    );
    assert!(
        !err.contains("nodes;"),
        "no node count for a pattern run: {err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(stdout(&out).contains("INCOMPLETE"), "{}", stdout(&out));
    let report: Value = serde_json::from_str(&fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["complete"], false);
    assert_eq!(report["outcome"], "incomplete");
    assert!(report["stopped"].as_str().unwrap().contains("time limit"));
    assert_eq!(report["patterns"], serde_json::json!([]));
    assert_eq!(report["undecided"], serde_json::json!([]));
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
    // A method without a store of rays refuses the bound rather than running unbounded
    // (the 2D search and pattern-search, 3D bnb had ignored it); pyramid honours it.
    let plug3d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plug3d.toml");
    let plug3d = plug3d.to_str().unwrap();
    let array = fixture("coupled_array.toml");
    for (problem, method, option) in [
        (array.as_str(), "search", "--max-rays"),
        (array.as_str(), "pattern-search", "--max-memory"),
        (plug3d, "bnb", "--max-rays"),
    ] {
        let out = wedged(&["enumerate", problem, "--method", method, option, "1000"]);
        assert_bad_input(
            &out,
            &[option, &format!("--method {method} has no such bound")],
        );
    }
    let out = wedged(&[
        "enumerate",
        plug3d,
        "--method",
        "pyramid",
        "--max-rays",
        "3",
    ]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
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

// ---- the critical friction coefficient ----------------------------------------------------------

/// Runs `critical` (or `sweep`) on a problem file with the given text, JSON to stdout; returns
/// the output (the directory is kept alive by the caller through the returned value).
fn critical_text(command: &str, toml: &str, extra: &[&str]) -> (Output, tempfile::TempDir) {
    let dir = dir_with(&[("p.toml", toml)]);
    let path = path_in(&dir, "p.toml");
    let mut args = vec![command, path.as_str()];
    args.extend_from_slice(extra);
    (wedged(&args), dir)
}

/// The fixed keys of the `critical` JSON.
fn check_critical_keys(report: &Value) {
    let keys: Vec<&str> = report
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    let mut expected = vec![
        "source",
        "dim",
        "nodes",
        "rigid_modes",
        "method",
        "status",
        "complete",
        "stopped",
        "mu_critical",
        "lower",
        "upper",
        "tol",
        "tol_achieved",
        "witness",
        "pattern",
        "thresholds",
        "undecided",
        "info",
        "certified",
        "certificate",
        "version",
    ];
    // `model` is there for a meshed body only.
    if keys.contains(&"model") {
        expected.push("model");
    }
    let mut keys = keys;
    keys.sort_unstable();
    expected.sort_unstable();
    assert_eq!(keys, expected);
    let info = report["info"].as_object().unwrap();
    for key in [
        "method",
        "nodes_visited",
        "pruned_infeasible",
        "leaves_solved",
        "bound_tightenings",
        "mirrored",
        "dive_nodes",
        "improvement_steps",
        "simplex_solves",
        "simplex_fallbacks",
        "simplex_relaxed",
        "dinkelbach_steps",
        "bisection_steps",
        "certificates",
        "loosened",
        "tol_achieved",
        "mu_enumerated",
        "patterns_enumerated",
        "socps",
        "retries",
        "uncertain",
        "groups",
        "seconds",
        "condensed_nodes",
        "condensed_mu",
        "condensed_seconds",
        "peak_rss_bytes",
    ] {
        assert!(info.contains_key(key), "missing info.{key}: {info:?}");
    }
    assert_eq!(info.len(), 27, "{info:?}");
}

/// One node with `K_nn = 2, K_nt = 1, K_tt = 1`: `mu* = K_tt / |K_nt| = 1`.
#[test]
fn critical_of_one_node_is_its_closed_form() {
    let toml = "dim = 2\nmu = 1.1\n[stiffness]\nrows = [[2.0, 1.0], [1.0, 1.0]]\n";
    let (out, _dir) = critical_text("critical", toml, &["--json", "-"]);
    let report = json_stdout(&out);
    check_critical_keys(&report);
    assert_eq!(report["status"], "wedged");
    assert_eq!(report["complete"], true);
    assert_eq!(report["method"], "bnb");
    assert_eq!(report["tol"], 1e-9);
    let mu = report["mu_critical"].as_f64().unwrap();
    let (lower, upper) = (
        report["lower"].as_f64().unwrap(),
        report["upper"].as_f64().unwrap(),
    );
    assert!((mu - 1.0).abs() < 1e-6, "{mu}");
    assert_eq!(mu, upper);
    assert!(
        lower <= 1.0 && 1.0 <= upper * (1.0 + 1e-12),
        "[{lower}, {upper}]"
    );
    let width = report["tol_achieved"].as_f64().unwrap();
    assert!((width - (upper - lower) / upper).abs() < 1e-12, "{width}");
    let witness = &report["witness"];
    let k = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 1.0]);
    let (residual, r_n) =
        residual_and_normal_sum(&k, 2, &floats(&witness["u"]), &floats(&witness["r"]));
    assert!(
        residual < 1e-9 && (r_n - 1.0).abs() < 1e-9,
        "{residual} {r_n}"
    );
    assert_eq!(witness["pattern"], serde_json::json!(["contact"]));
    assert_eq!(report["pattern"], serde_json::json!(["contact"]));
    assert_eq!(witness["status"], serde_json::json!(["slip+"]));
    assert_eq!(report["thresholds"], serde_json::json!([]));

    // The summary gives the answer, the node and the diagnostics.
    let (out, _dir) = critical_text("critical", toml, &[]);
    assert_success(&out);
    let text = stdout(&out);
    assert!(text.contains("\nmu* = 1 (certified bracket ["), "{text}");
    assert!(text.contains("slip+"), "{text}");
    assert!(text.contains("SOCPs solved"), "{text}");
}

/// No coupling between the normal and the tangent: friction never holds a deformation.
#[test]
fn a_decoupled_body_never_wedges_and_that_is_a_result() {
    let toml = "dim = 2\n[stiffness]\nrows = [[2.0, 0.0, 0.5, 0.0], [0.0, 1.0, 0.0, 0.3], \
                [0.5, 0.0, 2.0, 0.0], [0.0, 0.3, 0.0, 1.0]]\n";
    let (out, dir) = critical_text("critical", toml, &["--json", "-"]);
    let report = json_stdout(&out);
    check_critical_keys(&report);
    assert_eq!(report["status"], "never");
    assert_eq!(report["complete"], true);
    for key in [
        "mu_critical",
        "lower",
        "upper",
        "tol_achieved",
        "witness",
        "pattern",
    ] {
        assert_eq!(report[key], Value::Null, "{key}");
    }
    let out = wedged(&["critical", &path_in(&dir, "p.toml")]);
    assert_success(&out);
    assert!(
        stdout(&out).contains("No friction coefficient wedges this body (certified"),
        "{}",
        stdout(&out)
    );
    // sweep: the plot says so, and the run is still a success.
    let svg = path_in(&dir, "never.svg");
    let out = wedged(&["sweep", &path_in(&dir, "p.toml"), "--svg", &svg]);
    assert_success(&out);
    let text = fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"), "{text}");
    assert!(
        text.contains("No friction coefficient wedges this body"),
        "{text}"
    );
}

#[test]
fn critical_tolerance_out_of_range() {
    for tol in ["0", "0.5", "nan"] {
        let out = wedged(&["critical", &fixture("two_nodes.toml"), "--tol", tol]);
        assert_bad_input(&out, &["tolerance", "mu*"]);
    }
}

#[test]
fn critical_by_faces_agrees_with_bnb() {
    let mut brackets = Vec::new();
    for method in ["bnb", "faces", "enumerate"] {
        let report = json_stdout(&wedged(&[
            "critical",
            &fixture("coupled_array.toml"),
            "--method",
            method,
            "--json",
            "-",
        ]));
        assert_eq!(report["status"], "wedged", "{method}");
        assert_eq!(report["info"]["method"], method);
        let (lower, upper) = (
            report["lower"].as_f64().unwrap(),
            report["upper"].as_f64().unwrap(),
        );
        let (residual, r_n) = residual_and_normal_sum(
            &coupled_k(),
            2,
            &floats(&report["witness"]["u"]),
            &floats(&report["witness"]["r"]),
        );
        assert!(residual < 1e-9 && (r_n - 1.0).abs() < 1e-9, "{method}");
        brackets.push((method, lower, upper));
    }
    // The certified brackets overlap and their ends agree to the solver's accuracy.
    for &(m1, l1, u1) in &brackets {
        for &(m2, l2, u2) in &brackets {
            assert!(
                l1 <= u2 * (1.0 + 1e-9),
                "{m1} [{l1}, {u1}] vs {m2} [{l2}, {u2}]"
            );
            assert!((u1 - u2).abs() < 1e-6 * u1, "{m1} {u1} vs {m2} {u2}");
        }
    }
}

/// The 3D plug of the examples: no wedged configuration up to mu = 1.53, some at 1.535.
#[test]
fn critical_of_the_3d_plug() {
    let report = json_stdout(&wedged(&[
        "critical",
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/plug3d.toml")
            .display()
            .to_string(),
        "--json",
        "-",
    ]));
    check_critical_keys(&report);
    assert_eq!(report["dim"], 3);
    assert_eq!(report["status"], "wedged");
    let mu = report["mu_critical"].as_f64().unwrap();
    assert!(1.53 < mu && mu < 1.535, "{mu}");
    assert!(report["lower"].as_f64().unwrap() > 1.53);
    assert_eq!(report["model"]["contact"].as_array().unwrap().len(), 6);
    let status = report["witness"]["status"].as_array().unwrap();
    assert_eq!(status.len(), 6);
    assert!(status.iter().any(|s| s == "slip"), "{status:?}");
    assert!(status
        .iter()
        .all(|s| ["separated", "stick", "slip", "grazing"].contains(&s.as_str().unwrap())));
}

/// A small 3D stiffness: the witness solves K u = r.
#[test]
fn critical_of_a_3d_stiffness() {
    let (k, _dir, path) = random_3d(1.0, 3);
    let report = json_stdout(&wedged(&["critical", &path, "--json", "-"]));
    check_critical_keys(&report);
    match report["status"].as_str().unwrap() {
        "wedged" => {
            let w = &report["witness"];
            let (residual, r_n) =
                residual_and_normal_sum(&k, 3, &floats(&w["u"]), &floats(&w["r"]));
            assert!(residual < 1e-8 && (r_n - 1.0).abs() < 1e-8);
        }
        "never" => assert_eq!(report["witness"], Value::Null),
        other => panic!("{other}"),
    }
}

#[test]
fn critical_stopped_by_the_time_limit_is_marked_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let json = path_in(&dir, "out.json");
    let out = wedged(&[
        "critical",
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
    let report: Value = serde_json::from_str(&fs::read_to_string(&json).unwrap()).unwrap();
    check_critical_keys(&report);
    assert_eq!(report["complete"], false);
    assert_eq!(report["status"], "incomplete");
    assert!(report["stopped"].as_str().unwrap().contains("time limit"));
    assert_eq!(report["mu_critical"], Value::Null);
    assert_eq!(report["lower"], Value::Null);
    // sweep writes no plot then.
    let svg = path_in(&dir, "plot.svg");
    let out = wedged(&[
        "sweep",
        &fixture("coupled_array.toml"),
        "--svg",
        &svg,
        "--time-limit",
        "0",
    ]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(!Path::new(&svg).exists());
    assert_eq!(
        fs::read_dir(dir.path()).unwrap().count(),
        1,
        "no temporary file left"
    );
}

/// `-` is stdout for `--json`, `--jsonl` and `condense --mtx` (the matrix alone, as the file
/// holds it); every other output refuses it, where each had written a file or a directory
/// named `-` in the working directory.
#[test]
fn a_dash_is_stdout_for_the_file_outputs_only() {
    let dir = tempfile::tempdir().unwrap();
    let problem = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/plug2d.toml")
        .display()
        .to_string();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_wedged"))
            .args(args)
            .current_dir(dir.path())
            .output()
            .expect("the binary runs")
    };
    let file = path_in(&dir, "k.mtx");
    assert_eq!(
        run(&["condense", &problem, "--mtx", &file]).status.code(),
        Some(0)
    );
    let out = run(&["condense", &problem, "--mtx", "-"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(stdout(&out), fs::read_to_string(&file).unwrap());
    for args in [
        &["enumerate", &problem, "--svg", "-"][..],
        &["enumerate", &problem, "--vtk", "-"],
        &["sweep", &problem, "--svg", "-"],
        &["sweep", &problem, "--svg", "s.svg", "--vtk", "-"],
        &["study", &problem, "--vary", "mu=1", "--out", "-"],
        &["demo", "--out", "-"],
    ] {
        let out = run(args);
        assert_bad_input(&out, &["-: "]);
        assert!(
            stderr(&out).contains("stdout"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
    assert!(!dir.path().join("-").exists());
}

/// A run stopped by its time limit names the limit given, also where a part of the run was
/// handed what was left of it: the fine mesh after its coarser ones (`critical` on a generated
/// body of 80 contact nodes), the enumeration of `--method enumerate` (both said "0 s", or
/// whatever was left).
#[test]
fn a_stopped_critical_names_the_time_limit_given() {
    let chained = example_with("plug2d.toml", &[("nx", "40".into()), ("ny", "40".into())]);
    let enumerated = example_with("plug2d.toml", &[("ny", "20".into())]);
    for (toml, extra) in [(chained, None), (enumerated, Some("enumerate"))] {
        let dir = dir_with(&[("p.toml", &toml)]);
        let path = path_in(&dir, "p.toml");
        let mut args = vec!["critical", path.as_str(), "--time-limit", "0.05"];
        if let Some(method) = extra {
            args.extend(["--method", method]);
        }
        let out = wedged(&args);
        assert_eq!(out.status.code(), Some(3), "{extra:?}: {}", stderr(&out));
        let err = stderr(&out);
        assert!(
            err.contains("the time limit of 0.05 s ran out"),
            "{extra:?}: {err}"
        );
    }
}

#[test]
fn sweep_plots_each_patterns_threshold() {
    let dir = tempfile::tempdir().unwrap();
    let svg = path_in(&dir, "plot.svg");
    let json = path_in(&dir, "sweep.json");
    let out = wedged(&[
        "sweep",
        &fixture("coupled_array.toml"),
        "--svg",
        &svg,
        "--json",
        &json,
    ]);
    assert_success(&out);
    let report: Value = serde_json::from_str(&fs::read_to_string(&json).unwrap()).unwrap();
    check_critical_keys(&report);
    assert_eq!(report["method"], "enumerate");
    assert_eq!(report["info"]["mu_enumerated"], 1.5);
    let thresholds = report["thresholds"].as_array().unwrap();
    // The fixture has 4 convex pieces at mu = 1.5.
    assert_eq!(thresholds.len(), 4);
    let values: Vec<f64> = thresholds
        .iter()
        .map(|t| t["threshold"].as_f64().unwrap())
        .collect();
    assert!(values.windows(2).all(|w| w[0] <= w[1]), "{values:?}");
    assert!(values.iter().all(|&t| t <= 1.5));
    for t in thresholds {
        assert!(t["lower"].as_f64().unwrap() <= t["threshold"].as_f64().unwrap());
    }
    let mu = report["mu_critical"].as_f64().unwrap();
    assert_eq!(mu, values[0]);
    let text = stdout(&out);
    assert!(text.contains("4 maximal patterns at mu = 1.5"), "{text}");
    assert!(text.contains("\nmu* = "), "{text}");
    assert!(text.contains(&svg), "{text}");
    let plot = fs::read_to_string(&svg).unwrap();
    assert!(
        plot.starts_with("<svg") || plot.starts_with("<?xml"),
        "{plot}"
    );
    assert!(plot.trim_end().ends_with("</svg>"), "{plot}");
    assert!(plot.contains("mu* = 1.19"), "{plot}");
    assert!(plot.contains("stroke-dasharray"), "{plot}");
    assert_eq!(plot.matches("<circle").count(), 4, "{plot}");
}

#[test]
fn sweep_needs_its_svg_path() {
    let out = wedged(&["sweep", &fixture("two_nodes.toml")]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--svg"), "{}", stderr(&out));
    let dir = tempfile::tempdir().unwrap();
    let svg = path_in(&dir, "no/such/dir/plot.svg");
    let out = wedged(&["sweep", &fixture("two_nodes.toml"), "--svg", &svg]);
    assert_bad_input(&out, &[&svg, "cannot write"]);
}

#[test]
fn certify_flag_certifies_ray_methods() {
    for method in ["pruned-dd", "full-dd", "faces"] {
        let out = wedged(&[
            "enumerate",
            &fixture("coupled_array.toml"),
            "--method",
            method,
            "--certify",
            "--json",
            "-",
        ]);
        let report = json_stdout(&out);
        assert_eq!(report["certified"], Value::Bool(true), "{method}");
        // Three nodes: completeness is checked against the exact enumeration too.
        assert_eq!(report["certified_complete"], Value::Bool(true), "{method}");
        // The summary says so.
        let out = wedged(&[
            "enumerate",
            &fixture("coupled_array.toml"),
            "--method",
            method,
            "--certify",
        ]);
        assert_success(&out);
        assert!(
            stdout(&out).contains(
                "certified in exact rational arithmetic: 7 rays, 4 cones; complete: equal to the \
                 exact enumeration"
            ),
            "{}",
            stdout(&out)
        );
    }
    // Without the flag, the key is null and the summary has no such line.
    let out = wedged(&["enumerate", &fixture("coupled_array.toml"), "--json", "-"]);
    assert_eq!(json_stdout(&out)["certified"], Value::Null);
    assert_eq!(json_stdout(&out)["certified_complete"], Value::Null);
    let out = wedged(&["enumerate", &fixture("coupled_array.toml")]);
    assert_success(&out);
    assert!(!stdout(&out).contains("certified in exact"));
}

/// A pattern method certifies its sign patterns (tests/certify.rs has more).
#[test]
fn certify_flag_certifies_patterns() {
    let out = wedged(&[
        "enumerate",
        &fixture("coupled_array.toml"),
        "--method",
        "bnb",
        "--certify",
        "--json",
        "-",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let report: Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(report["certified"], true);
    assert_eq!(report["certified_complete"], true);
}

/// The rays (statuses and values) and cones of a `--json -` report.
fn rays_and_cones(report: &Value) -> (Vec<Value>, Vec<Vec<f64>>, Value) {
    let rays = report["rays"].as_array().unwrap();
    let statuses = rays.iter().map(|r| r["status"].clone()).collect();
    let values = rays.iter().map(|r| floats(&r["r"])).collect();
    (statuses, values, report["cones"].clone())
}

#[test]
fn exact_flag_gives_the_rays_of_pruned_dd() {
    // The fixture, and the example plug of examples/plug2d.toml on a coarser mesh (m = 6).
    let plug = fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plug2d.toml"),
    )
    .unwrap()
    .replace("nx = 8 ", "nx = 4 ")
    .replace("ny = 6 ", "ny = 3 ");
    assert!(
        plug.contains("nx = 4 ") && plug.contains("ny = 3 "),
        "{plug}"
    );
    let dir = dir_with(&[("plug.toml", &plug)]);
    let plug_path = path_in(&dir, "plug.toml");
    for (path, mu) in [
        (fixture("coupled_array.toml"), "1.5"),
        (plug_path.clone(), "1.8"),
        (plug_path, "3"),
    ] {
        let run = |extra: &[&str]| {
            let mut args = vec!["enumerate", path.as_str(), "--mu", mu, "--json", "-"];
            args.extend_from_slice(extra);
            let out = wedged(&args);
            assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
            json_stdout(&out)
        };
        let exact = run(&["--exact", "--certify"]);
        assert_eq!(exact["method"], "exact");
        assert_eq!(exact["certified"], Value::Bool(true));
        let pruned = run(&["--method", "pruned-dd"]);
        let (se, ve, ce) = rays_and_cones(&exact);
        let (sp, vp, cp) = rays_and_cones(&pruned);
        assert_eq!(se, sp, "{path}, mu {mu}");
        assert_eq!(ce, cp, "{path}, mu {mu}");
        for (a, b) in ve.iter().zip(&vp) {
            let d = a
                .iter()
                .zip(b)
                .fold(0.0f64, |d, (x, y)| d.max((x - y).abs()));
            assert!(d < 1e-9, "{path}, mu {mu}: rays differ by {d}");
        }
        // --method exact is the same run.
        let method = run(&["--method", "exact"]);
        assert_eq!(rays_and_cones(&method), (se, ve, ce));
    }
    // The summary names the method.
    let out = wedged(&["enumerate", &fixture("coupled_array.toml"), "--exact"]);
    assert_success(&out);
    assert!(stdout(&out).contains("method exact"), "{}", stdout(&out));
}

#[test]
fn exact_flag_needs_a_2d_ray_enumeration() {
    let (_, _dir, path) = random_3d(1.5, 1);
    let out = wedged(&["enumerate", &path, "--exact"]);
    assert_bad_input(&out, &[&path, "dim = 3", "--exact", "2D"]);
    let out = wedged(&["enumerate", &path, "--method", "exact"]);
    assert_bad_input(&out, &[&path, "dim = 3", "exact"]);
    for method in ["pruned-dd", "bnb"] {
        let out = wedged(&[
            "enumerate",
            &fixture("coupled_array.toml"),
            "--exact",
            "--method",
            method,
        ]);
        assert_bad_input(&out, &["--exact", method]);
    }
}

/// A `critical` run interrupted after a finished pass (the test hook
/// `WEDGED_INJECT_FAULT=halt-after-pass`, where Ctrl-C or a time limit would land at a time that
/// cannot be reproduced) reports the bracket proved so far: two independent nodes with
/// `mu* = 1`, searched from a first bar of 0.25, prove `mu* > 0.25` in their first pass; the
/// upper end is the all-contact set's checked configuration at 1. Exit 3, the JSON marked
/// incomplete with both ends, and both ends said in the summary and on stderr.
#[test]
fn an_interrupted_critical_run_reports_the_bracket_proved_so_far() {
    let toml = std::fs::read_to_string(fixture("two_nodes.toml"))
        .unwrap()
        .replace("mu = 1.1", "mu = 0.25");
    let dir = dir_with(&[("low.toml", &toml)]);
    let file = path_in(&dir, "low.toml");
    let run = |json: bool| {
        let mut args = vec!["critical", file.as_str()];
        if json {
            args.extend(["--json", "-"]);
        }
        Command::new(env!("CARGO_BIN_EXE_wedged"))
            .args(&args)
            .env("WEDGED_INJECT_FAULT", "halt-after-pass")
            .output()
            .expect("the binary runs")
    };
    let out = run(true);
    assert_eq!(out.status.code(), Some(3), "stderr: {}", stderr(&out));
    let report: Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    assert_eq!(report["status"], "incomplete");
    assert_eq!(report["complete"], false);
    assert_eq!(report["mu_critical"], Value::Null);
    assert_eq!(report["lower"].as_f64(), Some(0.25), "{report}");
    let upper = report["upper"].as_f64().expect("an upper end");
    assert!((upper - 1.0).abs() < 1e-9, "{upper}");
    let err = stderr(&out);
    assert!(err.contains("0.25 < mu* <= 1 "), "{err}");
    let out = run(false);
    assert_eq!(out.status.code(), Some(3));
    let text = stdout(&out);
    assert!(
        text.contains("INCOMPLETE: the run was interrupted; 0.25 < mu* <= 1 ("),
        "{text}"
    );
    // From a first bar above mu*, the first pass finds its configuration: complete, mu* = 1.
    let dir = dir_with(&[("high.toml", &toml.replace("mu = 0.25", "mu = 2.0"))]);
    let out = Command::new(env!("CARGO_BIN_EXE_wedged"))
        .args(["critical", &path_in(&dir, "high.toml"), "--json", "-"])
        .env("WEDGED_INJECT_FAULT", "halt-after-pass")
        .output()
        .expect("the binary runs");
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(json_stdout(&out)["status"], "wedged");
}

/// An internal failure (here the test hook `WEDGED_INJECT_FAULT=corrupt-witness`, which moves the
/// `mu*` witness off equilibrium before its final check) exits 1, on one line that says it is a
/// bug and what failed, and prints no answer; bad input still exits 2.
#[test]
fn an_internal_failure_exits_1_and_says_it_is_a_bug() {
    let run = |fault: &str| {
        Command::new(env!("CARGO_BIN_EXE_wedged"))
            .args(["critical", &fixture("two_nodes.toml"), "--json", "-"])
            .env("WEDGED_INJECT_FAULT", fault)
            .output()
            .expect("the binary runs")
    };
    let out = run("corrupt-witness");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "stderr: {err}");
    assert!(err.starts_with("error: "), "{err}");
    assert!(err.contains("internal failure"), "{err}");
    assert!(err.contains("bug"), "{err}");
    assert!(
        err.contains("witness") && err.contains("failed its check"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    assert!(
        stdout(&out).is_empty(),
        "an answer was printed: {}",
        stdout(&out)
    );
    // The same run without the fault succeeds, so the failure above is the fault's.
    assert_success(&wedged(&["critical", &fixture("two_nodes.toml")]));
    // An unknown fault name is bad input, not silently ignored.
    assert_bad_input(
        &run("no-such-fault"),
        &["WEDGED_INJECT_FAULT", "no-such-fault"],
    );
}

/// `critical --start`: a coarser mesh's answer of the same body, mapped by position, starts the
/// finer mesh's search (no dive) and leaves its bracket as it was; an earlier result of the same
/// problem too; a missing file, a file that is not JSON, a result without a witness and one of
/// another dimension are bad input.
#[test]
fn critical_starts_from_a_coarser_meshs_answer() {
    let with_size = |nx: usize, ny: usize| -> String {
        example_with(
            "plug2d.toml",
            &[("nx", nx.to_string()), ("ny", ny.to_string())],
        )
    };
    let dir = dir_with(&[
        ("coarse.toml", &with_size(5, 4)),
        ("fine.toml", &with_size(10, 8)),
        ("nothing.json", "{\"status\": \"never\"}"),
        ("text.json", "not json"),
    ]);
    let run = |file: &str, extra: &[&str]| -> Value {
        let mut args = vec!["critical", file, "--json", "-"];
        args.extend_from_slice(extra);
        let out = wedged(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        json_stdout(&out)
    };
    let (coarse, fine) = (path_in(&dir, "coarse.toml"), path_in(&dir, "fine.toml"));
    let coarse_json = path_in(&dir, "coarse.json");
    fs::write(&coarse_json, run(&coarse, &[]).to_string()).unwrap();
    let plain = run(&fine, &[]);
    let fine_json = path_in(&dir, "fine.json");
    fs::write(&fine_json, plain.to_string()).unwrap();
    assert_eq!(plain["status"], "wedged");
    assert!(plain["info"]["dive_nodes"].as_u64().unwrap() > 0);
    for start in [&coarse_json, &fine_json] {
        let started = run(&fine, &["--start", start]);
        assert_eq!(started["status"], "wedged", "{start}");
        assert_eq!(
            started["info"]["dive_nodes"], 0,
            "{start}: the dive was not skipped"
        );
        for end in ["lower", "upper"] {
            let (a, b) = (plain[end].as_f64().unwrap(), started[end].as_f64().unwrap());
            assert!((a - b).abs() <= 1e-8 * a, "{start}: {end} {a} against {b}");
        }
    }
    assert_bad_input(
        &wedged(&["critical", &fine, "--start", &path_in(&dir, "missing.json")]),
        &["cannot read", "missing.json"],
    );
    assert_bad_input(
        &wedged(&["critical", &fine, "--start", &path_in(&dir, "text.json")]),
        &["text.json", "is not JSON"],
    );
    assert_bad_input(
        &wedged(&["critical", &fine, "--start", &path_in(&dir, "nothing.json")]),
        &["nothing.json", "no witness pattern"],
    );
    // A 2D body's answer for a 3D body (it had said that the start has no node in contact).
    let plug3d = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/plug3d.toml");
    assert_bad_input(
        &wedged(&[
            "critical",
            plug3d.to_str().unwrap(),
            "--start",
            &coarse_json,
        ]),
        &[
            "coarse.json",
            "the result of a 2D body",
            "this problem's is 3D",
        ],
    );
}

/// `critical` on a condensed stiffness of 80 nodes (no mesh to coarsen: the plug's `K` written
/// by `condense`) starts from the problem condensed onto about half its nodes and says so; the
/// bracket is that of `--no-chain`, which does not.
#[test]
fn critical_starts_a_large_stiffness_from_its_condensed_problem() {
    let plug = example_with("plug2d.toml", &[("nx", "3".into()), ("ny", "40".into())]);
    let dir = dir_with(&[("plug.toml", &plug)]);
    let mtx = path_in(&dir, "K.mtx");
    let out = wedged(&["condense", &path_in(&dir, "plug.toml"), "--mtx", &mtx]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let toml = "dim = 2\nmu = 2.0\n[stiffness]\nmatrix_market = \"K.mtx\"\n";
    fs::write(dir.path().join("k.toml"), toml).unwrap();
    let problem = path_in(&dir, "k.toml");
    let json = |extra: &[&str]| -> Value {
        let mut args = vec!["critical", problem.as_str(), "--json", "-"];
        args.extend_from_slice(extra);
        let out = wedged(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        json_stdout(&out)
    };
    let (started, scratch) = (json(&[]), json(&["--no-chain"]));
    assert_eq!(started["nodes"], 80);
    let nodes = started["info"]["condensed_nodes"].as_u64().unwrap();
    assert!((27..=42).contains(&nodes), "{}", started["info"]);
    assert!(started["info"]["condensed_mu"].as_f64().unwrap() > 0.0);
    assert_eq!(started["info"]["dive_nodes"], 0);
    assert_eq!(scratch["info"]["condensed_nodes"], 0);
    assert_eq!(scratch["info"]["condensed_mu"], Value::Null);
    for end in ["lower", "upper"] {
        let (a, b) = (
            started[end].as_f64().unwrap(),
            scratch[end].as_f64().unwrap(),
        );
        assert!((a - b).abs() <= 2e-9 * a, "{end} {a} against {b}");
    }
    let out = wedged(&["critical", &problem]);
    // The summary's lines are wrapped: compare its words.
    let text = stdout(&out)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    assert!(
        text.contains(&format!(
            "the problem condensed onto {nodes} of its 80 nodes"
        )),
        "{text}"
    );
    let out = wedged(&["critical", &problem, "--no-chain"]);
    assert!(!stdout(&out).contains("condensed onto"));
}

/// `critical` on a generated 2D body of 80 contact nodes or more starts from its problem
/// condensed onto about half its nodes, says so, and skips the dive; the bracket is that of
/// `--no-chain`, which dives and says nothing of it; a body of fewer nodes is computed from
/// scratch; a 3D body of 40 nodes starts condensed too.
#[test]
fn critical_starts_a_large_generated_body_from_its_condensed_problem() {
    let with_ny = |ny: usize| -> String {
        example_with("plug2d.toml", &[("nx", "3".into()), ("ny", ny.to_string())])
    };
    // Two contact nodes a division up the two walls: 80 and 78.
    let dir = dir_with(&[("fine.toml", &with_ny(40)), ("small.toml", &with_ny(39))]);
    let (fine, small) = (path_in(&dir, "fine.toml"), path_in(&dir, "small.toml"));
    // The JSON and the summary's words (its lines are wrapped).
    let run = |file: &str, extra: &[&str]| -> (Value, String) {
        let mut args = vec!["critical", file, "--json", "-"];
        args.extend_from_slice(extra);
        let out = wedged(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let json = json_stdout(&out);
        let mut args = vec!["critical", file];
        args.extend_from_slice(extra);
        let out = wedged(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let words = stdout(&out)
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        (json, words)
    };
    // The two runs' brackets agree to 1e-8 (`what` names the body in a failure).
    let same_bracket = |scratch: &Value, chained: &Value, what: &str| {
        for end in ["lower", "upper"] {
            let (a, b) = (
                scratch[end].as_f64().unwrap(),
                chained[end].as_f64().unwrap(),
            );
            assert!((a - b).abs() <= 1e-8 * a, "{what} {end} {a} against {b}");
        }
    };
    let said = "the problem condensed onto";
    let (chained, text) = run(&fine, &[]);
    assert_eq!(chained["nodes"], 80, "{chained}");
    let nodes = chained["info"]["condensed_nodes"].as_u64().unwrap();
    assert!((27..=42).contains(&nodes), "{}", chained["info"]);
    assert!(
        text.contains(&format!("{said} {nodes} of its 80 nodes")),
        "{text}"
    );
    assert_eq!(chained["info"]["dive_nodes"], 0, "the dive was not skipped");
    let (scratch, text) = run(&fine, &["--no-chain"]);
    assert!(!text.contains(said), "{text}");
    assert_eq!(scratch["info"]["condensed_nodes"], 0);
    assert!(scratch["info"]["dive_nodes"].as_u64().unwrap() > 0);
    same_bracket(&scratch, &chained, "2D");
    let (fewer, text) = run(&small, &[]);
    assert_eq!(fewer["nodes"], 78, "{fewer}");
    assert!(!text.contains(said), "{text}");
    // In 3D from 40 nodes: the V-groove plug with ny = nz = 4.
    let groove = example_with(
        "plug3d.toml",
        &[("mu", "2.0".into()), ("ny", "4".into()), ("nz", "4".into())],
    );
    let dir = dir_with(&[("groove.toml", &groove)]);
    let groove = path_in(&dir, "groove.toml");
    let (chained, text) = run(&groove, &[]);
    assert_eq!(chained["nodes"], 40, "{chained}");
    assert!(text.contains(said), "{text}");
    assert!(chained["info"]["condensed_nodes"].as_u64().unwrap() > 0);
    let scratch = run(&groove, &["--no-chain"]).0;
    same_bracket(&scratch, &chained, "3D");
}

/// Two one-node bodies in one matrix (`K` block diagonal): `critical` searches each on its
/// own and says so; `mu*` is the lesser closed form `K_tt / |K_nt|` (1 and 2), in the summary
/// and in the JSON (`info.groups`), and the other body grazes in the witness.
#[test]
fn critical_searches_uncoupled_bodies_apart() {
    let dir = dir_with(&[(
        "pair.toml",
        "dim = 2\nmu = 0.5\n[stiffness]\nrows = [[3.0, -1.0, 0.0, 0.0], [-1.0, 2.0, 0.0, 0.0], \
         [0.0, 0.0, 2.0, 1.0], [0.0, 0.0, 1.0, 1.0]]\n",
    )]);
    let file = path_in(&dir, "pair.toml");
    let out = wedged(&["critical", &file]);
    assert_success(&out);
    let text = stdout(&out);
    assert!(
        text.contains("mu* = 1 ") || text.contains("mu* = 1.0"),
        "{text}"
    );
    assert!(
        text.contains("fall into 2 groups that K does not couple"),
        "{text}"
    );
    let report = json_stdout(&wedged(&["critical", &file, "--json", "-", "--certify"]));
    assert_eq!(report["info"]["groups"], 2);
    assert_eq!(report["certified"], true);
    let mu = report["mu_critical"].as_f64().unwrap();
    assert!((mu - 1.0).abs() < 1e-8, "{mu}");
    assert_eq!(report["witness"]["pattern"][0], "grazing");
    assert_eq!(report["witness"]["pattern"][1], "contact");
}
