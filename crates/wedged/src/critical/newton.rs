//! A leaf's threshold by Newton's method on its optimality conditions, and the certificate
//! those conditions give just below it.
//!
//! The conic solver's points put a 3D leaf's threshold about 1e-7 (relative) above the true
//! one, and the least-norm certificate's tight system (`polish.rs`) seldom shows a clean pole
//! in 3D, where each slipping node's direction moves with `mu`. So a leaf whose threshold
//! `polish::sharpen` cannot locate is polished here, from the exact point of ratio `theta` the
//! search already has:
//!
//! ```text
//! min theta  subject to  u_n_k = (G r)_k = 0  (k in the contact set, and the closed gaps off it),
//!                        sum r_n = 1,   ||r_t_j|| = theta r_n_j  (j slipping),
//! ```
//!
//! over the reactions of the pressed nodes (the others stay zero) and `theta`. Its first-order
//! conditions, with multipliers `alpha` of the gap rows, `gamma` of the sum and `beta` of the
//! slip rows, are a square system: `w = G^T alpha` has `w_j = (gamma - beta_j theta, beta_j
//! e_j)` at every pressed node (`e_j` the direction of `r_t_j`; `beta_j = 0` at a sticking node),
//! `sum beta_j r_n_j = 1`, and the constraints. Newton's method on it from the solver's point
//! (multipliers fitted by least squares) converges quadratically where the optimum is regular.
//!
//! The multipliers are the certificate. Multiplying the pressed nodes' conditions by `r_j` and
//! summing gives `gamma = 0`, so at `mu` below the threshold every slipping node has
//! `c_j = w_n_j + mu ||w_t_j|| = -beta_j (theta - mu) < 0`: `alpha` refutes the leaf at every
//! `mu < theta` where the other contact nodes also have `c_j < 0` (a sticking node has `c_j =
//! 0`; it gets a small correction, below). It is checked in floating point against every
//! inequality by `polish::check`, with a margin far above round-off, and, when certificates are
//! kept, re-checked exactly like every other. Nothing here is trusted unchecked: a point that
//! is not optimal, or multipliers of the wrong sign, fail the check and the leaf keeps the
//! solver's bracket.

use nalgebra::{DMatrix, DVector};

use super::polish;
use crate::conic::program::{Formulation, Refutation};
use crate::solution::tangential;

/// A node whose ratio is within this share of `theta` starts as slipping.
const SLIPPING: f64 = 1e-5;
/// A gap off the contact set below this (scaled) is a closed row.
const CLOSED: f64 = 1e-8;
/// Newton steps at most.
const STEPS: usize = 30;
/// Rounds of moving nodes between slipping and sticking, or dropping them.
const ROUNDS: usize = 8;
/// A node pressed less than this share of the most pressed one may be dropped.
const FAINT: f64 = 1e-3;

/// A polished threshold: `theta`, reactions there (made exact by the caller), and the
/// optimality multipliers of the scaled gap rows (zero on the open ones).
pub(crate) struct Polished {
    pub theta: f64,
    pub r: Vec<f64>,
    alpha: Vec<f64>,
    /// The pressed nodes that stick (`beta_j = 0`).
    sticking: Vec<usize>,
}

