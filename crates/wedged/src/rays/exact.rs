//! Exact enumeration of a 2D problem: every complementary extreme ray of `C`, found in exact
//! arithmetic, so that the answer is provably complete (`wedged enumerate FILE --exact`).
//!
//! The floating-point methods decide signs with a tolerance; on degenerate problems (symmetric
//! meshes, repeated nodes, rays exactly on a friction-cone edge) a tolerance decision can, in
//! principle, add or lose a ray. Here no decision has a tolerance. Every `f64` of the problem
//! (the entries of `K` and `mu`) is taken as the exact rational number it represents, as in
//! [`crate::certify`], so the answer is the exact answer for the problem as stored.
//!
//! Two independent methods:
//!
//! - [`enumerate_exact`] (and [`crate::Method::Exact`], which runs it under the usual limits): a
//!   double description of the cone `C` in `u`-space. With `r = K u` substituted (no inverse),
//!   `C` is `{u in Q^{2m} : A u >= 0}` with `4m` rows per MISSION section 3: per node `u_n >= 0`,
//!   `r_n >= 0`, `mu r_n - r_t >= 0`, `mu r_n + r_t >= 0` (in this order, as in
//!   [`crate::certify`]). Each row is scaled to a primitive integer vector and each ray is kept as
//!   a primitive integer vector (gcd one), so the arithmetic is on integers only and every sign is
//!   exact. The `2m` friction rows form the initial basis (they span `r`-space, and `K` is
//!   invertible): its extreme rays are `K^{-1} (e_n +/- mu e_t)`, found as null vectors by
//!   fraction-free elimination. The other rows are then added one by one (the `r_n >= 0` rows,
//!   implied by the friction rows, cut nothing but enter the zero sets; then `u_n >= 0` node by
//!   node), the seed's way (MISSION section 4): a pair on either side of the new row is combined
//!   only if its sum stays complementary at the nodes done and it is adjacent, decided by the
//!   **exact rank** of the constraints tight at both (`2m - 2`), after a held ray tight on all of
//!   them has rejected it combinatorially; rays with a gap and a pressure at the node just done
//!   are deleted. The rays left are the complementary extreme rays of `C`; each one's status is
//!   read off its exact zero set. The cones are the maximal cliques of cross-complementary rays,
//!   as for every method.
//! - [`enumerate_exact_full`]: the plain double description of every extreme ray of `C` (no
//!   pruning), adjacency by the **combinatorial test** alone (exact, since no ray is deleted
//!   before the end), then the complementary ones: slower, a check of the pruned one.
//! - [`brute_force_exact`]: every status vector in `{separated, grazing, stick, slip+,
//!   slip-}^m`, each turned into its ray (or rejected) by [`crate::rays::exact_ray::exact_ray_of_status`]:
//!   the null vector of its tight rows, kept when the rank is `4m - 1`, every strict inequality is
//!   strict and the ray is complementary. It shares no enumeration code with the double
//!   description; it is exponential (`5^m`) and meant for tests, `m <=`
//!   [`BRUTE_FORCE_MAX_NODES`].
//!
//! Both return [`ExactEnumeration`]: the exact rays (normalised to `sum r_n = 1`) with their
//! statuses in canonical order, and the cones. [`crate::enumerate()`] with [`crate::Method::Exact`]
//! returns the same answer as an ordinary [`crate::Enumeration`], the rays rounded to `f64` for
//! output; its statuses, the cones and the outcome are exact.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{Signed, Zero};
use rayon::prelude::*;

use crate::rational::{integer_row, null_space_int, to_f64};

use super::params::{Info, Progress};
use crate::problem::Problem;
use crate::rays::exact_ray::{ray_of_status_quiet, ExactProblem, ExactRay};
use crate::run::{Control, EnumerateError, Limits};
use crate::solution::{pieces, Cone, NodeStatus, Ray};

/// The most nodes [`brute_force_exact`] accepts (it tries `5^m` status vectors).
pub const BRUTE_FORCE_MAX_NODES: usize = 8;

