//! The binary on meshed bodies: `[mesh]` problem files (generated and Gmsh), `--vtk`, `--svg`,
//! `condense --mtx`, and the errors of the finite-element front end.

mod common;

use std::fs;
use std::path::Path;
use std::process::Output;

use common::{assert_bad_input, assert_success, fixture, printed_number, text, wedged};
use serde_json::Value;

const PLUG: &str = r#"
mu = 2.0
[mesh.generate]
kind = "plug2d"
bottom_width = 1.0
top_width = 2.0
height = 1.0
nx = 6
ny = 4
[material]
young = 210e9
poisson = 0.3
plane = "strain"
[[contact]]
group = "contact"
[[clamp]]
group = "top"
"#;

fn write(dir: &tempfile::TempDir, name: &str, content: &str) -> String {
    let path = dir.path().join(name);
    fs::write(&path, content).unwrap();
    path.display().to_string()
}

fn json_file(path: &Path) -> Value {
    serde_json::from_str(&fs::read_to_string(path).unwrap()).unwrap()
}

fn count(dir: &Path, ext: &str) -> usize {
    fs::read_dir(dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == ext)
        })
        .count()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn a_generated_plug_writes_json_vtu_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "plug.toml", PLUG);
    let out_dir = dir.path().join("out");
    // A stale file of an earlier run is removed; another file is left alone.
    fs::create_dir_all(&out_dir).unwrap();
    fs::write(out_dir.join("cone-99.vtu"), "old").unwrap();
    fs::write(out_dir.join("notes.txt"), "mine").unwrap();
    let json = dir.path().join("r.json");
    let out = wedged(&[
        "enumerate",
        &p,
        "--json",
        json.to_str().unwrap(),
        "--vtk",
        out_dir.to_str().unwrap(),
        "--svg",
        out_dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    let summary = text(&out.stdout);
    assert!(
        summary.contains("model ") && summary.contains("4-node quadrilaterals"),
        "{summary}"
    );
    assert!(summary.contains("contact nodes"), "{summary}");
    let report = json_file(&json);
    let cones = report["cones"].as_array().unwrap().len();
    assert!(cones > 0, "the plug wedges at mu = 2");
    assert_eq!(count(&out_dir, "vtu"), cones);
    assert_eq!(count(&out_dir, "svg"), cones);
    assert!(!out_dir.join("cone-99.vtu").exists());
    assert!(out_dir.join("notes.txt").exists());
    assert!(summary.contains(&format!("{cones} .vtu file")), "{summary}");
    // The collection lists every cone's file, cone N at time step N.
    let pvd = fs::read_to_string(out_dir.join("pieces.pvd")).unwrap();
    assert!(pvd.contains("type=\"Collection\""), "{pvd}");
    let width = (cones - 1).to_string().len();
    for c in 0..cones {
        let file = format!("cone-{c:0width$}.vtu");
        assert!(
            pvd.contains(&format!("timestep=\"{c}\" part=\"0\" file=\"{file}\"")),
            "{pvd}"
        );
    }
    assert_eq!(pvd.matches("<DataSet").count(), cones);
    assert!(summary.contains("pieces.pvd"), "{summary}");
    let model = &report["model"];
    assert_eq!(model["contact"].as_array().unwrap().len(), 8);
    assert_eq!(model["clamped_contact_nodes"], 2);
    let vtu = fs::read_to_string(out_dir.join("cone-0.vtu")).unwrap();
    assert!(vtu.contains("UnstructuredGrid") && vtu.contains("von_mises"));
    let svg = fs::read_to_string(out_dir.join("cone-0.svg")).unwrap();
    assert!(svg.starts_with("<?xml") || svg.starts_with("<svg"));
}

#[test]
fn condense_then_enumerate_the_matrix_gives_the_same_rays() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "plug.toml", PLUG);
    let k = dir.path().join("K.mtx");
    let out = wedged(&["condense", &p, "--mtx", k.to_str().unwrap()]);
    assert_success(&out);
    assert!(
        text(&out.stdout).contains("written to"),
        "{}",
        text(&out.stdout)
    );
    let q = write(
        &dir,
        "k.toml",
        "dim = 2\nmu = 2.0\n[stiffness]\nmatrix_market = \"K.mtx\"\n",
    );
    let a = wedged(&["enumerate", &p, "--json", "-"]);
    let b = wedged(&["enumerate", &q, "--json", "-"]);
    assert_success(&a);
    assert_success(&b);
    let (a, b): (Value, Value) = (
        serde_json::from_slice(&a.stdout).unwrap(),
        serde_json::from_slice(&b.stdout).unwrap(),
    );
    assert_eq!(
        a["rays"].as_array().unwrap().len(),
        b["rays"].as_array().unwrap().len()
    );
    for (x, y) in a["rays"]
        .as_array()
        .unwrap()
        .iter()
        .zip(b["rays"].as_array().unwrap())
    {
        assert_eq!(x["status"], y["status"]);
        for key in ["u", "r"] {
            let (x, y) = (floats(&x[key]), floats(&y[key]));
            let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (p, q) in x.iter().zip(&y) {
                assert!((p - q).abs() <= 1e-12 * scale, "{key}: {p} vs {q}");
            }
        }
    }
    assert_eq!(a["cones"], b["cones"]);
}

