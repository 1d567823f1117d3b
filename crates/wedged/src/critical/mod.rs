//! The critical friction coefficient (MISSION section 6): the least `mu*` for which the wedged
//! problem has a nontrivial solution, as a **global** optimum with a bracket `[lower, upper]`.
//!
//! `upper` comes with a witness: a solution of WP at `mu = upper`, checked here against WP.
//! `lower` is justified by certificates: every part of the search space was shown infeasible at
//! some friction coefficient `>= lower` by a checked Farkas certificate of the conic solver
//! (`conic/socp.rs`). Feasibility is monotone in `mu` (the friction cones only grow), so one
//! certificate at `mu` covers every smaller `mu`.
//!
//! Every nontrivial solution `(u, r)` has a *contact set* `A` (its pressed nodes) and lies in the
//! *leaf* of `A`: `u_n = 0` and `r` in the friction cone on `A`, `r = 0` and `u_n >= 0` off `A`.
//! Every point of a leaf solves WP (complementarity holds by construction), so `mu*` is the
//! least of the leaves' thresholds, and a leaf's threshold
//!
//! ```text
//! mu_A = min { max_{i in A, r_n_i > 0} ||r_t_i|| / r_n_i  :  (u, r) in the leaf of A, sum r_n = 1 }
//! ```
//!
//! is a generalised fractional program (linear-fractional in 2D). It is found by the
//! Dinkelbach-type method of Crouzeix, Ferland and Schaible (their second method): from a
//! feasible point with ratio `theta`, minimise `s` subject to `||r_t_i|| <= theta r_n_i + w_i s`
//! (`w` the pressures of that point); the optimum's ratio is the next `theta`. Where the
//! pressures stay away from zero it converges superlinearly (their analysis); where it stalls
//! (a node whose pressure vanishes at the optimum), probes below `theta` and then bisection take
//! over (`Ctx::leaf_threshold`). Each point is made an exact solution of the leaf (projected
//! onto its equalities) before its ratio is taken, so `upper` is the ratio of an actual
//! solution. Every probe found infeasible carries a checked Farkas certificate. Once the
//! descent stalls, `polish.rs` locates the threshold more closely from the tight constraints of
//! the least-norm certificate (the friction coefficient where they become singular), makes the
//! point there exact, and builds the certificate just below it: this reaches `tol` (1e-9 by
//! default) where the tight set can be read. Where it cannot (most 3D leaves, whose slip
//! directions turn with `mu`), `newton.rs` solves the leaf's optimality conditions by Newton's
//! method, and their multipliers are the certificate. Otherwise the bracket is narrowed to `tol` or
//! until the solver's feasibility resolution (about 1e-7 relative) stops it. The bracket
//! reported is the one certified.
//!
//! Three methods ([`CriticalMethod`]):
//! - `bnb` (`bnb.rs`): branch and bound over contact sets with an incumbent; a subtree is
//!   pruned when its relaxation cannot press its contact nodes at `min(bar, incumbent (1 -
//!   tol))` (certified infeasible). The bars of successive passes are the problem's `mu`, up by
//!   a factor 1.25 to about 16 times it, and `infinity` (friction unlimited): a tree pruned entirely there proves that
//!   no friction coefficient wedges the body.
//! - `enumerate` (`enumerate.rs`), the seed's method: the maximal patterns at a large `mu`,
//!   then each one's threshold; also gives the per-pattern thresholds of `wedged sweep`.
//! - `faces` (`faces.rs`): every contact set, each threshold by plain bisection: the test
//!   baseline.

mod bnb;
pub mod certify;
mod condensed;
mod edge;
mod enumerate;
mod exact;
mod faces;
mod groups;
mod improve;
mod newton;
mod polish;
mod progress;
mod shards;
mod witness;

use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use crate::solution::{check_solution, ContactPattern, NodeStatus};

use crate::conic::program::{
    leaf_classes, Counters, Decision, Formulation, Goal, Norm, Refutation,
};
use crate::conic::refutation::solve_again;
use crate::patterns::Undecided;
use crate::problem::Problem;
use crate::run::{Control, EnumerateError, Fault, Limits, Stop};
use crate::shard::{Shard, ShardReport};

