//! The wedged problem with some nodes' contact status fixed, as a conic program for
//! [`crate::conic::socp`], and the decisions taken from its answer.
//!
//! The unknowns are the reactions `r` of the nodes whose reaction may be nonzero; `u = K^{-1} r`
//! is eliminated. Each gap row `u_n_i` is divided by the largest entry of its compliance row, so
//! that gaps and pressures (normalised by `sum r_n = 1`) are numbers of order one whatever the
//! units of `K`. A node is in one of four classes ([`Class`]).
//!
//! A floating body (`Problem::is_floating`) has `k` more unknowns, the amplitudes `a` of its
//! rigid modes `R`: `u = G r + R a` with `G` the problem's generalised inverse, and every program
//! carries the `k` equalities `R^T r = 0` (the reactions do no work on a rigid motion). A point
//! of a program is then the reactions followed by `a` (`dim*m + k` numbers), and a gap row has
//! `dim*m + k` entries; everything indexed by node reads the reactions alone.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use crate::conic::socp::{solve, Affine, Answer, Program};
use crate::problem::Problem;
mod certificate;
mod split;
mod support;

/// An entry is positive when it can reach this value, with `sum r_n = 1` and gaps scaled as in
/// the module docs. Below it an entry counts as zero: the resolution of the method, a hundred
/// times the solver's accuracy (about `1e-9` after the checks of [`crate::conic::socp`]).
pub const POSITIVE: f64 = 1e-7;

/// A scaled gap row's entries (each row's largest is 1) at most this are round-off of the
/// compliance `K^-1` and count as zero ([`Formulation::new`]), as a rigid mode's normal
/// components below `1e-12` of its largest do.
const ROUNDOFF: f64 = 1e-12;

/// Optimal values within a factor of 100 of [`POSITIVE`] on either side are close calls: they
/// are decided, and counted in `info.near_degenerate`.
const NEAR: f64 = 100.0;

/// What a node is constrained to in one program.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Class {
    /// `u_n = 0`, `r` in the friction cone.
    Contact,
    /// `r = 0`, `u_n >= 0`.
    Separated,
    /// `u_n >= 0` and `r` in the friction cone, no complementarity (undecided in a search).
    Free,
    /// `u_n = 0` and `r = 0`.
    Grazing,
}

impl Class {
    /// Whether the node's reaction may be nonzero (contact or free).
    pub(crate) fn has_r(self) -> bool {
        matches!(self, Class::Contact | Class::Free)
    }
}

/// The classes of the leaf of a contact set: contact where `contact` says so, separated
/// elsewhere.
pub(crate) fn leaf_classes(contact: &[bool]) -> Vec<Class> {
    contact
        .iter()
        .map(|&c| if c { Class::Contact } else { Class::Separated })
        .collect()
}

/// Classes as a string, one letter per node: `C` contact, `S` separated, `*` free, `G`
/// grazing.
pub(crate) fn describe(classes: &[Class]) -> String {
    classes
        .iter()
        .map(|c| match c {
            Class::Contact => 'C',
            Class::Separated => 'S',
            Class::Free => '*',
            Class::Grazing => 'G',
        })
        .collect()
}

/// A quantity the program can push up: the normal pressure of a node, its (scaled) gap, or its
/// friction slack `mu r_n - ||r_t||`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Entry {
    Press(usize),
    Gap(usize),
    Stick(usize),
}

impl Entry {
    /// Names the entry (nodes counted from 1).
    pub(crate) fn name(self) -> String {
        match self {
            Entry::Press(i) => format!("the pressure of node {}", i + 1),
            Entry::Gap(i) => format!("the gap of node {}", i + 1),
            Entry::Stick(i) => format!("the friction slack of node {}", i + 1),
        }
    }
}

