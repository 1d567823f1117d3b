//! The one module that talks to the conic solver (Clarabel): small linear and second-order cone
//! programs, built with [`Program`] and answered by [`solve`] with a *verified* [`Answer`].
//!
//! # Contract
//!
//! A program minimises `q . x` over `x in R^n` subject to affine constraints `e(x) = 0`,
//! `e(x) >= 0` and `head(x) >= ||(tail_1(x), ..., tail_k(x))||` (`k >= 1`). [`solve`] passes it to
//! Clarabel as `A x + s = b, s in K`: all zero rows first (one `ZeroConeT`), then all nonnegative
//! rows (one `NonnegativeConeT`), then one `SecondOrderConeT(k + 1)` per [`Program::soc`], each
//! group in the order added; `A_i = -terms` and `b_i = constant`, so that `s_i = e_i(x)`. The
//! solver's word is never returned unchecked:
//!
//! 1. First attempt, Clarabel's usual settings (tolerances `1e-8`, 200 iterations). Status
//!    `Solved` whose point passes the optimality check below is [`Answer::Optimal`];
//!    `PrimalInfeasible` whose certificate passes the certificate check is
//!    [`Answer::Infeasible`].
//! 2. Anything else (another status, or a failed check) is retried once with tighter settings:
//!    gap, feasibility and `kappa/tau` tolerances `1e-10`, 1000 iterations, up to 50 steps of
//!    iterative refinement. (Static regularisation stays at its default: a smaller one made
//!    degenerate programs, with cones pinned at their apex, end `AlmostSolved` with points
//!    violating those cones by `~1e-8`.) The retry's answer is returned if it passes its check.
//! 3. `AlmostSolved` and `AlmostPrimalInfeasible` answers go through the same checks; one that
//!    passes is as verified as any other, and is returned when the retry gives nothing better.
//!    (A typical case: pure feasibility programs whose dual residual stalls just above `1e-8`,
//!    which is irrelevant with a zero objective.)
//! 4. When both fail, a third attempt with the usual tolerances and Ruiz equilibration off
//!    (measured on the floating cork, `examples/cork2d.toml`: 20 of 445 programs undecided by
//!    both, none by this one; switching equilibration off for every attempt also decided them,
//!    but would change every clamped run).
//! 5. A linear program (no cone) that all three leave undecided goes to the in-house simplex
//!    method ([`super::simplex`]; checked in its own form; an infeasibility then comes without
//!    a certificate in this module's form, `y` empty).
//! 6. Otherwise [`Answer::Uncertain`], with the status and failed check of every attempt; when
//!    the first two report dual infeasibility (an unbounded objective) the reason is exactly
//!    `"unbounded"`.
//!
//! A program with a non-finite number, a variable index out of range or a cone without a tail is
//! not solved: it is `Uncertain` with the reason (no debug assertion, so that every profile
//! behaves the same). A program without variables is decided exactly without the solver (which
//! cannot factor an empty system). A panic inside Clarabel is caught and reported as
//! `Uncertain`.
//!
//! # Tolerances
//!
//! As elsewhere in the crate, a quantity is tested against the terms it adds up ([`TOL_REL`] `=
//! 1e-7` of them, a per-row test much stricter than the solver's normwise one for rows whose
//! terms are small), plus a normwise floor, [`TOL_NORM`] `= 1e-8` (Clarabel's nominal accuracy),
//! for rows whose terms all but vanish, such as `x_j >= 0` at `x_j = 0` or a cone pinned at its
//! apex. (With a floor of `1e-9`, most programs of a degenerate family failed both attempts:
//! Clarabel's `Solved` points miss apex cones by `~3e-10` with `||x||_inf ~ 0.1`.)
//!
//! - **Point** (every answer `Optimal`): `x` finite; for a row with terms `c_k x_{j_k}` and
//!   constant `b`, with `scale = |b| + sum |c_k x_{j_k}|` and `size = sum |c_k| * ||x||_inf`, the
//!   allowance is `TOL_REL * scale + TOL_NORM * size` (for a cone, the sum over its rows). A zero
//!   row needs `|e(x)| <=` it, a nonnegative row `e(x) >= -`it, a cone `head(x) - ||tail(x)||
//!   >= -`it.
//! - **Optimality** (objective not zero; with a zero objective every feasible point is optimal
//!   and `value = 0`): the dual `z` may be at most `TOL_CONE * ||z||_inf` outside the dual cone
//!   ([`TOL_CONE`] `= 1e-9`; it is then projected onto it); each dual residual
//!   `r_j = q_j + (A^T z)_j` must be within `TOL_REL * (|q_j| + sum_i |A_ij z_i|) + TOL_NORM *
//!   (|q_j| + sum_i |A_ij| * ||z||_inf)`, and the duality gap `q . x + b . z` within `TOL_REL *
//!   (sum |q_j x_j| + sum |b_i z_i|) + TOL_NORM * ||q||_1 * ||x||_inf`. By weak duality,
//!   `value = q . x` then exceeds the optimum by at most the gap plus `sum_j |r_j x*_j|`.
//! - **Infeasibility**: Clarabel's certificate is its `z` for a `PrimalInfeasible` status, a `y`
//!   with `A^T y = 0`, `b . y < 0` and `y` in the dual cone `K*` (the zero cone's dual is free,
//!   the nonnegative and second-order cones are self-dual); for `x >= 1, x <= 0` it returns
//!   `y = (1, 1)` (tested). The check scales `y` to `||y||_inf = 1`, allows a move of at most
//!   `TOL_CONE` onto `K*` and projects it there, and with `beta = b . y`, `B = sum |b_i y_i|`
//!   requires `beta <= -CERT * B` and, for every variable `j`, `|(A^T y)_j| * ||b||_1 <= CERT *
//!   |beta| * sum_i |A_ij|`, with [`CERT`] `= 1e-6`. Then every `x` meeting the constraints has
//!   `0 <= y . s = beta - (A^T y) . x`, hence `sum_j |(A^T y)_j| |x_j| >= |beta|` and `sum_ij
//!   |A_ij x_j| >= ||b||_1 / CERT`: a feasible point would need variable terms a million times
//!   all the constants together. (`|beta| >= CERT * B` also keeps the certificate clear of points
//!   that pass the point check only within its tolerance.)
//!
//! The module does no I/O, never prints (Clarabel runs with `verbose = false` on one thread) and
//! keeps no global state, so [`solve`] may run on many threads at once.

