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
mod tests {
    use super::*;

    const ORIGIN: &str = "K.mtx";

    fn ok(text: &str) -> DMatrix<f64> {
        match parse(text, ORIGIN) {
            Ok(m) => m,
            Err(e) => panic!("unexpected error: {e}"),
        }
    }

    /// The error message for `text`, checked to be a single line.
    fn err(text: &str) -> String {
        let message = match parse(text, ORIGIN) {
            Ok(m) => panic!("expected an error, parsed {m}"),
            Err(e) => e.to_string(),
        };
        assert!(!message.contains('\n'), "multi-line message: {message}");
        assert!(message.starts_with("K.mtx"), "{message}");
        message
    }

    fn assert_contains(message: &str, parts: &[&str]) {
        for part in parts {
            assert!(message.contains(part), "message {message:?} lacks {part:?}");
        }
    }

    // ----- headers -----

    #[test]
    fn empty_file_is_missing_header() {
        let e = err("");
        assert_contains(&e, &["K.mtx: empty file", "%%MatrixMarket matrix"]);
    }

    #[test]
    fn missing_header() {
        let e = err("3 3\n1\n2\n3\n");
        assert_contains(
            &e,
            &["K.mtx:1: missing Matrix Market header", "found \"3 3\""],
        );
        let e = err("% just a comment\n3 3\n");
        assert_contains(&e, &["K.mtx:1: missing Matrix Market header"]);
    }

    #[test]
    fn garbled_header() {
        let e = err("%%MatrixMarket matrix array real\n1 1\n1\n");
        assert_contains(
            &e,
            &[
                "K.mtx:1: malformed Matrix Market header",
                "\"%%MatrixMarket matrix array real\"",
                SUPPORTED_HEADER,
            ],
        );
        let e = err("%%MatrixMarket matrix array real general extra\n1 1\n1\n");
        assert_contains(&e, &["K.mtx:1: malformed Matrix Market header"]);
        let e = err("%%MatrixMarket\n");
        assert_contains(&e, &["K.mtx:1: malformed Matrix Market header"]);
    }

    #[test]
    fn unsupported_object() {
        let e = err("%%MatrixMarket vector array real general\n1\n1\n");
        assert_contains(
            &e,
            &[
                "K.mtx:1: unsupported object \"vector\"",
                "only \"matrix\" is supported",
            ],
        );
    }

    #[test]
    fn unsupported_format() {
        let e = err("%%MatrixMarket matrix sparse real general\n1 1\n1\n");
        assert_contains(
            &e,
            &[
                "K.mtx:1: unsupported format \"sparse\"",
                "\"array\" and \"coordinate\"",
            ],
        );
    }

    #[test]
    fn unsupported_field_complex() {
        let e = err("%%MatrixMarket matrix array complex general\n1 1\n1 0\n");
        assert_contains(
            &e,
            &[
                "K.mtx:1: unsupported field \"complex\"",
                "\"real\", \"integer\" and \"double\"",
            ],
        );
    }

    #[test]
    fn unsupported_field_pattern() {
        let e = err("%%MatrixMarket matrix coordinate pattern general\n1 1 1\n1 1\n");
        assert_contains(
            &e,
            &[
                "K.mtx:1: unsupported field \"pattern\"",
                "supported fields are",
            ],
        );
    }

    #[test]
    fn unsupported_symmetry_hermitian() {
        let e = err("%%MatrixMarket matrix array real hermitian\n1 1\n1\n");
        assert_contains(
            &e,
            &[
                "K.mtx:1: unsupported symmetry \"hermitian\"",
                "\"general\" and \"symmetric\"",
            ],
        );
    }

    #[test]
    fn unsupported_symmetry_skew() {
        let e = err("%%MatrixMarket matrix coordinate real Skew-Symmetric\n2 2 1\n2 1 1\n");
        assert_contains(
            &e,
            &[
                "K.mtx:1: unsupported symmetry \"Skew-Symmetric\"",
                "\"general\" and \"symmetric\"",
            ],
        );
    }

    #[test]
    fn header_keywords_case_insensitive() {
        let m = ok("%%matrixmarket MATRIX Array REAL General\n1 1\n2.5\n");
        assert_eq!(m, DMatrix::from_element(1, 1, 2.5));
        let m = ok("%%MatrixMarket Matrix COORDINATE Double SYMMETRIC\n1 1 1\n1 1 4\n");
        assert_eq!(m, DMatrix::from_element(1, 1, 4.0));
    }