/// Newton's method on the leaf's optimality conditions from the exact point `r` of ratio
/// `theta`; `None` when it does not converge to a point whose multipliers have the right signs.
pub(crate) fn polish(
    form: &Formulation,
    contact: &[bool],
    theta: f64,
    r: &[f64],
) -> Option<Polished> {
    let (d, m) = (form.dim, form.m);
    if form.modes > 0 || !(theta > 0.0 && theta.is_finite()) {
        return None;
    }
    let mut pressed: Vec<usize> = (0..m).filter(|&i| contact[i] && r[d * i] > 0.0).collect();
    let top = pressed.iter().map(|&j| r[d * j]).fold(0.0f64, f64::max);
    let rows: Vec<usize> = (0..m)
        .filter(|&k| contact[k] || form.gap_of(r, k) < CLOSED)
        .collect();
    let ratio = |j: usize| tangential(r, d, j) / r[d * j];
    let mut slip: Vec<bool> = pressed
        .iter()
        .map(|&j| ratio(j) >= theta * (1.0 - SLIPPING))
        .collect();
    // A pressed node whose pressure vanishes at the optimum (it grazes there) is dropped, the
    // least pressed first: Newton's method fails on it (its slip direction is undefined at
    // zero) or takes its pressure below zero.
    let drop = |pressed: &mut Vec<usize>, slip: &mut Vec<bool>, p: usize| {
        pressed.remove(p);
        slip.remove(p);
    };
    for _ in 0..ROUNDS {
        if pressed.is_empty() {
            return None;
        }
        let sys = System {
            form,
            pressed: &pressed,
            rows: &rows,
            slip: &slip,
        };
        let Some(Optimum {
            theta,
            x,
            alpha,
            beta,
        }) = sys.solve(theta, r)
        else {
            let least = (0..pressed.len())
                .min_by(|&a, &b| r[d * pressed[a]].total_cmp(&r[d * pressed[b]]))?;
            if r[d * pressed[least]] >= FAINT * top {
                return None;
            }
            drop(&mut pressed, &mut slip, least);
            continue;
        };
        if let Some(p) = (0..pressed.len()).find(|&p| x[d * p] <= 0.0) {
            drop(&mut pressed, &mut slip, p);
            continue;
        }
        // A sticking node whose ratio rose past theta slips; a slipping node pulled the wrong
        // way (beta < 0) sticks.
        let mut changed = false;
        for p in 0..pressed.len() {
            let t = tangential(&x[d * p..], d, 0) / x[d * p];
            if !slip[p] && t > theta * (1.0 + 1e-12) {
                slip[p] = true;
                changed = true;
            } else if slip[p] && beta[p] < 0.0 {
                slip[p] = false;
                changed = true;
            }
        }
        if changed {
            continue;
        }
        // Closed gaps off the contact set must be held by nonnegative multipliers.
        if rows
            .iter()
            .zip(&alpha)
            .any(|(&k, &a)| !contact[k] && a < 0.0)
        {
            return None;
        }
        let mut full = vec![0.0; d * m];
        for (p, &j) in pressed.iter().enumerate() {
            full[d * j..d * j + d].copy_from_slice(&x[d * p..d * p + d]);
        }
        let mut y = vec![0.0; m];
        for (&k, &a) in rows.iter().zip(&alpha) {
            y[k] = a;
        }
        let sticking = pressed
            .iter()
            .zip(&slip)
            .filter(|&(_, &s)| !s)
            .map(|(&j, _)| j)
            .collect();
        return Some(Polished {
            theta,
            r: full,
            alpha: y,
            sticking,
        });
    }
    None
}

impl Polished {
    /// A refutation of the leaf at `mu` (below the threshold) from the multipliers, checked in
    /// floating point (`polish::check`).
    pub(crate) fn refute(
        &self,
        form: &Formulation,
        contact: &[bool],
        mu: f64,
    ) -> Option<Refutation> {
        if self.sticking.is_empty() {
            return polish::check(form, contact, &self.alpha, mu);
        }
        // A sticking node has c_j = 0 from alpha alone: add a correction y1 of the contact
        // rows with w_j = (-1, 0) at the sticking nodes (least norm), under a multiple of
        // alpha large enough that the slipping nodes stay negative.
        let (d, m) = (form.dim, form.m);
        let cols: Vec<usize> = (0..m).filter(|&k| contact[k]).collect();
        let a = DMatrix::from_fn(d * self.sticking.len(), cols.len(), |row, col| {
            form.gap_row(cols[col])[d * self.sticking[row / d] + row % d]
        });
        let b = DVector::from_fn(d * self.sticking.len(), |row, _| {
            if row % d == 0 {
                -1.0
            } else {
                0.0
            }
        });
        let svd = a.svd(true, true);
        let largest = svd.singular_values.iter().fold(0.0f64, |a, &x| a.max(x));
        let y1 = svd.solve(&b, 1e-12 * largest).ok()?;
        let mut correction = vec![0.0; m];
        for (c, &k) in cols.iter().enumerate() {
            correction[k] = y1[c];
        }
        let size = |y: &[f64]| y.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let (sa, sc) = (size(&self.alpha), size(&correction));
        if sa == 0.0 || sc == 0.0 {
            return None;
        }
        // alpha's slipping terms are of order |alpha| (theta - mu) / theta: scale it to
        // dominate the correction's by about 1e3.
        let gap = (self.theta - mu) / self.theta;
        [1e3, 1e5, 1e1].iter().find_map(|&f| {
            let k = f * sc / (sa * gap);
            let y: Vec<f64> = self
                .alpha
                .iter()
                .zip(&correction)
                .map(|(a, c)| k * a + c)
                .collect();
            polish::check(form, contact, &y, mu)
        })
    }
}

