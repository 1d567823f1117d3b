//! Floating bodies (issue 22): every method that applies agrees with an independent brute force.
//!
//! The brute force works in the displacements, not the reactions: `u` free, `r = K u`, so it
//! needs neither the rigid modes nor a generalised inverse (the library's programs use both:
//! `u = G r + R a` with `R^T r = 0`). Per contact set `S`, one linear (3D: second-order cone)
//! program per entry says which pressures (on `S`) and gaps (off `S`) some solution makes
//! positive; the maximal patterns of those supports are the pieces. `mu*` is the least `mu` at
//! which some contact set is feasible, by bisection per contact set.

#![allow(clippy::needless_range_loop)] // node loops index several arrays at once

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::DMatrix;
use wedged::examples::floating_notch;
use wedged::{
    critical, enumerate_patterns, ContactPattern, CriticalMethod, CriticalSettings, CriticalStatus,
    PatternMethod, PatternSettings, Problem, ProblemError,
};

/// An affine expression `c . x + c0` in the program's variables `x = (u, t)`.
type Expr = (Vec<f64>, f64);

/// A program: expressions that must be zero, nonnegative, or in a second-order cone.
#[derive(Default)]
struct Lp {
    /// A bound on every variable, far above any solution's size (with `sum r_n = 1`, `u` is
    /// of the size of the compliance): it keeps the simplex method off the rigid motions'
    /// unbounded directions, where its points lose every digit.
    bound: f64,
    zero: Vec<Expr>,
    nonneg: Vec<Expr>,
    soc: Vec<Vec<Expr>>,
}

/// The equalities `c . x + c0 = 0` as independent rows (an orthonormal basis of their row
/// space, from the SVD), or `None` when they are inconsistent. (`r_i = (K u)_i = 0` at several
/// nodes repeats rows of a singular `K`; an interior-point solver stalls on redundant
/// equalities.)
fn independent(zero: &[Expr]) -> Option<Vec<Expr>> {
    if zero.is_empty() {
        return Some(Vec::new());
    }
    let nvar = zero[0].0.len();
    let c = DMatrix::from_fn(zero.len(), nvar, |i, j| zero[i].0[j]);
    let rhs = nalgebra::DVector::from_fn(zero.len(), |i, _| -zero[i].1);
    let svd = c.svd(true, true);
    let (u, vt) = (svd.u.unwrap(), svd.v_t.unwrap());
    let top = svd.singular_values.max();
    let mut rows = Vec::new();
    let mut explained = nalgebra::DVector::zeros(zero.len());
    for (j, &s) in svd.singular_values.iter().enumerate() {
        if s > 1e-10 * top {
            let coef = u.column(j).dot(&rhs);
            explained += u.column(j) * coef;
            rows.push((vt.row(j).iter().copied().collect(), -coef / s));
        }
    }
    ((rhs - explained).norm() <= 1e-9 * (1.0 + top)).then_some(rows)
}

/// Solves `min q . x` over the program: `Some(x)` when solved, `None` when infeasible. A
/// linear program (2D) goes to a simplex method (`microlp`): the leaves of a floating body are
/// often degenerate (a body pinned between two nodes has a single solution, no interior), which
/// an interior-point method decides poorly. Cone programs (3D) go to Clarabel.
/// When one method fails, the other is asked; `Err` when neither decides.
fn try_solve(lp: &Lp, q: &[f64]) -> Result<Option<Vec<f64>>, String> {
    let first = if lp.soc.is_empty() {
        solve_simplex(lp, q)
    } else {
        solve_conic(lp, q)
    };
    first.or_else(|e| {
        if lp.soc.is_empty() {
            solve_conic(lp, q).map_err(|f| format!("{e}; {f}"))
        } else {
            Err(e)
        }
    })
}

