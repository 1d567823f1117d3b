//! A catalogue of hostile inputs (`tests/fixtures/hostile/`, small hand-made files next to the
//! MSH fixtures they reuse): each must end with exit code 2 and one line
//! `error: ...` on stderr that names the file and the problem, never a panic.

use std::path::Path;
use std::process::Command;

/// (problem file, needles that the one-line error must contain).
const CATALOGUE: &[(&str, &[&str])] = &[
    // Matrix Market
    ("mtx_truncated.toml", &["mtx_truncated.mtx", "truncated"]),
    (
        "mtx_garbage.toml",
        &["mtx_garbage.mtx:1", "missing Matrix Market header"],
    ),
    ("mtx_empty.toml", &["mtx_empty.mtx", "empty file"]),
    (
        "mtx_nan.toml",
        &["mtx_nan.mtx", "non-finite entry NaN at row 2, column 1"],
    ),
    ("mtx_inf.toml", &["mtx_inf.mtx", "non-finite entry inf"]),
    ("mtx_overflow.toml", &["mtx_overflow.mtx", "non-finite"]),
    ("mtx_huge.toml", &["mtx_huge.mtx", "not positive definite"]),
    (
        "mtx_odd_size.toml",
        &["mtx_odd_size.mtx", "not a multiple of dim = 2"],
    ),
    ("mtx_not_square.toml", &["mtx_not_square.mtx", "not square"]),
    (
        "mtx_index_out_of_range.toml",
        &["mtx_index_out_of_range.mtx:3", "out of range"],
    ),
    (
        "mtx_asymmetric.toml",
        &["mtx_asymmetric.mtx", "not symmetric", "K[1,2]"],
    ),
    (
        "mtx_indefinite.toml",
        &["mtx_indefinite.mtx", "not positive definite", "node 1"],
    ),
    ("mtx_complex.toml", &["mtx_complex.mtx:1", "complex"]),
    ("toml_missing_mtx.toml", &["nowhere.mtx", "cannot read"]),
    // TOML
    (
        "toml_negative_mu.toml",
        &["toml_negative_mu.toml", "mu", "-0.5"],
    ),
    ("toml_zero_mu.toml", &["toml_zero_mu.toml", "mu", "got 0"]),
    ("toml_nan_mu.toml", &["toml_nan_mu.toml", "NaN"]),
    ("toml_dim4.toml", &["toml_dim4.toml", "got 4"]),
    (
        "toml_unknown_key.toml",
        &["toml_unknown_key.toml", "line 5", "`tolerance`"],
    ),
    (
        "toml_misspelt_material.toml",
        &["line 11", "`poison`", "did you mean `poisson`?"],
    ),
    (
        "toml_not_toml.toml",
        &["toml_not_toml.toml", "TOML error at line 1"],
    ),
    ("toml_binary.toml", &["toml_binary.toml", "UTF-8"]),
    // Meshes and boundary groups
    ("mesh_missing_file.toml", &["nowhere.msh", "cannot read"]),
    ("mesh_garbage.toml", &["garbage.msh", "not a Gmsh MSH file"]),
    ("mesh_truncated.toml", &["truncated.msh", "truncated"]),
    (
        "mesh_msh22.toml",
        // MSH 2.2 is read: the error is the missing group's, with the file's groups.
        &[
            "clamp group 'top' does not exist",
            "'bottom' (1D), 'body' (2D)",
        ],
    ),
    (
        "mesh_second_order.toml",
        &["third_order.msh", "element type 21", "ElementOrder"],
    ),
    (
        "mesh_missing_group.toml",
        &["clamp group 'lid' does not exist", "'top' (1D)"],
    ),
    (
        "mesh_contact_is_body.toml",
        &["contact group 'body'", "2D elements"],
    ),
    (
        "mesh_contact_on_symmetry.toml",
        &["both a contact node", "'bottom'"],
    ),
    ("mesh_zero_normal.toml", &["normal", "zero vector"]),
    (
        "rigid_modes_wrong_size.toml",
        &["rigid_modes_wrong_size.toml", "rigid modes have 3 rows"],
    ),
    ("mesh_poisson_half.toml", &["[material]", "Poisson", "0.5"]),
    ("mesh_negative_young.toml", &["[material]", "Young"]),
    ("mesh_degenerate_element.toml", &["element 1", "zero area"]),
    (
        "mesh_inverted_element.toml",
        &["element 1", "Jacobian changes sign"],
    ),
];

#[test]
fn every_hostile_input_gets_a_one_line_error_and_exit_code_2() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hostile");
    assert!(CATALOGUE.len() >= 30);
    for (file, needles) in CATALOGUE {
        // Run from the fixture directory, as a user would, so that relative paths resolve.
        let out = Command::new(env!("CARGO_BIN_EXE_wedged"))
            .current_dir(&dir)
            .args(["enumerate", file])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{file}: {err}");
        assert!(
            !err.contains("panicked") && !err.contains("internal failure"),
            "{file}: {err}"
        );
        assert!(err.starts_with("error: "), "{file}: {err}");
        assert_eq!(
            err.trim_end().lines().count(),
            1,
            "{file}: not one line: {err}"
        );
        for needle in *needles {
            assert!(err.contains(needle), "{file}: {needle:?} not in {err}");
        }
        assert!(
            out.stdout.is_empty(),
            "{file}: stdout {}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
}

#[test]
fn the_catalogue_covers_every_problem_file_in_the_directory() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hostile");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml") && n != "mesh_ok_square.toml")
        .collect();
    files.sort();
    let mut listed: Vec<String> = CATALOGUE.iter().map(|(f, _)| f.to_string()).collect();
    listed.sort();
    assert_eq!(files, listed);
}

/// The hand-written one-quad mesh next to the broken ones is valid: the errors above come from
/// the broken element, not from the file around it.
#[test]
fn the_control_mesh_runs() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hostile");
    let out = Command::new(env!("CARGO_BIN_EXE_wedged"))
        .current_dir(&dir)
        .args(["enumerate", "mesh_ok_square.toml"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
