//! The witness of `mu*`: the best leaf's solution with each node's status, checked against WP.

use super::{CriticalWitness, Leaf};
use crate::conic::program::Formulation;
use crate::run::EnumerateError;
use crate::solution::{check_solution, tangential, ContactPattern, NodeStatus};

/// Two ratios within this relative distance of `upper` make the node slip.
const SLIP_TOL: f64 = 1e-9;

/// The witness of the best leaf, checked against WP at `mu = theta`.
pub(crate) fn witness_of(
    form: &Formulation,
    best: &Leaf,
) -> Result<CriticalWitness, EnumerateError> {
    let (d, m) = (form.dim, form.m);
    let mut r = best.r.clone();
    let u = form.problem.displacement(&r);
    let theta = best.theta;
    let mut status = Vec::with_capacity(m);
    let mut pattern = Vec::with_capacity(m);
    for i in 0..m {
        let rn = r[d * i];
        let (s, p) = if rn > 0.0 {
            let rt = tangential(&r, d, i);
            let s = if rt >= theta * rn * (1.0 - SLIP_TOL) {
                match d {
                    3 => NodeStatus::Slip,
                    _ if r[d * i + 1] > 0.0 => NodeStatus::SlipPlus,
                    _ => NodeStatus::SlipMinus,
                }
            } else {
                NodeStatus::Stick
            };
            (s, ContactPattern::Contact)
        } else if !best.contact[i] && form.gap_of(&r, i) > 1e-10 {
            (NodeStatus::Separated, ContactPattern::Separated)
        } else {
            (NodeStatus::Grazing, ContactPattern::Grazing)
        };
        status.push(s);
        pattern.push(p);
    }
    // A floating body's point ends with its rigid amplitudes, now in `u`.
    r.truncate(d * m);
    check_solution(form.problem, theta, &u, &r).map_err(|why| {
        EnumerateError::Internal(format!(
            "the witness of mu* = {theta} failed its check, so no answer is given: {why}"
        ))
    })?;
    Ok(CriticalWitness {
        u,
        r,
        status,
        pattern,
    })
}

/// The injected fault [`crate::run::Fault::CorruptWitness`]: move the first displacement by
/// more than the displacement's size, so that equilibrium fails by far more than any tolerance.
pub(crate) fn corrupt(u: &mut [f64]) {
    let size = u.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if let Some(first) = u.first_mut() {
        *first += 1.0 + 10.0 * size;
    }
}