/// The goal of one program.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Goal<'a> {
    /// Any feasible point.
    Feasible,
    /// Maximise the smallest of the entries (all of them at once): `t` with every entry `>= t`.
    MaxMin(&'a [Entry]),
    /// Minimise `s` with `||r_t_i|| <= mu r_n_i + w_i s` at every node with a reaction, for
    /// weights `w` (one per node, `>= 0`): the step of the Dinkelbach-type method for the least
    /// friction coefficient of a cone (Crouzeix, Ferland and Schaible's second method, `w` the
    /// pressures of the previous iterate). Needs [`Norm::Sum`] and a finite `mu`.
    MinSlack(&'a [f64]),
    /// Minimise a linear function of the reactions: one coefficient per reaction component
    /// (all `dim*m`; those of nodes without a reaction are ignored). The caller keeps it
    /// bounded ([`Norm::Sum`] and a finite `mu` bound every reaction; a function that is
    /// nonnegative on the program is bounded below by zero).
    Minimise(&'a [f64]),
}

/// How the cone of solutions is cut to make a program of it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Norm<'a> {
    /// `sum r_n = 1`: a nontrivial solution.
    Sum,
    /// `r_n_i >= 1` at every listed node (a nonempty list): a solution pressing all of them.
    /// Its infeasibility is a certificate that no solution presses them all at once.
    Pressed(&'a [usize]),
    /// The scaled gap of this node (separated or free) `>= 1`: its infeasibility is a
    /// certificate that no solution opens that gap.
    Gap(usize),
}

/// A [`Norm`] as kept by a [`Refutation`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Cut {
    Sum,
    Pressed(Vec<usize>),
    Gap(usize),
}

impl Cut {
    pub(crate) fn norm(&self) -> Norm<'_> {
        match self {
            Cut::Sum => Norm::Sum,
            Cut::Pressed(p) => Norm::Pressed(p),
            Cut::Gap(j) => Norm::Gap(*j),
        }
    }
}

/// The answer to one program, in the problem's terms.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Decision {
    /// Feasible; the reactions `r` (all `dim*m`, `sum r_n = 1`) and the optimal value (`0` for
    /// [`Goal::Feasible`]).
    Yes { r: Vec<f64>, value: f64 },
    /// Infeasible (certified by the solver adapter): no nontrivial solution.
    No,
    /// The solver could not decide, even after its retry.
    Unsure(String),
}

/// Counters shared by the threads of one run.
#[derive(Debug, Default)]
pub(crate) struct Counters {
    pub socps: AtomicU64,
    pub retries: AtomicU64,
    pub uncertain: AtomicU64,
    pub near_degenerate: AtomicU64,
}

impl Counters {
    fn add(c: &AtomicU64, n: u64) {
        c.fetch_add(n, Ordering::Relaxed);
    }
    pub(crate) fn get(c: &AtomicU64) -> u64 {
        c.load(Ordering::Relaxed)
    }
}

/// The support of a cone ([`Formulation::support`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Support {
    /// The entries some solution makes positive.
    pub entries: Vec<Entry>,
    /// A solution (reactions, `sum r_n = 1`) that makes all of them positive at once.
    pub r: Vec<f64>,
    /// The smallest of them at `r` (`0` when there are none).
    pub value: f64,
}

/// An infeasibility proved by the solver, kept for an exact re-check
/// ([`crate::critical::certify`]): a program of [`Goal::Feasible`] with these classes, at this
/// `mu`, with this normalisation, has no solution, and `z` (one per node) are the certificate's
/// multipliers of the gap rows `u_n_i` (`= 0` or `>= 0`), in the units of `u_n = (K^-1 r)_n`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Refutation {
    pub classes: Vec<Class>,
    pub mu: f64,
    /// The normalisation.
    pub cut: Cut,
    /// Empty when the solver gave no certificate (a program without variables).
    pub z: Vec<f64>,
    /// A floating body's multipliers `y` of `R^T r = 0`, one per mode (`w = G z + R y`).
    pub balance: Vec<f64>,
}

/// The data every program of a run shares.
pub(crate) struct Formulation<'a> {
    pub problem: &'a Problem,
    pub dim: usize,
    pub m: usize,
    pub mu: f64,
    /// The floating body's rigid modes (`k`; 0 when clamped).
    pub modes: usize,
    /// Each mode's amplitude variable among those that move some contact node normally (the
    /// others change no gap, so they are no unknown of a program; their amplitude is 0).
    amplitude: Vec<Option<usize>>,
    /// Scaled gap rows: `gap[i][c] = G[n_i, c] / scale[i]`, `scale[i] = max_c |G[n_i, c]|`,
    /// followed for a floating body by `R[n_i, j] / scale[i]`.
    gap: Vec<Vec<f64>>,
    scale: Vec<f64>,
    pub counters: Counters,
    /// When set, every infeasible [`Goal::Feasible`] program is kept here with its certificate.
    pub refutations: Option<Mutex<Vec<Refutation>>>,
    /// Decisions a search relied on that [`Formulation::confirm`] could not back.
    pub doubts: Mutex<Vec<String>>,
    /// With kept refutations, checks the refutations of [`Formulation::confirm`] exactly as
    /// they are made (the caller passes `refutation::Checker::check`; a closure keeps this
    /// module free of the exact arithmetic).
    pub checker: Option<RefutationCheck>,
    /// Refutations checked by the checker as they were made.
    pub settled: AtomicU64,
}