/// Rays as sets of per-node values keyed by the contact node's position, so that two meshes of
/// the same body with other node numbers can be compared.
/// A contact node's value in a ray: position (in 1e-6 units), status, `(u_n, u_t, r_n, r_t)`.
type NodeValue = (i64, i64, String, Vec<f64>);

fn rays_by_position(report: &Value) -> Vec<Vec<NodeValue>> {
    let contact = report["model"]["contact"].as_array().unwrap();
    let mut rays: Vec<Vec<NodeValue>> = report["rays"]
        .as_array()
        .unwrap()
        .iter()
        .map(|ray| {
            let u = floats(&ray["u"]);
            let r = floats(&ray["r"]);
            let mut nodes: Vec<NodeValue> = contact
                .iter()
                .enumerate()
                .map(|(i, c)| {
                    let x = floats(&c["x"]);
                    (
                        (x[0] * 1e6).round() as i64,
                        (x[1] * 1e6).round() as i64,
                        ray["status"][i].as_str().unwrap().to_string(),
                        vec![u[2 * i], u[2 * i + 1], r[2 * i], r[2 * i + 1]],
                    )
                })
                .collect();
            nodes.sort_by_key(|n| (n.0, n.1));
            nodes
        })
        .collect();
    rays.sort_by(|a, b| {
        let sa: Vec<&String> = a.iter().map(|n| &n.2).collect();
        let sb: Vec<&String> = b.iter().map(|n| &n.2).collect();
        sa.cmp(&sb)
    });
    rays
}

#[test]
fn a_gmsh_mesh_of_the_plug_gives_the_generators_answer() {
    // tests/fixtures/msh/plug2d_quad.msh was written by Gmsh 4.15 (tools/gmsh/make_fixtures.py)
    // for the same trapezoid with the same nodes as `nx = 6, ny = 4`, numbered differently,
    // and saved as MSH 4.1 and the legacy 2.2, ASCII and binary.
    for file in [
        "plug2d_quad.msh",
        "plug2d_quad_bin.msh",
        "plug2d_quad_22.msh",
        "plug2d_quad_22_bin.msh",
    ] {
        let dir = tempfile::tempdir().unwrap();
        let generated = write(&dir, "gen.toml", PLUG);
        let from_gmsh = write(
            &dir,
            "gmsh.toml",
            &PLUG.replace(
                "[mesh.generate]\nkind = \"plug2d\"\nbottom_width = 1.0\ntop_width = 2.0\nheight = 1.0\nnx = 6\nny = 4\n",
                &format!("[mesh]\ngmsh = \"{}\"\n", fixture(&format!("msh/{file}"))),
            ),
        );
        assert!(fs::read_to_string(&from_gmsh).unwrap().contains("gmsh ="));
        let a = wedged(&["enumerate", &generated, "--json", "-"]);
        let b = wedged(&["enumerate", &from_gmsh, "--json", "-"]);
        assert_success(&a);
        assert_success(&b);
        let a: Value = serde_json::from_slice(&a.stdout).unwrap();
        let b: Value = serde_json::from_slice(&b.stdout).unwrap();
        let (ra, rb) = (rays_by_position(&a), rays_by_position(&b));
        assert!(!ra.is_empty());
        assert_eq!(ra.len(), rb.len(), "{file}");
        for (x, y) in ra.iter().zip(&rb) {
            for (p, q) in x.iter().zip(y) {
                assert_eq!((p.0, p.1, &p.2), (q.0, q.1, &q.2), "{file}");
                let scale = p.3.iter().chain(&q.3).fold(0.0f64, |m, v| m.max(v.abs()));
                for (s, t) in p.3.iter().zip(&q.3) {
                    assert!(
                        (s - t).abs() <= 1e-9 * scale.max(1e-300),
                        "{file}: {s} vs {t}"
                    );
                }
            }
        }
    }
}

