//! `--certify`: answers re-checked in exact rational arithmetic. `wedged critical` (the
//! bracket of `mu*`) and `wedged enumerate` with a sign-pattern method (the patterns proven to
//! be all the maximal realised ones).

mod common;

use common::{assert_bad_input, example, pattern_list, wedged};
use serde_json::Value;

/// A run that exits 0 with `"certified": true` in the JSON on stdout.
fn certified_json(args: &[&str]) -> Value {
    let out = wedged(args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    assert_eq!(report["certified"], true, "{args:?}: {report}");
    report
}

/// `wedged enumerate FILE --method METHOD --certify --json -`, certified.
fn certified_enumerate(file: &str, method: &str) -> Value {
    certified_json(&[
        "enumerate",
        file,
        "--method",
        method,
        "--certify",
        "--json",
        "-",
    ])
}

/// A certified `critical` run, its exact upper end checked against the reported one.
fn certified_report(args: &[&str]) -> Value {
    let report = certified_json(args);
    let cert = &report["certificate"];
    assert_eq!(cert["refutations_failed"], 0);
    assert!(cert["refutations_checked"].as_u64().unwrap() > 0);
    assert!(cert["failures"].as_array().unwrap().is_empty());
    let (upper, exact) = (
        report["upper"].as_f64().unwrap(),
        cert["upper"].as_f64().unwrap(),
    );
    assert!((exact - upper).abs() <= 1e-12 * upper, "{exact} vs {upper}");
    assert!(report["lower"].as_f64().unwrap() <= exact);
    report
}

#[test]
fn the_2d_and_3d_plugs_are_certified() {
    for (file, dim) in [("plug2d.toml", 2), ("plug3d.toml", 3)] {
        let report = certified_report(&["critical", &example(file), "--certify", "--json", "-"]);
        assert_eq!(report["dim"], dim);
        assert_eq!(report["status"], "wedged");
    }
}

/// One node with `K_nn = 2, K_nt = 1, K_tt = 1`: `mu* = K_tt / |K_nt| = 1`, by both methods.
/// (Faces on the 2D plug leaves contact sets undecided, so the small case is used for it.)
#[test]
fn faces_is_certified_and_the_summary_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let one = dir.path().join("one.toml");
    std::fs::write(
        &one,
        "dim = 2\nmu = 1.1\n[stiffness]\nrows = [[2.0, 1.0], [1.0, 1.0]]\n",
    )
    .unwrap();
    let one = one.display().to_string();
    for method in ["faces", "bnb"] {
        let report = certified_report(&[
            "critical",
            &one,
            "--method",
            method,
            "--certify",
            "--json",
            "-",
        ]);
        let exact = report["certificate"]["upper"].as_f64().unwrap();
        assert!((exact - 1.0).abs() <= 1e-12, "{method}: {exact}");
        assert!(report["lower"].as_f64().unwrap() <= 1.0);
    }
    let file = example("plug2d.toml");
    let out = wedged(&["critical", &file, "--certify"]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("certified in exact rational arithmetic"),
        "{text}"
    );
}

#[test]
fn without_certify_the_fields_are_null() {
    let out = wedged(&["critical", &example("plug2d.toml"), "--json", "-"]);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(report["certified"].is_null());
    assert!(report["certificate"].is_null());
}

#[test]
fn certify_with_enumerate_is_refused() {
    let out = wedged(&[
        "critical",
        &example("plug2d.toml"),
        "--method",
        "enumerate",
        "--certify",
    ]);
    assert_bad_input(&out, &["--certify needs --method bnb or faces"]);
}

#[test]
fn certify_with_an_uncertifiable_pattern_method_is_refused() {
    // pyramid cannot prove its answers complete: refused before the run (exit 2), not
    // reported as a failed certification (exit 1) after it.
    let out = wedged(&[
        "enumerate",
        &example("plug2d.toml"),
        "--method",
        "pyramid",
        "--certify",
    ]);
    assert_bad_input(
        &out,
        &[
            "--certify cannot prove the answer of --method pyramid",
            "bnb, pattern-search (2D) or pattern-faces",
        ],
    );
    assert!(out.stdout.is_empty(), "nothing is run");
}

#[test]
fn the_3d_plug_is_certified_by_both_exact_methods() {
    let file = example("plug3d.toml");
    for method in ["bnb", "pattern-faces"] {
        let report = certified_enumerate(&file, method);
        assert_eq!(report["certified_complete"], true, "{method}");
        assert!(!report["patterns"].as_array().unwrap().is_empty());
    }
    let out = wedged(&["enumerate", &file, "--certify"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("certified in exact rational arithmetic")
            && text.contains("all the maximal patterns"),
        "{text}"
    );
}

#[test]
fn a_2d_plug_by_bnb_and_pattern_search_is_certified() {
    let file = example("plug2d_gmsh.toml");
    let (bnb, search) = (
        certified_enumerate(&file, "bnb"),
        certified_enumerate(&file, "pattern-search"),
    );
    assert_eq!(search["certified_complete"], true);
    assert!(!search["patterns"].as_array().unwrap().is_empty());
    assert_eq!(pattern_list(&bnb), pattern_list(&search));
}

/// The pyramid's candidates come from floating-point double description: `--certify` is
/// refused in 3D too, said plainly, exit code 2.
#[test]
fn the_pyramid_method_is_not_certified() {
    let out = wedged(&[
        "enumerate",
        &example("plug3d.toml"),
        "--method",
        "pyramid",
        "--certify",
    ]);
    assert_bad_input(&out, &["floating-point double description on the pyramid"]);
}
