//! The sign patterns of the wedged problem (MISSION section 5): in 3D the friction cone is round
//! and the solution set `S` is not spanned by finitely many rays, so it is described by its
//! convex pieces instead.
//!
//! A *pattern* says, for every node, which of `u_n_i` and `r_n_i` is positive:
//! [`ContactPattern::Contact`] (`r_n > 0`), [`ContactPattern::Separated`] (`u_n > 0`) or
//! [`ContactPattern::Grazing`] (both zero). The solutions whose positive entries lie within those
//! of a pattern `q` form a convex cone `F_q` (contact nodes: `u_n = 0` and the friction cone;
//! separated: `r = 0`, `u_n >= 0`; grazing: both zero). `q` is *realised* when some solution has
//! exactly its positive entries; realised patterns are closed under joins (the sum of two
//! compatible solutions), so `S` is the union of the `F_q` of the **maximal** realised patterns:
//! those are the convex pieces of `S`, the 3D counterpart of the 2D cones. Each is reported with
//! a witness from the relative interior of its piece.
//!
//! Three methods, which share nothing but the conic programs of `program.rs`:
//! - [`PatternMethod::Bnb`] (`bnb.rs`): branch and bound on contact / separated, pruning a subtree
//!   whose relaxation has no nontrivial solution or cannot press every node already in contact;
//! - [`PatternMethod::Pyramid`] (`pyramid.rs`): the 2D algorithm on a circumscribed pyramid with
//!   `k` faces, whose maximal patterns are candidates, each checked exactly;
//! - [`PatternMethod::Faces`] (`faces.rs`): brute force over the `2^m` contact sets, each entry
//!   maximised on its own; a test baseline.
//!
//! All conic programs go through `conic/socp.rs`, which returns checked answers or says it is
//! unsure. Every reported witness is checked again here against WP itself.

mod bnb;
mod certify;
mod faces;
mod groups;
mod leaf;
pub(crate) use leaf::leaf_pattern;
mod maximal;
mod merge;
mod orbits;

mod pyramid;
mod search;

use std::collections::HashMap;
use std::fmt;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Instant;

use crate::conic::contact_lp::ContactLp;
use crate::conic::program::{describe, Class, Counters, Entry, Formulation, Support, POSITIVE};
pub use certify::PatternCertificate;
pub use maximal::keep_maximal;
pub(crate) use maximal::maximal;
pub(crate) use merge::every_shard;
pub use merge::{check_shards, merge_shards, missing_text};

use crate::run::{check_zero_tol, Control, EnumerateError, Limits, Outcome, Stop};
use crate::shard::{Shard, ShardReport};

use crate::solution::{check_balance, ContactPattern, NodeStatus};

use crate::problem::Problem;
use crate::rays::Progress;

/// The default number of faces of the pyramid.
pub const DEFAULT_PYRAMID_FACES: usize = 8;

/// The most nodes [`PatternMethod::Faces`] accepts.
pub const FACES_MAX_NODES: usize = 12;

/// How the patterns are found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PatternMethod {
    /// Branch and bound with SOCP relaxations. The default.
    #[default]
    Bnb,
    /// The polyhedral approximation with a circumscribed pyramid of `faces` faces (3D; in 2D
    /// the friction law is already polyhedral and `faces` is ignored).
    Pyramid { faces: usize },
    /// Brute force over all `2^m` contact sets (a test baseline, `m <= 12`).
    Faces,
    /// 2D only: the depth-first search over contact sets of the `search` ray method, each
    /// branch decided by a warm-started simplex method; a leaf's pattern comes from its support
    /// program. No rays: the work follows the pieces, not their extreme rays.
    Search,
}

impl PatternMethod {
    /// The name used on the command line and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            PatternMethod::Bnb => "bnb",
            PatternMethod::Pyramid { .. } => "pyramid",
            PatternMethod::Faces => "pattern-faces",
            PatternMethod::Search => "pattern-search",
        }
    }
}

