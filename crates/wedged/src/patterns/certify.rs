//! Exact certification of a sign-pattern enumeration (`enumerate --certify` with `bnb` or
//! `pattern-faces`, 2D and 3D, or `pattern-search`, 2D: its search then runs without drive
//! cuts, and each prune of the simplex method is solved again by the cone solver and checked
//! at once, [`Formulation::confirm`]; a prune that fails its check is explored further).
//!
//! The claim is that the reported patterns are exactly the maximal realised patterns at the
//! problem's `mu`. It follows from three facts, each checked in exact rational arithmetic with
//! every `f64` of `K` and `mu` taken as the rational it represents:
//!
//! 1. **Every reported pattern is realised.** Its witness is recomputed exactly: the linear
//!    conditions of its pattern and statuses (`u_n = 0` on contact and grazing nodes, `r = K u = 0`
//!    on separated and grazing nodes; at a slipping node `r_t = mu r_n` times a direction, in 2D
//!    the sign of the slip, in 3D a rational point of the unit circle next to the witness's own
//!    direction) are solved exactly with the free coordinates taken from the floating-point
//!    witness; then `r_n > 0` on contact nodes, `u_n > 0` on separated ones, and friction
//!    (strict at sticking nodes) are checked exactly. (A 3D node that slips in every solution of
//!    its piece in an irrational direction cannot be recovered this way; it is named as a
//!    failure.)
//! 2. **Every realised pattern lies below a leaf of the search.** A realised pattern `q` with
//!    contact set `A` is a solution of every relaxation on the way to the leaf `A`, pressing its
//!    contact nodes. So every decision that cut the search short is backed by an infeasibility
//!    ([`crate::conic::program::Refutation`], re-checked by `critical::certify`): a pruned subtree has no
//!    nontrivial solution, or none pressing all its contact nodes; at a leaf, every pressure or
//!    gap left out of its pattern is zero in every solution. A decision that the solver would not
//!    back with a certificate is a failure ([`crate::conic::program::Formulation::confirm`]).
//! 3. **The reported patterns are the maximal ones among the leaves' patterns**, which is plain
//!    comparison of sign vectors and is not redone.
//!
//! A 2D floating body is certified the same way on its exact problem of
//! `conic::refutation::Compliance` (the witness in its reactions and rigid amplitudes, the
//! amplitudes bounded); a 3D one is refused (`super::floating_certify_refusal`).
//!
//! So every realised pattern is below a reported one and every reported one is realised: the
//! reported patterns are the maximal realised patterns. The statuses of the witnesses are
//! certified as statuses of that witness; the claim that a node slips in *every* solution of its
//! piece is not. The pyramid method's candidates come from floating-point double description,
//! so its completeness is not certified, and neither is an incomplete run's.

use num_bigint::BigInt;
use num_traits::{Signed, ToPrimitive, Zero};
use rayon::prelude::*;

use super::{classes_of, Pattern, PatternMethod};
use crate::conic::program::{describe, Formulation, Refutation};
use crate::conic::refutation::{floating_state, integer_floating, integer_stiffness, solve_again};
use crate::problem::Problem;
use crate::rational::{exact_state, rat};
use crate::solution::{ContactPattern, NodeStatus};

/// The outcome of the exact checks of a pattern enumeration.
#[derive(Debug, Clone, PartialEq)]
pub struct PatternCertificate {
    /// True when every check passed: the reported patterns are proven to be all the maximal
    /// realised patterns, each with an exact witness.
    pub certified: bool,
    /// Witnesses recomputed and checked exactly.
    pub witnesses_checked: usize,
    /// Witnesses that failed.
    pub witnesses_failed: usize,
    /// Infeasibility certificates checked exactly.
    pub refutations_checked: usize,
    /// Those that failed, even solved again.
    pub refutations_failed: usize,
    /// Decisions of the search the solver would not back with a certificate.
    pub doubts: usize,
    /// One line per failure (the first few of each kind, the rest counted).
    pub failures: Vec<String>,
}

