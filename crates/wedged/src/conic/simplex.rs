//! A dense bounded simplex method with warm starts, for the small linear programs of the 2D
//! searches over contact sets ([`super::node_lp`], [`super::contact_lp`]).
//!
//! **Why in-house.** A branch-and-bound child differs from its parent by a few bounds, and a
//! bound-tightening program by its objective: from the parent's optimal basis the dual (or
//! primal) simplex method needs a handful of pivots, where an interior-point solver
//! ([`crate::conic::socp`], Clarabel) starts over every time (about 6 ms a program at m = 40). No
//! pure-Rust crate offers warm starts across bound changes *and* the Farkas ray of an
//! infeasible program (`microlp` can fix variables and add rows, but gives no certificate and
//! cannot change the objective; HiGHS needs a C++ build). The programs are small and dense
//! (about `3m` rows and `2m` columns), so the method keeps the inverse of the basis as a dense
//! matrix.
//!
//! **The form.** Columns `x` (`n` of them), rows `A x = s`, and bounds on every one of the
//! `N = n + rows` variables `(x, s)` (infinite where absent), a cost on each; minimise. A row
//! activity `s_i` is a variable like any other, so a changed row bound is a changed variable
//! bound, which the dual simplex method takes in its stride.
//!
//! **The method.** From a given basis (or the slack basis): nonbasic variables at a bound (a
//! free one at zero). When the basis is not primal feasible, the costs of the nonbasic
//! variables whose reduced cost has the wrong sign are shifted to make it dual feasible, the
//! dual simplex method restores primal feasibility (Harris's two-pass ratio test; dual steepest
//! edge pricing, the weights exact from the explicit inverse), the shifts are dropped, and the
//! primal simplex method (Devex pricing, Harris's ratio test, bound flips) finishes. Idle rows (free, no cost) whose
//! activity is basic are left out of the basis and its inverse, and so are the rows that a
//! warm start's point leaves loose, until the part's point breaks them ([`active`]). The
//! basic values and the reduced costs are updated at each pivot and recomputed from the
//! inverse every [`REFRESH`] pivots and before every verdict; a pivot element that the pivot
//! row and the pivot column disagree on refactors the inverse. A refactor eliminates on the
//! basis's structural columns only (a basic row activity is a unit column; `dense::invert`).
//! Dot products run on eight
//! partial sums, which the compiler vectorises (on the 2D plug with m = 60 that alone halved
//! the search's time), and the dense kernels run as compiled for AVX2 where the processor has
//! it (`dense`).
//!
//! **Checked answers.** As in [`crate::conic::socp`], nothing is returned unchecked:
//! - `Optimal`: the row activities are recomputed as `A x` and every bound must hold within
//!   [`TOL`] of the terms that add up to it (plus [`TOL`] absolute); the reduced costs were
//!   within [`TOL`] of their signs at the last step.
//! - `Infeasible`: the certificate `y` (one multiplier per row; the row of the inverse that the
//!   dual method could not move) gives `c = y^T [A  -I]` with `c . (x, s) = 0` for every
//!   point; the least value of `c . (x, s)` over the bounds must be clearly positive
//!   (`>= CERT` of its terms). A row activity's bounds there are its own intersected with those
//!   its columns' bounds imply, so a program with bounded columns is checked with every term;
//!   otherwise entries of `c` against an infinite bound must be tiny (`<= TINY ||c||_inf`) and
//!   are dropped, and a feasible point would then need entries more than `CERT / TINY` times
//!   the bounds. (The same argument as Clarabel's certificates in [`super::socp`].)
//! - An optimal point that fails its check: the inverse, updated at each pivot, has drifted
//!   (an ill-conditioned basis, as the support programs of `contact_lp` have at m = 80); it is
//!   refactored and the run resumed from that basis, up to [`REFINE`] times.
//! - A failed check, a singular basis or too many pivots: one retry from the slack basis, then
//!   `Failed` with the reason, and the caller asks Clarabel.
//!
//! **Feasibility programs** (no costs at all) are dual degenerate at every basis, and the dual
//! method could cycle on them; their nonbasic variables get small distinct costs
//! ([`PERTURB`]) for the dual method, dropped before the primal one. Other programs get them
//! when the dual method has made [`STALL`] steps of length zero in a row; the primal method
//! then pivots by Bland's rule until a step moves again.

