//! The support of a leaf's cone in the 2D contact-set search (`rays/search`): which friction
//! edges and which gaps some solution makes positive, one linear program for the in-house
//! simplex method ([`super::simplex`]). (The search's node programs are [`super::node_lp`].)
//!
//! **Answers** are checked by the simplex method (a point within its tolerance). A program it
//! cannot decide goes to Clarabel one entry at a time ([`Formulation::decide_at`]);
//! [`LpCounters::fallbacks`] counts those.

use std::sync::atomic::Ordering;

use super::node_lp::{self, LpCounters};
use super::program::{Class, Decision, Entry, Formulation, Goal, Norm, Support, POSITIVE};
use super::simplex::{self, Answer, Lp};

/// The bound on the total pressure of [`ContactLp::support`]: an entry that no solution makes
/// larger than `1 / (2 SUPPORT_SCALE)` of its total pressure counts as zero (a resolution
/// below [`super::program::POSITIVE`]).
const SUPPORT_SCALE: f64 = 1e7;

/// The search's programs over one formulation, and what they cost.
pub(crate) struct ContactLp<'f> {
    form: &'f Formulation<'f>,
    pub counters: LpCounters,
}

impl<'f> ContactLp<'f> {
    /// The programs of `form` (2D only).
    pub(crate) fn new(form: &'f Formulation<'f>) -> ContactLp<'f> {
        assert_eq!(form.dim, 2, "the contact-set programs are 2D");
        ContactLp {
            form,
            counters: LpCounters::default(),
        }
    }

    /// The formulation the programs are made of.
    pub(crate) fn form(&self) -> &'f Formulation<'f> {
        self.form
    }

    /// The support of the cone of `classes` (no normalisation): which of the friction edges
    /// `a_i`, `b_i` of the nodes with a reaction (`Edge`) and which gaps of the separated and
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
        // Columns: the friction edges, a floating body's free amplitudes, then the `t_e`.
        let n1 = n0 + form.amplitudes();
        let n = n1 + q;
        // Rows: the m gaps, one per entry (`e - t_e`), the total pressure, and a floating
        // body's balance `R^T r = 0`.
        let balance = form.balance_rows();
        let rows = m + q + 1 + balance.len();
        let mut lp = Lp::new(n, rows);
        for i in 0..m {
            node_lp::put_row(
                form,
                mu,
                form.gap_row(i),
                &mut lp.a_mut()[i * n..(i + 1) * n],
            );
        }
        for (k, e) in entries.iter().enumerate() {
            let row = m + k;
            let a = lp.a_mut();
            match *e {
                Entry2::Edge(col) => a[row * n + col] = 1.0,
                Entry2::Gap(i) => {
                    for c in 0..n1 {
                        a[row * n + c] = a[i * n + c];
                    }
                }
            }
            a[row * n + n1 + k] = -1.0;
            (lp.lo[n1 + k], lp.hi[n1 + k]) = (0.0, 1.0);
            lp.cost[n1 + k] = -1.0;
            (lp.lo[n + row], lp.hi[n + row]) = (0.0, f64::INFINITY);
        }
        let total = m + q;
        let a = lp.a_mut();
        for c in 0..n0 {
            a[total * n + c] = 1.0;
        }
        (lp.lo[n + total], lp.hi[n + total]) = (0.0, SUPPORT_SCALE);
        for (j, row) in balance.iter().enumerate() {
            let k = total + 1 + j;
            node_lp::put_row(form, mu, row, &mut lp.a_mut()[k * n..(k + 1) * n]);
            (lp.lo[n + k], lp.hi[n + k]) = (0.0, 0.0);
        }
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
            .filter(|&(k, _)| x[n1 + k] > 0.5)
            .map(|(_, e)| *e)
            .collect();
        if positive.is_empty() {
            return Ok(None);
        }
        Ok(Some(LeafSupport { positive }))
    }
}

