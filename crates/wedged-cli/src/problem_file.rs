//! The problem file: TOML naming the dimension, the friction coefficient and the stiffness.
//!
//! ```toml
//! dim = 2
//! mu = 0.8
//! [stiffness]
//! matrix_market = "K.mtx"        # relative to this file's directory
//! # or, inline, the rows of K:
//! # rows = [[2.0, 1.0], [1.0, 1.0]]
//! ```
//!
//! Unknown keys are rejected by name. Every error is one line that starts with the file's name.

use std::fmt;
use std::fs;
use std::path::{Path, PathBuf};

use nalgebra::DMatrix;
use serde::Deserialize;
use wedged::{Problem, ProblemError};

use crate::{mtx, one_line};

/// A problem file that could not be read or is invalid; the message names the file.
#[derive(Debug)]
pub struct LoadError(String);

impl fmt::Display for LoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for LoadError {}

/// The file as written; every key is optional here so that a missing one gets its own message.
#[derive(Debug, Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a problem with keys `dim`, `mu` and [stiffness]"
)]
struct RawProblem {
    dim: Option<usize>,
    mu: Option<f64>,
    stiffness: Option<RawStiffness>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [stiffness] table")]
struct RawStiffness {
    matrix_market: Option<PathBuf>,
    rows: Option<Vec<Vec<f64>>>,
}

/// Reads and validates the problem in the TOML file at `path`.
pub fn load(path: &Path, mu_on_command_line: bool) -> Result<Problem, LoadError> {
    let name = path.display();
    let err = |m: String| LoadError(format!("{name}: {m}"));
    let text =
        fs::read_to_string(path).map_err(|e| err(format!("cannot read the problem file: {e}")))?;
    let raw: RawProblem = toml::from_str(&text).map_err(|e| err(toml_message(&text, &e)))?;

    let dim = raw
        .dim
        .ok_or_else(|| err("missing `dim` (the space dimension, 2 or 3)".into()))?;
    // With --mu on the command line the file's `mu` is not needed (and not read): the caller
    // replaces this placeholder with the command-line value, which the library validates.
    let mu = if mu_on_command_line {
        1.0
    } else {
        raw.mu.ok_or_else(|| {
            err("missing `mu` (the friction coefficient, > 0; or pass --mu)".into())
        })?
    };
    let stiffness = raw.stiffness.ok_or_else(|| {
        err("missing the [stiffness] table (with `matrix_market = \"K.mtx\"` or `rows = [[...], ...]`)"
            .into())
    })?;

    let (k, matrix_source) = match (stiffness.matrix_market, stiffness.rows) {
        (Some(_), Some(_)) => {
            return Err(err(
                "[stiffness] has both `matrix_market` and `rows`; give exactly one".into(),
            ))
        }
        (None, None) => {
            return Err(err(
                "[stiffness] needs `matrix_market = \"K.mtx\"` or `rows = [[...], ...]`".into(),
            ))
        }
        (None, Some(rows)) => (matrix_from_rows(&rows).map_err(err)?, name.to_string()),
        (Some(relative), None) => {
            let base = path.parent().unwrap_or(Path::new(""));
            let mtx_path = base.join(relative);
            let k = mtx::read(&mtx_path).map_err(|e| LoadError(one_line(&e.to_string())))?;
            (
                k,
                format!("{} (the stiffness of {name})", mtx_path.display()),
            )
        }
    };

    Problem::new(dim, k, mu).map_err(|e| match e {
        // Errors in K belong to the file that holds it; the others to the problem file.
        ProblemError::InvalidDim(_) | ProblemError::InvalidMu(_) => err(e.to_string()),
        _ => LoadError(format!("{matrix_source}: {e}")),
    })
}

/// The stiffness from its rows; the rows must all have the same length (squareness and the rest
/// are checked by [`Problem::new`]).
fn matrix_from_rows(rows: &[Vec<f64>]) -> Result<DMatrix<f64>, String> {
    let cols = rows.first().map_or(0, Vec::len);
    if let Some((i, row)) = rows.iter().enumerate().find(|(_, r)| r.len() != cols) {
        return Err(format!(
            "[stiffness] rows are ragged: row {} has {}, row 1 has {}",
            i + 1,
            entries(row.len()),
            entries(cols)
        ));
    }
    Ok(DMatrix::from_fn(rows.len(), cols, |i, j| rows[i][j]))
}

fn entries(n: usize) -> String {
    format!("{n} {}", if n == 1 { "entry" } else { "entries" })
}

/// A TOML error as one line with its position: `TOML error at line 3, column 5: ...`.
fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let message = one_line(e.message());
    match e.span() {
        Some(span) => {
            let start = span.start.min(text.len());
            let before = &text[..start];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("TOML error at line {line}, column {column}: {message}")
        }
        None => format!("TOML error: {message}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load_text(text: &str) -> Result<Problem, LoadError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.toml");
        fs::write(&path, text).unwrap();
        load(&path, false)
    }

    #[test]
    fn inline_rows() {
        let p = load_text("dim = 2\nmu = 1\n[stiffness]\nrows = [[2, 1], [1, 1]]\n").unwrap();
        assert_eq!(p.nodes(), 1);
        assert_eq!(p.mu(), 1.0);
        assert_eq!(p.stiffness()[(0, 1)], 1.0);
    }

    #[test]
    fn toml_errors_have_a_line() {
        let e = load_text("dim = 2\nmu = \n").unwrap_err().to_string();
        assert!(e.contains("line 2"), "{e}");
        assert!(!e.contains('\n'), "{e}");
        let e = load_text("dim = 2\nmu = 1\nfoo = 3\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 3") && e.contains("foo"), "{e}");
    }

    #[test]
    fn ragged_rows_are_named() {
        let e = matrix_from_rows(&[vec![1.0; 4], vec![1.0; 4], vec![1.0; 2]]).unwrap_err();
        assert_eq!(
            e,
            "[stiffness] rows are ragged: row 3 has 2 entries, row 1 has 4 entries"
        );
    }
}