mod active;
mod check;
mod dense;
mod pool;
mod steps;

use std::sync::Arc;

use check::{check_certificate, check_point};
use dense::{axpy, invert};

/// Feasibility and optimality tolerance, relative to the terms of each quantity.
const TOL: f64 = 1e-9;
/// A pivot element below this (relative to the largest candidate) is not taken.
const PIVOT: f64 = 1e-9;
/// How clearly an infeasibility certificate must exclude every point (see the module docs).
const CERT: f64 = 1e-6;
/// Entries of a certificate against an infinite bound up to this (relative) are dropped.
const TINY: f64 = 1e-12;
/// Values and reduced costs, updated at each pivot, are recomputed from the inverse after
/// this many pivots (and before every verdict).
const REFRESH: u64 = 32;
/// Steps of length zero in a row after which the dual method perturbs its costs and the
/// primal method pivots by Bland's rule ([`Run::solve`]).
const STALL: u64 = 64;
/// How often a basis whose optimal point fails its check is refactored ([`attempt`]).
const REFINE: usize = 2;
/// The size of the costs that a program without costs gets for its dual method
/// ([`Run::solve`]).
const PERTURB: f64 = 1e-7;

/// A linear program in the bounded form of the module docs.
#[derive(Debug, Clone)]
pub(crate) struct Lp {
    /// Columns.
    pub n: usize,
    /// Rows.
    pub rows: usize,
    /// The entries of `A`, row-major, shared by the programs of one shape (the search's
    /// nodes differ in bounds and costs only, [`super::node_lp`]) and by the part of a program
    /// that a solve works on ([`active::part`]).
    a: Arc<Vec<f64>>,
    /// The row of `a` that each row of the program is (`None`: row `k` is row `k`).
    map: Option<Vec<usize>>,
    /// `A` as a product with fewer unknowns, for the row products ([`Reduced`]).
    reduced: Option<Arc<Reduced>>,
    /// Bounds of the `n + rows` variables: columns, then row activities.
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// Costs of the `n + rows` variables (minimised).
    pub cost: Vec<f64>,
}

impl Lp {
    /// A program with `n` columns and `rows` rows, all zero, every variable free, no cost.
    pub(crate) fn new(n: usize, rows: usize) -> Lp {
        Lp::with_matrix(n, rows, Arc::new(pool::zeroed(n * rows)))
    }

    /// A program with `n` columns and the `rows` rows of `a` (row-major), every variable
    /// free, no cost.
    pub(crate) fn with_matrix(n: usize, rows: usize, a: Arc<Vec<f64>>) -> Lp {
        debug_assert_eq!(a.len(), n * rows);
        let total = n + rows;
        Lp {
            n,
            rows,
            a,
            map: None,
            reduced: None,
            lo: vec![f64::NEG_INFINITY; total],
            hi: vec![f64::INFINITY; total],
            cost: vec![0.0; total],
        }
    }

    /// The same program, its row products ([`Lp::row_times`]) taken through `reduced`, which
    /// must be `A`'s factors.
    pub(crate) fn with_reduced(mut self, reduced: Arc<Reduced>) -> Lp {
        debug_assert_eq!(reduced.a.len(), reduced.width * self.rows);
        self.reduced = Some(reduced);
        self
    }

    /// The entries of `A`, row-major, to be written (copied first when shared).
    pub(crate) fn a_mut(&mut self) -> &mut [f64] {
        assert!(self.map.is_none(), "a part of a program is not written");
        assert!(self.reduced.is_none(), "a factored program is not written");
        Arc::make_mut(&mut self.a).as_mut_slice()
    }

