//! Branch and bound for `mu*` over contact sets, with an incumbent.
//!
//! A search node fixes some nodes to contact (`u_n = 0`, friction cone) or separated (`r = 0`,
//! `u_n >= 0`) and relaxes the rest (`u_n >= 0`, friction cone, no complementarity). Its test
//! is one feasibility program at `theta = incumbent (1 - tol)` (at `mu = infinity`, friction
//! unlimited, while there is no incumbent): can every node in contact be pressed at once
//! (`r_n_i >= 1` for all of them; `sum r_n = 1` when none is in contact)?
//!
//! - Infeasible, with a checked Farkas certificate: no solution of the subtree whose contact set
//!   includes the fixed contact nodes exists at `theta` or below. A solution is found at the leaf
//!   of its pressed nodes, and every relaxation on the way there contains it with those nodes
//!   pressed, so the pruned subtree holds none of the solutions that decide `mu*`.
//! - Feasible: branch on the node whose relaxed solution breaks complementarity most.
//! - Undecided (the solver unsure): branch, never prune.
//!
//! A leaf (every node fixed) that passes the test gives a solution of its contact set with every
//! node pressed; its threshold ([`super::Ctx::leaf_threshold`]) is below the incumbent and
//! replaces it. Subtrees run in parallel (`rayon::join`) and share the incumbent.
//!
//! **Drive cuts (not certified).** Nodes down to [`TIGHTEN_DEPTH`] (deeper on larger 3D
//! problems, [`SETTLED_TIGHTEN_DEPTH`] below a settled 2D root) bound the drive of their undecided
//! nodes (again down to [`RETIGHTEN_DEPTH`] when the incumbent has dropped since), and every
//! program below carries the cuts those bounds give ([`crate::conic::cuts`]): a node that
//! presses must not be driven open. From [`SETTLE_FROM`] nodes on, the root repeats its
//! tightening with its own cuts until the bounds settle, as the enumeration's search does; the
//! dive's settled 2D root, rounded, gives the run's first leaf ([`ROUNDED`]). The program then
//! also minimises the undecided nodes' total gap and pressure, so that its point is a vertex
//! rather than a central one. On the 2D plug this cuts the tree by 10x to 50x and the time by
//! 3x to 8x (`BENCHMARKS.md`). In 3D the bounds come from the outer polyhedral relaxation of
//! the node (below), so they hold for its cone program too; on the 3D V-groove plug (m = 20)
//! the tree went from 31k nodes to 13k. (With Clarabel's central points, before the 3D simplex
//! programs, the cuts had made the 3D tree larger: 39k nodes against 12k.) A certified run
//! leaves them out, since its refutations must be checked exactly.
//!
//! **The simplex method (the same searches).** Their programs are linear programs of one
//! shape ([`crate::conic::node_lp`]); each is solved by the in-house simplex method from its parent's
//! basis (the tightening programs from the node's), a few pivots where Clarabel starts over.
//! On the 2D plug with m = 40 that took the search from 18 s to 0.8 s, with m = 60 from 268 s
//! to 7.9 s (`BENCHMARKS.md`). In 3D the program is an outer relaxation (the friction cone
//! inside a polygon's cone): an infeasible one prunes, a feasible one steers the branching,
//! and a leaf is decided by its cone program (Clarabel).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use super::edge::point_above;
use super::improve::{all_contact, improve, leaf_of};
use super::{CriticalInfo, CriticalProgress, Ctx, Found, Leaf};
use crate::conic::cuts::Drive;
use crate::conic::node_lp::{self as lp, LpCounters, Shape, Warm};
use crate::conic::program::{Class, Decision, Formulation, Goal, Norm};
use crate::patterns::Undecided;
use crate::run::{Control, Stop};
use crate::shard::{self, Explored, Shard, Walk};

mod tuning;
pub(super) use tuning::Hooks;
use tuning::{
    bars, DIVE_NODES_PER_NODE, DIVE_SETTLED, PASS_SETTLED, RESTART, RETIGHTEN_DEPTH, ROUNDED,
    SETTLED_TIGHTEN_DEPTH, SETTLE_DEPTH, SETTLE_FROM, SETTLE_PARTS, STALE, TIGHTEN_DEPTH,
};