pub use progress::CriticalProgress;
pub use shards::merge_shards;
pub(crate) use witness::{corrupt, witness_of};

/// The most nodes [`CriticalMethod::Faces`] accepts.
pub const CRITICAL_FACES_MAX_NODES: usize = 12;

/// The default relative width of the bracket.
pub const DEFAULT_TOL: f64 = 1e-9;

/// The loosest bracket a leaf's certificate may fall back to before the leaf is undecided...
const LOOSEST: f64 = 1e-3;

/// ... or the bracket asked for, when that is looser ([`loosest`]).
///
/// (With `LOOSEST` alone, a run asked for `tol` above `2e-3` certified each leaf's lower end
/// at `theta (1 - tol / 2)`, found that bracket wider than `LOOSEST`, and left every leaf
/// undecided: `critical --tol 1e-2` on the 2D plug at m = 50 ran for ten minutes, where the
/// default `tol` takes 0.12 s.)
pub(crate) fn loosest(tol: f64) -> f64 {
    LOOSEST.max(tol)
}

/// Where a leaf's threshold `theta` is refuted from its own solution (`polish`, `newton`), as
/// shares of `theta` below it, closest first: half the `tol` asked, then ten times further
/// each, down to half of [`DEFAULT_TOL`] (one share when `tol` is that or looser). A `tol`
/// finer than the certificates reach then still gets the default's bracket. (With the one
/// share, `critical --tol 1e-12` certified the 2D plug at m = 50 to 1e-7, where the default
/// reaches 1e-9, and the 3D V-groove plug at m = 40 to 1.3e-6.)
fn shares_below(tol: f64) -> impl Iterator<Item = f64> {
    let first = 0.5 * tol;
    std::iter::successors(Some(first), |g| Some(g * 10.0))
        .take_while(move |&g| g == first || g <= 0.5 * DEFAULT_TOL * (1.0 + 1e-9))
}

/// Programs per leaf threshold before it is given up as undecided.
const MAX_ROUNDS: usize = 400;

/// How `mu*` is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CriticalMethod {
    /// Branch and bound over contact sets with an incumbent. The default.
    #[default]
    Bnb,
    /// The seed's method: enumerate the maximal patterns at a large `mu`, then take the least of
    /// their thresholds.
    Enumerate,
    /// Every contact set, each threshold by bisection (a test baseline, `m <= 12`).
    Faces,
}

impl CriticalMethod {
    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            CriticalMethod::Bnb => "bnb",
            CriticalMethod::Enumerate => "enumerate",
            CriticalMethod::Faces => "faces",
        }
    }
}

impl fmt::Display for CriticalMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Tuning of a critical-coefficient run.
#[derive(Debug, Clone, PartialEq)]
pub struct CriticalSettings {
    /// The method. Default [`CriticalMethod::Bnb`].
    pub method: CriticalMethod,
    /// The relative width asked of the bracket: `upper - lower <= tol * upper`. Default `1e-9`,
    /// in `[1e-12, 0.1]`. The solver may not certify that close; see
    /// [`CriticalInfo::tol_achieved`].
    pub tol: f64,
    /// Bounds on the run (time and the cancel flag; rays and memory do not apply).
    pub limits: Limits,
    /// Keep every infeasibility certificate and re-check them, and the witness, in exact
    /// rational arithmetic ([`certify`]); the outcome is [`Critical::certificate`].
    pub certify: bool,
    /// Test hook, not part of the API: a fault to inject so that tests can see an internal
    /// failure reported as one (the CLI sets it from `WEDGED_INJECT_FAULT`). `None` in use.
    #[doc(hidden)]
    pub fault: Option<Fault>,
    /// Run one shard of the `bnb` search only ([`crate::shard`]): the bracket of `mu*` over
    /// its part of the tree; [`merge_shards`] gives the one-run bracket from all of them.
    /// `None` (the default): the whole search.
    pub shard: Option<Shard>,
    /// A contact set to start `bnb` from (one entry per node, `true` in contact), such as the
    /// answer on a coarser mesh of the same body mapped to this one: its leaf (from the
    /// problem's `mu`, doubled up to 64 times) improved by local search becomes the first
    /// incumbent, and the first leaf's dive is skipped. It changes how fast the bracket is
    /// found, never the bracket. (On the 2D plug at m = 400 the answer at m = 200 mapped
    /// gives 1.7719 in 2 s, about 1% above `mu*`, where the dive's rounded root gives 2.2812
    /// after 340 s; `BENCHMARKS.md`.) Not used by a certified run, a shard (whose top must be
    /// the same in every process) or the other methods. `None` (the default): the dive.
    pub start: Option<Vec<bool>>,
    /// Without a `start`, start `bnb` on a large problem (80 nodes or more in 2D, 40 in 3D;
    /// not certified, not a shard, not a floating body) from the answer of the problem
    /// condensed onto about half its nodes (`critical/condensed.rs`;
    /// [`CriticalInfo::condensed_nodes`]). It changes how fast the bracket is found, never the
    /// bracket. Default `true`; `false` computes from scratch (the command's `--no-chain`).
    pub condense: bool,
}

