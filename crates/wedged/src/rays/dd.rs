//! Double description in `r`-space (`u = K^{-1} r`), for the seed's pruned method and the plain
//! baseline, with a polyhedral friction law: in 2D the exact one, in 3D a circumscribed pyramid
//! (the candidate generator of the 3D sign patterns, see `crate::patterns`).
//!
//! Step 1: the friction constraints alone give the product of `m` polyhedral cones, whose extreme
//! rays are known: in 2D `r = e_{n_i} +/- mu e_{t_i}`, in 3D the `k` edges of each node's
//! pyramid. Step 2: the constraints `u_n_i >= 0` are added one node at a time. For every ray `a`
//! with `u_n_i > 0` and `b` with `u_n_i < 0` that are adjacent in the current cone, the point of
//! `[a, b]` on `u_n_i = 0` becomes a new ray; then the rays with `u_n_i < 0` are dropped.
//!
//! [`Variant::Pruned`] (MISSION section 4) also
//! - skips a pair whose combination would break complementarity at a processed node (filter (a));
//! - drops every ray that breaks complementarity at a processed node;
//! - and therefore decides adjacency **algebraically** (filter (b)): the constraints tight at both
//!   rays must have rank `dm - 2`. The combinatorial test (no other held ray is tight on every
//!   constraint common to `a` and `b`) is still sound as a filter that *rejects*, because every
//!   held ray is an extreme ray of the current cone; after the deletions it can no longer accept.
//!
//! [`Variant::Full`] keeps every ray, so the combinatorial test is exact; complementarity is
//! filtered at the end.
//!
//! Each ray carries its zero set (the constraints it is tight on) as a bitset. Zero sets are
//! propagated combinatorially: a new ray from adjacent `a`, `b` is tight exactly on
//! `Z(a) & Z(b)` plus the new constraint. The only floating-point decisions are the sign of
//! `u_n_i` at each ray (relative tolerance, see [`Settings::zero_tol`]) and the rank test.

use rayon::prelude::*;

use std::sync::atomic::{AtomicUsize, Ordering};

use crate::run::Control;

use super::params::{Info, Progress, RawRay, Settings};

use crate::linalg::rank;
use crate::problem::Problem;
use crate::solution::NodeStatus;

mod tree;
use tree::PatternTree;

/// Which double description runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Variant {
    /// The seed's method: pattern filter, pruning, algebraic adjacency.
    Pruned,
    /// Every extreme ray of `C`, then a complementarity filter.
    Full,
}

/// A polyhedral friction law, the same at every node: facet `j` is `mu r_n - a_j . r_t >= 0` for
/// a unit tangent direction `a_j`.
///
/// - 2D ([`Friction::planar`]): `a = +1, -1`, the exact law `|r_t| <= mu r_n`.
/// - 3D ([`Friction::pyramid`]): `a_j = (cos 2 pi j / k, sin 2 pi j / k)`, `k >= 3`: the pyramid
///   whose faces touch the round cone `||r_t|| <= mu r_n`, so it contains it (circumscribed).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Friction {
    dim: usize,
    mu: f64,
    /// The `k` tangent directions, `dim - 1` components each.
    dirs: Vec<Vec<f64>>,
}

impl Friction {
    /// The exact 2D law.
    pub(crate) fn planar(mu: f64) -> Friction {
        Friction {
            dim: 2,
            mu,
            dirs: vec![vec![1.0], vec![-1.0]],
        }
    }

    /// The circumscribed pyramid with `k >= 3` faces of the 3D cone.
    pub(crate) fn pyramid(mu: f64, k: usize) -> Friction {
        assert!((3..=64).contains(&k), "a pyramid has 3 to 64 faces");
        let dirs = (0..k)
            .map(|j| {
                let t = 2.0 * std::f64::consts::PI * j as f64 / k as f64;
                vec![t.cos(), t.sin()]
            })
            .collect();
        Friction { dim: 3, mu, dirs }
    }

    fn k(&self) -> usize {
        self.dirs.len()
    }

    /// Constraint bits per node in the zero sets: node `i` owns bits `(k + 1) i + f` for its facet
    /// `f` and `(k + 1) i + k` for `u_n_i >= 0`.
    fn per_node(&self) -> usize {
        self.k() + 1
    }

