//! The problem file: TOML naming the friction coefficient and either a condensed stiffness or a
//! meshed body with its material and boundary groups.
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
//! ```toml
//! mu = 0.8
//! [mesh]
//! gmsh = "plug.msh"              # MSH 4.1 or 2.2, ASCII or binary; or a Gmsh script,
//! # gmsh = "plug.geo"            # meshed by Gmsh with the numbers of [mesh.parameters]
//! # [mesh.parameters]            # (its DefineConstant values; see `geo`; `size_factor = 2`
//! #                              # in [mesh] doubles every mesh size); or a built-in body:
//! # half_angle = 10.0
//! # [mesh.generate]
//! # kind = "plug2d"              # plug2d | vgroove3d | frustum3d
//! # bottom_width = 1.0 ...
//! [material]
//! young = 210e9
//! poisson = 0.3
//! plane = "strain"               # 2D only: strain | stress
//! [[contact]]
//! group = "contact"              # optional: normal = [nx, ny(, nz)], the body's inward normal
//! [[clamp]]
//! group = "top"
//! [[symmetry]]                   # rollers: zero displacement along the group's normal
//! group = "axis"
//! ```
//!
//! Unknown keys are rejected by name. Every error is one line that starts with the file's name.

use std::fmt;
use std::fs;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use nalgebra::DMatrix;
use serde::Deserialize;
use wedged::fe::generate::{Frustum, Plug2d, VGroove};
use wedged::fe::{BoundarySpec, ContactSpec, Material, Mesh, Model, Plane};
use wedged::{Problem, ProblemError};

use crate::input::{geo, msh, mtx};
use crate::one_line;

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
    expecting = "a problem with `mu` and either [stiffness] or [mesh]"
)]
struct RawProblem {
    dim: Option<usize>,
    mu: Option<f64>,
    stiffness: Option<RawStiffness>,
    mesh: Option<RawMesh>,
    material: Option<RawMaterial>,
    #[serde(default)]
    contact: Vec<RawGroup>,
    #[serde(default)]
    clamp: Vec<RawGroup>,
    #[serde(default)]
    symmetry: Vec<RawGroup>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [mesh] table")]
struct RawMesh {
    gmsh: Option<PathBuf>,
    generate: Option<Generate>,
    /// A Gmsh script's parameters (`gmsh = "body.geo"`).
    parameters: Option<std::collections::BTreeMap<String, f64>>,
    /// A Gmsh script's mesh sizes times this (`-clscale`).
    size_factor: Option<f64>,
}

/// A built-in body. Widths, heights and lengths are in the units of the material's modulus.
#[derive(Debug, Deserialize)]
#[serde(
    tag = "kind",
    deny_unknown_fields,
    expecting = "a [mesh.generate] table with `kind`"
)]
enum Generate {
    #[serde(rename = "plug2d")]
    Plug2d {
        bottom_width: f64,
        top_width: f64,
        height: f64,
        nx: usize,
        ny: usize,
        #[serde(default)]
        element: Option<String>,
    },
    #[serde(rename = "vgroove3d")]
    VGroove {
        bottom_width: f64,
        top_width: f64,
        height: f64,
        length: f64,
        nx: usize,
        ny: usize,
        nz: usize,
        #[serde(default)]
        element: Option<String>,
    },
    #[serde(rename = "frustum3d")]
    Frustum {
        bottom_width: f64,
        top_width: f64,
        height: f64,
        n: usize,
        nz: usize,
        #[serde(default)]
        element: Option<String>,
    },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [material] table")]
struct RawMaterial {
    young: f64,
    poisson: f64,
    plane: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a table with `group` and optionally `normal`"
)]
struct RawGroup {
    group: String,
    normal: Option<Vec<f64>>,
}

