//! Maximal cliques by Bron-Kerbosch with pivoting (Tomita et al.), on bitsets.
//!
//! The graph joins cross-complementary rays; its maximal cliques are the maximal index sets `B`
//! whose cones `C_B` make up the solution set (de Moor, Vandenberghe & Vandewalle 1992).
//!
//! The outer level is Eppstein, Loeffler and Strash's: the vertices in a degeneracy order, and
//! for each vertex `v` the cliques whose first vertex in that order is `v` (`P` its later
//! neighbours, `X` its earlier ones), one independent search per vertex, on the threads. Below
//! it the sets lie in one neighbourhood, small against the graph, so each call works on the
//! words where its sets have members only. (One search from the whole graph, every call over
//! every word, on the 2D plug of `examples/plug2d.toml` at `mu = 10`, 8,488 sign classes of 222
//! neighbours on average in 133 words each: 190k calls, 3.3 s of a 3.6 s run.)

use rayon::prelude::*;

/// All maximal cliques of the undirected graph on `0..n` given by `adjacent(i, j)` (called only
/// with `i < j`; the graph is undirected). Each clique is sorted; the list is sorted. A vertex
/// with no neighbour is a clique of its own.
pub fn maximal_cliques(n: usize, adjacent: impl Fn(usize, usize) -> bool) -> Vec<Vec<usize>> {
    if n == 0 {
        return Vec::new();
    }
    let words = n.div_ceil(64);
    let mut nbr = vec![0u64; n * words];
    for i in 0..n {
        for j in i + 1..n {
            if adjacent(i, j) {
                nbr[i * words + j / 64] |= 1 << (j % 64);
                nbr[j * words + i / 64] |= 1 << (i % 64);
            }
        }
    }
    let given = Graph { words, nbr };
    let order = given.degeneracy_order();
    // The graph relabelled by position in the order.
    let mut position = vec![0; n];
    for (k, &v) in order.iter().enumerate() {
        position[v] = k;
    }
    let mut sorted = vec![0u64; n * words];
    for v in 0..n {
        let k = position[v];
        for w in ones(given.row(v)) {
            let l = position[w];
            sorted[k * words + l / 64] |= 1 << (l % 64);
        }
    }
    let graph = Graph { words, nbr: sorted };
    let mut out: Vec<Vec<usize>> = (0..n)
        .into_par_iter()
        .flat_map_iter(|k| {
            let row = graph.row(k);
            let (mut p, mut x) = (vec![0u64; words], vec![0u64; words]);
            for (w, &bits) in row.iter().enumerate() {
                // Bits above `k` in its word and every bit of later words go to `P`.
                let later = match (w * 64).cmp(&(k - k % 64)) {
                    std::cmp::Ordering::Less => 0,
                    std::cmp::Ordering::Equal => {
                        (!0u64).checked_shl(k as u32 % 64 + 1).unwrap_or(0)
                    }
                    std::cmp::Ordering::Greater => !0,
                };
                p[w] = bits & later;
                x[w] = bits & !later;
            }
            let mut found = Vec::new();
            graph.expand(&mut vec![k], p, x, &mut found);
            found
        })
        .collect();
    for c in &mut out {
        c.iter_mut().for_each(|v| *v = order[*v]);
        c.sort_unstable();
    }
    out.sort();
    out
}

struct Graph {
    words: usize,
    nbr: Vec<u64>,
}

