//! Enumeration of the 2D solution set: the complementary extreme rays of `C` and the maximal
//! cross-complementary sets of them (MISSION sections 3 and 4).
//!
//! Three methods find the rays; they share the finishing step in this file, which recomputes each
//! ray from its tight constraints, checks it ([`crate::verify`]), puts the rays in canonical order
//! and finds the maximal cliques ([`crate::cliques`]).
//!
//! - [`Method::PrunedDd`] (`dd.rs`, pruned variant): the seed's algorithm, the default.
//! - [`Method::FullDd`] (`dd.rs`, full variant): all extreme rays of `C` by double description,
//!   then a complementarity filter.
//! - [`Method::Faces`] (`faces.rs`): brute force over the `2^m` contact sets.
//! - [`Method::Exact`] ([`crate::exact`]): double description in exact integer arithmetic, no
//!   tolerance anywhere; its rays are exact (rounded to `f64` only for output), so they skip the
//!   floating-point check of the finishing step.

pub(crate) mod dd;
mod faces;

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use crate::cliques::maximal_cliques;
use crate::problem::Problem;
use crate::verify::{polish_and_verify, VerifyError};

/// Which algorithm finds the complementary extreme rays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// The seed's pruned double description (MISSION section 4). The default.
    #[default]
    PrunedDd,
    /// Plain double description of every extreme ray of `C`, then a complementarity filter.
    FullDd,
    /// Brute force over the `2^m` contact sets, the extreme rays of each face.
    Faces,
    /// Double description in exact arithmetic ([`crate::exact`]): every `f64` of `K` and `mu`
    /// taken as the rational it is, every sign decided exactly, so the rays, their statuses and
    /// the cones are provably all of them (`zero_tol` is not used). Slower than the others.
    Exact,
}

impl Method {
    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Method::PrunedDd => "pruned-dd",
            Method::FullDd => "full-dd",
            Method::Faces => "faces",
            Method::Exact => "exact",
        }
    }

    /// Every method, in a fixed order.
    pub const ALL: [Method; 4] = [
        Method::PrunedDd,
        Method::FullDd,
        Method::Faces,
        Method::Exact,
    ];
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The most nodes [`Method::Faces`] accepts: it is exponential twice over, a test baseline.
pub const FACES_MAX_NODES: usize = 16;

/// Tuning of an enumeration. Every field has a documented default.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// The algorithm. Default [`Method::PrunedDd`].
    pub method: Method,
    /// Relative zero tolerance. A value `x = sum_k a_k b_k` is taken as zero when
    /// `|x| <= zero_tol * sum_k |a_k b_k|`, so decisions do not depend on the scale of `K`; the
    /// same number is the relative threshold of the rank decisions. Default `1e-9`.
    pub zero_tol: f64,
    /// Bounds on the run; none by default.
    pub limits: Limits,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            method: Method::PrunedDd,
            zero_tol: 1e-9,
            limits: Limits::default(),
        }
    }
}

/// Bounds on a run. A run that reaches one stops cleanly: its outcome is
/// [`Outcome::Incomplete`], with the reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Limits {
    /// Most rays held at once (double description), a proxy for memory: each held ray of an
    /// `m`-node problem takes about `16 m + 3 m / 8` bytes.
    pub max_rays: Option<usize>,
    /// Most wall-clock time.
    pub time_limit: Option<Duration>,
    /// Most bytes for the rays held at once (double description's ray store, the part of
    /// memory that grows; see [`Info::peak_bytes`]).
    pub max_memory: Option<u64>,
}

/// Why a run stopped before it was complete.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// More rays would have been held than [`Limits::max_rays`].
    MaxRays(usize),
    /// [`Limits::time_limit`] ran out.
    TimeLimit(Duration),
    /// The rays held would have taken more than [`Limits::max_memory`] bytes.
    MaxMemory(u64),
    /// The caller's cancellation flag was set (Ctrl-C).
    Interrupted,
    /// The conic solver could not decide some programs, even with tighter settings (3D
    /// patterns): the patterns below them may be missing.
    Undecided,
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stop::MaxRays(n) => write!(f, "the limit of {n} rays held was reached"),
            Stop::TimeLimit(d) => write!(f, "the time limit of {} s ran out", d.as_secs_f64()),
            Stop::MaxMemory(b) => write!(
                f,
                "the memory limit of {} for the rays held was reached",
                bytes_text(*b)
            ),
            Stop::Interrupted => write!(f, "the run was interrupted"),
            Stop::Undecided => write!(f, "the solver could not decide some contact sets"),
        }
    }
}