/// Drive bounds and the level they hold at.
struct Bounds {
    level: f64,
    drive: Arc<Drive>,
}

struct Search<'a, 'b, 'c> {
    ctx: &'a Ctx<'b, 'c>,
    control: &'a Control<'a>,
    /// The incumbent's `theta` as `f64` bits (`INFINITY` before the first leaf).
    incumbent: AtomicU64,
    /// The bar of this pass (see [`run`]) as `f64` bits.
    bar: AtomicU64,
    best: Mutex<Option<Leaf>>,
    /// The least `lower` certified at a leaf.
    leaf_lower: Mutex<f64>,
    undecided: Mutex<Vec<Undecided>>,
    visited: AtomicU64,
    pruned: AtomicU64,
    leaves: AtomicU64,
    /// Whether the nodes' programs are the warm-started linear programs of `conic::node_lp`
    /// (2D, not in a certified run); otherwise Clarabel's.
    simplex: bool,
    /// Whether the search uses drive cuts (with `simplex`, not for a floating body: the cuts
    /// bound a node's gap over the reactions alone, and a floating body's gap also follows its
    /// rigid amplitudes).
    cut: bool,
    tightened: AtomicU64,
    /// 2D problems of this many nodes or more settle the root's bounds ([`SETTLE_FROM`]).
    settle_from: usize,
    /// The root's settled drive bounds, with the level they hold at (as `f64` bits) and the
    /// bases its tightening programs ended at: a pass at the same level starts from them.
    #[allow(clippy::type_complexity)]
    settled: Mutex<Option<(u64, Arc<Drive>, Arc<lp::Extremes>)>>,
    /// The simplex method's counts (the programs of a search with drive cuts).
    lp: LpCounters,
    /// The problem's symmetries ([`crate::Problem::symmetries`]), none in a certified run.
    mirrors: Vec<Vec<usize>>,
    /// Branchings that separated a mirror image too.
    mirrored: AtomicU64,
    /// Whether the present pass is the first leaf's dive ([`DIVE_NODES_PER_NODE`]): the
    /// separated child first, the pass ended at its first leaf or after its budget.
    dive: AtomicBool,
    /// Set to end the present pass at once (a dive that found its leaf or spent its budget):
    /// the pass proves nothing, and the next one starts over.
    end_pass: AtomicBool,
    /// Whether the run's first leaf was improved already ([`improve`]).
    improved: AtomicBool,
    /// The improvement's steps.
    improvement_steps: AtomicU64,
    /// Set with `end_pass` to start the present pass over ([`RESTART`]).
    restart: AtomicBool,
    /// Whether the run looks for a first leaf by a dive and improves it (not certified, not
    /// in shards: their passes must split the tree alike).
    heuristic: bool,
}

