//! A solver's point of a leaf made an exact solution of it ([`Ctx::exact_point`]): the step
//! between every solver answer and a leaf's threshold, its witness and its bracket's upper end.
//!
//! The point is projected (least change) onto the leaf's equalities. That corrects the
//! solver's residual, and on most problems the correction is far below every pressure. On the
//! 2D plug at m = 400 it is not: the simplex method's vertex of the all-contact leaf at its
//! bisected threshold leaves a residual of 7e-8 of the point (at m = 200, 8e-15), and its
//! correction (1e-9 per entry) turns the ratio of nodes pressed at 1e-6 of the most pressed by
//! a percent, above the level. Dropping them one by one (as below) changes the gaps by more
//! than the residual did (a node's compliance is large in the scaled units), and the run had
//! no first incumbent (`BENCHMARKS.md`). Such a point is a vertex of the leaf's linear
//! program, where the slipping nodes lie on the friction cone's edge by construction (one edge
//! column basic, the other at zero). So where the plain projection fails at a finite level, it
//! is done again with each node that slips at the level kept on its edge: its reaction moves
//! along that edge only (one unknown, not `dim`), so its ratio stays the level, and at a
//! vertex the equalities then leave only the vertex's own ray, onto which the point is
//! projected. That ray is singular only to the solver's accuracy, so the projection counts
//! the singular values up to ten times the point's residual as zero ([`NULL_EDGES`]), and the
//! equalities hold to that residual rather than to round-off; the point must pass the
//! witness's own check ([`check_solution`]). A gap off the contact set that the projection
//! closes past zero is closed exactly too and the projection redone.

use nalgebra::{DMatrix, DVector};

use super::Ctx;
use crate::solution::{check_solution, tangential};

/// A pressure below this share of the largest one (with `sum r_n = 1`) is taken as zero when a
/// solver point is made exact: far below the solver's accuracy.
const DROP: f64 = 1e-9;

/// A pressure below this share of the largest may be dropped when it spoils an exact point
/// ([`Ctx::exact_point`]).
const SMALL: f64 = 1e-4;

/// A scaled gap off the contact set below this is closed exactly when a solver point is made
/// exact: the solver's accuracy, far below [`crate::conic::program::POSITIVE`].
const CLOSED: f64 = 1e-8;

/// A pressed node whose ratio is within this share below the level its point was solved at
/// slips there: the second projection keeps it on the friction cone's edge
/// ([`Ctx::exact_point`]). (A vertex of the 2D linear program has such ratios equal to the
/// level to round-off; a cone program's point has its slipping nodes inside by about its
/// accuracy, 1e-8, and its projection stays the plain one.)
const ON_EDGE: f64 = 1e-12;

/// With the edges kept, the projection counts as zero the singular values up to this many
/// times the solver's point's own residual `|A x| / |x|` (one of them is at most that): at a
/// vertex the leaf's equalities leave only the vertex's own ray, which the solver's point
/// sees through its residual (on the 2D plug at m = 400 the smallest singular value was 2e-9
/// with a largest of 370, against a residual of 7e-8 of the point).
const NULL_EDGES: f64 = 10.0;

impl Ctx<'_, '_> {
    /// Makes a solver point of the leaf of `contact`, solved at friction coefficient `target`
    /// (`INFINITY` for none), exact: nodes with a negligible pressure get `r = 0`, the rest is
    /// projected (least change) onto the leaf's equalities `u_n_i = 0`, `i` in the contact set
    /// (and the gaps the solver left closed), and rescaled to `sum r_n = 1`. Returns its ratio
    /// `max ||r_t_i|| / r_n_i` and the point, or `None` when the projected point leaves the leaf
    /// (a gap open below zero beyond round-off).
    ///
    /// A node whose small pressure the solver should have left at zero (it only carries the
    /// solver's round-off) can spoil the point: after projection its pressure is negative, or
    /// its ratio exceeds `target`. Such a node, if its pressure is below [`SMALL`] of the
    /// largest, is dropped too (`r = 0`, its gap stays closed) and the projection redone.
    ///
    /// Where that fails, the same again with every node that slips at `target` kept on its
    /// edge (the module docs).
    pub(crate) fn exact_point(
        &self,
        contact: &[bool],
        r: &[f64],
        target: f64,
    ) -> Option<(f64, Vec<f64>)> {
        self.exact_point_with(contact, r, target, false)
            .or_else(|| {
                target
                    .is_finite()
                    .then(|| self.exact_point_with(contact, r, target, true))
                    .flatten()
            })
    }