impl Default for CriticalSettings {
    fn default() -> Self {
        CriticalSettings {
            method: CriticalMethod::Bnb,
            tol: DEFAULT_TOL,
            limits: Limits::default(),
            certify: false,
            fault: None,
            shard: None,
            start: None,
            condense: true,
        }
    }
}

/// What a run found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CriticalStatus {
    /// `mu*` is bracketed and a witness exists at `upper`.
    Wedged,
    /// No friction coefficient gives a nontrivial solution: the whole search was certified
    /// infeasible with the friction limit removed (`bnb`, `faces`).
    Never,
    /// The run stopped early or some programs stayed undecided: `upper`, when present, is
    /// still a checked witness, but `lower` is not certified.
    Incomplete(Stop),
}

impl CriticalStatus {
    /// `"wedged"`, `"never"` or `"incomplete"`.
    pub fn name(self) -> &'static str {
        match self {
            CriticalStatus::Wedged => "wedged",
            CriticalStatus::Never => "never",
            CriticalStatus::Incomplete(_) => "incomplete",
        }
    }
}

/// A solution of WP at `mu = upper`.
#[derive(Debug, Clone, PartialEq)]
pub struct CriticalWitness {
    /// Displacements, `dim*m`, local frames.
    pub u: Vec<f64>,
    /// Reactions, `dim*m`, `sum r_n = 1`.
    pub r: Vec<f64>,
    /// Per node at `mu = upper`: separated, grazing, stick, or slip (the nodes whose ratio
    /// `||r_t|| / r_n` equals `upper`).
    pub status: Vec<NodeStatus>,
    /// The sign pattern of the witness.
    pub pattern: Vec<ContactPattern>,
}

/// One maximal pattern of the enumeration at a large `mu` and its own threshold
/// ([`CriticalMethod::Enumerate`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PatternThreshold {
    /// The pattern at the enumerated `mu` ([`CriticalInfo::mu_enumerated`]).
    pub pattern: Vec<ContactPattern>,
    /// The least `mu` at which a solution of the pattern's closed piece exists (the upper end of
    /// its bracket).
    pub threshold: f64,
    /// The certified lower end of its bracket.
    pub lower: f64,
    /// A solution of the pattern's piece at `threshold` (made and checked as the run's own
    /// witness is); `None` when it failed that check (the threshold still stands: its bracket is
    /// the solver's).
    pub witness: Option<CriticalWitness>,
}

