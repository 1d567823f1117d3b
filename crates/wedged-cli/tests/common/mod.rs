//! What the command's integration tests share: running the binary and checking its exit code
//! and its one-line errors.

#![allow(dead_code)]

use std::process::{Command, Output};

/// The path of an example problem file (`examples/NAME`).
pub fn example(name: &str) -> String {
    format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// An example problem file (`examples/NAME`) with the lines of the given top-level or table
/// keys set to the values given (`key = value`), the others as they are.
pub fn example_with(name: &str, keys: &[(&str, String)]) -> String {
    std::fs::read_to_string(example(name))
        .unwrap()
        .lines()
        .map(|l| {
            let key = l.split(' ').next().unwrap_or("");
            match keys.iter().find(|(k, _)| *k == key) {
                Some((k, v)) => format!("{k} = {v}"),
                None => l.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The path of a test fixture (`tests/fixtures/NAME`).
pub fn fixture(name: &str) -> String {
    format!("{}/tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Runs `wedged` with `args`.
pub fn wedged(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wedged"))
        .args(args)
        .output()
        .expect("the binary runs")
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8(bytes.to_vec()).unwrap()
}

/// The exit code is `code`, and nothing panicked.
pub fn assert_code(out: &Output, code: i32) {
    assert_eq!(
        out.status.code(),
        Some(code),
        "stdout:\n{}\nstderr:\n{}",
        text(&out.stdout),
        text(&out.stderr)
    );
    assert!(!text(&out.stderr).contains("panicked"));
}

/// Exit code 0, and nothing panicked.
pub fn assert_success(out: &Output) {
    assert_code(out, 0);
}

/// Exit code 2 with a one-line error `error: ...` that contains every needle.
pub fn assert_bad_input(out: &Output, needles: &[&str]) {
    assert_code(out, 2);
    let err = text(&out.stderr);
    assert!(err.starts_with("error: "), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "not one line: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
}

/// The `"pattern"` of every piece of a pattern run's JSON, in order.
pub fn pattern_list(report: &serde_json::Value) -> Vec<serde_json::Value> {
    report["patterns"]
        .as_array()
        .expect("a pattern run's JSON")
        .iter()
        .map(|p| p["pattern"].clone())
        .collect()
}

/// The number printed right after the first `after` in `text` (up to the next whitespace), as
/// in `mu* = 0.5 (certified ...`: a value printed to the digits its bracket needs is compared
/// as a number, not as text.
pub fn printed_number(text: &str, after: &str) -> Option<f64> {
    text.split(after)
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|x| x.parse().ok())
}