use std::panic::{catch_unwind, AssertUnwindSafe};

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

/// Relative tolerance of every check, against the terms of the quantity checked.
const TOL_REL: f64 = 1e-7;
/// Normwise floor of the checks, against coefficient sizes times the largest entry of the vector.
const TOL_NORM: f64 = 1e-8;
/// Largest move of a dual vector (relative to its largest entry) onto the dual cone.
const TOL_CONE: f64 = 1e-9;
/// Margin of an infeasibility certificate (see the module docs).
const CERT: f64 = 1e-6;

/// An affine expression `sum_k c_k x_{j_k} + constant` of the program's variables.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Affine {
    /// The terms `(j_k, c_k)`; an index may repeat (the coefficients add up).
    pub terms: Vec<(usize, f64)>,
    /// The constant.
    pub constant: f64,
}

impl Affine {
    /// The variable `x_j`.
    pub(crate) fn var(j: usize) -> Affine {
        Affine {
            terms: vec![(j, 1.0)],
            constant: 0.0,
        }
    }

    /// `sum terms + constant`.
    pub(crate) fn new(terms: Vec<(usize, f64)>, constant: f64) -> Affine {
        Affine { terms, constant }
    }
}

/// A conic program: minimise `objective . x` subject to constraints added in any order.
#[derive(Debug, Clone)]
pub(crate) struct Program {
    vars: usize,
    objective: Vec<(usize, f64)>,
    zeros: Vec<Affine>,
    nonnegs: Vec<Affine>,
    socs: Vec<(Affine, Vec<Affine>)>,
}

