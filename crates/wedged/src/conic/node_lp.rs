//! The search node over contact sets (`critical`'s and the patterns' `bnb` in 2D and 3D, the
//! enumeration's `rays/search` in 2D) as a linear program for the in-house simplex method
//! ([`super::simplex`]), warm-started from the parent's basis.
//!
//! **In 3D the program is a relaxation.** The friction cone `||r_t|| <= mu r_n` is replaced by
//! the cone over a regular polygon of [`SIDES`](columns::SIDES) sides that holds its circle
//! (corners at `mu / cos(pi / SIDES)`). So an infeasible 3D program refutes the node's
//! second-order cone program too (a valid prune), but a feasible one's point may lie outside
//! the true cone: it steers branching only, and a leaf is decided by the cone program itself
//! (Clarabel).
//!
//! **The program** has one fixed shape for the whole search, so that a basis carries over from
//! a node to its children and to its bound-tightening programs, which differ only in bounds
//! and costs:
//! - per node, the friction cone's edges as columns, `a_i, b_i >= 0` in 2D: `r_n_i = a_i + b_i`,
//!   `r_t_i = mu (a_i - b_i)` (at `mu = infinity`: `r_n_i = a_i`, `r_t_i = b_i` free), so the
//!   friction law is a pair of bounds; in 3D the [`SIDES`](columns::SIDES) edges of the outer
//!   polygon's cone (at `mu = infinity` the reaction components, tangents free); a node
//!   without a reaction has them fixed at zero;
//! - for a floating body, one free column per rigid amplitude that moves some contact node
//!   normally ([`Formulation::amplitude_of`]): `u = G r + R a`;
//! - rows, each a row activity with bounds: the scaled gaps `u_n_i` (`= 0` in contact, `>= 0`
//!   otherwise), the pressures `r_n_i` (`>= 1` on the nodes of [`Norm::Pressed`], free
//!   otherwise), the total `sum r_n` (`= 1` for [`Norm::Sum`], free otherwise), one drive
//!   cut per node ([`cuts::row`]; free where the node is not undecided or has none), and for a
//!   floating body the balance `R^T r = 0` ([`Formulation::balance_rows`]). A point is the
//!   reactions, then the `k` amplitudes (`0` for a mode without a column), as
//!   [`Formulation`]'s programs give.
//!
//! The matrix depends on `mu` and on the drive bounds only: it is built once per such shape
//! and shared by the shape's programs (each thread keeps the last few, [`LpCounters`]), and a
//! [`Warm`] basis made for other ones keeps its basic set but forgets its inverse.
//!
//! **Answers** are checked by [`super::simplex`] as [`super::socp`] checks Clarabel's. A
//! program the simplex method cannot decide goes to Clarabel
//! ([`Formulation::decide_cut`]); `fallbacks` counts those. A search's inner node, whose
//! program only prunes or guides, first tries its relaxation normalised by the sum
//! ([`decide_inner`]; `relaxed` counts those).

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use super::cuts::{self, Drive};
use super::program::{Class, Decision, Formulation, Goal, Norm};
use super::simplex::{self, Answer, Basis, Lp, Reduced};

mod columns;

use columns::{corners, gather, per_node, spread};

/// The bound on the total pressure of a program normalised by [`Norm::Pressed`] (each contact
/// node `r_n_i >= 1`): such a program asks for a solution that presses every contact node with
/// at least `1 / PRESSED_TOTAL` of its total pressure, the resolution of the method
/// ([`super::program::POSITIVE`]). Without it, a solution that presses one node a million
/// times less than the others lies so far out that an infeasibility certificate may drop the
/// terms that would have admitted it: on issue 20's plug at m = 60 two pieces whose thinnest
/// contact pressure is 7e-7 of the total were lost that way.
const PRESSED_TOTAL: f64 = 1.0 / super::program::POSITIVE;

/// A basis and what its matrix was made for.
#[derive(Debug, Clone)]
pub(crate) struct Warm {
    basis: Basis,
    /// `mu` as bits.
    mu: u64,
    /// The drive bounds (by address; `0` for none).
    drive: usize,
}

impl Warm {
    /// The same start with every row that is not idle active ([`simplex::Basis::all_rows`]).
    pub(crate) fn all_rows(self) -> Warm {
        Warm {
            basis: self.basis.all_rows(),
            ..self
        }
    }