/// A solution of the optimality system: `theta`, the pressed nodes' reactions (`d` each), the
/// gap rows' multipliers and the slip rows' (0 at sticking nodes).
struct Optimum {
    theta: f64,
    x: Vec<f64>,
    alpha: Vec<f64>,
    beta: Vec<f64>,
}

/// The optimality system for one choice of slipping nodes.
struct System<'a, 'b> {
    form: &'a Formulation<'b>,
    pressed: &'a [usize],
    rows: &'a [usize],
    slip: &'a [bool],
}

impl System<'_, '_> {
    /// Newton's method from `(theta, r)`, if it converges to round-off.
    fn solve(&self, theta: f64, r: &[f64]) -> Option<Optimum> {
        let d = self.form.dim;
        let (p, q) = (self.pressed.len(), self.rows.len());
        let mut x: Vec<f64> = self
            .pressed
            .iter()
            .flat_map(|&j| r[d * j..d * j + d].to_vec())
            .collect();
        let mut theta = theta;
        let (mut alpha, mut gamma, mut beta) = self.fit(theta, &x)?;
        let n = d * p + 1 + q + 1 + p;
        let mut last = f64::INFINITY;
        for _ in 0..STEPS {
            let (jac, f) = self.linearise(theta, &x, &alpha, gamma, &beta, n);
            let norm = f.norm();
            if !norm.is_finite() {
                return None;
            }
            if norm <= 1e-14 || norm >= last {
                break;
            }
            last = norm;
            let step = jac.lu().solve(&(-f))?;
            if !step.iter().all(|v| v.is_finite()) {
                return None;
            }
            for (v, s) in x.iter_mut().zip(step.iter()) {
                *v += s;
            }
            theta += step[d * p];
            let o = d * p + 1;
            for (a, s) in alpha.iter_mut().zip(step.iter().skip(o)) {
                *a += s;
            }
            gamma += step[o + q];
            for (b, s) in beta.iter_mut().zip(step.iter().skip(o + q + 1)) {
                *b += s;
            }
        }
        // Converged to round-off?
        let (_, f) = self.linearise(theta, &x, &alpha, gamma, &beta, n);
        (f.norm() <= 1e-11 && theta > 0.0).then_some(Optimum {
            theta,
            x,
            alpha,
            beta,
        })
    }

    /// Multipliers that best fit the stationarity conditions at `(theta, x)`: those rows of
    /// the system (in `x` and in `theta`) are linear in the multipliers, so their block of the
    /// Jacobian at zero multipliers, against the residual there, is the least-squares problem.
    fn fit(&self, theta: f64, x: &[f64]) -> Option<(Vec<f64>, f64, Vec<f64>)> {
        let d = self.form.dim;
        let (p, q) = (self.pressed.len(), self.rows.len());
        let (oa, n) = (d * p + 1, d * p + 1 + q + 1 + p);
        let (jac, f) = self.linearise(theta, x, &vec![0.0; q], 0.0, &vec![0.0; p], n);
        let a = jac.view((0, oa), (oa, n - oa)).clone_owned();
        let b = -f.rows(0, oa);
        let svd = a.svd(true, true);
        let largest = svd.singular_values.iter().fold(0.0f64, |a, &x| a.max(x));
        let y = svd.solve(&b, 1e-12 * largest).ok()?;
        Some((y.rows(0, q).iter().copied().collect(), y[q], {
            y.rows(q + 1, p).iter().copied().collect()
        }))
    }

