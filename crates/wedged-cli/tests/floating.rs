//! Floating bodies end to end (issue 22): a meshed body with no clamp and a matrix problem with
//! declared rigid modes answer `critical` and `enumerate` (the same answer as the library on
//! the same problem); the methods that do not apply, and bad or missing rigid modes, are
//! one-line errors with exit code 2.

mod common;

use std::fs;

use common::{assert_bad_input, assert_code, pattern_list, printed_number, text, wedged};

use serde_json::Value;
use wedged::examples::floating_notch;
use wedged::{critical, CriticalSettings};

/// A cork: the generated plug in its V-notch (half angle atan(1/2)) with no clamp.
fn cork(nx: usize, ny: usize) -> String {
    format!(
        "mu = 1.0\n[mesh.generate]\nkind = \"plug2d\"\nbottom_width = 1.0\ntop_width = 2.0\n\
         height = 1.0\nnx = {nx}\nny = {ny}\nelement = \"quad\"\n[material]\nyoung = 1e7\n\
         poisson = 0.3\nplane = \"strain\"\n[[contact]]\ngroup = \"contact\"\n"
    )
}

/// A matrix as TOML rows (shortest round-trip digits).
fn rows(m: &nalgebra::DMatrix<f64>) -> String {
    let lines: Vec<String> = (0..m.nrows())
        .map(|i| {
            let row: Vec<String> = (0..m.ncols()).map(|j| format!("{:?}", m[(i, j)])).collect();
            format!("[{}]", row.join(", "))
        })
        .collect();
    format!("[{}]", lines.join(",\n  "))
}

/// A matrix problem file for `p`: `K` and (`with_modes`) `R` as inline rows.
fn matrix_toml(p: &wedged::Problem, with_modes: bool) -> String {
    let mut s = format!(
        "dim = {}\nmu = {:?}\n[stiffness]\nrows = {}\n",
        p.dim(),
        p.mu(),
        rows(p.stiffness())
    );
    if with_modes {
        s.push_str(&format!("rigid_modes = {}\n", rows(p.rigid_modes())));
    }
    s
}

#[test]
fn a_cork_is_wedged_above_the_tangent_of_its_notch() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cork.toml");
    fs::write(&path, cork(4, 3)).unwrap();
    let path = path.to_str().unwrap();
    let out = wedged(&["critical", path, "--json", "-"]);
    assert_code(&out, 0);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["rigid_modes"], 3);
    assert_eq!(report["status"], "wedged");
    let (lower, upper) = (
        report["lower"].as_f64().unwrap(),
        report["upper"].as_f64().unwrap(),
    );
    // Equilibrium along the axis: mu* >= tan(half angle) = 0.5; a uniform cork slips at every
    // node at once, so it is wedged right there.
    assert!(upper >= 0.5 * (1.0 - 1e-9), "{upper}");
    assert!(
        lower <= 0.5 * (1.0 + 1e-6) && upper <= 0.5 * (1.0 + 1e-6),
        "[{lower}, {upper}]"
    );
    let summary = wedged(&["critical", path]);
    assert_code(&summary, 0);
    assert!(text(&summary.stdout).contains("floating (3 free rigid motions)"));

    // enumerate: the default for a floating body is the pattern search.
    let out = wedged(&["enumerate", path, "--json", "-"]);
    assert_code(&out, 0);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["method"], "pattern-search");
    assert_eq!(report["rigid_modes"], 3);
    assert_eq!(report["outcome"], "wedged");
    assert!(!report["patterns"].as_array().unwrap().is_empty());
    // The same pieces as bnb, which carries the amplitudes in SOCPs.
    let bnb = wedged(&["enumerate", path, "--method", "bnb", "--json", "-"]);
    assert_code(&bnb, 0);
    let bnb: Value = serde_json::from_slice(&bnb.stdout).unwrap();
    assert_eq!(pattern_list(&report), pattern_list(&bnb));

    for args in [
        vec!["enumerate", path, "--method", "pruned-dd"],
        vec!["enumerate", path, "--exact"],
        vec!["enumerate", path, "--method", "pyramid"],
    ] {
        assert_bad_input(&wedged(&args), &[path, "float"]);
    }

    // --certify: a 2D floating body is checked exactly (the default method becomes bnb, whose
    // decisions are kept for the check); the same pieces and mu*.
    let out = wedged(&["enumerate", path, "--certify", "--json", "-"]);
    assert_code(&out, 0);
    let certified: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(certified["method"], "bnb");
    assert_eq!(certified["certified"], true);
    assert_eq!(pattern_list(&certified), pattern_list(&bnb));
    let out = wedged(&["critical", path, "--certify", "--json", "-"]);
    assert_code(&out, 0);
    let certified: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(certified["certified"], true);
    assert!((certified["upper"].as_f64().unwrap() - upper).abs() <= 1e-6 * upper);
}

