//! `wedged study` end to end: each point's `mu*` equals `wedged critical` on the same problem
//! file written by hand, a rerun resumes from `study.csv`, incomplete points are computed
//! again, and bad options or files are one-line errors with exit code 2. Also the other
//! series: `sweep --vtk`, each pattern at its own threshold with `mu` as ParaView's time.

use std::fs;
use std::path::Path;
use std::process::{Command, Output};

use serde_json::Value;

fn wedged(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wedged"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).unwrap()
}

fn assert_code(out: &Output, code: i32) {
    assert_eq!(
        out.status.code(),
        Some(code),
        "stdout:\n{}\nstderr:\n{}",
        text(&out.stdout),
        text(&out.stderr)
    );
    assert!(!text(&out.stderr).contains("panicked"));
}

/// Exit code 2 and one line on stderr naming every needle.
fn assert_bad_input(out: &Output, needles: &[&str]) {
    assert_code(out, 2);
    let err = text(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
}

/// A small generated plug (m = 6 with `ny = 2`).
fn plug(poisson: f64, ny: usize, top_width: f64) -> String {
    format!(
        "mu = 2.0\n[mesh.generate]\nkind = \"plug2d\"\nbottom_width = 1.0\ntop_width = {top_width:?}\n\
         height = 1.0\nnx = 2\nny = {ny}\nelement = \"quad\"\n[material]\nyoung = 1000.0\n\
         poisson = {poisson:?}\nplane = \"strain\"\n[[contact]]\ngroup = \"contact\"\n\
         [[clamp]]\ngroup = \"top\"\n"
    )
}

/// `wedged study` of the file `base` over the grid of `vary` (one `--vary` each), with `extra`
/// options, into `out_dir`; it succeeds.
fn study(base: &Path, out_dir: &Path, vary: &[&str], extra: &[&str]) -> Output {
    let mut args = vec!["study", base.to_str().unwrap()];
    for v in vary {
        args.extend(["--vary", v]);
    }
    args.extend(["--out", out_dir.to_str().unwrap()]);
    args.extend(extra);
    let out = wedged(&args);
    assert_code(&out, 0);
    out
}

/// [`study`] of the one point `material.poisson = 0.3`.
fn one_point(base: &Path, out_dir: &Path, extra: &[&str]) -> Output {
    study(base, out_dir, &["material.poisson=0.3"], extra)
}

/// `mu*` of a problem file by `wedged critical --json -`.
fn critical(dir: &Path, name: &str, toml: &str) -> f64 {
    let path = dir.join(name);
    fs::write(&path, toml).unwrap();
    let out = wedged(&["critical", path.to_str().unwrap(), "--json", "-"]);
    assert_code(&out, 0);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    report["mu_critical"].as_f64().expect("wedged")
}

/// The CSV as rows of fields, header first.
fn csv(path: &Path) -> Vec<Vec<String>> {
    fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

fn column(rows: &[Vec<String>], name: &str) -> Vec<String> {
    let j = rows[0].iter().position(|c| c == name).expect(name);
    rows[1..].iter().map(|r| r[j].clone()).collect()
}

#[test]
fn each_point_agrees_with_critical_and_a_rerun_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("plug.toml");
    fs::write(&base, plug(0.3, 2, 2.0)).unwrap();
    let out_dir = dir.path().join("study");
    let (b, o) = (base.to_str().unwrap(), out_dir.to_str().unwrap());
    let out = wedged(&[
        "study",
        b,
        "--vary",
        "material.poisson=0.2,0.3",
        "--vary",
        "half_angle=20,30",
        "--out",
        o,
        "--vtk",
    ]);
    assert_code(&out, 0);
    let rows = csv(&out_dir.join("study.csv"));
    assert_eq!(rows.len(), 5, "{rows:?}");
    assert_eq!(
        rows[0][..3],
        ["material.poisson", "half_angle", "m"].map(String::from)
    );
    assert!(column(&rows, "complete").iter().all(|c| c == "true"));
    assert!(column(&rows, "status").iter().all(|c| c == "wedged"));
    // Each point equals `critical` on the file written by hand (the same mesh, the same
    // search: the same number to round-off).
    let mus = column(&rows, "mu_star");
    let mut k = 0;
    for poisson in [0.2, 0.3] {
        for angle in [20.0_f64, 30.0] {
            let top = 1.0 + 2.0 * angle.to_radians().tan();
            let expected = critical(dir.path(), "hand.toml", &plug(poisson, 2, top));
            let got: f64 = mus[k].parse().unwrap();
            assert!(
                (got - expected).abs() <= 1e-9 * expected,
                "poisson {poisson}, angle {angle}: {got} against {expected}"
            );
            k += 1;
        }
    }
    // The witnesses and their collection.
    let pvd = fs::read_to_string(out_dir.join("study.pvd")).unwrap();
    for n in 0..4 {
        assert!(out_dir.join(format!("point-{n}.vtu")).exists());
        assert!(pvd.contains(&format!(
            "timestep=\"{n}\" part=\"0\" file=\"point-{n}.vtu\""
        )));
    }
    let svg = fs::read_to_string(out_dir.join("study.svg")).unwrap();
    assert_eq!(svg.matches("<circle").count(), 4);
    assert!(
        svg.contains("half_angle 20"),
        "a line per half-angle: {svg}"
    );

    // A rerun with a wider grid computes only the new points and keeps the old rows as they
    // were.
    let out = wedged(&[
        "study",
        b,
        "--vary",
        "material.poisson=0.2,0.3,0.4",
        "--vary",
        "half_angle=20,30",
        "--out",
        o,
    ]);
    assert_code(&out, 0);
    let stdout = text(&out.stdout);
    assert_eq!(stdout.matches("(from study.csv)").count(), 4, "{stdout}");
    assert!(
        stdout.contains("2 computed now, 4 from study.csv"),
        "{stdout}"
    );
    let again = csv(&out_dir.join("study.csv"));
    assert_eq!(again.len(), 7);
    assert_eq!(again[1..5], rows[1..5]);
}

#[test]
fn a_refinement_study_is_plotted_against_h_and_extrapolated() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("plug.toml");
    fs::write(&base, plug(0.3, 1, 2.0)).unwrap();
    let out_dir = dir.path().join("s");
    let out = wedged(&[
        "study",
        base.to_str().unwrap(),
        "--vary",
        "refine=1,2,3,4",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_code(&out, 0);
    let rows = csv(&out_dir.join("study.csv"));
    let m: Vec<usize> = column(&rows, "m")
        .iter()
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(m, vec![2, 4, 6, 8]);
    let h: Vec<f64> = column(&rows, "h")
        .iter()
        .map(|v| v.parse().unwrap())
        .collect();
    assert!(h.windows(2).all(|w| w[1] < w[0]), "{h:?}");
    let svg = fs::read_to_string(out_dir.join("study.svg")).unwrap();
    assert!(svg.contains("mesh size h"));
    // One line (the refinement is the x axis, not a legend).
    assert_eq!(
        svg.matches("<polyline points=").count(),
        2,
        "axes and one line"
    );
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("extrapolated to h = 0") || stdout.contains("no extrapolation"),
        "{stdout}"
    );
}

/// A finer mesh's point starts from the coarser point's answer of the same body (the same
/// Poisson's ratio), never from another body's, and the study's numbers are those of a study
/// that computes every point from scratch (`--no-chain`).
#[test]
fn finer_points_start_from_the_coarser_answer_of_the_same_body() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("plug.toml");
    fs::write(&base, plug(0.3, 1, 2.0)).unwrap();
    let run = |name: &str, extra: &[&str]| {
        let out_dir = dir.path().join(name);
        let vary = ["material.poisson=0.2,0.35", "refine=4,6,8"];
        let out = study(&base, &out_dir, &vary, extra);
        (csv(&out_dir.join("study.csv")), text(&out.stdout))
    };
    let (chained, said) = run("chained", &[]);
    let (scratch, said_scratch) = run("scratch", &["--no-chain"]);
    let started: Vec<bool> = said
        .lines()
        .filter(|l| l.contains("refine = "))
        .map(|l| l.contains("started from the coarser answer"))
        .collect();
    // Grid order: Poisson's ratio slowest; the first mesh of each body has nothing to start from.
    assert_eq!(started, [false, true, true, false, true, true], "{said}");
    assert!(!said_scratch.contains("started from"), "{said_scratch}");
    // A certified search uses no start, and the study says none.
    let (certified, said_certified) = run("certified", &["--certify"]);
    assert!(!said_certified.contains("started from"), "{said_certified}");
    assert_eq!(column(&certified, "m"), column(&chained, "m"));
    assert_eq!(column(&chained, "m"), ["8", "12", "16", "8", "12", "16"]);
    for key in ["lower", "upper"] {
        for (a, b) in column(&chained, key).iter().zip(column(&scratch, key)) {
            let (a, b): (f64, f64) = (a.parse().unwrap(), b.parse().unwrap());
            assert!((a - b).abs() <= 1e-8 * b.abs(), "{key}: {a} against {b}");
        }
    }
}