    /// The same start without the basis's dense inverse (`(3m)^2` numbers, refactored when
    /// next used): for a search node kept until later (a unit of a sharded search).
    pub(crate) fn shelved(&self) -> Warm {
        Warm {
            basis: self.basis.without_inverse(),
            mu: self.mu,
            drive: self.drive,
        }
    }
}

/// The matrix of a program: the level `mu` and the drive bounds of the cuts.
#[derive(Clone, Copy)]
pub(crate) struct Shape<'d> {
    pub mu: f64,
    pub drive: Option<&'d Arc<Drive>>,
}

impl Shape<'_> {
    fn drive_key(&self) -> usize {
        self.drive.map_or(0, |d| Arc::as_ptr(d) as usize)
    }
}

/// Counts of a run.
#[derive(Debug, Default)]
pub(crate) struct LpCounters {
    /// Programs the simplex method decided.
    pub solves: AtomicU64,
    /// Simplex pivots, in all.
    pub pivots: AtomicU64,
    /// Programs it could not, passed to Clarabel.
    pub fallbacks: AtomicU64,
    /// Inner nodes' pressed programs it could not decide but decided normalised by the sum
    /// instead ([`decide_inner`]).
    pub relaxed: AtomicU64,
    /// Which counters these are (the key of the matrices they kept, [`LpCounters::matrix`]).
    id: Id,
}

/// A process-wide number for each [`LpCounters`] (a thread's kept matrices are keyed by it, not
/// by an address that a later formulation may reuse).
#[derive(Debug)]
struct Id(u64);

impl Default for Id {
    fn default() -> Id {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        Id(NEXT.fetch_add(1, Ordering::Relaxed))
    }
}

/// A matrix kept for its shape: the counters' [`Id`], `mu` as bits, the drive bounds (held,
/// so that their address is not reused while they are compared by it) and the matrix.
struct Kept {
    id: u64,
    mu: u64,
    drive: Option<Arc<Drive>>,
    a: Arc<Vec<f64>>,
    reduced: Option<Arc<Reduced>>,
}

/// A shape's matrix and, in 3D, its factors ([`Reduced`]).
type Matrix = (Arc<Vec<f64>>, Option<Arc<Reduced>>);

/// At most this many shapes' matrices are kept per thread (a search uses a few at a time: its
/// current drive bounds and their parent's, `critical`'s levels).
const KEEP_SHAPES: usize = 8;

thread_local! {
    /// The matrices of the shapes this thread used last, the latest first.
    static SHAPES: RefCell<Vec<Kept>> = const { RefCell::new(Vec::new()) };
}