/// Failures listed by name per kind; the rest are counted.
const LISTED: usize = 5;

/// The exact checks of a finished run of `method` on `form`'s problem (the equilibrated one the
/// search ran on), whose reported patterns are `patterns` (in that problem's units); `complete`
/// when the run finished with nothing undecided.
pub(crate) fn certify(
    form: &mut Formulation,
    method: PatternMethod,
    patterns: &[Pattern],
    complete: bool,
) -> PatternCertificate {
    let problem = form.problem;
    let mut failures = Vec::new();
    if let PatternMethod::Pyramid { .. } = method {
        failures.push(
            "the pyramid method's candidates come from floating-point double description, so \
             its completeness is not certified (use bnb or pattern-faces)"
                .to_string(),
        );
    }
    if !complete {
        failures.push("the run is incomplete, so completeness is not certified".to_string());
    }
    let doubts = std::mem::take(&mut *form.doubts.lock().unwrap_or_else(|e| e.into_inner()));
    if !doubts.is_empty() {
        failures.push(format!(
            "{} decisions of the search could not be backed by a certificate",
            doubts.len()
        ));
        failures.extend(doubts.iter().take(LISTED).cloned());
    }
    let refutations = form.take_refutations();
    // A failing certificate is solved once more (with its own cut, then as a trivial cone).
    let again = |f: &Refutation, mu: f64, sum: bool| solve_again(problem, f, mu, sum);
    let checked =
        crate::conic::refutation::check_all(problem, &refutations, Some(problem.mu()), &again);
    failures.extend(checked.failures);
    let k = if problem.is_floating() {
        integer_floating(problem)
    } else {
        integer_stiffness(problem)
    };
    let witnesses: Vec<String> = patterns
        .par_iter()
        .enumerate()
        .filter_map(|(n, p)| {
            check_witness(problem, &k, p).err().map(|e| {
                let q = describe(&classes_of(&p.pattern));
                format!("pattern {} [{q}]: {e}", n + 1)
            })
        })
        .collect();
    let witnesses_failed = witnesses.len();
    if witnesses_failed > LISTED {
        failures.push(format!(
            "{witnesses_failed} of {} witnesses failed their exact check",
            patterns.len()
        ));
    }
    failures.extend(witnesses.into_iter().take(LISTED));
    PatternCertificate {
        certified: failures.is_empty(),
        witnesses_checked: patterns.len(),
        witnesses_failed,
        refutations_checked: refutations.len()
            + form.settled.load(std::sync::atomic::Ordering::Relaxed) as usize,
        refutations_failed: checked.failed,
        doubts: doubts.len(),
        failures,
    }
}

/// How far the rational parameter of a 3D slip direction may be from the witness's own.
const DIRECTION_TOL: f64 = 1e-7;

/// The simplest rational `a / b` (`b > 0`) in `[lo, hi]` (continued fractions; in floating
/// point, which only chooses the candidate: the checks that use it are exact).
fn simplest(lo: f64, hi: f64) -> (i64, i64) {
    if lo <= 0.0 && hi >= 0.0 {
        return (0, 1);
    }
    if hi < 0.0 {
        let (a, b) = simplest(-hi, -lo);
        return (-a, b);
    }
    let (mut lo, mut hi) = (lo, hi);
    // Convergents h/k of the common continued fraction of lo and hi.
    let (mut h0, mut h1, mut k0, mut k1) = (0i64, 1i64, 1i64, 0i64);
    for _ in 0..40 {
        let f = lo.floor();
        if f + 1.0 <= hi || f == lo {
            let a = if f == lo { f } else { f + 1.0 } as i64;
            return (a * h1 + h0, a * k1 + k0);
        }
        let a = f as i64;
        (h0, h1) = (h1, a * h1 + h0);
        (k0, k1) = (k1, a * k1 + k0);
        (lo, hi) = (1.0 / (hi - f), 1.0 / (lo - f));
        if !(lo.is_finite() && hi.is_finite()) || k1 > 1 << 30 {
            break;
        }
    }
    (h1, k1.max(1))
}