    /// The row of the shared matrix that row `k` of the program is.
    fn source_row(&self, k: usize) -> usize {
        self.map.as_ref().map_or(k, |map| map[k])
    }

    /// Row `k` of `A`.
    fn row(&self, k: usize) -> &[f64] {
        let at = self.source_row(k);
        &self.a[at * self.n..(at + 1) * self.n]
    }

    fn total(&self) -> usize {
        self.n + self.rows
    }

    /// Entry `k` of column `j` of `[A  -I]` (the tests' view of a basis column; the method
    /// itself reads rows).
    #[cfg(test)]
    fn entry(&self, k: usize, j: usize) -> f64 {
        if j < self.n {
            self.row(k)[j]
        } else if j - self.n == k {
            -1.0
        } else {
            0.0
        }
    }

    /// `v^T [A  -I]`, all `N` entries.
    fn row_times(&self, v: &[f64]) -> Vec<f64> {
        let mut out = Vec::new();
        self.row_times_into(v, &mut out);
        out
    }

    /// The activities `A x` of every row through the factors ([`Reduced`]), when the program
    /// has them: `width` terms a row instead of `n`. They may differ from the direct sums in
    /// the last bits; [`check::check_point`] checks a row against its bounds that way only
    /// with the tolerance that the direct sum's terms would give at least.
    fn activities(&self, x: &[f64]) -> Option<Vec<f64>> {
        let reduced = self.reduced.as_ref()?;
        let width = reduced.width;
        let mut w = vec![0.0; width];
        (reduced.gather)(&x[..self.n], &mut w);
        Some(
            (0..self.rows)
                .map(|k| {
                    let at = self.source_row(k);
                    dense::dot(&reduced.a[at * width..(at + 1) * width], &w)
                })
                .collect(),
        )
    }

    /// [`Lp::row_times`] into `out` (its storage reused).
    fn row_times_into(&self, v: &[f64], out: &mut Vec<f64>) {
        let n = self.n;
        out.clear();
        out.resize(self.total(), 0.0);
        if let Some(reduced) = &self.reduced {
            let width = reduced.width;
            let mut w = vec![0.0; width];
            for (k, &vk) in v.iter().enumerate() {
                if vk != 0.0 {
                    let at = self.source_row(k);
                    axpy(&mut w, vk, &reduced.a[at * width..(at + 1) * width]);
                    out[n + k] = -vk;
                }
            }
            (reduced.expand)(&w, &mut out[..n]);
            return;
        }
        for (k, &vk) in v.iter().enumerate() {
            if vk != 0.0 {
                axpy(&mut out[..n], vk, self.row(k));
                out[n + k] = -vk;
            }
        }
    }
}

/// A program's `A` as the product `R X` of a matrix `R` with fewer columns (`width`) and a
/// fixed map `X` of its columns onto `A`'s (`expand`: a row of `R`'s width to the row of `A`
/// it makes). The 3D search programs ([`super::node_lp`]) are such: each row is a functional of
/// the reaction components, and a node's `SIDES` ([`super::node_lp`]) columns are combinations of
/// its three components, so a combination of rows (the pivot row, the reduced costs, a
/// certificate's check) costs `width` a row and three terms a column, not `n`.
pub(crate) struct Reduced {
    pub width: usize,
    /// `R`, row-major: the rows of the whole program (a part maps its rows onto them as it
    /// does onto `A`'s).
    pub a: Vec<f64>,
    pub expand: Expand,
    /// The transpose: a point's columns `x` onto `R`'s width, `X x`, so that the row
    /// activities are `R (X x)` ([`Lp::activities`]).
    pub gather: Expand,
}

/// [`Reduced::expand`]: a row of `R`'s width into the row of `A` it makes.
pub(crate) type Expand = Box<dyn Fn(&[f64], &mut [f64]) + Send + Sync>;