fn enumerate_toml(toml: &str, extra: &[&str]) -> (Output, String) {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "p.toml", toml);
    let mut args = vec!["enumerate", p.as_str()];
    args.extend_from_slice(extra);
    let out = wedged(&args);
    drop(dir);
    (out, p)
}

#[test]
fn a_missing_group_is_named_with_the_available_ones() {
    let (out, p) = enumerate_toml(&PLUG.replace("group = \"top\"", "group = \"lid\""), &[]);
    assert_bad_input(&out, &[&p, "clamp group 'lid' does not exist", "'top'"]);
}

#[test]
fn a_missing_mesh_file_is_named() {
    let (out, p) = enumerate_toml(
        "mu = 1\n[mesh]\ngmsh = \"nowhere.msh\"\n[material]\nyoung = 1\npoisson = 0.3\n[[contact]]\ngroup = \"c\"\n",
        &[],
    );
    let _ = p;
    assert_bad_input(&out, &["nowhere.msh"]);
}

#[test]
fn bad_materials_are_named() {
    let (out, p) = enumerate_toml(&PLUG.replace("poisson = 0.3", "poisson = 0.5"), &[]);
    assert_bad_input(&out, &[&p, "[material]", "Poisson"]);
    let (out, _) = enumerate_toml(&PLUG.replace("young = 210e9", "young = -1"), &[]);
    assert_bad_input(&out, &["Young"]);
    let (out, _) = enumerate_toml(&PLUG.replace("plane = \"strain\"", "plane = \"flat\""), &[]);
    assert_bad_input(&out, &["plane = \"flat\""]);
    let (out, _) = enumerate_toml(
        &PLUG.replace(
            "[material]\nyoung = 210e9\npoisson = 0.3\nplane = \"strain\"\n",
            "",
        ),
        &[],
    );
    assert_bad_input(&out, &["missing the [material] table"]);
}

#[test]
fn bad_generator_parameters_are_named() {
    let (out, _) = enumerate_toml(&PLUG.replace("nx = 6", "nx = 0"), &[]);
    assert_bad_input(&out, &["[mesh.generate]", "nx"]);
    let (out, _) = enumerate_toml(&PLUG.replace("plug2d", "cork"), &[]);
    assert_bad_input(&out, &["cork"]);
    let (out, _) = enumerate_toml(&PLUG.replace("ny = 4", "ny = 4\nelement = \"hex\""), &[]);
    assert_bad_input(&out, &["element = \"hex\""]);
}

/// A body that nothing clamps is a floating body (issue 22), no longer refused; a ray method
/// is refused for it with the reason.
#[test]
fn a_floating_body_is_enumerated_by_sign_patterns() {
    let floating = PLUG.replace("[[clamp]]\ngroup = \"top\"\n", "");
    let (out, _) = enumerate_toml(&floating, &[]);
    assert_success(&out);
    assert!(text(&out.stdout).contains("floating (3 free rigid motions)"));
    let (out, _) = enumerate_toml(&floating, &["--method", "pruned-dd"]);
    assert_bad_input(&out, &["floats", "bnb"]);
}

#[test]
fn a_contact_node_cannot_be_a_roller() {
    let (out, _) = enumerate_toml(&format!("{PLUG}[[symmetry]]\ngroup = \"bottom\"\n"), &[]);
    assert_bad_input(&out, &["both a contact node", "'bottom'"]);
}

#[test]
fn a_normal_of_the_wrong_length_is_named() {
    let (out, _) = enumerate_toml(
        &PLUG.replace(
            "group = \"contact\"",
            "group = \"contact\"\nnormal = [1, 0, 0]",
        ),
        &[],
    );
    assert_bad_input(&out, &["`normal` has 3 components"]);
}

