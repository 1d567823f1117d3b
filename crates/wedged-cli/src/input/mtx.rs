//! Matrix Market reader for dense condensed stiffness matrices.
//!
//! Supported headers (keywords case-insensitive):
//!
//! ```text
//! %%MatrixMarket matrix array      real|integer|double general|symmetric
//! %%MatrixMarket matrix coordinate real|integer|double general|symmetric
//! ```
//!
//! `%` comment lines and blank lines may appear anywhere after the header.
//! Array data is column-major, one value per line; `array symmetric` stores
//! only the lower triangle (diagonal included), column by column.
//! Coordinate data is `row column value` with 1-based indices; in
//! `coordinate symmetric` files each entry may come from either triangle and
//! is mirrored, but a position (or its mirror) may only be given once.
//!
//! Non-square and non-finite matrices are read as they are: the library
//! reports those problems itself, with their location.
//!
//! **Why not a crate** (issue 19 asked): `nalgebra-sparse`'s reader (`io` feature) accepts a
//! position given twice and keeps both entries (its documentation says so), which a later
//! conversion adds up: a stiffness entry written twice would be doubled without a word; and it
//! refuses an `integer` file read as `f64` (`TypeMismatch`). Ours refuses the first, reads the
//! second, and names the file, the line and the entry in every error (the hostile fixtures of
//! `tests/hostile.rs`). The format is small; this reader stays.

use std::collections::HashMap;
use std::fmt;
use std::path::Path;

use nalgebra::DMatrix;

/// Largest number of rows or columns accepted for a dense matrix.
const MAX_DIM: usize = 20_000;

/// The header forms this reader understands, for error messages.
const SUPPORTED_HEADER: &str =
    "%%MatrixMarket matrix array|coordinate real|integer|double general|symmetric";

/// A Matrix Market file could not be read or parsed.
///
/// Its `Display` form is one line: the origin (a path), the line number where
/// one applies, and what is wrong.
#[derive(Debug)]
pub struct MtxError {
    origin: String,
    line: Option<usize>,
    message: String,
}

impl MtxError {
    /// An error about line `line` (1-based) of `origin`.
    fn at(origin: &str, line: usize, message: impl Into<String>) -> Self {
        MtxError {
            origin: origin.to_owned(),
            line: Some(line),
            message: message.into(),
        }
    }

    /// An error about `origin` as a whole.
    fn file(origin: &str, message: impl Into<String>) -> Self {
        MtxError {
            origin: origin.to_owned(),
            line: None,
            message: message.into(),
        }
    }
}

impl fmt::Display for MtxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.origin, line, self.message),
            None => write!(f, "{}: {}", self.origin, self.message),
        }
    }
}

impl std::error::Error for MtxError {}

/// Reads a Matrix Market file into a dense matrix.
pub fn read(path: &Path) -> Result<DMatrix<f64>, MtxError> {
    let origin = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| MtxError::file(&origin, format!("cannot read file: {e}")))?;
    parse_bytes(&bytes, &origin)
}

/// Parses the contents of a Matrix Market file, which must be UTF-8 text; `origin` names the
/// source in messages (a path).
pub fn parse_bytes(bytes: &[u8], origin: &str) -> Result<DMatrix<f64>, MtxError> {
    let text = match std::str::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => {
            let valid = e.valid_up_to();
            let line = 1 + bytes
                .get(..valid)
                .map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count());
            return Err(MtxError::at(
                origin,
                line,
                format!("not a text file: invalid UTF-8 at byte offset {valid}"),
            ));
        }
    };
    parse(text, origin)
}

/// Parses Matrix Market text; `origin` names the source in messages (a path).
pub fn parse(text: &str, origin: &str) -> Result<DMatrix<f64>, MtxError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text.lines().enumerate().map(|(i, line)| (i + 1, line));
    let header = parse_header(lines.next(), origin)?;

    let mut content = lines.filter(|(_, line)| {
        let t = line.trim();
        !t.is_empty() && !t.starts_with('%')
    });
    let Some((size_no, size_line)) = content.next() else {
        return Err(MtxError::file(
            origin,
            format!(
                "missing size line after the header: expected {}",
                header.format.size_form()
            ),
        ));
    };
    let size = parse_size(size_line, &header).map_err(|m| MtxError::at(origin, size_no, m))?;

    match header.format {
        Format::Array => read_array(content, &header, &size, origin),
        Format::Coordinate => read_coordinate(content, &header, &size, origin),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Array,
    Coordinate,
}