impl std::fmt::Debug for Reduced {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Reduced {{ width: {} }}", self.width)
    }
}

impl Drop for Lp {
    fn drop(&mut self) {
        let a = std::mem::replace(&mut self.a, Arc::new(Vec::new()));
        if let Some(a) = Arc::into_inner(a) {
            pool::recycle(a);
        }
    }
}

/// Where a nonbasic variable sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum At {
    Basic,
    Lower,
    Upper,
    /// A free variable at zero.
    Zero,
}

/// A basis: which variable is basic in each position, where the others sit, and the inverse
/// of the basis matrix (dropped with [`Basis::forget`] when the matrix changes), over the
/// active rows only (see [`active`]: the activity of every other row is basic). The inverse's
/// buffer is recycled ([`pool`]).
#[derive(Debug)]
pub(crate) struct Basis {
    /// The basic variable at each position (as many as `rows`).
    head: Vec<usize>,
    /// Where each of the program's `n + rows` variables sits.
    at: Vec<At>,
    /// `B^-1`, row-major: positions by active rows (in the order of `rows`).
    inv: Option<Vec<f64>>,
    /// The active rows.
    rows: Vec<usize>,
    /// The row activities at the optimal point the basis was left at (empty otherwise): a
    /// start leaves out the rows loose there ([`active`]).
    activity: Vec<f64>,
}

impl Clone for Basis {
    fn clone(&self) -> Basis {
        Basis {
            head: self.head.clone(),
            at: self.at.clone(),
            inv: self.inv.as_deref().map(pool::copy_of),
            rows: self.rows.clone(),
            activity: self.activity.clone(),
        }
    }
}

impl Drop for Basis {
    fn drop(&mut self) {
        if let Some(inv) = self.inv.take() {
            pool::recycle(inv);
        }
    }
}

impl Basis {
    /// Drops the inverse: the program's matrix has changed since (it is refactored from the
    /// basic columns on the next solve).
    pub(crate) fn forget(&mut self) {
        if let Some(inv) = self.inv.take() {
            pool::recycle(inv);
        }
    }

    /// The same start with every row that is not idle active (none left out as loose).
    pub(crate) fn all_rows(mut self) -> Basis {
        self.activity.clear();
        self
    }

    /// The same basis without its inverse (refactored on the next solve): small to keep.
    pub(crate) fn without_inverse(&self) -> Basis {
        Basis {
            head: self.head.clone(),
            at: self.at.clone(),
            inv: None,
            rows: self.rows.clone(),
            activity: self.activity.clone(),
        }
    }

    fn fits(&self, lp: &Lp) -> bool {
        self.head.len() == self.rows.len()
            && self.at.len() == lp.total()
            && self.rows.iter().all(|&k| k < lp.rows)
    }
}

/// The answer to one program. (The search reads only which it is; the certificate and the
/// reason are for the tests and for diagnostics.)
#[derive(Debug, Clone)]
#[allow(dead_code)]
pub(crate) enum Answer {
    /// Optimal: all `n + rows` values (columns, then row activities) and the cost.
    Optimal { x: Vec<f64>, value: f64 },
    /// Infeasible, with its checked certificate (one multiplier per row).
    Infeasible { y: Vec<f64> },
    /// Not decided: the reason.
    Failed(String),
}

/// What one solve cost.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Stats {
    pub pivots: u64,
}

/// Solves `lp` from `start` (or the slack basis). Returns the answer and the final basis (for
/// the next, similar program).
pub(crate) fn solve(lp: &Lp, start: Option<&Basis>) -> (Answer, Basis, Stats) {
    let mut stats = Stats::default();
    // The warm start adapted to the program's idle rows, then (lazily) the slack basis.
    let warm = start.filter(|b| b.fits(lp)).map(|b| active::adapt(lp, b));
    let tries = warm
        .into_iter()
        .chain(std::iter::once_with(|| active::slack(lp)));
    let mut last = String::new();
    for basis in tries {
        match attempt(lp, basis, &mut stats) {
            Ok((answer, basis)) => return (answer, basis, stats),
            Err(why) => last = why,
        }
    }
    (Answer::Failed(last), active::slack(lp), stats)
}

