//! A leaf's certificate just below its threshold, closer than the solver can certify.
//!
//! The conic solver certifies a leaf infeasible only about 1e-7 (relative) below its threshold
//! `theta`: closer, its Farkas certificate cannot be told from round-off (`socp.rs` asks a
//! margin of 1e-6). With `sum r_n = 1`, a certificate of the leaf at `mu` is a `z` (one per gap
//! row: any sign on the contact set, `>= 0` off it) whose `w = K^-1 z` has `c_i = w_n_i +
//! mu ||w_t_i|| < 0` at every contact node (`critical::certify` has the argument). Scaled so
//! that `c_i <= -1`, the one of least norm is unique, and it moves smoothly with `mu` as long as
//! the same constraints hold it tight (parametric programming: the tight set changes at finitely
//! many `mu`). So:
//!
//! 1. the least-norm certificate is solved at `mu_1 = theta (1 - 1e-4)` (then `1e-3`, `1e-5`),
//!    where the solver sees clearly which constraints are tight
//!    ([`Formulation::least_certificate`]);
//! 2. at the `mu` wanted, just below `theta`, the least-norm solution of those constraints as
//!    equalities (2D: `w_n + mu w_t + 1 = 0` on the tight side or sides; 3D: `w_n + mu (w_t .
//!    e) + 1 = 0` with `e` the direction of `w_t`, turned to the solution's own `w_t` a few
//!    times, or `w_t = 0`, `w_n = -1` where `w_t` vanished; `z_j = 0` where it was zero) is
//!    found by a singular value decomposition;
//! 3. it is checked in floating point against every inequality, with a margin far above
//!    round-off. When certificates are kept, it joins them and is re-checked exactly like every
//!    other.
//!
//! This is how a leaf's bracket reaches the `tol` asked (1e-9 by default) instead of the
//! solver's 1e-7. When the guess fails the check (the tight set changes between `mu_1` and
//! `mu`, a degenerate optimum, or a threshold that is a limit as a pressure vanishes, with no
//! singular point to find), the leaf keeps the solver's bracket.

use nalgebra::{DMatrix, DVector};

use crate::conic::program::{leaf_classes, Cut, Formulation, Refutation};

/// Where the tight constraints are read, as shares of `theta` below it.
const STEPS: [f64; 3] = [1e-4, 1e-3, 1e-5];
/// A constraint within this share of its terms is tight; a multiplier within this share of the
/// largest is zero.
const TIGHT: f64 = 1e-6;
/// Round-off allowed in the floating-point check, relative to the terms of each `c_i`.
const ROUNDOFF: f64 = 1e-12;

/// A refutation of the leaf of `contact` at the first of `mus` (each below `theta`, the
/// leaf's threshold, the closest first) for which the least-norm certificate's tight set gives
/// one that passes the check, with `sum r_n = 1`; with that `mu`.
pub(crate) fn refute_below(
    form: &Formulation,
    contact: &[bool],
    theta: f64,
    mus: &[f64],
) -> Option<(f64, Refutation)> {
    // A floating body's certificates carry the rigid modes too; not polished (the probes of
    // `leaf_threshold` bracket its thresholds instead).
    if !theta.is_finite() || form.modes > 0 {
        return None;
    }
    let mus: Vec<f64> = mus
        .iter()
        .copied()
        .filter(|&mu| mu < theta && mu > 0.0)
        .collect();
    // Each step's tight set read once (a certificate program), when first needed.
    let mut tights: Vec<Option<Option<Tight>>> = STEPS.iter().map(|_| None).collect();
    for &mu in &mus {
        for (step, slot) in STEPS.iter().zip(tights.iter_mut()) {
            let tight =
                slot.get_or_insert_with(|| Tight::read(form, contact, theta * (1.0 - step)));
            let Some(tight) = tight else { continue };
            if let Some(f) = tight
                .solve_aligned(form, mu)
                .and_then(|y| check(form, contact, &y, mu))
            {
                return Some((mu, f));
            }
        }
    }
    None
}

/// The leaf's threshold located more closely than the solver's points give it: the friction
/// coefficient where the tight system of the least-norm certificate becomes singular (the
/// certificate grows without bound as `mu` rises to the threshold), and reactions there (the
/// system's left null vector: each tight constraint's multiplier times its reaction
/// direction), to be made an exact point of the leaf by the caller. `None` when the system
/// does not behave so.
pub(crate) fn sharpen(form: &Formulation, contact: &[bool], theta: f64) -> Option<(f64, Vec<f64>)> {
    if !(theta > 0.0 && theta.is_finite()) || form.modes > 0 {
        return None;
    }
    let mut tight = Tight::read(form, contact, theta * (1.0 - STEPS[0]))?;
    let mut at = theta * (1.0 - 1e-6);
    let mut b = theta;
    // In 3D the slip directions are realigned near the pole found, and it is found again.
    for _ in 0..if form.dim == 3 { 3 } else { 1 } {
        if form.dim == 3 {
            tight.solve_aligned(form, at)?;
        }
        b = tight.pole(form, theta)?;
        at = b * (1.0 - 1e-9);
    }
    let r = tight.reactions(form, b)?;
    Some((b, r))
}

