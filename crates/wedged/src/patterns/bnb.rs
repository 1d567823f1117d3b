//! Branch and bound over the contact sets (MISSION section 5, second method).
//!
//! A search node fixes some nodes to contact (`u_n = 0`, friction cone) or separated (`r = 0`,
//! `u_n >= 0`) and relaxes the rest (`u_n >= 0`, friction cone, no complementarity). Its
//! relaxation maximises the smallest pressure of the nodes in contact, with `sum r_n = 1`. The
//! subtree is pruned when
//! - the relaxation is infeasible (no nontrivial solution below it), or
//! - its optimum is zero: some node in contact cannot be pressed, so every leaf below has a node
//!   in its contact set that is only ever grazing; such a leaf's pattern is never maximal,
//!   because the maximal pattern `q` is found at the leaf whose contact set is exactly the pressed
//!   nodes of `q`, and every relaxation above that leaf contains `q`'s witness.
//!
//! **Programs.** Without `--certify` an inner node's program is the warm-started simplex
//! method's ([`crate::conic::node_lp`]) with the nodes in contact pressed (`r_n_i >= 1`, the
//! total at most `1 / POSITIVE`), which is infeasible exactly when one of the two prunes above
//! applies, and which minimises the free nodes' gaps and pressures (a vertex for the branching
//! rule). In 3D that program is an outer polyhedral relaxation of the friction cone: its
//! refutation prunes the cone program too, its point only steers the branching. Nodes near the
//! root bound their free nodes' drives and hand the cuts down ([`crate::conic::cuts`], not for a
//! floating body). A leaf's pattern is always the cone program's. On the 3D V-groove plug
//! (m = 20, 1.2 `mu*`, 592 patterns) that took the whole run from 28 s (every node Clarabel's)
//! to about 4 s (`BENCHMARKS.md`). A certified run decides every node by Clarabel, as below.
//!
//! An undecided relaxation (the solver unsure) never prunes. A leaf (every node fixed) yields its
//! realised pattern ([`super::leaf_pattern`]). The next node to branch on is the one whose
//! relaxed solution breaks complementarity most (largest scaled `u_n r_n`); then the one pressed
//! most. The two subtrees run in parallel (`rayon::join`).

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use super::leaf::Leaf;
use super::orbits::Group;
use super::{leaf_pattern, Found, PatternInfo, Undecided};
use crate::conic::cuts::Drive;
use crate::conic::node_lp::{self as lp, LpCounters, Shape, Warm};
use crate::conic::program::{
    Class, Counters, Decision, Entry, Formulation, Goal, Norm, Support, POSITIVE,
};
use crate::rays::Progress;
use crate::run::Control;
use crate::shard::{self, Explored, Shard, Walk};
use crate::solution::ContactPattern;

/// A witness's gap or reaction component at most this (with `sum r_n = 1`) counts as zero when
/// deciding whether a child can inherit it: the solver's accuracy, far below [`POSITIVE`].
const INHERIT_ZERO: f64 = 1e-9;

/// Where a streamed search ([`run`]'s `stream`) hands each orbit of realised patterns without
/// grazing nodes (each maximal: such a pattern lies below no other) as soon as its first leaf
/// is decided: the orbit's patterns (sorted), the realised pattern of the orbit's least contact
/// set, and that pattern's witness when its leaf's program made one.
pub(super) type OrbitSink<'a> =
    &'a (dyn Fn(Vec<Vec<ContactPattern>>, Vec<ContactPattern>, Option<Support>) + Sync);

/// What a streamed search knows of an orbit, by its least contact set (as a whole pattern).
#[derive(Clone, Copy, PartialEq)]
enum Orbited {
    /// Its first leaf is being decided.
    Pending,
    /// Handed on to the sink.
    Streamed,
    /// Not realised, undecided, or kept for the finishing step (grazing nodes).
    Other,
}