    // ----- size line -----

    #[test]
    fn missing_size_line() {
        let e = err("%%MatrixMarket matrix array real general\n% comment\n\n");
        assert_contains(
            &e,
            &[
                "K.mtx: missing size line",
                "\"rows columns\" (array format)",
            ],
        );
        let e = err("%%MatrixMarket matrix coordinate real general");
        assert_contains(
            &e,
            &[
                "K.mtx: missing size line",
                "\"rows columns entries\" (coordinate format)",
            ],
        );
    }

    #[test]
    fn size_line_wrong_count() {
        let e = err("%%MatrixMarket matrix array real general\n2 2 4\n1\n2\n3\n4\n");
        assert_contains(
            &e,
            &[
                "K.mtx:2: size line: expected 2 integers \"rows columns\"",
                "found 3 tokens",
            ],
        );
        let e = err("%%MatrixMarket matrix coordinate real general\n%\n2 2\n1 1 1\n");
        assert_contains(
            &e,
            &[
                "K.mtx:3: size line: expected 3 integers \"rows columns entries\"",
                "found 2 tokens",
            ],
        );
    }

    #[test]
    fn size_line_not_integer() {
        let e = err("%%MatrixMarket matrix array real general\n2.5 2\n");
        assert_contains(
            &e,
            &["K.mtx:2: size line: number of rows \"2.5\" is not a non-negative integer"],
        );
        let e = err("%%MatrixMarket matrix array real general\n2 -2\n");
        assert_contains(
            &e,
            &["number of columns \"-2\" is not a non-negative integer"],
        );
        let e = err("%%MatrixMarket matrix coordinate real general\n2 2 many\n");
        assert_contains(
            &e,
            &["number of entries \"many\" is not a non-negative integer"],
        );
    }

    #[test]
    fn zero_rows() {
        let e = err("%%MatrixMarket matrix array real general\n0 0\n");
        assert_contains(&e, &["K.mtx:2: size line declares zero rows"]);
        let e = err("%%MatrixMarket matrix coordinate real general\n0 3 0\n");
        assert_contains(&e, &["K.mtx:2: size line declares zero rows"]);
    }

    #[test]
    fn zero_columns() {
        let e = err("%%MatrixMarket matrix array real general\n3 0\n");
        assert_contains(&e, &["K.mtx:2: size line declares zero columns"]);
    }

    #[test]
    fn too_large() {
        let e = err("%%MatrixMarket matrix array real general\n20001 20001\n");
        assert_contains(
            &e,
            &[
                "K.mtx:2: declared size 20001 x 20001",
                "too large for a dense condensed stiffness (limit 20000)",
            ],
        );
        let e = err("%%MatrixMarket matrix coordinate real general\n3 99999999999 0\n");
        assert_contains(
            &e,
            &["too large for a dense condensed stiffness (limit 20000)"],
        );
    }

    #[test]
    fn symmetric_must_be_square() {
        let e = err("%%MatrixMarket matrix array real symmetric\n2 3\n");
        assert_contains(&e, &["K.mtx:2: a symmetric matrix must be square", "2 x 3"]);
    }

    #[test]
    fn too_many_declared_entries() {
        let e = err("%%MatrixMarket matrix coordinate real symmetric\n2 2 4\n");
        assert_contains(
            &e,
            &["K.mtx:2: size line declares 4 entries", "holds at most 3"],
        );
    }

    // ----- entries -----

    #[test]
    fn entry_wrong_token_count_coordinate() {
        let e =
            err("%%MatrixMarket matrix coordinate real general\n% c\n%\n\n3 3 2\n1 1 1.0\n2 2\n");
        assert_eq!(
            e,
            "K.mtx:7: expected 3 numbers \"row column value\", found 2"
        );
        let e = err("%%MatrixMarket matrix coordinate real general\n3 3 1\n1 1 1.0 5\n");
        assert_eq!(
            e,
            "K.mtx:3: expected 3 numbers \"row column value\", found 4"
        );
    }

    #[test]
    fn entry_wrong_token_count_array() {
        let e = err("%%MatrixMarket matrix array real general\n2 2\n1 2\n3\n4\n");
        assert_contains(&e, &["K.mtx:3: expected 1 number \"value\"", "found 2"]);
    }