/// Diagnostics of a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CriticalInfo {
    /// The method's name.
    pub method: &'static str,
    /// Search nodes whose relaxation was solved (bnb).
    pub nodes_visited: u64,
    /// Subtrees (or contact sets, faces) pruned by a certified infeasibility.
    pub pruned_infeasible: u64,
    /// Contact sets whose threshold was computed (bnb: leaves reached, each tested and, when
    /// feasible, its threshold computed).
    pub leaves_solved: u64,
    /// Search nodes that tightened the bounds behind their drive cuts (bnb without
    /// `certify`; see `critical/cuts.rs`), two programs per undecided node each.
    pub bound_tightenings: u64,
    /// Branchings whose separated child separated the branch node's mirror images too (bnb
    /// without `certify`, on a problem with [`crate::Problem::symmetries`]).
    pub mirrored: u64,
    /// Nodes visited by the dive for a first leaf (bnb without `certify`, not in shards; see
    /// `critical/bnb.rs`).
    pub dive_nodes: u64,
    /// Steps of the local search that improved the run's leaves: its first one, and in 2D
    /// from 24 nodes on every new best one (see `critical/improve.rs`).
    pub improvement_steps: u64,
    /// Linear programs of a search with drive cuts decided by the in-house simplex method,
    /// warm-started (2D bnb without `certify`; see `simplex.rs`).
    pub simplex_solves: u64,
    /// Programs the simplex method could not decide, solved by Clarabel instead.
    pub simplex_fallbacks: u64,
    /// Inner nodes whose pressed program the simplex method could not decide, decided
    /// normalised by the sum instead (a relaxation; see `conic::node_lp::decide_inner`).
    pub simplex_relaxed: u64,
    /// Dinkelbach steps (programs minimising the slack).
    pub dinkelbach_steps: u64,
    /// Bisection steps (faces).
    pub bisection_steps: u64,
    /// Farkas certificates of infeasibility, checked (every prune and every leaf's lower end).
    pub certificates: u64,
    /// Certificates that had to be taken further below a threshold than `tol` asked.
    pub loosened: u64,
    /// The relative width of the bracket actually certified (`(upper - lower) / upper`).
    pub tol_achieved: f64,
    /// The friction coefficient at which the patterns were enumerated (enumerate).
    pub mu_enumerated: Option<f64>,
    /// Maximal patterns enumerated there (enumerate).
    pub patterns_enumerated: u64,
    /// Conic programs solved (retries included).
    pub socps: u64,
    /// Programs solved a second time with tighter settings.
    pub retries: u64,
    /// Programs the solver left undecided after its retry.
    pub uncertain: u64,
    /// Groups of contact nodes that `K` does not couple, each searched on its own (`mu*` the
    /// least of theirs; `critical/groups.rs`); 0 when the nodes are one group.
    pub groups: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// The nodes of the condensed problem whose answer started `bnb`
    /// ([`CriticalSettings::condense`]); 0 when none did.
    pub condensed_nodes: u64,
    /// That problem's `mu*` (its upper end if its run stopped early).
    pub condensed_mu: Option<f64>,
    /// The seconds its run took (within `seconds`).
    pub condensed_seconds: f64,
}

/// The result of [`critical`].
#[derive(Debug, Clone, PartialEq)]
pub struct Critical {
    /// Wedged (bracketed), never, or incomplete.
    pub status: CriticalStatus,
    /// `upper` when the status is [`CriticalStatus::Wedged`]: the least friction coefficient at
    /// which a checked solution was found; the true `mu*` lies in `[lower, upper]`.
    pub mu_critical: Option<f64>,
    /// The certified lower end: of the bracket when wedged; when incomplete, what the `bnb`
    /// passes finished before the stop proved (`mu*` above it: no contact set wedges the body
    /// at it), if they proved anything; none when never.
    pub lower: Option<f64>,
    /// The upper end: the ratio of the witness.
    pub upper: Option<f64>,
    /// A solution of WP at `mu = upper`.
    pub witness: Option<CriticalWitness>,
    /// Per maximal pattern, its own threshold (enumerate; sorted by threshold).
    pub thresholds: Vec<PatternThreshold>,
    /// Contact sets the solver could not decide.
    pub undecided: Vec<Undecided>,
    /// Diagnostics.
    pub info: CriticalInfo,
    /// The exact checks, when [`CriticalSettings::certify`] asked for them.
    pub certificate: Option<certify::CriticalCertificate>,
    /// How the search was split, for a run of one shard ([`CriticalSettings::shard`]).
    pub shard: Option<ShardReport>,
}

