//! The JSON result, a fixed format that scripts can rely on (written by [`crate::report::files`]).
//!
//! ```text
//! { "dim": 2, "mu": 1.0, "nodes": 4, "method": "pruned-dd",
//!   "outcome": "wedged" | "not-wedged" | "incomplete", "complete": true, "stopped": null | "why",
//!   "certified": true | false | null,
//!   "rays":  [ { "u": [..], "r": [..], "status": ["separated" | "stick" | "slip+" | "slip-" | "grazing", ..] } ],
//!   "cones": [ { "rays": [0-based ray indices], "status": ["contact" | "separated" | "grazing", ..] } ],
//!   "patterns": [ { "pattern": ["contact" | "separated" | "grazing", ..],
//!                   "status": ["separated" | "stick" | "slip" | "slip+" | "slip-" | "grazing", ..],
//!                   "u": [..], "r": [..], "margin": 0.01 | null } ],
//!   "undecided": [ { "contact": [true | false, ..], "reason": ".." } ],
//!   "info":  { every field of wedged::Info }                        (ray methods)
//!          | { "method", "pyramid_faces", every field of wedged::PatternInfo }  (pattern methods),
//!   "model": { .. },                                                (meshed bodies only)
//!   "version": "0.1.0",
//!   "shard": { "command", "index", "count", "fingerprint", "split_depth", "units",
//!              "own_units", "split_nodes" } }                      (--shard parts only)
//! ```
//!
//! Every key is always there (`model` for a meshed body only), whatever the method:
//!
//! - A ray method (`pruned-dd`, `full-dd`, `faces`, `search`; 2D) fills `rays` and `cones`, and derives
//!   `patterns` from the cones, one per cone in the same order (`patterns[N]` is `cones[N]`, and
//!   the files `cone-N.*`): `pattern` is the cone's, `status` is
//!   [`wedged::Enumeration::cone_status`], `(u, r)` is the cone's centroid (the mean of its
//!   rays, [`wedged::Enumeration::cone_centroid`]), and `margin` is `null`: the centroid is not
//!   pushed away from the piece's boundary as a pattern method's witness is, so it has no
//!   margin to report. `undecided` is empty.
//! - A pattern method (`bnb`, `pyramid`, `pattern-faces`, `pattern-search` (2D); 2D or 3D) leaves `rays` and `cones`
//!   empty and fills `patterns` with the maximal realised sign patterns, sorted by pattern, each
//!   with its witness (in the relative interior of its piece) and `margin`, the witness's
//!   smallest positive entry (pressures, scaled gaps, stick slacks). `undecided` lists the
//!   contact sets the conic solver could not decide (`contact[i]`: node `i` in contact), with
//!   its reason; when it is not empty the run is incomplete (`"complete": false`, `"stopped"`
//!   says why) because patterns below them may be missing. `info` holds `method`,
//!   `pyramid_faces` (the pyramid's faces, `null` for the other methods) and every field of
//!   `wedged::PatternInfo` under the same names. A run stopped early (time limit, Ctrl-C) lists
//!   the patterns it found before the stop: each realised and checked, but others may be
//!   missing and these may not all be maximal. With `--jsonl`, `patterns` is empty: the pieces
//!   went to that file, one object per line in the form of `patterns[N]`, and `info.streamed`
//!   counts them.
//!
//! `certified` is the result of `--certify`: for a ray method `true` when the rays and cones
//! passed every check of `wedged::certify` in exact rational arithmetic, for a pattern method
//! when every witness and every infeasibility certificate behind the search passed
//! (`wedged::PatternCertificate`); `false` when one failed (the exit code is then 1); `null`
//! when `--certify` was not given. `certified_complete` is `true` when, in addition, the answer
//! is proven complete: for rays, equal to the exact enumeration (checked up to 8 nodes, `null`
//! when not checked); for patterns, the same as `certified`.
//!
//! Vectors are in the local node frames, normal first (`n, t` in 2D, `n, t1, t2` in 3D), with
//! rays and witnesses normalised to `sum r_n = 1`. The top level and the lists are laid out one
//! item per line; each item is on one line.

use std::fmt;
use std::io::{self, Write};

use serde::Serialize;
use serde_json::ser::Formatter;
use wedged::fe::Model;
use wedged::patterns::{PatternInfo, Undecided};
use wedged::{Info, Outcome, Problem};

use crate::report::answer::{Answer, Choice, Piece};