    /// The extreme rays of one node's cone, as `(r_n, r_t...)` with `r_n = 1`, each with the
    /// facets it is tight on: in 2D the two ends `(1, +/-mu)`, in 3D the pyramid's edges, between
    /// faces `j` and `j + 1`.
    fn edges(&self) -> Vec<(Vec<f64>, Vec<usize>)> {
        let k = self.k();
        if self.dim == 2 {
            return (0..k)
                .map(|j| (vec![1.0, self.mu * self.dirs[j][0]], vec![j]))
                .collect();
        }
        (0..k)
            .map(|j| (self.edge(j).to_vec(), vec![j, (j + 1) % k]))
            .collect()
    }

    /// The 3D pyramid's edge between faces `j` and `j + 1`, `(1, r_t)`: `r_t` bisects their
    /// directions at the length that touches both faces.
    fn edge(&self, j: usize) -> [f64; 3] {
        let half = std::f64::consts::PI / self.k() as f64;
        let t = 2.0 * half * j as f64 + half;
        let len = self.mu / half.cos();
        [1.0, len * t.cos(), len * t.sin()]
    }

    /// A basis of the subspace of one node's `(r_n, r_t...)` where the facets in the bit mask
    /// `tight` hold with equality, appended to `out` (columns of `dim` values, padded to 3).
    fn basis(&self, tight: u64, out: &mut Vec<[f64; 3]>) {
        let (d, k, mu) = (self.dim, self.k(), self.mu);
        let first = tight.trailing_zeros() as usize;
        match tight.count_ones() as usize {
            0 => out.extend((0..d).map(|c| {
                let mut e = [0.0; 3];
                e[c] = 1.0;
                e
            })),
            l if l == k => {}
            1 => {
                let a = &self.dirs[first];
                // (1, mu a) lies on the facet; in 3D so does the tangent (0, a_perp).
                if d == 2 {
                    out.push([1.0, mu * a[0], 0.0]);
                } else {
                    out.push([1.0, mu * a[0], mu * a[1]]);
                    out.push([0.0, -a[1], a[0]]);
                }
            }
            2 if d == 3 => {
                let last = 63 - tight.leading_zeros() as usize;
                // Neighbouring faces meet on an edge; others only at the apex.
                let edge = if last == first + 1 {
                    Some(first)
                } else if first == 0 && last == k - 1 {
                    Some(k - 1)
                } else {
                    None
                };
                if let Some(j) = edge {
                    out.push(self.edge(j));
                }
            }
            _ => {}
        }
    }

    /// The status of a node whose facets in the mask `tight` hold with equality and whose gap is
    /// closed (`u_n = 0`), with `r != 0` (some facet slack). In 3D `Slip` means "on a face of
    /// the pyramid": a candidate, decided exactly by the SOCP later.
    fn pressed_status(&self, tight: u64) -> NodeStatus {
        match (self.dim, tight) {
            (_, 0) => NodeStatus::Stick,
            (2, 1) => NodeStatus::SlipPlus,
            (2, _) => NodeStatus::SlipMinus,
            (_, _) => NodeStatus::Slip,
        }
    }
}

/// Rays held contiguously: reactions with stride `n = 2m`, zero sets with stride `words`, and two
/// node masks with stride `node_words`: `gap` (node processed and `u_n > 0`) and `press`
/// (`r_n > 0`). The masks make filter (a) two word operations per pair.
struct Rays {
    n: usize,
    words: usize,
    node_words: usize,
    r: Vec<f64>,
    z: Vec<u64>,
    gap: Vec<u64>,
    press: Vec<u64>,
}