impl Critical {
    /// A result of `status` with the bracket `[lower, upper]` (`mu*` is `upper` where wedged),
    /// no per-pattern thresholds and no shard.
    pub(crate) fn of_bracket(
        status: CriticalStatus,
        (lower, upper): (Option<f64>, Option<f64>),
        witness: Option<CriticalWitness>,
        undecided: Vec<Undecided>,
        info: CriticalInfo,
        certificate: Option<certify::CriticalCertificate>,
    ) -> Critical {
        Critical {
            status,
            mu_critical: (status == CriticalStatus::Wedged)
                .then_some(upper)
                .flatten(),
            lower,
            upper,
            witness,
            thresholds: Vec::new(),
            undecided,
            info,
            certificate,
            shard: None,
        }
    }
}

/// Computes the critical friction coefficient of a 2D or 3D problem. The problem's own `mu` is a
/// starting guess: the first bar of [`CriticalMethod::Bnb`], the first `mu` to enumerate at for
/// [`CriticalMethod::Enumerate`]; [`CriticalMethod::Faces`] ignores it.
pub fn critical(
    problem: &Problem,
    settings: &CriticalSettings,
) -> Result<Critical, EnumerateError> {
    critical_with_control(problem, settings, &|_| {}, &AtomicBool::new(false))
}