/// One tight constraint of a certificate, as an equality in the scaled multipliers `y`.
enum Row {
    /// `y_j = 0`.
    Zero(usize),
    /// `w . (v0 + mu v1) = rhs`, with `w = sum_k y_k gap_row(k)` and `v0`, `v1` reactions of
    /// one node (`d` components each).
    Node {
        node: usize,
        v0: Vec<f64>,
        v1: Vec<f64>,
        rhs: f64,
    },
}

/// The tight constraints of the least-norm certificate at some `mu_1`.
struct Tight {
    rows: Vec<Row>,
}

impl Tight {
    /// Solves the least-norm certificate at `mu1` and reads its tight constraints.
    fn read(form: &Formulation, contact: &[bool], mu1: f64) -> Option<Tight> {
        let (d, m) = (form.dim, form.m);
        let y1 = form.least_certificate(contact, mu1)?;
        let top = y1.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let unit = |c: usize| -> Vec<f64> { (0..d).map(|k| (k == c) as usize as f64).collect() };
        let zero = vec![0.0; d];
        let mut rows = Vec::new();
        for i in 0..m {
            if !contact[i] {
                if y1[i] <= TIGHT * top {
                    rows.push(Row::Zero(i));
                }
                continue;
            }
            let (w, size) = w_of(form, &y1, i);
            let terms = 1.0 + size[0] + mu1 * size[1..].iter().sum::<f64>();
            let wt = w[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
            // w_n + mu (w_t . e) = -1 for a unit tangent e.
            let along = |e: &[f64]| {
                let mut v1 = vec![0.0; d];
                v1[1..].copy_from_slice(e);
                Row::Node {
                    node: i,
                    v0: unit(0),
                    v1,
                    rhs: -1.0,
                }
            };
            if d == 2 {
                for sign in [1.0, -1.0] {
                    if -(w[0] + 1.0) - sign * mu1 * w[1] <= TIGHT * terms {
                        rows.push(along(&[sign]));
                    }
                }
            } else if -(w[0] + 1.0) - mu1 * wt <= TIGHT * terms {
                if wt > TIGHT * terms {
                    // Only the row along e: with e the direction of w_t at the solution,
                    // the least-norm solution of these rows is the least-norm certificate
                    // (the same optimality conditions), and `realign` finds that e.
                    rows.push(along(&[w[1] / wt, w[2] / wt]));
                } else {
                    rows.push(Row::Node {
                        node: i,
                        v0: unit(0),
                        v1: zero.clone(),
                        rhs: -1.0,
                    });
                    for c in 1..d {
                        rows.push(Row::Node {
                            node: i,
                            v0: unit(c),
                            v1: zero.clone(),
                            rhs: 0.0,
                        });
                    }
                }
            }
        }
        (!rows.is_empty()).then_some(Tight { rows })
    }

    /// In 3D, a slipping node's row holds `w_n + mu (w_t . e) = -1` along a direction `e`
    /// read at `mu_1`; the right `e` is the direction of `w_t` at the solution, and it moves
    /// with `mu`. Turns each `e` to `w_t` of `y` (a solution near the `mu` wanted).
    fn realign(&mut self, form: &Formulation, y: &[f64]) {
        if form.dim != 3 {
            return;
        }
        for row in &mut self.rows {
            let Row::Node { node, v1, .. } = row else {
                continue;
            };
            if v1[1] == 0.0 && v1[2] == 0.0 {
                continue;
            }
            let (w, _) = w_of(form, y, *node);
            let wt = (w[1] * w[1] + w[2] * w[2]).sqrt();
            if wt > 0.0 && wt.is_finite() {
                v1[1] = w[1] / wt;
                v1[2] = w[2] / wt;
            }
        }
    }

    /// The least-norm solution at `mu`, the 3D slip directions realigned to it a few times.
    fn solve_aligned(&mut self, form: &Formulation, mu: f64) -> Option<Vec<f64>> {
        let mut y = self.solve(form, mu)?;
        if form.dim == 3 {
            for _ in 0..4 {
                self.realign(form, &y);
                y = self.solve(form, mu)?;
            }
        }
        Some(y)
    }

    /// The `mu` near `theta` (below it by about 1e-7 or less) where the system becomes
    /// singular: secant steps on `h(mu) = y_a . y_a / y_a . y(mu)` (`y_a` the solution a
    /// millionth below `theta`), about linear in `mu` and zero at the pole. A step whose `h`
    /// does not shrink has reached it to round-off (at the pole itself the least-norm solve
    /// drops the growing part, and `h` jumps).
    fn pole(&self, form: &Formulation, theta: f64) -> Option<f64> {
        let (mut a, mut b) = (theta * (1.0 - 1e-6), theta * (1.0 - 1e-7));
        let y_ref = self.solve(form, a)?;
        let dot = |y: &[f64]| y.iter().zip(&y_ref).map(|(p, q)| p * q).sum::<f64>();
        let norm = dot(&y_ref);
        let h = |mu: f64| self.solve(form, mu).map(|y| norm / dot(&y));
        let (mut ha, mut hb) = (1.0, h(b)?);
        for _ in 0..20 {
            if hb == ha {
                break;
            }
            let next = b - hb * (b - a) / (hb - ha);
            if !next.is_finite() {
                return None;
            }
            let hn = if (next - b).abs() <= 1e-15 * theta {
                None
            } else {
                h(next).filter(|hn| hn.abs() < hb.abs())
            };
            (a, ha) = (b, hb);
            b = next;
            match hn {
                Some(hn) => hb = hn,
                None => break,
            }
        }
        (b > theta * (1.0 - 1e-3) && b <= theta * (1.0 + 1e-12)).then_some(b)
    }

    /// The system at `mu`: one row per tight constraint over the `m` multipliers.
    fn system(&self, form: &Formulation, mu: f64) -> (DMatrix<f64>, DVector<f64>) {
        let (d, m) = (form.dim, form.m);
        let mut a = DMatrix::zeros(self.rows.len(), m);
        let mut b = DVector::zeros(self.rows.len());
        for (r, row) in self.rows.iter().enumerate() {
            match row {
                Row::Zero(j) => a[(r, *j)] = 1.0,
                Row::Node { node, v0, v1, rhs } => {
                    for k in 0..m {
                        let g = &form.gap_row(k)[d * node..d * node + d];
                        a[(r, k)] = (0..d).map(|c| g[c] * (v0[c] + mu * v1[c])).sum();
                    }
                    b[r] = *rhs;
                }
            }
        }
        (a, b)
    }

    /// The least-norm solution of the system at `mu`.
    fn solve(&self, form: &Formulation, mu: f64) -> Option<Vec<f64>> {
        let (a, b) = self.system(form, mu);
        let svd = a.svd(true, true);
        let largest = svd.singular_values.iter().fold(0.0f64, |a, &x| a.max(x));
        let y = svd.solve(&b, 1e-12 * largest).ok()?;
        y.iter()
            .all(|x| x.is_finite())
            .then(|| y.iter().copied().collect())
    }

    /// Reactions (`sum r_n = 1`) from the left null vector of the system at `mu`.
    fn reactions(&self, form: &Formulation, mu: f64) -> Option<Vec<f64>> {
        let (d, m) = (form.dim, form.m);
        let (a, _) = self.system(form, mu);
        if a.nrows() > m {
            return None;
        }
        let svd = a.svd(true, false);
        let u = svd.u.as_ref()?;
        let k = svd.singular_values.imin();
        let mut r = vec![0.0; d * m];
        for (row, lambda) in self.rows.iter().zip(u.column(k).iter()) {
            if let Row::Node { node, v0, v1, .. } = row {
                for c in 0..d {
                    r[d * node + c] += lambda * (v0[c] + mu * v1[c]);
                }
            }
        }
        let total: f64 = (0..m).map(|i| r[d * i]).sum();
        if total == 0.0 || !total.is_finite() {
            return None;
        }
        r.iter_mut().for_each(|x| *x /= total);
        Some(r)
    }
}

/// `w_i` (node `i`'s `d` components) of multipliers `y`, and the sums of the absolute terms.
fn w_of(form: &Formulation, y: &[f64], i: usize) -> (Vec<f64>, Vec<f64>) {
    let d = form.dim;
    let (mut w, mut size) = (vec![0.0; d], vec![0.0; d]);
    for (k, &yk) in y.iter().enumerate() {
        if yk == 0.0 {
            continue;
        }
        let g = &form.gap_row(k)[d * i..d * i + d];
        for c in 0..d {
            w[c] += yk * g[c];
            size[c] += (yk * g[c]).abs();
        }
    }
    (w, size)
}

/// The refutation of `y` (scaled multipliers) at `mu`, a negative multiplier off the contact
/// set taken as zero, if then every `c_i` is negative with a margin far above round-off.
pub(super) fn check(
    form: &Formulation,
    contact: &[bool],
    y: &[f64],
    mu: f64,
) -> Option<Refutation> {
    let m = form.m;
    let y: Vec<f64> = (0..m)
        .map(|k| if contact[k] { y[k] } else { y[k].max(0.0) })
        .collect();
    for i in (0..m).filter(|&i| contact[i]) {
        let (w, size) = w_of(form, &y, i);
        let wt = w[1..].iter().map(|x| x * x).sum::<f64>().sqrt();
        let terms = size[0] + mu * size[1..].iter().sum::<f64>();
        let c = w[0] + mu * wt;
        if c.is_nan() || c >= -ROUNDOFF * terms {
            return None;
        }
    }
    Some(Refutation {
        classes: leaf_classes(contact),
        mu,
        cut: Cut::Sum,
        z: (0..m).map(|k| y[k] / form.scale_of(k)).collect(),
        balance: Vec::new(),
    })
}
