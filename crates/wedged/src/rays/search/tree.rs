//! The depth-first search over contact sets.
//!
//! A search node fixes some nodes to contact or separated and leaves the rest free (the
//! relaxation: `u_n >= 0` and the friction cone, no complementarity). Its program asks for a
//! solution that presses every contact node at once (`r_n_i >= 1`, [`Norm::Pressed`]; with no
//! contact node yet, `sum r_n >= 1`). The subtree is pruned when that program is infeasible:
//! every leaf below would then have a contact node that no solution presses, and such a leaf's
//! face lies inside the face of a leaf with a smaller contact set (the node's reaction is zero
//! throughout, so it may as well be separated), which the search reaches on another branch.
//! So the leaves reached are exactly the contact sets `J` for which some solution presses
//! exactly `J`, and every complementary extreme ray lies in the face of one of them (the leaf of
//! the set it presses).
//!
//! **Drive cuts.** The relaxation lets a free node press with its gap open, and dead subtrees
//! (relaxation feasible, no complementary solution below) were 95% of the tree. Nodes near the
//! root (depth below [`tighten_depth`]) bound each free node's drive over their relaxation
//! ([`crate::conic::cuts::tighten`]) and every program below carries the cuts those bounds give: a node that
//! presses must not be driven open. The cuts hold for every solution of the subtree, so a
//! leaf's program is unchanged (a leaf has no free node, and its cuts are free rows) and a
//! prune still means that no solution presses the contact nodes at once. On issue 20's plug at
//! m = 40 this took the tree from 109k nodes to 7.6k (`BENCHMARKS.md`). The cuts rest on the
//! solver's optima in floating point, so a certified run (`pattern-search --certify`, whose
//! [`Formulation`](crate::conic::program::Formulation) keeps refutations) has none, and each of
//! its prunes stands only when the cone solver's refutation of it passes an exact check.
//!
//! Each program is a warm start of the simplex method from the parent's basis: a child differs
//! from its parent by the bounds of one node. A child whose parent's solution already meets its
//! constraints (the branched node's gap closed with a positive pressure, or its reaction zero)
//! inherits it and solves nothing. A program minimises the free nodes' total gap and pressure,
//! so that its point is a vertex at which few nodes break complementarity. The node to branch
//! on is the free node whose relaxed solution breaks complementarity most (`u_n r_n` largest),
//! then the one pressed most. The two subtrees run in parallel (`rayon::join`).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crate::conic::contact_lp::ContactLp;
use crate::conic::cuts::Drive;
use crate::conic::node_lp::{self, Shape, Warm as Basis};
use crate::conic::program::{Class, Decision, Norm, POSITIVE};
use crate::rays::Progress;
use crate::run::{with_progress, Control};
use crate::shard::{self, Explored, Shard, ShardReport, Walk};

/// A solution's gap or reaction component at most this (with `sum r_n = 1`, gaps scaled) counts
/// as zero when deciding whether a child inherits it.
const INHERIT_ZERO: f64 = 1e-9;