impl Program {
    /// A program in `vars` variables with no constraint and a zero objective.
    pub(crate) fn new(vars: usize) -> Program {
        Program {
            vars,
            objective: Vec::new(),
            zeros: Vec::new(),
            nonnegs: Vec::new(),
            socs: Vec::new(),
        }
    }

    /// The number of variables.
    pub(crate) fn vars(&self) -> usize {
        self.vars
    }

    /// Sets the linear objective to minimise (replacing any previous one; default zero, a pure
    /// feasibility problem). Repeated indices add up.
    pub(crate) fn minimise(&mut self, terms: &[(usize, f64)]) {
        self.objective = terms.to_vec();
    }

    /// Adds `e(x) = 0`; returns its row in an infeasibility certificate (zero rows come first).
    pub(crate) fn zero(&mut self, e: Affine) -> usize {
        self.zeros.push(e);
        self.zeros.len() - 1
    }

    /// Adds `e(x) >= 0`; returns its ordinal among the nonnegative rows (its row in a
    /// certificate is [`Program::nonneg_row`] of it, once every zero row is added).
    pub(crate) fn nonneg(&mut self, e: Affine) -> usize {
        self.nonnegs.push(e);
        self.nonnegs.len() - 1
    }

    /// The row of the nonnegative constraint with ordinal `k` in an infeasibility certificate.
    pub(crate) fn nonneg_row(&self, k: usize) -> usize {
        self.zeros.len() + k
    }

    /// Adds `head(x) >= ||(tail_1(x), ..., tail_k(x))||_2`, `k >= 1` (with `k = 1`,
    /// `|tail_1(x)| <= head(x)`, a second-order cone of dimension 2 for Clarabel).
    pub(crate) fn soc(&mut self, head: Affine, tail: Vec<Affine>) {
        self.socs.push((head, tail));
    }
}

/// The verified answer of [`solve`].
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Answer {
    /// Solved and checked: `x` satisfies every constraint within the tolerances of the module
    /// docs, and is optimal within them; `value = objective . x`.
    Optimal { x: Vec<f64>, value: f64 },
    /// Infeasible, with a checked certificate: `y`, one multiplier per row (zero rows in the
    /// order added, then nonnegative rows, then each cone's head and tail), scaled to
    /// `||y||_inf = 1` and projected onto the dual cone. Empty for a program without variables
    /// (a violated constant is then its own certificate), and for a linear program decided by
    /// the simplex method after Clarabel failed (its certificate, checked, is in its own form).
    Infeasible { y: Vec<f64> },
    /// Neither could be established, even after the retry; the reason in words (Clarabel's
    /// status, or which check failed and by how much, for both attempts; `"unbounded"` for an
    /// unbounded objective).
    Uncertain { reason: String },
}

/// Counts for diagnostics.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct SolveStats {
    /// Calls of the solver (1 to 3; 0 for a malformed program).
    pub solves: u64,
    /// Retries with tighter settings (0 or 1).
    pub retries: u64,
}