impl Rays {
    fn new(n: usize, words: usize, node_words: usize) -> Self {
        Rays {
            n,
            words,
            node_words,
            r: Vec::new(),
            z: Vec::new(),
            gap: Vec::new(),
            press: Vec::new(),
        }
    }
    fn len(&self) -> usize {
        self.r.len() / self.n
    }
    fn r(&self, a: usize) -> &[f64] {
        &self.r[a * self.n..(a + 1) * self.n]
    }
    fn z(&self, a: usize) -> &[u64] {
        &self.z[a * self.words..(a + 1) * self.words]
    }
    fn gap(&self, a: usize) -> &[u64] {
        &self.gap[a * self.node_words..(a + 1) * self.node_words]
    }
    fn press(&self, a: usize) -> &[u64] {
        &self.press[a * self.node_words..(a + 1) * self.node_words]
    }
    fn push(&mut self, r: &[f64], z: &[u64], gap: &[u64], press: &[u64]) {
        self.r.extend_from_slice(r);
        self.z.extend_from_slice(z);
        self.gap.extend_from_slice(gap);
        self.press.extend_from_slice(press);
    }
    fn append(&mut self, other: Rays) {
        self.r.extend(other.r);
        self.z.extend(other.z);
        self.gap.extend(other.gap);
        self.press.extend(other.press);
    }
}

/// Bit `b` of the bit set `z` (words of 64; also the faces' double description's,
/// `rays/search/face.rs`).
pub(super) fn bit(z: &[u64], b: usize) -> bool {
    z[b / 64] >> (b % 64) & 1 == 1
}
/// Sets bit `b` of `z`.
pub(super) fn set_bit(z: &mut [u64], b: usize) {
    z[b / 64] |= 1 << (b % 64);
}

impl Friction {
    /// The zero-set bit of facet `f` of node `i`.
    fn facet(&self, i: usize, f: usize) -> usize {
        self.per_node() * i + f
    }

    /// The zero-set bit of `u_n_i >= 0`.
    fn gap_bit(&self, i: usize) -> usize {
        self.per_node() * i + self.k()
    }

    /// The facets of node `j` tight in zero set `z`, as a bit mask.
    fn tight(&self, z: &[u64], j: usize) -> u64 {
        (0..self.k())
            .filter(|&f| bit(z, self.facet(j, f)))
            .fold(0, |acc, f| acc | 1 << f)
    }

    /// Node `j` has `r_j = 0` in a ray with zero set `z` (every friction facet tight).
    fn r_zero(&self, z: &[u64], j: usize) -> bool {
        (0..self.k()).all(|f| bit(z, self.facet(j, f)))
    }
}

/// The `press` mask of a zero set: nodes with `r_j != 0`.
fn press_mask(friction: &Friction, z: &[u64], m: usize, node_words: usize) -> Vec<u64> {
    let mut p = vec![0u64; node_words];
    for j in (0..m).filter(|&j| !friction.r_zero(z, j)) {
        set_bit(&mut p, j);
    }
    p
}

/// Counters of one node's pair loop, summed over threads.
#[derive(Default)]
struct PairCounts {
    pairs: u64,
    pattern: u64,
    combinatorial: u64,
    rank_tests: u64,
    /// Pairs rejected by the superset query on held rays.
    superset_rejects: u64,
    /// Rank tests that found the pair not adjacent.
    rank_rejects: u64,
}

/// Read-only data of one step.
struct Step<'a> {
    rays: &'a Rays,
    value: &'a [f64],
    /// The rays with `u_n_i < 0`, to find pairs.
    tree: &'a PatternTree,
    /// Every held ray (pruned variant), for the combinatorial rejection test.
    held: Option<&'a PatternTree>,
    processed: &'a [usize],
    gap_rows: &'a [f64],
    node: usize,
    m: usize,
    friction: &'a Friction,
    tol: f64,
    variant: Variant,
}

