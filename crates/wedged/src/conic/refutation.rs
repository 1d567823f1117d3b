//! Refutations checked exactly: a search's infeasible program ([`Refutation`]: classes, `mu`,
//! normalisation and the certificate's gap multipliers `z`) re-checked in rational arithmetic
//! on the stored `K` and `mu`. `w = K^-1 z` by the fraction-free elimination of
//! [`crate::rational`] on `K` scaled to integers ([`compliance`]); the sign of
//! `w_n_i + mu ||w_t_i||` at each node by a floating-point filter with a rigorous error bound
//! ([`filter`]) or else exactly ([`sign_c`]). [`Checker`] does this for a search as it goes.
//! A floating body's exact problem and its certificates: [`Compliance`].

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, ToPrimitive, Zero};
use rayon::prelude::*;

use super::program::{Class, Cut, Decision, Formulation, Goal, Norm, Refutation};
use crate::problem::Problem;
use crate::rational::{dyadic, eliminate, integers, kernel_point, rat, Sweep};

/// `K^-1` applied to the normal unit loads, exactly and rounded: `cols[j][a] / den = (K^-1
/// e_{n_j})_a` with one positive integer `den` (not kept: only signs are decided), `near[j][a]`
/// the nearest `f64` and `err[j][a]` a bound on its distance from the exact value.
///
/// A floating body (`k` rigid modes `R`) is certified on the problem as its programs state it,
/// `u = G r + R a`, `R^T r = 0`, with `G` its stored generalised inverse and `R` its stored
/// modes (each `f64` the rational it is), and one bound: `|a_l| <= A sum_i r_n_i`
/// ([`amplitude_exponent`]). The bound is what makes the exact problem the physical one: the
/// modes' normal components have exact dependencies that rounding breaks (the nodes of one
/// straight wall move alike under both translations, and affinely under a turn), and as exact
/// rationals a broken one is a real, if tiny, motion that an unbounded amplitude could use to
/// open or shut gaps at will. `A` is `2^20` times the ratio of `G`'s largest entry to `R`'s,
/// so only states whose rigid motion is a million times the elastic one are left out.
///
/// Its certificates also carry multipliers `y` of `R^T r = 0`: `cols[m + l]` is `R`'s column
/// `l` (on the same scale as `G`'s columns, so that `w = G z + R y` is `sum_j cols[j] (z, y)_j`),
/// and `rigid[l][j] = R[n_j, l]` (same scale) gives `rho = R_n^T z`, the certificate's pull on
/// the amplitudes: with the bound, `z . u_n = w . r + rho . a <= sum_i (c_i + A ||rho||_1)
/// r_n_i`, so each `c_i` is checked shifted by `A ||rho||_1` (exactly).
pub(crate) struct Compliance {
    pub(crate) cols: Vec<Vec<BigInt>>,
    pub(crate) near: Vec<Vec<f64>>,
    pub(crate) err: Vec<Vec<f64>>,
    pub(crate) rigid: Vec<Vec<BigInt>>,
    /// `log2 A` (floating bodies).
    pub(crate) bound: i32,
}

impl Compliance {
    /// Whether the body floats (its certificates carry the balance multipliers).
    fn floating(&self) -> bool {
        !self.rigid.is_empty()
    }

    /// `A ||R_n^T z||_1` in the units of `w` (`z` the gap multipliers), as `(shift, up)`: the
    /// signs of `c_i + A ||rho||_1` are those of `w_n up + shift, w_t up` (`up` a power of two,
    /// so that both are integers).
    fn shift(&self, z: &[BigInt]) -> (BigInt, usize) {
        let rho: BigInt = self
            .rigid
            .iter()
            .map(|row| {
                row.iter()
                    .zip(z)
                    .filter(|(a, b)| !a.is_zero() && !b.is_zero())
                    .map(|(a, b)| a * b)
                    .sum::<BigInt>()
                    .abs()
            })
            .sum();
        if self.bound >= 0 {
            (rho << self.bound as usize, 0)
        } else {
            (rho, (-self.bound) as usize)
        }
    }
}