impl Graph {
    /// The vertices in a degeneracy order: each has the fewest neighbours among those not yet
    /// taken, so that its later neighbours are few (Batagelj and Zaversnik's bucket algorithm,
    /// linear in the edges; a heap of degrees had cost a third of the cliques' time).
    fn degeneracy_order(&self) -> Vec<usize> {
        let n = self.nbr.len() / self.words;
        let mut degree: Vec<usize> = (0..n)
            .map(|v| self.row(v).iter().map(|w| w.count_ones() as usize).sum())
            .collect();
        let top = degree.iter().copied().max().unwrap_or(0);
        // `start[d]`: where the vertices of degree `d` begin in `order`, sorted by degree.
        let mut start = vec![0usize; top + 2];
        for &d in &degree {
            start[d + 1] += 1;
        }
        for d in 0..=top {
            start[d + 1] += start[d];
        }
        let mut order = vec![0usize; n];
        let mut position = vec![0usize; n];
        let mut next = start.clone();
        for v in 0..n {
            position[v] = next[degree[v]];
            order[position[v]] = v;
            next[degree[v]] += 1;
        }
        for k in 0..n {
            let v = order[k];
            for w in ones(self.row(v)) {
                if degree[w] > degree[v] {
                    // Move `w` to the front of its degree's bucket, then out of it (one down).
                    let d = degree[w];
                    let first = start[d];
                    let u = order[first];
                    if u != w {
                        order.swap(first, position[w]);
                        position[u] = position[w];
                        position[w] = first;
                    }
                    start[d] += 1;
                    degree[w] -= 1;
                }
            }
        }
        order
    }

    fn row(&self, v: usize) -> &[u64] {
        &self.nbr[v * self.words..(v + 1) * self.words]
    }

    /// Bron-Kerbosch with Tomita's pivot. The sets shrink fast (`P` is a neighbourhood after
    /// the first level): the pivot's counts and the children's `P` are taken over the words
    /// where `P` has members only, and `X` over its own. (Over all words, on the 2D plug of
    /// `examples/plug2d.toml` at `mu = 10`, 8,488 sign classes in 133 words each, the cliques
    /// took 3.3 s of a 3.6 s run: 190k calls, 15M members of `P` and `X` each counted over
    /// every word.)
    fn expand(&self, r: &mut Vec<usize>, p: Vec<u64>, x: Vec<u64>, out: &mut Vec<Vec<usize>>) {
        let p_words: Vec<usize> = (0..self.words).filter(|&w| p[w] != 0).collect();
        let x_words: Vec<usize> = (0..self.words).filter(|&w| x[w] != 0).collect();
        if p_words.is_empty() {
            if x_words.is_empty() {
                out.push(r.clone());
            }
            return;
        }
        // Pivot: the vertex of P u X with the most neighbours in P.
        let in_p = |v: usize| -> u32 {
            let row = self.row(v);
            p_words.iter().map(|&w| (row[w] & p[w]).count_ones()).sum()
        };
        let mut pivot = usize::MAX;
        let mut best = -1i64;
        for v in ones_in(&p, &p_words).chain(ones_in(&x, &x_words)) {
            let c = i64::from(in_p(v));
            if c > best {
                best = c;
                pivot = v;
            }
        }
        let pivot_row = self.row(pivot);
        let candidates: Vec<usize> = p_words
            .iter()
            .flat_map(|&w| bits_of(w, p[w] & !pivot_row[w]))
            .collect();
        let (mut p, mut x) = (p, x);
        for v in candidates {
            let nv = self.row(v);
            let mut p2 = vec![0u64; self.words];
            for &w in &p_words {
                p2[w] = p[w] & nv[w];
            }
            let mut x2 = vec![0u64; self.words];
            for &w in x_words.iter().chain(&p_words) {
                x2[w] = x[w] & nv[w];
            }
            r.push(v);
            self.expand(r, p2, x2, out);
            r.pop();
            p[v / 64] &= !(1 << (v % 64));
            x[v / 64] |= 1 << (v % 64);
        }
    }
}

/// The members of word `w` (bits `word`), increasing.
fn bits_of(w: usize, mut word: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (word != 0).then(|| {
            let b = word.trailing_zeros() as usize;
            word &= word - 1;
            w * 64 + b
        })
    })
}

/// The members of the set `bits` in its words `words` (the others empty), increasing.
fn ones_in<'a>(bits: &'a [u64], words: &'a [usize]) -> impl Iterator<Item = usize> + 'a {
    words.iter().flat_map(move |&w| bits_of(w, bits[w]))
}

