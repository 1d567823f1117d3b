//! The last resort of [`super::solve`] for a linear program: the in-house simplex method.

use super::{Answer, Form, Kind};
use crate::conic::simplex;

/// A linear program (no cone constraint) that Clarabel could not decide, by the in-house
/// simplex method ([`crate::conic::simplex`]), which needs no interior (the programs of a floating
/// body pinned between its walls often have none). Its answers are checked in its own form: an
/// optimum's bounds against recomputed activities, an infeasibility by its certificate. The
/// certificate is not returned (its multipliers are in the simplex method's form): an
/// infeasible answer carries an empty `y`, which an exact re-check treats as no certificate.
/// `None` for a program with a cone constraint.
pub(super) fn by_simplex(form: &Form) -> Option<Result<Answer, String>> {
    if form.cons.iter().any(|c| c.kind == Kind::Soc) {
        return None;
    }
    let (n, rows) = (form.n, form.rows.len());
    let mut lp = simplex::Lp::new(n, rows);
    let a = lp.a_mut();
    for (k, row) in form.rows.iter().enumerate() {
        for &(j, c) in &row.terms {
            a[k * n + j] = c;
        }
    }
    for con in &form.cons {
        for k in con.start..con.start + con.len {
            // e = terms . x + constant: zero, or >= 0.
            let at = -form.rows[k].constant;
            lp.lo[n + k] = at;
            if con.kind == Kind::Zero {
                lp.hi[n + k] = at;
            }
        }
    }
    lp.cost[..n].copy_from_slice(&form.q);
    Some(match simplex::solve(&lp, None).0 {
        simplex::Answer::Optimal { x, value } => Ok(Answer::Optimal {
            x: x[..n].to_vec(),
            value,
        }),
        simplex::Answer::Infeasible { .. } => Ok(Answer::Infeasible { y: Vec::new() }),
        simplex::Answer::Failed(why) => Err(why),
    })
}