/// `log2 A` of a floating body's amplitude bound `|a_l| <= A sum_i r_n_i` (see [`Compliance`]):
/// `A = 2^20 max|G| / max|R|`, rounded to a power of two.
pub(crate) fn amplitude_exponent(problem: &Problem) -> i32 {
    let g = problem.compliance().amax();
    let r = problem.rigid_modes().amax();
    let e = 20.0 + (g / r).log2().round();
    if e.is_finite() {
        e.clamp(-1000.0, 1000.0) as i32
    } else {
        20
    }
}

/// Whether a floating body's exact state meets the amplitude bound: `|a_l| <= A sum_i r_n_i`
/// (`a` and `r` integers times the same positive factor, `e = log2 A`).
fn amplitudes_bounded(a: &[BigInt], r: &[BigInt], d: usize, e: i32) -> bool {
    let total: BigInt = r.iter().step_by(d).sum();
    a.iter().all(|x| {
        if e >= 0 {
            x.abs() <= (&total << e as usize)
        } else {
            (x.abs() << (-e) as usize) <= total
        }
    })
}

/// `K` scaled by a power of two to integers (exact).
pub(crate) fn integer_stiffness(problem: &Problem) -> Vec<Vec<BigInt>> {
    integer_matrix(problem.stiffness())
}

/// A floating body's exact data as one matrix of `n` rows, `[G | R]`.
pub(crate) fn floating_matrix(problem: &Problem) -> nalgebra::DMatrix<f64> {
    let (g, rigid) = (problem.compliance(), problem.rigid_modes());
    let (n, k) = (g.nrows(), rigid.ncols());
    let mut joined = nalgebra::DMatrix::zeros(n, n + k);
    joined.columns_mut(0, n).copy_from(g);
    joined.columns_mut(n, k).copy_from(rigid);
    joined
}

/// [`floating_matrix`] scaled by one power of two to integers (exact).
pub(crate) fn integer_floating(problem: &Problem) -> Vec<Vec<BigInt>> {
    integer_matrix(&floating_matrix(problem))
}

/// An exact state of a floating body near the floating-point point `x` (the `n` reactions,
/// then the `k` amplitudes), in the problem of [`Compliance`]'s docs: the unknowns are the
/// reaction components `cols` (every other reaction is zero) and the amplitudes; the
/// conditions are `rows` (each over the `n` reactions, exactly and in floating point), `u_a =
/// 0` for each `a` in `shut`, and `R^T r = 0`. Solved by [`kernel_point`] (the free unknowns
/// taken from `x`); returns `(u, r)` with `u = G r + R a`, integers, each times its own
/// positive factor, or an error when an amplitude `a` breaks its bound
/// ([`amplitudes_bounded`]). `gr` is [`integer_floating`]'s.
pub(crate) fn floating_state(
    problem: &Problem,
    gr: &[Vec<BigInt>],
    cols: &[usize],
    shut: &[usize],
    rows: Vec<(Vec<BigInt>, Vec<f64>)>,
    x: &[f64],
) -> Result<(Vec<BigInt>, Vec<BigInt>), String> {
    let joined = floating_matrix(problem);
    let n = joined.nrows();
    let k = joined.ncols() - n;
    // The unknowns' columns of `[G | R]`: the reactions', then the amplitudes'.
    let unknowns: Vec<usize> = cols.iter().copied().chain(n..n + k).collect();
    let zeros = || (0..k).map(|_| BigInt::zero());
    let (mut exact, mut float) = (Vec::new(), Vec::new());
    for (e, f) in rows {
        exact.push(cols.iter().map(|&a| e[a].clone()).chain(zeros()).collect());
        float.push(
            cols.iter()
                .map(|&a| f[a])
                .chain((0..k).map(|_| 0.0))
                .collect(),
        );
    }
    for l in 0..k {
        exact.push(
            cols.iter()
                .map(|&a| gr[a][n + l].clone())
                .chain(zeros())
                .collect(),
        );
        float.push(
            cols.iter()
                .map(|&a| joined[(a, n + l)])
                .chain((0..k).map(|_| 0.0))
                .collect(),
        );
    }
    for &a in shut {
        exact.push(unknowns.iter().map(|&c| gr[a][c].clone()).collect());
        float.push(unknowns.iter().map(|&c| joined[(a, c)]).collect());
    }
    let start: Vec<f64> = unknowns.iter().map(|&c| x[c]).collect();
    let point = kernel_point(exact, float, &start);
    let mut reactions = vec![BigInt::zero(); n];
    for (&a, v) in cols.iter().zip(&point) {
        reactions[a] = v.clone();
    }
    let u = (0..n)
        .map(|a| {
            unknowns
                .iter()
                .zip(&point)
                .filter(|(&c, v)| !v.is_zero() && !gr[a][c].is_zero())
                .map(|(&c, v)| &gr[a][c] * v)
                .sum()
        })
        .collect();
    let bound = amplitude_exponent(problem);
    if !amplitudes_bounded(&point[cols.len()..], &reactions, problem.dim(), bound) {
        return Err("exact witness: a rigid amplitude beyond its bound (refutation.rs)".into());
    }
    Ok((u, reactions))
}

