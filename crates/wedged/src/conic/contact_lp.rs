//! The 2D programs of the contact-set search (`rays/search`) as linear programs for the in-house
//! simplex method ([`super::simplex`]), warm-started from the parent's basis.
//!
//! **The program** has one matrix for the whole search; a search node changes bounds only, so
//! the parent's basis (and its inverse) carries over to the children:
//! - two columns per node, `a_i, b_i >= 0`, the edges of the friction cone: `r_n_i = a_i + b_i`,
//!   `r_t_i = mu (a_i - b_i)`; a node without a reaction has both fixed at zero;
//! - rows (each a row activity with bounds): the scaled gaps `u_n_i` ([`Formulation::gap_row`];
//!   `= 0` in contact, `>= 0` otherwise), the pressures `r_n_i` (`>= 1` at the nodes of
//!   [`Norm::Pressed`], `>= 0` otherwise) and the total `sum r_n` (`>= 1` for [`Norm::Sum`]).
//!
//! Every program is a feasibility question about a cone, so `>= 1` is the same as `> 0`: a
//! pressed program is feasible exactly when one solution presses all the listed nodes at once.
//!
//! **Answers** are checked by the simplex method (a point within its tolerance, or a Farkas
//! certificate that excludes every point by a clear margin). A program it cannot decide goes to
//! Clarabel ([`Formulation::decide_at`]); [`LpCounters::fallbacks`] counts those.

use std::sync::atomic::{AtomicU64, Ordering};

use super::program::{Class, Decision, Formulation, Goal, Norm};
use super::simplex::{self, Answer, Basis, Lp};

/// A warm start handed from a search node to its children: the simplex method's final basis,
/// opaque outside `conic`.
pub(crate) type Warm = Basis;

/// The bound on the total pressure of [`ContactLp::support`]: an entry that no solution makes
/// larger than `1 / (2 SUPPORT_SCALE)` of its total pressure counts as zero (a resolution
/// below [`super::program::POSITIVE`]).
const SUPPORT_SCALE: f64 = 1e7;

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

/// The search's program: the matrix, made once, and the bounds of the free start.
pub(crate) struct ContactLp<'f> {
    form: &'f Formulation<'f>,
    template: Lp,
    pub counters: LpCounters,
}

