//! `bnb`'s start on a large problem with none given: the problem condensed onto about half its
//! nodes, solved first (itself so while large enough), its wedge spread back over the dropped
//! nodes as the search's first contact set ([`super::CriticalSettings::start`]).
//!
//! The nodes kept are a greedy independent set of the graph that joins each node to the
//! [`NEIGHBOURS`] nodes `K` couples it to most strongly (`|K_ij| / sqrt(|K_ii| |K_jj|)`, block
//! Frobenius norms: unchanged by a node's scale or a flipped tangent; not weaker than
//! [`STRONG`] times its strongest). On a body's contact surface these are its neighbours on
//! the surface, so about every other node is kept, without any geometry. The condensed
//! stiffness is the Schur complement of `K` on the kept nodes, the dropped ones free of
//! contact constraints; a dropped node starts in contact where the condensed wedge moves it
//! onto the obstacle or into it ([`spread`]).
//!
//! The search's own first leaf (its rounded root improved by local search) can stop far above
//! `mu*` on a fine mesh, and the tree is then searched at that level: the Gmsh plug of second
//! order at m = 128 took 91 s and 1.14M nodes from scratch, 5 s from the condensed start with
//! the same bracket. It needs no coarser mesh: a Gmsh mesh file, a condensed stiffness and a
//! matrix from Python start alike, and it did better than the coarser mesh it replaced (the
//! command solved the generated body with half the divisions first): the generated plug at m =
//! 100 0.79 s against 0.84 s, m = 200 13.4 s against 15.2 s, m = 400 246 s against 280 s
//! (`BENCHMARKS.md`). The bracket does not depend on the start: only the time does.

use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use nalgebra::DMatrix;

use super::{critical_with_control, CriticalMethod, CriticalProgress, CriticalSettings};
use crate::problem::Problem;
use crate::run::{EnumerateError, Stop};
use crate::solution::ContactPattern;

/// 2D problems of this many nodes or more start from their condensed problem. (The coarser
/// mesh that the command used to start from, measured on 2026-11-29: m = 50 no gain, m = 100
/// 0.81 paired.)
pub(crate) const CONDENSE_FROM: usize = 80;
/// The same in 3D.
pub(crate) const CONDENSE_FROM_3D: usize = 40;
/// Each node's strongest couplings that join it to its neighbours: two along a 2D body's
/// contact line. (In 3D too: on the V-groove plug at m = 40, four kept 10 nodes, a start no
/// better than the dive's; two kept 22.)
const NEIGHBOURS: usize = 2;

/// A node's [`NEIGHBOURS`] join it only where coupled at least this share of its strongest
/// coupling: the last node of the plug's side, beside the clamp, has one neighbour (0.41), and
/// its next coupling (0.015, two nodes on) must not keep it from being kept.
const STRONG: f64 = 0.25;

/// What the condensed problem gave: the start and how it was found.
#[derive(Debug, Clone)]
pub(crate) struct Condensed {
    /// One entry per node of the problem, `true` in contact.
    pub start: Vec<bool>,
    /// The condensed problem's nodes.
    pub nodes: usize,
    /// Its `mu*` (its upper end where its run stopped early).
    pub mu: f64,
    /// The seconds its run took.
    pub seconds: f64,
}

/// Whether a run of `settings` on `problem` starts from its condensed problem: `bnb` with no
/// start, not certified, not a shard, not a floating body, from [`CONDENSE_FROM`] nodes
/// ([`CONDENSE_FROM_3D`] in 3D).
pub(crate) fn applies(problem: &Problem, settings: &CriticalSettings) -> bool {
    settings.condense
        && settings.method == CriticalMethod::Bnb
        && !settings.certify
        && settings.shard.is_none()
        && settings.start.is_none()
        && !problem.is_floating()
        && problem.nodes()
            >= match problem.dim() {
                2 => CONDENSE_FROM,
                _ => CONDENSE_FROM_3D,
            }
}

