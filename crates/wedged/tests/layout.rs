//! The architecture invariants of ARCHITECTURE.md that a script over the sources can check, for
//! both crates (`wedged` and `wedged-cli`):
//!
//! - **No import circle between files.** A file depends on another when it names a path into it
//!   (`crate::a::b`, `super::x`, `wedged_cli::m` in a `use` or inline). A file's use of an
//!   ancestor module's file (its folder's `mod.rs`, the `foo.rs` of a `foo/` folder, the crate
//!   root) is containment, not an edge; every other reference is one, siblings included.
//! - **The top-level modules form layers**: the graph between them (each folder one node) has
//!   no circle either.
//! - **Only `conic` knows a solver**: no file outside `src/conic/` names `clarabel` or the
//!   simplex method.
//! - **The library does no file I/O**: no `std::fs` and no `File::` in `crates/wedged/src`.
//! - **No source file over 800 lines.**
//!
//! Comments and `#[cfg(test)]` modules are left out: tests may reach anywhere.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

const MAX_LINES: usize = 800;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a file relative to `src` (`rays/mod.rs` -> `["rays"]`).
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// The code of a file without comments and without its `#[cfg(test)]` modules.
fn code_of(text: &str) -> String {
    let mut out = String::new();
    let mut lines = text.lines().peekable();
    while let Some(line) = lines.next() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("#[cfg(test)]") {
            // Skip the item that follows: to the end of its braces (or its `;`).
            let mut depth = 0i64;
            let mut opened = false;
            for l in lines.by_ref() {
                let code = l.split("//").next().unwrap_or("");
                depth += code.matches('{').count() as i64 - code.matches('}').count() as i64;
                opened |= code.contains('{');
                if (opened && depth <= 0) || (!opened && code.trim_end().ends_with(';')) {
                    break;
                }
            }
            continue;
        }
        let code = match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        };
        out.push_str(code);
        out.push('\n');
    }
    out
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// Expands the use-tree starting at `s` (after a `crate::`-like prefix) into its paths.
fn paths_at(s: &[char], mut i: usize, prefix: Vec<String>, out: &mut Vec<Vec<String>>) -> usize {
    let mut path = prefix;
    loop {
        let start = i;
        while i < s.len() && is_ident(s[i]) {
            i += 1;
        }
        if i > start {
            path.push(s[start..i].iter().collect());
        }
        if i + 1 < s.len() && s[i] == ':' && s[i + 1] == ':' {
            i += 2;
            if i < s.len() && s[i] == '{' {
                i += 1;
                loop {
                    while i < s.len() && (s[i].is_whitespace() || s[i] == ',') {
                        i += 1;
                    }
                    if i >= s.len() || s[i] == '}' {
                        return i + 1;
                    }
                    i = paths_at(s, i, path.clone(), out);
                    // Skip an `as name` and anything up to the next item.
                    while i < s.len() && s[i] != ',' && s[i] != '}' {
                        i += 1;
                    }
                }
            }
            continue;
        }
        out.push(path);
        return i;
    }
}

struct Crate {
    /// File (relative to the repository) -> its module path.
    modules: BTreeMap<PathBuf, Vec<String>>,
    /// File -> the files it depends on.
    edges: BTreeMap<PathBuf, BTreeSet<PathBuf>>,
}

fn read_crate(src: &Path, lib_name: &str) -> Crate {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    files.sort();
    let modules: BTreeMap<PathBuf, Vec<String>> = files
        .iter()
        .map(|f| (f.clone(), module_of(f.strip_prefix(src).unwrap())))
        .collect();
    let by_module: BTreeMap<&Vec<String>, &PathBuf> = modules.iter().map(|(f, m)| (m, f)).collect();
    let mut edges = BTreeMap::new();
    for (file, module) in &modules {
        let text = fs::read_to_string(file).unwrap();
        let code: Vec<char> = code_of(&text).chars().collect();
        let is_mod_rs = file.file_name().is_some_and(|n| n == "mod.rs");
        let mut targets = BTreeSet::new();
        let mut i = 0;
        while i < code.len() {
            if i > 0 && (is_ident(code[i - 1]) || code[i - 1] == ':') {
                i += 1;
                continue;
            }
            let rest: String = code[i..code.len().min(i + 64)].iter().collect();
            let base: Option<(usize, Vec<String>)> = if rest.starts_with("crate::") {
                Some((7, vec![]))
            } else if rest.starts_with(&format!("{lib_name}::")) {
                Some((lib_name.len() + 2, vec![]))
            } else if rest.starts_with("super::") {
                // `super` of `a/b.rs` is `a`; of `a/mod.rs` (module `a`) it is the root.
                let mut parent = module.clone();
                parent.pop();
                Some((7, parent))
            } else if rest.starts_with("self::") && is_mod_rs {
                Some((6, module.clone()))
            } else {
                None
            };
            let Some((skip, prefix)) = base else {
                i += 1;
                continue;
            };
            let mut paths = Vec::new();
            i = paths_at(&code, i + skip, prefix, &mut paths);
            for p in paths {
                // The longest prefix of the path that is a module with a file.
                let target = (0..=p.len())
                    .rev()
                    .find_map(|k| by_module.get(&p[..k].to_vec()).copied());
                if let Some(t) = target {
                    let t_module = &modules[t];
                    // An ancestor module's file (`mod.rs`, `foo.rs` of `foo/`, the crate root)
                    // is containment, not an edge.
                    let ancestor = module.starts_with(t_module) && module.len() > t_module.len();
                    if t != file && !ancestor {
                        targets.insert(t.clone());
                    }
                }
            }
        }
        edges.insert(file.clone(), targets);
    }
    Crate { modules, edges }
}