/// A matrix scaled by one power of two to integers (exact).
fn integer_matrix(k: &nalgebra::DMatrix<f64>) -> Vec<Vec<BigInt>> {
    let parts: Vec<Vec<(BigInt, i32)>> = (0..k.nrows())
        .map(|a| (0..k.ncols()).map(|b| dyadic(k[(a, b)])).collect())
        .collect();
    let emin = parts
        .iter()
        .flatten()
        .filter(|(x, _)| !x.is_zero())
        .map(|&(_, e)| e)
        .min()
        .unwrap_or(0);
    parts
        .into_iter()
        .map(|row| {
            row.into_iter()
                .map(|(x, e)| x << ((e - emin) as usize))
                .collect()
        })
        .collect()
}

/// Solves `K X = E_n` by fraction-free Gauss-Jordan elimination (Bareiss's rule applied above
/// and below the pivot: every division is exact, every entry an integer minor), on `K` scaled
/// to integers. At the end every diagonal entry is `det K` (scaled) and the right block is
/// `det K * X`. `None` when `K` is singular. A floating body's are read from `[G | R]`.
pub(crate) fn compliance(problem: &Problem) -> Option<Compliance> {
    let (d, m) = (problem.dim(), problem.nodes());
    let n = d * m;
    if problem.is_floating() {
        let joined = floating_matrix(problem);
        let ints = integer_matrix(&joined);
        let k = joined.ncols() - n;
        // Columns of G at the normal components, then R's; G and R are exact as stored.
        let column = |j: usize| if j < m { d * j } else { n + j - m };
        return Some(Compliance {
            cols: (0..m + k)
                .map(|j| (0..n).map(|a| ints[a][column(j)].clone()).collect())
                .collect(),
            near: (0..m + k)
                .map(|j| (0..n).map(|a| joined[(a, column(j))]).collect())
                .collect(),
            err: vec![vec![0.0; n]; m + k],
            rigid: (0..k)
                .map(|l| (0..m).map(|j| ints[d * j][n + l].clone()).collect())
                .collect(),
            bound: amplitude_exponent(problem),
        });
    }
    let mut a: Vec<Vec<BigInt>> = integer_stiffness(problem)
        .into_iter()
        .enumerate()
        .map(|(i, mut row)| {
            row.extend((0..m).map(|j| {
                if i == d * j {
                    BigInt::one()
                } else {
                    BigInt::zero()
                }
            }));
            row
        })
        .collect();
    let order: Vec<usize> = (0..n).collect();
    if eliminate(&mut a, &order, Sweep::All).len() != n {
        return None;
    }
    let mut cols = Vec::with_capacity(m);
    let mut near = Vec::with_capacity(m);
    let mut err = Vec::with_capacity(m);
    for j in 0..m {
        let (mut c, mut nr, mut er) = (Vec::new(), Vec::new(), Vec::new());
        for (i, row) in a.iter().enumerate() {
            // Row i reads [D e_i | D (K^-1 E_n)_i] (row swaps leave the solution unchanged).
            let (num, diag) = (&row[n + j], &row[i]);
            let x = BigRational::new(num.clone(), diag.clone());
            let f = x.to_f64().unwrap_or(f64::NAN);
            let e = (&x - rat(f)).abs().to_f64().unwrap_or(f64::INFINITY);
            c.push(if diag.is_negative() {
                -num
            } else {
                num.clone()
            });
            nr.push(f);
            er.push(e * 2.0 + f64::MIN_POSITIVE);
        }
        cols.push(c);
        near.push(nr);
        err.push(er);
    }
    Some(Compliance {
        cols,
        near,
        err,
        rigid: Vec::new(),
        bound: 0,
    })
}

