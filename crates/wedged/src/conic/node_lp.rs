//! The 2D search node over contact sets (`critical`'s `bnb` and the enumeration's
//! `rays/search`) as a linear program for the in-house simplex method ([`super::simplex`]),
//! warm-started from the parent's basis.
//!
//! **The program** has one fixed shape for the whole search, so that a basis carries over from
//! a node to its children and to its bound-tightening programs, which differ only in bounds
//! and costs:
//! - two columns per node, `a_i, b_i >= 0`, the friction cone's edges: `r_n_i = a_i + b_i`,
//!   `r_t_i = mu (a_i - b_i)` (at `mu = infinity`: `r_n_i = a_i`, `r_t_i = b_i` free), so the
//!   friction law is a pair of bounds; a node without a reaction has both fixed at zero;
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
//! The matrix depends on `mu` and on the drive bounds only; a [`Warm`] basis made for other
//! ones keeps its basic set but forgets its inverse.
//!
//! **Answers** are checked by [`super::simplex`] as [`super::socp`] checks Clarabel's. A
//! program the simplex method cannot decide goes to Clarabel
//! ([`Formulation::decide_cut`]); `fallbacks` counts those.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use super::cuts::{self, Drive};
use super::program::{Class, Decision, Formulation, Goal, Norm};
use super::simplex::{self, Answer, Basis, Lp};

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
}

/// Column coefficients of a row over the reaction components (`2m`), at `mu`.
fn on_columns(row: &[f64], mu: f64) -> impl Iterator<Item = (f64, f64)> + '_ {
    row.chunks(2).map(move |w| {
        if mu.is_finite() {
            (w[0] + mu * w[1], w[0] - mu * w[1])
        } else {
            (w[0], w[1])
        }
    })
}

/// The program of `classes` at `shape`, normalised by `norm` ([`Norm::Sum`] or
/// [`Norm::Pressed`]), minimising `objective` over the reaction components (none: zero).
fn program(
    form: &Formulation,
    classes: &[Class],
    shape: Shape,
    norm: Norm,
    objective: Option<&[f64]>,
) -> Lp {
    let m = form.m;
    let reactions = 2 * m;
    let n = reactions + form.amplitudes();
    let modes = form.modes;
    let rows = 3 * m + 1 + modes;
    let mu = shape.mu;
    let mut lp = Lp::new(n, rows);
    let set_row = |lp: &mut Lp, k: usize, row: &[f64]| {
        put_row(form, mu, row, &mut lp.a[k * n..(k + 1) * n]);
    };
    let mut unit = vec![0.0; reactions];
    for i in 0..m {
        set_row(&mut lp, i, form.gap_row(i));
        unit.iter_mut().for_each(|x| *x = 0.0);
        unit[2 * i] = 1.0;
        set_row(&mut lp, m + i, &unit);
    }
    let all: Vec<f64> = (0..reactions)
        .map(|c| if c % 2 == 0 { 1.0 } else { 0.0 })
        .collect();
    set_row(&mut lp, 2 * m, &all);
    for (j, row) in form.balance_rows().iter().enumerate() {
        let k = 3 * m + 1 + j;
        set_row(&mut lp, k, row);
        (lp.lo[n + k], lp.hi[n + k]) = (0.0, 0.0);
    }
    if let Some(drive) = shape.drive {
        for (j, &(lo, hi)) in drive.iter().enumerate() {
            if let Some(row) = cuts::row(form, j, lo, hi) {
                set_row(&mut lp, 2 * m + 1 + j, &row);
                if classes[j] == Class::Free {
                    (lp.lo[n + 2 * m + 1 + j], lp.hi[n + 2 * m + 1 + j]) = (0.0, f64::INFINITY);
                }
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
        let (a, b) = (2 * i, 2 * i + 1);
        (lp.lo[a], lp.hi[a]) = (0.0, if has_r { cap } else { 0.0 });
        (lp.lo[b], lp.hi[b]) = match (has_r, mu.is_finite()) {
            (false, _) => (0.0, 0.0),
            (true, true) => (0.0, cap),
            (true, false) => (f64::NEG_INFINITY, f64::INFINITY),
        };
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

/// Writes `row` (over the `2m` reactions, then a floating body's `k` amplitudes) into `out`, a
/// program's row over the friction edges `a_i, b_i` at `mu` and then the amplitude columns.
pub(super) fn put_row(form: &Formulation, mu: f64, row: &[f64], out: &mut [f64]) {
    let reactions = 2 * form.m;
    for (i, (a, b)) in on_columns(&row[..reactions], mu).enumerate() {
        out[2 * i] = a;
        out[2 * i + 1] = b;
    }
    for (j, &x) in row.get(reactions..).unwrap_or(&[]).iter().enumerate() {
        if let Some(c) = form.amplitude_of(j) {
            out[reactions + c] = x;
        }
    }
}

/// The point of the columns `x` at `mu`: the reactions (`2m`), then for a floating body the
/// `k` rigid amplitudes.
fn point(form: &Formulation, x: &[f64], mu: f64) -> Vec<f64> {
    let m = form.m;
    let mut r = reactions(x, m, mu);
    r.extend((0..form.modes).map(|j| form.amplitude_of(j).map_or(0.0, |c| x[2 * m + c])));
    r
}

/// The reactions (`2m`) of the columns `x`, at `mu`.
fn reactions(x: &[f64], m: usize, mu: f64) -> Vec<f64> {
    let mut r = vec![0.0; 2 * m];
    for i in 0..m {
        let (a, b) = (x[2 * i], x[2 * i + 1]);
        if mu.is_finite() {
            r[2 * i] = a + b;
            r[2 * i + 1] = mu * (a - b);
        } else {
            r[2 * i] = a;
            r[2 * i + 1] = b;
        }
    }
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
    let lp = program(form, classes, shape, norm, objective);
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
                let total: f64 = r[..2 * form.m].iter().step_by(2).sum();
                r.iter_mut().for_each(|x| *x /= total);
            }
            (Decision::Yes { r, value }, Some(warm))
        }
        Answer::Infeasible { .. } => {
            counters.solves.fetch_add(1, Ordering::Relaxed);
            (Decision::No, Some(warm))
        }
        Answer::Failed(_) => {
            counters.fallbacks.fetch_add(1, Ordering::Relaxed);
            let rows = shape
                .drive
                .map(|d| cuts::rows(form, classes, d))
                .unwrap_or_default();
            let goal = objective.map_or(Goal::Feasible, Goal::Minimise);
            (
                form.decide_cut(classes, shape.mu, norm, goal, &rows).0,
                None,
            )
        }
    }
}

/// The relaxation of a search node (`classes` at `shape`, `sum r_n = 1`) as the closure that
/// [`cuts::tighten`] minimises over, each program started from `start`.
pub(crate) fn relaxation<'a>(
    form: &'a Formulation,
    counters: &'a LpCounters,
    classes: &'a [Class],
    shape: Shape<'a>,
    start: Option<Warm>,
) -> impl Fn(&[f64]) -> Decision + Sync + 'a {
    move |objective: &[f64]| {
        let start = start.as_ref();
        decide(
            form,
            counters,
            classes,
            shape,
            Norm::Sum,
            Some(objective),
            start,
        )
        .0
    }
}