/// Solves `p`: a verified optimum, a verified infeasibility, or the reason why neither could be
/// established after one retry with tighter settings (see the module docs).
pub(crate) fn solve(p: &Program) -> (Answer, SolveStats) {
    let mut stats = SolveStats::default();
    let form = match Form::new(p) {
        Ok(form) => form,
        Err(reason) => return (Answer::Uncertain { reason }, stats),
    };
    if form.n == 0 {
        // Nothing to solve (and Clarabel cannot factor an empty system): every row is a
        // constant, decided exactly.
        return (constant_answer(&form), stats);
    }
    stats.solves += 1;
    let first = match attempt(&form, Mode::Default) {
        Verdict::Verified(answer) => return (answer, stats),
        Verdict::Almost(answer) => Ok(answer),
        Verdict::Failed(failure) => Err(failure),
    };
    stats.solves += 1;
    stats.retries += 1;
    let answer = match (first, attempt(&form, Mode::Tight)) {
        (_, Verdict::Verified(answer) | Verdict::Almost(answer)) => answer,
        (Ok(almost), Verdict::Failed(_)) => almost,
        (Err(first), Verdict::Failed(second)) if first.unbounded && second.unbounded => {
            Answer::Uncertain {
                reason: "unbounded".to_string(),
            }
        }
        (Err(first), Verdict::Failed(second)) => {
            // The last attempt, without Ruiz equilibration: a floating body's programs (free
            // rigid amplitudes beside the reactions) stall both others now and then.
            stats.solves += 1;
            match attempt(&form, Mode::Unequilibrated) {
                Verdict::Verified(answer) | Verdict::Almost(answer) => answer,
                Verdict::Failed(third) => {
                    let mut reason = format!(
                        "{}; retry: {}; unequilibrated: {}",
                        first.reason, second.reason, third.reason
                    );
                    match by_simplex(&form) {
                        Some(Ok(answer)) => return (answer, stats),
                        Some(Err(why)) => reason.push_str(&format!("; simplex: {why}")),
                        None => {}
                    }
                    Answer::Uncertain { reason }
                }
            }
        }
    };
    (answer, stats)
}

/// The answer for a program without variables: optimal at `x = []` when every constraint holds
/// exactly, infeasible otherwise (the violated constant is its own certificate).
fn constant_answer(form: &Form) -> Answer {
    let holds = form.cons.iter().all(|con| {
        let v: Vec<f64> = form.rows[con.start..con.start + con.len]
            .iter()
            .map(|r| r.constant)
            .collect();
        match con.kind {
            Kind::Zero => v[0] == 0.0,
            Kind::Nonneg => v[0] >= 0.0,
            Kind::Soc => v[0] >= v[1..].iter().map(|t| t * t).sum::<f64>().sqrt(),
        }
    });
    if holds {
        Answer::Optimal {
            x: Vec::new(),
            value: 0.0,
        }
    } else {
        Answer::Infeasible { y: Vec::new() }
    }
}

/// The outcome of one attempt.
#[derive(Debug)]
enum Verdict {
    /// Status `Solved` or `PrimalInfeasible`, and the answer passed its check.
    Verified(Answer),
    /// Status `AlmostSolved` or `AlmostPrimalInfeasible`, and the answer passed the same check.
    Almost(Answer),
    /// No answer passed its check.
    Failed(Failure),
}

/// Why an attempt gave no verified answer.
#[derive(Debug)]
struct Failure {
    reason: String,
    /// Clarabel reported dual infeasibility (an unbounded objective).
    unbounded: bool,
}

impl Failure {
    fn new(reason: String) -> Failure {
        Failure {
            reason,
            unbounded: false,
        }
    }
}

/// The kind of a constraint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Zero,
    Nonneg,
    Soc,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Zero => "zero",
            Kind::Nonneg => "nonneg",
            Kind::Soc => "soc",
        }
    }
}

/// One row `e(x) = sum c x + constant`, terms sorted by index, merged and nonzero.
#[derive(Debug, Clone)]
struct Row {
    terms: Vec<(usize, f64)>,
    constant: f64,
}

impl Row {
    fn new(e: &Affine, vars: usize, what: &dyn Fn() -> String) -> Result<Row, String> {
        let terms = merge(&e.terms, vars, what)?;
        if !e.constant.is_finite() {
            return Err(format!("{} has the constant {}", what(), e.constant));
        }
        Ok(Row {
            terms,
            constant: e.constant,
        })
    }