#[test]
fn vtk_needs_a_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let out = wedged(&[
        "enumerate",
        &fixture("two_nodes.toml"),
        "--vtk",
        dir.path().to_str().unwrap(),
    ]);
    assert_bad_input(&out, &["--vtk needs a meshed body"]);
}

#[test]
fn vtk_into_a_file_is_refused_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "plug.toml", PLUG);
    let file = write(&dir, "taken", "x");
    let out = wedged(&["enumerate", &p, "--svg", &file]);
    assert_bad_input(&out, &[&file, "needs a directory"]);
}

#[test]
fn condense_needs_a_mesh() {
    let out = wedged(&[
        "condense",
        &fixture("two_nodes.toml"),
        "--mtx",
        "/tmp/never.mtx",
    ]);
    assert_bad_input(&out, &["no [mesh]"]);
}

#[test]
fn a_3d_plug_condenses() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        &dir,
        "v.toml",
        r#"
[mesh.generate]
kind = "frustum3d"
bottom_width = 1.0
top_width = 1.6
height = 1.0
n = 2
nz = 2
element = "tet"
[material]
young = 1.0
poisson = 0.25
[[contact]]
group = "contact"
[[clamp]]
group = "top"
"#,
    );
    let k = dir.path().join("K.mtx");
    let out = wedged(&["condense", &p, "--mtx", k.to_str().unwrap()]);
    assert_success(&out);
    let mtx = fs::read_to_string(&k).unwrap();
    assert!(mtx.starts_with("%%MatrixMarket matrix coordinate real symmetric"));
    assert!(mtx.contains("t2 = "));
    // 4 x 4 side nodes below the clamped top ring: 16 - ... contact nodes, 3 rows each.
    let summary = text(&out.stdout);
    assert!(summary.contains("3D mesh"), "{summary}");
}

/// The example problem files in `examples/` stay valid.
#[test]
fn the_example_files_run() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    for file in ["plug2d.toml", "plug2d_gmsh.toml"] {
        let out = wedged(&["enumerate", root.join(file).to_str().unwrap()]);
        assert_success(&out);
        assert!(
            text(&out.stdout).contains("wedged configurations"),
            "{file}"
        );
    }
    // The floating cork: mu* at the equilibrium bound, and its patterns at its file's mu.
    let cork = root.join("cork2d.toml");
    let out = wedged(&["critical", cork.to_str().unwrap()]);
    assert_success(&out);
    let stdout = text(&out.stdout);
    let printed = printed_number(&stdout, "mu* = ")
        .unwrap_or_else(|| panic!("cork2d.toml: no mu* printed: {stdout}"));
    assert!((printed - 0.5).abs() <= 1e-6, "cork2d.toml: {printed}");
    let out = wedged(&["enumerate", cork.to_str().unwrap()]);
    assert_success(&out);
    assert!(
        text(&out.stdout).contains("maximal sign patterns"),
        "cork2d.toml"
    );
    let cork = root.join("cork3d.toml");
    let out = wedged(&["critical", cork.to_str().unwrap()]);
    assert_success(&out);
    assert!(text(&out.stdout).contains("mu* = 0.350351"), "cork3d.toml");
    let dir = tempfile::tempdir().unwrap();
    let k = dir.path().join("K.mtx");
    let out = wedged(&[
        "condense",
        root.join("frustum3d.toml").to_str().unwrap(),
        "--mtx",
        k.to_str().unwrap(),
    ]);
    assert_success(&out);
}

/// The names of a VTU file's point and cell arrays, parsed back with `vtkio`, and its number of
/// points.
fn vtu_arrays(path: &Path) -> (Vec<String>, Vec<String>, usize) {
    use vtkio::model::{DataSet, Vtk};
    let bytes = fs::read(path).unwrap();
    let vtk = Vtk::parse_xml(bytes.as_slice()).expect("the VTU parses as VTK XML");
    let DataSet::UnstructuredGrid { mut pieces, .. } = vtk.data else {
        panic!("not an unstructured grid");
    };
    assert_eq!(pieces.len(), 1);
    let piece = pieces
        .remove(0)
        .into_loaded_piece_data(None)
        .expect("inline piece");
    let names = |a: &[vtkio::model::Attribute]| -> Vec<String> {
        a.iter().map(|x| x.name().to_string()).collect()
    };
    (
        names(&piece.data.point),
        names(&piece.data.cell),
        piece.num_points(),
    )
}