/// One try from `basis` (whole numbering) on its active rows, the rows left out that the
/// point breaks joining ([`active`]), a drifted inverse refactored (see the module docs).
fn attempt(lp: &Lp, mut basis: Basis, stats: &mut Stats) -> Result<(Answer, Basis), String> {
    let mut refined = 0;
    loop {
        let rows = basis.rows.clone();
        let part = active::part(lp, &rows);
        let mut inner = active::into_part(lp, basis);
        if inner.inv.is_none() {
            let inv = invert(&part, &inner.head);
            inner.inv = Some(inv.ok_or_else(|| "the warm-start basis is singular".to_string())?);
        }
        let mut run = Run::new(&part, inner);
        let outcome = run.solve(stats)?;
        let x = run.x[..lp.n].to_vec();
        let y = match outcome {
            Outcome::Infeasible(p) => {
                let r = part.rows;
                Some(active::spread(
                    lp.rows,
                    &rows,
                    &run.inv()[p * r..(p + 1) * r],
                ))
            }
            Outcome::Optimal => None,
        };
        let mut whole = active::from_part(lp, &rows, run.basis);
        whole.activity.clear();
        if let Some(y) = y {
            return Ok((check_certificate(lp, &y)?, whole));
        }
        // The row activities through the factors (3D), once for both the loose rows' test
        // and the point's check.
        let factored = lp.activities(&x);
        let broken = active::violated(lp, &rows, &x, factored.as_deref());
        if !broken.is_empty() {
            basis = active::add(lp, &whole, &broken);
            continue;
        }
        match check_point(lp, &x, factored.as_deref()) {
            Ok(answer) => {
                if let Answer::Optimal { x: all, .. } = &answer {
                    whole.activity = all[lp.n..].to_vec();
                }
                return Ok((answer, whole));
            }
            Err(_) if refined < REFINE => {
                refined += 1;
                whole.forget();
                basis = whole;
            }
            Err(why) => return Err(why),
        }
    }
}

/// What a run ends in, before the check.
enum Outcome {
    Optimal,
    /// The row position the dual method could not move.
    Infeasible(usize),
}

struct Run<'a> {
    lp: &'a Lp,
    basis: Basis,
    cost: Vec<f64>,
    /// Values of all variables (basic ones recomputed by [`Run::primal`]).
    x: Vec<f64>,
    /// Reduced costs (basic ones zero).
    d: Vec<f64>,
    /// Buffers that [`Run::primal`] and [`Run::dual`] reuse from call to call. (With a new
    /// vector for each of a run's products, a program of the random m = 9 enumeration made
    /// about 75 allocations.)
    scratch: [Vec<f64>; 3],
    /// The variables that are not fixed (`lo < hi`), in order: the only ones that can enter
    /// the basis, so the ratio tests and the pricing look at these alone. (A 3D search node's
    /// separated nodes fix their polygon's edges, a quarter of the columns halfway down the
    /// V-groove plug's tree.)
    movable: Vec<usize>,
}

