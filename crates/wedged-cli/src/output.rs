//! The JSON result, a fixed format that scripts can rely on, and its atomic writing.
//!
//! ```text
//! { "dim": 2, "mu": 1.0, "nodes": 4, "method": "pruned-dd", "outcome": "wedged" | "not-wedged",
//!   "rays":  [ { "u": [..], "r": [..], "status": ["separated" | "stick" | "slip+" | "slip-" | "grazing", ..] } ],
//!   "cones": [ { "rays": [0-based ray indices], "status": ["contact" | "separated" | "grazing", ..] } ],
//!   "info":  { every field of wedged::Info },
//!   "version": "0.1.0" }
//! ```
//!
//! Vectors are in the local node frames, normal first, with rays normalised to `sum r_n = 1`.
//! The top level and the lists are laid out one item per line; each item is on one line.

use std::fmt;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde_json::ser::Formatter;
use tempfile::NamedTempFile;
use wedged::fe::Model;
use wedged::{Enumeration, Info, Outcome, Problem, Settings};

/// The whole JSON document.
#[derive(Debug, Serialize)]
pub struct Report<'a> {
    pub dim: usize,
    pub mu: f64,
    pub nodes: usize,
    pub method: &'static str,
    pub outcome: &'static str,
    /// False when the run stopped at a limit or on Ctrl-C.
    pub complete: bool,
    /// Why an incomplete run stopped; `null` for a complete one.
    pub stopped: Option<String>,
    pub rays: Vec<RayJson<'a>>,
    pub cones: Vec<ConeJson<'a>>,
    pub info: InfoJson<'a>,
    /// For a meshed body: the model behind the condensed `K`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelJson>,
    pub version: &'static str,
}

/// The finite-element model of a `[mesh]` problem.
#[derive(Debug, Serialize)]
pub struct ModelJson {
    pub mesh_nodes: usize,
    pub elements: usize,
    pub dofs: usize,
    pub eliminated: usize,
    pub clamped_nodes: usize,
    pub roller_nodes: usize,
    /// Nodes of contact groups that are clamped, and so not contact nodes.
    pub clamped_contact_nodes: usize,
    /// One per WP node, in WP order.
    pub contact: Vec<ContactJson>,
    pub seconds_condense: f64,
}

/// A WP node: its mesh node (1-based, as in Gmsh) and local frame.
#[derive(Debug, Serialize)]
pub struct ContactJson {
    pub mesh_node: usize,
    pub x: Vec<f64>,
    pub n: Vec<f64>,
    pub t1: Vec<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t2: Option<Vec<f64>>,
}

impl ModelJson {
    pub fn new(model: &Model) -> ModelJson {
        let mesh = model.mesh();
        let dim = mesh.dim();
        let b = model.boundary();
        let stats = model.stats();
        ModelJson {
            mesh_nodes: mesh.node_count(),
            elements: mesh.elements().len(),
            dofs: stats.dofs,
            eliminated: stats.eliminated,
            clamped_nodes: b.clamped.len(),
            roller_nodes: b.rollers.len(),
            clamped_contact_nodes: b.clamped_contact,
            contact: b
                .contact_nodes
                .iter()
                .zip(&b.frames)
                .map(|(&a, f)| ContactJson {
                    mesh_node: a + 1,
                    x: mesh.coords()[a][..dim].to_vec(),
                    n: f.n[..dim].to_vec(),
                    t1: f.t1[..dim].to_vec(),
                    t2: (dim == 3).then(|| f.t2.to_vec()),
                })
                .collect(),
            seconds_condense: stats.seconds_assembly + stats.seconds_factor + stats.seconds_schur,
        }
    }
}

/// One complementary extreme ray.
#[derive(Debug, Serialize)]
pub struct RayJson<'a> {
    pub u: &'a [f64],
    pub r: &'a [f64],
    pub status: Vec<&'static str>,
}

/// One maximal cross-complementary set of rays, with its contact pattern.
#[derive(Debug, Serialize)]
pub struct ConeJson<'a> {
    pub rays: &'a [usize],
    pub status: Vec<&'static str>,
}