/// The whole JSON document.
#[derive(Debug, Serialize)]
pub struct Report<'a> {
    pub dim: usize,
    pub mu: f64,
    pub nodes: usize,
    /// A floating body's free rigid motions (0 when it is held).
    pub rigid_modes: usize,
    pub method: &'static str,
    pub outcome: &'static str,
    /// False when the run stopped at a limit or on Ctrl-C.
    pub complete: bool,
    /// Why an incomplete run stopped; `null` for a complete one.
    pub stopped: Option<String>,
    /// `--certify`: true when every exact check passed, false when one failed; `null` without
    /// `--certify`.
    pub certified: Option<bool>,
    /// `--certify` on a ray method of at most `wedged::certify::COMPLETENESS_MAX_NODES` nodes:
    /// true when the answer equals the exact enumeration (nothing is missing); `null` when not
    /// checked.
    pub certified_complete: Option<bool>,
    pub rays: Vec<RayJson<'a>>,
    pub cones: Vec<ConeJson<'a>>,
    /// The convex pieces, whatever the method (see the module documentation).
    pub patterns: PiecesJson<'a>,
    /// The contact sets a pattern method could not decide; empty for ray methods.
    pub undecided: Vec<UndecidedJson<'a>>,
    pub info: InfoJson<'a>,
    /// For a meshed body: the model behind the condensed `K`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelJson>,
    pub version: &'static str,
    /// A part of a sharded run (`--shard I/N`), for `wedged merge`; absent from a whole run's
    /// JSON (and from the merge's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shard: Option<ShardJson>,
}

/// How a shard's search was split ([`wedged::ShardReport`]), the command (`enumerate` or
/// `critical`), and the run's fingerprint ([`Choice::fingerprint`], [`super::answer::fingerprint`]), which
/// every part of one run shares.
#[derive(Debug, Serialize)]
pub struct ShardJson {
    pub command: &'static str,
    pub index: usize,
    pub count: usize,
    pub fingerprint: String,
    pub split_depth: usize,
    pub units: usize,
    pub own_units: usize,
    pub split_nodes: u64,
}

impl ShardJson {
    pub fn new(command: &'static str, s: &wedged::ShardReport, fingerprint: String) -> ShardJson {
        ShardJson {
            command,
            index: s.index,
            count: s.count,
            fingerprint,
            split_depth: s.split_depth,
            units: s.units,
            own_units: s.own_units,
            split_nodes: s.split_nodes,
        }
    }
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

/// One convex piece: its pattern, the status at its witness, the witness, the margin.
#[derive(Debug, Serialize)]
pub struct PatternJson {
    pub pattern: Vec<&'static str>,
    pub status: Vec<&'static str>,
    pub u: Vec<f64>,
    pub r: Vec<f64>,
    /// `null` for the cone of a ray method.
    pub margin: Option<f64>,
}

impl From<Piece> for PatternJson {
    fn from(piece: Piece) -> Self {
        PatternJson {
            pattern: piece.pattern.iter().map(|p| p.name()).collect(),
            status: piece.status.iter().map(|s| s.name()).collect(),
            u: piece.u,
            r: piece.r,
            margin: piece.margin,
        }
    }
}

/// The `patterns` of a report: an answer's pieces, each made as it is written
/// ([`Answer::each_piece`]), so that writing the JSON holds no copy of them all (the 3D
/// V-groove plug's 57,818 pieces at m = 40 are a 290 MB document).
pub struct PiecesJson<'a>(&'a Answer);

impl<'a> PiecesJson<'a> {
    /// The pieces as the JSON has them, one at a time.
    pub fn iter(&self) -> impl Iterator<Item = PatternJson> + 'a {
        self.0.each_piece().map(PatternJson::from)
    }
}

impl fmt::Debug for PiecesJson<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("PiecesJson")
    }
}

impl Serialize for PiecesJson<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.iter())
    }
}

impl From<&wedged::Pattern> for PatternJson {
    fn from(p: &wedged::Pattern) -> Self {
        PatternJson {
            pattern: p.pattern.iter().map(|q| q.name()).collect(),
            status: p.status.iter().map(|s| s.name()).collect(),
            u: p.u.clone(),
            r: p.r.clone(),
            margin: Some(p.margin),
        }
    }
}

/// One line of `--jsonl`: a pattern as `patterns[N]` of the JSON, compact, with a newline.
pub fn pattern_line(p: &wedged::Pattern) -> String {
    let mut line = serde_json::to_string(&PatternJson::from(p))
        .expect("a pattern of finite numbers serialises");
    line.push('\n');
    line
}

/// A contact set the solver could not decide.
#[derive(Debug, Serialize)]
pub struct UndecidedJson<'a> {
    pub contact: &'a [bool],
    pub reason: &'a str,
}

impl<'a> From<&'a Undecided> for UndecidedJson<'a> {
    fn from(u: &'a Undecided) -> Self {
        UndecidedJson {
            contact: &u.contact,
            reason: &u.reason,
        }
    }
}

/// The diagnostics: of a ray method or of a pattern method.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum InfoJson<'a> {
    Rays(RayInfoJson<'a>),
    Patterns(PatternInfoJson),
}