impl<'f> ContactLp<'f> {
    /// The program of `form` (2D only).
    pub(crate) fn new(form: &'f Formulation<'f>) -> ContactLp<'f> {
        assert_eq!(form.dim, 2, "the contact-set programs are 2D");
        let m = form.m;
        let n = 2 * m;
        let mu = form.mu;
        let mut lp = Lp::new(n, 2 * m + 1);
        for i in 0..m {
            for (j, w) in form.gap_row(i).chunks(2).enumerate() {
                lp.a[i * n + 2 * j] = w[0] + mu * w[1];
                lp.a[i * n + 2 * j + 1] = w[0] - mu * w[1];
            }
            lp.a[(m + i) * n + 2 * i] = 1.0;
            lp.a[(m + i) * n + 2 * i + 1] = 1.0;
            lp.a[2 * m * n + 2 * i] = 1.0;
            lp.a[2 * m * n + 2 * i + 1] = 1.0;
        }
        ContactLp {
            form,
            template: lp,
            counters: LpCounters::default(),
        }
    }

    /// The program of `classes` normalised by `norm`.
    fn program(&self, classes: &[Class], norm: Norm) -> Lp {
        let m = self.form.m;
        let n = 2 * m;
        let mut lp = self.template.clone();
        for (i, &c) in classes.iter().enumerate() {
            let hi = if c.has_r() { f64::INFINITY } else { 0.0 };
            for col in [2 * i, 2 * i + 1] {
                (lp.lo[col], lp.hi[col]) = (0.0, hi);
            }
            let gap = n + i;
            (lp.lo[gap], lp.hi[gap]) = match c {
                Class::Contact | Class::Grazing => (0.0, 0.0),
                Class::Separated | Class::Free => (0.0, f64::INFINITY),
            };
            (lp.lo[n + m + i], lp.hi[n + m + i]) = (0.0, f64::INFINITY);
        }
        (lp.lo[n + 2 * m], lp.hi[n + 2 * m]) = (0.0, f64::INFINITY);
        match norm {
            Norm::Sum => lp.lo[n + 2 * m] = 1.0,
            Norm::Pressed(nodes) => nodes.iter().for_each(|&i| lp.lo[n + m + i] = 1.0),
            Norm::Gap(j) => lp.lo[n + j] = 1.0,
        }
        lp
    }

    /// Decides whether the program of `classes` normalised by `norm` is feasible, from `warm`.
    /// Returns the decision (reactions rescaled to `sum r_n = 1`) and the final basis, when the
    /// simplex method decided (Clarabel decides the others, with no basis).
    pub(crate) fn decide(
        &self,
        classes: &[Class],
        norm: Norm,
        warm: Option<&Basis>,
    ) -> (Decision, Option<Basis>) {
        let lp = self.program(classes, norm);
        let (answer, basis, stats) = simplex::solve(&lp, warm);
        self.counters
            .pivots
            .fetch_add(stats.pivots, Ordering::Relaxed);
        match answer {
            Answer::Optimal { x, .. } => {
                self.counters.solves.fetch_add(1, Ordering::Relaxed);
                (
                    Decision::Yes {
                        r: self.reactions(&x),
                        value: 0.0,
                    },
                    Some(basis),
                )
            }
            Answer::Infeasible { .. } => {
                self.counters.solves.fetch_add(1, Ordering::Relaxed);
                (Decision::No, Some(basis))
            }
            Answer::Failed(_) => {
                self.counters.fallbacks.fetch_add(1, Ordering::Relaxed);
                let decision = self
                    .form
                    .decide_at(classes, self.form.mu, norm, Goal::Feasible);
                (decision, None)
            }
        }
    }

    /// The reactions (`2m`, `sum r_n = 1`) of the columns `x`.
    fn reactions(&self, x: &[f64]) -> Vec<f64> {
        let (m, mu) = (self.form.m, self.form.mu);
        let mut r = vec![0.0; 2 * m];
        for i in 0..m {
            let (a, b) = (x[2 * i], x[2 * i + 1]);
            r[2 * i] = a + b;
            r[2 * i + 1] = mu * (a - b);
        }
        let total: f64 = r.iter().step_by(2).sum();
        if total > 0.0 {
            r.iter_mut().for_each(|v| *v /= total);
        }
        r
    }

    /// The support of the cone of `classes` (no normalisation): which of the friction edges
    /// `a_i`, `b_i` of the nodes with a reaction ([`Edge`]) and which gaps of the separated and
    /// free nodes some solution makes positive. `Ok(None)` when the cone is `{0}`; `Err` when the
    /// simplex method cannot decide.
    ///
    /// One program: maximise `sum_e t_e` with `0 <= t_e <= 1` and `e >= t_e` for every entry
    /// `e`, and `sum r_n <= SUPPORT_SCALE`. The cone is closed under scaling, so the optimum
    /// has `t_e = 1` for the entries that some solution makes at least `1 / SUPPORT_SCALE` of
    /// its total pressure, and `0` for the entries that are zero; the decision is at `1/2`.
    /// (Without the bound on the total, round-off can make the program look unbounded.)
    pub(crate) fn support(&self, classes: &[Class]) -> Result<Option<LeafSupport>, String> {
        let form = self.form;
        let (m, mu) = (form.m, form.mu);
        let n0 = 2 * m;
        let mut entries: Vec<Entry2> = Vec::new();
        for (i, &c) in classes.iter().enumerate() {
            if c.has_r() {
                entries.push(Entry2::Edge(2 * i));
                entries.push(Entry2::Edge(2 * i + 1));
            }
            if matches!(c, Class::Separated | Class::Free) {
                entries.push(Entry2::Gap(i));
            }
        }
        let q = entries.len();
        let n = n0 + q;
        // Rows: the m gaps, one per entry (`e - t_e`), and the total pressure.
        let rows = m + q + 1;
        let mut lp = Lp::new(n, rows);
        for i in 0..m {
            for (j, w) in form.gap_row(i).chunks(2).enumerate() {
                lp.a[i * n + 2 * j] = w[0] + mu * w[1];
                lp.a[i * n + 2 * j + 1] = w[0] - mu * w[1];
            }
        }
        for (k, e) in entries.iter().enumerate() {
            let row = m + k;
            match *e {
                Entry2::Edge(col) => lp.a[row * n + col] = 1.0,
                Entry2::Gap(i) => {
                    for c in 0..n0 {
                        lp.a[row * n + c] = lp.a[i * n + c];
                    }
                }
            }
            lp.a[row * n + n0 + k] = -1.0;
            (lp.lo[n0 + k], lp.hi[n0 + k]) = (0.0, 1.0);
            lp.cost[n0 + k] = -1.0;
            (lp.lo[n + row], lp.hi[n + row]) = (0.0, f64::INFINITY);
        }
        for c in 0..n0 {
            lp.a[(rows - 1) * n + c] = 1.0;
        }
        (lp.lo[n + rows - 1], lp.hi[n + rows - 1]) = (0.0, SUPPORT_SCALE);
        for (i, &c) in classes.iter().enumerate() {
            let hi = if c.has_r() { f64::INFINITY } else { 0.0 };
            for col in [2 * i, 2 * i + 1] {
                (lp.lo[col], lp.hi[col]) = (0.0, hi);
            }
            (lp.lo[n + i], lp.hi[n + i]) = match c {
                Class::Contact | Class::Grazing => (0.0, 0.0),
                Class::Separated | Class::Free => (0.0, f64::INFINITY),
            };
        }
        let (answer, _, stats) = simplex::solve(&lp, None);
        self.counters
            .pivots
            .fetch_add(stats.pivots, Ordering::Relaxed);
        self.counters.solves.fetch_add(1, Ordering::Relaxed);
        let x = match answer {
            Answer::Optimal { x, .. } => x,
            Answer::Infeasible { .. } => {
                return Err("the support program is infeasible, but 0 solves it".into())
            }
            Answer::Failed(why) => {
                self.counters.fallbacks.fetch_add(1, Ordering::Relaxed);
                return self.support_one_at_a_time(classes, &entries, &why);
            }
        };
        let positive: Vec<Entry2> = entries
            .iter()
            .enumerate()
            .filter(|&(k, _)| x[n0 + k] > 0.5)
            .map(|(_, e)| *e)
            .collect();
        if positive.is_empty() {
            return Ok(None);
        }
        Ok(Some(LeafSupport { positive }))
    }
}