/// The sign of `c = w_n + mu ||w_t||` (`mu = None`: infinite, `w_t` must vanish).
pub(crate) fn sign_c(wn: &BigInt, wt: &[BigInt], mu: Option<&BigRational>) -> std::cmp::Ordering {
    use std::cmp::Ordering::*;
    let tangential_zero = wt.iter().all(|x| x.is_zero());
    if tangential_zero {
        return wn.sign_cmp();
    }
    let Some(mu) = mu else {
        return Greater;
    };
    if !wn.is_negative() {
        return Greater;
    }
    // mu^2 |w_t|^2 against w_n^2, with mu = p / q.
    let t2: BigInt = wt.iter().map(|x| x * x).sum();
    let (p, q) = (mu.numer(), mu.denom());
    (p * p * t2).cmp(&(q * q * (wn * wn)))
}

pub(crate) trait SignCmp {
    fn sign_cmp(&self) -> std::cmp::Ordering;
}

impl SignCmp for BigInt {
    fn sign_cmp(&self) -> std::cmp::Ordering {
        self.cmp(&BigInt::zero())
    }
}

/// Checks one refutation exactly; `Err` says why it fails. A certificate that fails as it
/// stands is repaired once ([`repair`]) and checked again.
pub(crate) fn check_refutation(
    problem: &Problem,
    comp: &Compliance,
    f: &Refutation,
) -> Result<(), String> {
    let (d, m) = (problem.dim(), problem.nodes());
    let v: Vec<usize> = (0..m)
        .filter(|&i| matches!(f.classes[i], Class::Contact | Class::Free))
        .collect();
    if v.is_empty() {
        return Ok(());
    }
    let k = comp.cols.len() - m;
    if f.z.len() != m || f.z.iter().chain(&f.balance).any(|x| !x.is_finite()) {
        return Err("the solver gave no usable certificate".into());
    }
    // z with the sign conditions of its rows (then a floating body's balance multipliers, any
    // sign; zero when the solver gave none).
    let zf: Vec<f64> = (0..m)
        .map(|j| match f.classes[j] {
            Class::Separated | Class::Free => f.z[j].max(0.0),
            Class::Contact | Class::Grazing => f.z[j],
        })
        .chain((0..k).map(|l| f.balance.get(l).copied().unwrap_or(0.0)))
        .collect();
    if zf.iter().all(|&x| x == 0.0) {
        return Err("the certificate's multipliers are all zero".into());
    }
    verdict(comp, f, d, &v, &zf, None)
        .or_else(|e| match repair(comp, f, d, &v, &zf) {
            Some(z) if verdict(comp, f, d, &v, &zf, Some(&z)).is_ok() => Ok(()),
            _ => Err(e),
        })
        .or_else(|e| {
            // A floating body held off by balance alone (the reactions that may press cannot
            // balance): the solver's gap multipliers are noise beside `y`, and `z = 0` with
            // its `y` is the certificate.
            if !comp.floating() {
                return Err(e);
            }
            let mut alone = zf.clone();
            alone[..m].iter_mut().for_each(|x| *x = 0.0);
            let exact = integers(&alone);
            verdict(comp, f, d, &v, &alone, Some(&exact)).map_err(|_| e)
        })
}

/// Unit round-off of `f64`.
pub(crate) const U: f64 = f64::EPSILON / 2.0;