/// Search nodes at depths below [`tighten_depth`], `max(TIGHTEN_DEPTH, (m - 20) / 20)`, bound
/// the drives of their free nodes ([`crate::conic::cuts::tighten`], two programs per free node) and hand the
/// cuts down to their subtrees; from [`SETTLE_FROM`] nodes on, the root settles its bounds
/// ([`node_lp::tighten_node`]). Deeper tightening visits fewer nodes but solves more programs.
/// (Measured on issue 20's plug, whole process, 2 threads: m = 40, depths 3, 4, 6, 8: 1.1,
/// 1.3, 1.8, 2.1 s (7.6k, 8.4k, 3.1k, 3.8k nodes); m = 50, depths 4, 6: 4.6, 6.3 s. Since the
/// simplex method leaves idle rows out (2026-11-26): m = 60, depths 4, 6, 8, 10: 13.6, 12.8,
/// 15.1, 18.6 s (87k, 48k, 32k, 22k nodes); m = 80, depths 5, 7, 9, 11: 245, 114, 99, 123 s
/// (844k, 270k, 130k, 114k nodes). With the root's bounds settled (2026-11-26, later):
/// m = 60, depths 3, 4, 6, 8: 0.53M, 0.52M, 0.59M, 0.70M pivots (5.1, 5.1, 5.9, 6.9 s);
/// m = 80, depths 4, 5, 6, 7, 9: 3.19M, 3.58M, 3.60M, 3.84M, 4.12M pivots (47, 48, 41, 53,
/// 61 s): the best depth grew by about 2 per 20 nodes. Since a node's program leaves its
/// loose rows out (2026-11-27), nodes are cheaper against the tightening programs (which keep
/// every row): m = 40, depths 2, 3, 4: 0.56, 0.59, 0.66 s; m = 60, depths 2, 3, 4, 6, 8: 3.9,
/// 3.2, 3.9, 5.2, 5.5 s; m = 80, depths 3, 4, 5, 6: 24.9, 24.8, 29.5, 27.6 s, one run each.)
const TIGHTEN_DEPTH: usize = 3;

/// Problems with fewer nodes do not tighten at all: their trees are small and a node's
/// program cheap against a free node's two tightening programs. (Measured 2026-11-27, whole
/// process, `farm-bench -n 20 --vs`, depth 0 against 3: random m = 9 problems at `mu = 1.5`,
/// seeds 0 to 4, `pattern-search`, medians of the paired ratios 0.90, 0.82, 0.83, 0.78, 0.79
/// (seed 0: 1,945 against 2,673 pivots); the plug at m = 16 0.79. At m = 20 and 26 the plug
/// took 1.1 to 1.25 times as long without tightening, so it tightens from 20 nodes on.)
const TIGHTEN_FROM: usize = 20;

/// The root settles its bounds ([`node_lp::tighten_node`]) from this many nodes on, and the
/// nodes at depths below [`settle_depth`] do: `(m - SETTLE_FROM) / SETTLE_EVERY`, at least
/// 1 and at most [`SETTLE_DEEPEST`].
const SETTLE_FROM: usize = 40;

/// ... one depth more for each this many nodes. A settled node refutes or shrinks subtrees
/// that hold no leaf (most of a large plug's tree) where one round of tightening leaves them
/// whole. (Measured on issue 20's plug, `mu = 2`, whole process, 2 cores, one run each,
/// 2026-11-30: m = 50, settling depths 1, 2: 0.33, 0.34 s (12.4k, 8.6k nodes); m = 60, 1, 2:
/// 0.64, 0.95 s (20.3k, 17.4k); m = 80, 1, 2, 3: 6.47, 3.95, 5.95 s (170k, 98k, 67k); m = 100,
/// 1, 2, 3, 4: 54.7, 45.2, 36.0, 86.0 s (961k, 748k, 577k, 325k). Settling every node at
/// m = 60 left 14.2k nodes and took 3.4 s: it does not refute every dead subtree.)
const SETTLE_EVERY: usize = 20;

/// ... and no deeper than this: at m = 120 settling down to depth 4 halved the tree (9.64M
/// nodes to 4.48M) but took 1,051 s against 852 s, its programs so ill-conditioned that
/// 16k of them went to Clarabel (2 without), 10 of those undecided.
const SETTLE_DEEPEST: usize = 3;

/// ... in this many parts ([`node_lp::Settle::InParts`]: each part's programs with the cuts of
/// the parts before it), as `critical`'s passes do. (Measured on issue 20's plug at 2.0,
/// `farm-bench --vs`, parts 3 against 1, paired wall medians: m = 40 1.06 (0.200 against 0.187
/// s), m = 60 0.83 (1.15 against 1.40 s), m = 80 0.91 (11.4 against 12.5 s; 194.5k -> 179.8k
/// nodes); the same pieces.)
const SETTLE_PARTS: usize = 3;