/// A point of 80 contact nodes or more with no coarser point before it starts, as `critical`
/// does, from its problem condensed onto about half its nodes (not with `--no-chain`); the
/// same `mu*`.
#[test]
fn a_large_first_point_starts_from_its_condensed_problem() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("plug.toml");
    fs::write(&base, plug(0.3, 40, 2.0)).unwrap();
    let mut mu = Vec::new();
    for (name, extra) in [("condensed", None), ("scratch", Some("--no-chain"))] {
        let out_dir = dir.path().join(name);
        let out = one_point(&base, &out_dir, extra.as_slice());
        let said = text(&out.stdout);
        assert_eq!(
            said.contains("started from its problem condensed onto "),
            extra.is_none(),
            "{said}"
        );
        let rows = csv(&out_dir.join("study.csv"));
        assert_eq!(column(&rows, "m"), ["80"]);
        mu.push(column(&rows, "mu_star")[0].parse::<f64>().unwrap());
    }
    assert!((mu[0] - mu[1]).abs() <= 2e-9 * mu[1], "{mu:?}");
}

#[test]
fn a_point_stopped_by_the_time_limit_is_incomplete_and_computed_again() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("plug.toml");
    fs::write(&base, plug(0.3, 2, 2.0)).unwrap();
    let out_dir = dir.path().join("s");
    let (b, o) = (base.to_str().unwrap(), out_dir.to_str().unwrap());
    let args = [
        "study",
        b,
        "--vary",
        "material.poisson=0.25,0.35",
        "--out",
        o,
    ];
    let mut limited = args.to_vec();
    limited.extend(["--time-limit", "0"]);
    let out = wedged(&limited);
    assert_code(&out, 3);
    let err = text(&out.stderr);
    assert!(err.contains("the study is incomplete"), "{err}");
    let rows = csv(&out_dir.join("study.csv"));
    assert_eq!(rows.len(), 3);
    assert!(column(&rows, "complete").iter().all(|c| c == "false"));
    assert!(column(&rows, "mu_star").iter().all(String::is_empty));
    let out = wedged(&args);
    assert_code(&out, 0);
    assert!(!text(&out.stdout).contains("(from study.csv)"));
    let rows = csv(&out_dir.join("study.csv"));
    assert!(column(&rows, "complete").iter().all(|c| c == "true"));
}

