//! The steps of a run of the simplex method ([`super::Run`]): nonbasic variables put at their
//! bounds, basic values and reduced costs recomputed from the inverse, the cost perturbation,
//! the tests of a variable's bounds and reduced cost, a pivot and a column of `B^-1 [A  -I]`.

use super::dense::{axpy, dot, eliminate, eliminate_norms, times_into};
use super::{At, Run, PERTURB, TOL};

impl Run<'_> {
    /// Puts every nonbasic variable at a bound it has (a free one at zero).
    pub(super) fn settle_nonbasic(&mut self) {
        let lp = self.lp;
        for j in 0..lp.total() {
            let (lo, hi) = (lp.lo[j], lp.hi[j]);
            let at = &mut self.basis.at[j];
            if *at == At::Basic {
                continue;
            }
            *at = match *at {
                _ if lo == hi => At::Lower,
                At::Upper if hi.is_finite() => At::Upper,
                At::Lower if lo.is_finite() => At::Lower,
                _ if lo.is_finite() => At::Lower,
                _ if hi.is_finite() => At::Upper,
                _ => At::Zero,
            };
            self.x[j] = match *at {
                At::Lower => lo,
                At::Upper => hi,
                _ => 0.0,
            };
        }
    }

    /// Basic values from the nonbasic ones: `x_B = -B^-1 N x_N`.
    pub(super) fn primal(&mut self) {
        let lp = self.lp;
        let n = lp.n;
        let [mut xn, mut rhs, mut xb] = std::mem::take(&mut self.scratch);
        // The nonbasic columns' values (zero at the basic ones).
        xn.clear();
        xn.extend((0..n).map(|j| {
            if self.basis.at[j] == At::Basic {
                0.0
            } else {
                self.x[j]
            }
        }));
        let any = xn.iter().any(|&v| v != 0.0);
        rhs.clear();
        rhs.extend((0..lp.rows).map(|k| {
            let from_columns = if any { -dot(lp.row(k), &xn) } else { 0.0 };
            let j = n + k;
            let own = if self.basis.at[j] != At::Basic {
                self.x[j]
            } else {
                0.0
            };
            from_columns + own
        }));
        times_into(self.inv(), &rhs, &mut xb);
        for (k, &v) in xb.iter().enumerate() {
            let j = self.basis.head[k];
            self.x[j] = v;
        }
        self.scratch = [xn, rhs, xb];
    }

    /// Reduced costs: `d = c - (c_B B^-1) [A  -I]`.
    pub(super) fn dual(&mut self) {
        let r = self.lp.rows;
        let [mut y, mut ya, other] = std::mem::take(&mut self.scratch);
        let inv = self.inv();
        y.clear();
        y.resize(r, 0.0);
        for (k, &j) in self.basis.head.iter().enumerate() {
            let c = self.cost[j];
            if c != 0.0 {
                axpy(&mut y, c, &inv[k * r..(k + 1) * r]);
            }
        }
        self.lp.row_times_into(&y, &mut ya);
        for (j, d) in self.d.iter_mut().enumerate() {
            *d = if self.basis.at[j] == At::Basic {
                0.0
            } else {
                self.cost[j] - ya[j]
            };
        }
        self.scratch = [y, ya, other];
    }

    /// How far basic variable `j` is below its lower bound (negative) or above its upper
    /// bound (positive), beyond the tolerance; zero when within.
    pub(super) fn violation(&self, j: usize) -> f64 {
        let (v, lo, hi) = (self.x[j], self.lp.lo[j], self.lp.hi[j]);
        if v < lo - TOL * (1.0 + lo.abs()) {
            v - lo
        } else if v > hi + TOL * (1.0 + hi.abs()) {
            v - hi
        } else {
            0.0
        }
    }

    /// Gives every nonbasic variable that is not fixed or free a small cost of the sign its
    /// bound wants, a different one for each (on top of its own; a shift, dropped after the
    /// dual method). Whether any was given.
    pub(super) fn perturb_costs(&mut self) -> bool {
        let lp = self.lp;
        let mut any = false;
        for j in 0..lp.total() {
            let at = self.basis.at[j];
            if at != At::Basic && at != At::Zero && lp.lo[j] != lp.hi[j] {
                let spread = ((j as u64).wrapping_mul(2_654_435_761) % 1024) as f64 / 1024.0;
                let size = PERTURB * (1.0 + spread);
                self.cost[j] += if at == At::Lower { size } else { -size };
                any = true;
            }
        }
        any
    }

    /// Whether nonbasic `j`'s reduced cost has the wrong sign for where it sits.
    pub(super) fn dual_wrong(&self, j: usize) -> bool {
        let d = self.d[j];
        match self.basis.at[j] {
            At::Basic => false,
            _ if self.lp.lo[j] == self.lp.hi[j] => false,
            At::Lower => d < -TOL,
            At::Upper => d > TOL,
            At::Zero => d.abs() > TOL,
        }
    }

    /// Pivots `q` into row position `p`, with `alpha = B^-1 a_q`; the leaving variable goes to
    /// `leave_at`. `norms`, when given, are the squared norms of the inverse's rows, kept
    /// exact ([`eliminate_norms`]).
    pub(super) fn pivot(
        &mut self,
        (p, q): (usize, usize),
        alpha: &[f64],
        leave_at: At,
        norms: Option<&mut [f64]>,
    ) {
        let r = self.lp.rows;
        let out = self.basis.head[p];
        let inv = self.basis.inv.as_mut().expect("inverted before the run");
        match norms {
            Some(norms) => eliminate_norms(inv, r, p, alpha, norms),
            None => eliminate(inv, r, p, alpha),
        }
        self.basis.head[p] = q;
        self.basis.at[q] = At::Basic;
        self.basis.at[out] = leave_at;
        self.x[out] = match leave_at {
            At::Lower => self.lp.lo[out],
            At::Upper => self.lp.hi[out],
            _ => 0.0,
        };
    }

    /// The squared norms of the inverse's rows: the dual method's steepest-edge weights.
    pub(super) fn row_norms(&self) -> Vec<f64> {
        let r = self.lp.rows;
        self.inv()
            .chunks_exact(r)
            .map(|row| dot(row, row))
            .collect()
    }

    /// `B^-1 a_q` into `alpha` (`col` a buffer for `a_q`; the storage of both reused).
    pub(super) fn column_into(&self, q: usize, col: &mut Vec<f64>, alpha: &mut Vec<f64>) {
        let (lp, r) = (self.lp, self.lp.rows);
        let inv = self.inv();
        if q < lp.n {
            col.clear();
            col.extend((0..r).map(|k| lp.row(k)[q]));
            times_into(inv, col, alpha);
        } else {
            let i = q - lp.n;
            alpha.clear();
            alpha.extend((0..r).map(|k| -inv[k * r + i]));
        }
    }
}