impl fmt::Display for PatternMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Tuning of a pattern enumeration.
#[derive(Debug, Clone, PartialEq)]
pub struct PatternSettings {
    /// The method. Default [`PatternMethod::Bnb`].
    pub method: PatternMethod,
    /// The relative zero tolerance of the pyramid's double description (as
    /// [`crate::Settings::zero_tol`]). Default `1e-9`.
    pub zero_tol: f64,
    /// Bounds on the run; none by default.
    pub limits: Limits,
    /// Certify the answer in exact arithmetic ([`Patterns::certificate`]): every decision
    /// the search took is backed by an infeasibility certificate, checked exactly afterwards
    /// with each witness. Off by default (it adds programs and exact arithmetic).
    pub certify: bool,
    /// Run one shard of the search only ([`crate::shard`]; `bnb` and `pattern-search`): its
    /// answer holds the maximal patterns of its part of the tree, and the union of all the
    /// shards' answers, without the patterns that another contains, is the one-run answer.
    /// `None` (the default): the whole search.
    pub shard: Option<Shard>,
}

impl Default for PatternSettings {
    fn default() -> Self {
        PatternSettings {
            method: PatternMethod::Bnb,
            zero_tol: 1e-9,
            limits: Limits::default(),
            certify: false,
            shard: None,
        }
    }
}

/// A maximal realised sign pattern: one convex piece of `S`, with a witness.
#[derive(Debug, Clone, PartialEq)]
pub struct Pattern {
    /// Per node: contact, separated or grazing throughout the piece's relative interior.
    pub pattern: Vec<ContactPattern>,
    /// Per node, the status at the witness, which is in the relative interior: separated,
    /// grazing, stick, or slip when every solution of the piece slips there (3D [`NodeStatus::Slip`],
    /// 2D slip+/slip- by the sign of `r_t`).
    pub status: Vec<NodeStatus>,
    /// The witness's displacements, `dim*m`, in the local node frames.
    pub u: Vec<f64>,
    /// The witness's reactions, `dim*m`; `sum r_n = 1`.
    pub r: Vec<f64>,
    /// How far the witness is from the piece's boundary: the smallest of its positive entries,
    /// which are the pressures `r_n` of contact nodes (with `sum r_n = 1`), the friction slacks
    /// `mu r_n - ||r_t||` of sticking nodes, and the gaps `u_n` of separated nodes, each gap
    /// divided by the largest entry of its row of `K^{-1}` (so it is the gap that a unit
    /// reaction at the most compliant place would open: dimensionless like the others).
    pub margin: f64,
}

/// A contact set the solver could not decide, so the answer may miss the patterns below it.
#[derive(Debug, Clone, PartialEq)]
pub struct Undecided {
    /// Per node: contact (`true`) or not.
    pub contact: Vec<bool>,
    /// The solver's reason.
    pub reason: String,
}

/// Diagnostics of a pattern enumeration.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PatternInfo {
    /// Branch-and-bound nodes reached above the leaves (their relaxation solved, or inherited).
    pub nodes_visited: u64,
    /// Of those, the nodes whose relaxation was not solved because their parent's solution
    /// already met their constraints (they are never pruned).
    pub nodes_inherited: u64,
    /// Nodes pruned because the relaxation had no nontrivial solution.
    pub pruned_infeasible: u64,
    /// Nodes pruned because some node already in contact could not be pressed.
    pub pruned_unpressed: u64,
    /// Leaves (complete contact sets) reached: realised, not pressable, or undecided.
    pub leaves: u64,
    /// Candidate patterns checked exactly (pyramid: maximal patterns of the approximation;
    /// faces: contact sets with a nontrivial cone).
    pub candidates: u64,
    /// Candidates that were not realised as they stood (pyramid).
    pub spurious: u64,
    /// Rays of the pyramid approximation.
    pub pyramid_rays: u64,
    /// Conic programs solved (retries included).
    pub socps: u64,
    /// Programs solved a second time with tighter settings.
    pub retries: u64,
    /// Programs the solver left undecided after its retry.
    pub uncertain: u64,
    /// Decisions whose optimal value was within a factor of 100 of the positivity threshold.
    pub near_degenerate: u64,
    /// Realised patterns found before the maximal ones were kept.
    pub realised: u64,
    /// Maximal patterns handed to the sink of [`enumerate_patterns_streaming`] (not kept in
    /// [`Patterns::patterns`]).
    pub streamed: u64,
    /// Search nodes that bounded their free nodes' drives for the cuts of their subtree
    /// (search).
    pub bound_tightenings: u64,
    /// Linear programs solved by the simplex method, their pivots, and the programs passed on
    /// to Clarabel (search).
    pub lp_solves: u64,
    pub lp_pivots: u64,
    pub lp_fallbacks: u64,
    /// `bnb`'s branchings that separated a node's mirror image too (orbital branching, see
    /// [`crate::Problem::symmetries`]), and the patterns made as images of those found (the
    /// patterns of the regions they skipped; `patterns/orbits.rs`, `Group::complete`).
    pub mirrored: u64,
    pub images: u64,
    /// 3D: leaves decided and witnesses made as images of their orbits' least pattern's,
    /// instead of by cone programs of their own (`patterns/orbits.rs`).
    pub mapped: u64,
    /// Groups of contact nodes that `K` does not couple, each searched on its own, the pieces
    /// their products (`patterns/groups.rs`); 0 when the nodes are one group.
    pub groups: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// The result of [`enumerate_patterns`].