/// A rational point `(c, s) / den` of the unit circle near the unit vector `(x, y)` (the
/// rational parametrisation by `t = tan(phi / 2)`, `t` the simplest rational within
/// [`DIRECTION_TOL`]).
fn circle_point(x: f64, y: f64) -> (BigInt, BigInt, BigInt) {
    let (flip, t) = if x >= 0.0 {
        (false, y / (1.0 + x))
    } else {
        (true, y / (1.0 - x))
    };
    let (a, b) = simplest(t - DIRECTION_TOL, t + DIRECTION_TOL);
    let (a, b) = (BigInt::from(a), BigInt::from(b));
    let c = &b * &b - &a * &a;
    let s = BigInt::from(2) * &a * &b;
    let den = &b * &b + &a * &a;
    (if flip { -c } else { c }, s, den)
}

/// Recomputes a pattern's witness exactly (see the module docs) and checks it; `k` is
/// [`integer_stiffness`], or [`integer_floating`] for a floating body.
fn check_witness(problem: &Problem, k: &[Vec<BigInt>], p: &Pattern) -> Result<(), String> {
    let (d, m) = (problem.dim(), problem.nodes());
    let n = d * m;
    let kf = problem.stiffness();
    let (q, status) = (&p.pattern, &p.status);
    if !q.contains(&ContactPattern::Contact) {
        return Err("no node is in contact".into());
    }
    let closed = |i: usize| matches!(q[i], ContactPattern::Contact | ContactPattern::Grazing);
    let free_r = |i: usize| q[i] == ContactPattern::Contact;
    let cols: Vec<usize> = (0..n).filter(|&c| !(c % d == 0 && closed(c / d))).collect();
    let mu = rat(problem.mu());
    let (mp, mq) = (mu.numer().clone(), mu.denom().clone());
    let mut exact: Vec<Vec<BigInt>> = Vec::new();
    let mut float: Vec<Vec<f64>> = Vec::new();
    let k_row = |a: usize| -> (Vec<BigInt>, Vec<f64>) {
        (
            cols.iter().map(|&c| k[a][c].clone()).collect(),
            cols.iter().map(|&c| kf[(a, c)]).collect(),
        )
    };
    // den q r_t_c - num_c p r_n = 0 (mu = p / q): r_t = mu r_n (num / den). Over u (r = K u)
    // when clamped, over r itself when floating.
    let floating = problem.is_floating();
    let unit = |a: usize| -> (Vec<BigInt>, Vec<f64>) {
        let mut e = vec![BigInt::zero(); n];
        let mut x = vec![0.0; n];
        e[a] = BigInt::from(1);
        x[a] = 1.0;
        (e, x)
    };
    let mut slip_rows = |i: usize, c: usize, num: &BigInt, den: &BigInt| {
        let row = |a: usize| if floating { unit(a) } else { k_row(a) };
        let (et, xt) = row(d * i + c);
        let (en, xn) = row(d * i);
        let (a, b) = (den * &mq, num * &mp);
        exact.push(et.iter().zip(&en).map(|(t, n)| &a * t - &b * n).collect());
        let ratio = num.to_f64().unwrap_or(0.0) / den.to_f64().unwrap_or(1.0);
        float.push(
            xt.iter()
                .zip(&xn)
                .map(|(t, n)| t - ratio * problem.mu() * n)
                .collect(),
        );
    };
    for (i, &st) in status.iter().enumerate().take(m) {
        if !free_r(i) {
            continue;
        }
        match st {
            NodeStatus::Stick => {}
            NodeStatus::SlipPlus | NodeStatus::SlipMinus if d == 2 => {
                let sign = BigInt::from(if st == NodeStatus::SlipPlus { 1 } else { -1 });
                slip_rows(i, 1, &sign, &BigInt::from(1));
            }
            NodeStatus::Slip if d == 3 => {
                let (x, y) = (p.r[3 * i + 1], p.r[3 * i + 2]);
                let norm = x.hypot(y);
                if norm.is_nan() || norm <= 0.0 {
                    return Err(format!("node {}: slips without a tangential force", i + 1));
                }
                let (c, s, den) = circle_point(x / norm, y / norm);
                slip_rows(i, 1, &c, &den);
                slip_rows(i, 2, &s, &den);
            }
            other => {
                return Err(format!(
                    "node {}: status {} does not fit contact",
                    i + 1,
                    other.name()
                ))
            }
        }
    }
    let (u, r) = if floating {
        // Unknowns: the contact nodes' reactions and the amplitudes (`k` is `[G | R]`).
        let reactions: Vec<usize> = (0..n).filter(|&a| free_r(a / d)).collect();
        let shut: Vec<usize> = (0..m).filter(|&i| closed(i)).map(|i| d * i).collect();
        let x = problem.point_of(&p.u, &p.r);
        let rows = exact.into_iter().zip(float).collect();
        floating_state(problem, k, &reactions, &shut, rows, &x)?
    } else {
        for a in (0..n).filter(|&a| !free_r(a / d)) {
            let (e, x) = k_row(a);
            exact.push(e);
            float.push(x);
        }
        exact_state(k, &cols, exact, float, &p.u)
    };
    for i in 0..m {
        let node = i + 1;
        let (un, rn) = (&u[d * i], &r[d * i]);
        let r_zero = (0..d).all(|c| r[d * i + c].is_zero());
        match q[i] {
            ContactPattern::Contact => {
                if !rn.is_positive() {
                    return Err(format!("exact witness: node {node} is not pressed"));
                }
                let t2: BigInt = (1..d).map(|c| &r[d * i + c] * &r[d * i + c]).sum();
                let lhs = &mq * &mq * t2;
                let rhs = &mp * &mp * (rn * rn);
                let ok = if status[i] == NodeStatus::Stick {
                    lhs < rhs
                } else {
                    lhs <= rhs
                };
                if !ok {
                    return Err(format!(
                        "exact witness: node {node} is {} the friction cone",
                        if lhs > rhs { "outside" } else { "on" }
                    ));
                }
            }
            ContactPattern::Separated => {
                if !un.is_positive() || !r_zero {
                    return Err(format!(
                        "exact witness: node {node} is not separated (u_n > 0, r = 0)"
                    ));
                }
            }
            ContactPattern::Grazing => {
                if !un.is_zero() || !r_zero {
                    return Err(format!(
                        "exact witness: node {node} is not grazing (u_n = 0, r = 0)"
                    ));
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::random_spd_problem_dim;
    use crate::patterns::{enumerate_patterns, PatternSettings};

    /// Every witness of a certified run passes exactly. Corrupted claims are caught: every
    /// witness checked at half the certified lower end of `mu*` (where nothing wedges), and a
    /// grazing node claimed separated or in contact (strictly above a maximal realised
    /// pattern, so not realised).
    #[test]
    fn corrupted_patterns_are_caught() {
        use crate::critical::{critical, CriticalSettings};
        let (mut checked, mut grazing) = (0, 0);
        for case in 0..40u64 {
            let dim = 2 + (case % 2) as usize;
            let m = 2 + (case % 4) as usize;
            let mu = [1.0, 2.0, 4.0][(case % 3) as usize];
            // In the units the search runs in (equilibration scales by powers of two).
            let p = random_spd_problem_dim(dim, m, mu, 900 + case)
                .equilibrated()
                .0;
            let settings = PatternSettings {
                certify: true,
                ..PatternSettings::default()
            };
            let run = enumerate_patterns(&p, &settings).unwrap();
            assert!(run.certificate.as_ref().unwrap().certified, "case {case}");
            let Some(lower) = critical(&p, &CriticalSettings::default()).unwrap().lower else {
                continue;
            };
            let low = Problem::new(dim, p.stiffness().clone(), lower / 2.0).unwrap();
            let k = integer_stiffness(&p);
            for pat in &run.patterns {
                assert_eq!(check_witness(&p, &k, pat), Ok(()), "case {case}");
                assert!(check_witness(&low, &k, pat).is_err(), "case {case}");
                checked += 1;
                for i in (0..m).filter(|&i| pat.pattern[i] == ContactPattern::Grazing) {
                    grazing += 1;
                    let mut bad = pat.clone();
                    bad.pattern[i] = ContactPattern::Separated;
                    bad.status[i] = NodeStatus::Separated;
                    assert!(check_witness(&p, &k, &bad).is_err(), "case {case}");
                    bad.pattern[i] = ContactPattern::Contact;
                    bad.status[i] = NodeStatus::Stick;
                    assert!(check_witness(&p, &k, &bad).is_err(), "case {case}");
                }
            }
        }
        assert!(
            checked >= 20,
            "{checked} patterns checked ({grazing} grazing nodes)"
        );
    }

    /// A piece at the method's resolution: on the 2D plug at m = 100 (`mu = 2`, 45 contact
    /// nodes) each entry of this pattern reaches [`POSITIVE`] on its own, but together only
    /// about 6.8e-8 (the mean of solutions that each lift one entry lifts all of them by less).
    /// Asking `POSITIVE` of them together left the leaf undecided and the run incomplete; the
    /// resolution together is half of it, what the witness check asks. The leaf is found
    /// maximal, witnessed, and its witness passes the exact check.
    #[test]
    fn a_piece_at_the_resolution_is_witnessed_exactly() {
        use crate::conic::contact_lp::ContactLp;
        use crate::conic::program::POSITIVE;
        use crate::run::{Control, Limits};
        let model = crate::examples::plug2d_tri(50).unwrap();
        let p = model.problem(2.0).unwrap().equilibrated().0;
        let form = Formulation::new(&p);
        let lp = ContactLp::new(&form);
        let cancel = std::sync::atomic::AtomicBool::new(false);
        let control = Control::new(Limits::default(), &cancel);
        let mut contact = vec![false; 100];
        let nodes = [1, 44, 46, 48, 50, 52, 54, 56, 58, 60, 62, 64, 91, 93];
        for i in nodes.into_iter().chain(65..90).chain(94..100) {
            contact[i] = true;
        }
        let (q, maximal, known) = super::super::search::leaf_piece(&lp, &control, &contact)
            .unwrap()
            .unwrap();
        assert!(maximal);
        assert_eq!(q, super::super::whole_pattern(&contact));
        let pat = super::super::finish(&form, Some(&lp), &q, known.as_ref()).unwrap();
        assert!(
            pat.margin < POSITIVE && pat.margin > POSITIVE / 2.0,
            "{}",
            pat.margin
        );
        assert_eq!(check_witness(&p, &integer_stiffness(&p), &pat), Ok(()));
    }

    #[test]
    fn simplest_rationals() {
        assert_eq!(simplest(-0.1, 0.1), (0, 1));
        assert_eq!(simplest(0.3, 0.4), (1, 3));
        assert_eq!(simplest(0.49, 0.51), (1, 2));
        assert_eq!(simplest(-0.51, -0.49), (-1, 2));
        assert_eq!(simplest(2.0, 2.0), (2, 1));
        let (a, b) = simplest(0.141_421_3, 0.141_421_4);
        let x = a as f64 / b as f64;
        assert!((0.141_421_3..=0.141_421_4).contains(&x), "{a}/{b}");
    }

    #[test]
    fn circle_points_are_on_the_circle_and_near() {
        for k in 0..64 {
            let phi = k as f64 * std::f64::consts::TAU / 64.0 + 0.01;
            let (x, y) = (phi.cos(), phi.sin());
            let (c, s, den) = circle_point(x, y);
            assert_eq!(&c * &c + &s * &s, &den * &den);
            let f = |v: &BigInt| v.to_f64().unwrap();
            assert!((f(&c) / f(&den) - x).abs() < 1e-6, "{k}");
            assert!((f(&s) / f(&den) - y).abs() < 1e-6, "{k}");
        }
    }
}