/// [`critical`] with progress reports (from the calling thread) and a cancellation flag.
pub fn critical_with_control(
    problem: &Problem,
    settings: &CriticalSettings,
    progress: &dyn Fn(CriticalProgress),
    cancel: &AtomicBool,
) -> Result<Critical, EnumerateError> {
    if !(1e-12..=0.1).contains(&settings.tol) {
        return Err(EnumerateError::InvalidSettings(format!(
            "the tolerance of mu* must be in [1e-12, 0.1], got {}",
            settings.tol
        )));
    }
    if settings.method == CriticalMethod::Faces && problem.nodes() > CRITICAL_FACES_MAX_NODES {
        return Err(EnumerateError::InvalidSettings(format!(
            "the faces method tries all 2^m contact sets; m = {} is more than its limit of \
             {CRITICAL_FACES_MAX_NODES} (use bnb)",
            problem.nodes()
        )));
    }
    if settings.shard.is_some() && settings.method != CriticalMethod::Bnb {
        return Err(EnumerateError::InvalidSettings(format!(
            "shards split the search tree of the bnb method; the {} method has none",
            settings.method.name()
        )));
    }
    if let Some(start) = &settings.start {
        if start.len() != problem.nodes() {
            return Err(EnumerateError::InvalidSettings(format!(
                "the start contact set has {} entries for {} nodes",
                start.len(),
                problem.nodes()
            )));
        }
        if !start.contains(&true) {
            return Err(EnumerateError::InvalidSettings(
                "the start contact set has no node in contact".to_string(),
            ));
        }
    }
    if problem.is_floating() {
        let why = crate::patterns::floating_certify_refusal(problem.dim(), settings.certify);
        if let Some(why) = why {
            return Err(EnumerateError::InvalidSettings(why));
        }
    }
    if settings.shard.is_none() && settings.method != CriticalMethod::Enumerate {
        let groups = crate::groups::uncoupled_groups(problem);
        if groups.len() > 1 {
            return groups::by_groups(problem, settings, &groups, progress, cancel);
        }
    }
    let start = Instant::now();
    // A large problem with no start given starts from its condensed problem's answer.
    let given = settings.limits.time_limit;
    let (condensed, own) = condensed::started(problem, settings, progress, cancel, start)?;
    let settings = own.as_ref().unwrap_or(settings);
    // Everything below runs on the problem in per-node units that bring K's diagonal near 1
    // (exactly equivalent, see Problem::equilibrated); the witness is mapped back at the end.
    let original = problem;
    let (scaled, scales) = problem.equilibrated();
    let problem = &scaled;
    let control = Control::new(settings.limits, cancel);
    let mut form = Formulation::new(problem);
    if settings.certify {
        form.refutations = Some(std::sync::Mutex::new(Vec::new()));
    }
    let ctx = Ctx {
        form: &form,
        tol: settings.tol,
        tally: Tally::default(),
    };
    let mut info = CriticalInfo {
        method: settings.method.name(),
        condensed_nodes: condensed.as_ref().map_or(0, |c| c.nodes as u64),
        condensed_mu: condensed.as_ref().map(|c| c.mu),
        condensed_seconds: condensed.as_ref().map_or(0.0, |c| c.seconds),
        ..CriticalInfo::default()
    };
    let found = if control.must_stop(0) {
        Found::default()
    } else {
        match settings.method {
            CriticalMethod::Bnb => {
                let hooks = bnb::Hooks::of(settings.fault);
                let start = settings.start.as_deref();
                bnb::run(
                    &ctx,
                    &mut info,
                    (settings.shard, start),
                    progress,
                    &control,
                    hooks,
                )
            }
            CriticalMethod::Faces => faces::run(&ctx, &mut info, progress, &control),
            CriticalMethod::Enumerate => {
                enumerate::run(&ctx, &mut info, progress, settings.limits, cancel, &control)?
            }
        }
    };
    let c = &form.counters;
    info.socps = Counters::get(&c.socps);
    info.retries = Counters::get(&c.retries);
    info.uncertain = Counters::get(&c.uncertain);
    let t = &ctx.tally;
    info.dinkelbach_steps = t.dinkelbach.load(Ordering::Relaxed);
    info.bisection_steps += t.bisection.load(Ordering::Relaxed);
    info.certificates = t.certificates.load(Ordering::Relaxed);
    info.loosened = t.loosened.load(Ordering::Relaxed);
    let stop = found
        .stop
        .or_else(|| control.stopped())
        .or_else(|| (!found.undecided.is_empty()).then_some(Stop::Undecided));
    let witness = match &found.best {
        Some(best) => Some(witness_of(&form, best)?),
        None => None,
    };
    let upper = found.best.as_ref().map(|b| b.theta);
    let stop = condensed::given_limit(stop, given);
    let (status, lower) = match (stop, upper) {
        // A stopped run keeps what its finished passes proved: `mu* > proved`.
        (Some(s), _) => (CriticalStatus::Incomplete(s), found.proved),
        (None, None) => (CriticalStatus::Never, None),
        (None, Some(_)) => (CriticalStatus::Wedged, Some(found.lower)),
    };
    if let (Some(l), Some(u)) = (lower, upper) {
        info.tol_achieved = (u - l) / u;
    }
    let certificate = settings.certify.then(|| {
        let refutations = form.take_refutations();
        let closed: Option<Vec<bool>> = witness.as_ref().map(|w| {
            w.pattern
                .iter()
                .map(|&p| p != ContactPattern::Separated)
                .collect()
        });
        let note = (settings.method == CriticalMethod::Enumerate).then(|| {
            "the enumerate method's lower end rests on the floating-point enumeration of \
             patterns, which is not certified (use --method bnb or faces)"
                .to_string()
        });
        let again = |f: &Refutation, mu: f64, sum: bool| solve_again(problem, f, mu, sum);
        certify::certify(
            problem,
            &refutations,
            witness
                .as_ref()
                .zip(closed.as_ref())
                .zip(upper)
                .map(|((w, c), up)| (&w.u[..], &w.r[..], &c[..], up)),
            lower.or(upper),
            &again,
            note,
        )
    });
    info.seconds = start.elapsed().as_secs_f64();
    let mut thresholds = found.thresholds;
    let witness = match (witness, upper) {
        (Some(w), Some(up)) => {
            let (mut u, r) = original.unscale(&scales, &w.u, &w.r);
            if settings.fault == Some(Fault::CorruptWitness) {
                corrupt(&mut u);
            }
            check_solution(original, up, &u, &r).map_err(|why| {
                EnumerateError::Internal(format!(
                    "the witness of mu* = {up}, in the problem's own units, failed its check, so \
                     no answer is given: {why}"
                ))
            })?;
            Some(CriticalWitness { u, r, ..w })
        }
        (w, _) => w,
    };
    thresholds.sort_by(|a, b| {
        a.threshold
            .total_cmp(&b.threshold)
            .then(a.pattern.cmp(&b.pattern))
    });
    Ok(Critical {
        thresholds,
        shard: found.shard,
        ..Critical::of_bracket(
            status,
            (lower, upper),
            witness,
            found.undecided,
            info,
            certificate,
        )
    })
}