struct Search<'a, 'b> {
    form: &'a Formulation<'b>,
    control: &'a Control<'a>,
    found: Mutex<Vec<Vec<ContactPattern>>>,
    /// The witnesses that leaves' programs made, for the finishing step.
    witnesses: Mutex<HashMap<Vec<ContactPattern>, Support>>,
    undecided: Mutex<Vec<Undecided>>,
    visited: AtomicU64,
    inherited: AtomicU64,
    pruned_infeasible: AtomicU64,
    pruned_unpressed: AtomicU64,
    leaves: AtomicU64,
    /// Whether the inner nodes' programs are the warm-started linear programs of
    /// `conic::node_lp` (not in a certified run, whose prunes must be checked exactly).
    simplex: bool,
    lp: LpCounters,
    /// Search nodes above this depth bound their free nodes' drives ([`crate::conic::cuts`],
    /// as the 2D `pattern-search` does); `0` without the simplex method or for a floating body.
    tighten_depth: usize,
    tightened: AtomicU64,
    /// The problem's symmetries, for orbital branching ([`super::orbits`]); none in a
    /// certified or a sharded run (a skipped region's images come from another subtree).
    symmetries: Vec<Vec<usize>>,
    /// The branchings that skipped a region.
    mirrored: AtomicU64,
    /// The group by whose orbits the finishing step maps witnesses ([`Group::of`]),
    /// for the leaves ([`Search::leaf`]); empty in a certified run.
    group: Group,
    /// The leaves decided so far that are their orbits' least, by contact set (as a whole
    /// pattern): the realised pattern, none, or why undecided.
    least_leaves: Mutex<HashMap<Vec<ContactPattern>, LeafOutcome>>,
    /// Leaves decided as images.
    mapped: AtomicU64,
    /// Realised patterns found (for the progress line and [`PatternInfo::realised`]).
    realised: AtomicU64,
    /// A streamed search's sink (not in a certified or a sharded run), the group of the
    /// symmetries of the orbital branching (whose orbits a streamed search hands on, and by
    /// which a kept one completes its patterns at the end), each streamed orbit's state, and
    /// the patterns handed on with an orbit's first leaf that were not that leaf's own.
    stream: Option<OrbitSink<'a>>,
    orbit_group: Group,
    streamed_orbits: Mutex<HashMap<Vec<ContactPattern>, Orbited>>,
    images: AtomicU64,
}

/// A leaf's realised pattern, none, or why it was not decided.
type LeafOutcome = Result<Option<Vec<ContactPattern>>, String>;

/// A search node: the class of every node and, perhaps, a solution of its relaxation passed
/// down from the parent, whose smallest pressure over the nodes in contact is positive: the
/// node is then not pruned, which is always safe, and its program is not solved.
#[derive(Clone)]
struct Node {
    classes: Vec<Class>,
    inherited: Option<Vec<f64>>,
    /// The last basis of the linear programs on the way here.
    warm: Option<Arc<Warm>>,
    /// The drive bounds known so far (see [`Search::tighten_depth`]).
    drive: Option<Arc<Drive>>,
    /// The bases the last tightening's programs ended at (shelved), by program.
    extremes: Option<Arc<lp::Extremes>>,
}

impl shard::Tree for Search<'_, '_> {
    type Node = Node;

    /// The problem and `mu` make every decision (not with `--certify`, whose refutations are
    /// recorded as they are made).
    fn split_key(&self) -> Option<u64> {
        self.form.split_key(0xb4b_5ea4c, &[])
    }

