//! The rows a solve works on: an **idle** row (free activity, no cost) whose activity is basic
//! can never leave the basis (a free basic variable is never infeasible and never blocks a
//! ratio test), so it changes no pivot and no answer, and the method leaves it out: the basis
//! and its dense inverse cover the **active** rows only ([`Basis::rows`]).
//!
//! The search's programs have many such rows: a drive cut is free once its node is decided,
//! and a pressure row is free unless the node is pressed. On the 2D plug most of a deep node's
//! `3m + 1` rows are idle, and the inverse's updates cost the square of the rows kept.
//!
//! **Loose rows are left out too, and brought back when broken.** A warm start carries the row
//! activities of the optimal point it was left at ([`Basis::activity`]); a row whose activity
//! is basic there, has no cost, and is inside its bounds by more than [`LOOSE`] of them (an
//! open gap, a slack cut) is left out of the child's solve, which then works on a relaxation:
//! an infeasibility certificate of the part is one of the whole (zero multipliers on the rows
//! left out), and an optimal point of the part that meets every row left out ([`violated`]) is
//! optimal for the whole. When it breaks some, they join with their activities basic ([`add`])
//! and the run resumes (the dual method restores them); rows only join within a solve, so it
//! ends. A search node's program changes one node's bounds, and most of its open gaps stay
//! open: on issue 20's plug at m = 80 the rows worked on fell from about 127 to 44 a program
//! (about 1.5 runs a program), and the enumeration from 41-47 s to 27 s. A program whose
//! point moves far from the start's (a bound-tightening program, a new objective) breaks many
//! rows and pays a dual phase for each round, so such starts keep every row
//! ([`Basis::all_rows`]; measured there: 2.5 times the pivots).
//!
//! A start made for other bounds is **adapted** to the program ([`adapt`]): a row that is now
//! idle (or loose) and whose activity is basic is dropped (its basis position and its column
//! of the inverse deleted: the basis matrix has that activity's unit column, so the rest of the
//! inverse is the inverse of the rest), and a row that is no longer idle (nor loose) is added
//! with its activity basic (the inverse gains one row, `a^T B^-1` over the kept positions, and
//! a `-1`): `O(r^2)` per row, against the `O(r^3)` of refactoring. An idle row whose activity
//! is nonbasic stays active until it has entered the basis.
//!
//! The checks of the answers ([`super::check`]) run on the whole program: a point's row
//! activities are all recomputed, a certificate has zero multipliers on the rows left out.

use std::borrow::Cow;
use std::sync::Arc;

use super::dense::dot;
use super::{pool, At, Basis, Lp, TOL};

/// Whether row `k` is idle: free activity, no cost.
fn idle(lp: &Lp, k: usize) -> bool {
    let j = lp.n + k;
    lp.lo[j] == f64::NEG_INFINITY && lp.hi[j] == f64::INFINITY && lp.cost[j] == 0.0
}

/// The slack basis over the rows that are not idle (at least one row, so that the inverse is
/// never empty), in the whole program's numbering.
pub(super) fn slack(lp: &Lp) -> Basis {
    let mut rows: Vec<usize> = (0..lp.rows).filter(|&k| !idle(lp, k)).collect();
    if rows.is_empty() && lp.rows > 0 {
        rows.push(0);
    }
    let r = rows.len();
    let mut inv = pool::zeroed(r * r);
    for k in 0..r {
        inv[k * r + k] = -1.0;
    }
    let mut at = vec![At::Lower; lp.total()];
    for a in &mut at[lp.n..] {
        *a = At::Basic;
    }
    Basis {
        head: rows.iter().map(|&k| lp.n + k).collect(),
        at,
        inv: Some(inv),
        rows,
        activity: Vec::new(),
    }
}

/// Whether row `k` has no cost and its activity at the point a basis was left at
/// (`activity`, empty when unknown) lies inside the row's bounds in `lp` by more than
/// [`LOOSE`] of them: a row that such a start leaves out.
pub(super) fn loose(lp: &Lp, activity: &[f64], k: usize) -> bool {
    if activity.len() != lp.rows || lp.cost[lp.n + k] != 0.0 {
        return false;
    }
    let (v, lo, hi) = (activity[k], lp.lo[lp.n + k], lp.hi[lp.n + k]);
    (lo == f64::NEG_INFINITY || v - lo > LOOSE * (1.0 + lo.abs()))
        && (hi == f64::INFINITY || hi - v > LOOSE * (1.0 + hi.abs()))
}