impl Step<'_> {
    /// The new rays from plus ray `a` and every minus ray (in the tree's leaf order). Subtrees
    /// of the minus rays are skipped whole when filter (a) or the count fails for all of them.
    fn combine(&self, a: usize, out: &mut Rays, counts: &mut PairCounts) {
        let rays = self.rays;
        let tree = self.tree;
        let (n, words) = (rays.n, rays.words);
        let mut common = vec![0u64; words];
        let mut scratch = Vec::new();
        let (za, ga, pa) = (rays.z(a), rays.gap(a), rays.press(a));
        let pruned = self.variant == Variant::Pruned;
        let mut stack = vec![0usize];
        while let Some(t) = stack.pop() {
            let node = &tree.nodes[t];
            let size = (node.end - node.start) as u64;
            // Filter (a) for the whole subtree: a gap of `a` where all of them press, or a
            // pressure of `a` where all of them have a gap.
            if pruned && clash(ga, pa, tree.and_gap(t), tree.and_press(t)) {
                counts.pairs += size;
                counts.pattern += size;
                continue;
            }
            // No ray of the subtree shares n - 2 tight constraints with `a`.
            let shared: u32 = za
                .iter()
                .zip(tree.or_z(t))
                .map(|(x, y)| (x & y).count_ones())
                .sum();
            if shared as usize + 2 < n {
                counts.pairs += size;
                counts.combinatorial += size;
                continue;
            }
            if let Some((left, right)) = node.children {
                stack.push(right);
                stack.push(left);
                continue;
            }
            for &b in &tree.items[node.start..node.end] {
                counts.pairs += 1;
                let (zb, gb, pb) = (rays.z(b), rays.gap(b), rays.press(b));
                // Filter (a): the sum stays complementary at the processed nodes. Each ray is
                // complementary on its own, so only a gap of one against a pressure of the other
                // fails.
                if pruned && clash(ga, pa, gb, pb) {
                    counts.pattern += 1;
                    continue;
                }
                let mut count = 0;
                for w in 0..words {
                    common[w] = za[w] & zb[w];
                    count += common[w].count_ones() as usize;
                }
                // Rank n - 2 needs at least n - 2 tight constraints.
                if count + 2 < n {
                    counts.combinatorial += 1;
                    continue;
                }
                self.emit(a, b, &common, out, counts, &mut scratch);
            }
        }
    }

    /// Decides adjacency of `a` and `b` (whose common zero set is `common`) and, if they are
    /// adjacent, pushes their combination on `u_n_i = 0`.
    fn emit(
        &self,
        a: usize,
        b: usize,
        common: &[u64],
        out: &mut Rays,
        counts: &mut PairCounts,
        scratch: &mut Vec<f64>,
    ) {
        let rays = self.rays;
        let adjacent = match self.variant {
            // Every extreme ray of the current cone is held: the combinatorial test is exact.
            Variant::Full => combinatorial_adjacent(rays, a, b, common),
            // Rays were deleted: decide algebraically. The combinatorial test is still a sound
            // filter that rejects (every held ray is an extreme ray of the current cone), and a
            // superset query on the tree of held rays is cheaper than the rank.
            Variant::Pruned => {
                if self
                    .held
                    .is_some_and(|held| held.has_superset(rays, common, a, b))
                {
                    counts.combinatorial += 1;
                    counts.superset_rejects += 1;
                    return;
                }
                counts.rank_tests += 1;
                let adjacent = algebraic_adjacent(
                    common,
                    self.m,
                    self.friction,
                    self.processed,
                    self.gap_rows,
                    self.tol,
                    scratch,
                );
                counts.rank_rejects += !adjacent as u64;
                adjacent
            }
        };
        if !adjacent {
            counts.combinatorial += (self.variant == Variant::Full) as u64;
            return;
        }
        // The point of [a, b] on u_n_i = 0, normalised to sum r_n = 1.
        let (va, vb) = (self.value[a], -self.value[b]);
        let (ra, rb) = (rays.r(a), rays.r(b));
        let mut r: Vec<f64> = ra.iter().zip(rb).map(|(x, y)| va * y + vb * x).collect();
        normalise(&mut r, self.friction.dim);
        let mut z = common.to_vec();
        set_bit(&mut z, self.friction.gap_bit(self.node));
        // The new ray has u_n_i = 0; elsewhere it has a gap or a pressure where a or b has.
        let or = |x: &[u64], y: &[u64]| x.iter().zip(y).map(|(p, q)| p | q).collect::<Vec<u64>>();
        out.push(
            &r,
            &z,
            &or(rays.gap(a), rays.gap(b)),
            &or(rays.press(a), rays.press(b)),
        );
    }
}