/// What the search found and what it cost.
#[derive(Debug, Default)]
pub(crate) struct Tree {
    /// Leaves found (kept or handed on).
    pub found: u64,
    /// Leaves and search nodes whose program could not be decided (explored as if feasible);
    /// a leaf among them is kept, so nothing is lost, but the run is not certain.
    pub undecided: u64,
    /// Search nodes visited (leaves included).
    pub nodes: u64,
    /// Nodes that inherited their parent's solution.
    pub inherited: u64,
    /// Nodes pruned (their program infeasible).
    pub pruned: u64,
    /// Nodes that tightened the drive bounds.
    pub tightened: u64,
    /// How the search was split, for one shard of it.
    pub shard: Option<ShardReport>,
}

/// What the search does with a leaf's contact set as it finds it (from a worker thread: the
/// enumeration describes the leaf's face there, pattern-search its pattern).
pub(crate) type OnLeaf<'a> = &'a (dyn Fn(Vec<bool>) + Sync);

/// Searches the contact sets of `lp`'s formulation (both 2D search methods), the whole tree or
/// `shard`'s part of it ([`crate::shard`]), reporting the explored share (`done` of `total`)
/// and the leaves found (`rays`) to `progress` from the calling thread. Each leaf goes to
/// `on_leaf` as it is found.
pub(crate) fn search(
    lp: &ContactLp,
    control: &Control,
    shard: Option<Shard>,
    progress: &dyn Fn(Progress),
    on_leaf: OnLeaf,
) -> Tree {
    let search = Search::new(lp, control, on_leaf, vec![Class::Free; lp.form().m]);
    let explored = Explored::new();
    let walk = Walk::new(&search, &explored);
    let report = || {
        progress(Progress {
            done: explored.permille(),
            total: 1000,
            rays: search.leaves_found(),
            nodes: search.nodes.load(Ordering::Relaxed),
        })
    };
    let split = with_progress(|| walk.run(shard), report);
    let mut tree = search.finish();
    tree.shard = split;
    tree
}

/// Whether some solution of the cone of `classes` (contact nodes pressed at once, separated ones
/// with `r = 0`, free ones complementary) presses a free node: the subtree of the search whose
/// root is `classes` has a leaf with a free node in contact. (The maximality test of a
/// `pattern-search` leaf, `patterns/search.rs`: its grazing nodes free.) `Err` when a program
/// of the subtree could not be decided.
pub(crate) fn presses_a_free_node(
    lp: &ContactLp,
    control: &Control,
    classes: &[Class],
) -> Result<bool, String> {
    let free: Vec<usize> = (0..classes.len())
        .filter(|&i| classes[i] == Class::Free)
        .collect();
    let pressed = std::sync::atomic::AtomicBool::new(false);
    let on_leaf = |leaf: Vec<bool>| {
        if free.iter().any(|&i| leaf[i]) {
            pressed.store(true, Ordering::Relaxed);
        }
    };
    let search = Search::new(lp, control, &on_leaf, classes.to_vec());
    let explored = Explored::new();
    Walk::new(&search, &explored).run(None);
    if search.undecided.load(Ordering::Relaxed) > 0 {
        return Err("a program below the leaf could not be decided".into());
    }
    Ok(pressed.into_inner())
}

/// A search node: the class of every node, a solution of its program handed down by the
/// parent (then nothing is solved), the parent's final basis and the cuts known so far.
#[derive(Clone)]
pub(crate) struct Node {
    classes: Vec<Class>,
    inherited: Option<Vec<f64>>,
    warm: Option<Arc<Basis>>,
    drive: Option<Arc<Drive>>,
    /// The bases the last tightening's programs ended at (shelved), by program.
    extremes: Option<Arc<node_lp::Extremes>>,
}