/// `examples/plug3d.toml` end to end: a 3D body enumerated by sign patterns, one VTU and one SVG
/// per maximal pattern.
#[test]
fn the_3d_plug_example_writes_a_file_per_pattern() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("out");
    // Stale files of earlier runs, cones and patterns, are removed; others are left alone.
    fs::create_dir_all(&out_dir).unwrap();
    for stale in [
        "cone-0.vtu",
        "cone-3.svg",
        "pattern-99.vtu",
        "pattern-99.svg",
    ] {
        fs::write(out_dir.join(stale), "old").unwrap();
    }
    fs::write(out_dir.join("pattern-notes.txt"), "mine").unwrap();
    let json = dir.path().join("r.json");
    let out = wedged(&[
        "enumerate",
        root.join("plug3d.toml").to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
        "--vtk",
        out_dir.to_str().unwrap(),
        "--svg",
        out_dir.to_str().unwrap(),
    ]);
    assert_success(&out);
    let summary = text(&out.stdout);
    assert!(summary.contains("3D mesh"), "{summary}");
    assert!(summary.contains("dim 3, 6 nodes"), "{summary}");
    assert!(summary.contains("method bnb"), "{summary}");
    assert!(summary.contains("maximal sign patterns"), "{summary}");
    let report = json_file(&json);
    assert_eq!(report["dim"], 3);
    assert_eq!(report["complete"], true);
    assert_eq!(report["outcome"], "wedged");
    assert_eq!(report["model"]["contact"].as_array().unwrap().len(), 6);
    assert!(report["model"]["contact"][0]["t2"].is_array());
    let patterns = report["patterns"].as_array().unwrap();
    assert!(!patterns.is_empty(), "the plug wedges at the example's mu");
    assert_eq!(count(&out_dir, "vtu"), patterns.len());
    assert_eq!(count(&out_dir, "svg"), patterns.len());
    for stale in [
        "cone-0.vtu",
        "cone-3.svg",
        "pattern-99.vtu",
        "pattern-99.svg",
    ] {
        assert!(!out_dir.join(stale).exists(), "{stale}");
    }
    assert!(out_dir.join("pattern-notes.txt").exists());
    assert!(
        summary.contains(&format!(
            "{} .vtu files written to {} (pattern-N.vtu",
            patterns.len(),
            out_dir.display()
        )),
        "{summary}"
    );
    // Zero-padded names when there are ten patterns or more.
    let first = if patterns.len() > 10 {
        "pattern-00"
    } else {
        "pattern-0"
    };
    let vtu = out_dir.join(format!("{first}.vtu"));
    let (point, cell, points) = vtu_arrays(&vtu);
    assert_eq!(
        points,
        report["model"]["mesh_nodes"].as_u64().unwrap() as usize
    );
    for name in ["displacement", "force", "contact_status", "normal"] {
        assert!(point.contains(&name.to_string()), "{name} not in {point:?}");
    }
    // A pattern's file shows its witness: no per-ray arrays.
    assert!(!point.iter().any(|n| n.starts_with("ray_")), "{point:?}");
    for name in ["von_mises", "stress"] {
        assert!(cell.contains(&name.to_string()), "{name} not in {cell:?}");
    }
    let text_vtu = fs::read_to_string(&vtu).unwrap();
    assert!(
        text_vtu.contains("pattern #0 of"),
        "the title names the pattern"
    );
    let svg = fs::read_to_string(out_dir.join(format!("{first}.svg"))).unwrap();
    assert!(svg.starts_with("<?xml") || svg.starts_with("<svg"));
    assert_eq!(svg.matches("<circle class=\"contact ").count(), 6);
    assert!(svg.contains("pattern #0 of"));
}

#[test]
fn a_bad_mu_of_a_meshed_body_is_named_as_such() {
    let (out, p) = enumerate_toml(&PLUG.replace("mu = 2.0", "mu = -1.0"), &[]);
    assert_bad_input(
        &out,
        &[&p, "friction coefficient mu must be finite and > 0, got -1"],
    );
    assert!(!String::from_utf8_lossy(&out.stderr).contains("condensed stiffness"));
}

