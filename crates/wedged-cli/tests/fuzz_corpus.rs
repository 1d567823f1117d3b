//! The fuzz targets' inputs on the stable toolchain: every seed in `fuzz/corpus/<target>/` and
//! every kept crash in `fuzz/regressions/<target>/` (see FUZZING.md) goes through the same
//! library entry point as in `fuzz/fuzz_targets/<target>.rs`, and must give a value or a
//! one-line error, never a panic.

use std::fs;
use std::path::{Path, PathBuf};

use wedged_cli::input::{msh, mtx, problem_file};

/// The files of `fuzz/<kind>/<target>/` for `kind` = corpus and regressions, sorted.
fn inputs(target: &str) -> Vec<PathBuf> {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz");
    let mut files = Vec::new();
    for kind in ["corpus", "regressions"] {
        let Ok(entries) = fs::read_dir(fuzz.join(kind).join(target)) else {
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            if path.is_file() {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn assert_one_line(file: &Path, message: &str) {
    assert!(
        !message.contains('\n'),
        "{}: not one line: {message}",
        file.display()
    );
}

#[test]
fn matrix_market_inputs() {
    let files = inputs("mtx");
    assert!(files.len() >= 5, "{files:?}");
    for file in files {
        let bytes = fs::read(&file).unwrap();
        if let Err(e) = mtx::parse_bytes(&bytes, "fuzz.mtx") {
            let message = e.to_string();
            assert!(message.starts_with("fuzz.mtx"), "{message}");
            assert_one_line(&file, &message);
        }
    }
}

#[test]
fn gmsh_inputs() {
    let files = inputs("msh");
    assert!(files.len() >= 5, "{files:?}");
    for file in files {
        let bytes = fs::read(&file).unwrap();
        if let Err(e) = msh::parse(&bytes, "fuzz.msh") {
            let message = e.to_string();
            assert!(message.starts_with("fuzz.msh: "), "{message}");
            assert_one_line(&file, &message);
        }
    }
}

#[test]
fn problem_file_inputs() {
    let files = inputs("problem_toml");
    assert!(files.len() >= 5, "{files:?}");
    // As in the fuzz target: the file lives in a directory that does not exist.
    let path = Path::new("/nonexistent-wedged-fuzz/problem.toml");
    for file in files {
        let bytes = fs::read(&file).unwrap();
        let Ok(text) = std::str::from_utf8(&bytes) else {
            continue;
        };
        for result in [
            problem_file::parse_str(text, path, false).map(drop),
            problem_file::parse_str_for_critical(text, path).map(drop),
        ] {
            if let Err(e) = result {
                assert_one_line(&file, &e.to_string());
            }
        }
    }
}