/// A complementary extreme ray of `C` in exact arithmetic, with its status.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactSolution {
    /// Per-node status, exact.
    pub status: Vec<NodeStatus>,
    /// The ray, normalised to `sum r_n = 1`.
    pub ray: ExactRay,
}

impl ExactSolution {
    /// The ray rounded to the nearest `f64`s, as the floating methods report it.
    pub fn rounded(&self) -> Ray {
        let round = |v: &[BigRational]| v.iter().map(to_f64).collect();
        Ray {
            u: round(&self.ray.u),
            r: round(&self.ray.r),
            status: self.status.clone(),
        }
    }
}

/// The exact answer of a 2D problem: every complementary extreme ray and every maximal
/// cross-complementary set.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactEnumeration {
    /// The complementary extreme rays, in canonical order (by status vector).
    pub rays: Vec<ExactSolution>,
    /// The maximal cross-complementary sets, in canonical order (as [`crate::Enumeration`]'s).
    pub cones: Vec<Cone>,
}

impl ExactEnumeration {
    /// The rays rounded to `f64`.
    pub fn rounded_rays(&self) -> Vec<Ray> {
        self.rays.iter().map(ExactSolution::rounded).collect()
    }
}

fn check_dim(problem: &Problem) -> Result<(), EnumerateError> {
    if problem.dim() == 2 {
        Ok(())
    } else {
        Err(EnumerateError::UnsupportedDim(problem.dim()))
    }
}

/// Sorts the rays canonically and forms the cones.
fn finish(mut rays: Vec<ExactSolution>) -> ExactEnumeration {
    rays.sort_by(|a, b| a.status.cmp(&b.status));
    rays.dedup_by(|a, b| a.status == b.status);
    let statuses: Vec<&[NodeStatus]> = rays.iter().map(|r| r.status.as_slice()).collect();
    let cones = pieces(&statuses);
    ExactEnumeration { rays, cones }
}

/// Every complementary extreme ray of `C` and the cones of a 2D problem, by double description
/// in exact integer arithmetic (see the module documentation), with no limit on time or memory.
/// Use [`crate::enumerate()`] with [`crate::Method::Exact`] for a run under [`Limits`].
pub fn enumerate_exact(problem: &Problem) -> Result<ExactEnumeration, EnumerateError> {
    check_dim(problem)?;
    let cancel = AtomicBool::new(false);
    let control = Control::new(Limits::default(), &cancel);
    let rays = run(
        problem,
        Variant::Pruned,
        &mut Info::default(),
        &|_| {},
        &control,
    )?;
    Ok(finish(rays))
}

/// [`enumerate_exact`] by the plain double description: every extreme ray of `C` with the
/// combinatorial adjacency test, then the complementary ones. The same answer, found differently
/// (no pruning, no rank test); much slower beyond a few nodes.
pub fn enumerate_exact_full(problem: &Problem) -> Result<ExactEnumeration, EnumerateError> {
    check_dim(problem)?;
    let cancel = AtomicBool::new(false);
    let control = Control::new(Limits::default(), &cancel);
    let rays = run(
        problem,
        Variant::Full,
        &mut Info::default(),
        &|_| {},
        &control,
    )?;
    Ok(finish(rays))
}

