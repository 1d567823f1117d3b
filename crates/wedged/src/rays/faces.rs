//! Brute force over the `2^m` contact sets: the baseline method ([`super::Method::Faces`]).
//!
//! In `r`-space (`u = G r`, `G = K^{-1}`) the cone of MISSION section 3 is
//!
//! ```text
//! C = { r : mu r_n_i - r_t_i >= 0,  mu r_n_i + r_t_i >= 0,  (G r)_{n_i} >= 0,  i = 0..m-1 }
//! ```
//!
//! For a contact set `J`, the set `F_J = { r in C : r_k = 0 (k not in J), (G r)_{n_k} = 0
//! (k in J) }` is a face of `C` whose points are all complementary, and the complementary extreme
//! rays of `C` are exactly the extreme rays of the faces `F_J`. A face lives in the `2|J|`
//! variables `r_J`; a feasible nonzero `r_J` is an extreme ray of it iff its equalities and the
//! inequalities tight at it have rank `2|J| - 1`. So, for every `J`, every set `T` of
//! `2|J| - 1 - rank(equalities)` inequalities is tried: when the equalities and `T` have rank
//! `2|J| - 1`, their null vector (with the feasible sign, if either is) is an extreme ray.
//!
//! This knows nothing of double description; it is exponential twice over and meant as an
//! independent check of the other methods for small `m`.

use std::collections::HashSet;

use nalgebra::DMatrix;

use crate::run::Control;

use super::params::{Info, RawRay, Settings};

use crate::linalg::{null_vector, rank};
use crate::problem::Problem;
use crate::solution::NodeStatus;

pub(crate) fn run(
    problem: &Problem,
    settings: &Settings,
    info: &mut Info,
    control: &Control,
) -> Vec<RawRay> {
    assert_eq!(problem.dim(), 2, "the faces method is 2D only");
    let m = problem.nodes();
    assert!(
        m < 32,
        "the faces method enumerates 2^m contact sets; m = {m} is far too many"
    );
    let tol = settings.zero_tol;
    let mut seen: HashSet<Vec<NodeStatus>> = HashSet::new();
    let mut rays = Vec::new();
    for mask in 1u32..(1u32 << m) {
        // Rays found so far are final: each comes from a finished contact set.
        if control.must_stop(rays.len()) {
            break;
        }
        let face = Face::new(problem, mask);
        face.extreme_rays(tol, info, |ray| {
            if seen.insert(ray.status.clone()) {
                rays.push(ray);
            }
        });
    }
    rays
}

/// One face `F_J`, in the variables `r_J`: variable `2a + c` is component `c` (0 = n, 1 = t) of
/// node `members[a]`.
struct Face<'a> {
    problem: &'a Problem,
    /// `J`, increasing.
    members: Vec<usize>,
    /// `|J|` equality rows `G_{n_k, J}` (`k` in `J`), row-major, `2|J|` columns.
    eq: Vec<f64>,
    /// Inequality rows `>= 0`, row-major: two friction rows per member, then `G_{n_k, J}` for
    /// every `k` not in `J`.
    ineq: Vec<f64>,
    /// Per row of `eq`, then of `ineq`: the largest entry of its whole compliance row
    /// `G_{n_k, :}` (0 for a friction row), for the round-off floor [`super::dd::NOISE`].
    eq_row_max: Vec<f64>,
    ineq_row_max: Vec<f64>,
}