/// The sign of `c_i = w_n_i + mu ||w_t_i||` (`w = K^-1 Z`) from floating point with a rigorous
/// error bound, when that bound decides it (`Less` or `Greater`; `None`: evaluate exactly).
///
/// `w_a = sum_j X_aj z_j` with `X` rounded (`near`, off by at most `err`): the sum is off by at
/// most `sum_j err_aj |z_j|` from the data and `(m + 2) u sum_j |near_aj z_j|` from its
/// rounding (the standard bound `gamma_m`, `u` the unit round-off, with room to spare). The
/// tangential norm moves by at most the norm of its entries' bounds, and the last few
/// operations by a few `u` of their magnitudes; the bound used is twice all that.
pub(crate) fn filter(
    comp: &Compliance,
    z: &[f64],
    d: usize,
    i: usize,
    mu: f64,
) -> Option<std::cmp::Ordering> {
    let m = z.len();
    let gamma = (m as f64 + 2.0) * U;
    let entry = |a: usize| -> (f64, f64) {
        let (mut w, mut abs, mut data) = (0.0f64, 0.0f64, 0.0f64);
        for j in (0..m).filter(|&j| z[j] != 0.0) {
            let t = comp.near[j][a] * z[j];
            w += t;
            abs += t.abs();
            data += comp.err[j][a] * z[j].abs();
        }
        (
            w,
            2.0 * (data + gamma * abs) + f64::MIN_POSITIVE * 4.0 * m as f64,
        )
    };
    let (wn, en) = entry(d * i);
    let tangential: Vec<(f64, f64)> = (1..d).map(|c| entry(d * i + c)).collect();
    let norm = tangential.iter().map(|(w, _)| w * w).sum::<f64>().sqrt();
    let spread = tangential.iter().map(|(_, e)| e * e).sum::<f64>().sqrt();
    let norm_hi = (norm + spread) * (1.0 + 8.0 * U);
    let norm_lo = ((norm - spread) * (1.0 - 8.0 * U)).max(0.0);
    if !mu.is_finite() {
        // c = +infinity unless w_t = 0 exactly, which floating point cannot show.
        return (norm_lo > 0.0).then_some(std::cmp::Ordering::Greater);
    }
    let slack = 8.0 * U * (wn.abs() + en + mu * norm_hi) + f64::MIN_POSITIVE;
    let hi = wn + en + mu * norm_hi + slack;
    let lo = wn - en + mu * norm_lo - slack;
    if hi < 0.0 {
        Some(std::cmp::Ordering::Less)
    } else if lo > 0.0 {
        Some(std::cmp::Ordering::Greater)
    } else {
        None
    }
}

/// Names a refutation in a failure line.
pub(crate) fn describe(f: &Refutation) -> String {
    let classes = crate::conic::program::describe(&f.classes);
    let norm = match &f.cut {
        Cut::Sum => "sum r_n = 1".to_string(),
        Cut::Pressed(p) => format!("{} nodes pressed", p.len()),
        Cut::Gap(j) => format!("the gap of node {} open", j + 1),
    };
    format!("infeasibility at mu = {} of [{classes}] ({norm})", f.mu)
}

/// The exact check of refutations of one problem, as they are made (a search that relies on
/// a decision only when its certificate passes). Holds the exact compliance.
pub(crate) struct Checker {
    problem: Problem,
    comp: Option<Compliance>,
}

impl Checker {
    pub(crate) fn new(problem: &Problem) -> Checker {
        Checker {
            problem: problem.clone(),
            comp: compliance(problem),
        }
    }

    pub(crate) fn check(&self, f: &Refutation) -> Result<(), String> {
        match &self.comp {
            None => Err("K is singular in exact arithmetic".into()),
            Some(comp) => check_refutation(&self.problem, comp, f),
        }
    }
}