/// The exact brute force: every status vector of `{separated, grazing, stick, slip+, slip-}^m`
/// whose tight rows determine an extreme ray of `C` with exactly that status (see
/// [`crate::rays::exact_ray::exact_ray_of_status`]). Independent of the double description; for tests,
/// `m <=` [`BRUTE_FORCE_MAX_NODES`].
pub fn brute_force_exact(problem: &Problem) -> Result<ExactEnumeration, EnumerateError> {
    check_dim(problem)?;
    let m = problem.nodes();
    if m > BRUTE_FORCE_MAX_NODES {
        return Err(EnumerateError::InvalidSettings(format!(
            "the exact brute force tries all 5^m status vectors; m = {m} is more than its limit \
             of {BRUTE_FORCE_MAX_NODES}"
        )));
    }
    const ALPHABET: [NodeStatus; 5] = [
        NodeStatus::Separated,
        NodeStatus::Grazing,
        NodeStatus::Stick,
        NodeStatus::SlipPlus,
        NodeStatus::SlipMinus,
    ];
    let p = ExactProblem::new(problem);
    let total = 5usize.pow(m as u32);
    let rays: Vec<ExactSolution> = (0..total)
        .into_par_iter()
        .filter_map(|mut code| {
            let status: Vec<NodeStatus> = (0..m)
                .map(|_| {
                    let s = ALPHABET[code % 5];
                    code /= 5;
                    s
                })
                .collect();
            ray_of_status_quiet(&p, &status).map(|ray| ExactSolution { status, ray })
        })
        .collect();
    Ok(finish(rays))
}

/// Which double description: both are exact and give the same answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Variant {
    /// The seed's (MISSION section 4): pairs whose sum breaks complementarity at a node done are
    /// not combined, rays with a gap and a pressure at the node just done are deleted, so
    /// adjacency is decided by the exact rank of the common zero set (a held ray tight on all of
    /// it rejects a pair first). What [`crate::Method::Exact`] and [`enumerate_exact`] run.
    Pruned,
    /// Every extreme ray of `C`, combinatorial adjacency, the complementary ones at the end
    /// ([`enumerate_exact_full`]): slower, simpler, a check of the pruned one.
    Full,
}

/// A ray of the double description: a primitive integer vector `u` and its zero set over the
/// rows processed so far (bit `4 i + k` for row `k` of node `i`).
struct DdRay {
    x: Vec<BigInt>,
    z: Vec<u64>,
}

fn set_bit(z: &mut [u64], b: usize) {
    z[b / 64] |= 1 << (b % 64);
}

fn has_bit(z: &[u64], b: usize) -> bool {
    z[b / 64] >> (b % 64) & 1 == 1
}

fn dot(row: &[BigInt], x: &[BigInt]) -> BigInt {
    row.iter()
        .zip(x)
        .filter(|(a, b)| !a.is_zero() && !b.is_zero())
        .fold(BigInt::zero(), |s, (a, b)| s + a * b)
}

/// Divides by the gcd of the entries (the direction is kept).
fn primitive(mut x: Vec<BigInt>) -> Vec<BigInt> {
    let g = x.iter().fold(BigInt::zero(), |g, v| g.gcd(v));
    if !g.is_zero() && g != BigInt::from(1) {
        for v in &mut x {
            *v /= &g;
        }
    }
    x
}

/// Counters of one plus ray's pairs.
#[derive(Default)]
struct PairCounts {
    pairs: u64,
    pattern: u64,
    combinatorial: u64,
    rank_tests: u64,
}

/// The rank of the constraints in the zero set `common`, exactly: each tight gap fixes its
/// column, the other rows are eliminated (fraction-free) on the remaining columns.
fn common_rank(p: &ExactProblem, common: &[u64]) -> usize {
    let n = p.n;
    let fixed: Vec<bool> = (0..n)
        .map(|j| j % 2 == 0 && has_bit(common, 4 * (j / 2)))
        .collect();
    let columns: Vec<usize> = (0..n).filter(|&j| !fixed[j]).collect();
    let rows: Vec<Vec<BigInt>> = (0..2 * n)
        .filter(|&id| id % 4 != 0 && has_bit(common, id))
        .map(|id| columns.iter().map(|&j| p.rows[id][j].clone()).collect())
        .collect();
    let (rank, _) = null_space_int(rows, columns.len());
    rank + (n - columns.len())
}

/// Bytes of one held ray, roughly: its integers with their digits, and its zero set.
fn ray_bytes(ray: &DdRay) -> u64 {
    let ints: u64 = ray
        .x
        .iter()
        .map(|v| std::mem::size_of::<BigInt>() as u64 + v.bits().div_ceil(64) * 8)
        .sum();
    ints + 8 * ray.z.len() as u64 + 2 * std::mem::size_of::<Vec<u64>>() as u64
}