/// Where [`applies`], the condensed problem's answer ([`start`]) and `settings` starting from
/// it, their time limit what the condensed run (begun at `began`) left of it.
pub(crate) fn started(
    problem: &Problem,
    settings: &CriticalSettings,
    progress: &dyn Fn(CriticalProgress),
    cancel: &AtomicBool,
    began: Instant,
) -> Result<(Option<Condensed>, Option<CriticalSettings>), EnumerateError> {
    if !applies(problem, settings) {
        return Ok((None, None));
    }
    let Some(condensed) = start(problem, settings, progress, cancel)? else {
        return Ok((None, None));
    };
    let mut own = settings.clone();
    own.start = Some(condensed.start.clone());
    let limits = &mut own.limits;
    limits.time_limit = limits.time_limit.map(|l| l.saturating_sub(began.elapsed()));
    Ok((Some(condensed), Some(own)))
}

/// A run stopped by its time limit names the limit `given`, not what the condensed run left.
pub(crate) fn given_limit(stop: Option<Stop>, given: Option<Duration>) -> Option<Stop> {
    match (stop, given) {
        (Some(Stop::TimeLimit(_)), Some(limit)) => Some(Stop::TimeLimit(limit)),
        (stop, _) => stop,
    }
}

/// The start of `problem` from its condensed problem, run with `settings` (no start; the time
/// limit what is left of it) and `cancel`; `None` where that run found no wedge. A failure of
/// the condensed run that is a bug is returned as such. That run's progress goes to `progress`
/// marked with the condensed problem's nodes ([`CriticalProgress::condensed`]), so that a
/// long start (about 11 s of 250 at m = 400) shows where it is.
pub(crate) fn start(
    problem: &Problem,
    settings: &CriticalSettings,
    progress: &dyn Fn(CriticalProgress),
    cancel: &AtomicBool,
) -> Result<Option<Condensed>, EnumerateError> {
    let began = Instant::now();
    let kept = keep(problem);
    let Some((k, follow)) = condense(problem, &kept) else {
        return Ok(None);
    };
    let Ok(small) = Problem::new(problem.dim(), k, problem.mu()) else {
        return Ok(None);
    };
    let mut sub = settings.clone();
    sub.start = None;
    // A test's injected fault is the run's own, not its start's.
    sub.fault = None;
    // The condensed run's own start reports the smaller problem, which it runs first.
    let nodes = small.nodes();
    let marked = |p: CriticalProgress| {
        progress(CriticalProgress {
            condensed: Some(p.condensed.unwrap_or(nodes)),
            ..p
        })
    };
    let result = match critical_with_control(&small, &sub, &marked, cancel) {
        Ok(result) => result,
        Err(e @ EnumerateError::Internal(_)) => return Err(e),
        Err(_) => return Ok(None),
    };
    let (Some(witness), Some(mu)) = (result.witness, result.upper) else {
        return Ok(None);
    };
    let closed: Vec<bool> = witness
        .pattern
        .iter()
        .map(|&p| p != ContactPattern::Separated)
        .collect();
    let start = spread(problem.dim(), &kept, &closed, &witness.u, &follow);
    Ok(start.contains(&true).then(|| Condensed {
        start,
        nodes: kept.len(),
        mu,
        seconds: began.elapsed().as_secs_f64(),
    }))
}

/// The strength of the coupling of each pair of nodes: `|K_ij| / sqrt(|K_ii| |K_jj|)` with
/// block Frobenius norms, 0 on the diagonal.
fn coupling(problem: &Problem) -> DMatrix<f64> {
    let (d, m) = (problem.dim(), problem.nodes());
    let k = problem.stiffness();
    let block = |i: usize, j: usize| k.view((d * i, d * j), (d, d)).norm();
    let own: Vec<f64> = (0..m).map(|i| block(i, i).sqrt()).collect();
    DMatrix::from_fn(m, m, |i, j| {
        if i == j {
            0.0
        } else {
            block(i, j) / (own[i] * own[j])
        }
    })
}

