//! Arbitrary UTF-8 text as a problem file: a problem or a one-line error that names the file,
//! never a panic.
//!
//! The file is taken to live in a directory that does not exist, so a relative `matrix_market`
//! or `gmsh` reference is a "cannot read" error. Two kinds of input are skipped because they
//! are costly rather than wrong: references that could reach real files (absolute paths, `..`;
//! `/dev/zero` would be read forever) and built-in meshes of more than `MAX_NODES` nodes (the
//! library accepts 20 million; condensing them takes minutes).
#![no_main]

use std::path::{Component, Path};

use libfuzzer_sys::fuzz_target;
use wedged_cli::input::problem_file;

const MAX_NODES: u64 = 5_000;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if !affordable(text) {
        return;
    }
    let path = Path::new("/nonexistent-wedged-fuzz/problem.toml");
    for result in [
        problem_file::parse_str(text, path, false).map(drop),
        problem_file::parse_str_for_critical(text, path).map(drop),
    ] {
        if let Err(e) = result {
            let message = e.to_string();
            assert!(!message.contains('\n'), "not one line: {message}");
        }
    }
});

/// Whether the input is cheap to load: file references stay under the file's directory, and a
/// `[mesh.generate]` table asks for at most `MAX_NODES` nodes. Text that is not TOML is cheap.
fn affordable(text: &str) -> bool {
    let Ok(table) = text.parse::<toml::Table>() else {
        return true;
    };
    let confined = |value: Option<&toml::Value>| match value {
        Some(toml::Value::String(s)) => Path::new(s)
            .components()
            .all(|c| matches!(c, Component::Normal(_) | Component::CurDir)),
        _ => true,
    };
    let stiffness = table.get("stiffness").and_then(toml::Value::as_table);
    let mesh = table.get("mesh").and_then(toml::Value::as_table);
    if !confined(stiffness.and_then(|t| t.get("matrix_market")))
        || !confined(mesh.and_then(|t| t.get("gmsh")))
    {
        return false;
    }
    let Some(generate) = mesh
        .and_then(|t| t.get("generate"))
        .and_then(toml::Value::as_table)
    else {
        return true;
    };
    let mut nodes: u64 = 1;
    for key in ["nx", "ny", "nz", "n"] {
        if let Some(toml::Value::Integer(k)) = generate.get(key) {
            // A frustum's `n` divides both x and y.
            let factor = if key == "n" { 2 } else { 1 };
            for _ in 0..factor {
                nodes = nodes.saturating_mul(k.unsigned_abs().saturating_add(1));
            }
        }
    }
    nodes <= MAX_NODES
}