    /// `(e(x), |constant| + sum |c x|, sum |c|)`.
    fn eval(&self, x: &[f64]) -> (f64, f64, f64) {
        let (mut e, mut scale, mut coef) = (self.constant, self.constant.abs(), 0.0);
        for &(j, c) in &self.terms {
            e += c * x[j];
            scale += (c * x[j]).abs();
            coef += c.abs();
        }
        (e, scale, coef)
    }
}

/// Sorted, merged, nonzero terms, checked for range and finiteness.
fn merge(
    terms: &[(usize, f64)],
    vars: usize,
    what: &dyn Fn() -> String,
) -> Result<Vec<(usize, f64)>, String> {
    if let Some(&(j, _)) = terms.iter().find(|&&(j, _)| j >= vars) {
        return Err(format!(
            "{} uses variable {j} of a program with {vars}",
            what()
        ));
    }
    if let Some(&(j, c)) = terms.iter().find(|&&(_, c)| !c.is_finite()) {
        return Err(format!(
            "{} has the coefficient {c} on variable {j}",
            what()
        ));
    }
    let mut sorted = terms.to_vec();
    sorted.sort_by_key(|&(j, _)| j);
    let mut out: Vec<(usize, f64)> = Vec::with_capacity(sorted.len());
    for (j, c) in sorted {
        match out.last_mut() {
            Some(last) if last.0 == j => last.1 += c,
            _ => out.push((j, c)),
        }
    }
    if out.iter().any(|&(_, c)| !c.is_finite()) {
        return Err(format!("{} has coefficients whose sum overflows", what()));
    }
    out.retain(|&(_, c)| c != 0.0);
    Ok(out)
}

/// A constraint: rows `start..start + len` of the form, the `ordinal`-th of its kind.
#[derive(Debug, Clone, Copy)]
struct Con {
    kind: Kind,
    ordinal: usize,
    start: usize,
    len: usize,
}

impl Con {
    fn name(&self) -> String {
        format!("{} constraint #{}", self.kind.name(), self.ordinal)
    }
}

/// A validated program in row form: all zero rows, then all nonnegative rows, then the cones.
#[derive(Debug, Clone)]
struct Form {
    n: usize,
    q: Vec<f64>,
    rows: Vec<Row>,
    cons: Vec<Con>,
}

impl Form {
    fn new(p: &Program) -> Result<Form, String> {
        let n = p.vars();
        let mut q = vec![0.0; n];
        for (j, c) in merge(&p.objective, n, &|| "the objective".to_string())? {
            q[j] = c;
        }
        let mut rows = Vec::new();
        let mut cons = Vec::new();
        let mut push = |kind: Kind, ordinal: usize, es: &[&Affine]| -> Result<(), String> {
            let what = || format!("{} constraint #{ordinal}", kind.name());
            let start = rows.len();
            for e in es {
                rows.push(Row::new(e, n, &what)?);
            }
            cons.push(Con {
                kind,
                ordinal,
                start,
                len: es.len(),
            });
            Ok(())
        };
        for (k, e) in p.zeros.iter().enumerate() {
            push(Kind::Zero, k, &[e])?;
        }
        for (k, e) in p.nonnegs.iter().enumerate() {
            push(Kind::Nonneg, k, &[e])?;
        }
        for (k, (head, tail)) in p.socs.iter().enumerate() {
            if tail.is_empty() {
                return Err(format!("soc constraint #{k} has no tail"));
            }
            let es: Vec<&Affine> = std::iter::once(head).chain(tail).collect();
            push(Kind::Soc, k, &es)?;
        }
        Ok(Form { n, q, rows, cons })
    }