/// A circle of the graph, if it has one (depth-first search).
fn find_circle<N: Ord + Clone>(edges: &BTreeMap<N, BTreeSet<N>>) -> Option<Vec<N>> {
    fn visit<N: Ord + Clone>(
        n: &N,
        edges: &BTreeMap<N, BTreeSet<N>>,
        state: &mut BTreeMap<N, u8>,
        stack: &mut Vec<N>,
    ) -> Option<Vec<N>> {
        state.insert(n.clone(), 1);
        stack.push(n.clone());
        for t in edges.get(n).into_iter().flatten() {
            match state.get(t).copied().unwrap_or(0) {
                1 => {
                    let at = stack.iter().position(|x| x == t).unwrap();
                    let mut circle = stack[at..].to_vec();
                    circle.push(t.clone());
                    return Some(circle);
                }
                0 => {
                    if let Some(c) = visit(t, edges, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in edges.keys() {
        if state.get(n).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, edges, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

fn crates_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn both() -> Vec<(Crate, PathBuf)> {
    let root = crates_dir();
    vec![
        (
            read_crate(&root.join("wedged/src"), "wedged"),
            root.join("wedged/src"),
        ),
        (
            read_crate(&root.join("wedged-cli/src"), "wedged_cli"),
            root.join("wedged-cli/src"),
        ),
    ]
}

#[test]
fn no_import_circle_between_files() {
    for (c, src) in both() {
        assert!(
            c.edges.values().any(|t| !t.is_empty()),
            "no dependency found in {}: the scan is broken",
            src.display()
        );
        if let Some(circle) = find_circle(&c.edges) {
            let names: Vec<String> = circle
                .iter()
                .map(|f| f.strip_prefix(&src).unwrap().display().to_string())
                .collect();
            panic!("import circle: {}", names.join(" -> "));
        }
    }
}

#[test]
fn top_level_modules_form_layers() {
    for (c, src) in both() {
        let top = |f: &PathBuf| c.modules[f].first().cloned().unwrap_or_default();
        let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (from, targets) in &c.edges {
            for to in targets {
                let (a, b) = (top(from), top(to));
                // The crate root (lib.rs, main.rs) only declares and re-exports.
                if a != b && !a.is_empty() && !b.is_empty() {
                    edges.entry(a).or_default().insert(b);
                }
            }
        }
        if let Some(circle) = find_circle(&edges) {
            panic!(
                "the top-level modules of {} depend on each other in a circle: {}",
                src.display(),
                circle.join(" -> ")
            );
        }
    }
}

#[test]
fn the_scan_sees_a_circle() {
    // The checker itself: two sibling files naming each other are a circle; a child naming
    // its folder's mod.rs is not.
    let dir = std::env::temp_dir().join(format!("wedged-layout-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(dir.join("a")).unwrap();
    fs::write(dir.join("lib.rs"), "mod a;\n").unwrap();
    fs::write(dir.join("a/mod.rs"), "mod b;\nmod c;\npub struct T;\n").unwrap();
    fs::write(dir.join("a/b.rs"), "use super::T;\nuse super::c::{X, Y};\n").unwrap();
    fs::write(dir.join("a/c.rs"), "fn f() { crate::a::b::g(); }\n").unwrap();
    let c = read_crate(&dir, "none");
    let circle = find_circle(&c.edges).expect("b and c name each other");
    assert_eq!(circle.len(), 3, "{circle:?}");
    fs::write(dir.join("a/c.rs"), "// crate::a::b::g()\nuse super::T;\n").unwrap();
    let c = read_crate(&dir, "none");
    assert!(find_circle(&c.edges).is_none());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn only_conic_knows_a_solver() {
    let src = crates_dir().join("wedged/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    for f in files {
        let rel = f.strip_prefix(&src).unwrap().to_path_buf();
        let code = code_of(&fs::read_to_string(&f).unwrap());
        let in_conic = rel.starts_with("conic");
        assert!(
            in_conic || !code.contains("clarabel::"),
            "{} names clarabel: only src/conic/ may",
            rel.display()
        );
        assert!(
            in_conic || !code.contains("conic::simplex"),
            "{} calls the simplex method: only src/conic/ may",
            rel.display()
        );
    }
}

#[test]
fn the_library_does_no_file_io() {
    let src = crates_dir().join("wedged/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    for f in files {
        let code = code_of(&fs::read_to_string(&f).unwrap());
        for word in ["std::fs", "File::", "OpenOptions"] {
            assert!(
                !code.contains(word),
                "{} uses {word}: the library does no file I/O",
                f.display()
            );
        }
    }
}

#[test]
fn no_source_file_over_800_lines() {
    let mut long = Vec::new();
    for dir in ["wedged/src", "wedged-cli/src", "wedged-py/src"] {
        let mut files = Vec::new();
        rust_files(&crates_dir().join(dir), &mut files);
        for f in files {
            let n = fs::read_to_string(&f).unwrap().lines().count();
            if n > MAX_LINES {
                long.push(format!("{} ({n} lines)", f.display()));
            }
        }
    }
    assert!(
        long.is_empty(),
        "over {MAX_LINES} lines: {}",
        long.join(", ")
    );
}