/// The exact check of a refutation's multipliers: `exact` (integers up to one positive
/// factor), or when `None` the floats `zf` themselves, whose signs of `c_i` are first tried by
/// the floating-point [`filter`].
pub(crate) fn verdict(
    comp: &Compliance,
    f: &Refutation,
    d: usize,
    v: &[usize],
    zf: &[f64],
    exact: Option<&[BigInt]>,
) -> Result<(), String> {
    let (m, width) = (f.classes.len(), zf.len());
    // The exact multipliers, made when first needed.
    let made = std::cell::OnceCell::new();
    let zi = || -> &[BigInt] { exact.unwrap_or_else(|| made.get_or_init(|| integers(zf))) };
    if let Some(z) = exact {
        if z.iter().all(|x| x.is_zero()) {
            return Err("the repaired multipliers are all zero".into());
        }
        if let Some(j) = (0..m)
            .find(|&j| matches!(f.classes[j], Class::Separated | Class::Free) && z[j].is_negative())
        {
            return Err(format!(
                "the repaired multiplier of node {}'s gap is negative",
                j + 1
            ));
        }
    }
    // w (times a positive factor), exactly.
    let w = |a: usize| -> BigInt {
        let zi = zi();
        (0..width)
            .filter(|&j| !zi[j].is_zero())
            .map(|j| &comp.cols[j][a] * &zi[j])
            .sum()
    };
    let mu = f.mu.is_finite().then(|| rat(f.mu));
    let mut some_negative_pressed = false;
    let strict_needed = f.cut == Cut::Sum;
    // A floating body's c_i are shifted by A ||R_n^T z||_1 (exactly; no filter).
    let shift = comp.floating().then(|| comp.shift(&zi()[..m]));
    for &i in v {
        let s = (exact.is_none() && shift.is_none())
            .then(|| filter(comp, zf, d, i, f.mu))
            .flatten()
            .unwrap_or_else(|| {
                let (mut wn, mut wt) = (w(d * i), (1..d).map(|c| w(d * i + c)).collect::<Vec<_>>());
                if let Some((by, up)) = &shift {
                    wn = (wn << *up) + by;
                    wt.iter_mut().for_each(|x| *x <<= *up);
                }
                sign_c(&wn, &wt, mu.as_ref())
            });
        match s {
            std::cmp::Ordering::Less => {
                if matches!(&f.cut, Cut::Pressed(p) if p.contains(&i)) {
                    some_negative_pressed = true;
                }
            }
            std::cmp::Ordering::Equal if !strict_needed => {}
            _ => {
                return Err(format!(
                    "node {}: w_n + mu ||w_t|| is {} (needs < 0{})",
                    i + 1,
                    if s == std::cmp::Ordering::Equal {
                        "0"
                    } else {
                        "positive"
                    },
                    if strict_needed { "" } else { " or = 0" }
                ))
            }
        }
    }
    match f.cut {
        Cut::Pressed(_) if !some_negative_pressed => {
            Err("no pressed node has w_n + mu ||w_t|| < 0".into())
        }
        Cut::Gap(j) if !zi()[j].is_positive() => Err(format!(
            "the multiplier of node {}'s gap, the one claimed shut, is not positive",
            j + 1
        )),
        _ => Ok(()),
    }
}