/// The members of the set `bits`, increasing.
fn ones(bits: &[u64]) -> impl Iterator<Item = usize> + '_ {
    bits.iter()
        .enumerate()
        .flat_map(|(w, &word)| bits_of(w, word))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Brute force: every subset that is a clique and is not contained in a larger clique.
    fn brute(n: usize, adj: &dyn Fn(usize, usize) -> bool) -> Vec<Vec<usize>> {
        let is_clique = |s: u32| {
            (0..n)
                .all(|i| (0..n).all(|j| i == j || s >> i & 1 == 0 || s >> j & 1 == 0 || adj(i, j)))
        };
        let mut out = Vec::new();
        for s in 1u32..(1 << n) {
            if is_clique(s) && (0..n).all(|v| s >> v & 1 == 1 || !is_clique(s | 1 << v)) {
                out.push((0..n).filter(|&i| s >> i & 1 == 1).collect());
            }
        }
        out.sort();
        out
    }

    #[test]
    fn matches_brute_force_on_random_graphs() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for trial in 0..300 {
            let n = 1 + trial % 12;
            let density = rng.gen_range(0.1..0.9);
            // Upper triangle drawn, read symmetrically.
            let upper: Vec<bool> = (0..n * n).map(|_| rng.gen_bool(density)).collect();
            let adj = |i: usize, j: usize| upper[i.min(j) * n + i.max(j)];
            assert_eq!(maximal_cliques(n, adj), brute(n, &adj), "trial {trial}");
        }
    }

    /// Bron-Kerbosch without pivot or ordering, on lists: a second, plain implementation.
    fn plain(n: usize, adj: &dyn Fn(usize, usize) -> bool) -> Vec<Vec<usize>> {
        fn bk(
            adj: &dyn Fn(usize, usize) -> bool,
            r: &mut Vec<usize>,
            mut p: Vec<usize>,
            mut x: Vec<usize>,
            out: &mut Vec<Vec<usize>>,
        ) {
            if p.is_empty() && x.is_empty() {
                let mut c = r.clone();
                c.sort_unstable();
                out.push(c);
            }
            while let Some(v) = p.pop() {
                let near = |s: &[usize]| s.iter().copied().filter(|&w| adj(v, w)).collect();
                r.push(v);
                bk(adj, r, near(&p), near(&x), out);
                r.pop();
                x.push(v);
            }
        }
        let mut out = Vec::new();
        bk(adj, &mut Vec::new(), (0..n).collect(), Vec::new(), &mut out);
        out.sort();
        out
    }

    /// Graphs of 65 to 260 vertices (several words, vertices of degree zero), random ones and
    /// the graphs the pieces use (cross-complementary sign vectors): the same cliques as the
    /// plain implementation.
    #[test]
    fn matches_a_plain_search_on_larger_graphs() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for trial in 0..40 {
            let n = rng.gen_range(65..260);
            let adj: Box<dyn Fn(usize, usize) -> bool> = if trial % 2 == 0 {
                let density = rng.gen_range(0.0..0.08);
                let upper: Vec<bool> = (0..n * n).map(|_| rng.gen_bool(density)).collect();
                Box::new(move |i: usize, j: usize| upper[i.min(j) * n + i.max(j)])
            } else {
                // Sign vectors over 10 nodes: pressed, open or neither.
                let signs: Vec<(u16, u16)> = (0..n)
                    .map(|_| {
                        let pressed: u16 = rng.gen::<u16>() & 0x3ff;
                        (pressed, rng.gen::<u16>() & 0x3ff & !pressed)
                    })
                    .collect();
                Box::new(move |i: usize, j: usize| {
                    let (a, b) = (signs[i], signs[j]);
                    (a.0 | b.0) & (a.1 | b.1) == 0
                })
            };
            let fast = maximal_cliques(n, &adj);
            assert!(!fast.is_empty(), "trial {trial}");
            assert_eq!(fast, plain(n, &adj), "trial {trial}, {n} vertices");
        }
    }

    #[test]
    fn handles_more_than_64_vertices() {
        // Two disjoint complete graphs of 40 and 50 vertices.
        let adj = |i: usize, j: usize| (i < 40) == (j < 40);
        let c = maximal_cliques(90, adj);
        assert_eq!(c, vec![(0..40).collect::<Vec<_>>(), (40..90).collect()]);
        assert!(maximal_cliques(0, adj).is_empty());
    }
}