fn solve_simplex(lp: &Lp, q: &[f64]) -> Result<Option<Vec<f64>>, String> {
    use microlp::{ComparisonOp, OptimizationDirection};
    let mut p = microlp::Problem::new(OptimizationDirection::Minimize);
    let x: Vec<_> = q
        .iter()
        .map(|&c| p.add_var(c, (-lp.bound, lp.bound)))
        .collect();
    let terms = |e: &Expr| -> Vec<(microlp::Variable, f64)> {
        e.0.iter()
            .enumerate()
            .filter(|(_, c)| **c != 0.0)
            .map(|(j, &c)| (x[j], c))
            .collect()
    };
    let Some(zero) = independent(&lp.zero) else {
        return Ok(None);
    };
    for e in &zero {
        p.add_constraint(terms(e).as_slice(), ComparisonOp::Eq, -e.1);
    }
    for e in &lp.nonneg {
        p.add_constraint(terms(e).as_slice(), ComparisonOp::Ge, -e.1);
    }
    match p.solve() {
        Ok(outcome) => {
            let sol = outcome.solution().expect("no limits were set");
            let x: Vec<f64> = x.iter().map(|&v| sol[v]).collect();
            // The point is checked against every constraint, relative to its terms.
            let off = |e: &Expr| {
                let v: f64 = e.0.iter().zip(&x).map(|(c, y)| c * y).sum::<f64>() + e.1;
                let terms: f64 = e.0.iter().zip(&x).map(|(c, y)| (c * y).abs()).sum::<f64>();
                (v, 1e-7 * (terms + e.1.abs()))
            };
            let bad = lp.zero.iter().map(off).any(|(v, t)| v.abs() > t)
                || lp.nonneg.iter().map(off).any(|(v, t)| v < -t)
                || x.iter().any(|y| y.abs() >= 0.5 * lp.bound);
            if bad {
                return Err("simplex: its point fails the constraints".into());
            }
            Ok(Some(x))
        }
        Err(microlp::Error::Infeasible) => Ok(None),
        Err(e) => Err(format!("simplex: {e}")),
    }
}

fn solve_conic(lp: &Lp, q: &[f64]) -> Result<Option<Vec<f64>>, String> {
    let nvar = q.len();
    let mut rows = Vec::new();
    let mut b = Vec::new();
    let mut cones = Vec::new();
    let mut push = |e: &Expr, rows: &mut Vec<Vec<f64>>| {
        rows.push(e.0.iter().map(|c| -c).collect::<Vec<f64>>());
        b.push(e.1);
    };
    let Some(zero) = independent(&lp.zero) else {
        return Ok(None);
    };
    for e in &zero {
        push(e, &mut rows);
    }
    if !zero.is_empty() {
        cones.push(SupportedConeT::ZeroConeT(zero.len()));
    }
    for e in &lp.nonneg {
        push(e, &mut rows);
    }
    if !lp.nonneg.is_empty() {
        cones.push(SupportedConeT::NonnegativeConeT(lp.nonneg.len()));
    }
    for block in &lp.soc {
        for e in block {
            push(e, &mut rows);
        }
        cones.push(SupportedConeT::SecondOrderConeT(block.len()));
    }
    let a = CscMatrix::from(&rows);
    let p = CscMatrix::zeros((nvar, nvar));
    // Clarabel's defaults first; when it stalls, tighter tolerances and more iterations.
    let mut last = None;
    // Clarabel's defaults, then tighter tolerances, then without Ruiz equilibration.
    for (tight, plain) in [(false, false), (true, false), (true, true)] {
        let mut settings = DefaultSettingsBuilder::default();
        settings.verbose(false).equilibrate_enable(!plain);
        if tight && !plain {
            settings
                .max_iter(1000)
                .tol_gap_abs(1e-10)
                .tol_gap_rel(1e-10)
                .tol_feas(1e-10);
        }
        let settings = settings.build().unwrap();
        let mut solver = DefaultSolver::new(&p, q, &a, &b, &cones, settings).unwrap();
        solver.solve();
        // Reduced accuracy is accepted on the second round only: the leaves next to a rigid
        // motion (r = 0, u = R a) are infeasible by a thin margin.
        match solver.solution.status {
            SolverStatus::Solved => return Ok(Some(solver.solution.x.clone())),
            SolverStatus::AlmostSolved if tight => return Ok(Some(solver.solution.x.clone())),
            SolverStatus::PrimalInfeasible => return Ok(None),
            SolverStatus::AlmostPrimalInfeasible if tight => return Ok(None),
            s => last = Some(s),
        }
    }
    Err(format!("Clarabel: {last:?}"))
}