/// Runs the double description with the friction law `friction` (of the problem's dimension and
/// `mu`) and returns the complementary extreme rays.
pub(crate) fn run(
    problem: &Problem,
    friction: &Friction,
    settings: &Settings,
    info: &mut Info,
    variant: Variant,
    progress: &dyn Fn(Progress),
    control: &Control,
) -> Vec<RawRay> {
    let m = problem.nodes();
    let d = problem.dim();
    assert_eq!(
        d, friction.dim,
        "the friction law's dimension is the problem's"
    );
    let n = d * m;
    let g = problem.compliance();
    let tol = settings.zero_tol;
    let words = (friction.per_node() * m).div_ceil(64);
    let node_words = m.div_ceil(64);
    let mut rays = Rays::new(n, words, node_words);
    let ray_bytes = 8 * (n + words + 2 * node_words) as u64;
    control.set_ray_bytes(ray_bytes);

    // Step 1: the extreme rays of the friction cones, `k` per node.
    let edges = friction.edges();
    for i in 0..m {
        for (edge, tight) in &edges {
            let mut r = vec![0.0; n];
            r[d * i..d * i + d].copy_from_slice(edge);
            let mut z = vec![0u64; words];
            for j in (0..m).filter(|&j| j != i) {
                for f in 0..friction.k() {
                    set_bit(&mut z, friction.facet(j, f));
                }
            }
            for &f in tight {
                set_bit(&mut z, friction.facet(i, f));
            }
            let press = press_mask(friction, &z, m, node_words);
            rays.push(&r, &z, &vec![0u64; node_words], &press);
        }
    }
    info.peak_rays = rays.len();
    info.peak_bytes = info.peak_rays as u64 * ray_bytes;

    // Dense copy of the compliance rows `G[n_j, :]`, for cache-friendly dot products.
    let gap_rows: Vec<f64> = (0..m)
        .flat_map(|j| g.row(d * j).iter().copied().collect::<Vec<_>>())
        .collect();
    let mut processed: Vec<usize> = Vec::with_capacity(m);

    // Step 2: add u_n_i >= 0 node by node, in the input order. (Measured: a greedy order, fewest
    // pairs first, held fewer rays on some problems and more on others, within a factor of two,
    // and cost a classification of every remaining node at each step; the input order was as fast
    // or faster on the random and lattice families. The answer does not depend on the order.)
    let mut use_superset_filter = true;
    for i in 0..m {
        let (value, plus, minus, zero, near) = classify(&rays, &gap_rows[i * n..(i + 1) * n], tol);
        info.near_degenerate += near;
        let tree = PatternTree::build(&rays, &minus);
        // The superset filter pays only where the count lets many non-adjacent pairs through
        // (degenerate problems); where nearly every candidate is adjacent, its failing queries
        // cost more than the rank tests they would save. Decide per node from the last one.
        let held = (variant == Variant::Pruned && use_superset_filter).then(|| {
            let all: Vec<usize> = (0..rays.len()).collect();
            PatternTree::build(&rays, &all)
        });
        let step = Step {
            rays: &rays,
            value: &value,
            tree: &tree,
            held: held.as_ref(),
            processed: &processed,
            gap_rows: &gap_rows,
            node: i,
            m,
            friction,
            tol,
            variant,
        };
        // Rays created in this step so far, for the max-rays limit.
        let created = AtomicUsize::new(0);
        let chunks: Vec<(Rays, PairCounts)> = plus
            .par_chunks(16)
            .map(|chunk| {
                let mut out = Rays::new(n, words, node_words);
                let mut counts = PairCounts::default();
                for &a in chunk {
                    if control.must_stop(rays.len() + created.load(Ordering::Relaxed)) {
                        break;
                    }
                    let before = out.len();
                    step.combine(a, &mut out, &mut counts);
                    created.fetch_add(out.len() - before, Ordering::Relaxed);
                }
                (out, counts)
            })
            .collect();
        if control.must_stop(rays.len() + created.load(Ordering::Relaxed)) {
            // No ray is final before the last node: report none.
            return Vec::new();
        }

        // Keep: rays with u_n_i > 0 (in the pruned variant only if r_i = 0), rays with u_n_i = 0
        // (now tight on the new constraint), and the new rays.
        let mut kept = Rays::new(n, words, node_words);
        for &a in &plus {
            if variant == Variant::Full || friction.r_zero(rays.z(a), i) {
                let mut gap = rays.gap(a).to_vec();
                set_bit(&mut gap, i);
                kept.push(rays.r(a), rays.z(a), &gap, rays.press(a));
            }
        }
        for &a in &zero {
            let mut z = rays.z(a).to_vec();
            set_bit(&mut z, friction.gap_bit(i));
            kept.push(rays.r(a), &z, rays.gap(a), rays.press(a));
        }
        let (mut superset_rejects, mut rank_tests, mut rank_rejects) = (0, 0, 0);
        for (new, counts) in chunks {
            superset_rejects += counts.superset_rejects;
            rank_tests += counts.rank_tests;
            rank_rejects += counts.rank_rejects;
            info.pairs_tested += counts.pairs;
            info.pairs_rejected_pattern += counts.pattern;
            info.pairs_rejected_combinatorial += counts.combinatorial;
            info.adjacency_tests += counts.rank_tests;
            info.rays_created += new.len() as u64;
            kept.append(new);
        }
        // In memory at once: the old set and the new one.
        info.peak_rays = info.peak_rays.max(rays.len() + kept.len());
        info.peak_bytes = info.peak_rays as u64 * ray_bytes;
        // Keep the filter while it rejects at least a tenth of what reaches it; turn it on when
        // more than half of the rank tests reject.
        let reached = superset_rejects + rank_tests;
        use_superset_filter = if held.is_some() {
            reached > 0 && superset_rejects * 10 >= reached
        } else {
            rank_rejects * 2 > rank_tests
        };
        rays = kept;
        processed.push(i);
        info.node_order.push(i);
        info.rays_after_node.push(rays.len());
        progress(Progress {
            done: processed.len(),
            total: m,
            rays: rays.len(),
            nodes: 0,
        });
    }

    if variant == Variant::Full {
        info.extreme_rays_total = rays.len();
    }
    (0..rays.len())
        .filter_map(|a| {
            let z = rays.z(a);
            let status: Option<Vec<NodeStatus>> =
                (0..m).map(|j| status_of(friction, z, j)).collect();
            status.map(|status| RawRay {
                r: rays.r(a).to_vec(),
                status,
            })
        })
        .collect()
}