impl LpCounters {
    /// The matrix of `shape`'s programs for `form` (the one formulation that these counters
    /// serve), built when this thread does not keep it.
    fn matrix(&self, form: &Formulation, shape: Shape) -> Matrix {
        let (id, mu) = (self.id.0, shape.mu.to_bits());
        let same = |k: &Kept| {
            k.id == id
                && k.mu == mu
                && match (&k.drive, shape.drive) {
                    (None, None) => true,
                    (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                    _ => false,
                }
        };
        let kept = SHAPES.with(|shapes| {
            let mut shapes = shapes.borrow_mut();
            let at = shapes.iter().position(same)?;
            let kept = shapes.remove(at);
            let a = (Arc::clone(&kept.a), kept.reduced.clone());
            shapes.insert(0, kept);
            Some(a)
        });
        if let Some(a) = kept {
            return a;
        }
        let (a, reduced) = matrix(form, shape);
        let (a, reduced) = (Arc::new(a), reduced.map(Arc::new));
        SHAPES.with(|shapes| {
            let mut shapes = shapes.borrow_mut();
            shapes.insert(
                0,
                Kept {
                    id,
                    mu,
                    drive: shape.drive.cloned(),
                    a: Arc::clone(&a),
                    reduced: reduced.clone(),
                },
            );
            shapes.truncate(KEEP_SHAPES);
        });
        (a, reduced)
    }
}

/// The matrix of the programs of `shape` (`3m + 1 + k` rows of the columns, row-major; see
/// the module docs): the same for every node of a search that has the same `mu` and drive
/// bounds, so built once and kept by each thread that uses it ([`LpCounters::matrix`]). In
/// 3D also its factors ([`Reduced`]: the rows over the reaction components and amplitudes,
/// and [`put_row`]'s map of them onto the columns), through which the simplex method takes
/// its row products: a row of `3m + k` numbers and two terms a column instead of `SIDES m`.
fn matrix(form: &Formulation, shape: Shape) -> (Vec<f64>, Option<Reduced>) {
    let m = form.m;
    let d = form.dim;
    let reactions = d * m;
    let n = per_node(d) * m + form.amplitudes();
    let rows = 3 * m + 1 + form.modes;
    let mu = shape.mu;
    let width = form.width();
    let mut a = vec![0.0; n * rows];
    let mut small = vec![0.0; width * rows];
    let mut set_row = |k: usize, row: &[f64]| {
        put_row(form, mu, row, &mut a[k * n..(k + 1) * n]);
        small[k * width..k * width + row.len()].copy_from_slice(row);
    };
    let mut unit = vec![0.0; reactions];
    for i in 0..m {
        set_row(i, form.gap_row(i));
        unit.iter_mut().for_each(|x| *x = 0.0);
        unit[d * i] = 1.0;
        set_row(m + i, &unit);
    }
    let all: Vec<f64> = (0..reactions)
        .map(|c| if c % d == 0 { 1.0 } else { 0.0 })
        .collect();
    set_row(2 * m, &all);
    for (j, row) in form.balance_rows().iter().enumerate() {
        set_row(3 * m + 1 + j, row);
    }
    if let Some(drive) = shape.drive {
        for (j, &(lo, hi)) in drive.iter().enumerate() {
            if let Some(row) = cuts::row(form, j, lo, hi) {
                set_row(2 * m + 1 + j, &row);
            }
        }
    }
    let reduced = (d == 3).then(|| {
        let amplitude: Vec<Option<usize>> = (0..form.modes).map(|j| form.amplitude_of(j)).collect();
        let amplitude = Arc::new(amplitude);
        let of = Arc::clone(&amplitude);
        Reduced {
            width,
            a: small,
            expand: Box::new(move |w: &[f64], out: &mut [f64]| {
                spread((d, m, mu), |j| amplitude[j], w, out)
            }),
            gather: Box::new(move |x: &[f64], w: &mut [f64]| gather((d, m, mu), |j| of[j], x, w)),
        }
    });
    (a, reduced)
}

/// The program of `classes` at `shape`, normalised by `norm` ([`Norm::Sum`] or
/// [`Norm::Pressed`]), minimising `objective` over the reaction components (none: zero).
fn program(
    form: &Formulation,
    counters: &LpCounters,
    classes: &[Class],
    shape: Shape,
    norm: Norm,
    objective: Option<&[f64]>,
) -> Lp {
    let m = form.m;
    let d = form.dim;
    let g = per_node(d);
    let n = g * m + form.amplitudes();
    let modes = form.modes;
    let rows = 3 * m + 1 + modes;
    let mu = shape.mu;
    let (a, reduced) = counters.matrix(form, shape);
    let mut lp = Lp::with_matrix(n, rows, a);
    if let Some(reduced) = reduced {
        lp = lp.with_reduced(reduced);
    }
    for k in 3 * m + 1..rows {
        (lp.lo[n + k], lp.hi[n + k]) = (0.0, 0.0);
    }
    if let Some(drive) = shape.drive {
        for (j, &(lo, hi)) in drive.iter().enumerate() {
            if cuts::has_row(lo, hi) && classes[j] == Class::Free {
                (lp.lo[n + 2 * m + 1 + j], lp.hi[n + 2 * m + 1 + j]) = (0.0, f64::INFINITY);
            }
        }
    }
    // Every friction edge is at most the total pressure: 1, or PRESSED_TOTAL when the
    // contact nodes are pressed (bounds that make an infeasibility certificate need no term
    // dropped, see `simplex`).
    let cap = match norm {
        Norm::Pressed(_) => PRESSED_TOTAL,
        _ => 1.0,
    };
    for (i, &c) in classes.iter().enumerate() {
        let has_r = c.has_r();
        let columns = g * i..g * (i + 1);
        for (k, col) in columns.enumerate() {
            (lp.lo[col], lp.hi[col]) = match (has_r, mu.is_finite(), k) {
                (false, _, _) => (0.0, 0.0),
                (true, true, _) | (true, false, 0) => (0.0, cap),
                (true, false, k) if k < d => (f64::NEG_INFINITY, f64::INFINITY),
                (true, false, _) => (0.0, 0.0),
            };
        }
        let gap = n + i;
        (lp.lo[gap], lp.hi[gap]) = match c {
            Class::Contact | Class::Grazing => (0.0, 0.0),
            Class::Separated | Class::Free => (0.0, f64::INFINITY),
        };
    }
    match norm {
        Norm::Sum => (lp.lo[n + 2 * m], lp.hi[n + 2 * m]) = (1.0, 1.0),
        Norm::Pressed(nodes) => {
            for &i in nodes {
                lp.lo[n + m + i] = 1.0;
            }
            (lp.lo[n + 2 * m], lp.hi[n + 2 * m]) = (0.0, PRESSED_TOTAL);
        }
        Norm::Gap(_) => unreachable!("the search normalises by the sum or by pressed nodes"),
    }
    if let Some(objective) = objective {
        put_row(form, mu, objective, &mut lp.cost[..n]);
    }
    lp
}

/// Writes `row` (over the `dm` reactions, then a floating body's `k` amplitudes) into `out`, a
/// program's row over each node's friction edges ([`per_node`] of them) at `mu` and then the
/// amplitude columns.
pub(super) fn put_row(form: &Formulation, mu: f64, row: &[f64], out: &mut [f64]) {
    spread((form.dim, form.m, mu), |j| form.amplitude_of(j), row, out)
}

/// The point of the columns `x` at `mu`: the reactions (`dm`), then for a floating body the
/// `k` rigid amplitudes.
fn point(form: &Formulation, x: &[f64], mu: f64) -> Vec<f64> {
    let (m, d) = (form.m, form.dim);
    let g = per_node(d);
    let mut r = vec![0.0; d * m];
    for (cols, out) in x.chunks(g).zip(r.chunks_mut(d)).take(m) {
        match (d, mu.is_finite()) {
            (2, true) => {
                out[0] = cols[0] + cols[1];
                out[1] = mu * (cols[0] - cols[1]);
            }
            (_, true) => {
                for (&l, &(c, s)) in cols.iter().zip(corners()) {
                    out[0] += l;
                    out[1] += mu * c * l;
                    out[2] += mu * s * l;
                }
            }
            (_, false) => out.copy_from_slice(&cols[..d]),
        }
    }
    r.extend((0..form.modes).map(|j| form.amplitude_of(j).map_or(0.0, |c| x[g * m + c])));
    r
}

/// A start for programs of `shape` from `warm` (its inverse dropped when it was made for
/// another matrix).
fn start(warm: Option<&Warm>, shape: Shape) -> Option<Basis> {
    let warm = warm?;
    let mut basis = warm.basis.clone();
    if warm.mu != shape.mu.to_bits() || warm.drive != shape.drive_key() {
        basis.forget();
    }
    Some(basis)
}

/// Solves the program of `classes` at `shape` with `norm` and `objective` (see [`program`]),
/// from `warm`. Returns the decision (reactions rescaled to `sum r_n = 1`; value the optimal
/// cost, `0` without an objective) and the final basis, when the simplex method decided; a
/// program it could not decide is solved by Clarabel, with no basis.
pub(crate) fn decide(
    form: &Formulation,
    counters: &LpCounters,
    classes: &[Class],
    shape: Shape,
    norm: Norm,
    objective: Option<&[f64]>,
    warm: Option<&Warm>,
) -> (Decision, Option<Warm>) {
    match by_simplex(form, counters, classes, shape, norm, objective, warm) {
        Ok((decision, warm)) => (decision, Some(warm)),
        Err(_) => (
            by_clarabel(form, counters, classes, shape, norm, objective),
            None,
        ),
    }
}

/// As [`decide`], for a search's inner node, whose program only says whether its subtree may
/// hold a solution (`No` prunes it; a point only guides the branching): a pressed program
/// ([`Norm::Pressed`]) that the simplex method cannot decide is asked again normalised by the
/// sum ([`Norm::Sum`], a relaxation of it: a pressed point divided by its total pressure is a
/// point of it), by the simplex method from the same start. Its `No` prunes the subtree as
/// well, and its point is a point of the subtree for the branching rule; only when it too
/// is undecided does Clarabel solve the pressed program.
///
/// (The pressed programs the simplex method could not decide, on the 2D plug at m = 200, all
/// ended in an infeasibility certificate whose check failed on terms at the rounding level,
/// about `1e-15` of the largest, against the pressed bound `1e7` of the basic columns; and
/// Clarabel then found every one of them feasible, at about 0.3 s each: 61 programs and
/// some 30% of the run's processor time.)
pub(crate) fn decide_inner(
    form: &Formulation,
    counters: &LpCounters,
    classes: &[Class],
    shape: Shape,
    norm: Norm,
    objective: Option<&[f64]>,
    warm: Option<&Warm>,
) -> (Decision, Option<Warm>) {
    let first = if pressed_fails() {
        Err("made to fail by a test".to_string())
    } else {
        by_simplex(form, counters, classes, shape, norm, objective, warm)
    };
    if let Ok((decision, warm)) = first {
        return (decision, Some(warm));
    }
    if matches!(norm, Norm::Pressed(_)) {
        let relaxed = by_simplex(form, counters, classes, shape, Norm::Sum, objective, warm);
        if let Ok((decision, warm)) = relaxed {
            counters.relaxed.fetch_add(1, Ordering::Relaxed);
            return (decision, Some(warm));
        }
    }
    (
        by_clarabel(form, counters, classes, shape, norm, objective),
        None,
    )
}

#[cfg(test)]
thread_local! {
    /// Whether [`decide_inner`] takes its pressed program as undecided (the tests' way to reach
    /// the relaxation, which the small problems of a test never need).
    static PRESSED_FAILS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

#[cfg(test)]
fn pressed_fails() -> bool {
    PRESSED_FAILS.with(|f| f.get())
}

#[cfg(not(test))]
fn pressed_fails() -> bool {
    false
}

/// The simplex method's decision on the program of [`decide`] and its final basis, or why it
/// could not decide.
fn by_simplex(
    form: &Formulation,
    counters: &LpCounters,
    classes: &[Class],
    shape: Shape,
    norm: Norm,
    objective: Option<&[f64]>,
    warm: Option<&Warm>,
) -> Result<(Decision, Warm), String> {
    let lp = program(form, counters, classes, shape, norm, objective);
    let basis = start(warm, shape);
    let (answer, basis, stats) = simplex::solve(&lp, basis.as_ref());
    counters.pivots.fetch_add(stats.pivots, Ordering::Relaxed);
    let warm = Warm {
        basis,
        mu: shape.mu.to_bits(),
        drive: shape.drive_key(),
    };
    match answer {
        Answer::Optimal { x, value } => {
            counters.solves.fetch_add(1, Ordering::Relaxed);
            let mut r = point(form, &x, shape.mu);
            if !matches!(norm, Norm::Sum) {
                let d = form.dim;
                let total: f64 = r[..d * form.m].iter().step_by(d).sum();
                r.iter_mut().for_each(|x| *x /= total);
            }
            Ok((Decision::Yes { r, value }, warm))
        }
        Answer::Infeasible { .. } => {
            counters.solves.fetch_add(1, Ordering::Relaxed);
            Ok((Decision::No, warm))
        }
        Answer::Failed(why) => Err(why),
    }
}

/// The program of [`decide`] solved by Clarabel ([`Formulation::decide_cut`]), counted as a
/// fallback.
fn by_clarabel(
    form: &Formulation,
    counters: &LpCounters,
    classes: &[Class],
    shape: Shape,
    norm: Norm,
    objective: Option<&[f64]>,
) -> Decision {
    counters.fallbacks.fetch_add(1, Ordering::Relaxed);
    let rows = shape
        .drive
        .map(|d| cuts::rows(form, classes, d))
        .unwrap_or_default();
    let goal = objective.map_or(Goal::Feasible, Goal::Minimise);
    form.decide_cut(classes, shape.mu, norm, goal, &rows).0
}

/// The relaxation of a search node (the classes [`cuts::tighten`] hands it, at `shape`, `sum
/// r_n = 1`) as the closure that [`cuts::tighten`] minimises over, each program started from
/// `start`, or from `previous`'s basis for the same program (its key, [`cuts::tighten`]) when
/// there is one; with `found`, each program's final basis is kept there (shelved, with the row
/// activities of its optimum) under its key.
pub(crate) fn relaxation<'a>(
    form: &'a Formulation,
    counters: &'a LpCounters,
    shape: Shape<'a>,
    start: Option<Warm>,
    previous: Option<&'a [Option<Warm>]>,
    found: Option<&'a [std::sync::Mutex<Option<Warm>>]>,
) -> impl Fn(usize, &[Class], &[f64]) -> Decision + Sync + 'a {
    // A tightening program's optimum lies far from the start's point: leaving out the rows
    // loose there costs more pivots than it saves (see the simplex method's `active`).
    let start = start.map(Warm::all_rows);
    move |key: usize, fixed: &[Class], objective: &[f64]| {
        let own = previous.and_then(|p| p.get(key)).and_then(|w| w.as_ref());
        let (decision, basis) = decide(
            form,
            counters,
            fixed,
            shape,
            Norm::Sum,
            Some(objective),
            own.or(start.as_ref()),
        );
        if let (Some(found), Some(basis)) = (found, basis) {
            if let Some(slot) = found.get(key) {
                *slot.lock().expect("no panics while held") = Some(basis.shelved());
            }
        }
        decision
    }
}