/// Runs `wedged` with `args` and the Gmsh program `gmsh`.
fn wedged_with_gmsh(gmsh: &str, args: &[&str]) -> Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_wedged"))
        .args(args)
        .env("WEDGED_GMSH", gmsh)
        .output()
        .expect("the binary runs")
}

/// A stand-in for Gmsh (a shell script; `cargo test` does not have Gmsh, the Python tests run
/// the real one): it logs its arguments, answers the parse-only run by `reply_parse`, prints
/// `reply_mesh` and writes the Gmsh plug fixture where `-o` says.
#[cfg(unix)]
fn fake_gmsh(dir: &tempfile::TempDir, reply_parse: &str, reply_mesh: &str) -> String {
    use std::os::unix::fs::PermissionsExt;
    let log = dir.path().join("args.log");
    let script = format!(
        "#!/bin/sh\necho \"$@\" >> '{log}'\n\
         case \" $* \" in *' -parse_and_exit '*) printf '{reply_parse}'; exit 0;; esac\n\
         while [ $# -gt 0 ]; do if [ \"$1\" = -o ]; then cp '{msh}' \"$2\"; fi; shift; done\n\
         printf '{reply_mesh}'\n",
        log = log.display(),
        msh = fixture("msh/plug2d_quad.msh"),
    );
    let path = write(dir, "gmsh.sh", &script);
    fs::set_permissions(&path, fs::Permissions::from_mode(0o755)).unwrap();
    path
}

/// `gmsh = "body.geo"` runs Gmsh on the script with the file's `[mesh.parameters]`, and reads
/// the mesh it writes; what Gmsh reports, and parameters the script does not take as given,
/// are one-line errors (exit 2).
#[cfg(unix)]
#[test]
fn a_gmsh_script_is_meshed_by_gmsh_with_its_parameters() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir, "plug.geo", "// meshed by the stand-in\n");
    let toml = PLUG.replace(
        "[mesh.generate]\nkind = \"plug2d\"\nbottom_width = 1.0\ntop_width = 2.0\nheight = 1.0\nnx = 6\nny = 4\n",
        "[mesh]\ngmsh = \"plug.geo\"\n[mesh.parameters]\nangle = 10\nlc = 0.25\n",
    );
    let problem = write(&dir, "plug.toml", &toml);
    let msh = write(
        &dir,
        "msh.toml",
        &toml
            .replace("plug.geo", &fixture("msh/plug2d_quad.msh"))
            .replace("[mesh.parameters]\nangle = 10\nlc = 0.25\n", ""),
    );
    let ok = "wedged-parameter angle 10\\nwedged-parameter lc 0.25\\n";
    let gmsh = fake_gmsh(&dir, "", ok);
    let out = wedged_with_gmsh(&gmsh, &["critical", &problem, "--json", "-"]);
    assert_success(&out);
    let from_script: Value = serde_json::from_slice(&out.stdout).unwrap();
    let out = wedged(&["critical", &msh, "--json", "-"]);
    assert_success(&out);
    let from_msh: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(from_script["mu_critical"], from_msh["mu_critical"]);
    // Two runs: a parse for the parameters' existence, then the mesh with them set.
    let log = fs::read_to_string(dir.path().join("args.log")).unwrap();
    let runs: Vec<&str> = log.lines().collect();
    assert_eq!(runs.len(), 2, "{log}");
    assert!(runs[0].contains("plug.geo") && runs[0].contains("exists.geo -parse_and_exit"));
    assert!(runs[1].contains("check.geo -3 -format msh41 -o "), "{log}");
    assert!(
        runs[1].contains("-setnumber angle 1e1 -setnumber lc 2.5e-1"),
        "{log}"
    );

    let cases: [(&str, &str, &[&str]); 3] = [
        (
            "",
            "wedged-parameter angle 10\\nwedged-parameter lc 0.1\\n",
            &[
                "plug.toml: [mesh.parameters]: lc = 0.25, but ",
                "set it to 0.1",
                "DefineConstant[ lc = {0.1} ]",
            ],
        ),
        (
            "wedged-parameter lc undefined\\n",
            ok,
            &[
                "plug.geo has no variable lc",
                "DefineConstant[ lc = {...} ]",
            ],
        ),
        (
            "",
            "Info : x\\nError   : plug.geo, line 3: syntax error (Pint)\\n",
            &[
                "Gmsh failed on ",
                "plug.geo: plug.geo, line 3: syntax error (Pint)",
            ],
        ),
    ];
    for (parse, mesh, needles) in cases {
        let gmsh = fake_gmsh(&dir, parse, mesh);
        assert_bad_input(&wedged_with_gmsh(&gmsh, &["critical", &problem]), needles);
    }
    assert_bad_input(
        &wedged_with_gmsh(
            &dir.path().join("nowhere").display().to_string(),
            &["critical", &problem],
        ),
        &[
            "meshing ",
            "needs Gmsh, and `",
            "was not found",
            "WEDGED_GMSH",
        ],
    );
    let bad_name = write(
        &dir,
        "bad.toml",
        &toml.replace("angle = 10", "\"an gle\" = 10"),
    );
    assert_bad_input(
        &wedged_with_gmsh(&gmsh, &["critical", &bad_name]),
        &["`an gle` is not a Gmsh variable name"],
    );
    let with_msh = write(
        &dir,
        "params.toml",
        &toml.replace("plug.geo", &fixture("msh/plug2d_quad.msh")),
    );
    assert_bad_input(
        &wedged(&["critical", &with_msh]),
        &["[mesh.parameters] are for a Gmsh script"],
    );
}