/// What a method hands back.
#[derive(Default)]
pub(crate) struct Found {
    /// The best leaf.
    pub best: Option<Leaf>,
    /// The certified lower end (meaningful with a best leaf and no stop).
    pub lower: f64,
    /// A lower end proved even if the run stops later: the level of the last finished
    /// pass that found no wedged configuration at or below it (`bnb` only; `mu* >` it).
    pub proved: Option<f64>,
    pub thresholds: Vec<PatternThreshold>,
    pub undecided: Vec<Undecided>,
    /// A reason the method stopped on its own (enumerate: the enumeration's).
    pub stop: Option<Stop>,
    /// How a sharded search was split.
    pub shard: Option<ShardReport>,
}

/// Counters of the threshold computations.
#[derive(Default)]
pub(crate) struct Tally {
    pub dinkelbach: AtomicU64,
    pub bisection: AtomicU64,
    pub certificates: AtomicU64,
    pub loosened: AtomicU64,
}

/// What every method shares.
pub(crate) struct Ctx<'a, 'b> {
    pub form: &'a Formulation<'b>,
    pub tol: f64,
    pub tally: Tally,
}

/// A contact set's threshold: the ratio `theta` of a solution `r` of its leaf, and a friction
/// coefficient `lower` at which the leaf was certified infeasible.
#[derive(Debug, Clone)]
pub(crate) struct Leaf {
    pub contact: Vec<bool>,
    pub theta: f64,
    pub r: Vec<f64>,
    pub lower: f64,
}