/// The method, the pyramid's faces and every field of [`wedged::patterns::PatternInfo`], under
/// the same names.
#[derive(Debug, Serialize)]
pub struct PatternInfoJson {
    pub method: &'static str,
    pub pyramid_faces: Option<usize>,
    pub nodes_visited: u64,
    pub nodes_inherited: u64,
    pub pruned_infeasible: u64,
    pub pruned_unpressed: u64,
    pub leaves: u64,
    pub candidates: u64,
    pub spurious: u64,
    pub pyramid_rays: u64,
    pub socps: u64,
    pub retries: u64,
    pub uncertain: u64,
    pub near_degenerate: u64,
    pub realised: u64,
    pub streamed: u64,
    pub bound_tightenings: u64,
    pub lp_solves: u64,
    pub lp_pivots: u64,
    pub lp_fallbacks: u64,
    pub mirrored: u64,
    pub images: u64,
    pub mapped: u64,
    pub groups: u64,
    pub seconds: f64,
    /// The process's peak resident memory (see [`peak_rss_bytes`]).
    pub peak_rss_bytes: Option<u64>,
}

impl PatternInfoJson {
    fn new(choice: &Choice, info: &PatternInfo) -> PatternInfoJson {
        // No `..`: a new field of PatternInfo must be added here too.
        let PatternInfo {
            nodes_visited,
            nodes_inherited,
            pruned_infeasible,
            pruned_unpressed,
            leaves,
            candidates,
            spurious,
            pyramid_rays,
            socps,
            retries,
            uncertain,
            near_degenerate,
            realised,
            streamed,
            bound_tightenings,
            lp_solves,
            lp_pivots,
            lp_fallbacks,
            mirrored,
            images,
            mapped,
            groups,
            seconds,
        } = *info;
        PatternInfoJson {
            method: choice.name(),
            pyramid_faces: choice.pyramid_faces(),
            nodes_visited,
            nodes_inherited,
            pruned_infeasible,
            pruned_unpressed,
            leaves,
            candidates,
            spurious,
            pyramid_rays,
            socps,
            retries,
            uncertain,
            near_degenerate,
            realised,
            streamed,
            bound_tightenings,
            lp_solves,
            lp_pivots,
            lp_fallbacks,
            mirrored,
            images,
            mapped,
            groups,
            seconds,
            peak_rss_bytes: peak_rss_bytes(),
        }
    }
}

/// Every field of [`wedged::Info`], under the same names.
#[derive(Debug, Serialize)]
pub struct RayInfoJson<'a> {
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
    pub near_degenerate: u64,
    pub search_nodes: u64,
    pub search_inherited: u64,
    pub search_pruned: u64,
    pub search_leaves: u64,
    pub search_undecided: u64,
    pub search_tightenings: u64,
    pub search_undecided_faces: &'a [String],
    pub largest_face: usize,
    pub lp_solves: u64,
    pub lp_pivots: u64,
    pub lp_fallbacks: u64,
    pub seconds: f64,
    /// The process's peak resident memory (see [`peak_rss_bytes`]).
    pub peak_rss_bytes: Option<u64>,
}

impl<'a> From<&'a Info> for RayInfoJson<'a> {
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
            near_degenerate,
            search_nodes,
            search_inherited,
            search_pruned,
            search_leaves,
            search_undecided,
            search_tightenings,
            search_undecided_faces,
            largest_face,
            lp_solves,
            lp_pivots,
            lp_fallbacks,
            seconds,
        } = info;
        RayInfoJson {
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
            near_degenerate: *near_degenerate,
            search_nodes: *search_nodes,
            search_inherited: *search_inherited,
            search_pruned: *search_pruned,
            search_leaves: *search_leaves,
            search_undecided: *search_undecided,
            search_tightenings: *search_tightenings,
            search_undecided_faces,
            largest_face: *largest_face,
            lp_solves: *lp_solves,
            lp_pivots: *lp_pivots,
            lp_fallbacks: *lp_fallbacks,
            seconds: *seconds,
            peak_rss_bytes: peak_rss_bytes(),
        }
    }
}

/// `", peak memory X MiB"` for the summaries' info lines (empty where it is not known).
pub fn peak_memory_text() -> String {
    peak_rss_bytes()
        .map(|b| format!(", peak memory {:.1} MiB", b as f64 / 1048576.0))
        .unwrap_or_default()
}

/// The peak resident memory of this process so far (`VmHWM` of `/proc/self/status`, Linux), in
/// bytes; `None` where that file does not exist. The library's own measure of the memory that
/// grows with a run is `peak_bytes` (the double description's ray store, which `--max-memory`
/// bounds); this one is the whole process, parsers and solver included.
pub fn peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line
        .trim_start_matches("VmHWM:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb * 1024)
}