/// The leaf of contact set `s` at `mu` (`INFINITY`: no friction limit) in the variables
/// `(u, t)`: `u_n = 0` and `r = K u` in the friction cone on `s`, `r = 0` and `u_n >= 0` off it,
/// `sum r_n = 1`.
/// How a 3D leaf's friction cone is written: exactly, or as the pyramid with [`FACES`] faces
/// inscribed in it (a smaller set of solutions) or circumscribed about it (a larger one).
#[derive(Clone, Copy, PartialEq)]
enum Cone3 {
    Exact,
    Inner,
    Outer,
}

/// Faces of the 3D pyramids.
const FACES: usize = 24;

fn leaf_with(p: &Problem, s: &[bool], mu: f64, cone: Cone3) -> Lp {
    let (d, m) = (p.dim(), p.nodes());
    let n = d * m;
    let k = p.stiffness();
    let r = |a: usize| -> Expr {
        (
            (0..=n)
                .map(|b| if b < n { k[(a, b)] } else { 0.0 })
                .collect(),
            0.0,
        )
    };
    let u = |a: usize| -> Expr {
        (
            (0..=n).map(|b| if b == a { 1.0 } else { 0.0 }).collect(),
            0.0,
        )
    };
    let g = k.clone().pseudo_inverse(1e-12 * k.amax()).expect("an SVD");
    let mut lp = Lp {
        bound: 1e4 * n as f64 * g.amax(),
        ..Lp::default()
    };
    let mut total = vec![0.0; n + 1];
    for i in 0..m {
        if s[i] {
            lp.zero.push(u(d * i));
            let (rn, _) = r(d * i);
            total.iter_mut().zip(&rn).for_each(|(t, x)| *t += x);
            lp.nonneg.push(r(d * i));
            if mu.is_finite() {
                let head: Vec<f64> = rn.iter().map(|x| mu * x).collect();
                if d == 2 {
                    let (rt, _) = r(d * i + 1);
                    for sign in [1.0, -1.0] {
                        let e = head.iter().zip(&rt).map(|(h, t)| h + sign * t).collect();
                        lp.nonneg.push((e, 0.0));
                    }
                } else if cone == Cone3::Exact {
                    lp.soc.push(vec![(head, 0.0), r(d * i + 1), r(d * i + 2)]);
                } else {
                    // cos(a) r_t1 + sin(a) r_t2 <= c mu r_n, c = cos(pi / FACES) inscribed.
                    let c = if cone == Cone3::Inner {
                        (std::f64::consts::PI / FACES as f64).cos()
                    } else {
                        1.0
                    };
                    let (t1, _) = r(d * i + 1);
                    let (t2, _) = r(d * i + 2);
                    for f in 0..FACES {
                        let a = 2.0 * std::f64::consts::PI * f as f64 / FACES as f64;
                        let e = (0..=n)
                            .map(|b| c * head[b] - a.cos() * t1[b] - a.sin() * t2[b])
                            .collect();
                        lp.nonneg.push((e, 0.0));
                    }
                }
            }
        } else {
            for c in 0..d {
                lp.zero.push(r(d * i + c));
            }
            lp.nonneg.push(u(d * i));
        }
    }
    lp.zero.push((total, -1.0));
    lp
}

/// The sign pattern that contact set `s` realises at `mu` (its support), or `None` when the leaf
/// is infeasible. Gaps are measured in units of `1 / max |K|`.
fn realised(
    p: &Problem,
    s: &[bool],
    mu: f64,
    cone: Cone3,
) -> Result<Option<Vec<ContactPattern>>, String> {
    let (d, m) = (p.dim(), p.nodes());
    let n = d * m;
    let base = leaf_with(p, s, mu, cone);
    if try_solve(&base, &vec![0.0; n + 1])?.is_none() {
        return Ok(None);
    }
    let kmax = p.stiffness().amax();
    let mut pattern = Vec::with_capacity(m);
    for i in 0..m {
        // max t with entry >= t, t <= 1.
        let mut lp = leaf_with(p, s, mu, cone);
        let mut e = vec![0.0; n + 1];
        if s[i] {
            for b in 0..n {
                e[b] = p.stiffness()[(d * i, b)];
            }
        } else {
            e[d * i] = kmax;
        }
        e[n] = -1.0;
        lp.nonneg.push((e, 0.0));
        let mut cap = vec![0.0; n + 1];
        cap[n] = -1.0;
        lp.nonneg.push((cap, 1.0));
        let mut q = vec![0.0; n + 1];
        q[n] = -1.0;
        // The leaf is feasible, so this program is: a simplex method that says otherwise
        // is overruled by Clarabel.
        // When neither finds it feasible the leaf's feasibility was a round-off call of the
        // simplex method (a leaf on the verge, infeasible to Clarabel): the leaf is dropped.
        let Some(x) = try_solve(&lp, &q)?.or_else(|| solve_conic(&lp, &q).ok().flatten()) else {
            return Ok(None);
        };
        let positive = x[n] > 1e-6;
        pattern.push(match (s[i], positive) {
            (true, true) => ContactPattern::Contact,
            (false, true) => ContactPattern::Separated,
            _ => ContactPattern::Grazing,
        });
    }
    Ok(Some(pattern))
}