#[derive(Debug, Clone, PartialEq)]
pub struct Patterns {
    /// Complete or not, wedged or not. A run with undecided contact sets is complete in the
    /// sense that it finished, but see [`Patterns::undecided`].
    pub outcome: Outcome,
    /// The maximal realised patterns, sorted by pattern.
    pub patterns: Vec<Pattern>,
    /// Contact sets the solver could not decide.
    pub undecided: Vec<Undecided>,
    /// Diagnostics.
    pub info: PatternInfo,
    /// The exact certificate, when [`PatternSettings::certify`] asked for one.
    pub certificate: Option<PatternCertificate>,
    /// How the search was split, for a run of one shard ([`PatternSettings::shard`]).
    pub shard: Option<ShardReport>,
}

/// What a method hands to the finishing step: realised patterns (not necessarily maximal).
#[derive(Default)]
pub(crate) struct Found {
    pub patterns: Vec<Vec<ContactPattern>>,
    pub undecided: Vec<Undecided>,
    /// How a sharded search was split.
    pub shard: Option<ShardReport>,
    /// Witnesses already made on the way ([`leaf::Leaf::witness`]), by pattern: the finishing step
    /// takes them instead of solving its program again.
    pub witnesses: HashMap<Vec<ContactPattern>, Support>,
    /// Every realised pattern without grazing nodes has been handed on already (`bnb`'s
    /// streamed search); `patterns` lists them only for the maximal filter of the others.
    pub streamed: bool,
}

/// A pattern run's outcome (one run, the shards' merge, the groups' products): incomplete when
/// it stopped (`stop`) or left a contact set `undecided` (the patterns below it may be
/// missing), else wedged when it `found` a pattern.
pub(crate) fn outcome_of(stop: Option<Stop>, undecided: bool, found: bool) -> Outcome {
    match stop {
        Some(stop) => Outcome::Incomplete(stop),
        None if undecided => Outcome::Incomplete(Stop::Undecided),
        None if !found => Outcome::NotWedged,
        None => Outcome::Wedged,
    }
}

/// Enumerates the maximal realised sign patterns of a 2D or 3D problem.
pub fn enumerate_patterns(
    problem: &Problem,
    settings: &PatternSettings,
) -> Result<Patterns, EnumerateError> {
    enumerate_patterns_with_control(problem, settings, &|_| {}, &AtomicBool::new(false))
}

/// [`enumerate_patterns`] with progress reports (from the calling thread: `done` out of `total`
/// is the explored fraction of the search, `rays` the realised patterns found so far) and a
/// cancellation flag.
pub fn enumerate_patterns_with_control(
    problem: &Problem,
    settings: &PatternSettings,
    progress: &dyn Fn(Progress),
    cancel: &AtomicBool,
) -> Result<Patterns, EnumerateError> {
    run(problem, settings, progress, cancel, None)
}