    /// [`Ctx::exact_point`], with the slipping nodes kept on their edges or not.
    fn exact_point_with(
        &self,
        contact: &[bool],
        r: &[f64],
        target: f64,
        edges: bool,
    ) -> Option<(f64, Vec<f64>)> {
        let f = self.form;
        let (d, m) = (f.dim, f.m);
        let top = (0..m).map(|i| r[d * i]).fold(0.0f64, f64::max);
        if top <= 0.0 {
            return None;
        }
        // A vertex's basic pressure can be tiny and still needed: with the edges kept every
        // pressure counts.
        let drop = if edges { 0.0 } else { DROP };
        let mut pressed: Vec<usize> = (0..m)
            .filter(|&i| contact[i] && r[d * i] > drop * top)
            .collect();
        let on_edge = |j: usize| {
            edges
                && target.is_finite()
                && tangential(r, d, j) >= target * (1.0 - ON_EDGE) * r[d * j]
        };
        // The leaf's equalities, and the gaps off the contact set that the solver left at zero
        // (within its accuracy, possibly a little negative): those are closed exactly too.
        let mut rows: Vec<usize> = (0..m)
            .filter(|&i| contact[i] || f.gap_of(r, i) < CLOSED)
            .collect();
        loop {
            let out = self.project(r, &pressed, &rows, (&on_edge, target))?;
            let ratio = |j: usize| tangential(&out, d, j) / out[d * j];
            let bad = pressed
                .iter()
                .copied()
                .filter(|&j| out[d * j] <= 0.0 || ratio(j) > target * (1.0 + 1e-9))
                .min_by(|&a, &b| r[d * a].total_cmp(&r[d * b]));
            match bad {
                Some(j) if r[d * j] < SMALL * top && pressed.len() > 1 => {
                    pressed.retain(|&i| i != j);
                }
                _ => {
                    if pressed.iter().any(|&j| out[d * j] <= 0.0) {
                        return None;
                    }
                    // Gaps off the contact set stay open or closed (round-off allowed: scaled
                    // gaps are of order one).
                    let shut = (0..m)
                        .filter(|&i| !contact[i] && f.gap_of(&out, i) < -1e-12)
                        .min_by(|&a, &b| f.gap_of(&out, a).total_cmp(&f.gap_of(&out, b)));
                    if let Some(i) = shut {
                        // With the edges kept, a gap that the projection closed past zero was
                        // one that the solver's residual had left a little open: it is closed
                        // exactly too, and the projection done again.
                        if !edges || rows.contains(&i) {
                            return None;
                        }
                        rows.push(i);
                        rows.sort_unstable();
                        continue;
                    }
                    let theta = pressed.iter().map(|&j| ratio(j)).fold(0.0f64, f64::max);
                    // With the edges kept the equalities hold to the solver's residual, not to
                    // round-off: the point must pass the witness's own check.
                    if edges {
                        let u = f.problem.displacement(&out);
                        check_solution(f.problem, theta, &u, &out).ok()?;
                    }
                    return Some((theta, out));
                }
            }
        }
    }

