//! The parameters, diagnostics and result of a 2D ray enumeration (the `Params / Info /
//! result` shape): [`Method`], [`Settings`], [`Info`], [`Progress`], [`Enumeration`], and the
//! [`RawRay`] a method hands to the finishing step.

use std::fmt;

use crate::run::{Limits, Outcome};
use crate::solution::{Cone, NodeStatus, Ray};

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
    /// Depth-first search over contact sets, each decided by a warm-started simplex method,
    /// then the rays of each reached face by double description in the face's own dimension
    /// (`rays/search`): its work follows the contact sets that some solution presses, not
    /// the intermediate rays of a double description over the whole cone.
    Search,
}

impl Method {
    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Method::PrunedDd => "pruned-dd",
            Method::FullDd => "full-dd",
            Method::Faces => "faces",
            Method::Exact => "exact",
            Method::Search => "search",
        }
    }

    /// Every method, in a fixed order.
    pub const ALL: [Method; 5] = [
        Method::PrunedDd,
        Method::FullDd,
        Method::Faces,
        Method::Exact,
        Method::Search,
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
    /// decided by the tolerance; `--certify` checks the reported rays exactly. For search: the
    /// faces whose support no solver settled, described by the tolerance alone.
    pub near_degenerate: u64,
    /// Search nodes visited, leaves included (search).
    pub search_nodes: u64,
    /// Search nodes that took their parent's solution and solved nothing (search).
    pub search_inherited: u64,
    /// Search nodes pruned: no solution presses their contact nodes at once (search).
    pub search_pruned: u64,
    /// Leaves reached: the contact sets that some solution presses exactly (search).
    pub search_leaves: u64,
    /// Search nodes whose program neither solver could decide (explored, never pruned).
    pub search_undecided: u64,
    /// Search nodes that bounded their free nodes' drives for the cuts of their subtree.
    pub search_tightenings: u64,
    /// Why the faces of some leaves could not be computed (search; the run is then
    /// incomplete, [`crate::Stop::Undecided`]).
    pub search_undecided_faces: Vec<String>,
    /// The largest dimension of a leaf's face (search).
    pub largest_face: usize,
    /// Linear programs solved by the simplex method, their pivots, and the programs passed on
    /// to Clarabel (search).
    pub lp_solves: u64,
    pub lp_pivots: u64,
    pub lp_fallbacks: u64,
    /// Wall-clock seconds for the whole run.
    pub seconds: f64,
}

/// The result of [`crate::enumerate`].
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
    /// Search nodes visited so far (the searches over contact sets; 0 for the double
    /// descriptions). With the explored share `done / total` (each finished subtree counts
    /// `2^-depth` of the tree) it estimates the whole tree: `nodes / share`, the weighted
    /// backtrack estimator of Kilby et al. (2006), Knuth's estimator averaged over the paths
    /// the search has taken.
    pub nodes: u64,
}