/// Every field of [`wedged::Info`], under the same names.
#[derive(Debug, Serialize)]
pub struct InfoJson<'a> {
    pub rays_after_node: &'a [usize],
    pub node_order: &'a [usize],
    pub pairs_tested: u64,
    pub pairs_rejected_pattern: u64,
    pub pairs_rejected_combinatorial: u64,
    pub adjacency_tests: u64,
    pub rays_created: u64,
    pub peak_rays: usize,
    pub peak_bytes: u64,
    pub candidates: u64,
    pub extreme_rays_total: usize,
    pub seconds: f64,
}

impl<'a> From<&'a Info> for InfoJson<'a> {
    fn from(info: &'a Info) -> Self {
        // No `..`: a new field of Info must be added here too.
        let Info {
            rays_after_node,
            node_order,
            pairs_tested,
            pairs_rejected_pattern,
            pairs_rejected_combinatorial,
            adjacency_tests,
            rays_created,
            peak_rays,
            peak_bytes,
            candidates,
            extreme_rays_total,
            seconds,
        } = info;
        InfoJson {
            rays_after_node,
            node_order,
            pairs_tested: *pairs_tested,
            pairs_rejected_pattern: *pairs_rejected_pattern,
            pairs_rejected_combinatorial: *pairs_rejected_combinatorial,
            adjacency_tests: *adjacency_tests,
            rays_created: *rays_created,
            peak_rays: *peak_rays,
            peak_bytes: *peak_bytes,
            candidates: *candidates,
            extreme_rays_total: *extreme_rays_total,
            seconds: *seconds,
        }
    }
}

impl<'a> Report<'a> {
    pub fn new(
        problem: &Problem,
        settings: &Settings,
        result: &'a Enumeration,
        model: Option<&Model>,
    ) -> Report<'a> {
        Report {
            dim: problem.dim(),
            mu: problem.mu(),
            nodes: problem.nodes(),
            method: settings.method.name(),
            outcome: match result.outcome {
                Outcome::Wedged => "wedged",
                Outcome::NotWedged => "not-wedged",
                Outcome::Incomplete(_) => "incomplete",
            },
            complete: !matches!(result.outcome, Outcome::Incomplete(_)),
            stopped: match result.outcome {
                Outcome::Incomplete(stop) => Some(stop.to_string()),
                _ => None,
            },
            rays: result
                .rays
                .iter()
                .map(|ray| RayJson {
                    u: &ray.u,
                    r: &ray.r,
                    status: ray.status.iter().map(|s| s.name()).collect(),
                })
                .collect(),
            cones: result
                .cones
                .iter()
                .map(|cone| ConeJson {
                    rays: &cone.rays,
                    status: cone.pattern.iter().map(|p| p.name()).collect(),
                })
                .collect(),
            info: InfoJson::from(&result.info),
            model: model.map(ModelJson::new),
            version: env!("CARGO_PKG_VERSION"),
        }
    }
}

/// The JSON text of a result, ending with a newline.
pub fn to_json(
    problem: &Problem,
    settings: &Settings,
    result: &Enumeration,
    model: Option<&Model>,
) -> String {
    let report = Report::new(problem, settings, result, model);
    let mut buf = Vec::new();
    let mut ser = serde_json::Serializer::with_formatter(&mut buf, ShallowPretty::default());
    report
        .serialize(&mut ser)
        .expect("a report of finite numbers serialises");
    buf.push(b'\n');
    String::from_utf8(buf).expect("serde_json writes UTF-8")
}

/// Containers nested at most this deep get one item per line; deeper ones are compact.
const PRETTY_DEPTH: usize = 2;

/// A JSON layout between compact and pretty: the top-level object and its lists and objects have
/// one item per line; each ray, cone and info list is on one line. Files stay small for large `m`
/// and are still readable.
#[derive(Debug, Default)]
struct ShallowPretty {
    depth: usize,
    has_value: bool,
}

impl ShallowPretty {
    fn newline<W: ?Sized + Write>(&self, w: &mut W, depth: usize) -> io::Result<()> {
        w.write_all(b"\n")?;
        for _ in 0..depth {
            w.write_all(b"  ")?;
        }
        Ok(())
    }

    fn open<W: ?Sized + Write>(&mut self, w: &mut W, bracket: &[u8]) -> io::Result<()> {
        self.depth += 1;
        self.has_value = false;
        w.write_all(bracket)
    }