/// The values `u_n_j` at every held ray, the rays where it is positive, negative, zero, and the
/// number of close calls.
type Signs = (Vec<f64>, Vec<usize>, Vec<usize>, Vec<usize>, u64);

/// The round-off floor of a computed compliance row, relative to its largest entry: a value
/// `sum_k G_jk r_k` below `NOISE * max_k |G_jk| * sum_k |r_k|` is zero. (`K^-1` from a Cholesky
/// factor carries errors of a few hundred ulps of its largest entries on these problems; this
/// floor is far below the method's resolution `zero_tol`.)
pub(crate) const NOISE: f64 = 1024.0 * f64::EPSILON;

/// A sign decision is a close call when `|x|` is within this factor of its zero threshold, on
/// either side ([`Info::near_degenerate`](crate::Info::near_degenerate)).
const NEAR: f64 = 100.0;

/// `u_n_j` (the dot product of `row = G[n_j, :]` with each ray) and the rays where it is positive,
/// negative and zero. Zero means `|x| <= tol * sum_k |G_{n_j k} r_k|`; a value within a factor
/// [`NEAR`] of that bound, either way, is also counted as a close call.
fn classify(rays: &Rays, row: &[f64], tol: f64) -> Signs {
    let (mut plus, mut minus, mut zero) = (Vec::new(), Vec::new(), Vec::new());
    let mut near = 0u64;
    let row_max = row.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let value: Vec<f64> = (0..rays.len())
        .map(|a| {
            let (mut v, mut s, mut size) = (0.0, 0.0, 0.0);
            for (g, r) in row.iter().zip(rays.r(a)) {
                let t = g * r;
                v += t;
                s += t.abs();
                size += r.abs();
            }
            // Below the noise floor of the computed compliance row, whatever its own terms: an
            // entry of K^-1 that is zero in exact arithmetic comes out as round-off, and a value
            // made only of such entries must not count as a sign (found by the degenerate
            // family: integer K, edge trial 4).
            let floor = NOISE * row_max * size;
            if v.abs() > tol * s / NEAR && v.abs() <= tol * s * NEAR {
                near += 1;
            }
            if v.abs() <= tol * s || v.abs() <= floor {
                zero.push(a);
            } else if v > 0.0 {
                plus.push(a);
            } else {
                minus.push(a);
            }
            v
        })
        .collect();
    (value, plus, minus, zero, near)
}