impl Ctx<'_, '_> {
    /// The threshold of the leaf of `contact`, from a solution `r` of it at ratio `hi`, or
    /// `None` when the leaf is certified infeasible at `cap()` (the caller's current bar, read
    /// afresh each step; `INFINITY` for none).
    ///
    /// The bracket `[lo, hi]` starts at `[0, hi]` (at `mu = 0` no nontrivial solution exists:
    /// `r_t = 0` makes `u_n . r_n = r_n^T K^-1_nn r_n > 0`). Each round either takes a
    /// Dinkelbach step from `hi` (while they improve), or tests feasibility at a probe: first
    /// just below `hi` (`hi (1 - gap)`, `gap` from `tol` growing tenfold while the probes are
    /// feasible), then, once a probe is certified infeasible, halfway between `lo` and `hi`. A
    /// feasible probe's exact point lowers `hi`; a feasible probe whose exact point does not
    /// (the solver's resolution reached) ends the narrowing with the bracket certified so far.
    pub(crate) fn leaf_threshold(
        &self,
        contact: &[bool],
        hi: f64,
        r: Vec<f64>,
        control: &Control,
        cap: &dyn Fn() -> f64,
    ) -> Result<Option<Leaf>, String> {
        let classes = leaf_classes(contact);
        let (d, m) = (self.form.dim, self.form.m);
        let (mut hi, mut r) = (hi, r);
        let mut lo = 0.0f64;
        let mut gap = self.tol;
        let mut descend = true;
        let mut polished = false;
        let better = |t: f64, than: f64| t < than * (1.0 - self.tol * 0.01);
        let certified = |at: f64| {
            self.tally.certificates.fetch_add(1, Ordering::Relaxed);
            at
        };
        for _ in 0..MAX_ROUNDS {
            if control.must_stop(0) {
                return Err("stopped".into());
            }
            if hi - lo <= self.tol * hi {
                break;
            }
            let bar = cap();
            if bar < hi {
                // Someone else found better: is this leaf still of interest?
                match self
                    .form
                    .decide_at(&classes, bar, Norm::Sum, Goal::Feasible)
                {
                    Decision::No => {
                        certified(bar);
                        return Ok(None);
                    }
                    Decision::Yes { r: next, .. } => {
                        if let Some((t, p)) = self.exact_point(contact, &next, bar) {
                            if t < hi {
                                (hi, r, descend) = (t, p, true);
                                continue;
                            }
                        }
                    }
                    Decision::Unsure(_) => {}
                }
            }
            if descend && hi > 0.0 {
                let w: Vec<f64> = (0..m)
                    .map(|i| if contact[i] { r[d * i] } else { 0.0 })
                    .collect();
                self.tally.dinkelbach.fetch_add(1, Ordering::Relaxed);
                if let Decision::Yes { r: next, .. } =
                    self.form
                        .decide_at(&classes, hi, Norm::Sum, Goal::MinSlack(&w))
                {
                    if let Some((t, p)) = self.exact_point(contact, &next, hi) {
                        if better(t, hi) {
                            (hi, r) = (t, p);
                            continue;
                        }
                    }
                }
                descend = false;
            }
            if lo == 0.0 && !polished {
                // The threshold is reached (Dinkelbach stalls): its own solution gives the
                // certificate just below it (polish.rs), closer than the solver can.
                polished = true;
                if let Some((t, guess)) = polish::sharpen(self.form, contact, hi) {
                    if let Some((t, p)) = self.exact_point(contact, &guess, t) {
                        if t < hi {
                            (hi, r) = (t, p);
                        }
                    }
                }
                let below: Vec<f64> = shares_below(self.tol).map(|g| hi * (1.0 - g)).collect();
                if let Some((at, f)) = polish::refute_below(self.form, contact, hi, &below) {
                    self.form.keep(f);
                    lo = certified(at);
                    continue;
                }
                // No clean pole (most 3D leaves): Newton's method on the leaf's optimality
                // conditions gives the threshold and its multipliers the certificate.
                if let Some(p) = newton::polish(self.form, contact, hi, &r) {
                    if let Some((t, q)) = self.exact_point(contact, &p.r, p.theta) {
                        if t < hi {
                            (hi, r) = (t, q);
                        }
                    }
                    let refuted = shares_below(self.tol)
                        .map(|g| hi * (1.0 - g))
                        .find_map(|at| Some((at, p.refute(self.form, contact, at)?)));
                    if let Some((at, f)) = refuted {
                        self.form.keep(f);
                        lo = certified(at);
                        continue;
                    }
                }
            }
            let probe = if lo > 0.0 {
                0.5 * (lo + hi)
            } else {
                hi * (1.0 - gap)
            };
            match self
                .form
                .decide_at(&classes, probe, Norm::Sum, Goal::Feasible)
            {
                Decision::No => lo = certified(probe),
                Decision::Yes { r: next, .. } => match self.exact_point(contact, &next, probe) {
                    Some((t, p)) if t < hi && t >= lo => {
                        (hi, r, descend) = (t, p, true);
                        if lo == 0.0 {
                            gap = (gap * 10.0).min(0.5);
                        }
                    }
                    // Feasible by the solver's accuracy, no exact point below hi.
                    _ if lo > 0.0 => break,
                    _ => gap = (gap * 10.0).min(0.5),
                },
                Decision::Unsure(_) if lo > 0.0 => break,
                Decision::Unsure(_) => gap = (gap * 10.0).min(0.5),
            }
        }
        let loosest = loosest(self.tol);
        if lo == 0.0 || hi - lo > loosest * hi {
            return Err(format!(
                "the solver could not certify the threshold {hi} of this contact set to within \
                 {loosest:e} (certified below {lo})"
            ));
        }
        if hi - lo > self.tol * hi * 1.000001 {
            self.tally.loosened.fetch_add(1, Ordering::Relaxed);
        }
        Ok(Some(Leaf {
            contact: contact.to_vec(),
            theta: hi,
            r,
            lower: lo,
        }))
    }
}