#[test]
fn a_matrix_problem_with_rigid_modes_answers_as_the_library_does() {
    let dir = tempfile::tempdir().unwrap();
    let p = floating_notch(2, 5, 20f64.to_radians(), 0.8, 11);
    let path = dir.path().join("notch.toml");
    fs::write(&path, matrix_toml(&p, true)).unwrap();
    let path = path.to_str().unwrap();
    let out = wedged(&["critical", path, "--json", "-"]);
    assert_code(&out, 0);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let cli = report["mu_critical"].as_f64().unwrap();
    let lib = critical(&p, &CriticalSettings::default())
        .unwrap()
        .mu_critical
        .unwrap();
    assert!((cli - lib).abs() <= 1e-6 * lib, "{cli} vs {lib}");
    assert!(cli >= 20f64.to_radians().tan() * (1.0 - 1e-9));

    // Without the modes the singular K is refused, and the message says how to declare them.
    let bare = dir.path().join("bare.toml");
    fs::write(&bare, matrix_toml(&p, false)).unwrap();
    assert_bad_input(
        &wedged(&["critical", bare.to_str().unwrap()]),
        &["not positive definite", "rigid_modes"],
    );
}

#[test]
fn bad_rigid_modes_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let p = floating_notch(2, 4, 20f64.to_radians(), 0.8, 12);
    let mut off = p.rigid_modes().clone();
    off[(0, 0)] += 0.5;
    let head = format!(
        "dim = 2\nmu = 1.0\n[stiffness]\nrows = {}\n",
        rows(p.stiffness())
    );
    let cases = [
        // A mode that is not rigid: K R != 0.
        (
            format!("{head}rigid_modes = {}\n", rows(&off)),
            vec!["rigid mode 1", "null space"],
        ),
        // Wrong number of rows.
        (
            "dim = 2\nmu = 1.0\n[stiffness]\nrows = [[2.0, 0.0], [0.0, 1.0]]\n\
             rigid_modes = [[1.0], [0.0], [0.0]]\n"
                .to_string(),
            vec!["rigid modes have 3 rows", "2"],
        ),
        // Dependent modes.
        (
            "dim = 2\nmu = 1.0\n[stiffness]\nrows = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], \
             [0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]]\n\
             rigid_modes = [[0.0, 0.0], [0.0, 0.0], [1.0, 2.0], [0.0, 0.0]]\n"
                .to_string(),
            vec!["linearly dependent", "mode 2"],
        ),
        // A missing file.
        (
            format!("{head}rigid_modes = \"nowhere.mtx\"\n"),
            vec!["nowhere.mtx"],
        ),
    ];
    for (k, (toml, needles)) in cases.iter().enumerate() {
        let path = dir.path().join(format!("bad{k}.toml"));
        fs::write(&path, toml).unwrap();
        let path = path.to_str().unwrap();
        let mut all = needles.clone();
        all.push(if k == 3 { "nowhere" } else { "bad" });
        assert_bad_input(&wedged(&["critical", path]), &all);
    }
}

#[test]
fn the_cork_demo_runs() {
    let dir = tempfile::tempdir().unwrap();
    let out = wedged(&["demo", "--cork", "--out", dir.path().to_str().unwrap()]);
    assert_code(&out, 0);
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("floating (3 free rigid motions)"),
        "{stdout}"
    );
    // The 2D cork's mu* is 0.5 (printed to the bracket's digits: "0.5" or "0.50000001").
    let printed = printed_number(&stdout, "critical friction coefficient: mu* = ")
        .unwrap_or_else(|| panic!("no 2D mu* printed: {stdout}"));
    assert!((printed - 0.5).abs() <= 1e-6, "{printed}: {stdout}");
    assert!(
        stdout.contains("the 3D cork") && stdout.contains("mu* = 0.350351"),
        "{stdout}"
    );
    for file in [
        "result.json",
        "pattern-0.svg",
        "pattern-0.vtu",
        "pieces.pvd",
    ] {
        assert!(dir.path().join(file).exists(), "{file} missing");
    }
    let svg = fs::read_to_string(dir.path().join("pattern-0.svg")).unwrap();
    assert!(svg.contains("nothing clamps the body"));
}
