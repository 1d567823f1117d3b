//! The checks of the simplex method's answers (see the module docs of [`super`]): an optimal
//! point against every bound, an infeasibility certificate against the bounds of every variable.

use super::dense::{dot_terms, implied};
use super::{Answer, Lp, CERT, TINY, TOL};

/// The optimal point of columns `x`: row activities recomputed, every bound checked (see the
/// module docs); `factored`, the activities through the factors ([`Lp::activities`]) where the
/// program has them.
pub(super) fn check_point(lp: &Lp, x: &[f64], factored: Option<&[f64]>) -> Result<Answer, String> {
    let n = lp.n;
    let mut all = x.to_vec();
    let mut terms = vec![0.0; lp.total()];
    for (j, v) in x.iter().enumerate() {
        terms[j] = v.abs();
    }
    // Through the factors where the program has them: a row whose activity lies within
    // `TOL (1 + |activity|)` of its bounds passes at once, since the direct sum's terms add up
    // to at least `|activity|`; any other row is summed directly, with its terms. (The check
    // was a twentieth of the 3D V-groove plug's search.)
    for k in 0..lp.rows {
        let j = n + k;
        let quick = factored.map(|v| v[k]).filter(|&v| {
            let allowed = TOL * (1.0 + v.abs());
            v >= lp.lo[j] - allowed && v <= lp.hi[j] + allowed
        });
        let (activity, size) = match quick {
            Some(v) => (v, v.abs()),
            None => dot_terms(lp.row(k), x),
        };
        all.push(activity);
        terms[j] = size;
    }
    for (j, &v) in all.iter().enumerate() {
        if !v.is_finite() {
            return Err(format!("variable {j} is not finite"));
        }
        let allowed = TOL * (1.0 + terms[j]);
        if v < lp.lo[j] - allowed || v > lp.hi[j] + allowed {
            return Err(format!(
                "variable {j} = {v:e} is outside [{:e}, {:e}]",
                lp.lo[j], lp.hi[j]
            ));
        }
    }
    let value = all.iter().zip(&lp.cost).map(|(a, b)| a * b).sum();
    Ok(Answer::Optimal { x: all, value })
}

/// An infeasibility certificate `y` (one multiplier per row), checked as the module docs say.
pub(super) fn check_certificate(lp: &Lp, y: &[f64]) -> Result<Answer, String> {
    if y.iter().any(|v| !v.is_finite()) {
        return Err("the certificate is not finite".into());
    }
    let c = lp.row_times(y);
    let cmax = c.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    if cmax == 0.0 {
        return Err("the certificate is zero".into());
    }
    // The least and the greatest of c . v over the bounds, from the finite terms, and
    // whether a non-tiny term is unbounded that way. A row activity's bounds are its own
    // intersected with those its columns' bounds imply, so that a program whose columns are
    // all bounded needs no term dropped.
    let bounds = effective_bounds(lp, y);
    let (mut least, mut most, mut least_terms, mut most_terms) = (0.0, 0.0, 0.0, 0.0);
    let (mut least_open, mut most_open) = (false, false);
    for (j, &cj) in c.iter().enumerate() {
        let (lo, hi) = bounds[j];
        if cj.abs() <= TINY * cmax && !(lo.is_finite() && hi.is_finite()) {
            continue;
        }
        let (at_least, at_most) = if cj > 0.0 { (lo, hi) } else { (hi, lo) };
        if at_least.is_finite() {
            least += cj * at_least;
            least_terms += (cj * at_least).abs();
        } else {
            least_open = true;
        }
        if at_most.is_finite() {
            most += cj * at_most;
            most_terms += (cj * at_most).abs();
        } else {
            most_open = true;
        }
    }
    // Each side against the terms it is made of.
    let clear = |terms: f64| CERT * terms.max(f64::MIN_POSITIVE);
    if (!least_open && least > clear(least_terms)) || (!most_open && most < -clear(most_terms)) {
        Ok(Answer::Infeasible { y: y.to_vec() })
    } else {
        Err("the certificate does not exclude every point".into())
    }
}

/// The bounds of every variable: a column's own, a row activity's own intersected with the
/// interval that its columns' bounds imply (`A_k . x` over the box; infinite where a column
/// is unbounded the way that matters). The implied interval is worked out only for the rows
/// with a multiplier in `y` (another row's activity has a zero entry in the certificate, so
/// its bounds do not count).
fn effective_bounds(lp: &Lp, y: &[f64]) -> Vec<(f64, f64)> {
    let n = lp.n;
    let mut out: Vec<(f64, f64)> = (0..lp.total()).map(|j| (lp.lo[j], lp.hi[j])).collect();
    // Columns all bounded (as a search node's are, `node_lp`): each row's interval by a
    // vectorised kernel, without the tests for infinite bounds (an infeasible program's check
    // was a twelfth of the 3D V-groove plug's search).
    let (col_lo, col_hi) = (&lp.lo[..n], &lp.hi[..n]);
    let bounded = col_lo.iter().chain(col_hi).all(|v| v.is_finite());
    for k in (0..lp.rows).filter(|&k| y[k] != 0.0) {
        let row = lp.row(k);
        if bounded {
            let (lo, hi) = implied(row, col_lo, col_hi);
            let (own_lo, own_hi) = out[n + k];
            out[n + k] = (own_lo.max(lo), own_hi.min(hi));
            continue;
        }
        let (mut lo, mut hi) = (0.0, 0.0);
        for (j, &a) in row.iter().enumerate() {
            if a == 0.0 {
                continue;
            }
            let (at_lo, at_hi) = if a > 0.0 {
                (lp.lo[j], lp.hi[j])
            } else {
                (lp.hi[j], lp.lo[j])
            };
            lo += a * at_lo;
            hi += a * at_hi;
        }
        // An infinite sum (or inf - inf) leaves the row's own bound.
        let (own_lo, own_hi) = out[n + k];
        if lo.is_finite() {
            out[n + k].0 = own_lo.max(lo);
        }
        if hi.is_finite() {
            out[n + k].1 = own_hi.min(hi);
        }
    }
    out
}