    /// Clarabel's `A` (column-major, sorted row indices), `b` and cones.
    fn clarabel(&self) -> (CscMatrix<f64>, Vec<f64>, Vec<SupportedConeT<f64>>) {
        let (m, n) = (self.rows.len(), self.n);
        let mut colptr = vec![0usize; n + 1];
        for row in &self.rows {
            for &(j, _) in &row.terms {
                colptr[j + 1] += 1;
            }
        }
        for j in 0..n {
            colptr[j + 1] += colptr[j];
        }
        let nnz = colptr[n];
        let mut next = colptr.clone();
        let mut rowval = vec![0usize; nnz];
        let mut nzval = vec![0.0; nnz];
        // Rows in increasing order: each column's row indices come out sorted; the terms of a
        // row are merged, so there are no duplicates.
        for (i, row) in self.rows.iter().enumerate() {
            for &(j, c) in &row.terms {
                rowval[next[j]] = i;
                nzval[next[j]] = -c;
                next[j] += 1;
            }
        }
        let a = CscMatrix::new(m, n, colptr, rowval, nzval);
        let b = self.rows.iter().map(|r| r.constant).collect();
        let count = |kind| self.cons.iter().filter(|c| c.kind == kind).count();
        let mut cones = Vec::new();
        let (zeros, nonnegs) = (count(Kind::Zero), count(Kind::Nonneg));
        if zeros > 0 {
            cones.push(SupportedConeT::ZeroConeT(zeros));
        }
        if nonnegs > 0 {
            cones.push(SupportedConeT::NonnegativeConeT(nonnegs));
        }
        for con in self.cons.iter().filter(|c| c.kind == Kind::Soc) {
            cones.push(SupportedConeT::SecondOrderConeT(con.len));
        }
        (a, b, cones)
    }

    /// `(A^T y, sum_i |A_ij y_i|, sum_i |A_ij|)` per column.
    fn at_times(&self, y: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = self.n;
        let (mut g, mut mag, mut coef) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for (row, &yi) in self.rows.iter().zip(y) {
            for &(j, c) in &row.terms {
                g[j] -= c * yi;
                mag[j] += (c * yi).abs();
                coef[j] += c.abs();
            }
        }
        (g, mag, coef)
    }
}

/// Which attempt: Clarabel's usual settings, the tighter retry, or the last one without
/// Ruiz equilibration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    Default,
    Tight,
    Unequilibrated,
}

/// Clarabel's settings for an attempt.
fn settings(mode: Mode) -> Result<DefaultSettings<f64>, String> {
    let mut b = DefaultSettingsBuilder::<f64>::default();
    b.verbose(false)
        .max_threads(1)
        .direct_solve_method("qdldl".to_string());
    if mode == Mode::Unequilibrated {
        b.equilibrate_enable(false);
    }
    if mode == Mode::Tight {
        b.max_iter(1000)
            .tol_gap_abs(1e-10)
            .tol_gap_rel(1e-10)
            .tol_feas(1e-10)
            .tol_ktratio(1e-10)
            .iterative_refinement_max_iter(50)
            .iterative_refinement_reltol(1e-15)
            .iterative_refinement_abstol(1e-14);
    } else {
        b.max_iter(200)
            .tol_gap_abs(1e-8)
            .tol_gap_rel(1e-8)
            .tol_feas(1e-8);
    }
    b.build().map_err(|e| format!("clarabel settings: {e}"))
}

/// What Clarabel returned: status, `x`, `z`.
type Raw = (SolverStatus, Vec<f64>, Vec<f64>);

/// One run of Clarabel on `form`.
fn run(form: &Form, mode: Mode) -> Result<Raw, String> {
    let settings = settings(mode)?;
    let (a, b, cones) = form.clarabel();
    let p = CscMatrix::zeros((form.n, form.n));
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let mut solver = DefaultSolver::new(&p, &form.q, &a, &b, &cones, settings)
            .map_err(|e| format!("clarabel setup: {e}"))?;
        solver.solve();
        let s = &solver.solution;
        Ok((s.status, s.x.clone(), s.z.clone()))
    }));
    outcome.unwrap_or_else(|_| Err("clarabel panicked".to_string()))
}

