//! Groups of contact nodes that `K` does not couple (separate bodies condensed into one
//! problem, or a matrix assembled so), for the searches that take them apart: `mu*` is the
//! least of the groups' (`critical/groups.rs`), and the maximal pieces are the products of
//! the groups' (`patterns/groups.rs`).
//!
//! The groups are found from exact zeros only (a coupling of 1e-300 is a coupling), so no
//! answer rests on a judgement of what is small. A floating body is one group: its rigid modes
//! couple nodes that `K` may not.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use nalgebra::DMatrix;

use crate::problem::Problem;
use crate::run::{EnumerateError, Limits, Stop};

/// The groups of nodes that `K` couples: the connected components of the graph with an edge
/// between two nodes whose block of `K` has a nonzero entry, each group in increasing order,
/// the groups by their first node. One group for a floating body.
pub(crate) fn uncoupled_groups(problem: &Problem) -> Vec<Vec<usize>> {
    let (d, m) = (problem.dim(), problem.nodes());
    if problem.is_floating() || m == 0 {
        return vec![(0..m).collect()];
    }
    let k = problem.stiffness();
    let mut root: Vec<usize> = (0..m).collect();
    fn find(root: &mut [usize], mut i: usize) -> usize {
        while root[i] != i {
            root[i] = root[root[i]];
            i = root[i];
        }
        i
    }
    for i in 0..m {
        for j in i + 1..m {
            let coupled = (0..d).any(|a| (0..d).any(|b| k[(d * i + a, d * j + b)] != 0.0));
            if coupled {
                let (a, b) = (find(&mut root, i), find(&mut root, j));
                root[a.max(b)] = a.min(b);
            }
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut index = vec![usize::MAX; m];
    for i in 0..m {
        let r = find(&mut root, i);
        if index[r] == usize::MAX {
            index[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[index[r]].push(i);
    }
    groups
}

/// The problem of the nodes `nodes` alone (their block of `K`, the same `mu`).
pub(crate) fn restricted(problem: &Problem, nodes: &[usize]) -> Result<Problem, EnumerateError> {
    let d = problem.dim();
    let n = d * nodes.len();
    let at = |a: usize| nodes[a / d] * d + a % d;
    let k = problem.stiffness();
    let block = DMatrix::from_fn(n, n, |i, j| k[(at(i), at(j))]);
    Problem::new(d, block, problem.mu())
        .map_err(|e| EnumerateError::Internal(format!("a group of uncoupled contact nodes: {e}")))
}

/// A group's contact set (one entry per node of `group`) on the whole problem's `m` nodes,
/// the other nodes not in contact.
pub(crate) fn spread_contact(group: &[usize], m: usize, contact: &[bool]) -> Vec<bool> {
    let mut whole = vec![false; m];
    for (a, &i) in group.iter().enumerate() {
        whole[i] = contact[a];
    }
    whole
}

/// Before the next group's search: the time it has left of `limits` since `clock`, or why the
/// run stops first (the cancel flag, or no time left).
pub(crate) fn time_for_next(
    limits: &Limits,
    clock: &Instant,
    cancel: &AtomicBool,
) -> Result<Option<Duration>, Stop> {
    if cancel.load(Ordering::Relaxed) {
        return Err(Stop::Interrupted);
    }
    match limits.time_limit {
        Some(limit) => {
            let left = limit.saturating_sub(clock.elapsed());
            if left.is_zero() {
                Err(Stop::TimeLimit(limit))
            } else {
                Ok(Some(left))
            }
        }
        None => Ok(None),
    }
}