/// Decides when a run must stop: limits and the cancellation flag, checked by the methods
/// between units of work (from any thread). The first reason found is kept.
pub(crate) struct Control<'a> {
    start: Instant,
    limits: Limits,
    cancel: &'a AtomicBool,
    stop: OnceLock<Stop>,
    /// Bytes per held ray, set by the method that holds rays.
    ray_bytes: OnceLock<u64>,
}

/// `1.5 GB`, `320 MB`, `12 kB`, `800 B` (powers of 1000).
pub fn bytes_text(b: u64) -> String {
    let b = b as f64;
    if b >= 1e9 {
        format!("{:.2} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.1} MB", b / 1e6)
    } else if b >= 1e3 {
        format!("{:.0} kB", b / 1e3)
    } else {
        format!("{b} B")
    }
}

impl<'a> Control<'a> {
    /// A control starting now.
    pub(crate) fn new(limits: Limits, cancel: &'a AtomicBool) -> Control<'a> {
        Control {
            start: Instant::now(),
            limits,
            cancel,
            stop: OnceLock::new(),
            ray_bytes: OnceLock::new(),
        }
    }

    /// Declares the memory of one held ray, for the memory limit.
    pub(crate) fn set_ray_bytes(&self, bytes: u64) {
        let _ = self.ray_bytes.set(bytes);
    }

    /// Whether the run must stop, with `held` rays in memory now.
    pub(crate) fn must_stop(&self, held: usize) -> bool {
        if self.stop.get().is_some() {
            return true;
        }
        let reason = if self.cancel.load(Ordering::Relaxed) {
            Some(Stop::Interrupted)
        } else if self
            .limits
            .time_limit
            .is_some_and(|t| self.start.elapsed() >= t)
        {
            self.limits.time_limit.map(Stop::TimeLimit)
        } else if let Some(n) = self.limits.max_rays.filter(|&n| held > n) {
            Some(Stop::MaxRays(n))
        } else {
            let bytes = held as u64 * self.ray_bytes.get().copied().unwrap_or(0);
            self.limits
                .max_memory
                .filter(|&b| bytes > b)
                .map(Stop::MaxMemory)
        };
        match reason {
            Some(r) => {
                let _ = self.stop.set(r);
                true
            }
            None => false,
        }
    }

    pub(crate) fn stopped(&self) -> Option<Stop> {
        self.stop.get().copied()
    }
}

/// The status of one contact node in one solution (MISSION section 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum NodeStatus {
    /// `u_n > 0`, `r = 0`.
    Separated,
    /// `u_n = 0`, `|r_t| < mu r_n`.
    Stick,
    /// `u_n = 0`, `r_t = +mu r_n > 0`.
    SlipPlus,
    /// `u_n = 0`, `r_t = -mu r_n < 0`.
    SlipMinus,
    /// 3D: `u_n = 0`, `||r_t|| = mu r_n > 0` (on the boundary of the round friction cone).
    Slip,
    /// `u_n = 0`, `r = 0`.
    Grazing,
}

impl NodeStatus {
    /// The name used in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            NodeStatus::Separated => "separated",
            NodeStatus::Stick => "stick",
            NodeStatus::SlipPlus => "slip+",
            NodeStatus::SlipMinus => "slip-",
            NodeStatus::Slip => "slip",
            NodeStatus::Grazing => "grazing",
        }
    }

    /// `u_n > 0` in this status.
    pub fn gap_open(self) -> bool {
        self == NodeStatus::Separated
    }

    /// `r_n > 0` in this status.
    pub fn pressed(self) -> bool {
        matches!(
            self,
            NodeStatus::Stick | NodeStatus::SlipPlus | NodeStatus::SlipMinus | NodeStatus::Slip
        )
    }
}

/// The contact pattern of one node over a whole convex piece `C_B`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ContactPattern {
    /// `u_n = 0` throughout, `r_n > 0` in the relative interior.
    Contact,
    /// `r = 0` throughout, `u_n > 0` in the relative interior.
    Separated,
    /// `u_n = 0` and `r = 0` throughout.
    Grazing,
}