struct Search<'a, 'f> {
    lp: &'a ContactLp<'f>,
    control: &'a Control<'a>,
    m: usize,
    /// Where the leaves go, as they are found.
    on_leaf: OnLeaf<'a>,
    /// Leaves found (kept or handed on).
    found: AtomicU64,
    undecided: AtomicU64,
    nodes: AtomicU64,
    inherited: AtomicU64,
    pruned: AtomicU64,
    /// Search nodes above this depth tighten the drive bounds ([`tighten_depth`]).
    tighten_depth: usize,
    /// ... and those above this one settle them ([`settle_depth`]; `0` but for the whole
    /// search's tree).
    settle_depth: usize,
    /// The root's classes (every node free, or a subtree's for [`presses_a_free_node`]).
    root: Vec<Class>,
    tightened: AtomicU64,
}

impl<'a, 'f> Search<'a, 'f> {
    fn new(
        lp: &'a ContactLp<'f>,
        control: &'a Control<'a>,
        on_leaf: OnLeaf<'a>,
        root: Vec<Class>,
    ) -> Search<'a, 'f> {
        let m = lp.form().m;
        // A floating body's gaps also follow its rigid amplitudes, which the drive cuts do not
        // bound: no cuts (`critical`'s bnb does the same). Nor in a certified run: the cuts
        // rest on floating-point optima that are not kept for an exact check.
        let tighten = if lp.form().modes > 0 || lp.form().refutations.is_some() {
            0
        } else {
            tighten_depth(m)
        };
        let whole = root.iter().all(|&c| c == Class::Free);
        let depths = Depths {
            tighten,
            settle: if whole { settle_depth(m) } else { 0 },
        };
        Search::with_depths(lp, control, on_leaf, root, depths)
    }

    /// [`Search::new`] with the depths given.
    fn with_depths(
        lp: &'a ContactLp<'f>,
        control: &'a Control<'a>,
        on_leaf: OnLeaf<'a>,
        root: Vec<Class>,
        depths: Depths,
    ) -> Search<'a, 'f> {
        let m = lp.form().m;
        Search {
            lp,
            control,
            m,
            on_leaf,
            found: AtomicU64::new(0),
            undecided: AtomicU64::new(0),
            nodes: AtomicU64::new(0),
            inherited: AtomicU64::new(0),
            pruned: AtomicU64::new(0),
            tighten_depth: depths.tighten,
            settle_depth: depths.settle.min(depths.tighten),
            tightened: AtomicU64::new(0),
            root,
        }
    }

    /// Leaves found so far.
    fn leaves_found(&self) -> usize {
        self.found.load(Ordering::Relaxed) as usize
    }

    fn finish(self) -> Tree {
        Tree {
            found: self.found.into_inner(),
            undecided: self.undecided.into_inner(),
            nodes: self.nodes.into_inner(),
            inherited: self.inherited.into_inner(),
            pruned: self.pruned.into_inner(),
            tightened: self.tightened.into_inner(),
            shard: None,
        }
    }
}

impl shard::Tree for Search<'_, '_> {
    type Node = Node;

    /// The tightening nodes: two programs per free node each.
    fn keep_depth(&self) -> usize {
        self.tighten_depth
    }

    /// The problem, `mu` and the tightening depth make every decision (not with `--certify`,
    /// whose refutations are recorded as they are made).
    fn split_key(&self) -> Option<u64> {
        self.lp
            .form()
            .split_key(0x2d5e_a4c8, &[self.tighten_depth as u64])
    }

    fn alarms(&self) -> u64 {
        let undecided = self.undecided.load(Ordering::Relaxed);
        self.lp
            .form()
            .alarms(undecided, self.control.stopped().is_some())
    }

    fn shelve(&self, node: Node) -> Node {
        Node {
            warm: node.warm.map(|w| Arc::new(w.shelved())),
            ..node
        }
    }