/// Where [`enumerate_patterns_streaming`] hands each maximal pattern (from any thread).
pub type PatternSink<'a> = &'a (dyn Fn(Pattern) + Sync);

/// [`enumerate_patterns_with_control`] that hands each maximal pattern, witnessed and checked,
/// to `sink` instead of keeping it: [`Patterns::patterns`] is then empty and
/// [`PatternInfo::streamed`] counts them. `pattern-search` hands each one on as soon as its
/// leaf is decided (each leaf is tested for maximality on its own, see `search.rs`), in the
/// order found, so memory does not grow with the number of pieces; `bnb` (not sharded) hands
/// on each orbit of patterns without grazing nodes as the search meets its first leaf
/// (`bnb.rs`, `Search::stream_leaf`), holding each orbit's state only, and the others at the
/// end; the other methods find
/// their maximal patterns at the end and hand them on then, sorted, as their witnesses are
/// made a chunk at a time (the realised patterns and the orbits' least witnesses are held
/// until then, not every witnessed pattern). A run that stops early has
/// handed on the patterns found so far (it is marked incomplete, as without a sink).
pub fn enumerate_patterns_streaming(
    problem: &Problem,
    settings: &PatternSettings,
    progress: &dyn Fn(Progress),
    cancel: &AtomicBool,
    sink: PatternSink,
) -> Result<Patterns, EnumerateError> {
    run(problem, settings, progress, cancel, Some(sink))
}

