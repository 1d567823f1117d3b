//! Tests of `mtx.rs`.

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
    let e = err("%%MatrixMarket matrix coordinate real general\n% c\n%\n\n3 3 2\n1 1 1.0\n2 2\n");
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
    let m = ok("%%MatrixMarket matrix coordinate real general\n2 3 3\n1 1 1.5\n2 3 -2\n1 2 7e-1\n");
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