/// An exact check of one refutation: `Ok` when it holds, otherwise why not.
pub type RefutationCheck = Box<dyn Fn(&Refutation) -> Result<(), String> + Send + Sync>;

impl<'a> Formulation<'a> {
    pub(crate) fn new(problem: &'a Problem) -> Formulation<'a> {
        let (dim, m) = (problem.dim(), problem.nodes());
        let g = problem.compliance();
        let scale: Vec<f64> = (0..m)
            .map(|i| g.row(dim * i).iter().fold(0.0f64, |a, x| a.max(x.abs())))
            .collect();
        let rigid = problem.rigid_modes();
        // A mode's normal components below round-off of its largest entry are zero: a motion
        // that slides every contact node along its wall (a turn of a square frustum's corners
        // about its axis) has none, and its amplitude is no unknown of the programs.
        let modes = rigid.ncols();
        let floor: Vec<f64> = (0..modes).map(|j| 1e-12 * rigid.column(j).amax()).collect();
        let normal = |i: usize, j: usize| {
            let x = rigid[(dim * i, j)];
            if x.abs() <= floor[j] {
                0.0
            } else {
                x
            }
        };
        // A gap row's entries below round-off of its largest are zero too: a node whose
        // compliance couples it to no node of a contact set (a body whose flexibility keeps
        // two parts apart) has a gap that is exactly zero there, not a few ulps, and a cone
        // program that must keep it nonnegative would otherwise be checked against the ulps
        // (such leaves were left undecided: `tests/mirror.rs`, the grazing problems).
        let zeroed = |x: f64| if x.abs() <= ROUNDOFF { 0.0 } else { x };
        let gap: Vec<Vec<f64>> = (0..m)
            .map(|i| {
                g.row(dim * i)
                    .iter()
                    .copied()
                    .chain((0..modes).map(|j| normal(i, j)))
                    .map(|x| zeroed(x / scale[i]))
                    .collect()
            })
            .collect();
        let mut amplitude = vec![None; modes];
        let mut used = 0;
        for (j, slot) in amplitude.iter_mut().enumerate() {
            if (0..m).any(|i| normal(i, j) != 0.0) {
                *slot = Some(used);
                used += 1;
            }
        }
        Formulation {
            problem,
            dim,
            m,
            mu: problem.mu(),
            modes,
            amplitude,
            gap,
            scale,
            counters: Counters::default(),
            refutations: None,
            doubts: Mutex::new(Vec::new()),
            checker: None,
            settled: AtomicU64::new(0),
        }
    }

    /// When refutations are kept (a certified run): backs a decision of the search that the
    /// program of `classes` normalised by `norm` has no solution (taken from an optimal value
    /// at or below [`POSITIVE`], or from an infeasible program of another goal) with a
    /// refutation of its own, solved now with [`Goal::Feasible`] and checked exactly at once
    /// ([`Formulation::checker`]). Returns whether the decision stands; when it does not, the
    /// refutation is not kept, and a search should not rely on the decision (it explores
    /// further instead), or, when it must, record `what()` among [`Formulation::doubts`] with
    /// [`Formulation::doubt`]. Without kept refutations, every decision stands.
    pub(crate) fn confirm(&self, classes: &[Class], norm: Norm) -> Result<(), String> {
        if self.refutations.is_none() {
            return Ok(());
        }
        match self.decide_kept(classes, self.mu, norm, Goal::Feasible) {
            (Decision::No, Some(f)) => self.settle(f),
            (Decision::No, None) => Err("the solver gave no certificate".into()),
            (Decision::Yes { .. }, _) => Err("a solution exists after all".into()),
            (Decision::Unsure(why), _) => Err(format!("the solver could not decide ({why})")),
        }
    }

    /// Keeps a refutation for the exact check at the end, when refutations are kept.
    pub(crate) fn keep(&self, f: Refutation) {
        if let Some(log) = &self.refutations {
            log.lock().expect("no panics while held").push(f);
        }
    }

    /// The refutations kept so far, taken out (none when they are not kept).
    pub(crate) fn take_refutations(&mut self) -> Vec<Refutation> {
        self.refutations
            .take()
            .map(|log| log.into_inner().unwrap_or_default())
            .unwrap_or_default()
    }

    /// Records a decision the search relied on without a certificate.
    pub(crate) fn doubt(&self, what: String) {
        self.doubts.lock().expect("no panics while held").push(what);
    }

    /// [`Formulation::confirm`] of a decision that no solution of `classes` makes the entry
    /// `e` positive: a pressure by [`Norm::Pressed`] of its node, a gap by [`Norm::Gap`]. (A
    /// stick slack is only described, never relied on: it always stands.)
    pub(crate) fn confirm_entry(&self, classes: &[Class], e: Entry) -> Result<(), String> {
        let node;
        let norm = match e {
            Entry::Press(i) => {
                node = [i];
                Norm::Pressed(&node)
            }
            Entry::Gap(i) => Norm::Gap(i),
            Entry::Stick(_) => return Ok(()),
        };
        self.confirm(classes, norm)
    }

    /// Node `i`'s scaled gap row: `u_n_i / scale_of(i)` is this row times `r` (for a floating
    /// body, times the reactions and rigid amplitudes).
    pub(crate) fn gap_row(&self, i: usize) -> &[f64] {
        &self.gap[i]
    }

    /// The length of a gap row and of a program's point: `dim*m` reactions, `k` amplitudes.
    pub(crate) fn width(&self) -> usize {
        self.dim * self.m + self.modes
    }

    /// The variable (among the amplitudes that are unknowns of the programs) of rigid mode
    /// `j`'s amplitude: `None` for a mode that moves no contact node normally.
    pub(crate) fn amplitude_of(&self, j: usize) -> Option<usize> {
        self.amplitude[j]
    }

    /// The rows of `R^T r = 0` (no work on a rigid motion) over the `dim*m` reactions, scaled
    /// to entries at most 1 (none when clamped): independent, though maybe not on the nodes a
    /// program lets press, which a bounded simplex method does not mind.
    pub(crate) fn balance_rows(&self) -> Vec<Vec<f64>> {
        let rigid = self.problem.rigid_modes();
        (0..self.modes)
            .map(|j| {
                let big = rigid.column(j).amax();
                rigid.column(j).iter().map(|x| x / big).collect()
            })
            .collect()
    }

    /// How many amplitudes are unknowns of the programs.
    pub(crate) fn amplitudes(&self) -> usize {
        self.amplitude.iter().flatten().count()
    }

    /// The scale of node `i`'s gap row ([`Formulation::gap_row`]).
    pub(crate) fn scale_of(&self, i: usize) -> f64 {
        self.scale[i]
    }

    /// The scaled gap `u_n_i` of reactions `r` (all `dim*m`).
    pub(crate) fn gap_of(&self, r: &[f64], i: usize) -> f64 {
        self.gap[i].iter().zip(r).map(|(g, x)| g * x).sum()
    }

    /// The friction slack `mu r_n - ||r_t||` of node `i`.
    pub(crate) fn slack_of(&self, r: &[f64], i: usize) -> f64 {
        let d = self.dim;
        let rt = r[d * i + 1..d * i + d]
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        self.mu * r[d * i] - rt
    }

    /// The value of an entry at reactions `r`.
    pub(crate) fn entry_of(&self, r: &[f64], e: Entry) -> f64 {
        match e {
            Entry::Press(i) => r[self.dim * i],
            Entry::Gap(i) => self.gap_of(r, i),
            Entry::Stick(i) => self.slack_of(r, i),
        }
    }

    /// Solves the program of `classes` with `goal`, at the problem's `mu`, normalised by
    /// `sum r_n = 1`.
    pub(crate) fn decide(&self, classes: &[Class], goal: Goal) -> Decision {
        self.decide_at(classes, self.mu, Norm::Sum, goal)
    }

    /// Solves the program of `classes` with `goal` at friction coefficient `mu`
    /// (`f64::INFINITY`: the friction cones become `r_n >= 0`, any `r_t`) and normalisation
    /// `norm`. A returned `r` is rescaled to `sum r_n = 1`.
    pub(crate) fn decide_at(&self, classes: &[Class], mu: f64, norm: Norm, goal: Goal) -> Decision {
        let (decision, refutation) = self.decide_kept(classes, mu, norm, goal);
        if let (Some(f), Goal::Feasible) = (refutation, goal) {
            self.keep(f);
        }
        decision
    }

    /// [`Formulation::decide`] for a search that prunes on an infeasible answer: in a certified
    /// run the refutation is settled at once ([`Formulation::settle`]), and one that fails its
    /// exact check turns the answer into [`Decision::Unsure`], so that nothing is pruned on it.
    pub(crate) fn decide_checked(&self, classes: &[Class], goal: Goal) -> Decision {
        match self.decide_kept(classes, self.mu, Norm::Sum, goal) {
            (Decision::No, Some(f)) => match self.settle(f) {
                Ok(()) => Decision::No,
                Err(e) => Decision::Unsure(e),
            },
            (decision, _) => decision,
        }
    }

    /// A refutation a certified search relies on: checked exactly at once by the
    /// [`Formulation::checker`] and counted in [`Formulation::settled`] (or, without a
    /// checker, kept for a check at the end).
    fn settle(&self, f: Refutation) -> Result<(), String> {
        match &self.checker {
            Some(checker) => {
                checker(&f).map_err(|e| format!("its certificate fails exactly: {e}"))?;
                self.settled.fetch_add(1, Ordering::Relaxed);
            }
            None => self.keep(f),
        }
        Ok(())
    }

    /// [`Formulation::decide_at`], with the refutation of an infeasible [`Goal::Feasible`]
    /// program returned rather than kept (when refutations are kept).
    fn decide_kept(
        &self,
        classes: &[Class],
        mu: f64,
        norm: Norm,
        goal: Goal,
    ) -> (Decision, Option<Refutation>) {
        self.decide_cut(classes, mu, norm, goal, &[])
    }

    /// [`Formulation::decide_kept`] with extra valid inequalities `cut . r >= 0` (each a row
    /// over all `dim*m` reaction components; those of nodes without a reaction are ignored).
    /// A refutation only covers the gap rows, so a program with cuts keeps none.
    pub(crate) fn decide_cut(
        &self,
        classes: &[Class],
        mu: f64,
        norm: Norm,
        goal: Goal,
        cuts: &[Vec<f64>],
    ) -> (Decision, Option<Refutation>) {
        let (d, m) = (self.dim, self.m);
        // Variable offsets of the nodes with a reaction.
        let mut offset = vec![usize::MAX; m];
        let mut vars = 0;
        for i in (0..m).filter(|&i| classes[i].has_r()) {
            offset[i] = vars;
            vars += d;
        }
        if vars == 0 {
            // Every reaction is zero: only the trivial solution.
            return (
                Decision::No,
                self.refuted(classes, mu, norm, goal, Vec::new(), Vec::new()),
            );
        }
        let (entries, weights): (&[Entry], Option<&[f64]>) = match goal {
            Goal::Feasible | Goal::Minimise(_) => (&[], None),
            Goal::MaxMin(e) => (e, None),
            Goal::MinSlack(w) => (&[], Some(w)),
        };
        debug_assert!(weights.is_none() || (mu.is_finite() && matches!(norm, Norm::Sum)));
        // A floating body's rigid amplitudes follow the reactions.
        let (reactions, k) = (vars, self.modes);
        let vars = vars + self.amplitude.iter().flatten().count();
        let t = (!entries.is_empty() || weights.is_some()).then_some(vars);
        let mut p = Program::new(vars + t.is_some() as usize);
        // A row over all `dim*m` reaction components as terms in the program's variables (and,
        // when it has them, over the `k` rigid amplitudes after).
        let on_reactions = |row: &[f64]| -> Vec<(usize, f64)> {
            let amplitudes = row.get(d * m..).unwrap_or(&[]);
            (0..m)
                .filter(|&j| classes[j].has_r())
                .flat_map(|j| (0..d).map(move |c| (j, c)))
                .map(|(j, c)| (offset[j] + c, row[d * j + c]))
                .chain(
                    amplitudes
                        .iter()
                        .enumerate()
                        .filter_map(|(j, &x)| Some((reactions + self.amplitude[j]?, x))),
                )
                .filter(|&(_, x)| x != 0.0)
                .collect()
        };
        let mut balance_rows = Vec::new();
        if k > 0 {
            // R^T r = 0 (no work on a rigid motion) on the reactions that may be nonzero, as
            // independent rows: with few such nodes the k rows are dependent (one node in 2D:
            // 2 unknowns, 3 rows), and an interior-point solver stalls on dependent equalities.
            let rigid = self.problem.rigid_modes();
            let cols: Vec<usize> = (0..m)
                .filter(|&j| classes[j].has_r())
                .flat_map(|j| (0..d).map(move |c| d * j + c))
                .collect();
            let block = nalgebra::DMatrix::from_fn(k, cols.len(), |j, c| rigid[(cols[c], j)]);
            let svd = block.svd(true, true);
            let top = svd.singular_values.max();
            let (u, vt) = (svd.u.expect("asked for"), svd.v_t.expect("asked for"));
            for (row, &sigma) in svd.singular_values.iter().enumerate() {
                if sigma > 1e-9 * top {
                    let mut full = vec![0.0; d * m];
                    for (c, &a) in cols.iter().enumerate() {
                        full[a] = vt[(row, c)];
                    }
                    // `v^T r = u^T R^T r / sigma`: a multiplier `u / sigma` of the modes' rows.
                    let index = p.zero(Affine::new(on_reactions(&full), 0.0));
                    balance_rows.push((index, u.column(row) / sigma));
                }
            }
        }
        let gap = |i: usize, minus_t: bool, constant: f64| {
            let mut terms = on_reactions(&self.gap[i]);
            if minus_t {
                terms.push((vars, -1.0));
            }
            Affine::new(terms, constant)
        };
        let stick: Vec<usize> = entries
            .iter()
            .filter_map(|e| match e {
                Entry::Stick(i) => Some(*i),
                _ => None,
            })
            .collect();
        // Each node's gap row: (is a zero row, ordinal among its kind).
        let mut gap_rows = Vec::with_capacity(m);
        for i in 0..m {
            let c = classes[i];
            gap_rows.push(match c {
                Class::Contact | Class::Grazing => (true, p.zero(gap(i, false, 0.0))),
                Class::Separated | Class::Free => {
                    let cut = matches!(norm, Norm::Gap(j) if j == i);
                    (
                        false,
                        p.nonneg(gap(
                            i,
                            t.is_some() && entries.contains(&Entry::Gap(i)),
                            if cut { -1.0 } else { 0.0 },
                        )),
                    )
                }
            });
            if c.has_r() {
                let o = offset[i];
                // Friction: (mu r_n [- t | + w_i s], r_t) in the cone; in 2D two half-planes.
                let mut head = vec![(o, mu)];
                if stick.contains(&i) {
                    head.push((vars, -1.0));
                }
                if let Some(w) = weights {
                    if w[i] != 0.0 {
                        head.push((vars, w[i]));
                    }
                }
                if mu.is_infinite() {
                    // No friction limit: only r_n >= 0 (below).
                } else if d == 2 {
                    for sign in [1.0, -1.0] {
                        let mut terms = head.clone();
                        terms.push((o + 1, -sign));
                        p.nonneg(Affine::new(terms, 0.0));
                    }
                } else {
                    p.soc(
                        Affine::new(head, 0.0),
                        (1..d).map(|c| Affine::var(o + c)).collect(),
                    );
                }
                p.nonneg(if entries.contains(&Entry::Press(i)) {
                    Affine::new(vec![(o, 1.0), (vars, -1.0)], 0.0)
                } else {
                    Affine::var(o)
                });
            }
        }
        match norm {
            Norm::Sum => {
                let normal: Vec<(usize, f64)> = (0..m)
                    .filter(|&i| classes[i].has_r())
                    .map(|i| (offset[i], 1.0))
                    .collect();
                p.zero(Affine::new(normal, -1.0));
            }
            Norm::Pressed(nodes) => {
                for &i in nodes {
                    debug_assert!(classes[i].has_r());
                    p.nonneg(Affine::new(vec![(offset[i], 1.0)], -1.0));
                }
            }
            Norm::Gap(j) => {
                // The gap row itself carries the cut (above).
                debug_assert!(matches!(classes[j], Class::Separated | Class::Free));
            }
        }
        for cut in cuts {
            p.nonneg(Affine::new(on_reactions(cut), 0.0));
        }
        if let Goal::Minimise(objective) = goal {
            p.minimise(&on_reactions(objective));
        }
        if let Some(t) = t {
            if weights.is_some() {
                // Minimise s. It is bounded below: some node with w_i > 0 has
                // w_i s >= -mu r_n_i >= -mu. The bound below only helps the solver.
                let w_max = weights.map_or(1.0, |w| w.iter().fold(0.0f64, |a, &x| a.max(x)));
                let floor = -(mu + 1.0) / w_max.max(1e-300) * m as f64;
                p.nonneg(Affine::new(vec![(t, 1.0)], -floor));
                p.minimise(&[(t, 1.0)]);
            } else {
                // t <= 1 keeps the program bounded whatever the entries.
                p.nonneg(Affine::new(vec![(t, -1.0)], 1.0));
                p.minimise(&[(t, -1.0)]);
            }
        }
        let (answer, stats) = solve(&p);
        Counters::add(&self.counters.socps, stats.solves);
        Counters::add(&self.counters.retries, stats.retries);
        let decision = match answer {
            Answer::Optimal { x, .. } => {
                let mut r = vec![0.0; d * m + k];
                for i in (0..m).filter(|&i| classes[i].has_r()) {
                    r[d * i..d * i + d].copy_from_slice(&x[offset[i]..offset[i] + d]);
                }
                for (j, a) in self.amplitude.iter().enumerate() {
                    r[d * m + j] = a.map_or(0.0, |a| x[reactions + a]);
                }
                if !matches!(norm, Norm::Sum) {
                    let total: f64 = (0..m).map(|i| r[d * i]).sum();
                    r.iter_mut().for_each(|x| *x /= total);
                }
                let value = t.map_or(0.0, |t| x[t]);
                if !entries.is_empty() && value > POSITIVE / NEAR && value < POSITIVE * NEAR {
                    Counters::add(&self.counters.near_degenerate, 1);
                }
                Decision::Yes { r, value }
            }
            // The simplex method's fallback decided a linear program that Clarabel could not,
            // and its certificate is not in this module's form: a search that keeps
            // refutations (a certified run) must not rely on it.
            Answer::Infeasible { y } if y.is_empty() && self.refutations.is_some() => {
                Counters::add(&self.counters.uncertain, 1);
                Decision::Unsure(
                    "infeasible by the simplex method, with no certificate to keep".into(),
                )
            }
            Answer::Infeasible { y } => {
                let z = if self.refutations.is_some() && !y.is_empty() {
                    gap_rows
                        .iter()
                        .enumerate()
                        .map(|(i, &(zero, k))| {
                            let row = if zero { k } else { p.nonneg_row(k) };
                            y[row] / self.scale[i]
                        })
                        .collect()
                } else {
                    Vec::new()
                };
                let balance = if z.is_empty() {
                    Vec::new()
                } else {
                    balance_rows
                        .iter()
                        .fold(vec![0.0; k], |mut b, (index, along)| {
                            b.iter_mut()
                                .zip(along.iter())
                                .for_each(|(b, a)| *b += y[*index] * a);
                            b
                        })
                };
                let kept = if cuts.is_empty() {
                    self.refuted(classes, mu, norm, goal, z, balance)
                } else {
                    None
                };
                return (Decision::No, kept);
            }
            Answer::Uncertain { reason } => {
                Counters::add(&self.counters.uncertain, 1);
                Decision::Unsure(reason)
            }
        };
        (decision, None)
    }

    /// The refutation of an infeasible program, when they are kept (and the goal is
    /// [`Goal::Feasible`]).
    fn refuted(
        &self,
        classes: &[Class],
        mu: f64,
        norm: Norm,
        goal: Goal,
        z: Vec<f64>,
        balance: Vec<f64>,
    ) -> Option<Refutation> {
        // A max-min program is infeasible exactly when its feasibility program is (its `t` is
        // free below), and the exact check rests on the gap multipliers alone, so its
        // certificate is kept as the feasibility program's.
        let (Some(_), Goal::Feasible | Goal::MaxMin(_)) = (&self.refutations, goal) else {
            return None;
        };
        let cut = match norm {
            Norm::Sum => Cut::Sum,
            Norm::Pressed(nodes) => Cut::Pressed(nodes.to_vec()),
            Norm::Gap(j) => Cut::Gap(j),
        };
        Some(Refutation {
            classes: classes.to_vec(),
            mu,
            cut,
            z,
            balance,
        })
    }
}