impl Search<'_, '_, '_> {
    fn form(&self) -> &Formulation<'_> {
        self.ctx.form
    }

    fn incumbent(&self) -> f64 {
        f64::from_bits(self.incumbent.load(Ordering::Relaxed))
    }

    /// The friction coefficient at which nodes are tested now.
    fn level(&self) -> f64 {
        let best = self.incumbent();
        let bar = f64::from_bits(self.bar.load(Ordering::Relaxed));
        if best.is_finite() {
            (best * (1.0 - self.ctx.tol)).min(bar)
        } else {
            bar
        }
    }

    /// Nodes down to this depth tighten the drive bounds.
    fn tighten_depth(&self) -> usize {
        let m = self.form().m;
        match self.form().dim {
            2 if self.settles() => SETTLED_TIGHTEN_DEPTH,
            2 => TIGHTEN_DEPTH,
            _ => crate::conic::cuts::tighten_depth_3d(m),
        }
    }

    /// Offers a leaf found by the search (`own`: one of its tree's, with its certified lower
    /// end) or by rounding the dive's root ([`ROUNDED`]); the run's first one (and where the
    /// root settles, every new best one) is improved first ([`improve`]), and a dive ends at
    /// it.
    fn found(&self, leaf: Leaf, own: bool) {
        if self.dive.load(Ordering::Relaxed) {
            self.end_pass.store(true, Ordering::Relaxed);
        }
        // Where the root settles (2D and 3D), every new best leaf is improved too: on the 2D plug
        // at m = 140 the rounded leaf's local search stops at 1.7996, 3% above `mu*`, and the
        // pass's first leaf below it improves to about `mu*` (without, the pass crawled down
        // through 38 leaves in 110 s).
        let again = self.settles() && leaf.theta < self.incumbent();
        if self.heuristic && (!self.improved.swap(true, Ordering::Relaxed) || again) {
            let (better, steps) = improve(self.ctx, &self.lp, self.control, leaf.clone());
            self.improvement_steps
                .fetch_add(steps as u64, Ordering::Relaxed);
            if steps > 0 {
                // An improved leaf is made exact with its threshold's certified lower end.
                self.offer(better);
            }
        }
        if own {
            self.offer(leaf);
            self.check_restart();
        } else {
            // A rounded leaf's lower end is its bisection's, in floating point: offered
            // without it, as the all-contact leaf is.
            self.offer_start(leaf);
        }
    }

    /// The dive's first leaf by rounding the root's relaxed solution `r` (see [`ROUNDED`]):
    /// the contact set of the nodes pressed by more than that fraction of the most pressed.
    fn rounded(&self, r: &[f64], level: f64) {
        let d = self.form().dim;
        let m = self.form().m;
        let most = (0..m).map(|i| r[d * i]).fold(0.0, f64::max);
        let contact: Vec<bool> = (0..m).map(|i| r[d * i] > ROUNDED * most).collect();
        if most > 0.0 {
            if let Some(leaf) = leaf_of(self.ctx, &self.lp, self.control, contact, level) {
                self.found(leaf, false);
            }
        }
    }

    /// Whether the root settles its bounds ([`SETTLE_FROM`]).
    fn settles(&self) -> bool {
        self.form().m >= self.settle_from
    }

    /// Ends the present pass to start it over ([`RESTART`]) when the incumbent has dropped
    /// that far below the level its root settled at.
    fn check_restart(&self) {
        if !self.heuristic || self.dive.load(Ordering::Relaxed) || !self.settles() {
            return;
        }
        let at = self
            .settled
            .lock()
            .ok()
            .and_then(|c| c.as_ref().map(|c| f64::from_bits(c.0)));
        if at.is_some_and(|at| at > self.level() * (1.0 + RESTART)) {
            self.restart.store(true, Ordering::Relaxed);
            self.end_pass.store(true, Ordering::Relaxed);
        }
    }

    fn offer(&self, leaf: Leaf) {
        {
            let mut low = self.leaf_lower.lock().expect("no panics while held");
            *low = low.min(leaf.lower);
        }
        self.offer_start(leaf);
    }

    /// Offers a leaf found outside the search (the all-contact set's, [`all_contact`]) as the
    /// incumbent, without its lower end: the search decides that set's own leaf in its tree
    /// like any other (refuted at the level, or its threshold computed there), so the proof
    /// needs no bracket of it, and its bisection's (`1e-7`) would widen the run's.
    fn offer_start(&self, leaf: Leaf) {
        let mut best = self.best.lock().expect("no panics while held");
        if best.as_ref().is_none_or(|b| leaf.theta < b.theta) {
            self.incumbent
                .store(leaf.theta.to_bits(), Ordering::Relaxed);
            *best = Some(leaf);
        }
    }

    fn undecided(&self, contact: Vec<bool>, reason: String) {
        self.undecided
            .lock()
            .expect("no panics while held")
            .push(Undecided { contact, reason });
    }
}

/// A search node: the class of every node, the drive bounds known so far and the parent's
/// final basis.
#[derive(Clone)]
struct Node {
    classes: Vec<Class>,
    drive: Option<Arc<Bounds>>,
    warm: Option<Arc<Warm>>,
    /// The bases the parent's tightening programs ended at (shelved), by program.
    extremes: Option<Arc<lp::Extremes>>,
}