/// The status of node `j` in a ray with zero set `z` (all constraints processed), or `None` when
/// the ray breaks complementarity there.
fn status_of(friction: &Friction, z: &[u64], j: usize) -> Option<NodeStatus> {
    let tight = friction.tight(z, j);
    let r_zero = tight.count_ones() as usize == friction.k();
    Some(match (r_zero, bit(z, friction.gap_bit(j))) {
        (true, false) => NodeStatus::Separated,
        (true, true) => NodeStatus::Grazing,
        (false, false) => return None,
        (false, true) => friction.pressed_status(tight),
    })
}

/// Filter (a) on node masks: one side has a gap where the other presses, so a positive
/// combination would break complementarity there. (With the AND masks of a subtree as `b`, it is
/// true only when it holds for every ray of the subtree.)
fn clash(gap_a: &[u64], press_a: &[u64], gap_b: &[u64], press_b: &[u64]) -> bool {
    let crossed = |g: &[u64], p: &[u64]| g.iter().zip(p).any(|(x, y)| x & y != 0);
    crossed(gap_a, press_b) || crossed(gap_b, press_a)
}

fn normalise(r: &mut [f64], dim: usize) {
    let s: f64 = r.iter().step_by(dim).sum();
    r.iter_mut().for_each(|x| *x /= s);
}

/// The combinatorial test: no held ray other than `a` and `b` is tight on every constraint in
/// `common = Z(a) & Z(b)`. Exact when every extreme ray of the current cone is held (the full
/// variant). It is the same test as [`PatternTree::has_superset`], written as the textbook scan on
/// purpose: `full-dd` is the plain double description the seed improves on (cddlib's test).
/// Given the tree, full-dd runs about 14x faster (BENCHMARKS.md).
fn combinatorial_adjacent(rays: &Rays, a: usize, b: usize, common: &[u64]) -> bool {
    (0..rays.len())
        .all(|c| c == a || c == b || rays.z(c).iter().zip(common).any(|(zc, w)| w & !zc != 0))
}

/// Filter (b), algebraically: the constraints in `common` (friction facets of every node, `u_n`
/// rows of the processed nodes) have rank `dm - 2`.
///
/// The tight facets of node `k` leave a subspace of its `(r_n, r_t)` space ([`Friction::basis`]):
/// all of it (none tight), a facet's plane or line, an edge's line, or `{0}`. With `B` a basis
/// of their product (`f` columns), the rank is `(dm - f) + rank(M)`, where `M` holds the tight
/// `u_n_j` rows `G[n_j, :] B`. So the test is `rank(M) = f - 2`; `M` is small.
fn algebraic_adjacent(
    common: &[u64],
    m: usize,
    friction: &Friction,
    processed: &[usize],
    gap_rows: &[f64],
    tol: f64,
    scratch: &mut Vec<f64>,
) -> bool {
    let d = friction.dim;
    let n = d * m;
    // Columns of B as (node, local vector).
    let mut columns: Vec<(usize, [f64; 3])> = Vec::with_capacity(n);
    let mut local = Vec::with_capacity(d);
    for k in 0..m {
        local.clear();
        friction.basis(friction.tight(common, k), &mut local);
        columns.extend(local.drain(..).map(|v| (k, v)));
    }
    let f = columns.len();
    let tight: Vec<usize> = processed
        .iter()
        .copied()
        .filter(|&j| bit(common, friction.gap_bit(j)))
        .collect();
    if tight.len() + 2 < f {
        return false;
    }
    scratch.clear();
    for &j in &tight {
        let row = &gap_rows[j * n..(j + 1) * n];
        // An entry that cancels to within `tol` of its own terms is zero: otherwise a projected
        // row of pure round-off (~1e-16) would be scaled up to unit size by `rank` and count as
        // independent, and a true adjacency would be missed (found by the degenerate family:
        // an edge ray of a 2-node problem lost).
        scratch.extend(columns.iter().map(|(k, v)| {
            let (sum, size) = v
                .iter()
                .zip(&row[d * k..d * k + d])
                .fold((0.0f64, 0.0f64), |(s, z), (a, b)| {
                    (s + a * b, z + (a * b).abs())
                });
            if sum.abs() <= tol * size {
                0.0
            } else {
                sum
            }
        }));
    }
    rank(scratch, tight.len(), f, tol) + 2 == f
}
