//! Maximal cliques by Bron-Kerbosch with pivoting (Tomita et al.), on bitsets.
//!
//! The graph joins cross-complementary rays; its maximal cliques are the maximal index sets `B`
//! whose cones `C_B` make up the solution set (de Moor, Vandenberghe & Vandewalle 1992).

/// All maximal cliques of the undirected graph on `0..n` given by `adjacent(i, j)` (called only
/// with `i != j`; it must be symmetric). Each clique is sorted; the list is sorted. A vertex with
/// no neighbour is a clique of its own.
pub fn maximal_cliques(n: usize, adjacent: impl Fn(usize, usize) -> bool) -> Vec<Vec<usize>> {
    if n == 0 {
        return Vec::new();
    }
    let words = n.div_ceil(64);
    let mut nbr = vec![0u64; n * words];
    for i in 0..n {
        for j in 0..n {
            if i != j && adjacent(i, j) {
                nbr[i * words + j / 64] |= 1 << (j % 64);
            }
        }
    }
    let graph = Graph { words, nbr };
    let mut p = vec![0u64; words];
    for i in 0..n {
        p[i / 64] |= 1 << (i % 64);
    }
    let mut out = Vec::new();
    let mut r = Vec::new();
    graph.expand(&mut r, p, vec![0u64; words], &mut out);
    for c in &mut out {
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
    fn row(&self, v: usize) -> &[u64] {
        &self.nbr[v * self.words..(v + 1) * self.words]
    }

    fn expand(&self, r: &mut Vec<usize>, p: Vec<u64>, x: Vec<u64>, out: &mut Vec<Vec<usize>>) {
        if p.iter().all(|&w| w == 0) {
            if x.iter().all(|&w| w == 0) {
                out.push(r.clone());
            }
            return;
        }
        // Pivot: the vertex of P u X with the most neighbours in P.
        let mut pivot = usize::MAX;
        let mut best = -1i64;
        for v in ones(&p).chain(ones(&x)) {
            let c: u32 = self
                .row(v)
                .iter()
                .zip(&p)
                .map(|(a, b)| (a & b).count_ones())
                .sum();
            if c as i64 > best {
                best = c as i64;
                pivot = v;
            }
        }
        let candidates: Vec<u64> = p.iter().zip(self.row(pivot)).map(|(a, b)| a & !b).collect();
        let (mut p, mut x) = (p, x);
        for v in ones(&candidates).collect::<Vec<_>>() {
            let nv = self.row(v);
            let p2 = p.iter().zip(nv).map(|(a, b)| a & b).collect();
            let x2 = x.iter().zip(nv).map(|(a, b)| a & b).collect();
            r.push(v);
            self.expand(r, p2, x2, out);
            r.pop();
            p[v / 64] &= !(1 << (v % 64));
            x[v / 64] |= 1 << (v % 64);
        }
    }
}

fn ones(bits: &[u64]) -> impl Iterator<Item = usize> + '_ {
    bits.iter().enumerate().flat_map(|(w, &word)| {
        (0..64)
            .filter(move |b| word >> b & 1 == 1)
            .map(move |b| w * 64 + b)
    })
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

    #[test]
    fn handles_more_than_64_vertices() {
        // Two disjoint complete graphs of 40 and 50 vertices.
        let adj = |i: usize, j: usize| (i < 40) == (j < 40);
        let c = maximal_cliques(90, adj);
        assert_eq!(c, vec![(0..40).collect::<Vec<_>>(), (40..90).collect()]);
        assert!(maximal_cliques(0, adj).is_empty());
    }
}