/// The bases the tightening programs of a node ended at ([`tighten_node`]), shelved, by program
/// key ([`cuts::tighten`]); `None` for a program that has none.
pub(crate) type Extremes = Vec<Option<Warm>>;

/// Where a tightening ([`tighten_node`]) starts: the node's relaxation from `warm` (the
/// parent's basis), each tightening program from its own basis in `previous` (by program key)
/// when there is one.
#[derive(Clone, Copy, Default)]
pub(crate) struct Starts<'a> {
    pub warm: Option<&'a Warm>,
    pub previous: Option<&'a [Option<Warm>]>,
    /// Whether a program's own basis leaves out the rows that were loose at its last optimum
    /// (the simplex method's `active`; they join again where the new optimum breaks them),
    /// or starts with every row. The same program's optimum moves little from round to round,
    /// so the rows loose there mostly stay so, and every pivot and refactoring works on fewer
    /// rows. (Measured, `farm-bench --vs` on one build, paired wall medians, 2026-11-28:
    /// `critical` on the 2D plug m = 50 0.94, m = 100 0.90, m = 140 0.93 (one run), the 3D
    /// V-groove m = 40 0.97, each with the same programs and answer; `enumerate` on the 2D
    /// plug at m = 80 1.05, so it keeps every row.)
    pub loose: bool,
}

