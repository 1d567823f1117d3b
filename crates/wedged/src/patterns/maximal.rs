//! The maximal patterns of a set (those below no other: `a` is below `b` when every positive
//! entry of `a` is one of `b`): [`maximal`] (one run's) and [`keep_maximal`] (a
//! union of shards', the first of equal ones).
//!
//! **Without comparing every pair.** `a` lies below `b` (`a != b`) when `b` has `a`'s entry at
//! every node where `a`'s is not grazing; they then differ on `a`'s grazing nodes, so a pattern
//! without grazing nodes lies below none, and one with grazing set `G` lies below another
//! exactly when another pattern agrees with it off `G`. So the patterns are grouped by grazing
//! set, and for each set that occurs, every pattern is keyed by its entries off that set and
//! the keys counted: a pattern of the group is below another exactly when its key is counted
//! twice (the patterns are distinct). The work is `n m` per grazing set that occurs (none on a
//! generic problem) instead of `n^2` comparisons: the V-groove plug's 57,818 patterns at
//! m = 40 have no grazing node, and comparing every pair took 22 s of one core there
//! (`BENCHMARKS.md`).

use std::collections::{HashMap, HashSet};

use rayon::prelude::*;

use crate::solution::ContactPattern;

/// The maximal elements of a set of patterns, without repeats, sorted.
pub(crate) fn maximal(mut all: Vec<Vec<ContactPattern>>) -> Vec<Vec<ContactPattern>> {
    all.sort();
    all.dedup();
    let distinct: Vec<&[ContactPattern]> = all.iter().map(|q| &q[..]).collect();
    let lower = below_another(&distinct);
    all.into_iter()
        .zip(lower)
        .filter_map(|(q, low)| (!low).then_some(q))
        .collect()
}

/// Which of `patterns` are maximal: below no other, and the first of equal ones.
pub fn keep_maximal(patterns: &[&[ContactPattern]]) -> Vec<bool> {
    let mut seen = HashSet::new();
    let first: Vec<bool> = patterns.iter().map(|&q| seen.insert(q)).collect();
    let distinct: Vec<&[ContactPattern]> = patterns
        .iter()
        .zip(&first)
        .filter_map(|(&q, &f)| f.then_some(q))
        .collect();
    let mut lower = below_another(&distinct).into_iter();
    first
        .iter()
        .map(|&f| f && !lower.next().expect("one answer per first pattern"))
        .collect()
}

/// Whether each of `distinct` (no two equal, all of one length) lies below another of them.
fn below_another(distinct: &[&[ContactPattern]]) -> Vec<bool> {
    let mut groups: HashMap<Vec<bool>, Vec<usize>> = HashMap::new();
    for (a, q) in distinct.iter().enumerate() {
        if q.contains(&ContactPattern::Grazing) {
            let grazing = q.iter().map(|&c| c == ContactPattern::Grazing).collect();
            groups.entry(grazing).or_default().push(a);
        }
    }
    let groups: Vec<(Vec<bool>, Vec<usize>)> = groups.into_iter().collect();
    let found: Vec<Vec<usize>> = groups
        .par_iter()
        .map(|(grazing, members)| {
            let key = |q: &[ContactPattern]| -> Vec<ContactPattern> {
                q.iter()
                    .zip(grazing)
                    .filter_map(|(&c, &g)| (!g).then_some(c))
                    .collect()
            };
            let mut count: HashMap<Vec<ContactPattern>, u32> = HashMap::new();
            for q in distinct {
                *count.entry(key(q)).or_default() += 1;
            }
            members
                .iter()
                .copied()
                .filter(|&a| count[&key(distinct[a])] >= 2)
                .collect()
        })
        .collect();
    let mut lower = vec![false; distinct.len()];
    for a in found.into_iter().flatten() {
        lower[a] = true;
    }
    lower
}

#[cfg(test)]
mod tests {
    use super::*;
    use ContactPattern::{Contact as C, Grazing as G, Separated as S};

    /// `a <= b`: every positive entry of `a` is a positive entry of `b` (the definition).
    fn below(a: &[ContactPattern], b: &[ContactPattern]) -> bool {
        a.iter()
            .zip(b)
            .all(|(&x, &y)| x == ContactPattern::Grazing || x == y)
    }

    /// The definition, pair by pair (the way both filters were computed until 2026-12-01).
    fn keep_by_pairs(patterns: &[&[ContactPattern]]) -> Vec<bool> {
        (0..patterns.len())
            .map(|a| {
                !(0..patterns.len()).any(|b| {
                    b != a
                        && below(patterns[a], patterns[b])
                        && (patterns[a] != patterns[b] || b < a)
                })
            })
            .collect()
    }

    /// A small deterministic generator (xorshift), so that the cases are seeded.
    fn patterns(seed: u64, n: usize, m: usize, grazing: u64) -> Vec<Vec<ContactPattern>> {
        let mut x = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        (0..n)
            .map(|_| {
                (0..m)
                    .map(|_| match next() % 100 {
                        r if r < grazing => G,
                        r if r % 2 == 0 => C,
                        _ => S,
                    })
                    .collect()
            })
            .collect()
    }

    /// Against the definition on 400 seeded sets: few nodes (so that repeats and patterns
    /// below others are common), grazing shares from none to most, in every order.
    #[test]
    fn the_filters_agree_with_the_pairwise_definition() {
        let mut lowered = 0;
        for seed in 0..400u64 {
            let (n, m) = (1 + (seed as usize * 7) % 60, 1 + (seed as usize) % 6);
            let grazing = [0, 10, 30, 60, 90][(seed % 5) as usize];
            let all = patterns(seed, n, m, grazing);
            let refs: Vec<&[ContactPattern]> = all.iter().map(|q| &q[..]).collect();
            let expected = keep_by_pairs(&refs);
            assert_eq!(keep_maximal(&refs), expected, "seed {seed}");
            let mut kept: Vec<Vec<ContactPattern>> = all
                .iter()
                .zip(&expected)
                .filter(|&(_, &k)| k)
                .map(|(q, _)| q.clone())
                .collect();
            kept.sort();
            assert_eq!(maximal(all.clone()), kept, "seed {seed}");
            let mut distinct = all.clone();
            distinct.sort();
            distinct.dedup();
            lowered += distinct.len() - kept.len();
        }
        // The cases do hold patterns below others (the test could fail).
        assert!(lowered > 100, "{lowered} patterns below others in all");
    }

    #[test]
    fn grazing_patterns_below_others_are_dropped() {
        let all = vec![
            vec![C, G, S],
            vec![C, C, S],
            vec![C, G, S],
            vec![G, G, S],
            vec![S, G, C],
        ];
        assert_eq!(maximal(all), vec![vec![C, C, S], vec![S, G, C]]);
        let refs: Vec<&[ContactPattern]> = vec![&[C, G], &[C, G], &[G, G], &[S, S]];
        assert_eq!(keep_maximal(&refs), vec![true, false, false, true]);
    }
}