/// A row is left out of a start when its activity is inside its bounds by more than this share
/// of them (see the module docs). (Measured on issue 20's plug, `enumerate`, m = 60: 1e-7,
/// 1e-3, 1e-2, 5e-2, 0.2 with bound-tightening programs leaving rows out too: 6.9, 8.9, 6.4,
/// 4.2 s; with them keeping every row, 1e-2, 5e-2, 0.2: 3.8-3.9, 4.0, 4.1 s: a row nearly at
/// its bound is soon broken again.)
const LOOSE: f64 = 5e-2;

/// `start` (made for a program of the same shape, whole numbering) adapted to `lp`: its idle
/// and loose rows left out, every other row active (see the module docs).
pub(super) fn adapt(lp: &Lp, start: &Basis) -> Basis {
    let n = lp.n;
    let out = |k: usize| idle(lp, k) || loose(lp, &start.activity, k);
    // Rows dropped: out now, activity basic (an active row's activity is basic exactly when
    // it is at some position of the basis).
    let dropped = |k: usize| out(k) && start.at[n + k] == At::Basic;
    let mut active = vec![false; lp.rows];
    for &k in &start.rows {
        active[k] = !dropped(k);
    }
    let mut added: Vec<usize> = (0..lp.rows).filter(|&k| !active[k] && !out(k)).collect();
    if !active.contains(&true) && added.is_empty() && lp.rows > 0 {
        added.push(0);
    }
    reshape(lp, start, &dropped, &added)
}

/// `basis` (whole numbering) with the rows `added` (left out so far, so their activities are
/// basic) made active: the rows that the point of a solve on the part violates.
pub(super) fn add(lp: &Lp, basis: &Basis, added: &[usize]) -> Basis {
    reshape(lp, basis, &|_| false, added)
}

/// The rows of `lp` that `rows` leaves out, that are not idle, and whose activity at the
/// columns `x` breaks a bound by more than [`TOL`] of it: the activity from `factored`
/// ([`Lp::activities`], the same sums in another order) where the program has its factors.
pub(super) fn violated(lp: &Lp, rows: &[usize], x: &[f64], factored: Option<&[f64]>) -> Vec<usize> {
    let mut active = vec![false; lp.rows];
    for &k in rows {
        active[k] = true;
    }
    (0..lp.rows)
        .filter(|&k| !active[k] && !idle(lp, k))
        .filter(|&k| {
            let (lo, hi) = (lp.lo[lp.n + k], lp.hi[lp.n + k]);
            let v = factored.map_or_else(|| dot(lp.row(k), x), |v| v[k]);
            !(v >= lo - TOL * (1.0 + lo.abs()) && v <= hi + TOL * (1.0 + hi.abs()))
        })
        .collect()
}

/// `start` with the active rows for which `dropped` holds (their activities basic) left out
/// and the rows `added` (activities basic) made active.
fn reshape(lp: &Lp, start: &Basis, dropped: &dyn Fn(usize) -> bool, added: &[usize]) -> Basis {
    let n = lp.n;
    let keep_pos: Vec<usize> = (0..start.head.len())
        .filter(|&p| start.head[p] < n || !dropped(start.head[p] - n))
        .collect();
    let keep_cols: Vec<usize> = (0..start.rows.len())
        .filter(|&c| !dropped(start.rows[c]))
        .collect();
    let mut at = start.at.clone();
    let mut head: Vec<usize> = keep_pos.iter().map(|&p| start.head[p]).collect();
    let mut rows: Vec<usize> = keep_cols.iter().map(|&c| start.rows[c]).collect();
    for &k in added {
        // Outside the active rows an activity is basic; made so in case a start broke that.
        at[n + k] = At::Basic;
        head.push(n + k);
        rows.push(k);
    }
    let inv = start.inv.as_deref().map(|old| {
        let (r0, kept, r) = (start.rows.len(), keep_cols.len(), rows.len());
        let mut inv = pool::zeroed(r * r);
        for (p2, &p) in keep_pos.iter().enumerate() {
            for (c2, &c) in keep_cols.iter().enumerate() {
                inv[p2 * r + c2] = old[p * r0 + c];
            }
        }
        // An added row k: `a_k^T B'^-1` over the kept positions (a_k at each basic variable:
        // its column's entry, zero at another row's activity), then -1 on its own.
        for (t, &k) in added.iter().enumerate() {
            let row = kept + t;
            let a_k = lp.row(k);
            for p2 in 0..kept {
                let j = head[p2];
                if j >= n {
                    continue;
                }
                let a = a_k[j];
                if a != 0.0 {
                    for c2 in 0..kept {
                        inv[row * r + c2] += a * inv[p2 * r + c2];
                    }
                }
            }
            inv[row * r + row] = -1.0;
        }
        inv
    });
    Basis {
        head,
        at,
        inv,
        rows,
        activity: start.activity.clone(),
    }
}