impl ContactPattern {
    /// The name used in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            ContactPattern::Contact => "contact",
            ContactPattern::Separated => "separated",
            ContactPattern::Grazing => "grazing",
        }
    }
}

/// A complementary extreme ray of `C`: a wedged configuration, normalised to `sum r_n = 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct Ray {
    /// Displacements, `dim*m`, in the local node frames.
    pub u: Vec<f64>,
    /// Reactions, `dim*m`, in the local node frames; `sum r_n = 1`.
    pub r: Vec<f64>,
    /// Per-node status.
    pub status: Vec<NodeStatus>,
}

/// A maximal cross-complementary set of rays: every nonnegative combination of them is a
/// solution, with the same contact pattern.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cone {
    /// Indices into [`Enumeration::rays`], increasing.
    pub rays: Vec<usize>,
    /// Per-node pattern of the piece.
    pub pattern: Vec<ContactPattern>,
}

/// How the run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Complete; at least one wedged configuration exists.
    Wedged,
    /// Complete; only the trivial solution `(0, 0)` exists.
    NotWedged,
    /// Stopped before the end: nothing is claimed about the rays not reported. The double
    /// descriptions have final rays only once every node is processed, so they report none;
    /// `faces` reports the (checked) rays of the contact sets it finished. Cones are not formed.
    Incomplete(Stop),
}

/// Diagnostics of a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Info {
    /// Rays held after each node was processed (pruned-dd, full-dd), in processing order.
    pub rays_after_node: Vec<usize>,
    /// The order in which the nodes were processed (0-based).
    pub node_order: Vec<usize>,
    /// Pairs of rays with opposite signs considered for combination.
    pub pairs_tested: u64,
    /// Pairs rejected because their combination would break complementarity (pruned-dd).
    pub pairs_rejected_pattern: u64,
    /// Pairs rejected by counting or by the combinatorial test.
    pub pairs_rejected_combinatorial: u64,
    /// Algebraic adjacency (rank) tests performed.
    pub adjacency_tests: u64,
    /// New rays created by combining adjacent pairs.
    pub rays_created: u64,
    /// Largest number of rays in memory at once: during a node's step, the rays before it and
    /// the rays after it.
    pub peak_rays: usize,
    /// Bytes of the ray store at its peak (`peak_rays` times the bytes of one ray: its `2m`
    /// values and its bit sets); zero for `faces`.
    pub peak_bytes: u64,
    /// Candidate tight sets examined (faces).
    pub candidates: u64,
    /// Extreme rays of `C` found before the complementarity filter (full-dd).
    pub extreme_rays_total: usize,
    /// Close calls among the floating-point sign decisions of `u_n_i` at a held ray (pruned-dd,
    /// full-dd): values within a factor of 100 of the zero tolerance, on either side. They were
    /// decided by the tolerance; `--certify` checks the reported rays exactly.
    pub near_degenerate: u64,
    /// Wall-clock seconds for the whole run.
    pub seconds: f64,
}

/// The result of [`enumerate`].
#[derive(Debug, Clone, PartialEq)]
pub struct Enumeration {
    /// Whether wedged configurations exist.
    pub outcome: Outcome,
    /// The complementary extreme rays, in canonical order (by status vector).
    pub rays: Vec<Ray>,
    /// The maximal cross-complementary sets, in canonical order.
    pub cones: Vec<Cone>,
    /// Diagnostics.
    pub info: Info,
}

impl Enumeration {
    /// The centroid of a cone's rays, `(u, r)`: a solution in the cone's relative interior,
    /// normalised like the rays (`sum r_n = 1`).
    pub fn cone_centroid(&self, cone: &Cone) -> (Vec<f64>, Vec<f64>) {
        let n = self.rays.first().map_or(0, |r| r.u.len());
        let mut u = vec![0.0; n];
        let mut r = vec![0.0; n];
        let w = 1.0 / cone.rays.len().max(1) as f64;
        for &k in &cone.rays {
            for i in 0..n {
                u[i] += w * self.rays[k].u[i];
                r[i] += w * self.rays[k].r[i];
            }
        }
        (u, r)
    }

