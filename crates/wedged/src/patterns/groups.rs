//! The maximal patterns of a problem whose contact nodes fall into groups that `K` does not
//! couple ([`crate::groups::uncoupled_groups`]): the products of the groups' own.
//!
//! **Why it holds.** With `K` block diagonal over the groups, a solution of WP is a solution
//! of each group's problem on its nodes, and any solutions of the groups' problems side by side
//! are one of the whole (a group's reactions open no gap at another's nodes). So the set of
//! wedged configurations is the product of the groups' sets, each with its trivial solution
//! `0`, and its maximal convex pieces are the products of one maximal piece of each group, or
//! of `{0}` (every node grazing) for a group that never wedges; the product of `{0}`s alone is
//! the trivial solution, not a piece. A product's pattern is its factors' side by side; its
//! witness is the factors' witnesses added (each with `sum r_n = 1`) and scaled to `sum r_n =
//! 1`, which lies in the product's relative interior, and is checked against the whole problem
//! before it is reported. Its margin is the least of its factors', scaled alike.
//!
//! **Why it pays.** The whole search meets every combination of the groups' pieces on its way:
//! the 2D plug's stiffness at m = 50 and at m = 20 side by side (575 pieces = 115 x 5) took
//! 76 s as one `pattern-search`, against 0.30 s and 7 ms for the two alone (`BENCHMARKS.md`).
//!
//! Not for a shard (every process must split the same tree). With `--certify` each group's
//! search is certified exactly; the products follow from the exact zeros between the groups.

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use super::certify::PatternCertificate;
use super::{Pattern, PatternInfo, PatternSettings, PatternSink, Patterns, Undecided};
use crate::groups::{restricted, spread_contact, time_for_next};
use crate::problem::Problem;
use crate::rays::Progress;
use crate::run::{EnumerateError, Outcome, Stop};
use crate::solution::{check_solution, ContactPattern, NodeStatus};