impl ContactLp<'_> {
    /// The max-min program of [`Formulation::support`]'s witness (2D, a clamped body): the
    /// largest `t` such that one solution of the cone of `classes` with `sum r_n = 1` has
    /// every entry of `entries` at least `t` (a pressure `r_n_i`, a scaled gap, a stick slack
    /// `mu r_n_i - |r_t_i|`), with that solution `r` (`t <= 1`). `Ok(None)` when the cone is
    /// `{0}`; `Err` when the simplex method cannot decide (the caller asks Clarabel).
    ///
    /// In the friction edges (`r_n = a + b`, `r_t = mu (a - b)`) a stick slack is
    /// `2 mu min(a, b)`, so it is two rows `a, b >= t / (2 mu)`. The point is a vertex of the
    /// optimal set, where Clarabel's lies inside it: the same value, every entry at least `t`.
    pub(crate) fn max_min(
        &self,
        classes: &[Class],
        entries: &[Entry],
    ) -> Result<Option<(Vec<f64>, f64)>, String> {
        let form = self.form;
        assert_eq!(form.modes, 0, "a clamped body's program");
        let (m, mu) = (form.m, form.mu);
        let t = 2 * m;
        let n = t + 1;
        let rows_of = |e: &Entry| if matches!(e, Entry::Stick(_)) { 2 } else { 1 };
        let rows = m + entries.iter().map(rows_of).sum::<usize>() + 1;
        let mut lp = Lp::new(n, rows);
        for (i, &class) in classes.iter().enumerate() {
            node_lp::put_row(
                form,
                mu,
                form.gap_row(i),
                &mut lp.a_mut()[i * n..(i + 1) * n],
            );
            (lp.lo[n + i], lp.hi[n + i]) = match class {
                Class::Contact | Class::Grazing => (0.0, 0.0),
                Class::Separated | Class::Free => (0.0, f64::INFINITY),
            };
            let hi = if class.has_r() { 1.0 } else { 0.0 };
            for col in [2 * i, 2 * i + 1] {
                (lp.lo[col], lp.hi[col]) = (0.0, hi);
            }
        }
        let mut row = m;
        for &e in entries {
            let a = lp.a_mut();
            match e {
                Entry::Press(i) => {
                    a[row * n + 2 * i] = 1.0;
                    a[row * n + 2 * i + 1] = 1.0;
                    a[row * n + t] = -1.0;
                }
                Entry::Gap(i) => {
                    for c in 0..t {
                        a[row * n + c] = a[i * n + c];
                    }
                    a[row * n + t] = -1.0;
                }
                Entry::Stick(i) => {
                    for (k, col) in [2 * i, 2 * i + 1].into_iter().enumerate() {
                        a[(row + k) * n + col] = 1.0;
                        a[(row + k) * n + t] = -0.5 / mu;
                    }
                }
            }
            for k in row..row + rows_of(&e) {
                (lp.lo[n + k], lp.hi[n + k]) = (0.0, f64::INFINITY);
            }
            row += rows_of(&e);
        }
        let a = lp.a_mut();
        for c in 0..t {
            a[row * n + c] = 1.0;
        }
        (lp.lo[n + row], lp.hi[n + row]) = (1.0, 1.0);
        (lp.lo[t], lp.hi[t], lp.cost[t]) = (0.0, 1.0, -1.0);
        let (answer, _, stats) = simplex::solve(&lp, None);
        self.counters
            .pivots
            .fetch_add(stats.pivots, Ordering::Relaxed);
        self.counters.solves.fetch_add(1, Ordering::Relaxed);
        match answer {
            Answer::Optimal { x, .. } => {
                let mut r = vec![0.0; 2 * m];
                for i in 0..m {
                    let (a, b) = (x[2 * i], x[2 * i + 1]);
                    (r[2 * i], r[2 * i + 1]) = (a + b, mu * (a - b));
                }
                Ok(Some((r, x[t])))
            }
            Answer::Infeasible { .. } => Ok(None),
            Answer::Failed(why) => {
                self.counters.fallbacks.fetch_add(1, Ordering::Relaxed);
                Err(why)
            }
        }
    }

    /// [`Formulation::support`] by the simplex method (2D, a clamped body): the entries of
    /// `wanted` that some solution makes positive and a solution that makes them all at least
    /// its `value`. First all of them pushed up together ([`ContactLp::max_min`]); when some
    /// stay at zero, the cone's support ([`ContactLp::support`], one program) says which can
    /// be positive (a stick slack when both friction edges can), and those are pushed up
    /// together. `Err` when a program cannot be decided or the entries positive in the support
    /// do not reach half of [`POSITIVE`] together (the caller then asks Clarabel).
    pub(crate) fn witness(
        &self,
        classes: &[Class],
        wanted: &[Entry],
    ) -> Result<Option<Support>, String> {
        let Some((r, value)) = self.max_min(classes, wanted)? else {
            return Ok(None);
        };
        if value > POSITIVE {
            let entries = wanted.to_vec();
            return Ok(Some(Support { entries, r, value }));
        }
        let Some(support) = self.support(classes)? else {
            return Ok(None);
        };
        let edge = |c: usize| support.positive.contains(&Entry2::Edge(c));
        let found: Vec<Entry> = wanted
            .iter()
            .copied()
            .filter(|&e| match e {
                Entry::Press(i) => edge(2 * i) || edge(2 * i + 1),
                Entry::Stick(i) => edge(2 * i) && edge(2 * i + 1),
                Entry::Gap(i) => support.positive.contains(&Entry2::Gap(i)),
            })
            .collect();
        if found.is_empty() {
            return Ok(Some(Support {
                entries: found,
                r,
                value: 0.0,
            }));
        }
        // The support program's own optimum makes every entry of `found` at least
        // `1 / (2 SUPPORT_SCALE)` = `POSITIVE / 2` of its total pressure (the decision is at
        // `t_e = 1/2`), so that is what they reach together, and what the witness check asks
        // (`patterns::check_witness`). Asking `POSITIVE` here left a piece of the 2D plug at
        // m = 100 undecided (together 6.8e-8, its entries each above `POSITIVE` on their own).
        match self.max_min(classes, &found)? {
            Some((r, value)) if value > POSITIVE * 0.5 => Ok(Some(Support {
                entries: found,
                r,
                value,
            })),
            Some((_, value)) => Err(format!(
                "entries in the support reached only {value:e} together"
            )),
            None => Ok(None),
        }
    }

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
        let mu = form.mu;
        let mut positive = Vec::new();
        for &e in entries {
            // Minimise minus the entry, a linear function of the reactions:
            // a_i = (r_n + r_t / mu) / 2, b_i = (r_n - r_t / mu) / 2.
            let mut c = vec![0.0; form.width()];
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