/// `size_factor` reaches Gmsh as `-clscale` and is read back after the script ran; it is
/// refused for a mesh file, and where it is not positive or the script sets it itself.
#[cfg(unix)]
#[test]
fn a_scripts_size_factor_goes_to_gmsh() {
    let dir = tempfile::tempdir().unwrap();
    write(&dir, "plug.geo", "// meshed by the stand-in\n");
    let mesh = "[mesh]\ngmsh = \"plug.geo\"\nsize_factor = 2.5\n";
    let toml = PLUG.replace(
        "[mesh.generate]\nkind = \"plug2d\"\nbottom_width = 1.0\ntop_width = 2.0\nheight = 1.0\nnx = 6\nny = 4\n",
        mesh,
    );
    assert!(toml.contains(mesh));
    let problem = write(&dir, "plug.toml", &toml);
    let gmsh = fake_gmsh(&dir, "", "wedged-parameter Mesh.MeshSizeFactor 2.5\\n");
    assert_success(&wedged_with_gmsh(&gmsh, &["critical", &problem]));
    let log = fs::read_to_string(dir.path().join("args.log")).unwrap();
    // No parameters: no parse-only run; the factor after the output file.
    assert_eq!(log.lines().count(), 1, "{log}");
    assert!(log.contains("-clscale 2.5e0"), "{log}");

    let cases: [(&str, &[&str]); 2] = [
        (
            "wedged-parameter Mesh.MeshSizeFactor 1\\n",
            &[
                "plug.toml: [mesh]: size_factor = 2.5, but ",
                "sets Mesh.MeshSizeFactor = 1 itself",
            ],
        ),
        ("Info : meshed\\n", &["printed no Mesh.MeshSizeFactor"]),
    ];
    for (reply, needles) in cases {
        let gmsh = fake_gmsh(&dir, "", reply);
        assert_bad_input(&wedged_with_gmsh(&gmsh, &["critical", &problem]), needles);
    }
    for (bad, shown) in [("0", "0"), ("-1.0", "-1"), ("nan", "NaN")] {
        let path = write(
            &dir,
            "bad.toml",
            &toml.replace("size_factor = 2.5", &format!("size_factor = {bad}")),
        );
        assert_bad_input(
            &wedged_with_gmsh(&gmsh, &["critical", &path]),
            &[&format!(
                "[mesh]: size_factor = {shown} is not a positive number"
            )],
        );
    }
    let with_msh = write(
        &dir,
        "factor.toml",
        &toml.replace("plug.geo", &fixture("msh/plug2d_quad.msh")),
    );
    assert_bad_input(
        &wedged(&["critical", &with_msh]),
        &["[mesh]: size_factor is for a Gmsh script"],
    );
}