/// A repaired certificate, for a claim that some node cannot be pressed or some gap cannot
/// open (cut [`Cut::Pressed`] or [`Cut::Gap`]), or a claim at `mu = infinity`. Such claims are
/// degenerate: every valid certificate has `w_i = K^-1 Z` exactly zero at the nodes that some
/// solution presses while sticking (`w_i . r_i = c_i r_n_i` must vanish on an open set of
/// `r_i`), `c_i = 0` exactly (2D: `w_n + sigma mu w_t = 0`, `sigma` the sign of `w_t`) at those
/// that only slip, and `w_t = 0` at infinite `mu`; floating point leaves a hair there, on
/// either side. The repair makes them exact: these linear conditions on `z` (chosen where the
/// floating-point `w` is within 1e-6 of them, relative to its scale), together with `z_j = 0`
/// on the gap rows whose multiplier is negligible, are solved exactly with the other entries of
/// `z` kept as they are (complete pivoting in floating point picks which are solved for).
/// `None` when there is nothing to repair. For a floating body `R_n^T z = 0` joins the
/// conditions (so that no `c_i` is shifted), for every claim. The unknowns solved for are
/// picked among those a change cannot flip the sign of (`z` of the rows `u_n = 0`, `y`) or
/// large ones.
pub(crate) fn repair(
    comp: &Compliance,
    f: &Refutation,
    d: usize,
    v: &[usize],
    zf: &[f64],
) -> Option<Vec<BigInt>> {
    // A claim with `sum r_n = 1` at a finite `mu` needs every `c_i < 0` strictly: nothing to
    // make exact but a floating body's amplitudes.
    let degenerate = !(f.cut == Cut::Sum && f.mu.is_finite());
    if !degenerate && !comp.floating() {
        return None;
    }
    let (m, width) = (f.classes.len(), zf.len());
    let wf = |a: usize| -> f64 { (0..width).map(|j| comp.near[j][a] * zf[j]).sum() };
    let w: Vec<Vec<f64>> = v
        .iter()
        .map(|&i| (0..d).map(|c| wf(d * i + c)).collect())
        .collect();
    let norm = |x: &[f64]| x.iter().map(|y| y * y).sum::<f64>().sqrt();
    // A multiplier's size is that of its term in `w` (a floating body's `z` and `y` have
    // different units).
    let size: Vec<f64> = (0..width)
        .map(|j| zf[j].abs() * comp.near[j].iter().fold(0.0f64, |a, x| a.max(x.abs())))
        .collect();
    let big_z = size.iter().fold(0.0f64, |a, &x| a.max(x));
    // The scale a hair of `w` is measured against: its largest entry on the nodes with a
    // reaction, or, when even that is a hair of the terms `w` sums (a claim about a block of
    // `K` that the nodes with a reaction do not reach, so that `w` vanishes on all of them:
    // `tests/search.rs`'s block problems), the largest term.
    let big_w = w.iter().fold(0.0f64, |a, x| a.max(norm(x)));
    let big_w = if big_w <= 1e-6 * big_z { big_z } else { big_w };
    let row = |a: usize| -> (Vec<BigInt>, Vec<f64>) {
        (
            (0..width).map(|j| comp.cols[j][a].clone()).collect(),
            (0..width).map(|j| comp.near[j][a]).collect(),
        )
    };
    let (mut exact, mut float) = (Vec::new(), Vec::new());
    // A floating body's amplitudes: R_n^T z = 0, so that the shift of every c_i vanishes (a
    // degenerate claim needs some c_i = 0 exactly).
    for (l, row) in comp.rigid.iter().enumerate() {
        let mut e = row.clone();
        e.resize(width, BigInt::zero());
        exact.push(e);
        // R[n_j, l] (the column of mode l holds R as stored).
        float.push(
            (0..width)
                .map(|j| if j < m { comp.near[m + l][d * j] } else { 0.0 })
                .collect(),
        );
    }
    for (&i, wi) in v.iter().zip(&w).filter(|_| degenerate) {
        let wt = norm(&wi[1..]);
        let components: Vec<usize> = if norm(wi) <= 1e-6 * big_w {
            (0..d).collect()
        } else if !f.mu.is_finite() {
            (1..d).collect()
        } else {
            Vec::new()
        };
        for c in components {
            let (e, x) = row(d * i + c);
            exact.push(e);
            float.push(x);
        }
        if d == 2
            && f.mu.is_finite()
            && norm(wi) > 1e-6 * big_w
            && (wi[0] + f.mu * wt).abs() <= 1e-6 * (wi[0].abs() + f.mu * wt)
        {
            // q w_n + sigma p w_t = 0, mu = p / q.
            let mu = rat(f.mu);
            let sigma = if wi[1] < 0.0 { -1 } else { 1 };
            let (p, q) = (mu.numer() * BigInt::from(sigma), mu.denom().clone());
            let (en, xn) = row(d * i);
            let (et, xt) = row(d * i + 1);
            exact.push(en.iter().zip(&et).map(|(a, b)| &q * a + &p * b).collect());
            float.push(
                xn.iter()
                    .zip(&xt)
                    .map(|(a, b)| a + sigma as f64 * f.mu * b)
                    .collect(),
            );
        }
    }
    if exact.is_empty() {
        return None;
    }
    for j in 0..m {
        if matches!(f.classes[j], Class::Separated | Class::Free) && size[j] <= 1e-9 * big_z {
            let mut e = vec![BigInt::zero(); width];
            e[j] = BigInt::one();
            let mut x = vec![0.0; width];
            x[j] = 1.0;
            exact.push(e);
            float.push(x);
        }
    }
    // The unknowns solved for are taken where a change cannot flip a sign that matters: a
    // multiplier of a row `u_n_j >= 0` weighs its share of the largest, the others (any sign)
    // weigh 1, so that pivoting prefers them (the float rows only choose the pivots).
    let weight: Vec<f64> = (0..width)
        .map(|j| match f.classes.get(j) {
            Some(Class::Separated | Class::Free) => size[j] / big_z.max(f64::MIN_POSITIVE),
            _ => 1.0,
        })
        .collect();
    for row in float.iter_mut() {
        row.iter_mut().zip(&weight).for_each(|(x, w)| *x *= w);
    }
    Some(kernel_point(exact, float, zf))
}