/// Bound tightening at a search node ([`cuts::tighten`] over its relaxation at `shape`): the
/// new drive bounds, the relaxation's basis, and the basis each tightening program ended at
/// (shelved, by program key), or `None` when the relaxation is infeasible (the subtree holds no
/// solution at `shape.mu` or below). The relaxation is solved first from `warm`, so that an
/// infeasible node costs one program. Once `stop()`, the programs not yet solved are skipped
/// (their bounds stay).
///
/// Each program starts from the basis the same program ended at in `previous` (the last
/// tightening above this node, or the last round), else from the relaxation's. The objective
/// is the same and the feasible set a little smaller (a node fixed, tighter cuts), so that
/// basis is nearly optimal: it has no inverse (the cut rows changed) and is refactored, which
/// costs less than the pivots from the relaxation's basis to the optimum. (Measured on
/// issue 20's plug, whole process, paired medians on an idle machine: `critical` m = 60
/// 4.35 -> 3.76 s, m = 80 19.0 -> 16.7 s; `enumerate` m = 60 3.19 -> 2.54 s (485k -> 338k
/// pivots), m = 80 24.6 -> 21.1 s; the 3D V-groove at m = 20 unchanged.)
///
/// Settled ([`Settle::InParts`]), the tightening is repeated with the cuts of the bounds it
/// found until no bound interval shrinks by more than its `until` ([`SETTLED`] but in
/// `critical`'s passes) of its width in a round (at most [`SETTLE_ROUNDS`] rounds): each
/// round's cuts tighten the next round's relaxation. The searches settle their root's bounds,
/// which every node inherits. (Measured on issue 20's
/// plug, `enumerate`, whole process: m = 60, the root tightened once, 3, 8, 12, 20 times:
/// 46.5k, 41.6k, 27.1k, 22.8k, 16.2k nodes, 1.03M, 0.93M, 0.67M, 0.64M, 0.62M pivots; settled,
/// 17.2k nodes, 0.59M pivots.)
pub(crate) fn tighten_node(
    form: &Formulation,
    counters: &LpCounters,
    classes: &[Class],
    shape: Shape,
    start: Starts,
    settle: Settle,
    stop: &(dyn Fn() -> bool + Sync),
) -> Option<(Drive, Option<Warm>, Extremes)> {
    let Starts {
        warm,
        previous,
        loose,
    } = start;
    let mut known: Option<Arc<Drive>> = shape.drive.cloned();
    let mut warm = warm.cloned();
    let found: Vec<std::sync::Mutex<Option<Warm>>> = (0..2 * form.m)
        .map(|_| std::sync::Mutex::new(None))
        .collect();
    // This tightening's own bases once a round has ended; until then, `previous`'s.
    let mut kept: Option<Extremes> = None;
    // Programs per round come in `parts`; a settled tightening takes at most `SETTLE_ROUNDS`
    // whole rounds.
    let (parts, rounds, until) = match settle {
        Settle::Once => (1, 1, SETTLED),
        Settle::InParts { parts, until } => (parts.max(1), SETTLE_ROUNDS * parts.max(1), until),
    };
    // The largest shrink over the parts of the present round.
    let mut shrunk = 0.0f64;
    for pass in 0..rounds {
        let round = Shape {
            mu: shape.mu,
            drive: known.as_ref(),
        };
        let (first, basis) = decide(
            form,
            counters,
            classes,
            round,
            Norm::Sum,
            None,
            warm.as_ref(),
        );
        if first == Decision::No {
            return None;
        }
        let start = basis.or(warm);
        let minimise = relaxation(
            form,
            counters,
            round,
            start.clone(),
            kept.as_deref().or(previous),
            Some(&found[..]),
        );
        let part = (pass % parts, parts);
        let tight = cuts::tighten(form, classes, known.as_deref(), part, &minimise, stop)?;
        drop(minimise);
        // A program not solved this round (a stop, or one Clarabel decided) keeps the basis it
        // started from.
        let ended: Extremes = found
            .iter()
            .enumerate()
            .map(|(key, f)| {
                let own = f.lock().expect("no panics while held").take();
                let own = own.map(|w| if loose { w } else { w.all_rows() });
                own.or_else(|| kept.as_deref().or(previous)?.get(key)?.clone())
            })
            .collect();
        kept = Some(ended);
        let shrink = known
            .as_deref()
            .map_or(1.0, |old| cuts::largest_shrink(old, &tight));
        known = Some(Arc::new(tight));
        warm = start;
        shrunk = shrunk.max(shrink);
        if stop() {
            break;
        }
        if (pass + 1) % parts == 0 {
            if shrunk <= until {
                break;
            }
            shrunk = 0.0;
        }
    }
    let tight = known.map(Arc::unwrap_or_clone)?;
    Some((tight, warm, kept.unwrap_or_default()))
}