/// Contact sets as bit masks.
fn contact_sets(m: usize) -> impl Iterator<Item = Vec<bool>> {
    (1u32..1 << m).map(move |b| (0..m).map(|i| b >> i & 1 == 1).collect())
}

/// The maximal realised patterns by brute force, sorted, and the contact sets that neither
/// solver could decide (on the verge of feasibility: a body pinned between two nodes has a
/// single solution and no interior).
fn brute_patterns(p: &Problem, cone: Cone3) -> (Vec<Vec<ContactPattern>>, Vec<Vec<bool>>) {
    let mut undecided = Vec::new();
    let all: Vec<Vec<ContactPattern>> = contact_sets(p.nodes())
        .filter_map(|s| match realised(p, &s, p.mu(), cone) {
            Ok(q) => q,
            Err(_) => {
                undecided.push(s);
                None
            }
        })
        .filter(|q| q.contains(&ContactPattern::Contact))
        .collect();
    let below = |a: &[ContactPattern], b: &[ContactPattern]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| x == y || *x == ContactPattern::Grazing)
    };
    let mut maximal: Vec<Vec<ContactPattern>> = all
        .iter()
        .filter(|a| !all.iter().any(|b| b != *a && below(a, b)))
        .cloned()
        .collect();
    maximal.sort();
    maximal.dedup();
    (maximal, undecided)
}

/// `mu*` by brute force: the least over contact sets of the least `mu` at which the leaf is
/// feasible (bisection to `1e-8` relative), `None` when no contact set is feasible without a
/// friction limit; and whether some contact set was left out because a program of its
/// bisection was decided by neither solver (then the answer is only an upper bound).
fn brute_critical(p: &Problem, cone: Cone3) -> (Option<(f64, f64)>, bool) {
    let m = p.nodes();
    let n = p.dim() * m;
    let feasible = |s: &[bool], mu: f64| -> Result<bool, String> {
        Ok(try_solve(&leaf_with(p, s, mu, cone), &vec![0.0; n + 1])?.is_some())
    };
    let (mut best, mut floor) = (f64::INFINITY, f64::INFINITY);
    let mut partial = false;
    for s in contact_sets(m) {
        let leaf = || -> Result<Option<(f64, f64)>, String> {
            if !feasible(&s, f64::INFINITY)? {
                return Ok(None);
            }
            let mut hi = if best.is_finite() { best } else { 1.0 };
            if best.is_finite() {
                if !feasible(&s, best)? {
                    return Ok(None);
                }
            } else {
                while !feasible(&s, hi)? {
                    hi *= 2.0;
                    assert!(
                        hi < 1e6,
                        "a leaf feasible without friction limit needs mu < 1e6"
                    );
                }
            }
            // A probe that neither solver decides (the leaf is thin near its threshold) ends
            // the bisection with the bracket so far.
            let mut lo = 0.0;
            while hi - lo > 1e-8 * hi {
                let mid = 0.5 * (lo + hi);
                match feasible(&s, mid) {
                    Ok(true) => hi = mid,
                    Ok(false) => lo = mid,
                    Err(_) => break,
                }
            }
            Ok(Some((lo, hi)))
        };
        match leaf() {
            Ok(Some((lo, hi))) => {
                best = best.min(hi);
                floor = floor.min(lo);
            }
            Ok(None) => {}
            Err(_) => partial = true,
        }
    }
    (best.is_finite().then_some((floor.min(best), best)), partial)
}