/// The refutation `f`'s program solved anew at `mu`, with its own normalisation or, when `sum`,
/// with `sum r_n = 1`: its new refutation, or `None` when it is not infeasible there. (What
/// `critical::certify::certify` does with a certificate that fails its exact check.)
pub(crate) fn solve_again(
    problem: &Problem,
    f: &Refutation,
    mu: f64,
    sum: bool,
) -> Option<Refutation> {
    let mut form = Formulation::new(problem);
    form.refutations = Some(std::sync::Mutex::new(Vec::new()));
    let norm = if sum { Norm::Sum } else { f.cut.norm() };
    match form.decide_at(&f.classes, mu, norm, Goal::Feasible) {
        Decision::No => form.take_refutations().pop(),
        _ => None,
    }
}

/// Failures listed by name; the rest are counted.
const LISTED: usize = 5;

/// What [`check_all`] found.
pub(crate) struct Checked {
    /// One line for the count of failed refutations, then the first few by name; or that `K`
    /// is singular in exact arithmetic.
    pub(crate) failures: Vec<String>,
    /// Refutations that failed.
    pub(crate) failed: usize,
    /// Refutations that failed as they stood but passed once solved again.
    pub(crate) resolved: usize,
    /// `K` is singular in exact arithmetic: nothing could be checked.
    pub(crate) singular: bool,
}

/// Checks every refutation of a finished run exactly. One that fails as it stands is solved
/// again at `lower` (when it claims `mu` at or above it) by `again(refutation, mu, sum)`, with
/// its own normalisation and then with `sum r_n = 1`; a new certificate that passes replaces
/// it.
pub(crate) fn check_all(
    problem: &Problem,
    refutations: &[Refutation],
    lower: Option<f64>,
    again: &(dyn Fn(&Refutation, f64, bool) -> Option<Refutation> + Sync),
) -> Checked {
    let mut failures = Vec::new();
    let resolved = std::sync::atomic::AtomicUsize::new(0);
    let comp = compliance(problem);
    let results: Vec<Result<(), String>> = match &comp {
        None => {
            failures.push("K is singular in exact arithmetic".into());
            Vec::new()
        }
        Some(comp) => refutations
            .par_iter()
            .map(|f| {
                check_refutation(problem, comp, f).or_else(|e| {
                    let retry = lower.filter(|&l| l <= f.mu && l.is_finite());
                    for sum in [false, true] {
                        let Some(mu) = retry else { break };
                        if let Some(g) = again(f, mu, sum) {
                            if check_refutation(problem, comp, &g).is_ok() {
                                resolved.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                                return Ok(());
                            }
                        }
                    }
                    Err(format!("{}: {e}", describe(f)))
                })
            })
            .collect(),
    };
    let failed: Vec<String> = results.into_iter().filter_map(Result::err).collect();
    let count = failed.len();
    if count > 0 {
        failures.push(format!(
            "{count} of {} infeasibility certificates failed their exact check",
            refutations.len()
        ));
        failures.extend(failed.into_iter().take(LISTED));
    }
    Checked {
        failures,
        failed: count,
        resolved: resolved.into_inner(),
        singular: comp.is_none(),
    }
}