fn run(
    problem: &Problem,
    settings: &PatternSettings,
    progress: &dyn Fn(Progress),
    cancel: &AtomicBool,
    sink: Option<PatternSink>,
) -> Result<Patterns, EnumerateError> {
    check_zero_tol(settings.zero_tol)?;
    if problem.is_floating() {
        let certify = floating_certify_refusal(problem.dim(), settings.certify);
        if let Some(why) = floating_refusal(settings.method).or(certify) {
            return Err(EnumerateError::InvalidSettings(why));
        }
    }
    match settings.method {
        PatternMethod::Faces if problem.nodes() > FACES_MAX_NODES => {
            return Err(EnumerateError::InvalidSettings(format!(
                "the pattern-faces method tries all 2^m contact sets; m = {} is more than its \
                 limit of {FACES_MAX_NODES} (use bnb)",
                problem.nodes()
            )))
        }
        PatternMethod::Pyramid { faces } => check_faces(faces)?,
        PatternMethod::Search if problem.dim() != 2 => {
            return Err(EnumerateError::InvalidSettings(format!(
                "the pattern-search method is 2D (its friction cones are polyhedral); this \
                 problem is {}D (use bnb)",
                problem.dim()
            )))
        }
        _ => {}
    }
    if settings.shard.is_some()
        && !matches!(settings.method, PatternMethod::Bnb | PatternMethod::Search)
    {
        return Err(EnumerateError::InvalidSettings(format!(
            "shards split a search tree (the methods bnb and pattern-search); the {} method \
             has none",
            settings.method.name()
        )));
    }
    if settings.shard.is_none() {
        let groups = crate::groups::uncoupled_groups(problem);
        if groups.len() > 1 {
            return groups::by_groups(problem, settings, &groups, progress, cancel, sink);
        }
    }
    let start = Instant::now();
    // The search runs in per-node units that bring K's diagonal near 1 (exactly equivalent, see
    // Problem::equilibrated); each witness is mapped back and checked again at the end.
    let original = problem;
    let (scaled, scales) = problem.equilibrated();
    let problem = &scaled;
    let control = Control::new(settings.limits, cancel);
    let mut form = Formulation::new(problem);
    if settings.certify {
        form.refutations = Some(std::sync::Mutex::new(Vec::new()));
        let checker = crate::conic::refutation::Checker::new(problem);
        form.checker = Some(Box::new(move |f| checker.check(f)));
    }
    let mut info = PatternInfo::default();
    // A maximal pattern witnessed (in the search's units), mapped back to the problem's units
    // and checked there: the reported pattern and the scaled one (for the certificate).
    let witness_lp = simplex_witness(&form).then(|| ContactLp::new(&form));
    // `known`: the pattern's witness, when the search made it already.
    let in_units = |p: Pattern| {
        let (u, r) = original.unscale(&scales, &p.u, &p.r);
        crate::solution::check_solution(original, original.mu(), &u, &r)
            .map_err(|why| format!("the witness in the problem's own units: {why}"))?;
        Ok((Pattern { u, r, ..p.clone() }, p))
    };
    let finish_checked = |q: &[ContactPattern], known: Option<&Support>| {
        finish(&form, witness_lp.as_ref(), q, known).and_then(in_units)
    };
    let failed = |q: &[ContactPattern], reason: String| Undecided {
        contact: contact_set(q),
        reason,
    };
    // pattern-search hands on each maximal pattern as it is found: kept for the finishing
    // step, or witnessed and streamed (not with --certify, where it returns every leaf's
    // pattern and the finishing step below streams the maximal ones).
    let kept = std::sync::Mutex::new((Vec::new(), HashMap::new()));
    let streamed = AtomicU64::new(0);
    let unfinished = std::sync::Mutex::new(Vec::new());
    // In 3D (a clamped body) the patterns of one orbit of the problem's symmetries share the
    // witness of the orbit's least pattern, mapped (`orbits::Group`): one cone program an orbit.
    let group = orbits::Group::of(&form);
    let map_witness = |q: &[ContactPattern], k: usize, (_, least): &(Pattern, Pattern)| {
        let (r, status) = (
            group.map_point(k, &least.r),
            group.map_nodes(k, &least.status),
        );
        let u = form.problem.displacement(&r);
        check_witness(&form, q, &status, &u, &r)?;
        let pattern = q.to_vec();
        in_units(Pattern {
            pattern,
            status,
            u,
            r,
            ..least.clone()
        })
    };
    // A pattern finished as it was found: to the sink, or listed as undecided.
    let hand_on =
        |sink: PatternSink, q: &[ContactPattern], finished: Result<(Pattern, _), _>| match finished
        {
            Ok((p, _)) => {
                streamed.fetch_add(1, Ordering::Relaxed);
                sink(p)
            }
            Err(reason) => unfinished
                .lock()
                .expect("no panics while held")
                .push(failed(q, reason)),
        };
    // bnb's streamed search hands on each orbit of patterns without grazing nodes as its first
    // leaf is decided: witnessed by orbit as below and handed to the sink at once.
    let stream_mapped = AtomicU64::new(0);
    let emit_orbit = |members: Vec<Vec<ContactPattern>>,
                      least: Vec<ContactPattern>,
                      witness: Option<Support>| {
        let Some(sink) = sink else { return };
        let known = |q: &[ContactPattern]| witness.as_ref().filter(|_| q == least);
        let finish_one = |q: &[ContactPattern]| finish_checked(q, known(q));
        let n = orbits::finish_by_orbits(&group, &members, false, finish_one, map_witness, {
            |q, finished| hand_on(sink, q, finished)
        });
        stream_mapped.fetch_add(n, Ordering::Relaxed);
    };
    let emit = |q: Vec<ContactPattern>, witness: Option<Support>| match sink {
        None => {
            let mut kept = kept.lock().expect("no panics while held");
            if let Some(w) = witness {
                kept.1.insert(q.clone(), w);
            }
            kept.0.push(q)
        }
        Some(sink) => hand_on(sink, &q, finish_checked(&q, witness.as_ref())),
    };
    let found = if control.must_stop(0) {
        Found::default()
    } else {
        match settings.method {
            PatternMethod::Bnb => {
                let stream = sink.is_some().then_some(&emit_orbit as bnb::OrbitSink);
                bnb::run(&form, &mut info, settings.shard, progress, &control, stream)
            }
            PatternMethod::Faces => faces::run(&form, &mut info, &control),
            PatternMethod::Search => {
                let mut found =
                    search::run(&form, &mut info, settings.shard, progress, &control, &emit);
                let (patterns, witnesses) = kept.into_inner().expect("no panics while held");
                found.patterns.extend(patterns);
                found.witnesses.extend(witnesses);
                found
            }
            PatternMethod::Pyramid { faces } => pyramid::run(
                &form,
                faces,
                settings.zero_tol,
                &mut info,
                progress,
                &control,
            ),
        }
    };
    // pattern-search counts its leaves' patterns itself (maximal or not).
    info.realised = info.realised.max(found.patterns.len() as u64);
    let shard = found.shard;
    let known = found.witnesses;
    let mut patterns = Vec::new();
    // The witnesses in the units the search ran in, for the certificate.
    let mut scaled = Vec::new();
    let mut undecided = found.undecided;
    undecided.extend(unfinished.into_inner().unwrap_or_default());
    // Each witness is one cone program: they run in parallel (in order; one at a time with
    // --certify, whose refutations are recorded as they are made), by orbit (`group` above).
    let mut pieces = maximal(found.patterns);
    if found.streamed {
        pieces.retain(|q| q.contains(&ContactPattern::Grazing));
    }
    // The answers in the order of `pieces` (sorted by pattern, as `maximal` leaves them), a
    // chunk at a time: kept, or handed to the sink at once.
    let mapped = orbits::finish_by_orbits(
        &group,
        &pieces,
        settings.certify,
        |q| finish_checked(q, known.get(q)),
        map_witness,
        |q, finished| match finished {
            Ok((p, s)) => {
                if settings.certify {
                    scaled.push(s);
                }
                match sink {
                    Some(sink) => {
                        streamed.fetch_add(1, Ordering::Relaxed);
                        sink(p);
                    }
                    None => patterns.push(p),
                }
            }
            Err(reason) => undecided.push(failed(q, reason)),
        },
    );
    info.mapped += mapped + stream_mapped.into_inner();
    patterns.sort_by(|a, b| a.pattern.cmp(&b.pattern));
    info.streamed = streamed.into_inner();
    let c = &form.counters;
    info.socps = Counters::get(&c.socps);
    info.retries = Counters::get(&c.retries);
    info.uncertain = Counters::get(&c.uncertain);
    info.near_degenerate = Counters::get(&c.near_degenerate);
    let found = !patterns.is_empty() || info.streamed > 0;
    let outcome = outcome_of(control.stopped(), !undecided.is_empty(), found);
    let certificate = settings.certify.then(|| {
        let complete = !matches!(outcome, Outcome::Incomplete(_));
        certify::certify(&mut form, settings.method, &scaled, complete)
    });
    info.seconds = start.elapsed().as_secs_f64();
    Ok(Patterns {
        outcome,
        patterns,
        undecided,
        info,
        certificate,
        shard,
    })
}