/// One attempt: run, then check what the status claims.
fn attempt(form: &Form, mode: Mode) -> Verdict {
    let (status, x, z) = match run(form, mode) {
        Ok(raw) => raw,
        Err(reason) => return Verdict::Failed(Failure::new(reason)),
    };
    let which = match mode {
        Mode::Default => "default",
        Mode::Tight => "tight",
        Mode::Unequilibrated => "unequilibrated",
    };
    let checked = match status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            check_optimal(form, &x, &z).map(|value| Answer::Optimal { x, value })
        }
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            check_certificate(form, &z).map(|y| Answer::Infeasible { y })
        }
        SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => {
            return Verdict::Failed(Failure {
                reason: format!("status {status:?} ({which} settings): unbounded"),
                unbounded: true,
            })
        }
        _ => {
            return Verdict::Failed(Failure::new(format!(
                "status {status:?} ({which} settings)"
            )))
        }
    };
    match checked {
        Ok(answer)
            if matches!(
                status,
                SolverStatus::Solved | SolverStatus::PrimalInfeasible
            ) =>
        {
            Verdict::Verified(answer)
        }
        Ok(answer) => Verdict::Almost(answer),
        Err(why) => Verdict::Failed(Failure::new(format!(
            "status {status:?} ({which} settings) but {why}"
        ))),
    }
}

/// `v <= allowed`; false if either is NaN.
fn within(v: f64, allowed: f64) -> bool {
    v <= allowed
}

/// `max |v_i|` (0 for an empty vector).
fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Moves `y` (rows of `form`) onto the dual cone `K*`; returns the largest change of an entry.
fn project_dual(form: &Form, y: &mut [f64]) -> f64 {
    let mut moved = 0.0f64;
    for con in &form.cons {
        let block = &mut y[con.start..con.start + con.len];
        match con.kind {
            Kind::Zero => {}
            Kind::Nonneg => {
                if block[0] < 0.0 {
                    moved = moved.max(-block[0]);
                    block[0] = 0.0;
                }
            }
            Kind::Soc => {
                let (h, t) = (
                    block[0],
                    block[1..].iter().map(|v| v * v).sum::<f64>().sqrt(),
                );
                if t <= h {
                    continue;
                }
                let a = if t <= -h { 0.0 } else { 0.5 * (h + t) };
                let new_h = a;
                moved = moved.max((new_h - h).abs());
                block[0] = new_h;
                for v in &mut block[1..] {
                    let new_v = if a == 0.0 { 0.0 } else { *v * (a / t) };
                    moved = moved.max((new_v - *v).abs());
                    *v = new_v;
                }
            }
        }
    }
    moved
}

/// Checks a claimed optimum `x` with dual `z` (see the module docs); returns `q . x`.
fn check_optimal(form: &Form, x: &[f64], z: &[f64]) -> Result<f64, String> {
    if x.len() != form.n || x.iter().any(|v| !v.is_finite()) {
        return Err("the point has a non-finite entry or the wrong length".to_string());
    }
    check_point(form, x)?;
    let value: f64 = form.q.iter().zip(x).map(|(q, x)| q * x).sum();
    if form.q.iter().all(|&q| q == 0.0) {
        return Ok(value);
    }
    if z.len() != form.rows.len() || z.iter().any(|v| !v.is_finite()) {
        return Err("the dual has a non-finite entry or the wrong length".to_string());
    }
    let mut z = z.to_vec();
    let zmax = inf_norm(&z);
    let moved = project_dual(form, &mut z);
    if moved > TOL_CONE * zmax {
        return Err(format!(
            "the dual is {moved:e} outside the dual cone (|z|_inf = {zmax:e})"
        ));
    }
    let (g, mag, coef) = form.at_times(&z);
    for j in 0..form.n {
        let q = form.q[j];
        let r = (q + g[j]).abs();
        let allowed = TOL_REL * (q.abs() + mag[j]) + TOL_NORM * (q.abs() + coef[j] * zmax);
        if !within(r, allowed) {
            return Err(format!(
                "the dual residual of variable {j} is {r:e} (allowed {allowed:e})"
            ));
        }
    }
    let bz: f64 = form.rows.iter().zip(&z).map(|(r, z)| r.constant * z).sum();
    let bz_terms: f64 = form
        .rows
        .iter()
        .zip(&z)
        .map(|(r, z)| (r.constant * z).abs())
        .sum();
    let qx_terms: f64 = form.q.iter().zip(x).map(|(q, x)| (q * x).abs()).sum();
    let q1: f64 = form.q.iter().map(|q| q.abs()).sum();
    let gap = (value + bz).abs();
    let allowed = TOL_REL * (qx_terms + bz_terms) + TOL_NORM * q1 * inf_norm(x);
    if !within(gap, allowed) {
        return Err(format!("the duality gap is {gap:e} (allowed {allowed:e})"));
    }
    Ok(value)
}