    fn close<W: ?Sized + Write>(&mut self, w: &mut W, bracket: &[u8]) -> io::Result<()> {
        let pretty = self.depth <= PRETTY_DEPTH;
        self.depth -= 1;
        if pretty && self.has_value {
            self.newline(w, self.depth)?;
        }
        w.write_all(bracket)
    }

    fn item<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        if !first {
            w.write_all(b",")?;
        }
        if self.depth <= PRETTY_DEPTH {
            self.newline(w, self.depth)?;
        }
        Ok(())
    }
}

impl Formatter for ShallowPretty {
    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, b"[")
    }

    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.close(w, b"]")
    }

    fn begin_array_value<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        self.item(w, first)
    }

    fn end_array_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }

    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.open(w, b"{")
    }

    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.close(w, b"}")
    }

    fn begin_object_key<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        self.item(w, first)
    }

    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        w.write_all(if self.depth <= PRETTY_DEPTH {
            b": "
        } else {
            b":"
        })
    }

    fn end_object_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        self.has_value = true;
        Ok(())
    }
}

/// Where `--json` sends the JSON. A file target holds its temporary file, created in the
/// destination's directory before the run, and is renamed into place by [`JsonTarget::commit`].
#[derive(Debug)]
pub enum JsonTarget {
    Stdout,
    File { path: PathBuf, temp: NamedTempFile },
}

/// The JSON file could not be written; the message names it.
#[derive(Debug)]
pub struct WriteError(String);

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for WriteError {}

impl JsonTarget {
    /// `-` is stdout; anything else a file, whose temporary sibling is created now.
    pub fn open(path: &Path) -> Result<JsonTarget, WriteError> {
        if path == Path::new("-") {
            return Ok(JsonTarget::Stdout);
        }
        let fail = |e: io::Error| {
            WriteError(format!(
                "{}: cannot write the JSON file: {e}",
                path.display()
            ))
        };
        if path.is_dir() {
            return Err(WriteError(format!(
                "{}: is a directory, not a JSON file name",
                path.display()
            )));
        }
        let temp = temp_beside(path).map_err(fail)?;
        Ok(JsonTarget::File {
            path: path.to_path_buf(),
            temp,
        })
    }

    /// Writes `text` to the temporary file and renames it over the destination. Stdout targets
    /// are written by the caller.
    pub fn commit(self, text: &str) -> Result<(), WriteError> {
        let JsonTarget::File { path, mut temp } = self else {
            return Ok(());
        };
        let fail = |e: io::Error| {
            WriteError(format!(
                "{}: cannot write the JSON file: {e}",
                path.display()
            ))
        };
        temp.write_all(text.as_bytes()).map_err(fail)?;
        temp.as_file().sync_all().map_err(fail)?;
        temp.persist(&path).map_err(|e| fail(e.error))?;
        Ok(())
    }
}

/// A temporary file in `path`'s directory (so that renaming it over `path` is atomic), with the
/// permissions of an ordinary new file (0666 less the umask), not tempfile's 0600.
fn temp_beside(path: &Path) -> io::Result<NamedTempFile> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".wedged-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    builder.tempfile_in(dir)
}

/// Writes `bytes` to `path` through a temporary sibling renamed into place, so that a reader
/// never sees a half-written file. `what` names the file in errors ("VTU file").
pub fn write_atomic(path: &Path, bytes: &[u8], what: &str) -> Result<(), WriteError> {
    let fail =
        |e: io::Error| WriteError(format!("{}: cannot write the {what}: {e}", path.display()));
    let mut temp = temp_beside(path).map_err(fail)?;
    temp.write_all(bytes).map_err(fail)?;
    temp.as_file().sync_all().map_err(fail)?;
    temp.persist(path).map_err(|e| fail(e.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_is_shallow_pretty_and_valid() {
        let value = serde_json::json!({
            "a": 1,
            "list": [{"x": [1, 2], "y": "s"}, {"x": [], "y": "t"}],
            "empty": [],
            "obj": {"k": [3, 4]}
        });
        let mut buf = Vec::new();
        let mut ser = serde_json::Serializer::with_formatter(&mut buf, ShallowPretty::default());
        value.serialize(&mut ser).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, value);
        assert!(
            text.contains("\n    {\"x\":[1,2],\"y\":\"s\"},\n"),
            "{text}"
        );
        assert!(text.contains("\"empty\": []"), "{text}");
        assert!(text.contains("\n    \"k\": [3,4]\n"), "{text}");
    }
}