impl shard::Tree for Search<'_, '_, '_> {
    type Node = Node;

    fn is_leaf(&self, node: &Node) -> bool {
        node.classes.iter().all(|&c| c != Class::Free)
    }

    fn root(&self) -> Node {
        Node {
            classes: vec![Class::Free; self.form().m],
            drive: None,
            warm: None,
            extremes: None,
        }
    }

    /// The tightening nodes (two programs per undecided node each).
    fn keep_depth(&self) -> usize {
        if self.cut {
            self.tighten_depth() + 1
        } else {
            0
        }
    }

    fn shelve(&self, node: Node) -> Node {
        Node {
            warm: node.warm.map(|w| Arc::new(w.shelved())),
            ..node
        }
    }

    /// Decides the node (a leaf: its threshold, offered as the incumbent; not in a rehearsal,
    /// which leaves leaves alone); returns its children unless it is pruned or a leaf.
    fn visit(&self, node: Node, depth: usize, rehearsal: bool) -> Option<(Node, Node)> {
        if self.control.must_stop(0) || self.end_pass.load(Ordering::Relaxed) {
            return None;
        }
        if self.dive.load(Ordering::Relaxed)
            && self.visited.load(Ordering::Relaxed) >= DIVE_NODES_PER_NODE * self.form().m as u64
        {
            self.end_pass.store(true, Ordering::Relaxed);
            return None;
        }
        let Node {
            classes,
            drive,
            warm,
            extremes,
        } = node;
        let mut extremes = extremes;
        let m = self.form().m;
        let contact: Vec<usize> = (0..m).filter(|&i| classes[i] == Class::Contact).collect();
        let free: Vec<usize> = (0..m).filter(|&i| classes[i] == Class::Free).collect();
        if free.is_empty() && (contact.is_empty() || rehearsal) {
            // Every node separated: only the trivial solution. (Or a leaf in a rehearsal.)
            return None;
        }
        let level = self.level();
        let norm = if contact.is_empty() {
            Norm::Sum
        } else {
            Norm::Pressed(&contact)
        };
        self.visited.fetch_add(1, Ordering::Relaxed);
        let mut drive = drive;
        let mut warm = warm;
        let stale = drive
            .as_ref()
            .is_some_and(|b| b.level > level * (1.0 + STALE));
        if self.cut
            && !free.is_empty()
            && level.is_finite()
            && (depth <= self.tighten_depth() || (stale && depth <= RETIGHTEN_DEPTH))
        {
            self.tightened.fetch_add(1, Ordering::Relaxed);
            let known = drive.as_ref().map(|b| &b.drive);
            let shape = Shape {
                mu: level,
                drive: known,
            };
            // The root of a search of [`SETTLE_FROM`] nodes or more settles its bounds (the
            // tightening repeated with its own cuts, `lp::tighten_node`), and so do its
            // children ([`SETTLE_DEPTH`]); every node inherits them: on the 2D plug at m = 80
            // the tree went from 72k nodes to 7.1k and the run from 13.3 s to 5.4 s, at m =
            // 100 from 427k nodes to 30k and 84 s to 23 s (`BENCHMARKS.md`). (Measured before
            // loose rows were left out of the node programs, on 2026-11-26, the tree at m = 60
            // and 80 had been the same.) 3D too since each node's bounds impose its own
            // complementarity (`cuts::tighten`; the 3D numbers at [`SETTLE_FROM`]). A root
            // settled at the same level before (the dive's, when it found no leaf) is taken
            // as it is.
            let root = depth == 0 && classes.iter().all(|&c| c == Class::Free);
            let settle = depth <= SETTLE_DEPTH && self.settles();
            // A root settled before at a higher level (the dive's, whose leaf lowered the
            // level) starts this one's settling: its bounds hold here too (the relaxation at a
            // lower `mu` lies inside the one above), and its programs' last bases start these.
            // (On the 2D plug at m = 100 the pass's root then settled in 0.65 s against 1.43
            // s; m = 120 6.4 -> 4.5 s to the end of its root.)
            let settled = self.settled.lock().ok().and_then(|c| c.clone());
            let cached = settled.clone().filter(|c| root && c.0 == level.to_bits());
            let above = settled.filter(|c| root && f64::from_bits(c.0) > level);
            let shape = Shape {
                drive: above.as_ref().map(|c| &c.1).or(shape.drive),
                ..shape
            };
            let previous = match &above {
                Some(c) => Some(&c.2[..]),
                None => extremes.as_deref().map(|e| &e[..]),
            };
            let tight = match cached {
                Some((_, tight, kept)) => {
                    extremes = Some(kept);
                    Some(tight)
                }
                None => lp::tighten_node(
                    self.form(),
                    &self.lp,
                    &classes,
                    shape,
                    lp::Starts {
                        warm: warm.as_deref(),
                        previous,
                        loose: true,
                    },
                    match (settle, self.dive.load(Ordering::Relaxed)) {
                        (false, _) => lp::Settle::Once,
                        (true, true) => lp::Settle::InParts {
                            parts: 1,
                            until: DIVE_SETTLED,
                        },
                        (true, false) => lp::Settle::InParts {
                            parts: SETTLE_PARTS,
                            until: PASS_SETTLED,
                        },
                    },
                    &|| self.control.must_stop(0),
                )
                .map(|(tight, _, kept)| {
                    let (tight, kept) = (Arc::new(tight), Arc::new(kept));
                    if root && settle && !self.control.must_stop(0) {
                        if let Ok(mut c) = self.settled.lock() {
                            *c = Some((level.to_bits(), tight.clone(), kept.clone()));
                        }
                    }
                    extremes = Some(kept);
                    tight
                }),
            };
            match tight {
                Some(tight) => {
                    drive = Some(Arc::new(Bounds {
                        level,
                        drive: tight,
                    }))
                }
                None => {
                    self.ctx.tally.certificates.fetch_add(1, Ordering::Relaxed);
                    self.pruned.fetch_add(1, Ordering::Relaxed);
                    return None;
                }
            }
        }
        let mut decision = if self.simplex {
            // Towards a vertex: the least total of the undecided nodes' gaps and pressures.
            // (An interior-point solver returns a central point, at which many nodes break
            // complementarity a little, and the branching rule picks worse: on the 2D plug
            // with m = 40 and Clarabel, 2.9k nodes and 17 s with this objective, 5.6k and 20 s
            // without.)
            let objective = lp::vertex_objective(self.form(), &free);
            let shape = Shape {
                mu: level,
                drive: drive.as_ref().map(|b| &b.drive),
            };
            // An inner node's program only prunes or guides the branching (`lp::decide_inner`).
            let decide = if free.is_empty() {
                lp::decide
            } else {
                lp::decide_inner
            };
            let (decision, basis) = decide(
                self.form(),
                &self.lp,
                &classes,
                shape,
                norm,
                (!free.is_empty()).then_some(&objective[..]),
                warm.as_deref(),
            );
            // A program left to Clarabel has no basis: the children start from the parent's.
            // (From the slack basis they failed as their parent had, and so on down the
            // subtree: on the 2D plug at m = 200, 59 of the 61 programs left to Clarabel.)
            warm = basis.map(Arc::new).or(warm);
            decision
        } else {
            self.form().decide_at(&classes, level, norm, Goal::Feasible)
        };
        if self.simplex && free.is_empty() && self.form().dim == 3 && decision != Decision::No {
            // A 3D leaf that its linear program (an outer relaxation, `conic::node_lp`) does
            // not refute is decided by its cone program. (Most leaves are refuted: on the 3D
            // V-groove plug with m = 40, 31k leaves asked Clarabel before this screen.)
            decision = self.form().decide_at(&classes, level, norm, Goal::Feasible);
        }
        if free.is_empty() && matches!(decision, Decision::Unsure(_)) {
            // The same question cut the other way: any nontrivial solution of the leaf. Its
            // infeasibility is the stronger certificate; a solution of it is as good a start.
            decision = self
                .form()
                .decide_at(&classes, level, Norm::Sum, Goal::Feasible);
        }
        if free.is_empty() {
            self.leaves.fetch_add(1, Ordering::Relaxed);
            let set: Vec<bool> = classes.iter().map(|&c| c == Class::Contact).collect();
            match decision {
                Decision::No => {
                    self.ctx.tally.certificates.fetch_add(1, Ordering::Relaxed);
                    self.pruned.fetch_add(1, Ordering::Relaxed);
                }
                Decision::Unsure(why) => self.undecided(set, why),
                Decision::Yes { r, .. } => match self
                    .ctx
                    .exact_point(&set, &r, level)
                    .or_else(|| point_above(self.ctx, &set, level))
                {
                    None => self.undecided(
                        set,
                        "the solver's point could not be made an exact solution".into(),
                    ),
                    Some((theta, p)) => {
                        let cap = || self.level();
                        match self.ctx.leaf_threshold(&set, theta, p, self.control, &cap) {
                            Ok(Some(leaf)) => self.found(leaf, true),
                            Ok(None) => {
                                self.pruned.fetch_add(1, Ordering::Relaxed);
                            }
                            Err(_) if self.control.stopped().is_some() => {}
                            Err(why) => self.undecided(set, why),
                        }
                    }
                },
            }
            return None;
        }
        let witness = match decision {
            Decision::No => {
                self.ctx.tally.certificates.fetch_add(1, Ordering::Relaxed);
                self.pruned.fetch_add(1, Ordering::Relaxed);
                return None;
            }
            Decision::Yes { r, .. } => Some(r),
            Decision::Unsure(_) => None,
        };
        if let Some(r) = witness
            .as_ref()
            .filter(|_| depth == 0 && self.form().dim == 2 && self.dive.load(Ordering::Relaxed))
        {
            self.rounded(r, level);
            if self.end_pass.load(Ordering::Relaxed) {
                return None;
            }
        }
        Some(self.branch(classes, witness, &free, drive, warm, extremes))
    }
}