    /// The per-node status of every strictly positive combination of a cone's rays, decided
    /// combinatorially from the rays' statuses: separated if some ray separates the node;
    /// grazing if every ray grazes; slip in one direction if every pressing ray slips that way
    /// (grazing rays add nothing); stick otherwise.
    pub fn cone_status(&self, cone: &Cone) -> Vec<NodeStatus> {
        let m = self.rays.first().map_or(0, |r| r.status.len());
        (0..m)
            .map(|i| {
                let statuses: Vec<NodeStatus> =
                    cone.rays.iter().map(|&k| self.rays[k].status[i]).collect();
                if statuses.contains(&NodeStatus::Separated) {
                    return NodeStatus::Separated;
                }
                let pressing: Vec<NodeStatus> = statuses
                    .into_iter()
                    .filter(|&s| s != NodeStatus::Grazing)
                    .collect();
                match pressing.first() {
                    None => NodeStatus::Grazing,
                    Some(&first)
                        if first != NodeStatus::Stick && pressing.iter().all(|&s| s == first) =>
                    {
                        first
                    }
                    Some(_) => NodeStatus::Stick,
                }
            })
            .collect()
    }
}

/// Why an enumeration could not give an answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EnumerateError {
    /// The enumeration of patterns by rays is the 2D algorithm; 3D goes through sign patterns.
    #[error("enumeration of rays needs dim = 2, the problem has dim = {0}")]
    UnsupportedDim(usize),
    /// A setting is out of range.
    #[error("invalid setting: {0}")]
    InvalidSettings(String),
    /// A ray failed its check before output: floating point could not be trusted here.
    #[error("a computed ray failed verification, so no answer is given: {0}")]
    Verification(#[from] VerifyError),
}

/// What a method hands to the finishing step: a ray's reactions (any positive scale) and the
/// per-node status that the method decided for it.
#[derive(Debug, Clone)]
pub(crate) struct RawRay {
    pub r: Vec<f64>,
    pub status: Vec<NodeStatus>,
}

/// Where a running enumeration is, reported after each node is processed (double description
/// methods) or each contact set is done (faces).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    /// Steps done.
    pub done: usize,
    /// Steps in all.
    pub total: usize,
    /// Rays held now.
    pub rays: usize,
}

/// Enumerates the complementary extreme rays and the maximal cross-complementary sets of a 2D
/// problem.
pub fn enumerate(problem: &Problem, settings: &Settings) -> Result<Enumeration, EnumerateError> {
    enumerate_with_progress(problem, settings, &|_| {})
}

/// [`enumerate`], calling `progress` as the run goes (from the calling thread).
pub fn enumerate_with_progress(
    problem: &Problem,
    settings: &Settings,
    progress: &dyn Fn(Progress),
) -> Result<Enumeration, EnumerateError> {
    enumerate_with_control(problem, settings, progress, &AtomicBool::new(false))
}

/// [`enumerate_with_progress`], stopping cleanly ([`Outcome::Incomplete`]) as soon as `cancel`
/// is set (by a Ctrl-C handler, say) or a limit of `settings.limits` is reached.
pub fn enumerate_with_control(
    problem: &Problem,
    settings: &Settings,
    progress: &dyn Fn(Progress),
    cancel: &AtomicBool,
) -> Result<Enumeration, EnumerateError> {
    if problem.dim() != 2 {
        return Err(EnumerateError::UnsupportedDim(problem.dim()));
    }
    check_zero_tol(settings.zero_tol)?;
    if settings.method == Method::Faces && problem.nodes() > FACES_MAX_NODES {
        return Err(EnumerateError::InvalidSettings(format!(
            "the faces method tries every one of the 2^m contact sets; m = {} is more than its \
             limit of {FACES_MAX_NODES} (use pruned-dd)",
            problem.nodes()
        )));
    }
    let start = Instant::now();
    let control = Control::new(settings.limits, cancel);
    let mut info = Info::default();
    let mut exact_rays: Vec<Ray> = Vec::new();
    let raw = if control.must_stop(0) {
        Vec::new()
    } else {
        match settings.method {
            // Exact rays need no floating-point check: they go straight to the finishing step.
            Method::Exact => {
                exact_rays = crate::exact::run(
                    problem,
                    crate::exact::Variant::Pruned,
                    &mut info,
                    progress,
                    &control,
                )?
                .iter()
                .map(crate::exact::ExactSolution::rounded)
                .collect();
                Vec::new()
            }
            Method::PrunedDd => dd::run(
                problem,
                &dd::Friction::planar(problem.mu()),
                settings,
                &mut info,
                dd::Variant::Pruned,
                progress,
                &control,
            ),
            Method::FullDd => dd::run(
                problem,
                &dd::Friction::planar(problem.mu()),
                settings,
                &mut info,
                dd::Variant::Full,
                progress,
                &control,
            ),
            Method::Faces => faces::run(problem, settings, &mut info, &control),
        }
    };
    let mut rays = exact_rays;
    for raw_ray in raw {
        rays.push(polish_and_verify(
            problem,
            &raw_ray.r,
            raw_ray.status,
            settings.zero_tol,
        )?);
    }
    rays.sort_by(|a, b| a.status.cmp(&b.status));
    rays.dedup_by(|a, b| a.status == b.status);
    info.seconds = start.elapsed().as_secs_f64();
    let (outcome, cones) = match control.stopped() {
        Some(stop) => (Outcome::Incomplete(stop), Vec::new()),
        None if rays.is_empty() => (Outcome::NotWedged, Vec::new()),
        None => (Outcome::Wedged, cones_of(&rays)),
    };
    Ok(Enumeration {
        outcome,
        rays,
        cones,
        info,
    })
}