#[test]
fn bad_studies_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("plug.toml");
    fs::write(&base, plug(0.3, 2, 2.0)).unwrap();
    let b = base.to_str().unwrap();
    let o = dir.path().join("s");
    let o = o.to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["study", b, "--out", o];
        args.extend_from_slice(extra);
        wedged(&args)
    };
    assert_bad_input(
        &run(&["--vary", "material.poison=0.2"]),
        &[
            "material.poison",
            "no such key",
            "the numbers it sets: material.poisson",
        ],
    );
    // A key without its table is named with it.
    assert_bad_input(
        &run(&["--vary", "poisson=0.2"]),
        &["no such key", "did you mean material.poisson?"],
    );
    assert_bad_input(
        &run(&["--vary", "nope.ny=2"]),
        &["no table \"nope\"", "mesh.generate.ny"],
    );
    // A malformed --vary is clap's usage error (exit 2, with the usage line).
    let out = run(&["--vary", "poisson"]);
    assert_code(&out, 2);
    assert!(text(&out.stderr).contains("expected KEY=V1,V2,... or KEY=FROM:TO:COUNT"));
    assert_bad_input(&run(&["--vary", "mesh.generate.ny=2.5"]), &["whole number"]);
    assert_bad_input(
        &run(&["--vary", "material.poisson=0.5"]),
        &["material.poisson = 0.5"],
    );
    assert_bad_input(
        &run(&["--vary", "refine=2", "--x", "poisson"]),
        &["--x poisson", "refine"],
    );
    let missing = dir.path().join("missing.toml");
    assert_bad_input(
        &wedged(&[
            "study",
            missing.to_str().unwrap(),
            "--vary",
            "refine=1",
            "--out",
            o,
        ]),
        &["missing.toml"],
    );
    // Another study's CSV in the directory is not overwritten.
    fs::create_dir_all(o).unwrap();
    fs::write(Path::new(o).join("study.csv"), "refine,m,h\n1,2,3\n").unwrap();
    assert_bad_input(
        &run(&["--vary", "material.poisson=0.2"]),
        &["study.csv", "header"],
    );
    // --out must be a directory.
    let file = dir.path().join("f");
    fs::write(&file, "x").unwrap();
    assert_bad_input(
        &wedged(&[
            "study",
            b,
            "--vary",
            "refine=1",
            "--out",
            file.to_str().unwrap(),
        ]),
        &["directory"],
    );
}