fn patterns_of(p: &Problem, method: PatternMethod) -> Vec<Vec<ContactPattern>> {
    let settings = PatternSettings {
        method,
        ..PatternSettings::default()
    };
    let found = enumerate_patterns(p, &settings).expect("a floating body's patterns");
    assert!(
        found.undecided.is_empty(),
        "undecided contact sets: {:?}",
        found.undecided
    );
    let mut q: Vec<_> = found.patterns.iter().map(|p| p.pattern.clone()).collect();
    q.sort();
    q
}

/// The notches of the tests: (dim, m, half angle in degrees, mu, seed).
const NOTCHES: [(usize, usize, f64, f64, u64); 14] = [
    (2, 4, 20.0, 0.6, 1),
    (2, 5, 15.0, 0.5, 2),
    (2, 5, 30.0, 0.9, 3),
    (2, 6, 10.0, 0.4, 4),
    (2, 6, 25.0, 1.5, 5),
    (2, 5, 20.0, 0.2, 6),
    (3, 4, 20.0, 0.8, 7),
    (3, 5, 15.0, 1.0, 8),
    (2, 7, 12.0, 0.7, 9),
    (2, 7, 35.0, 1.2, 10),
    (2, 6, 5.0, 0.3, 11),
    (2, 8, 18.0, 0.9, 12),
    (3, 5, 30.0, 1.4, 13),
    (3, 6, 10.0, 0.6, 14),
];

/// How many of [`NOTCHES`] are 2D.
const PLANE: usize = 10;

fn notch(i: usize) -> Problem {
    let (dim, m, angle, mu, seed) = NOTCHES[i];
    floating_notch(dim, m, angle.to_radians(), mu, seed)
}

#[test]
fn the_patterns_of_a_floating_body_agree_with_the_brute_force_in_displacements() {
    let below = |a: &[ContactPattern], b: &[ContactPattern]| {
        a.iter()
            .zip(b)
            .all(|(x, y)| x == y || *x == ContactPattern::Grazing)
    };
    let contact = |q: &[ContactPattern]| -> Vec<bool> {
        q.iter().map(|&c| c == ContactPattern::Contact).collect()
    };
    let (mut nonempty, mut compared, mut undecided_sets) = (0, 0, 0);
    for i in 0..NOTCHES.len() {
        let p = notch(i);
        // 2D: the exact brute force. 3D: the inscribed pyramid's patterns are realised, and
        // the circumscribed one's contain every realised pattern.
        let (inner, outer) = if p.dim() == 2 {
            let exact = brute_patterns(&p, Cone3::Exact);
            (exact.clone(), exact)
        } else {
            (
                brute_patterns(&p, Cone3::Inner),
                brute_patterns(&p, Cone3::Outer),
            )
        };
        undecided_sets += inner.1.len() + outer.1.len();
        let methods: &[PatternMethod] = if p.dim() == 2 {
            &[
                PatternMethod::Bnb,
                PatternMethod::Faces,
                PatternMethod::Search,
            ]
        } else {
            &[PatternMethod::Bnb, PatternMethod::Faces]
        };
        for &method in methods {
            let found = patterns_of(&p, method);
            nonempty += !found.is_empty() as usize;
            if p.dim() == 2 && inner.1.is_empty() {
                assert_eq!(
                    found,
                    inner.0,
                    "notch {i} ({:?}), {}",
                    NOTCHES[i],
                    method.name()
                );
                compared += 1;
                continue;
            }
            // A pattern whose contact set the brute force could not decide is not asked for.
            for q in &inner.0 {
                assert!(
                    found.iter().any(|f| below(q, f)),
                    "notch {i}, {}: {q:?} missing",
                    method.name()
                );
            }
            for f in found.iter().filter(|f| !outer.1.contains(&contact(f))) {
                assert!(
                    outer.0.iter().any(|q| below(f, q)),
                    "notch {i}, {}: {f:?} not realised",
                    method.name()
                );
            }
        }
    }
    // Most notches wedge at their mu; one (mu below tan of its angle) cannot. Most are
    // compared in full.
    assert!(
        nonempty >= 2 * (NOTCHES.len() - 2),
        "only {nonempty} answers have patterns"
    );
    // bnb, pattern-faces and pattern-search on every plane notch.
    assert_eq!(compared, 3 * PLANE, "answers compared in full");
    eprintln!(
        "{undecided_sets} contact sets undecided by the brute force, {compared} compared in full"
    );
    assert!(
        undecided_sets == 0,
        "{undecided_sets} contact sets undecided by the brute force"
    );
}