    fn is_leaf(&self, node: &Node) -> bool {
        node.classes.iter().all(|&c| c != Class::Free)
    }

    fn root(&self) -> Node {
        Node {
            classes: self.root.clone(),
            inherited: None,
            warm: None,
            drive: None,
            extremes: None,
        }
    }

    /// Decides the node: a prune or a leaf ends its subtree; otherwise its children.
    fn visit(&self, node: Node, depth: usize, rehearsal: bool) -> Option<(Node, Node)> {
        if self.control.must_stop(0) {
            return None;
        }
        let Node {
            classes,
            inherited,
            warm,
            drive,
            mut extremes,
        } = node;
        self.nodes.fetch_add(1, Ordering::Relaxed);
        let m = self.m;
        let contact: Vec<usize> = (0..m).filter(|&i| classes[i] == Class::Contact).collect();
        let free: Vec<usize> = (0..m).filter(|&i| classes[i] == Class::Free).collect();
        if contact.is_empty() && free.is_empty() {
            // Every node separated: only r = 0.
            self.pruned.fetch_add(1, Ordering::Relaxed);
            return None;
        }
        let form = self.lp.form();
        let counters = &self.lp.counters;
        let (mut drive, mut warm, mut inherited) = (drive, warm, inherited);
        if !free.is_empty() && depth < self.tighten_depth {
            // Bound the free nodes' drives over this node's relaxation (with the cuts known so
            // far); the relaxation itself first, whose basis starts every tightening program.
            self.tightened.fetch_add(1, Ordering::Relaxed);
            let shape = Shape {
                mu: form.mu,
                drive: drive.as_ref(),
            };
            // The root of the whole search settles its bounds (every node inherits them), on
            // a problem large enough for it to pay (a random m = 9 problem: 155 programs
            // without, 214 with; the plug: m = 40 even, m = 50 and up faster), and on a larger
            // one the nodes just below it.
            let settle = depth < self.settle_depth;
            let Some((tight, start, kept)) = node_lp::tighten_node(
                form,
                counters,
                &classes,
                shape,
                node_lp::Starts {
                    warm: warm.as_deref(),
                    previous: extremes.as_deref().map(|e| &e[..]),
                    loose: false,
                },
                if settle {
                    node_lp::Settle::InParts {
                        parts: SETTLE_PARTS,
                        until: node_lp::SETTLED,
                    }
                } else {
                    node_lp::Settle::Once
                },
                &|| self.control.must_stop(0),
            ) else {
                self.pruned.fetch_add(1, Ordering::Relaxed);
                return None;
            };
            drive = Some(Arc::new(tight));
            extremes = Some(Arc::new(kept));
            // The inherited solution may break the new cuts: solve again.
            inherited = None;
            warm = start.map(Arc::new);
        }
        let (witness, basis) = match inherited {
            Some(r) => {
                self.inherited.fetch_add(1, Ordering::Relaxed);
                (Some(r), warm)
            }
            None => {
                let norm = if contact.is_empty() {
                    Norm::Sum
                } else {
                    Norm::Pressed(&contact)
                };
                // Towards a vertex: the least total of the free nodes' gaps and pressures (a
                // point at which few free nodes break complementarity, so the branching rule
                // picks well, as in `critical`'s `bnb`).
                let objective = node_lp::vertex_objective(form, &free);
                let shape = Shape {
                    mu: form.mu,
                    drive: drive.as_ref(),
                };
                let (decision, basis) = node_lp::decide(
                    form,
                    counters,
                    &classes,
                    shape,
                    norm,
                    (!free.is_empty()).then_some(&objective[..]),
                    warm.as_deref(),
                );
                let basis = basis.map(Arc::new).or(warm);
                match decision {
                    // In a certified run a prune stands only when its refutation, solved again
                    // by the cone solver, passes its exact check at once (the simplex method's
                    // own certificate, tried first, failed the filter of that check at most
                    // nodes: its basic columns have reduced costs of exactly zero, which exact
                    // arithmetic then decides, 7x slower on the m = 20 plug); otherwise the
                    // subtree is explored further (nothing is lost, so nothing is undecided).
                    Decision::No if form.confirm(&classes, norm).is_err() => (None, basis),
                    Decision::No => {
                        self.pruned.fetch_add(1, Ordering::Relaxed);
                        return None;
                    }
                    Decision::Yes { r, .. } => (Some(r), basis),
                    Decision::Unsure(_) => {
                        self.undecided.fetch_add(1, Ordering::Relaxed);
                        (None, basis)
                    }
                }
            }
        };
        if free.is_empty() {
            let leaf: Vec<bool> = classes.iter().map(|&c| c == Class::Contact).collect();
            if !rehearsal {
                self.found.fetch_add(1, Ordering::Relaxed);
                (self.on_leaf)(leaf);
            }
            return None;
        }
        let branch = match &witness {
            None => free[0],
            Some(r) => {
                let key = |i: usize| {
                    let rn = r[2 * i];
                    let gap = self.lp.form().gap_of(r, i).max(0.0);
                    (gap * rn, rn)
                };
                let order = |a: usize, b: usize| {
                    let (x, y) = (key(a), key(b));
                    x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1))
                };
                free.iter()
                    .copied()
                    .max_by(|&a, &b| order(a, b))
                    .unwrap_or(free[0])
            }
        };
        let (to_contact, to_separated) = match &witness {
            Some(r) => {
                let (gap, rn) = (self.lp.form().gap_of(r, branch), r[2 * branch]);
                let closed = gap.abs() <= INHERIT_ZERO;
                let none = r[2 * branch..2 * branch + 2]
                    .iter()
                    .all(|x| x.abs() <= INHERIT_ZERO);
                (
                    (closed && rn > POSITIVE).then(|| r.clone()),
                    none.then(|| r.clone()),
                )
            }
            None => (None, None),
        };
        let mut contact_child = classes.clone();
        contact_child[branch] = Class::Contact;
        let mut separated_child = classes;
        separated_child[branch] = Class::Separated;
        Some((
            Node {
                classes: contact_child,
                inherited: to_contact,
                warm: basis.clone(),
                drive: drive.clone(),
                extremes: extremes.clone(),
            },
            Node {
                classes: separated_child,
                inherited: to_separated,
                warm: basis,
                drive,
                extremes,
            },
        ))
    }
}