/// How many rounds a tightening ([`tighten_node`]) takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Settle {
    /// One round: every free node's two programs over the node's relaxation.
    Once,
    /// Rounds until the bounds settle, each round in this many parts: the free nodes taken in
    /// turn by their position among the free ones modulo the parts, each part's programs with
    /// the cuts of the bounds the parts before it found (as Gauss and Seidel's iteration takes
    /// each unknown with those updated before it; one part is Jacobi's, every program of a
    /// round with the last round's cuts). A part has the programs of a round over as many
    /// nodes, so a round costs about the same, and its later parts start from tighter cuts.
    /// (`critical`'s passes and the enumeration's root settle in three: `critical/bnb/tuning.rs`,
    /// `rays/search/tree.rs`.) The rounds stop when no bound interval shrinks by more than
    /// `until` of its width in a whole round ([`SETTLED`] unless a search measured better).
    InParts { parts: usize, until: f64 },
}

/// A settled tightening ([`tighten_node`]) stops when no bound interval shrinks by more than
/// this share of its width...
pub(crate) const SETTLED: f64 = 0.05;
/// ... or after this many rounds.
const SETTLE_ROUNDS: usize = 30;

/// The objective that asks a search node's program for a vertex: the least total of the
/// `free` nodes' scaled gaps and pressures (a point at which few free nodes break
/// complementarity, so the branching rule picks well; an interior point, at which many break
/// it a little, made the 2D plug's tree twice as large).
pub(crate) fn vertex_objective(form: &Formulation, free: &[usize]) -> Vec<f64> {
    let mut objective = vec![0.0; form.width()];
    for &j in free {
        for (a, g) in objective.iter_mut().zip(form.gap_row(j)) {
            *a += g;
        }
        objective[form.dim * j] += 1.0;
    }
    objective
}

#[cfg(test)]
mod tests;