/// `mu*` of every method: the brute force's answer over the contact sets it decides is an
/// upper bound of `mu*` (so of every certified lower end); where it decided every contact set it
/// is `mu*` and must lie in the bracket. The methods agree with each other, every witness passes
/// WP's check at `upper`, and no `upper` beats the equilibrium bound `tan(half angle)`.
///
/// (The brute force in displacements often cannot decide a leaf of a floating body near its
/// threshold: the leaf is thin there, the simplex method's point fails its check and Clarabel
/// stalls. Those leaves are left out and counted.)
#[test]
fn the_critical_coefficient_of_a_floating_body_agrees_with_the_brute_force() {
    let (mut decided, mut complete, mut widest) = (0, 0, 0.0f64);
    let mut widest_own = 0.0f64;
    for i in 0..NOTCHES.len() {
        let p = notch(i);
        let (_, _, angle, _, _) = NOTCHES[i];
        let bound = angle.to_radians().tan();
        // 3D: mu* of the circumscribed pyramid is below mu*, the inscribed one's above.
        let (cone, slack) = if p.dim() == 2 {
            (Cone3::Exact, 1.0)
        } else {
            (
                Cone3::Outer,
                1.0 / (std::f64::consts::PI / FACES as f64).cos(),
            )
        };
        let (brute, partial) = brute_critical(&p, cone);
        decided += brute.is_some() as usize;
        complete += !partial as usize;
        if let Some((floor, top)) = brute {
            widest = widest.max((top - floor) / top);
        }
        let mut uppers = Vec::new();
        for method in [
            CriticalMethod::Bnb,
            CriticalMethod::Faces,
            CriticalMethod::Enumerate,
        ] {
            let settings = CriticalSettings {
                method,
                tol: 1e-7,
                ..CriticalSettings::default()
            };
            let c = critical(&p, &settings).expect("mu* of a floating body");
            let name = method.name();
            assert_eq!(c.status, CriticalStatus::Wedged, "notch {i}, {name}");
            let (lower, upper) = (c.lower.unwrap(), c.upper.unwrap());
            // The bracket the certificates reach: asked 1e-7; without the polish of clamped
            // leaves (not written for floating bodies) 3D brackets stop near 3e-5.
            assert!(
                upper - lower <= 1e-4 * upper,
                "notch {i}, {name}: [{lower}, {upper}]"
            );
            widest_own = widest_own.max((upper - lower) / upper);
            if let Some((floor, brute)) = brute {
                // The brute force meets its constraints to about 1e-7 of their terms, so it
                // decides mu* to about 1e-6; [floor, brute] is its bracket.
                assert!(
                    lower <= brute * slack * (1.0 + 1e-5),
                    "notch {i}, {name}: lower end {lower} above the brute force's {brute}"
                );
                if !partial {
                    assert!(
                        upper >= floor * (1.0 - 1e-5),
                        "notch {i}, {name}: {upper} below the brute force's [{floor}, {brute}]"
                    );
                }
            }
            assert!(
                upper >= bound * (1.0 - 1e-9),
                "notch {i}, {name}: mu* {upper} below the equilibrium bound {bound}"
            );
            let w = c.witness.unwrap();
            assert_eq!(w.r.len(), p.dim() * p.nodes());
            wedged::solution::check_solution(&p, upper, &w.u, &w.r).unwrap();
            uppers.push(upper);
        }
        for u in &uppers {
            assert!(
                (u - uppers[0]).abs() <= 1e-5 * uppers[0],
                "notch {i}: {uppers:?}"
            );
        }
    }
    assert!(
        decided >= 6,
        "the brute force decided a leaf of only {decided} notches"
    );
    eprintln!(
        "the brute force decided every contact set of {complete} notches of {}; its widest \
         bracket is {widest:e} of mu*, the library's {widest_own:e}",
        NOTCHES.len()
    );
    assert!(
        complete >= 6,
        "the brute force decided every contact set of {complete} notches"
    );
}