/// Why a floating body is refused by a pattern method: `None` when it applies. (`bnb`,
/// `pattern-faces` and `pattern-search` carry the rigid amplitudes in every program, and
/// `--certify` checks them exactly; `pyramid` runs on a double description written for a
/// clamped body.)
pub fn floating_refusal(method: PatternMethod) -> Option<String> {
    match method {
        PatternMethod::Pyramid { .. } => Some(format!(
            "--method {} is written for a clamped body; this body floats: use --method \
             pattern-search (2D), bnb or pattern-faces",
            method.name()
        )),
        _ => None,
    }
}

/// Why `--certify` is refused for a floating body of dimension `dim`: in 3D. Its exact
/// checks take the rigid modes as stored (`conic::refutation::Compliance`), and in 3D two
/// pressed nodes balance only to round-off (the turn about the line through them does work on
/// their reactions as stored), so a witness of such a piece has no exact state and the run
/// could not be certified; in 2D the checks apply.
pub fn floating_certify_refusal(dim: usize, certify: bool) -> Option<String> {
    (certify && dim == 3).then(|| {
        "--certify is not available for a 3D floating body (its rigid modes, rounded, leave \
         the witnesses of some pieces without an exact state); 2D floating bodies are \
         certified: drop --certify"
            .to_string()
    })
}