    /// The reactions of `pressed` in `r`, projected onto `u_n_i = 0` for `i` in `rows`,
    /// normalised (`None` when nothing is left). A node for which `on_edge` holds stays on the
    /// edge of its friction cone at `target` in its own reaction's tangential direction.
    fn project(
        &self,
        r: &[f64],
        pressed: &[usize],
        rows: &[usize],
        (on_edge, target): (&dyn Fn(usize) -> bool, f64),
    ) -> Option<Vec<f64>> {
        let f = self.form;
        let (d, m) = (f.dim, f.m);
        if pressed.is_empty() {
            return None;
        }
        // The unknowns for the reactions: each a combination of reaction components (index,
        // weight), starting at its value in `r`. A free node has one per component (weight 1,
        // so that the plain projection is computed exactly as it was before the edges), a node
        // on its edge one, its normal pressure, along the edge in its own tangential direction.
        let mut columns: Vec<Vec<(usize, f64)>> = Vec::new();
        let mut x: Vec<f64> = Vec::new();
        for &j in pressed {
            if on_edge(j) {
                // The direction with the level's ratio exactly: the vertex's own column.
                let t = tangential(r, d, j);
                columns.push(
                    (0..d)
                        .map(|c| match c {
                            0 => (d * j, 1.0),
                            _ => (d * j + c, r[d * j + c] / t * target),
                        })
                        .collect(),
                );
                x.push(r[d * j]);
            } else {
                for c in 0..d {
                    columns.push(vec![(d * j + c, 1.0)]);
                    x.push(r[d * j + c]);
                }
            }
        }
        let on = columns.len();
        let edges_kept = on < d * pressed.len();
        // Then (a floating body) the rigid amplitudes; a point without them (a pattern's
        // witness) starts them at zero.
        let k = f.modes;
        x.extend((0..k).map(|j| r.get(d * m + j).copied().unwrap_or(0.0)));
        let gap = f.problem.compliance();
        let rigid = f.problem.rigid_modes();
        let sum = |col: usize, of: &dyn Fn(usize) -> f64| -> f64 {
            columns[col].iter().map(|&(p, w)| w * of(p)).sum()
        };
        // Rows: the closed gaps `u_n_i = (G r + R a)_n_i = 0`, then `R^T r = 0`.
        let a = DMatrix::from_fn(rows.len() + k, x.len(), |row, col| {
            match (rows.get(row), col < on) {
                (Some(&i), true) => sum(col, &|p| gap[(d * i, p)]),
                (Some(&i), false) => rigid[(d * i, col - on)],
                (None, true) => sum(col, &|p| rigid[(p, row - rows.len())]),
                (None, false) => 0.0,
            }
        });
        if a.nrows() > 0 {
            // Two rounds of least-change projection x -= A^+ (A x).
            let svd = a.clone().svd(true, true);
            let mut cutoff = 1e-13 * svd.singular_values.max();
            if edges_kept {
                let x0 = DVector::from_column_slice(&x);
                cutoff = cutoff.max(NULL_EDGES * (&a * &x0).norm() / x0.norm());
            }
            for _ in 0..2 {
                let ax = &a * DVector::from_column_slice(&x);
                let dx = svd.solve(&ax, cutoff).ok()?;
                x.iter_mut().zip(dx.iter()).for_each(|(v, dv)| *v -= dv);
            }
        }
        let mut out = vec![0.0; d * m + k];
        for (column, v) in columns.iter().zip(&x) {
            for &(p, w) in column {
                out[p] = w * v;
            }
        }
        out[d * m..].copy_from_slice(&x[on..]);
        let total: f64 = (0..m).map(|i| out[d * i]).sum();
        if total <= 0.0 || !total.is_finite() {
            return None;
        }
        out.iter_mut().for_each(|v| *v /= total);
        Some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conic::node_lp::{self as lp, LpCounters, Shape};
    use crate::conic::program::{leaf_classes, Decision, Formulation, Norm};
    use crate::critical::improve::tests::{ctx, set};
    use crate::examples::random_spd_problem_dim;

    /// The point made exact with the slipping nodes kept on their edges, from the simplex
    /// method's vertex of a 2D leaf at a level a little above the leaf's least (bisected on the
    /// same program), and from that vertex with each node's reaction scaled by up to `1e-7`
    /// (a residual as large as the one that defeated the plain projection at m = 400): a
    /// solution of WP at the level with its ratio at most the level (the plain projection's
    /// can be above it: it moves a slipping node off its edge).
    #[test]
    fn a_vertex_made_exact_on_its_edges_solves_the_leaf() {
        let mut checked = 0;
        let (mut edges, mut missed) = ([0; 2], [0; 2]);
        for case in 0..40u64 {
            let m = 3 + (case % 6) as usize;
            let problem = random_spd_problem_dim(2, m, 1.0, 900 + case);
            let form = Formulation::new(&problem);
            let ctx = ctx(&form);
            let counters = LpCounters::default();
            let vertex = |contact: &[bool], mu: f64| {
                let shape = Shape { mu, drive: None };
                match lp::decide(
                    &form,
                    &counters,
                    &leaf_classes(contact),
                    shape,
                    Norm::Sum,
                    None,
                    None,
                )
                .0
                {
                    Decision::Yes { r, .. } => Some(r),
                    _ => None,
                }
            };
            for mask in 1..1usize << m {
                let contact = set(mask, m);
                if vertex(&contact, 50.0).is_none() {
                    continue;
                }
                // The leaf's least level on its program, to 1e-6.
                let (mut lo, mut hi) = (0.0, 50.0);
                while hi - lo > 1e-6 * hi {
                    let mid = 0.5 * (lo + hi);
                    match vertex(&contact, mid) {
                        Some(_) => hi = mid,
                        None => lo = mid,
                    }
                }
                let r = vertex(&contact, hi).expect("feasible at the bisection's upper end");
                let what = format!("case {case}, set {mask:b}, level {hi}");
                // The vertex, and the vertex perturbed: each node's reaction by its own factor
                // (its ratio kept, as the simplex method's edge columns keep it).
                let noisy: Vec<f64> = r
                    .iter()
                    .enumerate()
                    .map(|(k, v)| v * (1.0 + 1e-9 * ((k / 2 * 7 + case as usize) % 5) as f64 / 4.0))
                    .collect();
                for (point, perturbed) in [(&r, false), (&noisy, true)] {
                    let what = format!("{what}, perturbed {perturbed}");
                    // Both ways: the plain projection, then the edges kept where it fails.
                    let (theta, p) = ctx.exact_point(&contact, point, hi).expect(&what);
                    let u = problem.displacement(&p);
                    check_solution(&problem, theta, &u, &p)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    // The edges kept alone.
                    match ctx.exact_point_with(&contact, point, hi, true) {
                        Some((theta, p)) => {
                            assert!(
                                theta <= hi * (1.0 + 1e-9),
                                "{what}: ratio {theta} on the edges"
                            );
                            let u = problem.displacement(&p);
                            check_solution(&problem, hi, &u, &p)
                                .unwrap_or_else(|e| panic!("{what}: on the edges: {e}"));
                            for i in 0..m {
                                assert!(
                                    contact[i] || p[2 * i] == 0.0,
                                    "{what}: node {i} off the set"
                                );
                            }
                            edges[perturbed as usize] += 1;
                        }
                        None => missed[perturbed as usize] += 1,
                    }
                }
                checked += 1;
            }
        }
        assert!(checked >= 200, "only {checked} leaves");
        // The edges' projection lands on the vertex where the vertex is not degenerate (a
        // basic column at zero, a node sticking within `ON_EDGE` of the level): at 1,486 of
        // 1,496 vertices, and of the perturbed ones.
        for k in 0..2 {
            assert!(
                missed[k] * 50 <= checked && edges[k] + missed[k] == checked,
                "the edges made {} of {checked} exact (perturbed: {})",
                edges[k],
                k == 1
            );
        }
    }
}