impl Format {
    /// What the size line must look like.
    fn size_form(self) -> &'static str {
        match self {
            Format::Array => "2 integers \"rows columns\" (array format)",
            Format::Coordinate => "3 integers \"rows columns entries\" (coordinate format)",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Field {
    /// `real` or `double`.
    Real,
    Integer,
}

#[derive(Debug)]
struct Header {
    format: Format,
    field: Field,
    symmetric: bool,
}

#[derive(Debug)]
struct Size {
    rows: usize,
    cols: usize,
    /// Declared number of stored entries (coordinate format only).
    entries: Option<usize>,
}

/// Parses the banner line `%%MatrixMarket matrix <format> <field> <symmetry>`.
fn parse_header(first: Option<(usize, &str)>, origin: &str) -> Result<Header, MtxError> {
    let Some((no, line)) = first else {
        return Err(MtxError::file(
            origin,
            format!("empty file: expected a Matrix Market header \"{SUPPORTED_HEADER}\""),
        ));
    };
    let err = |m: String| MtxError::at(origin, no, m);
    let tokens: Vec<&str> = line.split_whitespace().collect();
    match tokens.first() {
        Some(banner) if banner.eq_ignore_ascii_case("%%MatrixMarket") => {}
        _ => {
            return Err(err(format!(
                "missing Matrix Market header: expected \"{SUPPORTED_HEADER}\", found {}",
                show(line)
            )))
        }
    }
    let [_, object, format, field, symmetry] = tokens[..] else {
        return Err(err(format!(
            "malformed Matrix Market header {}: expected \"{SUPPORTED_HEADER}\"",
            show(line)
        )));
    };
    if !object.eq_ignore_ascii_case("matrix") {
        return Err(err(format!(
            "unsupported object {}: only \"matrix\" is supported",
            show(object)
        )));
    }
    let format = match format.to_ascii_lowercase().as_str() {
        "array" => Format::Array,
        "coordinate" => Format::Coordinate,
        _ => {
            return Err(err(format!(
                "unsupported format {}: supported formats are \"array\" and \"coordinate\"",
                show(format)
            )))
        }
    };
    let field = match field.to_ascii_lowercase().as_str() {
        "real" | "double" => Field::Real,
        "integer" => Field::Integer,
        _ => {
            return Err(err(format!(
                "unsupported field {}: supported fields are \"real\", \"integer\" and \"double\"",
                show(field)
            )))
        }
    };
    let symmetric = match symmetry.to_ascii_lowercase().as_str() {
        "general" => false,
        "symmetric" => true,
        _ => {
            return Err(err(format!(
                "unsupported symmetry {}: supported symmetries are \"general\" and \"symmetric\"",
                show(symmetry)
            )))
        }
    };
    Ok(Header {
        format,
        field,
        symmetric,
    })
}

/// Parses and checks the size line; the error is the message without location.
fn parse_size(line: &str, header: &Header) -> Result<Size, String> {
    let names: &[&str] = match header.format {
        Format::Array => &["rows", "columns"],
        Format::Coordinate => &["rows", "columns", "entries"],
    };
    let tokens: Vec<&str> = line.split_whitespace().collect();
    if tokens.len() != names.len() {
        return Err(format!(
            "size line: expected {}, found {} {}",
            header.format.size_form(),
            tokens.len(),
            plural(tokens.len(), "token", "tokens")
        ));
    }
    let mut values = [0usize; 3];
    for ((value, token), name) in values.iter_mut().zip(&tokens).zip(names) {
        *value = token.parse().map_err(|_| {
            format!(
                "size line: number of {name} {} is not a non-negative integer",
                show(token)
            )
        })?;
    }
    let [rows, cols, entries] = values;
    if rows == 0 {
        return Err("size line declares zero rows: the matrix is empty".to_owned());
    }
    if cols == 0 {
        return Err("size line declares zero columns: the matrix is empty".to_owned());
    }
    if rows > MAX_DIM || cols > MAX_DIM {
        return Err(format!(
            "declared size {rows} x {cols} is too large for a dense condensed stiffness \
             (limit {MAX_DIM})"
        ));
    }
    if header.symmetric && rows != cols {
        return Err(format!(
            "a symmetric matrix must be square, but the size line declares {rows} x {cols}"
        ));
    }
    let entries = match header.format {
        Format::Array => None,
        Format::Coordinate => {
            let capacity = capacity(rows, cols, header.symmetric);
            if entries > capacity {
                return Err(format!(
                    "size line declares {entries} entries, but {} holds at most {capacity}",
                    describe(rows, cols, header.symmetric)
                ));
            }
            Some(entries)
        }
    };
    Ok(Size {
        rows,
        cols,
        entries,
    })
}

/// Number of distinct stored positions: the whole matrix, or one triangle.
fn capacity(rows: usize, cols: usize, symmetric: bool) -> usize {
    if symmetric {
        rows * (rows + 1) / 2
    } else {
        rows * cols
    }
}

fn describe(rows: usize, cols: usize, symmetric: bool) -> String {
    if symmetric {
        format!("a symmetric {rows} x {cols} matrix (one triangle stored)")
    } else {
        format!("a {rows} x {cols} matrix")
    }
}

fn read_array<'a>(
    content: impl Iterator<Item = (usize, &'a str)>,
    header: &Header,
    size: &Size,
    origin: &str,
) -> Result<DMatrix<f64>, MtxError> {
    let (rows, cols, symmetric) = (size.rows, size.cols, header.symmetric);
    let expected = capacity(rows, cols, symmetric);
    let mut m = DMatrix::zeros(rows, cols);
    let mut count = 0usize;
    // Next position to fill; always in bounds while `count < expected`.
    let (mut i, mut j) = (0usize, 0usize);
    for (no, line) in content {
        let err = |m: String| MtxError::at(origin, no, m);
        if count == expected {
            return Err(err(format!(
                "more entries than declared: {} holds {expected} values",
                describe(rows, cols, symmetric)
            )));
        }
        let [token] = split::<1>(line).map_err(|n| {
            err(format!(
                "expected 1 number \"value\" (array format, one value per line), found {n}"
            ))
        })?;
        let v = parse_value(token, header.field).map_err(err)?;
        m[(i, j)] = v;
        if symmetric {
            m[(j, i)] = v;
        }
        count += 1;
        i += 1;
        if i == rows {
            j += 1;
            i = if symmetric { j } else { 0 };
        }
    }
    if count < expected {
        return Err(MtxError::file(
            origin,
            format!("truncated: expected {expected} entries, found {count}"),
        ));
    }
    Ok(m)
}

fn read_coordinate<'a>(
    content: impl Iterator<Item = (usize, &'a str)>,
    header: &Header,
    size: &Size,
    origin: &str,
) -> Result<DMatrix<f64>, MtxError> {
    let (rows, cols, symmetric) = (size.rows, size.cols, header.symmetric);
    let expected = size.entries.unwrap_or(0);
    let mut m = DMatrix::zeros(rows, cols);
    // Canonical position -> (line, row, column) as first given.
    let mut seen: HashMap<(usize, usize), (usize, usize, usize)> = HashMap::new();
    let mut count = 0usize;
    for (no, line) in content {
        let err = |m: String| MtxError::at(origin, no, m);
        if count == expected {
            return Err(err(format!(
                "more entries than declared: the size line declares {expected} {}",
                plural(expected, "entry", "entries")
            )));
        }
        let [r, c, v] = split::<3>(line).map_err(|n| {
            err(format!(
                "expected 3 numbers \"row column value\", found {n}"
            ))
        })?;
        let i = parse_index(r, "row", rows).map_err(err)?;
        let j = parse_index(c, "column", cols).map_err(err)?;
        let v = parse_value(v, header.field).map_err(err)?;
        let key = if symmetric {
            (i.max(j), i.min(j))
        } else {
            (i, j)
        };
        if let Some(&(prev_no, pi, pj)) = seen.get(&key) {
            return Err(err(if (pi, pj) == (i, j) {
                format!(
                    "duplicate entry ({}, {}): already given at line {prev_no}",
                    i + 1,
                    j + 1
                )
            } else {
                format!(
                    "duplicate entry ({}, {}): the matrix is symmetric and its mirror ({}, {}) \
                     was already given at line {prev_no}",
                    i + 1,
                    j + 1,
                    pi + 1,
                    pj + 1
                )
            }));
        }
        seen.insert(key, (no, i, j));
        m[(i, j)] = v;
        if symmetric {
            m[(j, i)] = v;
        }
        count += 1;
    }
    if count < expected {
        return Err(MtxError::file(
            origin,
            format!("truncated: expected {expected} entries, found {count}"),
        ));
    }
    Ok(m)
}

/// Splits `line` into exactly `N` whitespace-separated tokens, or returns the
/// number of tokens found.
fn split<const N: usize>(line: &str) -> Result<[&str; N], usize> {
    let mut out = [""; N];
    let mut tokens = line.split_whitespace();
    for (k, slot) in out.iter_mut().enumerate() {
        *slot = tokens.next().ok_or(k)?;
    }
    match tokens.count() {
        0 => Ok(out),
        extra => Err(N + extra),
    }
}

/// Parses a 1-based index into a 0-based one below `bound`.
fn parse_index(token: &str, what: &str, bound: usize) -> Result<usize, String> {
    let out_of_range = || {
        format!(
            "{what} index {} is out of range: the matrix has {bound} {what}s (valid 1..={bound})",
            clip(token)
        )
    };
    match token.parse::<i64>() {
        Ok(k) => match usize::try_from(k) {
            Ok(k) if (1..=bound).contains(&k) => Ok(k - 1),
            _ => Err(out_of_range()),
        },
        Err(_) if is_integer_literal(token) => Err(out_of_range()),
        Err(_) => Err(format!("{what} index {} is not an integer", show(token))),
    }
}

/// Whether `token` is an optionally signed run of decimal digits (perhaps one
/// too large for `i64`).
fn is_integer_literal(token: &str) -> bool {
    let digits = token.strip_prefix(['+', '-']).unwrap_or(token);
    !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit())
}

/// Parses a value. `nan` and `inf` (any case) are accepted: the library
/// reports non-finite entries itself.
fn parse_value(token: &str, field: Field) -> Result<f64, String> {
    let v = parse_number(token).ok_or_else(|| format!("value {} is not a number", show(token)))?;
    if field == Field::Integer && v.is_finite() && v.fract() != 0.0 {
        return Err(format!(
            "value {} is not an integer, but the header declares field \"integer\"",
            show(token)
        ));
    }
    Ok(v)
}

/// `str::parse::<f64>`, also accepting Fortran exponents such as `1.5D+03`.
fn parse_number(token: &str) -> Option<f64> {
    token.parse().ok().or_else(|| {
        if token.contains(['d', 'D']) {
            token.replace(['d', 'D'], "e").parse().ok()
        } else {
            None
        }
    })
}

fn plural<'a>(n: usize, one: &'a str, many: &'a str) -> &'a str {
    if n == 1 {
        one
    } else {
        many
    }
}

/// `s` cut to a length fit for a one-line message.
fn clip(s: &str) -> String {
    const MAX_CHARS: usize = 60;
    match s.char_indices().nth(MAX_CHARS) {
        Some((cut, _)) => format!("{}...", &s[..cut]),
        None => s.to_owned(),
    }
}

/// `s` clipped and quoted, with control characters escaped.
fn show(s: &str) -> String {
    format!("{:?}", clip(s))
}

/// The condensed stiffness of a model as Matrix Market text (coordinate real symmetric, lower
/// triangle, shortest round-trip decimals), with comment lines naming each contact node's mesh
/// node and local frame, so that the matrix can be read back exactly.
pub fn write_condensed(model: &wedged::fe::Model, source: &str) -> String {
    use std::fmt::Write;
    let k = model.k();
    let n = k.nrows();
    let dim = model.mesh().dim();
    let b = model.boundary();
    let mut out = String::new();
    out.push_str("%%MatrixMarket matrix coordinate real symmetric\n");
    let _ = writeln!(
        out,
        "% condensed stiffness of {source}, written by wedged {}",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        out,
        "% {} contact nodes, {dim} rows each, normal first ({}); rows and columns are 1-based",
        b.contact_nodes.len(),
        if dim == 2 { "n, t" } else { "n, t1, t2" }
    );
    for (i, (&a, f)) in b.contact_nodes.iter().zip(&b.frames).enumerate() {
        let x = model.mesh().coords()[a];
        let v = |w: [f64; 3]| {
            w[..dim]
                .iter()
                .map(|c| format!("{c:e}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let _ = write!(
            out,
            "% node {} (rows {}-{}): mesh node {} at {}; n = {}; t1 = {}",
            i + 1,
            dim * i + 1,
            dim * i + dim,
            a + 1,
            v(x),
            v(f.n),
            v(f.t1)
        );
        if dim == 3 {
            let _ = write!(out, "; t2 = {}", v(f.t2));
        }
        out.push('\n');
    }
    let entries: Vec<(usize, usize, f64)> = (0..n)
        .flat_map(|j| (j..n).map(move |i| (i, j)))
        .filter(|&(i, j)| k[(i, j)] != 0.0)
        .map(|(i, j)| (i, j, k[(i, j)]))
        .collect();
    let _ = writeln!(out, "{n} {n} {}", entries.len());
    for (i, j, v) in entries {
        let _ = writeln!(out, "{} {} {v:e}", i + 1, j + 1);
    }
    out
}

#[cfg(test)]
mod tests;