/// Checks that `x` (finite, of the right length) meets every constraint of `form`.
fn check_point(form: &Form, x: &[f64]) -> Result<(), String> {
    let xmax = inf_norm(x);
    for con in &form.cons {
        let mut allowed = 0.0;
        let mut values = Vec::with_capacity(con.len);
        for row in &form.rows[con.start..con.start + con.len] {
            let (e, scale, coef) = row.eval(x);
            allowed += TOL_REL * scale + TOL_NORM * coef * xmax;
            values.push(e);
        }
        let violation = match con.kind {
            Kind::Zero => values[0].abs(),
            Kind::Nonneg => -values[0],
            Kind::Soc => values[1..].iter().map(|v| v * v).sum::<f64>().sqrt() - values[0],
        };
        if !within(violation, allowed) {
            return Err(format!(
                "{} is violated by {violation:e} (allowed {allowed:e})",
                con.name()
            ));
        }
    }
    Ok(())
}

/// Checks Clarabel's certificate of primal infeasibility `y` (see the module docs); returns it
/// scaled and projected as checked.
fn check_certificate(form: &Form, y: &[f64]) -> Result<Vec<f64>, String> {
    if y.len() != form.rows.len() || y.iter().any(|v| !v.is_finite()) {
        return Err("the certificate has a non-finite entry or the wrong length".to_string());
    }
    let ymax = inf_norm(y);
    if ymax == 0.0 {
        return Err("the certificate is zero".to_string());
    }
    let mut y: Vec<f64> = y.iter().map(|v| v / ymax).collect();
    let moved = project_dual(form, &mut y);
    if moved > TOL_CONE {
        return Err(format!(
            "the certificate is {moved:e} outside the dual cone (relative)"
        ));
    }
    let beta: f64 = form.rows.iter().zip(&y).map(|(r, y)| r.constant * y).sum();
    let b_terms: f64 = form
        .rows
        .iter()
        .zip(&y)
        .map(|(r, y)| (r.constant * y).abs())
        .sum();
    if !within(beta, -CERT * b_terms) || beta >= 0.0 {
        return Err(format!(
            "b . y = {beta:e} is not clearly negative (terms {b_terms:e})"
        ));
    }
    let b1: f64 = form.rows.iter().map(|r| r.constant.abs()).sum();
    let (g, _, coef) = form.at_times(&y);
    for j in 0..form.n {
        if !within(g[j].abs() * b1, CERT * -beta * coef[j]) {
            return Err(format!(
                "(A^T y)_{j} = {:e} does not vanish (allowed {:e})",
                g[j],
                CERT * -beta * coef[j] / b1
            ));
        }
    }
    Ok(y)
}

mod fallback;
use fallback::by_simplex;

#[cfg(test)]
mod tests;