/// How deep a search over all contact sets tightens and settles (the whole search: both
/// [`tighten_depth`] and [`settle_depth`]; a subtree's search settles nowhere).
#[derive(Debug, Clone, Copy)]
struct Depths {
    tighten: usize,
    settle: usize,
}

/// The depth down to which the nodes of a search over all contact sets of a problem of `m`
/// nodes settle their drive bounds (nodes at depths below it settle): none below
/// [`SETTLE_FROM`] nodes, the root from there, one depth more every [`SETTLE_EVERY`] nodes
/// from `SETTLE_FROM + 2 SETTLE_EVERY` on (where it pays, see [`SETTLE_EVERY`]), down to
/// [`SETTLE_DEEPEST`].
pub(crate) fn settle_depth(m: usize) -> usize {
    if m < SETTLE_FROM {
        return 0;
    }
    ((m - SETTLE_FROM) / SETTLE_EVERY).clamp(1, SETTLE_DEEPEST)
}

/// The depth down to which search nodes tighten the drive bounds of a problem of `m` nodes
/// (nodes at depths below it tighten; the rest inherit the bounds; none below
/// [`TIGHTEN_FROM`] nodes).
pub(crate) fn tighten_depth(m: usize) -> usize {
    if m < TIGHTEN_FROM {
        return 0;
    }
    TIGHTEN_DEPTH.max(m.saturating_sub(20) / 20)
}

#[cfg(test)]
mod tests;
