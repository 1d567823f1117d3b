//! The rows a solve works on: an **idle** row (free activity, no cost) whose activity is basic
//! can never leave the basis (a free basic variable is never infeasible and never blocks a
//! ratio test), so it changes no pivot and no answer, and the method leaves it out: the basis
//! and its dense inverse cover the **active** rows only ([`Basis::rows`]).
//!
//! The search's programs have many such rows: a drive cut is free once its node is decided,
//! and a pressure row is free unless the node is pressed. On the 2D plug most of a deep node's
//! `3m + 1` rows are idle, and the inverse's updates cost the square of the rows kept.
//!
//! A start made for other bounds is **adapted** to the program ([`adapt`]): a row that is now
//! idle and whose activity is basic is dropped (its basis position and its column of the
//! inverse deleted: the basis matrix has that activity's unit column, so the rest of the
//! inverse is the inverse of the rest), and a row that is no longer idle is added with its
//! activity basic (the inverse gains one row, `a^T B^-1` over the kept positions, and a `-1`):
//! `O(r^2)` per row, against the `O(r^3)` of refactoring. An idle row whose activity is
//! nonbasic stays active until it has entered the basis.
//!
//! The checks of the answers ([`super::check`]) run on the whole program: a point's row
//! activities are all recomputed, a certificate has zero multipliers on the rows left out.

use std::borrow::Cow;
use std::sync::Arc;

use super::{pool, At, Basis, Lp};

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
    }
}

/// `start` (made for a program of the same shape, whole numbering) adapted to `lp`'s idle rows:
/// see the module docs.
pub(super) fn adapt(lp: &Lp, start: &Basis) -> Basis {
    let n = lp.n;
    // Rows dropped: idle now, activity basic (an active row's activity is basic exactly when
    // it is at some position of the basis).
    let dropped = |k: usize| idle(lp, k) && start.at[n + k] == At::Basic;
    let keep_pos: Vec<usize> = (0..start.head.len())
        .filter(|&p| start.head[p] < n || !dropped(start.head[p] - n))
        .collect();
    let keep_cols: Vec<usize> = (0..start.rows.len())
        .filter(|&c| !dropped(start.rows[c]))
        .collect();
    let mut active = vec![false; lp.rows];
    for &c in &keep_cols {
        active[start.rows[c]] = true;
    }
    let mut added: Vec<usize> = (0..lp.rows)
        .filter(|&k| !active[k] && !idle(lp, k))
        .collect();
    if keep_cols.is_empty() && added.is_empty() && lp.rows > 0 {
        added.push(0);
    }
    let mut at = start.at.clone();
    let mut head: Vec<usize> = keep_pos.iter().map(|&p| start.head[p]).collect();
    let mut rows: Vec<usize> = keep_cols.iter().map(|&c| start.rows[c]).collect();
    for &k in &added {
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