/// Renumbering the nodes and scaling `K` leave the answer unchanged.
#[test]
fn renumbering_and_scaling_a_floating_body_change_nothing() {
    let p = notch(1);
    let m = p.nodes();
    let base = critical(&p, &CriticalSettings::default())
        .unwrap()
        .upper
        .unwrap();
    let order: Vec<usize> = (0..m).rev().collect();
    let permuted = p.permuted(&order);
    let again = critical(&permuted, &CriticalSettings::default())
        .unwrap()
        .upper
        .unwrap();
    assert!((again - base).abs() <= 1e-6 * base, "{again} vs {base}");
    let scaled =
        Problem::floating(2, p.stiffness() * 1e6, p.rigid_modes().clone(), p.mu()).unwrap();
    let again = critical(&scaled, &CriticalSettings::default())
        .unwrap()
        .upper
        .unwrap();
    assert!((again - base).abs() <= 1e-6 * base, "{again} vs {base}");
    for method in [PatternMethod::Bnb, PatternMethod::Search] {
        let mut q = patterns_of(&p, method);
        let mut back: Vec<Vec<ContactPattern>> = patterns_of(&permuted, method)
            .into_iter()
            .map(|x| x.into_iter().rev().collect())
            .collect();
        q.sort();
        back.sort();
        assert_eq!(q, back, "{method}");
        let mut big = patterns_of(&scaled, method);
        big.sort();
        assert_eq!(q, big, "{method}, K scaled by 1e6");
    }
}

/// A body touching one wall only cannot balance its reactions: no wedged configuration at any
/// `mu` is an answer, not an error.
#[test]
fn a_body_on_one_wall_is_never_wedged() {
    let two = notch(1);
    let d = two.dim();
    // Keep the nodes on the left wall (even indices).
    let keep: Vec<usize> = (0..two.nodes()).filter(|i| i % 2 == 0).collect();
    let idx: Vec<usize> = keep
        .iter()
        .flat_map(|&i| (0..d).map(move |c| d * i + c))
        .collect();
    let n = idx.len();
    // The stiffness of the kept nodes: the Schur complement with the others free (their
    // reactions zero) keeps the rigid modes in the null space.
    let g = two.compliance();
    let r = two.rigid_modes();
    let sub_r = DMatrix::from_fn(n, r.ncols(), |a, j| r[(idx[a], j)]);
    // K' = pseudo-inverse of the kept block of G, projected off the kept modes.
    let gk = DMatrix::from_fn(n, n, |a, b| g[(idx[a], idx[b])]);
    let q = sub_r
        .clone()
        .svd(true, false)
        .u
        .unwrap()
        .columns(0, 3)
        .clone_owned();
    let proj = DMatrix::identity(n, n) - &q * q.transpose();
    let k = &proj * (&proj * gk * &proj).pseudo_inverse(1e-10).unwrap() * &proj;
    let p = Problem::floating(d, k, q, 5.0).unwrap();
    let c = critical(&p, &CriticalSettings::default()).unwrap();
    assert_eq!(c.status, CriticalStatus::Never);
    assert_eq!(brute_critical(&p, Cone3::Exact), (None, false));
    let found = enumerate_patterns(&p, &PatternSettings::default()).unwrap();
    assert!(found.patterns.is_empty());
}

#[test]
fn bad_rigid_modes_are_named() {
    let p = notch(0);
    let (k, r) = (p.stiffness().clone(), p.rigid_modes().clone());
    let n = k.nrows();
    let short = r.rows(0, n - 2).clone_owned();
    assert!(matches!(
        Problem::floating(2, k.clone(), short, 1.0),
        Err(ProblemError::RigidModesSize { .. })
    ));
    let mut dependent = r.clone();
    let first = r.column(0).clone_owned();
    dependent.column_mut(2).copy_from(&(first * 2.0));
    assert!(matches!(
        Problem::floating(2, k.clone(), dependent, 1.0),
        Err(ProblemError::RigidModesDependent { mode: 3, .. })
    ));
    let mut off = r.clone();
    off[(0, 1)] += 0.5;
    let e = Problem::floating(2, k.clone(), off, 1.0).unwrap_err();
    assert!(matches!(e, ProblemError::NotRigid { mode: 2, .. }), "{e}");
    assert!(e.to_string().contains("null space"), "{e}");
    // Too few modes declared: K is singular off them.
    let e = Problem::floating(2, k.clone(), r.columns(0, 2).clone_owned(), 1.0).unwrap_err();
    assert!(matches!(e, ProblemError::NotDefiniteOffRigid { .. }), "{e}");
    let e = Problem::floating(2, k.clone(), DMatrix::zeros(n, 4), 1.0).unwrap_err();
    assert!(
        matches!(e, ProblemError::RigidModesCount { count: 4, .. }),
        "{e}"
    );
    let mut nan = r.clone();
    nan[(3, 0)] = f64::NAN;
    assert!(matches!(
        Problem::floating(2, k.clone(), nan, 1.0),
        Err(ProblemError::RigidModesNonFinite { row: 4, col: 1, .. })
    ));
    // The clamped constructor still refuses the singular K.
    assert!(matches!(
        Problem::new(2, k, 1.0),
        Err(ProblemError::NotPositiveDefinite { .. })
    ));
}