impl ContactLp<'_> {
    /// [`ContactLp::support`] when the simplex method cannot settle its program (an
    /// ill-conditioned face): Clarabel pushes each entry up on its own, normalised by
    /// `sum r_n = 1`, and an entry is positive when its largest value exceeds
    /// [`super::program::POSITIVE`]. One program per entry, so only a fallback.
    fn support_one_at_a_time(
        &self,
        classes: &[Class],
        entries: &[Entry2],
        why: &str,
    ) -> Result<Option<LeafSupport>, String> {
        let form = self.form;
        let (m, mu) = (form.m, form.mu);
        let mut positive = Vec::new();
        for &e in entries {
            // Minimise minus the entry, a linear function of the reactions:
            // a_i = (r_n + r_t / mu) / 2, b_i = (r_n - r_t / mu) / 2.
            let mut c = vec![0.0; 2 * m];
            match e {
                Entry2::Edge(col) => {
                    let i = col / 2;
                    let sign = if col % 2 == 0 { 1.0 } else { -1.0 };
                    c[2 * i] = -0.5;
                    c[2 * i + 1] = -0.5 * sign / mu;
                }
                Entry2::Gap(i) => {
                    c.iter_mut().zip(form.gap_row(i)).for_each(|(a, g)| *a = -g);
                }
            }
            match form.decide_at(classes, mu, Norm::Sum, Goal::Minimise(&c)) {
                Decision::No => return Ok(None),
                Decision::Unsure(e) => {
                    return Err(format!(
                        "the support program failed ({why}), and so did Clarabel ({e})"
                    ))
                }
                Decision::Yes { r, .. } => {
                    // The program reports no value for this goal: the entry at its optimum.
                    let value: f64 = c.iter().zip(&r).map(|(a, b)| -a * b).sum();
                    if value > super::program::POSITIVE {
                        positive.push(e);
                    }
                }
            }
        }
        Ok((!positive.is_empty()).then_some(LeafSupport { positive }))
    }
}

/// An entry of [`ContactLp::support`]: a friction edge (column `2i` is `a_i`, `2i + 1` is
/// `b_i`) or the gap of a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Entry2 {
    Edge(usize),
    Gap(usize),
}

/// The support of a cone ([`ContactLp::support`]).
#[derive(Debug, Clone)]
pub(crate) struct LeafSupport {
    /// The entries some solution makes positive.
    pub positive: Vec<Entry2>,
}

impl LeafSupport {
    /// Every friction edge of the nodes with a reaction and every gap of the others: the
    /// support assumed when it cannot be decided.
    pub(crate) fn everything(classes: &[Class]) -> LeafSupport {
        let mut positive = Vec::new();
        for (i, &c) in classes.iter().enumerate() {
            if c.has_r() {
                positive.extend([Entry2::Edge(2 * i), Entry2::Edge(2 * i + 1)]);
            } else {
                positive.push(Entry2::Gap(i));
            }
        }
        LeafSupport { positive }
    }
}