    /// `d/dr_j (||r_t_j|| - theta r_n_j)`, component `c`, at pressed node `pi`.
    fn slip_gradient(&self, theta: f64, x: &[f64], pi: usize, c: usize) -> f64 {
        let d = self.form.dim;
        if c == 0 {
            -theta
        } else {
            x[d * pi + c] / tangential(x, d, pi)
        }
    }

    /// The Jacobian and the residual of the optimality system. Unknowns: `x` (`d p`), `theta`,
    /// `alpha` (`q`), `gamma`, `beta` (`p`; a sticking node's is held at zero by its row).
    fn linearise(
        &self,
        theta: f64,
        x: &[f64],
        alpha: &[f64],
        gamma: f64,
        beta: &[f64],
        n: usize,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let d = self.form.dim;
        let (p, q) = (self.pressed.len(), self.rows.len());
        let (ot, oa) = (d * p, d * p + 1);
        let (og, ob) = (oa + q, oa + q + 1);
        let mut jac = DMatrix::zeros(n, n);
        let mut f = DVector::zeros(n);
        // Stationarity in x: -(G^T alpha)_j + gamma e_n + beta_j grad_j = 0.
        for (pi, &j) in self.pressed.iter().enumerate() {
            let rt = tangential(x, d, pi);
            for c in 0..d {
                let row = d * pi + c;
                let mut v = 0.0;
                for (ri, &k) in self.rows.iter().enumerate() {
                    let g = self.form.gap_row(k)[d * j + c];
                    v -= g * alpha[ri];
                    jac[(row, oa + ri)] = -g;
                }
                if c == 0 {
                    v += gamma;
                    jac[(row, og)] = 1.0;
                }
                if self.slip[pi] {
                    let grad = self.slip_gradient(theta, x, pi, c);
                    v += beta[pi] * grad;
                    jac[(row, ob + pi)] = grad;
                    if c == 0 {
                        jac[(row, ot)] = -beta[pi];
                    } else {
                        // beta_j times the Hessian of ||r_t||: (I - e e^T) / ||r_t||.
                        for c2 in 1..d {
                            let delta = if c == c2 { 1.0 } else { 0.0 };
                            let h = (delta - x[d * pi + c] * x[d * pi + c2] / (rt * rt)) / rt;
                            jac[(row, d * pi + c2)] = beta[pi] * h;
                        }
                    }
                }
                f[row] = v;
            }
        }
        // Stationarity in theta: 1 - sum beta_j r_n_j = 0.
        f[ot] = 1.0;
        for pi in 0..p {
            if self.slip[pi] {
                f[ot] -= beta[pi] * x[d * pi];
                jac[(ot, d * pi)] = -beta[pi];
                jac[(ot, ob + pi)] = -x[d * pi];
            }
        }
        // The gap rows: (G r)_k = 0.
        for (ri, &k) in self.rows.iter().enumerate() {
            let g = self.form.gap_row(k);
            let mut v = 0.0;
            for (pi, &j) in self.pressed.iter().enumerate() {
                for c in 0..d {
                    v += g[d * j + c] * x[d * pi + c];
                    jac[(oa + ri, d * pi + c)] = g[d * j + c];
                }
            }
            f[oa + ri] = v;
        }
        // The sum: sum r_n - 1 = 0.
        f[og] = -1.0;
        for pi in 0..p {
            f[og] += x[d * pi];
            jac[(og, d * pi)] = 1.0;
        }
        // Slip rows ||r_t_j|| - theta r_n_j = 0, or beta_j = 0 at a sticking node.
        for pi in 0..p {
            let row = ob + pi;
            if self.slip[pi] {
                f[row] = tangential(x, d, pi) - theta * x[d * pi];
                for c in 0..d {
                    jac[(row, d * pi + c)] = self.slip_gradient(theta, x, pi, c);
                }
                jac[(row, ot)] = -x[d * pi];
            } else {
                f[row] = beta[pi];
                jac[(row, ob + pi)] = 1.0;
            }
        }
        (jac, f)
    }
}