    #[test]
    fn value_not_a_number() {
        let e = err("%%MatrixMarket matrix array real general\n1 2\n1.0\nabc\n");
        assert_eq!(e, "K.mtx:4: value \"abc\" is not a number");
        let e = err("%%MatrixMarket matrix coordinate real general\n2 2 1\n1 2 1,5\n");
        assert_eq!(e, "K.mtx:3: value \"1,5\" is not a number");
    }

    #[test]
    fn index_not_an_integer() {
        let e = err("%%MatrixMarket matrix coordinate real general\n2 2 1\nx 1 1.0\n");
        assert_eq!(e, "K.mtx:3: row index \"x\" is not an integer");
        let e = err("%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1.0 1.0\n");
        assert_eq!(e, "K.mtx:3: column index \"1.0\" is not an integer");
    }

    #[test]
    fn index_out_of_range() {
        let header = "%%MatrixMarket matrix coordinate real general\n3 4 1\n";
        let e = err(&format!("{header}4 1 1.0\n"));
        assert_eq!(
            e,
            "K.mtx:3: row index 4 is out of range: the matrix has 3 rows (valid 1..=3)"
        );
        let e = err(&format!("{header}1 5 1.0\n"));
        assert_eq!(
            e,
            "K.mtx:3: column index 5 is out of range: the matrix has 4 columns (valid 1..=4)"
        );
        let e = err(&format!("{header}0 1 1.0\n"));
        assert_contains(&e, &["row index 0 is out of range", "valid 1..=3"]);
        let e = err(&format!("{header}1 -2 1.0\n"));
        assert_contains(&e, &["column index -2 is out of range"]);
        let e = err(&format!("{header}99999999999999999999999 1 1.0\n"));
        assert_contains(&e, &["row index 99999999999999999999999 is out of range"]);
    }

    #[test]
    fn truncated_array() {
        let e = err("%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n");
        assert_eq!(e, "K.mtx: truncated: expected 4 entries, found 3");
        let e = err("%%MatrixMarket matrix array real symmetric\n3 3\n1\n2\n3\n4\n5\n");
        assert_eq!(e, "K.mtx: truncated: expected 6 entries, found 5");
    }

    #[test]
    fn truncated_coordinate() {
        let e = err("%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 1\n2 2 1\n");
        assert_eq!(e, "K.mtx: truncated: expected 3 entries, found 2");
    }

    #[test]
    fn more_entries_than_declared_array() {
        let e = err("%%MatrixMarket matrix array real general\n1 2\n1\n2\n3\n");
        assert_contains(
            &e,
            &["K.mtx:5: more entries than declared", "1 x 2", "2 values"],
        );
        let e = err("%%MatrixMarket matrix array real symmetric\n2 2\n1\n2\n3\n4\n");
        assert_contains(&e, &["K.mtx:6: more entries than declared", "3 values"]);
    }

    #[test]
    fn more_entries_than_declared_coordinate() {
        let e = err("%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 1\n2 2 1\n");
        assert_eq!(
            e,
            "K.mtx:4: more entries than declared: the size line declares 1 entry"
        );
    }

    #[test]
    fn duplicate_entry_general() {
        let e = err("%%MatrixMarket matrix coordinate real general\n2 2 3\n1 2 1\n2 1 1\n1 2 5\n");
        assert_eq!(
            e,
            "K.mtx:5: duplicate entry (1, 2): already given at line 3"
        );
    }

    #[test]
    fn duplicate_entry_symmetric_mirror() {
        let e = err("%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n2 1 1\n1 2 1\n");
        assert_contains(
            &e,
            &[
                "K.mtx:4: duplicate entry (1, 2)",
                "mirror (2, 1) was already given at line 3",
            ],
        );
        let e = err("%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n2 2 1\n2 2 1\n");
        assert_eq!(
            e,
            "K.mtx:4: duplicate entry (2, 2): already given at line 3"
        );
    }

    #[test]
    fn integer_field_rejects_fractions() {
        let e = err("%%MatrixMarket matrix array integer general\n1 1\n1.5\n");
        assert_contains(
            &e,
            &["K.mtx:3: value \"1.5\" is not an integer", "\"integer\""],
        );
    }