/// The nodes kept, ascending.
fn keep(problem: &Problem) -> Vec<usize> {
    let m = problem.nodes();
    let c = coupling(problem);
    // The strongest partners first; ties by index, so that the order is deterministic.
    let ranked = |i: usize| {
        let mut others: Vec<usize> = (0..m).filter(|&j| j != i).collect();
        others.sort_by(|&a, &b| c[(i, b)].total_cmp(&c[(i, a)]).then(a.cmp(&b)));
        others
    };
    let mut joined = vec![Vec::new(); m];
    for i in 0..m {
        let top = ranked(i);
        let strongest = top.first().map_or(0.0, |&j| c[(i, j)]);
        for j in top.into_iter().take(NEIGHBOURS) {
            if c[(i, j)] >= STRONG * strongest {
                joined[i].push(j);
                joined[j].push(i);
            }
        }
    }
    let mut taken = vec![false; m];
    let mut blocked = vec![false; m];
    for i in 0..m {
        if !blocked[i] {
            taken[i] = true;
            for &j in &joined[i] {
                blocked[j] = true;
            }
        }
    }
    (0..m).filter(|&i| taken[i]).collect()
}

/// The Schur complement of `K` on the `kept` nodes (the others free: `K_kk - K_kd K_dd^-1
/// K_dk`), symmetrised, and `K_dd^-1 K_dk` (the dropped nodes' displacements are `-K_dd^-1
/// K_dk u_k`); `None` where nothing is dropped or `K_dd` fails its Cholesky factorisation.
fn condense(problem: &Problem, kept: &[usize]) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let (d, m) = (problem.dim(), problem.nodes());
    let dofs = |nodes: &[usize]| -> Vec<usize> {
        nodes
            .iter()
            .flat_map(|&i| (0..d).map(move |c| d * i + c))
            .collect()
    };
    let dropped: Vec<usize> = (0..m).filter(|i| kept.binary_search(i).is_err()).collect();
    if dropped.is_empty() || kept.is_empty() {
        return None;
    }
    let (a, b) = (dofs(kept), dofs(&dropped));
    let k = problem.stiffness();
    let part = |rows: &[usize], cols: &[usize]| {
        DMatrix::from_fn(rows.len(), cols.len(), |i, j| k[(rows[i], cols[j])])
    };
    let k_ab = part(&a, &b);
    let follow = part(&b, &b).cholesky()?.solve(&k_ab.transpose());
    let s = part(&a, &a) - &k_ab * &follow;
    Some(((&s + s.transpose()) * 0.5, follow))
}

/// The start on all nodes: a kept node's contact as the condensed wedge's pattern `closed`
/// says; a dropped node in contact where that wedge (displacements `u_k` of the kept nodes)
/// moves it onto the obstacle or into it: `u_d = -K_dd^-1 K_dk u_k` (`follow` the matrix
/// `K_dd^-1 K_dk`), its normal part at most `1e-9` of the largest of the kept nodes'. (The
/// first rule tried, in contact where its two most strongly coupled kept nodes are, closed
/// whole stretches where the wedge of the 2D triangle plug alternates between contact and gap,
/// and at m = 80 that start had no leaf: 267 nodes and 1.0 s against 3 and 0.49 s.)
fn spread(
    dim: usize,
    kept: &[usize],
    closed: &[bool],
    u_k: &[f64],
    follow: &DMatrix<f64>,
) -> Vec<bool> {
    let u_d = -(follow * DMatrix::from_column_slice(u_k.len(), 1, u_k));
    let scale = u_k.iter().step_by(dim).fold(0.0f64, |a, v| a.max(v.abs()));
    let m = kept.len() + u_d.nrows() / dim;
    let mut dropped = 0;
    (0..m)
        .map(|i| match kept.binary_search(&i) {
            Ok(q) => closed[q],
            Err(_) => {
                dropped += 1;
                u_d[(dim * (dropped - 1), 0)] <= 1e-9 * scale
            }
        })
        .collect()
}

#[cfg(test)]
mod tests;