impl Search<'_, '_, '_> {
    /// The children of a node: the free node whose relaxed solution breaks complementarity
    /// most, in contact and separated.
    fn branch(
        &self,
        classes: Vec<Class>,
        witness: Option<Vec<f64>>,
        free: &[usize],
        drive: Option<Arc<Bounds>>,
        warm: Option<Arc<Warm>>,
        extremes: Option<Arc<lp::Extremes>>,
    ) -> (Node, Node) {
        let branch = match &witness {
            None => free[0],
            Some(r) => {
                let d = self.form().dim;
                // (Measured: this rule against "most pressed first" on the plugs: 2D m = 16, 24:
                // 0.9k and 7.6k nodes against 1.3k and 4.8k; 3D m = 20: 15k against 23k.)
                let key = |i: usize| {
                    let rn = r[d * i];
                    let gap = self.form().gap_of(r, i).max(0.0);
                    (gap * rn, rn)
                };
                free.iter()
                    .copied()
                    .max_by(|&a, &b| {
                        let (x, y) = (key(a), key(b));
                        x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1))
                    })
                    .unwrap_or(free[0])
            }
        };
        // Orbital branching: at a node whose classes a symmetry keeps, a solution with the
        // branch node separated and its image pressed has an image (the same friction ratios,
        // in this node's subtree) with the branch node pressed, which the first child holds;
        // so the second child separates the image too, for every symmetry that keeps the
        // classes at once (each such solution is covered by its own symmetry's image).
        let images: Vec<usize> = self
            .mirrors
            .iter()
            .filter(|s| s.iter().enumerate().all(|(i, &j)| classes[j] == classes[i]))
            .map(|s| s[branch])
            .filter(|&j| j != branch)
            .collect();
        let mut to_contact = classes.clone();
        to_contact[branch] = Class::Contact;
        let mut to_separated = classes;
        to_separated[branch] = Class::Separated;
        for &image in &images {
            to_separated[image] = Class::Separated;
        }
        if !images.is_empty() {
            self.mirrored.fetch_add(1, Ordering::Relaxed);
        }
        let contact = Node {
            classes: to_contact,
            drive: drive.clone(),
            warm: warm.clone(),
            extremes: extremes.clone(),
        };
        let separated = Node {
            classes: to_separated,
            drive,
            warm,
            extremes,
        };
        if self.dive.load(Ordering::Relaxed) {
            (separated, contact)
        } else {
            (contact, separated)
        }
    }
}