    #[test]
    fn long_and_odd_tokens_stay_on_one_line() {
        let long = "x".repeat(500);
        let e = err(&format!(
            "%%MatrixMarket matrix array real general\n1 1\n{long}\n"
        ));
        assert!(e.len() < 150, "{e}");
        let e = err("%%MatrixMarket matrix array real general\n1 1\n\u{7}\u{1b}\n");
        assert_contains(&e, &["is not a number"]);
    }

    // ----- successful reads -----

    #[test]
    fn array_general_is_column_major() {
        let m = ok("%%MatrixMarket matrix array real general\n2 3\n1\n2\n3\n4\n5\n6\n");
        assert_eq!(
            m,
            DMatrix::from_row_slice(2, 3, &[1.0, 3.0, 5.0, 2.0, 4.0, 6.0])
        );
    }

    #[test]
    fn array_symmetric_lower_triangle() {
        // Lower triangle column by column: (1,1) (2,1) (3,1) (2,2) (3,2) (3,3).
        let m = ok("%%MatrixMarket matrix array real symmetric\n3 3\n1\n2\n3\n4\n5\n6\n");
        assert_eq!(
            m,
            DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 3.0, 2.0, 4.0, 5.0, 3.0, 5.0, 6.0])
        );
    }

    #[test]
    fn coordinate_general() {
        let m =
            ok("%%MatrixMarket matrix coordinate real general\n2 3 3\n1 1 1.5\n2 3 -2\n1 2 7e-1\n");
        assert_eq!(
            m,
            DMatrix::from_row_slice(2, 3, &[1.5, 0.7, 0.0, 0.0, 0.0, -2.0])
        );
    }

    #[test]
    fn coordinate_symmetric_lower_and_upper() {
        let m = ok("%%MatrixMarket matrix coordinate real symmetric\n\
                    3 3 4\n1 1 4\n2 1 -1\n2 3 -2\n3 3 5\n");
        assert_eq!(
            m,
            DMatrix::from_row_slice(3, 3, &[4.0, -1.0, 0.0, -1.0, 0.0, -2.0, 0.0, -2.0, 5.0])
        );
    }

    #[test]
    fn integer_field() {
        let m = ok("%%MatrixMarket matrix array integer symmetric\n2 2\n2\n-1\n3\n");
        assert_eq!(m, DMatrix::from_row_slice(2, 2, &[2.0, -1.0, -1.0, 3.0]));
        let m = ok("%%MatrixMarket matrix coordinate integer general\n1 2 2\n1 1 +4\n1 2 -7\n");
        assert_eq!(m, DMatrix::from_row_slice(1, 2, &[4.0, -7.0]));
    }

    #[test]
    fn comments_blank_lines_crlf_and_bom() {
        let text = "\u{feff}%%MatrixMarket matrix coordinate real general\r\n\
                    % written by a test\r\n\
                    \r\n\
                    %another comment\r\n\
                    \t 2 2 2 \r\n\
                    \r\n\
                    % between entries\r\n\
                       1   1   1.0\r\n\
                    \r\n\
                    2\t2\t2.0\r\n\
                    % trailing comment\r\n\
                    \r\n";
        let m = ok(text);
        assert_eq!(m, DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 2.0]));
    }

    #[test]
    fn non_finite_values_are_read() {
        let m = ok("%%MatrixMarket matrix array real general\n2 2\nNaN\ninf\n-INFINITY\nnan\n");
        assert!(m[(0, 0)].is_nan());
        assert_eq!(m[(1, 0)], f64::INFINITY);
        assert_eq!(m[(0, 1)], f64::NEG_INFINITY);
        assert!(m[(1, 1)].is_nan());
        let m = ok("%%MatrixMarket matrix array integer general\n1 1\nInf\n");
        assert_eq!(m[(0, 0)], f64::INFINITY);
    }

    #[test]
    fn fortran_exponents() {
        let m = ok("%%MatrixMarket matrix array double general\n1 2\n1.5D+02\n-2d-1\n");
        assert_eq!(m, DMatrix::from_row_slice(1, 2, &[150.0, -0.2]));
    }

    #[test]
    fn non_square_is_read() {
        let m = ok("%%MatrixMarket matrix coordinate real general\n2 3 0\n");
        assert_eq!(m, DMatrix::zeros(2, 3));
    }

    #[test]
    fn three_by_three_entry_by_entry() {
        let text = "%%MatrixMarket matrix coordinate real symmetric\n\
                    % condensed stiffness, 3 DOF\n\
                    3 3 5\n\
                    1 1  2.0e3\n\
                    2 1 -1.0e3\n\
                    2 2  2.5e3\n\
                    3 2 -1.5e3\n\
                    3 3  1.5e3\n";
        let m = ok(text);
        assert_eq!(m.shape(), (3, 3));
        let expected = [
            [2000.0, -1000.0, 0.0],
            [-1000.0, 2500.0, -1500.0],
            [0.0, -1500.0, 1500.0],
        ];
        for (i, row) in expected.iter().enumerate() {
            for (j, &value) in row.iter().enumerate() {
                assert_eq!(m[(i, j)], value, "entry ({}, {})", i + 1, j + 1);
            }
        }
        // The same matrix in array symmetric and array general form.
        let array_sym = "%%MatrixMarket matrix array real symmetric\n3 3\n\
                         2000\n-1000\n0\n2500\n-1500\n1500\n";
        assert_eq!(ok(array_sym), m);
        let array_gen = "%%MatrixMarket matrix array real general\n3 3\n\
                         2000\n-1000\n0\n-1000\n2500\n-1500\n0\n-1500\n1500\n";
        assert_eq!(ok(array_gen), m);
    }

    #[test]
    fn read_missing_path() {
        let dir = tempfile::tempdir().expect("temporary directory");
        let path = dir.path().join("K.mtx");
        let e = read(&path).expect_err("missing file").to_string();
        assert!(
            e.starts_with(&format!("{}: cannot read file: ", path.display())),
            "{e}"
        );
        assert!(!e.contains('\n'), "{e}");
    }

    #[test]
    fn read_file() {
        let dir = tempfile::tempdir().expect("temporary directory");
        let path = dir.path().join("K.mtx");
        std::fs::write(
            &path,
            "%%MatrixMarket matrix array real symmetric\n2 2\n3\n-1\n3\n",
        )
        .expect("write");
        let m = read(&path).expect("read");
        assert_eq!(m, DMatrix::from_row_slice(2, 2, &[3.0, -1.0, -1.0, 3.0]));

        std::fs::write(
            &path,
            "%%MatrixMarket matrix array real general\n1 1\n\x00\n",
        )
        .expect("write");
        let e = read(&path).expect_err("NUL value").to_string();
        assert!(
            e.starts_with(&format!("{}:3: value ", path.display())),
            "{e}"
        );
    }

    #[test]
    fn read_invalid_utf8() {
        let dir = tempfile::tempdir().expect("temporary directory");
        let path = dir.path().join("K.mtx");
        std::fs::write(
            &path,
            b"%%MatrixMarket matrix array real general\n1 1\n\xff\xfe\n".as_slice(),
        )
        .expect("write");
        let e = read(&path).expect_err("binary").to_string();
        assert_eq!(
            e,
            format!(
                "{}:3: not a text file: invalid UTF-8 at byte offset 45",
                path.display()
            )
        );
    }

    /// Every prefix and a set of corruptions of valid files must give a
    /// result, not a panic.
    #[test]
    fn never_panics_on_mangled_input() {
        let samples = [
            "%%MatrixMarket matrix coordinate real symmetric\n% c\n3 3 4\n1 1 4\n2 1 -1\n2 3 -2\n3 3 5\n",
            "%%MatrixMarket matrix array real symmetric\n3 3\n1\n2\n3\n4\n5\n6\n",
            "%%MatrixMarket matrix array integer general\n2 3\n1\n2\n3\n4\n5\n6\n",
        ];
        let replacements = [
            "", " ", "\n", "%", "0", "-1", "99999", "1e400", "nan", "x", "\u{e9}", "1 1", "\r",
        ];
        for sample in samples {
            let cuts: Vec<usize> = sample.char_indices().map(|(i, _)| i).collect();
            for &cut in &cuts {
                let _ = parse(&sample[..cut], ORIGIN);
                for r in replacements {
                    let mut mangled = String::with_capacity(sample.len() + r.len());
                    mangled.push_str(&sample[..cut]);
                    mangled.push_str(r);
                    let rest = sample.get(cut + 1..).unwrap_or("");
                    mangled.push_str(rest);
                    if let Err(e) = parse(&mangled, ORIGIN) {
                        assert!(!e.to_string().contains('\n'), "{e}");
                    }
                }
            }
        }
    }
}