/// The exact double description under `control` (see the module documentation). Returns the
/// complementary extreme rays, unsorted; none when `control` stopped the run (no ray is final
/// before the last row).
pub(crate) fn run(
    problem: &Problem,
    variant: Variant,
    info: &mut Info,
    progress: &dyn Fn(Progress),
    control: &Control,
) -> Result<Vec<ExactSolution>, EnumerateError> {
    let pruned = variant == Variant::Pruned;
    let p = ExactProblem::new(problem);
    let n = p.n;
    let m = n / 2;
    let words = (4 * m).div_ceil(64);
    let node_words = m.div_ceil(64);
    // The rows, primitive integer vectors, row 4 i + k for inequality k of node i.
    let rows = &p.rows;
    // The initial cone: the friction rows, a basis. Ray b is tight on every basis row but b.
    let basis: Vec<usize> = (0..m).flat_map(|i| [4 * i + 2, 4 * i + 3]).collect();
    let singular = || {
        EnumerateError::InvalidSettings(
            "the stiffness is singular in exact arithmetic (the friction rows are dependent)"
                .into(),
        )
    };
    let initial: Vec<Option<DdRay>> = basis
        .par_iter()
        .map(|&b| {
            if control.must_stop(0) {
                return Ok(None);
            }
            let others: Vec<Vec<BigInt>> = basis
                .iter()
                .filter(|&&c| c != b)
                .map(|&c| rows[c].clone())
                .collect();
            let (_, null) = null_space_int(others, n);
            let x = integer_row(&null.ok_or_else(singular)?);
            let x = match dot(&rows[b], &x).sign() {
                num_bigint::Sign::Plus => x,
                num_bigint::Sign::Minus => x.into_iter().map(|v| -v).collect(),
                num_bigint::Sign::NoSign => return Err(singular()),
            };
            let mut z = vec![0u64; words];
            for &c in basis.iter().filter(|&&c| c != b) {
                set_bit(&mut z, c);
            }
            Ok(Some(DdRay { x, z }))
        })
        .collect::<Result<_, _>>()?;
    let Some(mut rays) = initial.into_iter().collect::<Option<Vec<DdRay>>>() else {
        return Ok(Vec::new());
    };
    let bytes = rays.iter().map(ray_bytes).sum::<u64>() / rays.len().max(1) as u64;
    control.set_ray_bytes(bytes);
    info.peak_rays = rays.len();
    info.peak_bytes = info.peak_rays as u64 * bytes;

    // Then the pressure rows (implied: they only enter the zero sets), then the gaps, node by
    // node.
    let order = (0..m).map(|i| 4 * i + 1).chain((0..m).map(|i| 4 * i));
    for id in order {
        if control.must_stop(rays.len()) {
            return Ok(Vec::new());
        }
        let row = &rows[id];
        let values: Vec<BigInt> = rays.par_iter().map(|ray| dot(row, &ray.x)).collect();
        let (mut plus, mut minus, mut zero) = (Vec::new(), Vec::new(), Vec::new());
        for (a, v) in values.iter().enumerate() {
            match v.sign() {
                num_bigint::Sign::Plus => plus.push(a),
                num_bigint::Sign::Minus => minus.push(a),
                num_bigint::Sign::NoSign => zero.push(a),
            }
        }
        let created = AtomicUsize::new(0);
        let held = rays.len();
        // The gap rows processed before this one, and per ray the nodes with a gap open among
        // them and the nodes pressed (filter (a) of the pruned variant).
        let gap_node = (id % 4 == 0).then_some(id / 4);
        let done: Vec<usize> = match gap_node {
            Some(i) => (0..i).collect(),
            None => Vec::new(),
        };
        let masks: Vec<(Vec<u64>, Vec<u64>)> = if pruned && gap_node.is_some() {
            rays.iter()
                .map(|ray| {
                    let (mut gap, mut press) = (vec![0u64; node_words], vec![0u64; node_words]);
                    for &j in &done {
                        if !has_bit(&ray.z, 4 * j) {
                            set_bit(&mut gap, j);
                        }
                    }
                    for j in 0..m {
                        if !has_bit(&ray.z, 4 * j + 1) {
                            set_bit(&mut press, j);
                        }
                    }
                    (gap, press)
                })
                .collect()
        } else {
            Vec::new()
        };
        let combined: Vec<(Vec<DdRay>, PairCounts)> = if minus.is_empty() {
            Vec::new()
        } else {
            plus.par_iter()
                .map(|&a| {
                    let mut out = Vec::new();
                    let mut counts = PairCounts::default();
                    if control.must_stop(held + created.load(Ordering::Relaxed)) {
                        return (out, counts);
                    }
                    let (ra, va) = (&rays[a], &values[a]);
                    for &b in &minus {
                        // Pairs can be slow (an exact rank each): poll the limits per pair.
                        if control.must_stop(held + created.load(Ordering::Relaxed)) {
                            break;
                        }
                        counts.pairs += 1;
                        // Filter (a): the sum would have a gap and a pressure at a node done.
                        if let (Some((ga, pa)), Some((gb, pb))) = (masks.get(a), masks.get(b)) {
                            let clash =
                                (0..node_words).any(|w| ga[w] & pb[w] != 0 || gb[w] & pa[w] != 0);
                            if clash {
                                counts.pattern += 1;
                                continue;
                            }
                        }
                        let rb = &rays[b];
                        let common: Vec<u64> = ra.z.iter().zip(&rb.z).map(|(p, q)| p & q).collect();
                        let count: u32 = common.iter().map(|w| w.count_ones()).sum();
                        // Adjacent iff the common zero set has rank n - 2; a count below n - 2
                        // cannot. With every extreme ray of the current cone held (full), that
                        // is: no other ray is tight on all of it. Pruned, a held ray tight on all
                        // of it still proves the pair not adjacent, but the converse needs the
                        // rank.
                        let superset = || {
                            rays.iter().enumerate().any(|(c, rc)| {
                                c != a
                                    && c != b
                                    && rc.z.iter().zip(&common).all(|(w, q)| w & q == *q)
                            })
                        };
                        let adjacent = count as usize + 2 >= n
                            && !superset()
                            && (!pruned || {
                                counts.rank_tests += 1;
                                common_rank(&p, &common) + 2 == n
                            });
                        if !adjacent {
                            counts.combinatorial += 1;
                            continue;
                        }
                        // va > 0 > vb: va x_b - vb x_a is zero on the row, positive combination.
                        let vb = &values[b];
                        let g = va.gcd(vb);
                        let (ca, cb) = (va / &g, -(vb / &g));
                        let x: Vec<BigInt> =
                            rb.x.iter()
                                .zip(&ra.x)
                                .map(|(xb, xa)| &ca * xb + &cb * xa)
                                .collect();
                        let mut z = common;
                        set_bit(&mut z, id);
                        out.push(DdRay { x: primitive(x), z });
                        created.fetch_add(1, Ordering::Relaxed);
                    }
                    (out, counts)
                })
                .collect()
        };
        if control.must_stop(held + created.load(Ordering::Relaxed)) {
            // No ray is final before the last row: report none.
            return Ok(Vec::new());
        }
        let mut old: Vec<Option<DdRay>> = rays.into_iter().map(Some).collect();
        let mut kept: Vec<DdRay> = Vec::with_capacity(plus.len() + zero.len());
        for &a in &plus {
            // Pruned: a ray with u_n_i > 0 and r_n_i > 0 can only have non-complementary
            // descendants.
            let complementary = |ray: &DdRay| gap_node.is_none_or(|i| has_bit(&ray.z, 4 * i + 1));
            if let Some(ray) = old[a].take().filter(|ray| !pruned || complementary(ray)) {
                kept.push(ray);
            }
        }
        for &a in &zero {
            if let Some(mut ray) = old[a].take() {
                set_bit(&mut ray.z, id);
                kept.push(ray);
            }
        }
        let mut created = 0;
        for (new, counts) in combined {
            info.pairs_tested += counts.pairs;
            info.pairs_rejected_pattern += counts.pattern;
            info.pairs_rejected_combinatorial += counts.combinatorial;
            info.adjacency_tests += counts.rank_tests;
            info.rays_created += new.len() as u64;
            created += new.len();
            kept.extend(new);
        }
        info.peak_rays = info.peak_rays.max(held + created);
        info.peak_bytes = info.peak_rays as u64 * bytes;
        rays = kept;
        if id % 4 == 0 {
            let i = id / 4;
            info.node_order.push(i);
            info.rays_after_node.push(rays.len());
            progress(Progress {
                done: i + 1,
                total: m,
                rays: rays.len(),
                nodes: 0,
            });
        }
    }
    if !pruned {
        info.extreme_rays_total = rays.len();
    }

    // The complementary ones, their statuses read off the (now complete) zero sets.
    let solutions = rays
        .par_iter()
        .filter_map(|ray| {
            let status: Option<Vec<NodeStatus>> = (0..m)
                .map(|i| {
                    let t = [0, 1, 2, 3].map(|k| has_bit(&ray.z, 4 * i + k));
                    match t {
                        [false, true, true, true] => Some(NodeStatus::Separated),
                        [true, true, true, true] => Some(NodeStatus::Grazing),
                        [true, false, false, false] => Some(NodeStatus::Stick),
                        [true, false, true, false] => Some(NodeStatus::SlipPlus),
                        [true, false, false, true] => Some(NodeStatus::SlipMinus),
                        // u_n > 0 and r_n > 0: not complementary. (r_n = 0 makes both friction
                        // rows tight, and both tight make r_n = 0, so nothing else occurs.)
                        _ => None,
                    }
                })
                .collect();
            let status = status?;
            let u: Vec<BigRational> = ray
                .x
                .iter()
                .map(|v| BigRational::from_integer(v.clone()))
                .collect();
            let r = p.reaction(&u);
            let total = r.iter().step_by(2).fold(BigRational::zero(), |s, x| s + x);
            debug_assert!(total.is_positive(), "a nonzero ray of C presses somewhere");
            let scale = total.recip();
            let normalise = |v: Vec<BigRational>| v.into_iter().map(|x| x * &scale).collect();
            Some(ExactSolution {
                status,
                ray: ExactRay {
                    u: normalise(u),
                    r: normalise(r),
                },
            })
        })
        .collect();
    Ok(solutions)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// One node, `K = [[2, 1], [1, 1]]`: wedged iff `mu >= K_tt / |K_nt| = 1`. At `mu = 1`
    /// exactly, the stick ray `u = (0, 1)`, `r = (1, 1)` is on the friction edge: slip+.
    #[test]
    fn one_node_at_and_around_its_critical_mu() {
        let k = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 1.0]);
        for (mu, expect) in [
            (0.75, None),
            (1.0, Some(NodeStatus::SlipPlus)),
            (1.25, Some(NodeStatus::Stick)),
        ] {
            let p = Problem::new(2, k.clone(), mu).unwrap();
            let dd = enumerate_exact(&p).unwrap();
            let brute = brute_force_exact(&p).unwrap();
            assert_eq!(dd, brute, "mu = {mu}");
            let statuses: Vec<NodeStatus> = dd.rays.iter().map(|r| r.status[0]).collect();
            assert_eq!(
                statuses,
                expect.into_iter().collect::<Vec<_>>(),
                "mu = {mu}"
            );
            if expect.is_some() {
                let one = BigRational::from_integer(1.into());
                assert_eq!(dd.rays[0].ray.r, vec![one.clone(), one.clone()]);
                assert_eq!(dd.rays[0].ray.u, vec![BigRational::zero(), one]);
                assert_eq!(dd.cones.len(), 1);
            }
        }
    }
}