/// The range of [`Settings::zero_tol`], shared by the pattern methods.
pub(crate) fn check_zero_tol(zero_tol: f64) -> Result<(), EnumerateError> {
    if zero_tol > 0.0 && zero_tol < 1e-2 {
        Ok(())
    } else {
        Err(EnumerateError::InvalidSettings(format!(
            "zero_tol must be in (0, 0.01), got {zero_tol}"
        )))
    }
}

/// Two rays are cross-complementary when their sum is complementary at every node.
pub fn cross_complementary(a: &[NodeStatus], b: &[NodeStatus]) -> bool {
    a.iter().zip(b).all(|(&x, &y)| {
        let gap = x.gap_open() || y.gap_open();
        let pressed = x.pressed() || y.pressed();
        !(gap && pressed)
    })
}

/// The maximal cross-complementary sets of `rays`, each with its pattern, in canonical order.
fn cones_of(rays: &[Ray]) -> Vec<Cone> {
    let statuses: Vec<&[NodeStatus]> = rays.iter().map(|r| r.status.as_slice()).collect();
    cones_of_statuses(&statuses)
}

/// The patterns of the maximal cross-complementary sets of rays with these statuses (the
/// pyramid method's candidates).
///
/// Cross-complementarity depends only on which entries are positive, so rays with the same
/// positive entries are merged first (each stands for all, being compatible with itself): the
/// graph then has one vertex per distinct sign pattern, not one per ray (a piece of a fine
/// pyramid has thousands of rays).
pub(crate) fn cones_of_status(statuses: &[Vec<NodeStatus>]) -> Vec<Vec<ContactPattern>> {
    let mut signs: Vec<Vec<NodeStatus>> = statuses
        .iter()
        .map(|s| {
            s.iter()
                .map(|&x| if x.pressed() { NodeStatus::Stick } else { x })
                .collect()
        })
        .collect();
    signs.sort();
    signs.dedup();
    let statuses: Vec<&[NodeStatus]> = signs.iter().map(|s| s.as_slice()).collect();
    cones_of_statuses(&statuses)
        .into_iter()
        .map(|c| c.pattern)
        .collect()
}

pub(crate) fn cones_of_statuses(statuses: &[&[NodeStatus]]) -> Vec<Cone> {
    let p = statuses.len();
    let adjacent: Vec<Vec<bool>> = (0..p)
        .map(|i| {
            (0..p)
                .map(|j| i != j && cross_complementary(statuses[i], statuses[j]))
                .collect()
        })
        .collect();
    let mut cones: Vec<Cone> = maximal_cliques(p, |i, j| adjacent[i][j])
        .into_iter()
        .map(|members| {
            let m = statuses.first().map_or(0, |s| s.len());
            let pattern = (0..m)
                .map(|k| {
                    if members.iter().any(|&i| statuses[i][k].pressed()) {
                        ContactPattern::Contact
                    } else if members.iter().any(|&i| statuses[i][k].gap_open()) {
                        ContactPattern::Separated
                    } else {
                        ContactPattern::Grazing
                    }
                })
                .collect();
            Cone {
                rays: members,
                pattern,
            }
        })
        .collect();
    cones.sort_by(|a, b| a.rays.cmp(&b.rays));
    cones
}