/// The candidates of the pyramid method with `faces` faces, before they are checked: the
/// maximal patterns of the polyhedral approximation (a diagnostic, and the test of how the
/// approximation tightens as `faces` grows).
pub fn pyramid_candidates(
    problem: &Problem,
    faces: usize,
    zero_tol: f64,
) -> Result<Vec<Vec<ContactPattern>>, EnumerateError> {
    if problem.dim() == 3 {
        check_faces(faces)?;
    }
    let cancel = AtomicBool::new(false);
    let control = Control::new(Limits::default(), &cancel);
    Ok(pyramid::candidates(problem, faces, zero_tol, &|_| {}, &control).0)
}

/// The range of the pyramid's faces.
fn check_faces(faces: usize) -> Result<(), EnumerateError> {
    if (3..=64).contains(&faces) {
        Ok(())
    } else {
        Err(EnumerateError::InvalidSettings(format!(
            "the pyramid needs 3 to 64 faces, got {faces}"
        )))
    }
}

/// The classes of the cone `F_q` of a pattern.
pub(crate) fn classes_of(q: &[ContactPattern]) -> Vec<Class> {
    q.iter()
        .map(|c| match c {
            ContactPattern::Contact => Class::Contact,
            ContactPattern::Separated => Class::Separated,
            ContactPattern::Grazing => Class::Grazing,
        })
        .collect()
}

/// The entries a pattern says are positive.
pub(crate) fn positives(q: &[ContactPattern]) -> Vec<Entry> {
    q.iter()
        .enumerate()
        .filter_map(|(i, c)| match c {
            ContactPattern::Contact => Some(Entry::Press(i)),
            ContactPattern::Separated => Some(Entry::Gap(i)),
            ContactPattern::Grazing => None,
        })
        .collect()
}

/// The pattern of a support: contact where pressed, separated where the gap opens.
pub(crate) fn pattern_of(m: usize, support: &[Entry]) -> Vec<ContactPattern> {
    let mut q = vec![ContactPattern::Grazing; m];
    for e in support {
        match *e {
            Entry::Press(i) => q[i] = ContactPattern::Contact,
            Entry::Gap(i) => q[i] = ContactPattern::Separated,
            Entry::Stick(_) => {}
        }
    }
    q
}

/// The witness of a maximal realised pattern: the nodes that can stick are found, then one
/// solution makes every positive entry and every stick slack positive at once; it is checked
/// against WP before it is returned.
///
/// In 2D (a clamped body) the programs are the simplex method's (`lp`,
/// [`ContactLp::witness`]; its witness is a vertex of the optimal set, the value the same), and
/// Clarabel's when it cannot decide. (Measured: on a random m = 9 problem the witnesses' cone
/// programs were about a quarter of the whole process.)
fn finish(
    form: &Formulation,
    lp: Option<&ContactLp>,
    q: &[ContactPattern],
    known: Option<&Support>,
) -> Result<Pattern, String> {
    let classes = classes_of(q);
    let wanted = positives(q);
    let all = witness_entries(q);
    let Support {
        entries: support,
        r,
        value: margin,
    } = match known {
        Some(known) if all.iter().all(|e| known.entries.contains(e)) => Some(known.clone()),
        _ => match lp.map(|lp| lp.witness(&classes, &all)) {
            Some(Ok(support)) => support,
            _ => form.support(&classes, &all)?,
        },
    }
    .ok_or("a realised pattern's cone has become trivial")?;
    if !wanted.iter().all(|e| support.contains(e)) {
        return Err(format!(
            "the pattern is not realised when stick is asked for too (reached {margin:e})"
        ));
    }
    let status: Vec<NodeStatus> = (0..form.m)
        .map(|i| match q[i] {
            ContactPattern::Separated => NodeStatus::Separated,
            ContactPattern::Grazing => NodeStatus::Grazing,
            ContactPattern::Contact if support.contains(&Entry::Stick(i)) => NodeStatus::Stick,
            ContactPattern::Contact if form.dim == 3 => NodeStatus::Slip,
            ContactPattern::Contact if r[2 * i + 1] > 0.0 => NodeStatus::SlipPlus,
            ContactPattern::Contact => NodeStatus::SlipMinus,
        })
        .collect();
    let u = form.problem.displacement(&r);
    check_witness(form, q, &status, &u, &r)?;
    // A floating body's point ends with its rigid amplitudes, now in `u`.
    let mut r = r;
    r.truncate(form.dim * form.m);
    Ok(Pattern {
        pattern: q.to_vec(),
        status,
        u,
        r,
        margin,
    })
}