    fn alarms(&self) -> u64 {
        let uncertain = Counters::get(&self.form.counters.uncertain);
        self.form
            .alarms(uncertain, self.control.stopped().is_some())
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
            classes: vec![Class::Free; self.form.m],
            inherited: None,
            warm: None,
            drive: None,
            extremes: None,
        }
    }

    /// Decides the node: a leaf or a prune ends its subtree; otherwise its children.
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
        let m = self.form.m;
        let press: Vec<Entry> = (0..m)
            .filter(|&i| classes[i] == Class::Contact)
            .map(Entry::Press)
            .collect();
        let free: Vec<usize> = (0..m).filter(|&i| classes[i] == Class::Free).collect();
        if free.is_empty() {
            if rehearsal {
                // The shard's own walk decides it again.
                return None;
            }
            let contact: Vec<bool> = classes.iter().map(|&c| c == Class::Contact).collect();
            self.leaves.fetch_add(1, Ordering::Relaxed);
            if self.simplex
                && !press.is_empty()
                && self.pressed_set_refuted(&classes, &drive, &warm)
            {
                // No solution presses every contact node (the unpressed prune, at the leaf).
                self.pruned_unpressed.fetch_add(1, Ordering::Relaxed);
                return None;
            }
            if let Some(stream) = self.stream {
                self.stream_leaf(&contact, stream);
                return None;
            }
            match self.leaf(&contact) {
                Ok(Some(leaf)) => {
                    self.keep_witness(&leaf.pattern, leaf.witness);
                    self.realised.fetch_add(1, Ordering::Relaxed);
                    self.found
                        .lock()
                        .expect("no panics while held")
                        .push(leaf.pattern)
                }
                Ok(None) => {}
                Err(reason) => self
                    .undecided
                    .lock()
                    .expect("no panics while held")
                    .push(Undecided { contact, reason }),
            }
            return None;
        }
        let goal = if press.is_empty() {
            Goal::Feasible
        } else {
            Goal::MaxMin(&press)
        };
        self.visited.fetch_add(1, Ordering::Relaxed);
        let (mut warm, mut drive, mut inherited) = (warm, drive, inherited);
        if depth < self.tighten_depth {
            // Bound the free nodes' drives over this node's relaxation (with the cuts known so
            // far); an infeasible relaxation prunes.
            self.tightened.fetch_add(1, Ordering::Relaxed);
            let shape = Shape {
                mu: self.form.mu,
                drive: drive.as_ref(),
            };
            // The root settles its bounds (3D V-groove plug, m = 20, `enumerate` at 1.2 `mu*`:
            // 25.2k nodes and 3.8 s without, 23.0k and 3.3 s with).
            let settle = depth == 0 && classes.iter().all(|&c| c == Class::Free);
            let Some((tight, start, kept)) = lp::tighten_node(
                self.form,
                &self.lp,
                &classes,
                shape,
                lp::Starts {
                    warm: warm.as_deref(),
                    previous: extremes.as_deref().map(|e| &e[..]),
                    loose: false,
                },
                if settle {
                    lp::Settle::InParts {
                        parts: 1,
                        until: lp::SETTLED,
                    }
                } else {
                    lp::Settle::Once
                },
                &|| self.control.must_stop(0),
            ) else {
                self.pruned_infeasible.fetch_add(1, Ordering::Relaxed);
                return None;
            };
            drive = Some(Arc::new(tight));
            extremes = Some(Arc::new(kept));
            // An inherited solution may break the new cuts: solve again.
            inherited = None;
            warm = start.map(Arc::new).or(warm);
        }
        // Whether a feasible decision's value is the least pressure of the nodes in contact
        // (Clarabel's program), to be tested against `POSITIVE`.
        let mut maxmin = !press.is_empty();
        let decision = match inherited {
            Some(r) => {
                self.inherited.fetch_add(1, Ordering::Relaxed);
                Decision::Yes { r, value: 1.0 }
            }
            None if self.simplex => {
                // The nodes in contact pressed (`r_n_i >= 1`, total at most `1 / POSITIVE`):
                // infeasible exactly when their least pressure is below `POSITIVE` of the total
                // (or there is no solution), so one program makes both prunes. In 3D it is an
                // outer relaxation (`conic::node_lp`): a prune still holds, and a feasible
                // point only steers the branching. Its objective, as in `critical`'s `bnb`,
                // asks for a vertex: the least total of the free nodes' gaps and pressures.
                maxmin = false;
                let contact: Vec<usize> =
                    (0..m).filter(|&i| classes[i] == Class::Contact).collect();
                let norm = if contact.is_empty() {
                    Norm::Sum
                } else {
                    Norm::Pressed(&contact)
                };
                let objective = lp::vertex_objective(self.form, &free);
                let shape = Shape {
                    mu: self.form.mu,
                    drive: drive.as_ref(),
                };
                let (decision, basis) = lp::decide(
                    self.form,
                    &self.lp,
                    &classes,
                    shape,
                    norm,
                    Some(&objective),
                    warm.as_deref(),
                );
                if let Some(basis) = basis {
                    warm = Some(Arc::new(basis));
                }
                decision
            }
            None => self.form.decide_checked(&classes, goal),
        };
        // In a certified run a prune stands only when its certificate passes exactly
        // (`decide_checked`, `confirm`); otherwise the subtree is explored further, as if
        // undecided.
        let witness = match decision {
            Decision::No => {
                self.pruned_infeasible.fetch_add(1, Ordering::Relaxed);
                return None;
            }
            Decision::Yes { value, .. }
                if maxmin && value <= POSITIVE && {
                    let nodes: Vec<usize> =
                        (0..m).filter(|&i| classes[i] == Class::Contact).collect();
                    self.form.confirm(&classes, Norm::Pressed(&nodes)).is_ok()
                } =>
            {
                self.pruned_unpressed.fetch_add(1, Ordering::Relaxed);
                return None;
            }
            Decision::Yes { r, .. } => Some(r),
            // Not decided: no pruning, branch on the first free node.
            Decision::Unsure(_) => None,
        };
        // (Measured on the 3D plug, m = 20 at 1.2 mu*: this rule and "most pressed first" both
        // take about 40 s; the input order took 290 s.)
        let branch = match &witness {
            None => free[0],
            Some(r) => {
                let d = self.form.dim;
                let key = |i: usize| {
                    let rn = r[d * i];
                    let gap = self.form.gap_of(r, i).max(0.0);
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
        // A child inherits the witness when it already meets the child's constraints: a
        // closed gap with a positive pressure (contact), or no reaction (separated).
        let (to_contact, mut to_separated) = match &witness {
            Some(r) => {
                let d = self.form.dim;
                let (gap, rn) = (self.form.gap_of(r, branch), r[d * branch]);
                let closed = gap.abs() <= INHERIT_ZERO;
                let free = r[d * branch..d * branch + d]
                    .iter()
                    .all(|x| x.abs() <= INHERIT_ZERO);
                (
                    (closed && rn > POSITIVE).then(|| r.clone()),
                    free.then(|| r.clone()),
                )
            }
            None => (None, None),
        };
        // Orbital branching ([`super::orbits`]): where a symmetry keeps the classes, the
        // separated child separates the branch node's image too; the patterns it skips are
        // images of the contact child's, made from the patterns found by the group's orbits
        // (with each orbit's first leaf when streamed, else after the search).
        let images: Vec<usize> = (0..self.symmetries.len())
            .filter(|&k| {
                let s = &self.symmetries[k];
                s[branch] != branch && (0..m).all(|i| classes[s[i]] == classes[i])
            })
            .collect();
        let mut contact = classes.clone();
        contact[branch] = Class::Contact;
        let mut separated = classes.clone();
        separated[branch] = Class::Separated;
        if !images.is_empty() {
            for &k in &images {
                separated[self.symmetries[k][branch]] = Class::Separated;
            }
            to_separated = None;
            if !rehearsal {
                self.mirrored.fetch_add(1, Ordering::Relaxed);
            }
        }
        Some((
            Node {
                classes: contact,
                inherited: to_contact,
                warm: warm.clone(),
                drive: drive.clone(),
                extremes: extremes.clone(),
            },
            Node {
                classes: separated,
                inherited: to_separated,
                warm,
                drive,
                extremes,
            },
        ))
    }
}

impl Search<'_, '_> {
    /// The realised pattern of the leaf whose contact set is `contact`
    /// ([`super::leaf_pattern`]). Where the finishing step maps witnesses by orbit, a contact
    /// set that is not its orbit's least takes the image of the least one's pattern, decided
    /// once (here or where the search meets it; its witness kept for the finishing step), and
    /// its own cone programs are not solved: a symmetry maps the solutions of one leaf onto
    /// the other's. (3D V-groove plug, m = 30: cone programs 5,778 to 2,374.)
    fn leaf(&self, contact: &[bool]) -> Result<Option<Leaf>, String> {
        if self.group.is_empty() {
            return leaf_pattern(self.form, contact);
        }
        let (least, by) = self.group.representative(&super::whole_pattern(contact));
        let known = self
            .least_leaves
            .lock()
            .expect("no panics while held")
            .get(&least)
            .cloned();
        let outcome = match known {
            Some(outcome) => outcome,
            None => {
                let outcome = match leaf_pattern(self.form, &super::contact_set(&least)) {
                    Ok(Some(Leaf { pattern, witness })) => {
                        self.keep_witness(&pattern, witness);
                        Ok(Some(pattern))
                    }
                    Ok(None) => Ok(None),
                    Err(why) => Err(why),
                };
                let mut all = self.least_leaves.lock().expect("no panics while held");
                all.insert(least, outcome.clone());
                outcome
            }
        };
        if by.is_some() {
            self.mapped.fetch_add(1, Ordering::Relaxed);
        }
        Ok(outcome?.map(|pattern| Leaf {
            pattern: match by {
                Some(k) => self.group.map_nodes(k, &pattern),
                None => pattern,
            },
            witness: None,
        }))
    }

    /// Keeps the witness a leaf's program made, if any, for the finishing step
    /// ([`Found::witnesses`]).
    fn keep_witness(&self, pattern: &[ContactPattern], witness: Option<Support>) {
        if let Some(w) = witness {
            let mut known = self.witnesses.lock().expect("no panics while held");
            known.insert(pattern.to_vec(), w);
        }
    }

    /// A streamed search's leaf ([`OrbitSink`]): the first leaf of an orbit (under
    /// [`Search::orbit_group`]) decides the orbit's least contact set by its cone programs, as
    /// [`Search::leaf`] does, and hands the whole orbit on at once when that pattern has no
    /// grazing node; a pattern with grazing nodes may lie below another, so its orbit is kept
    /// for the finishing step's maximal filter. A later leaf of the orbit has nothing to do.
    /// Only the orbits' states are held, not their witnesses. Every realised pattern is in the
    /// orbit of a leaf the search reaches (the regions that orbital branching skips hold
    /// images of its contact children's patterns), and each orbit is handed on once.
    fn stream_leaf(&self, contact: &[bool], stream: OrbitSink) {
        let (least, by) = self
            .orbit_group
            .representative(&super::whole_pattern(contact));
        {
            let mut seen = self.streamed_orbits.lock().expect("no panics while held");
            if seen.contains_key(&least) {
                self.mapped.fetch_add(1, Ordering::Relaxed);
                return;
            }
            seen.insert(least.clone(), Orbited::Pending);
        }
        if by.is_some() {
            self.mapped.fetch_add(1, Ordering::Relaxed);
        }
        let mine = super::contact_set(&least);
        let state = match leaf_pattern(self.form, &mine) {
            Ok(Some(Leaf { pattern, witness })) => {
                let members = self.orbit_group.orbit(&pattern);
                let n = members.len() as u64;
                self.realised.fetch_add(n, Ordering::Relaxed);
                if pattern.contains(&ContactPattern::Grazing) {
                    self.keep_witness(&pattern, witness);
                    let mut found = self.found.lock().expect("no panics while held");
                    found.extend(members);
                    Orbited::Other
                } else {
                    self.images.fetch_add(n - 1, Ordering::Relaxed);
                    stream(members, pattern, witness);
                    Orbited::Streamed
                }
            }
            Ok(None) => Orbited::Other,
            Err(reason) => {
                let mut undecided = self.undecided.lock().expect("no panics while held");
                undecided.push(Undecided {
                    contact: mine,
                    reason,
                });
                Orbited::Other
            }
        };
        let mut seen = self.streamed_orbits.lock().expect("no panics while held");
        seen.insert(least, state);
    }

    /// Whether the linear program of a leaf (`conic::node_lp`, its contact nodes pressed; in 3D
    /// an outer relaxation) is infeasible: then no solution presses its whole contact set, and
    /// its pattern, if any, lies below the pattern found at the leaf of its pressed nodes. A
    /// leaf costs a few pivots this way where its cone programs cost milliseconds: on the 3D
    /// V-groove plug (m = 20) most leaves the search reaches end here.
    fn pressed_set_refuted(
        &self,
        classes: &[Class],
        drive: &Option<Arc<Drive>>,
        warm: &Option<Arc<Warm>>,
    ) -> bool {
        let contact: Vec<usize> = (0..self.form.m)
            .filter(|&i| classes[i] == Class::Contact)
            .collect();
        let shape = Shape {
            mu: self.form.mu,
            drive: drive.as_ref(),
        };
        let norm = Norm::Pressed(&contact);
        let (decision, _) = lp::decide(
            self.form,
            &self.lp,
            classes,
            shape,
            norm,
            None,
            warm.as_deref(),
        );
        decision == Decision::No
    }
}

/// The depth down to which a 3D search tightens ([`crate::conic::cuts::enumeration_depth_3d`],
/// or a test's `DEPTH`).
fn depth_3d(m: usize) -> usize {
    #[cfg(test)]
    {
        let depth = DEPTH.load(Ordering::Relaxed);
        if depth != usize::MAX {
            return depth;
        }
    }
    crate::conic::cuts::enumeration_depth_3d(m)
}

/// A test's tightening depth for the 3D searches (`usize::MAX`: the default), to show that the
/// depth changes the tree and never the answer.
#[cfg(test)]
static DEPTH: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(usize::MAX);

/// Runs the search; progress is reported from the calling thread every 200 ms. With `stream`
/// (not in a certified or a sharded run) the patterns without grazing nodes go to it as their
/// orbits' first leaves are decided ([`OrbitSink`]), and the returned [`Found`] holds the
/// others (with the streamed ones for the maximal filter, when there are others).
pub(super) fn run(
    form: &Formulation,
    info: &mut PatternInfo,
    shard: Option<Shard>,
    progress: &dyn Fn(Progress),
    control: &Control,
    stream: Option<OrbitSink>,
) -> Found {
    let stream = stream.filter(|_| shard.is_none() && form.refutations.is_none());
    // The symmetries of the orbital branching (none in a certified or a sharded run).
    let orbit_generators = if form.refutations.is_none() && shard.is_none() {
        form.problem.symmetries_with_signs()
    } else {
        Vec::new()
    };
    let search = Search {
        form,
        control,
        found: Mutex::new(Vec::new()),
        witnesses: Mutex::new(HashMap::new()),
        undecided: Mutex::new(Vec::new()),
        visited: AtomicU64::new(0),
        inherited: AtomicU64::new(0),
        pruned_infeasible: AtomicU64::new(0),
        pruned_unpressed: AtomicU64::new(0),
        leaves: AtomicU64::new(0),
        simplex: form.refutations.is_none(),
        lp: LpCounters::default(),
        tighten_depth: if form.refutations.is_none() && form.modes == 0 {
            match form.dim {
                2 => crate::rays::search::tree::tighten_depth(form.m),
                _ => depth_3d(form.m),
            }
        } else {
            0
        },
        tightened: AtomicU64::new(0),
        symmetries: orbit_generators.iter().map(|(s, _)| s.clone()).collect(),
        mirrored: AtomicU64::new(0),
        group: match form.refutations.is_none() {
            true => Group::of(form),
            false => Group::default(),
        },
        least_leaves: Mutex::new(HashMap::new()),
        mapped: AtomicU64::new(0),
        realised: AtomicU64::new(0),
        stream,
        orbit_group: Group::new(orbit_generators),
        streamed_orbits: Mutex::new(HashMap::new()),
        images: AtomicU64::new(0),
    };
    let explored = Explored::new();
    let walk = Walk::new(&search, &explored);
    let report = || {
        progress(Progress {
            done: explored.permille(),
            total: 1000,
            rays: search.realised.load(Ordering::Relaxed) as usize,
            nodes: search.visited.load(Ordering::Relaxed),
        });
    };
    let split = crate::run::with_progress(|| walk.run(shard), report);
    info.nodes_visited = search.visited.into_inner();
    info.nodes_inherited = search.inherited.into_inner();
    info.pruned_infeasible = search.pruned_infeasible.into_inner();
    info.pruned_unpressed = search.pruned_unpressed.into_inner();
    info.leaves = search.leaves.into_inner();
    info.bound_tightenings = search.tightened.into_inner();
    info.lp_solves = search.lp.solves.into_inner();
    info.lp_pivots = search.lp.pivots.into_inner();
    info.lp_fallbacks = search.lp.fallbacks.into_inner();
    let mut patterns = search.found.into_inner().unwrap_or_default();
    info.mirrored = search.mirrored.into_inner();
    let streamed = search.stream.is_some();
    if streamed {
        // The kept orbits (grazing nodes) are whole already; the streamed ones join them for
        // the maximal filter, when there is anything to filter.
        if !patterns.is_empty() {
            let seen = search.streamed_orbits.into_inner().unwrap_or_default();
            for (least, state) in seen {
                if state == Orbited::Streamed {
                    patterns.extend(search.orbit_group.orbit(&least));
                }
            }
        }
        info.images = search.images.into_inner();
    } else {
        info.images = search.orbit_group.complete(&mut patterns);
    }
    info.realised = search.realised.into_inner();
    info.mapped = search.mapped.into_inner();
    Found {
        streamed,
        patterns,
        undecided: search.undecided.into_inner().unwrap_or_default(),
        shard: split,
        witnesses: search.witnesses.into_inner().unwrap_or_default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{enumerate_patterns, PatternMethod, PatternSettings};

    /// The tightening depth changes the tree, never the answer: the 3D V-groove plug at
    /// m = 20 (1.2 `mu*`) has the same patterns, statuses, witnesses and margins without
    /// tightening, at the old depth (5) and at the default one (8), each search a different
    /// size.
    #[test]
    fn the_tightening_depth_keeps_the_answer() {
        let model = crate::examples::plug3d(4, 2).expect("the example mesh");
        let problem = model.problem(1.7895).expect("the example problem");
        assert_eq!(problem.nodes(), 20);
        assert_eq!(depth_3d(20), 8);
        let settings = PatternSettings {
            method: PatternMethod::Bnb,
            ..PatternSettings::default()
        };
        let run = |depth: usize| {
            DEPTH.store(depth, Ordering::Relaxed);
            let found = enumerate_patterns(&problem, &settings);
            DEPTH.store(usize::MAX, Ordering::Relaxed);
            found.expect("the plug's patterns")
        };
        let runs = [run(0), run(5), run(8)];
        let pieces = |p: &crate::Patterns| -> Vec<_> {
            p.patterns
                .iter()
                .map(|q| {
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    (
                        q.pattern.clone(),
                        q.status.clone(),
                        bits(&q.r),
                        q.margin.to_bits(),
                    )
                })
                .collect()
        };
        assert_eq!(runs[0].patterns.len(), 592);
        for run in &runs {
            assert!(run.undecided.is_empty());
            assert_eq!(pieces(run), pieces(&runs[0]));
        }
        let nodes: Vec<u64> = runs.iter().map(|p| p.info.nodes_visited).collect();
        assert!(
            nodes[0] > nodes[1] && nodes[1] > nodes[2],
            "nodes {nodes:?}"
        );
    }
}