/// Runs the search; progress is reported from the calling thread every 200 ms. `hooks`: the
/// tests' ([`Hooks`]), none in use.
pub(super) fn run(
    ctx: &Ctx,
    info: &mut CriticalInfo,
    (shard, start): (Option<Shard>, Option<&[bool]>),
    progress: &dyn Fn(CriticalProgress),
    control: &Control,
    hooks: Hooks,
) -> Found {
    let Hooks {
        halt,
        settle_always,
    } = hooks;
    let search = Search {
        ctx,
        control,
        incumbent: AtomicU64::new(f64::INFINITY.to_bits()),
        bar: AtomicU64::new(f64::INFINITY.to_bits()),
        best: Mutex::new(None),
        leaf_lower: Mutex::new(f64::INFINITY),
        undecided: Mutex::new(Vec::new()),
        visited: AtomicU64::new(0),
        pruned: AtomicU64::new(0),
        leaves: AtomicU64::new(0),
        simplex: ctx.form.refutations.is_none(),
        cut: ctx.form.refutations.is_none() && ctx.form.modes == 0,
        tightened: AtomicU64::new(0),
        settle_from: if settle_always { 0 } else { SETTLE_FROM },
        settled: Mutex::new(None),
        lp: LpCounters::default(),
        // Not in a certified run: the subtrees it skips have no refutation to check.
        mirrors: if ctx.form.refutations.is_none() {
            ctx.form.problem.symmetries()
        } else {
            Vec::new()
        },
        mirrored: AtomicU64::new(0),
        dive: AtomicBool::new(false),
        end_pass: AtomicBool::new(false),
        improved: AtomicBool::new(false),
        improvement_steps: AtomicU64::new(0),
        restart: AtomicBool::new(false),
        heuristic: ctx.form.refutations.is_none() && shard.is_none(),
    };
    let explored = Explored::new();
    // The nodes visited before the present pass.
    let before = AtomicU64::new(0);
    // The lower end proved by the finished passes, as `f64` bits (0: none yet), read by the
    // progress line while the passes run.
    let proved_bits = AtomicU64::new(0);
    let proved = |bits: u64| Some(f64::from_bits(bits)).filter(|&l| l > 0.0);
    let report = || {
        let best = search.incumbent();
        let bar = f64::from_bits(search.bar.load(Ordering::Relaxed));
        progress(CriticalProgress {
            explored: explored.fraction(),
            upper: best.is_finite().then_some(best),
            nodes: search
                .visited
                .load(Ordering::Relaxed)
                .saturating_sub(before.load(Ordering::Relaxed)),
            bar: bar.is_finite().then_some(bar),
            lower: proved(proved_bits.load(Ordering::Relaxed)),
            condensed: None,
            programs: search.lp.solves.load(Ordering::Relaxed),
        });
    };
    // A pass per bar; each shard's passes split their trees alike (see `crate::shard`: the
    // top is decided at the bar, before any leaf).
    let (split, dive_nodes) = crate::run::with_progress(
        || {
            let mut split = None;
            let mut dived = 0;
            if search.heuristic && !control.must_stop(0) {
                // The all-contact set's leaf is the incumbent until the search finds a better
                // one (offered as it is: the search's first leaf is the one improved). In 2D
                // first: a few linear programs, the incumbent where the dive's rounded root
                // gives none ([`ROUNDED`]); the 2D dive finds no leaf of its own from m = 80 on.
                // In 3D only when the dive finds none: its threshold needs cone programs (on
                // the V-groove at m = 40, 36 of them and 1.18x the run's time), and the dive
                // finds a leaf there in about 130 nodes.
                let first = |search: &Search| {
                    if let Some(leaf) = all_contact(ctx, &search.lp, control, ctx.form.mu) {
                        search.offer_start(leaf);
                    }
                };
                if ctx.form.dim == 2 {
                    first(&search);
                }
                // The caller's start (`CriticalSettings::start`): its leaf, improved as the
                // run's first (`found`), replaces the dive, which on the 2D plug at m = 400
                // found nothing below such a leaf in its 4,000 nodes.
                let started = start
                    .and_then(|s| leaf_of(ctx, &search.lp, control, s.to_vec(), ctx.form.mu))
                    .map(|leaf| search.found(leaf, false))
                    .is_some();
                // The dive: the first bar's tree, the separated child first, ended at its
                // first leaf (improved by `found`) or after its budget. It proves nothing; the
                // passes below start over with its leaf as the incumbent.
                if !started {
                    search.dive.store(true, Ordering::Relaxed);
                    search.bar.store(ctx.form.mu.to_bits(), Ordering::Relaxed);
                    explored.reset();
                    Walk::new(&search, &explored).run(None);
                    search.dive.store(false, Ordering::Relaxed);
                    search.end_pass.store(false, Ordering::Relaxed);
                }
                dived = search.visited.load(Ordering::Relaxed);
                if ctx.form.dim != 2 && search.best.lock().is_ok_and(|b| b.is_none()) {
                    first(&search);
                }
            }
            for bar in bars(ctx.form.mu) {
                search.bar.store(bar.to_bits(), Ordering::Relaxed);
                before.store(search.visited.load(Ordering::Relaxed), Ordering::Relaxed);
                let undecided = search.undecided.lock().map_or(0, |u| u.len());
                explored.reset();
                split = Walk::new(&search, &explored).run(shard);
                // A pass ended for a restart proved nothing: it starts over at the same bar
                // with the lower incumbent, and what it left undecided is decided again.
                while search.restart.swap(false, Ordering::Relaxed) && !control.must_stop(0) {
                    search.end_pass.store(false, Ordering::Relaxed);
                    if let Ok(mut u) = search.undecided.lock() {
                        u.truncate(undecided);
                    }
                    explored.reset();
                    split = Walk::new(&search, &explored).run(shard);
                }
                // Done once the incumbent set this pass's level (it lies at or below the bar):
                // then everything below `incumbent (1 - tol)` is refuted. An incumbent above
                // the bar (the all-contact leaf, not the search's) leaves the pass a proof
                // that `mu* > bar`, and the next bar follows.
                let found = search
                    .best
                    .lock()
                    .map_or(true, |b| b.as_ref().is_some_and(|b| b.theta <= bar));
                if found || control.stopped().is_some() {
                    break;
                }
                // The pass ran to its end and found no leaf at or below its bar: every node
                // was refuted at the level or above (the level only falls during a pass), and
                // every leaf offered has its own lower end, so `mu*` lies above the lesser.
                // Kept for a run stopped later; not when the solver left a node undecided.
                // (The last pass, with no bar, ends the loop: the body never wedges.)
                if search.undecided.lock().map_or(0, |u| u.len()) == undecided {
                    let leaf_lower = search.leaf_lower.lock().map_or(0.0, |l| *l);
                    let level = search.level().min(leaf_lower);
                    if level.is_finite() {
                        proved_bits.store(level.to_bits(), Ordering::Relaxed);
                    }
                }
                if halt && bar.is_finite() {
                    control.halt(Stop::Interrupted);
                    break;
                }
            }
            (split, dived)
        },
        report,
    );
    info.nodes_visited = search.visited.into_inner();
    info.pruned_infeasible = search.pruned.into_inner();
    info.leaves_solved = search.leaves.into_inner();
    info.bound_tightenings = search.tightened.into_inner();
    info.mirrored = search.mirrored.into_inner();
    info.dive_nodes = dive_nodes;
    info.improvement_steps = search.improvement_steps.into_inner();
    info.simplex_solves = search.lp.solves.into_inner();
    info.simplex_fallbacks = search.lp.fallbacks.into_inner();
    info.simplex_relaxed = search.lp.relaxed.into_inner();
    let best = search.best.into_inner().unwrap_or(None);
    let leaf_lower = search.leaf_lower.into_inner().unwrap_or(f64::INFINITY);
    // Every prune of the last pass was at min(bar, incumbent (1 - tol)) or above.
    let bar = f64::from_bits(search.bar.into_inner());
    let lower = best.as_ref().map_or(0.0, |b| {
        (b.theta * (1.0 - ctx.tol)).min(leaf_lower).min(bar)
    });
    Found {
        best,
        lower,
        thresholds: Vec::new(),
        undecided: search.undecided.into_inner().unwrap_or_default(),
        stop: None,
        shard: split,
        proved: proved(proved_bits.into_inner()),
    }
}