/// A loaded problem: the WP, and for a meshed body the model that produced it.
pub struct Loaded {
    /// The condensed problem.
    pub problem: Problem,
    /// The finite-element model, for a `[mesh]` problem.
    pub model: Option<Model>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [stiffness] table")]
struct RawStiffness {
    matrix_market: Option<PathBuf>,
    rows: Option<Vec<Vec<f64>>>,
    /// A floating body's rigid modes: a Matrix Market file (`dim*m` x `k`) or rows.
    rigid_modes: Option<RawMatrix>,
}

/// A matrix given by a Matrix Market file (relative to the problem file) or inline rows.
#[derive(Debug, Deserialize)]
#[serde(untagged, expecting = "a Matrix Market file name or rows of numbers")]
enum RawMatrix {
    File(PathBuf),
    Rows(Vec<Vec<f64>>),
}

/// Reads and validates the problem in the TOML file at `path`. With `mu_on_command_line` the
/// file's `mu` is optional and a placeholder 1.0 stands for it (the caller replaces it).
pub fn load(path: &Path, mu_on_command_line: bool) -> Result<Loaded, LoadError> {
    parse_str(&read_text(path)?, path, mu_on_command_line)
}

/// [`load`] of the text of a problem file, already in memory; `path` is where the file is (or
/// would be): it names the file in messages and the files it refers to are relative to its
/// directory (and read from there).
pub fn parse_str(text: &str, path: &Path, mu_on_command_line: bool) -> Result<Loaded, LoadError> {
    let (raw, err) = parse_raw(text, path)?;
    // With --mu on the command line the file's `mu` is not needed (and not read): the caller
    // replaces this placeholder with the command-line value, which the library validates.
    load_raw(
        path,
        raw,
        err,
        if mu_on_command_line { Some(1.0) } else { None },
    )
}

/// Reads and validates the problem in the TOML file at `path` for a computation of `mu*`, which
/// needs no friction coefficient: the file's `mu`, when given (and then validated), else 1.0.
/// Also returns whether the file gave `mu`.
pub fn load_for_critical(path: &Path) -> Result<(Loaded, bool), LoadError> {
    parse_str_for_critical(&read_text(path)?, path)
}

/// [`load_for_critical`] of text in memory, as [`parse_str`].
pub fn parse_str_for_critical(text: &str, path: &Path) -> Result<(Loaded, bool), LoadError> {
    let (raw, err) = parse_raw(text, path)?;
    let given = raw.mu.is_some();
    let loaded = load_raw(path, raw, err, if given { None } else { Some(1.0) })?;
    Ok((loaded, given))
}

/// The problem of a parsed file, with the friction coefficient to use instead of the file's
/// (`None`: the file's, which must then be there).
fn load_raw(
    path: &Path,
    raw: RawProblem,
    err: Err,
    mu_instead: Option<f64>,
) -> Result<Loaded, LoadError> {
    let mu = match mu_instead {
        Some(mu) => mu,
        None => raw.mu.ok_or_else(|| {
            err("missing `mu` (the friction coefficient, > 0; or pass --mu)".into())
        })?,
    };
    if raw.mesh.is_some() {
        if let Some(dim) = raw.dim {
            if dim != 2 && dim != 3 {
                return Err(err(format!("dimension must be 2 or 3, got {dim}")));
            }
        }
        let model = load_model_from(path, raw)?;
        let problem = model_problem(&model, mu).map_err(err)?;
        return Ok(Loaded {
            problem,
            model: Some(model),
        });
    }
    let problem = load_stiffness(path, raw, mu)?;
    Ok(Loaded {
        problem,
        model: None,
    })
}

/// Reads a `[mesh]` problem file and condenses it; `mu` is not needed.
pub fn load_model(path: &Path) -> Result<Model, LoadError> {
    model_from_str(&read_text(path)?, path)
}

/// [`load_model`] of text in memory, as [`parse_str`].
pub fn model_from_str(text: &str, path: &Path) -> Result<Model, LoadError> {
    let (raw, err) = parse_raw(text, path)?;
    if raw.mesh.is_none() {
        return Err(err(
            "has no [mesh] table: only a meshed body can be condensed".to_string(),
        ));
    }
    let model = load_model_from(path, raw)?;
    // The condensed stiffness must be positive definite for the WP: say so now.
    model_problem(&model, 1.0).map_err(err)?;
    Ok(model)
}

type Err = Box<dyn Fn(String) -> LoadError>;

/// The errors about the problem file at `path`: its name, then the message.
fn error_for(path: &Path) -> Err {
    let name = path.display().to_string();
    Box::new(move |m: String| LoadError(format!("{name}: {m}")))
}

/// The text of the problem file at `path` (an error naming it when it cannot be read).
pub fn read_text(path: &Path) -> Result<String, LoadError> {
    fs::read_to_string(path)
        .map_err(|e| error_for(path)(format!("cannot read the problem file: {e}")))
}

fn parse_raw(text: &str, path: &Path) -> Result<(RawProblem, Err), LoadError> {
    let err = error_for(path);
    let raw: RawProblem = toml::from_str(text).map_err(|e| err(toml_message(text, &e)))?;
    Ok((raw, err))
}

/// The WP of a model's condensed stiffness, or why it is not one, in the terms of the model.
fn model_problem(model: &Model, mu: f64) -> Result<Problem, String> {
    model.problem(mu).map_err(|e| match e {
        ProblemError::NotPositiveDefinite { node, .. } => format!(
            "the condensed stiffness is singular at contact node {node}: the body can move \
             rigidly in a way that is not a rigid motion of the whole mesh; check the mesh for \
             loose elements or a mechanism"
        ),
        ProblemError::NotDefiniteOffRigid { node, modes, .. } => format!(
            "the body floats ({modes} rigid motions are free) and its condensed stiffness is \
             singular beyond them at contact node {node}: check the mesh for loose elements or \
             a mechanism"
        ),
        e @ ProblemError::InvalidMu(_) => e.to_string(),
        e => format!("the condensed stiffness: {e}"),
    })
}

fn load_stiffness(path: &Path, raw: RawProblem, mu: f64) -> Result<Problem, LoadError> {
    let name = path.display();
    let err = |m: String| LoadError(format!("{name}: {m}"));
    for (present, key) in [
        (raw.material.is_some(), "[material]"),
        (!raw.contact.is_empty(), "[[contact]]"),
        (!raw.clamp.is_empty(), "[[clamp]]"),
        (!raw.symmetry.is_empty(), "[[symmetry]]"),
    ] {
        if present {
            return Err(err(format!(
                "{key} needs a [mesh]; with [stiffness] it has no use"
            )));
        }
    }
    let dim = raw
        .dim
        .ok_or_else(|| err("missing `dim` (the space dimension, 2 or 3)".into()))?;
    let stiffness = raw.stiffness.ok_or_else(|| {
        err("missing the [stiffness] table (with `matrix_market = \"K.mtx\"` or `rows = [[...], ...]`), or a [mesh]"
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

    let rigid = match stiffness.rigid_modes {
        None => None,
        Some(RawMatrix::Rows(rows)) => Some((
            matrix_from_rows(&rows)
                .map_err(|m| err(m.replace("[stiffness] rows", "[stiffness] rigid_modes rows")))?,
            format!("{name} ([stiffness] rigid_modes)"),
        )),
        Some(RawMatrix::File(relative)) => {
            let base = path.parent().unwrap_or(Path::new(""));
            let r_path = base.join(relative);
            let r = mtx::read(&r_path).map_err(|e| LoadError(one_line(&e.to_string())))?;
            Some((
                r,
                format!("{} (the rigid modes of {name})", r_path.display()),
            ))
        }
    };
    let Some((rigid, rigid_source)) = rigid else {
        return Problem::new(dim, k, mu).map_err(|e| match e {
            // Errors in K belong to the file that holds it; the others to the problem file.
            ProblemError::InvalidDim(_) | ProblemError::InvalidMu(_) => err(e.to_string()),
            ProblemError::NotPositiveDefinite { .. } => LoadError(format!(
                "{matrix_source}: {e} (a floating body: declare its rigid modes with \
                 `rigid_modes = \"R.mtx\"` in [stiffness], a dim*m x k matrix in the same local \
                 frames, K R = 0)"
            )),
            _ => LoadError(format!("{matrix_source}: {e}")),
        });
    };
    Problem::floating(dim, k, rigid, mu).map_err(|e| match e {
        ProblemError::InvalidDim(_) | ProblemError::InvalidMu(_) => err(e.to_string()),
        ProblemError::RigidModesSize { .. }
        | ProblemError::RigidModesCount { .. }
        | ProblemError::RigidModesNonFinite { .. }
        | ProblemError::RigidModesDependent { .. }
        | ProblemError::NotRigid { .. } => LoadError(format!("{rigid_source}: {e}")),
        _ => LoadError(format!("{matrix_source}: {e}")),
    })
}

fn load_model_from(path: &Path, raw: RawProblem) -> Result<Model, LoadError> {
    let name = path.display();
    let err = |m: String| LoadError(format!("{name}: {m}"));
    if raw.stiffness.is_some() {
        return Err(err(
            "has both [stiffness] and [mesh]; give exactly one".to_string()
        ));
    }
    let raw_mesh = raw.mesh.expect("checked by the caller");
    let script = raw_mesh
        .gmsh
        .as_ref()
        .is_some_and(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("geo")));
    if raw_mesh.size_factor.is_some() && !script {
        return Err(err(
            "[mesh]: size_factor is for a Gmsh script (`gmsh = \"body.geo\"`); a built-in \
             body's mesh is set by its division counts"
                .into(),
        ));
    }
    if raw_mesh.parameters.is_some() && !script {
        return Err(err(
            "[mesh.parameters] are for a Gmsh script (`gmsh = \"body.geo\"`), which Gmsh \
             meshes with them"
                .into(),
        ));
    }
    let mesh = match (raw_mesh.gmsh, raw_mesh.generate) {
        (Some(_), Some(_)) => {
            return Err(err(
                "[mesh] has both `gmsh` and [mesh.generate]; give exactly one".into(),
            ))
        }
        (None, None) => {
            return Err(err(
                "[mesh] needs `gmsh = \"body.msh\"` or a [mesh.generate] table".into(),
            ))
        }
        (Some(relative), None) => {
            // Relative to the problem file's directory.
            let file = path.parent().unwrap_or(Path::new("")).join(relative);
            if script {
                let parameters = raw_mesh.parameters.unwrap_or_default();
                geo::mesh(&file, &parameters, raw_mesh.size_factor)
                    .map_err(|m| err(one_line(&m)))?
            } else {
                msh::read(&file).map_err(|e| LoadError(one_line(&e.to_string())))?
            }
        }
        (None, Some(generate)) => {
            generate_mesh(generate).map_err(|m| err(format!("[mesh.generate]: {m}")))?
        }
    };
    if let Some(dim) = raw.dim {
        if dim != mesh.dim() {
            return Err(err(format!(
                "`dim = {dim}`, but the mesh is {}D",
                mesh.dim()
            )));
        }
    }
    let material = raw
        .material
        .ok_or_else(|| err("missing the [material] table (`young`, `poisson`)".into()))?;
    let plane = match material.plane.as_deref() {
        None | Some("strain") => Plane::Strain,
        Some("stress") => Plane::Stress,
        Some(other) => {
            return Err(err(format!(
                "[material] plane = \"{other}\": expected \"strain\" or \"stress\""
            )))
        }
    };
    let material = Material::new(material.young, material.poisson, plane)
        .map_err(|e| err(format!("[material]: {e}")))?;
    let dim = mesh.dim();
    let normal = |g: &RawGroup, table: &str| -> Result<Option<[f64; 3]>, LoadError> {
        match &g.normal {
            None => Ok(None),
            Some(v) if v.len() == dim => {
                let mut n = [0.0; 3];
                n[..dim].copy_from_slice(v);
                Ok(Some(n))
            }
            Some(v) => Err(err(format!(
                "[[{table}]] group '{}': `normal` has {} components, the mesh is {dim}D",
                g.group,
                v.len()
            ))),
        }
    };
    for g in &raw.clamp {
        if g.normal.is_some() {
            return Err(err(format!(
                "[[clamp]] group '{}': a clamp has no `normal` (it fixes every direction)",
                g.group
            )));
        }
    }
    let spec = BoundarySpec {
        contact: raw
            .contact
            .iter()
            .map(|g| {
                Ok(ContactSpec {
                    group: g.group.clone(),
                    normal: normal(g, "contact")?,
                })
            })
            .collect::<Result<_, LoadError>>()?,
        clamp: raw.clamp.iter().map(|g| g.group.clone()).collect(),
        symmetry: raw
            .symmetry
            .iter()
            .map(|g| Ok((g.group.clone(), normal(g, "symmetry")?)))
            .collect::<Result<_, LoadError>>()?,
    };
    // Large meshes take seconds to condense: say so to a person at a terminal.
    let live = std::io::stderr().is_terminal() && mesh.node_count() * dim > 20_000;
    if live {
        eprint!(
            "\r  condensing {} nodes ({} elements) onto the contact nodes ...",
            mesh.node_count(),
            mesh.elements().len()
        );
    }
    let model = Model::build(mesh, material, &spec).map_err(|e| err(e.to_string()));
    if live {
        eprintln!(" done");
    }
    model
}

fn generate_mesh(generate: Generate) -> Result<Mesh, String> {
    let simplices = |element: Option<String>, brick: &str, simplex: &str| match element.as_deref() {
        None => Ok(false),
        Some(e) if e == brick => Ok(false),
        Some(e) if e == simplex => Ok(true),
        Some(e) => Err(format!(
            "element = \"{e}\": expected \"{brick}\" or \"{simplex}\""
        )),
    };
    let mesh = match generate {
        Generate::Plug2d {
            bottom_width,
            top_width,
            height,
            nx,
            ny,
            element,
        } => Plug2d {
            bottom_width,
            top_width,
            height,
            nx,
            ny,
            simplices: simplices(element, "quad", "tri")?,
        }
        .mesh(),
        Generate::VGroove {
            bottom_width,
            top_width,
            height,
            length,
            nx,
            ny,
            nz,
            element,
        } => VGroove {
            bottom_width,
            top_width,
            height,
            length,
            nx,
            ny,
            nz,
            simplices: simplices(element, "hex", "tet")?,
        }
        .mesh(),
        Generate::Frustum {
            bottom_width,
            top_width,
            height,
            n,
            nz,
            element,
        } => Frustum {
            bottom_width,
            top_width,
            height,
            n,
            nz,
            simplices: simplices(element, "hex", "tet")?,
        }
        .mesh(),
    };
    mesh.map_err(|e| e.to_string())
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
    let mut message = one_line(e.message());
    if let Some(suggestion) = suggestion(&message) {
        message.push_str(&format!(" (did you mean `{suggestion}`?)"));
    }
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

/// For serde's "unknown field `x`, expected one of `a`, `b`" (or "expected `a` or `b`"), the
/// expected name closest to `x`, if it is within a third of its length in edits.
fn suggestion(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    let (unknown, expected) = rest.split_once('`')?;
    let names: Vec<&str> = expected.split('`').skip(1).step_by(2).collect();
    let (best, distance) = names
        .iter()
        .map(|n| (*n, edit_distance(unknown, n)))
        .min_by_key(|&(_, d)| d)?;
    (distance > 0 && distance * 3 <= unknown.len().max(3)).then(|| best.to_string())
}

/// Levenshtein distance.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut previous = row[0];
        row[0] = i + 1;
        for j in 0..b.len() {
            let current = row[j + 1];
            row[j + 1] = (previous + usize::from(ca != b[j]))
                .min(row[j] + 1)
                .min(current + 1);
            previous = current;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn misspelt_keys_get_a_suggestion() {
        assert_eq!(
            suggestion("unknown field `poison`, expected one of `young`, `poisson`, `plane`"),
            Some("poisson".to_string())
        );
        assert_eq!(
            suggestion("unknown field `matrix_maket`, expected `matrix_market` or `rows`"),
            Some("matrix_market".to_string())
        );
        assert_eq!(
            suggestion("unknown field `tolerance`, expected `matrix_market` or `rows`"),
            None
        );
        assert_eq!(suggestion("invalid key"), None);
    }

    fn load_text(text: &str) -> Result<Problem, LoadError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("p.toml");
        fs::write(&path, text).unwrap();
        load(&path, false).map(|l| l.problem)
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