/// The report's scalars and diagnostics, without its records: what the Python bindings hand
/// back at once (the records follow when asked for).
pub struct Header<'a> {
    pub dim: usize,
    pub mu: f64,
    pub nodes: usize,
    pub rigid_modes: usize,
    pub method: &'static str,
    pub outcome: &'static str,
    pub complete: bool,
    pub stopped: Option<String>,
    pub info: InfoJson<'a>,
}

impl<'a> Header<'a> {
    pub fn new(problem: &Problem, choice: &Choice, answer: &'a Answer) -> Header<'a> {
        let outcome = answer.outcome();
        Header {
            dim: problem.dim(),
            mu: problem.mu(),
            nodes: problem.nodes(),
            rigid_modes: problem.rigid_modes().ncols(),
            method: choice.name(),
            outcome: match outcome {
                Outcome::Wedged => "wedged",
                Outcome::NotWedged => "not-wedged",
                Outcome::Incomplete(_) => "incomplete",
            },
            complete: !matches!(outcome, Outcome::Incomplete(_)),
            stopped: match outcome {
                Outcome::Incomplete(stop) => Some(stop.to_string()),
                _ => None,
            },
            info: match answer {
                Answer::Rays(result) => InfoJson::Rays(RayInfoJson::from(&result.info)),
                Answer::Patterns(result) => {
                    InfoJson::Patterns(PatternInfoJson::new(choice, &result.info))
                }
            },
        }
    }
}

impl<'a> Report<'a> {
    pub fn new(
        problem: &Problem,
        choice: &Choice,
        answer: &'a Answer,
        model: Option<&Model>,
    ) -> Report<'a> {
        let (rays, cones, undecided) = match answer {
            Answer::Rays(result) => (
                result
                    .rays
                    .iter()
                    .map(|ray| RayJson {
                        u: &ray.u,
                        r: &ray.r,
                        status: ray.status.iter().map(|s| s.name()).collect(),
                    })
                    .collect(),
                result
                    .cones
                    .iter()
                    .map(|cone| ConeJson {
                        rays: &cone.rays,
                        status: cone.pattern.iter().map(|p| p.name()).collect(),
                    })
                    .collect(),
                Vec::new(),
            ),
            Answer::Patterns(result) => (
                Vec::new(),
                Vec::new(),
                result.undecided.iter().map(UndecidedJson::from).collect(),
            ),
        };
        let header = Header::new(problem, choice, answer);
        Report {
            dim: header.dim,
            mu: header.mu,
            nodes: header.nodes,
            rigid_modes: header.rigid_modes,
            method: header.method,
            outcome: header.outcome,
            complete: header.complete,
            stopped: header.stopped,
            certified: None,
            certified_complete: None,
            rays,
            cones,
            patterns: PiecesJson(answer),
            undecided,
            info: header.info,
            model: model.map(ModelJson::new),
            version: env!("CARGO_PKG_VERSION"),
            shard: answer
                .shard()
                .map(|s| ShardJson::new("enumerate", &s, choice.fingerprint(problem))),
        }
    }
}

/// The JSON text of a result, ending with a newline; `certificate` is the result of
/// `--certify`.
pub fn to_json(
    problem: &Problem,
    choice: &Choice,
    answer: &Answer,
    model: Option<&Model>,
    certificate: Option<&crate::report::answer::Certified>,
) -> String {
    let mut buf = Vec::new();
    write_json(problem, choice, answer, model, certificate, &mut buf)
        .expect("writing to memory does not fail");
    String::from_utf8(buf).expect("serde_json writes UTF-8")
}

/// [`to_json`] written to `out` as it is made (a file's writer: no copy of the document is
/// held).
pub fn write_json(
    problem: &Problem,
    choice: &Choice,
    answer: &Answer,
    model: Option<&Model>,
    certificate: Option<&crate::report::answer::Certified>,
    out: &mut dyn Write,
) -> io::Result<()> {
    let mut report = Report::new(problem, choice, answer, model);
    report.certified = certificate.map(|c| c.certified());
    report.certified_complete = certificate.and_then(|c| c.complete());
    layout_into(&report, out)
}

/// The JSON text of any report (this one's or `wedged critical`'s), in the shallow-pretty
/// layout, ending with a newline.
pub fn layout<T: Serialize>(report: &T) -> String {
    let mut buf = Vec::new();
    layout_into(report, &mut buf).expect("writing to memory does not fail");
    String::from_utf8(buf).expect("serde_json writes UTF-8")
}

/// [`layout`] written to `out`. An error is the writer's (a report of finite numbers always
/// serialises).
pub fn layout_into<T: Serialize>(report: &T, out: &mut dyn Write) -> io::Result<()> {
    let mut ser = serde_json::Serializer::with_formatter(&mut *out, ShallowPretty::default());
    report.serialize(&mut ser).map_err(io::Error::from)?;
    out.write_all(b"\n")
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

#[cfg(test)]
mod tests;