#[test]
fn sweep_writes_each_pattern_at_its_threshold_as_a_series() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("plug.toml");
    fs::write(&base, plug(0.3, 2, 2.0)).unwrap();
    let series = dir.path().join("series");
    // An old series file is replaced, not mixed in.
    fs::create_dir_all(&series).unwrap();
    fs::write(series.join("threshold-7.vtu"), "old").unwrap();
    let svg = dir.path().join("plot.svg");
    let out = wedged(&[
        "sweep",
        base.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
        "--vtk",
        series.to_str().unwrap(),
        "--json",
        "-",
    ]);
    assert_code(&out, 0);
    assert!(!series.join("threshold-7.vtu").exists());
    let report: Value = serde_json::from_slice(&out.stdout).unwrap();
    let thresholds: Vec<f64> = report["thresholds"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["threshold"].as_f64().unwrap())
        .collect();
    assert!(!thresholds.is_empty());
    let pvd = fs::read_to_string(series.join("sweep.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), thresholds.len(), "{pvd}");
    for (k, t) in thresholds.iter().enumerate() {
        let name = format!("threshold-{k}.vtu");
        assert!(series.join(&name).exists());
        assert!(
            pvd.contains(&format!("timestep=\"{t}\" part=\"0\" file=\"{name}\"")),
            "{pvd}"
        );
    }
    // A condensed stiffness has no mesh to draw.
    let stiffness = dir.path().join("k.toml");
    fs::write(
        &stiffness,
        "dim = 2\nmu = 2.0\n[stiffness]\nrows = [[2.0, 1.0], [1.0, 1.0]]\n",
    )
    .unwrap();
    assert_bad_input(
        &wedged(&[
            "sweep",
            stiffness.to_str().unwrap(),
            "--svg",
            svg.to_str().unwrap(),
            "--vtk",
            series.to_str().unwrap(),
        ]),
        &["--vtk needs a meshed body"],
    );
}

/// A point's line shows as many digits of `mu*` as its bracket certifies, as `critical` does:
/// four with `--tol 1e-2`, ten with the default (whose `mu*` it matches to 1e-2).
#[test]
fn a_points_line_shows_the_digits_its_bracket_certifies() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("plug.toml");
    fs::write(&base, plug(0.3, 2, 2.0)).unwrap();
    let line = |tol: Option<&str>, out: &str| -> String {
        let extra: Vec<&str> = tol.map(|t| vec!["--tol", t]).unwrap_or_default();
        let out = one_point(&base, &dir.path().join(out), &extra);
        let stdout = text(&out.stdout);
        let line = stdout
            .lines()
            .find(|l| l.contains("mu* = "))
            .unwrap_or_default();
        let after = line.split("mu* = ").nth(1).unwrap_or_default();
        after
            .split_whitespace()
            .next()
            .unwrap_or_default()
            .to_string()
    };
    let (loose, fine) = (line(Some("1e-2"), "loose"), line(None, "fine"));
    let digits = |s: &str| s.chars().filter(char::is_ascii_digit).count();
    assert_eq!(digits(&loose), 4, "{loose}");
    assert_eq!(digits(&fine), 10, "{fine}");
    let (a, b): (f64, f64) = (loose.parse().unwrap(), fine.parse().unwrap());
    assert!((a - b).abs() <= 1e-2 * b && a >= b, "{a} against {b}");
}