/// [`super::enumerate_patterns_with_control`] (or its streaming form, with `sink`) on each
/// group of `groups` (more than one), the products of their maximal patterns reported (see the
/// module docs). A stop (time limit, Ctrl-C) leaves the groups not yet searched without
/// patterns, so the products reported are those of the patterns found so far (none when a
/// group was not reached), marked incomplete.
pub(super) fn by_groups(
    problem: &Problem,
    settings: &PatternSettings,
    groups: &[Vec<usize>],
    progress: &dyn Fn(Progress),
    cancel: &AtomicBool,
    sink: Option<PatternSink>,
) -> Result<Patterns, EnumerateError> {
    let clock = Instant::now();
    let (d, m) = (problem.dim(), problem.nodes());
    let mut parts: Vec<Patterns> = Vec::with_capacity(groups.len());
    let mut stop: Option<Stop> = None;
    for nodes in groups {
        let left = match time_for_next(&settings.limits, &clock, cancel) {
            Ok(left) => left,
            Err(s) => {
                stop = stop.or(Some(s));
                break;
            }
        };
        let sub = restricted(problem, nodes)?;
        let mut own = settings.clone();
        own.limits.time_limit = left;
        let part = super::run(&sub, &own, progress, cancel, None)?;
        if let Outcome::Incomplete(s) = part.outcome {
            stop = stop.or(Some(s));
        }
        parts.push(part);
    }

    let mut info = PatternInfo {
        groups: groups.len() as u64,
        ..PatternInfo::default()
    };
    let mut undecided = Vec::new();
    let mut certificate: Option<PatternCertificate> = None;
    for (g, part) in parts.iter().enumerate() {
        super::merge::add_info(&mut info, &part.info);
        undecided.extend(part.undecided.iter().map(|u| Undecided {
            contact: spread_contact(&groups[g], m, &u.contact),
            reason: u.reason.clone(),
        }));
        if let Some(c) = &part.certificate {
            let sum = certificate.get_or_insert_with(|| PatternCertificate {
                certified: true,
                witnesses_checked: 0,
                witnesses_failed: 0,
                refutations_checked: 0,
                refutations_failed: 0,
                doubts: 0,
                failures: Vec::new(),
            });
            sum.certified &= c.certified;
            sum.witnesses_checked += c.witnesses_checked;
            sum.witnesses_failed += c.witnesses_failed;
            sum.refutations_checked += c.refutations_checked;
            sum.refutations_failed += c.refutations_failed;
            sum.doubts += c.doubts;
            let first = groups[g][0] + 1;
            sum.failures.extend(
                c.failures
                    .iter()
                    .map(|f| format!("the group of node {first}: {f}")),
            );
        }
    }
    if let Some(c) = certificate.as_mut() {
        // A group not searched leaves the whole unproven.
        c.certified &= parts.len() == groups.len();
    }

    // Each group's factors: its maximal patterns, or `{0}` (`None`) when it never wedges.
    let factors: Vec<Vec<Option<&Pattern>>> = parts
        .iter()
        .map(|part| match part.outcome {
            Outcome::NotWedged => vec![None],
            _ => part.patterns.iter().map(Some).collect(),
        })
        .collect();
    let mut patterns = Vec::new();
    let mut streamed = 0u64;
    if parts.len() == groups.len() && factors.iter().all(|f| !f.is_empty()) {
        // Every combination, the last group fastest (an odometer).
        let mut at = vec![0usize; factors.len()];
        loop {
            let chosen: Vec<(usize, &Pattern)> = at
                .iter()
                .enumerate()
                .filter_map(|(g, &k)| factors[g][k].map(|p| (g, p)))
                .collect();
            if !chosen.is_empty() {
                let p = product(problem, groups, &chosen, d, m)?;
                match sink {
                    Some(sink) => {
                        streamed += 1;
                        sink(p);
                    }
                    None => patterns.push(p),
                }
            }
            // The next combination.
            let mut g = factors.len();
            loop {
                if g == 0 {
                    break;
                }
                g -= 1;
                at[g] += 1;
                if at[g] < factors[g].len() {
                    break;
                }
                at[g] = 0;
            }
            if at.iter().all(|&k| k == 0) {
                break;
            }
        }
    }
    patterns.sort_by(|a, b| a.pattern.cmp(&b.pattern));
    info.streamed = streamed;
    info.seconds = clock.elapsed().as_secs_f64();
    let found = !patterns.is_empty() || streamed > 0;
    let outcome = super::outcome_of(stop, !undecided.is_empty(), found);
    Ok(Patterns {
        outcome,
        patterns,
        undecided,
        info,
        certificate,
        shard: None,
    })
}

/// The product of the groups' patterns `chosen` (the others `{0}`), its witness checked on the
/// whole problem.
fn product(
    problem: &Problem,
    groups: &[Vec<usize>],
    chosen: &[(usize, &Pattern)],
    d: usize,
    m: usize,
) -> Result<Pattern, EnumerateError> {
    let share = 1.0 / chosen.len() as f64;
    let mut p = Pattern {
        pattern: vec![ContactPattern::Grazing; m],
        status: vec![NodeStatus::Grazing; m],
        u: vec![0.0; d * m],
        r: vec![0.0; d * m],
        margin: f64::INFINITY,
    };
    for &(g, q) in chosen {
        for (a, &i) in groups[g].iter().enumerate() {
            p.pattern[i] = q.pattern[a];
            p.status[i] = q.status[a];
            for c in 0..d {
                p.u[d * i + c] = share * q.u[d * a + c];
                p.r[d * i + c] = share * q.r[d * a + c];
            }
        }
        p.margin = p.margin.min(share * q.margin);
    }
    check_solution(problem, problem.mu(), &p.u, &p.r).map_err(|why| {
        EnumerateError::Internal(format!(
            "the witness of a product of uncoupled groups' patterns failed its check on the \
             whole problem: {why}"
        ))
    })?;
    Ok(p)
}