/// Whether `rows` are all of `lp`'s, in order (then the program is solved as it is).
fn whole(lp: &Lp, rows: &[usize]) -> bool {
    rows.len() == lp.rows && rows.iter().enumerate().all(|(i, &k)| i == k)
}

/// The program on `rows` only (its activities numbered `n + i` in the order of `rows`; its
/// matrix shared with `lp`'s).
pub(super) fn part<'a>(lp: &'a Lp, rows: &[usize]) -> Cow<'a, Lp> {
    if whole(lp, rows) {
        return Cow::Borrowed(lp);
    }
    let n = lp.n;
    let map = rows.iter().map(|&k| lp.source_row(k)).collect();
    let pick = |v: &[f64]| -> Vec<f64> {
        v[..n]
            .iter()
            .chain(rows.iter().map(|&k| &v[n + k]))
            .copied()
            .collect()
    };
    Cow::Owned(Lp {
        n,
        rows: rows.len(),
        a: Arc::clone(&lp.a),
        map: Some(map),
        reduced: lp.reduced.clone(),
        lo: pick(&lp.lo),
        hi: pick(&lp.hi),
        cost: pick(&lp.cost),
    })
}

/// `basis` (whole numbering, over `basis.rows`) in the numbering of [`part`].
pub(super) fn into_part(lp: &Lp, basis: Basis) -> Basis {
    if whole(lp, &basis.rows) {
        return basis;
    }
    let n = lp.n;
    let mut position = vec![usize::MAX; lp.rows];
    for (i, &k) in basis.rows.iter().enumerate() {
        position[k] = i;
    }
    let head = basis
        .head
        .iter()
        .map(|&j| if j < n { j } else { n + position[j - n] })
        .collect();
    let at = basis.at[..n]
        .iter()
        .copied()
        .chain(basis.rows.iter().map(|&k| basis.at[n + k]))
        .collect();
    let r = basis.rows.len();
    let mut basis = basis;
    Basis {
        head,
        at,
        inv: basis.inv.take(),
        rows: (0..r).collect(),
        activity: std::mem::take(&mut basis.activity),
    }
}

/// A basis of [`part`] (over `rows`) back in the whole numbering.
pub(super) fn from_part(lp: &Lp, rows: &[usize], mut basis: Basis) -> Basis {
    if whole(lp, rows) {
        return basis;
    }
    let n = lp.n;
    let head = basis
        .head
        .iter()
        .map(|&j| if j < n { j } else { n + rows[j - n] })
        .collect();
    let mut at = vec![At::Basic; lp.total()];
    at[..n].copy_from_slice(&basis.at[..n]);
    for (i, &k) in rows.iter().enumerate() {
        at[n + k] = basis.at[n + i];
    }
    Basis {
        head,
        at,
        inv: basis.inv.take(),
        rows: rows.to_vec(),
        activity: std::mem::take(&mut basis.activity),
    }
}

/// A certificate over `rows` as one over all `total` rows (zero on the others).
pub(super) fn spread(total: usize, rows: &[usize], y: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; total];
    for (&k, &v) in rows.iter().zip(y) {
        out[k] = v;
    }
    out
}