impl<'a> Run<'a> {
    fn new(lp: &'a Lp, basis: Basis) -> Run<'a> {
        let mut run = Run {
            lp,
            basis,
            cost: lp.cost.clone(),
            x: vec![0.0; lp.total()],
            d: vec![0.0; lp.total()],
            scratch: Default::default(),
            movable: (0..lp.total()).filter(|&j| lp.lo[j] != lp.hi[j]).collect(),
        };
        run.settle_nonbasic();
        run
    }

    fn inv(&self) -> &[f64] {
        self.basis.inv.as_deref().expect("inverted before the run")
    }

    fn solve(&mut self, stats: &mut Stats) -> Result<Outcome, String> {
        let limit = 50 * (self.lp.total() as u64) + 1000;
        let mut steps = 0u64;
        self.primal();
        self.dual();
        let lp = self.lp;
        // The pivots' vectors, their storage reused from pivot to pivot.
        let (mut alpha, mut alpha_row, mut col) = (Vec::new(), Vec::new(), Vec::new());
        let mut cands: Vec<(usize, f64, f64)> = Vec::new();
        let infeasible = self.basis.head.iter().any(|&j| self.violation(j) != 0.0);
        if infeasible {
            // Shift costs to make the start dual feasible, then the dual method.
            let mut shifted = false;
            // A program without costs (a feasibility question) is dual degenerate at every
            // basis: every ratio test ties, and the dual method could cycle (on issue 20's
            // plug at m = 80 some tightening nodes' first programs ran into the pivot limit).
            // Each nonbasic variable then gets a small cost of the right sign, a different
            // one for each, dropped with the shifts once the basis is primal feasible.
            let perturb = lp.cost.iter().all(|&c| c == 0.0);
            if perturb {
                shifted |= self.perturb_costs();
            } else {
                for i in 0..self.movable.len() {
                    let j = self.movable[i];
                    if self.dual_wrong(j) {
                        self.cost[j] -= self.d[j];
                        shifted = true;
                    }
                }
            }
            if shifted {
                self.dual();
            }
            // Values and reduced costs are updated at each pivot, recomputed every
            // `REFRESH` pivots and before a verdict.
            let mut since = 0u64;
            // Consecutive dual steps of length zero: from `STALL` on, the costs are perturbed
            // (once) as a feasibility program's are, so that the ratio tests stop tying. (A
            // bound-tightening program with its node fixed cycled into the pivot limit twice
            // on the 2D plug at m = 100.)
            let mut stalled = 0u64;
            let mut perturbed = perturb;
            // The squared norms of the inverse's rows, kept exact at each pivot and computed
            // again at a refactor.
            let mut norms = self.row_norms();
            loop {
                steps += 1;
                if steps > limit {
                    return Err(format!("no answer after {limit} pivots"));
                }
                if stalled >= STALL && !perturbed {
                    perturbed = true;
                    shifted |= self.perturb_costs();
                    // Values and reduced costs fresh again (`since = 0` promises both).
                    self.primal();
                    self.dual();
                    since = 0;
                    stalled = 0;
                }
                // Dual steepest edge: the basic variable whose infeasibility is largest against
                // the norm of its row of the inverse leaves.
                let Some((p, _, v)) = (0..lp.rows)
                    .map(|k| (k, self.violation(self.basis.head[k])))
                    .filter(|&(_, v)| v != 0.0)
                    .map(|(k, v)| (k, v * v / norms[k], v))
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                else {
                    if since == 0 {
                        break;
                    }
                    since = 0;
                    self.primal();
                    self.dual();
                    continue;
                };
                let s = if v < 0.0 { 1.0 } else { -1.0 };
                let r = lp.rows;
                lp.row_times_into(&self.inv()[p * r..(p + 1) * r], &mut alpha_row);
                let big = alpha_row.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                // Harris's two passes over the candidates (d_j moves by theta s alpha_j).
                cands.clear();
                cands.extend(self.movable.iter().filter_map(|&j| {
                    let at = self.basis.at[j];
                    if at == At::Basic {
                        return None;
                    }
                    let a = s * alpha_row[j];
                    if a.abs() <= PIVOT * big {
                        return None;
                    }
                    let d = self.d[j];
                    let room = match at {
                        At::Lower if a < 0.0 => d.max(0.0),
                        At::Upper if a > 0.0 => (-d).max(0.0),
                        At::Zero => {
                            if a < 0.0 {
                                d.max(0.0)
                            } else {
                                (-d).max(0.0)
                            }
                        }
                        _ => return None,
                    };
                    Some((j, room, a.abs()))
                }));
                if cands.is_empty() {
                    if since > 0 {
                        since = 0;
                        self.primal();
                        self.dual();
                        continue;
                    }
                    return Ok(Outcome::Infeasible(p));
                }
                let bound = cands
                    .iter()
                    .map(|&(_, room, a)| (room + TOL) / a)
                    .fold(f64::INFINITY, f64::min);
                let &(q, _, _) = cands
                    .iter()
                    .filter(|&&(_, room, a)| room / a <= bound)
                    .max_by(|x, y| x.2.total_cmp(&y.2))
                    .expect("the least ratio is a candidate");
                self.column_into(q, &mut col, &mut alpha);
                let arq = alpha_row[q];
                if alpha[p].abs() <= PIVOT * big.max(1.0) * 1e-3 {
                    return Err("a vanishing pivot".into());
                }
                if (alpha[p] - arq).abs() > 1e-7 * (1.0 + arq.abs()) {
                    // The inverse has drifted: refactor and look again.
                    self.basis.inv =
                        Some(invert(lp, &self.basis.head).ok_or("the basis became singular")?);
                    norms = self.row_norms();
                    since = 0;
                    self.primal();
                    self.dual();
                    continue;
                }
                // The dual step, then the primal one.
                let theta = (-self.d[q] / (s * arq)).max(0.0);
                if theta * arq.abs() <= TOL {
                    stalled += 1;
                } else {
                    stalled = 0;
                }
                // Every entry moves (a basic one's is put back to zero after), which the
                // compiler vectorises; a test per entry cost a tenth of a 3D search's time.
                let step = theta * s;
                for (d, &a) in self.d.iter_mut().zip(&alpha_row) {
                    *d += step * a;
                }
                for &j in &self.basis.head {
                    self.d[j] = 0.0;
                }
                let out = self.basis.head[p];
                let target = if s > 0.0 { lp.lo[out] } else { lp.hi[out] };
                let step = (self.x[out] - target) / arq;
                for (k, &ak) in alpha.iter().enumerate() {
                    let j = self.basis.head[k];
                    self.x[j] -= ak * step;
                }
                self.x[q] += step;
                let leave_at = if s > 0.0 { At::Lower } else { At::Upper };
                self.pivot((p, q), &alpha, leave_at, Some(&mut norms));
                self.d[q] = 0.0;
                self.d[out] = s * theta;
                stats.pivots += 1;
                since += 1;
                if since >= REFRESH {
                    since = 0;
                    self.primal();
                    self.dual();
                }
            }
            if shifted {
                self.cost.copy_from_slice(&lp.cost);
                self.dual();
            }
        }
        // The primal method: Devex pricing (reference weights, Forrest and Goldfarb), the
        // values and reduced costs updated at each pivot and recomputed every
        // `REFRESH` pivots and before optimality is declared.
        let mut weight = vec![1.0f64; lp.total()];
        let mut rooms: Vec<(usize, f64, f64, f64, At)> = Vec::new();
        let mut since = 0u64;
        // Consecutive steps that moved nothing; from `STALL` on, Bland's rule (the first
        // candidate by index to enter, the first by index among the least ratios to leave)
        // until a step moves again: Devex with Harris's ratio test can cycle on a degenerate
        // vertex (a bound-tightening program with its node fixed ran into the pivot limit
        // twice on the 2D plug at m = 100).
        let mut stalled = 0u64;
        loop {
            steps += 1;
            if steps > limit {
                return Err(format!("no answer after {limit} pivots"));
            }
            let bland = stalled >= STALL;
            let pick = |run: &Run| {
                let wrong = run.movable.iter().copied().filter(|&j| run.dual_wrong(j));
                if bland {
                    return wrong.min();
                }
                wrong.max_by(|&a, &b| {
                    (run.d[a] * run.d[a] / weight[a]).total_cmp(&(run.d[b] * run.d[b] / weight[b]))
                })
            };
            let q = match pick(self) {
                Some(q) => q,
                None if since == 0 => return Ok(Outcome::Optimal),
                None => {
                    // Fresh values and reduced costs before the verdict.
                    since = 0;
                    self.primal();
                    self.dual();
                    match pick(self) {
                        Some(q) => q,
                        None => return Ok(Outcome::Optimal),
                    }
                }
            };
            // Increase q when its reduced cost is negative.
            let sigma = if self.d[q] < 0.0 { 1.0 } else { -1.0 };
            self.column_into(q, &mut col, &mut alpha);
            let big = alpha.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            // Basic k moves by -sigma t alpha_k: (position, room, rate, bound hit, at).
            rooms.clear();
            rooms.extend((0..lp.rows).filter_map(|k| {
                let j = self.basis.head[k];
                let delta = -sigma * alpha[k];
                if delta.abs() <= PIVOT * big {
                    return None;
                }
                let (v, lo, hi) = (self.x[j], lp.lo[j], lp.hi[j]);
                if delta < 0.0 && lo.is_finite() {
                    Some((k, (v - lo).max(0.0), -delta, lo, At::Lower))
                } else if delta > 0.0 && hi.is_finite() {
                    Some((k, (hi - v).max(0.0), delta, hi, At::Upper))
                } else {
                    None
                }
            }));
            let own = if sigma > 0.0 {
                lp.hi[q] - self.x[q]
            } else {
                self.x[q] - lp.lo[q]
            };
            let bound = rooms
                .iter()
                .map(|&(_, room, a, b, _)| (room + TOL * (1.0 + b.abs())) / a)
                .fold(f64::INFINITY, f64::min);
            let step_basic = |run: &mut Run, t: f64| {
                for (k, &ak) in alpha.iter().enumerate() {
                    let j = run.basis.head[k];
                    run.x[j] -= sigma * t * ak;
                }
            };
            stats.pivots += 1;
            since += 1;
            if own.is_finite() && own <= bound {
                // A bound flip.
                step_basic(self, own);
                self.basis.at[q] = if sigma > 0.0 { At::Upper } else { At::Lower };
                self.x[q] = if sigma > 0.0 { lp.hi[q] } else { lp.lo[q] };
                continue;
            }
            let ties = rooms
                .iter()
                .filter(|&&(_, room, a, _, _)| room / a <= bound);
            let chosen = if bland {
                ties.min_by_key(|x| self.basis.head[x.0])
            } else {
                ties.max_by(|x, y| x.2.total_cmp(&y.2))
            };
            let Some(&(p, room, rate, _, leave_at)) = chosen else {
                return Err("the program is unbounded".into());
            };
            let t = room / rate;
            if room <= TOL * (1.0 + self.x[self.basis.head[p]].abs()) {
                stalled += 1;
            } else {
                stalled = 0;
            }
            step_basic(self, t);
            self.x[q] += sigma * t;
            // The pivot row, for the reduced costs and the weights.
            let r = lp.rows;
            lp.row_times_into(&self.inv()[p * r..(p + 1) * r], &mut alpha_row);
            let row = &alpha_row;
            let (aq, dq, wq) = (alpha[p], self.d[q], weight[q]);
            let out = self.basis.head[p];
            for j in 0..lp.total() {
                if self.basis.at[j] != At::Basic && j != q && row[j] != 0.0 {
                    let ratio = row[j] / aq;
                    self.d[j] -= dq * ratio;
                    weight[j] = weight[j].max(ratio * ratio * wq);
                }
            }
            self.pivot((p, q), &alpha, leave_at, None);
            self.d[q] = 0.0;
            self.d[out] = -dq / aq;
            weight[out] = (wq / (aq * aq)).max(1.0);
            if since >= REFRESH {
                since = 0;
                self.primal();
                self.dual();
            }
        }
    }
}

#[cfg(test)]
mod tests;