/// The contact set of a pattern: its nodes in contact (the inverse of [`whole_pattern`]).
pub(super) fn contact_set(q: &[ContactPattern]) -> Vec<bool> {
    q.iter().map(|&c| c == ContactPattern::Contact).collect()
}

/// The pattern of a leaf whose contact set is `contact` when every node of it is pressed and
/// every other gap opens (the first thing a leaf asks; [`leaf_pattern`], `search.rs`).
pub(super) fn whole_pattern(contact: &[bool]) -> Vec<ContactPattern> {
    contact
        .iter()
        .map(|&c| match c {
            true => ContactPattern::Contact,
            false => ContactPattern::Separated,
        })
        .collect()
}

/// The entries a witness of the pattern `q` pushes up together ([`finish`]): its positive
/// entries, then the stick slack of each contact node.
pub(super) fn witness_entries(q: &[ContactPattern]) -> Vec<Entry> {
    let mut all = positives(q);
    all.extend(
        (0..q.len())
            .filter(|&i| q[i] == ContactPattern::Contact)
            .map(Entry::Stick),
    );
    all
}

/// The relative accuracy a witness must meet: equalities within it (relative to the terms they
/// sum), positive entries above [`POSITIVE`] (they were pushed up to at least that).
const WITNESS_TOL: f64 = 1e-6;

/// Checks a witness against WP: equilibrium `K u = r`, normalisation, `u_n >= 0`, friction,
/// complementarity and every claimed status.
pub(crate) fn check_witness(
    form: &Formulation,
    q: &[ContactPattern],
    status: &[NodeStatus],
    u: &[f64],
    r: &[f64],
) -> Result<(), String> {
    let (d, m) = (form.dim, form.m);
    check_balance(form.problem, u, r, WITNESS_TOL)?;
    let u_scale = u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for i in 0..m {
        let (un, rn) = (u[d * i], r[d * i]);
        let gap = form.gap_of(r, i);
        let slack = form.slack_of(r, i);
        let r_norm = r[d * i..d * i + d]
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        let un_zero = un.abs() <= WITNESS_TOL * u_scale;
        let fail = |what: &str| {
            Err(format!(
                "node {}: {what} (u_n = {un:e}, r_n = {rn:e}, friction slack {slack:e})",
                i + 1
            ))
        };
        if slack < -WITNESS_TOL {
            return fail("outside the friction cone");
        }
        if un < -WITNESS_TOL * u_scale {
            return fail("penetrates the obstacle");
        }
        let ok = match (q[i], status[i]) {
            (ContactPattern::Separated, NodeStatus::Separated) => {
                r_norm == 0.0 && gap > POSITIVE * 0.5
            }
            (ContactPattern::Grazing, NodeStatus::Grazing) => r_norm == 0.0 && un_zero,
            (ContactPattern::Contact, s) => {
                let pressed = un_zero && rn > POSITIVE * 0.5;
                let stick = slack > POSITIVE * 0.5;
                pressed
                    && match s {
                        NodeStatus::Stick => stick,
                        NodeStatus::Slip | NodeStatus::SlipPlus | NodeStatus::SlipMinus => true,
                        _ => false,
                    }
            }
            _ => false,
        };
        if !ok {
            return fail(&format!(
                "claimed {} is not what the witness shows",
                status[i].name()
            ));
        }
    }
    Ok(())
}

/// Whether [`finish`] makes its witnesses by the simplex method: 2D, a clamped body.
pub(super) fn simplex_witness(form: &Formulation) -> bool {
    form.dim == 2 && form.modes == 0
}