/// The methods that are not written for a floating body say so instead of answering.
#[test]
fn methods_that_do_not_apply_refuse_a_floating_body() {
    let p = notch(1);
    let e = wedged::enumerate(&p, &wedged::Settings::default()).unwrap_err();
    assert!(e.to_string().contains("floats"), "{e}");
    let settings = PatternSettings {
        method: PatternMethod::Pyramid { faces: 8 },
        ..PatternSettings::default()
    };
    let e = enumerate_patterns(&p, &settings).unwrap_err();
    assert!(e.to_string().contains("floats"), "{e}");
}

/// `--certify` on a floating body: on every plane notch `bnb` and `pattern-faces` certify
/// their patterns (the same as without `--certify`) and `critical` its bracket (containing the
/// uncertified `mu*`), but for one claim at a leaf's threshold that is degenerate, which is
/// named (`BENCHMARKS.md`, floating bodies). 3D floating bodies are refused (exit 2).
#[test]
fn a_floating_body_is_certified_exactly() {
    let (mut certified, mut named) = (0, 0);
    for i in (0..NOTCHES.len()).filter(|&i| NOTCHES[i].0 == 2) {
        let p = notch(i);
        for method in [PatternMethod::Bnb, PatternMethod::Faces] {
            let settings = PatternSettings {
                method,
                certify: true,
                ..PatternSettings::default()
            };
            let run = enumerate_patterns(&p, &settings).unwrap();
            let mut q: Vec<_> = run.patterns.iter().map(|p| p.pattern.clone()).collect();
            q.sort();
            assert_eq!(q, patterns_of(&p, method), "notch {i}, {}", method.name());
            let c = run.certificate.expect("asked for");
            assert!(
                c.certified,
                "notch {i}, {}: {:?}",
                method.name(),
                c.failures
            );
        }
        let settings = CriticalSettings {
            certify: true,
            ..CriticalSettings::default()
        };
        let c = critical(&p, &settings).unwrap();
        let plain = critical(&p, &CriticalSettings::default()).unwrap();
        let (lower, upper, mu) = (c.lower.unwrap(), c.upper.unwrap(), plain.upper.unwrap());
        assert!(
            lower <= mu * (1.0 + 1e-7) && mu <= upper * (1.0 + 1e-7),
            "notch {i}: [{lower}, {upper}] against {mu}"
        );
        let cert = c.certificate.expect("asked for");
        if !cert.certified {
            eprintln!("notch {i}, critical: {:?}", cert.failures);
        }
        certified += cert.certified as usize;
        named += (!cert.certified && !cert.failures.is_empty()) as usize;
    }
    assert_eq!(certified + named, PLANE);
    assert!(
        certified + 1 >= PLANE,
        "{certified} of {PLANE} brackets certified"
    );
    for i in (0..NOTCHES.len()).filter(|&i| NOTCHES[i].0 == 3) {
        let p = notch(i);
        let settings = CriticalSettings {
            certify: true,
            ..CriticalSettings::default()
        };
        let e = critical(&p, &settings).unwrap_err();
        assert!(e.to_string().contains("3D floating body"), "{e}");
        let settings = PatternSettings {
            certify: true,
            ..PatternSettings::default()
        };
        let e = enumerate_patterns(&p, &settings).unwrap_err();
        assert!(e.to_string().contains("3D floating body"), "{e}");
    }
}
