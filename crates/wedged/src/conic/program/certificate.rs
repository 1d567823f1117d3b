//! The least-norm certificate of a leaf's infeasibility, for `critical::polish`.

use super::{Counters, Formulation};
use crate::conic::socp::{solve, Affine, Answer, Program};

impl Formulation<'_> {
    /// The least-norm certificate of the leaf of `contact` at `mu` (contact nodes `u_n = 0`
    /// and friction cones, the others `r = 0`, `u_n >= 0`; `sum r_n = 1`): multipliers `y` of
    /// the scaled gap rows (any sign on the contact set, `>= 0` off it) with, at every contact
    /// node, `w_n_i + mu ||w_t_i|| <= -1`, where `w = sum_k y_k gap_row(k)`, and `||y||` least.
    /// `None` when the solver finds none (the leaf is feasible at `mu`) or is unsure. Used by
    /// `critical::polish` to read off which constraints a certificate holds tight.
    pub(crate) fn least_certificate(&self, contact: &[bool], mu: f64) -> Option<Vec<f64>> {
        let (d, m) = (self.dim, self.m);
        if self.modes > 0 {
            // Not written for a floating body (its certificate also balances the rigid modes).
            return None;
        }
        let t = m;
        let mut p = Program::new(m + 1);
        let w = |i: usize, c: usize, sign: f64| -> Vec<(usize, f64)> {
            (0..m)
                .map(|k| (k, sign * self.gap[k][d * i + c]))
                .filter(|&(_, g)| g != 0.0)
                .collect()
        };
        for (i, &on) in contact.iter().enumerate() {
            if !on {
                p.nonneg(Affine::var(i));
                continue;
            }
            // -(w_n + 1) >= mu ||w_t||.
            let head = Affine::new(w(i, 0, -1.0), -1.0);
            if d == 2 {
                for sign in [1.0, -1.0] {
                    let mut terms = head.terms.clone();
                    terms.extend(w(i, 1, -sign * mu));
                    p.nonneg(Affine::new(terms, -1.0));
                }
            } else {
                let tail = (1..d).map(|c| Affine::new(w(i, c, mu), 0.0)).collect();
                p.soc(head, tail);
            }
        }
        p.soc(Affine::var(t), (0..m).map(Affine::var).collect());
        p.minimise(&[(t, 1.0)]);
        let (answer, stats) = solve(&p);
        Counters::add(&self.counters.socps, stats.solves);
        Counters::add(&self.counters.retries, stats.retries);
        match answer {
            Answer::Optimal { x, .. } => Some(x[..m].to_vec()),
            _ => None,
        }
    }
}