impl<'a> Face<'a> {
    fn new(problem: &'a Problem, mask: u32) -> Face<'a> {
        let m = problem.nodes();
        let g = problem.compliance();
        let mu = problem.mu();
        let members: Vec<usize> = (0..m).filter(|&i| mask & (1 << i) != 0).collect();
        let nv = 2 * members.len();
        let gap_row = |k: usize, out: &mut Vec<f64>| {
            for &j in &members {
                out.push(g[(2 * k, 2 * j)]);
                out.push(g[(2 * k, 2 * j + 1)]);
            }
        };
        let row_max = |k: usize| (0..2 * m).fold(0.0f64, |a, j| a.max(g[(2 * k, j)].abs()));
        let mut eq = Vec::with_capacity(members.len() * nv);
        let eq_row_max: Vec<f64> = members.iter().map(|&k| row_max(k)).collect();
        for &k in &members {
            gap_row(k, &mut eq);
        }
        let mut ineq_row_max = vec![0.0; 2 * members.len()];
        let mut ineq = Vec::with_capacity((m + members.len()) * nv);
        for a in 0..members.len() {
            for sign in [-1.0, 1.0] {
                let start = ineq.len();
                ineq.resize(start + nv, 0.0);
                ineq[start + 2 * a] = mu;
                ineq[start + 2 * a + 1] = sign;
            }
        }
        for k in (0..m).filter(|&k| mask & (1 << k) == 0) {
            gap_row(k, &mut ineq);
            ineq_row_max.push(row_max(k));
        }
        Face {
            problem,
            members,
            eq,
            ineq,
            eq_row_max,
            ineq_row_max,
        }
    }

    fn nv(&self) -> usize {
        2 * self.members.len()
    }

    /// Calls `found` with every extreme ray of the face (possibly several times for one ray),
    /// each with its numerically decided status.
    fn extreme_rays(&self, tol: f64, info: &mut Info, mut found: impl FnMut(RawRay)) {
        let nv = self.nv();
        let q = self.members.len();
        let n_ineq = self.ineq.len() / nv;
        let rank_eq = rank(&mut self.eq.clone(), q, nv, tol);
        // `G_{n_J, n_J}` is a principal submatrix of a definite matrix, so `rank_eq = q < nv`.
        let Some(t) = (nv - 1).checked_sub(rank_eq) else {
            return;
        };
        if t > n_ineq {
            return;
        }
        let mut a = DMatrix::<f64>::zeros(q + t, nv);
        for i in 0..q {
            for j in 0..nv {
                a[(i, j)] = self.eq[i * nv + j];
            }
        }
        let mut comb: Vec<usize> = (0..t).collect();
        loop {
            info.candidates += 1;
            for (row, &c) in comb.iter().enumerate() {
                for j in 0..nv {
                    a[(q + row, j)] = self.ineq[c * nv + j];
                }
            }
            if let Some(ray) = self.ray_of(&a, tol) {
                found(ray);
            }
            if !next_combination(&mut comb, n_ineq) {
                break;
            }
        }
    }

    /// The extreme ray cut out by the rows of `a` (equalities and a candidate tight set), if they
    /// have rank `nv - 1` and one sign of their null vector is in the face.
    fn ray_of(&self, a: &DMatrix<f64>, tol: f64) -> Option<RawRay> {
        let nv = self.nv();
        let (sigma, mut v) = null_vector(a);
        let smax = sigma[nv - 1];
        if sigma[1] <= tol * smax || sigma[0] > tol * smax {
            return None; // rank below or above nv - 1
        }
        // Nodes whose reaction is zero up to the tolerance get exactly zero.
        let vmax = v.iter().fold(0.0f64, |acc, x| acc.max(x.abs()));
        for pair in v.chunks_mut(2) {
            if pair[0].abs() <= tol * vmax && pair[1].abs() <= tol * vmax {
                pair.fill(0.0);
            }
        }
        if !self.feasible(&v, tol) {
            v.iter_mut().for_each(|x| *x = -*x);
            if !self.feasible(&v, tol) {
                return None;
            }
        }
        let m = self.problem.nodes();
        let mut r = vec![0.0; 2 * m];
        for (a, &k) in self.members.iter().enumerate() {
            r[2 * k] = v[2 * a];
            r[2 * k + 1] = v[2 * a + 1];
        }
        let sum_n: f64 = r.iter().step_by(2).sum();
        if sum_n.is_nan() || sum_n <= 0.0 {
            return None;
        }
        r.iter_mut().for_each(|x| *x /= sum_n);
        let status = classify(self.problem, &r, tol)?;
        Some(RawRay { r, status })
    }

    /// Every equality and inequality of the face holds at `v`, up to the relative tolerance.
    /// (A gap row's value below the round-off floor of its compliance row counts as zero: an
    /// entry of `K^-1` that is zero in exact arithmetic comes out as round-off.)
    fn feasible(&self, v: &[f64], tol: f64) -> bool {
        let nv = self.nv();
        let size: f64 = v.iter().map(|x| x.abs()).sum();
        let floor = |row_max: f64| super::dd::NOISE * row_max * size;
        let eq_ok = self.eq.chunks(nv).zip(&self.eq_row_max).all(|(row, &top)| {
            let (x, scale) = dot(row, v);
            x.abs() <= (tol * scale).max(floor(top))
        });
        let ineq_ok = self
            .ineq
            .chunks(nv)
            .zip(&self.ineq_row_max)
            .all(|(row, &top)| {
                let (x, scale) = dot(row, v);
                x >= -(tol * scale).max(floor(top))
            });
        eq_ok && ineq_ok
    }
}

/// `sum a_k b_k` and `sum |a_k b_k|`.
fn dot(a: &[f64], b: &[f64]) -> (f64, f64) {
    a.iter()
        .zip(b)
        .fold((0.0, 0.0), |(s, t), (x, y)| (s + x * y, t + (x * y).abs()))
}

/// The status of every node of the reaction `r` (length `2m`), decided with the relative
/// tolerance; `None` if some node is not complementary or breaks a constraint.
fn classify(problem: &Problem, r: &[f64], tol: f64) -> Option<Vec<NodeStatus>> {
    let g = problem.compliance();
    let mu = problem.mu();
    let rmax = r.iter().fold(0.0f64, |acc, x| acc.max(x.abs()));
    (0..problem.nodes())
        .map(|i| {
            let (rn, rt) = (r[2 * i], r[2 * i + 1]);
            let (un, u_scale) = (0..r.len()).fold((0.0, 0.0), |(s, t), j| {
                (s + g[(2 * i, j)] * r[j], t + (g[(2 * i, j)] * r[j]).abs())
            });
            let row_max = (0..r.len()).fold(0.0f64, |a, j| a.max(g[(2 * i, j)].abs()));
            let size: f64 = r.iter().map(|x| x.abs()).sum();
            let gap_zero = un.abs() <= (tol * u_scale).max(super::dd::NOISE * row_max * size);
            let r_zero = rn.abs() <= tol * rmax && rt.abs() <= tol * rmax;
            if r_zero {
                return if gap_zero {
                    Some(NodeStatus::Grazing)
                } else if un > 0.0 {
                    Some(NodeStatus::Separated)
                } else {
                    None
                };
            }
            if !gap_zero {
                return None;
            }
            let f_scale = mu * rn.abs() + rt.abs();
            let (plus, minus) = (mu * rn - rt, mu * rn + rt);
            let tight = |x: f64| x.abs() <= tol * f_scale;
            match (tight(plus), tight(minus)) {
                (true, false) if minus > 0.0 => Some(NodeStatus::SlipPlus),
                (false, true) if plus > 0.0 => Some(NodeStatus::SlipMinus),
                (false, false) if plus > 0.0 && minus > 0.0 => Some(NodeStatus::Stick),
                _ => None,
            }
        })
        .collect()
}

/// Advances `c` (increasing indices below `n`) to the next combination in lexicographic order;
/// `false` when `c` was the last one.
fn next_combination(c: &mut [usize], n: usize) -> bool {
    let t = c.len();
    for i in (0..t).rev() {
        if c[i] < n - t + i {
            c[i] += 1;
            for j in (i + 1)..t {
                c[j] = c[j - 1] + 1;
            }
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rays::verify::polish_and_verify;
    use crate::rays::Method;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn settings() -> Settings {
        Settings {
            method: Method::Faces,
            ..Settings::default()
        }
    }

    fn solve(k: DMatrix<f64>, mu: f64) -> (Problem, Vec<RawRay>, Info) {
        let p = Problem::new(2, k, mu).unwrap();
        let mut info = Info::default();
        let cancel = std::sync::atomic::AtomicBool::new(false);
        let control = crate::run::Control::new(Default::default(), &cancel);
        let rays = run(&p, &settings(), &mut info, &control);
        (p, rays, info)
    }

    fn check_all(p: &Problem, rays: &[RawRay]) {
        let mut seen = HashSet::new();
        for ray in rays {
            assert!(
                seen.insert(ray.status.clone()),
                "status repeated: {:?}",
                ray.status
            );
            polish_and_verify(p, &ray.r, ray.status.clone(), settings().zero_tol)
                .unwrap_or_else(|e| panic!("{e}"));
        }
    }

    fn statuses(rays: &[RawRay]) -> Vec<Vec<NodeStatus>> {
        let mut s: Vec<_> = rays.iter().map(|r| r.status.clone()).collect();
        s.sort();
        s
    }

    #[test]
    fn combinations_are_all_listed() {
        let mut c = vec![0, 1];
        let mut all = vec![c.clone()];
        while next_combination(&mut c, 4) {
            all.push(c.clone());
        }
        assert_eq!(all, [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]);
        let mut empty: Vec<usize> = vec![];
        assert!(!next_combination(&mut empty, 3));
    }

    /// One node, `K = [[knn, knt], [knt, ktt]]`: `u_n = (ktt r_n - knt r_t) / det = 0` gives
    /// `r_t / r_n = ktt / knt`, inside the friction cone iff `mu >= ktt / |knt|`. Strictly above,
    /// the ray is stick with `r_t` of the sign of `knt`; at the critical value it is slip.
    #[test]
    fn one_node_closed_form() {
        for (knn, knt, ktt) in [
            (2.0, 1.0, 1.0),
            (3.0, -1.5, 2.0),
            (5.0, 0.7, 0.4),
            (1.0, -0.9, 1.0),
        ] {
            let k = DMatrix::from_row_slice(2, 2, &[knn, knt, knt, ktt]);
            let crit: f64 = ktt / f64::abs(knt);
            let (_, below, _) = solve(k.clone(), crit * 0.99);
            assert!(below.is_empty(), "no ray below mu* for {k}");
            let (p, above, info) = solve(k.clone(), crit * 1.01);
            assert!(info.candidates > 0);
            check_all(&p, &above);
            assert_eq!(statuses(&above), [vec![NodeStatus::Stick]]);
            let r = &above[0].r;
            assert!((r[1] / r[0] - ktt / knt).abs() < 1e-12);
            assert!((r[0] - 1.0).abs() < 1e-15);
        }
        // Exactly at the critical value (all numbers exact): slip, signed like K_nt.
        for (knt, want) in [(1.0, NodeStatus::SlipPlus), (-1.0, NodeStatus::SlipMinus)] {
            let k = DMatrix::from_row_slice(2, 2, &[2.0, knt, knt, 1.0]);
            let (p, rays, _) = solve(k, 1.0);
            check_all(&p, &rays);
            assert_eq!(statuses(&rays), [vec![want]]);
        }
    }

    #[test]
    fn one_node_uncoupled_never_wedges() {
        let k = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
        for mu in [0.1, 1.0, 1e3] {
            assert!(solve(k.clone(), mu).1.is_empty());
        }
    }

    /// Block-diagonal `K`: `C` is a product, so its complementary extreme rays are one node's
    /// ray with the other node grazing (`r = 0` and, uncoupled, `u = 0`).
    #[test]
    fn decoupled_nodes_give_the_union() {
        use NodeStatus::{Grazing, Stick};
        let block = |k: &mut DMatrix<f64>, i: usize, b: [f64; 3]| {
            k[(2 * i, 2 * i)] = b[0];
            k[(2 * i, 2 * i + 1)] = b[1];
            k[(2 * i + 1, 2 * i)] = b[1];
            k[(2 * i + 1, 2 * i + 1)] = b[2];
        };
        // mu* of the blocks: 1, 2, none.
        let blocks = [[2.0, 1.0, 1.0], [3.0, -1.0, 2.0], [1.0, 0.0, 1.0]];
        for (b0, b1, mu, want) in [
            (0, 1, 1.5, vec![vec![Stick, Grazing]]),
            (0, 1, 2.5, vec![vec![Stick, Grazing], vec![Grazing, Stick]]),
            (0, 1, 0.5, vec![]),
            (2, 1, 2.5, vec![vec![Grazing, Stick]]),
            (2, 2, 9.0, vec![]),
        ] {
            let mut k = DMatrix::zeros(4, 4);
            block(&mut k, 0, blocks[b0]);
            block(&mut k, 1, blocks[b1]);
            let (p, rays, _) = solve(k, mu);
            check_all(&p, &rays);
            assert_eq!(statuses(&rays), want, "blocks {b0} {b1}, mu {mu}");
        }
    }

    /// The rows that `status` makes tight (as in `verify`), to test completeness independently.
    fn tight_rows(p: &Problem, status: &[NodeStatus]) -> DMatrix<f64> {
        let n = 2 * status.len();
        let (g, mu) = (p.compliance(), p.mu());
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for (i, s) in status.iter().enumerate() {
            let unit = |a: f64, b: f64| {
                let mut v = vec![0.0; n];
                v[2 * i] = a;
                v[2 * i + 1] = b;
                v
            };
            let gap: Vec<f64> = g.row(2 * i).iter().copied().collect();
            match s {
                NodeStatus::Separated => rows.extend([unit(1.0, 0.0), unit(0.0, 1.0)]),
                NodeStatus::Grazing => rows.extend([unit(1.0, 0.0), unit(0.0, 1.0), gap]),
                NodeStatus::Stick | NodeStatus::Slip => rows.push(gap),
                NodeStatus::SlipPlus => rows.extend([gap, unit(mu, -1.0)]),
                NodeStatus::SlipMinus => rows.extend([gap, unit(mu, 1.0)]),
            }
        }
        DMatrix::from_fn(rows.len(), n, |i, j| rows[i][j])
    }

    /// Every status vector (`5^m` of them) whose tight constraints give a ray that passes the
    /// check: an independent list of the complementary extreme rays.
    fn rays_by_status(p: &Problem) -> Vec<Vec<NodeStatus>> {
        use NodeStatus::*;
        let all = [Separated, Stick, SlipPlus, SlipMinus, Grazing];
        let m = p.nodes();
        let mut out = Vec::new();
        for code in 0..5usize.pow(m as u32) {
            let status: Vec<NodeStatus> = (0..m)
                .map(|i| all[(code / 5usize.pow(i as u32)) % 5])
                .collect();
            let (_, mut v) = null_vector(&tight_rows(p, &status));
            if v.iter().step_by(2).sum::<f64>() < 0.0 {
                v.iter_mut().for_each(|x| *x = -*x);
            }
            if polish_and_verify(p, &v, status.clone(), settings().zero_tol).is_ok() {
                out.push(status);
            }
        }
        out.sort();
        out
    }

    #[test]
    fn random_problems_verify_and_are_complete() {
        let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_fa11);
        let mut wedged = 0;
        let mut total_rays = 0;
        for case in 0..48 {
            let m = 1 + case % 4;
            let n = 2 * m;
            let a = DMatrix::from_fn(n, n, |_, _| rng.gen_range(-1.0..1.0));
            let d = DMatrix::from_fn(n, n, |i, j| {
                if i == j {
                    rng.gen_range(0.01..0.5)
                } else {
                    0.0
                }
            });
            let k = &a * a.transpose() + d;
            let mu = rng.gen_range(0.2..3.0);
            let (p, rays, info) = solve(k, mu);
            assert!(info.candidates > 0);
            check_all(&p, &rays);
            assert_eq!(
                statuses(&rays),
                rays_by_status(&p),
                "case {case}, m = {m}, mu = {mu}"
            );
            wedged += usize::from(!rays.is_empty());
            total_rays += rays.len();
        }
        assert!(
            wedged >= 10 && total_rays >= 20,
            "too few wedged cases: {wedged}, {total_rays}"
        );
    }
}
