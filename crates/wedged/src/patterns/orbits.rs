//! Orbital branching in the pattern search (`bnb`): the patterns of the subtrees it skips,
//! made as images of the patterns found.
//!
//! A symmetry of the problem ([`crate::Problem::symmetries`]: an involution `s` of the nodes
//! with the frames turned by a sign matrix `D`) maps every solution to a solution,
//! and so every realised pattern `q` to the realised pattern `s(q)` (node `s(i)` takes node
//! `i`'s entry). At a search node whose classes a symmetry keeps, the branching on node `j`
//! makes the usual contact child (`j` in contact) and a separated child that separates `s(j)`
//! too, for every symmetry `s` that keeps the classes (as `critical`'s `bnb` does). The region
//! skipped, `j` separated with some `s(j)` in contact, holds exactly the images `s(q)` of the
//! patterns `q` of the contact child with `s(j)` not in contact. The realised patterns are
//! closed under the group the symmetries generate ([`Group`]), so the patterns found at the
//! leaves and their images under the group are all of them: a kept search completes its
//! patterns so after it ends ([`Group::complete`]), a streamed one hands on each orbit whole
//! when its first leaf is decided (`bnb.rs`). (Until 2026-12-01 the kept search recorded each
//! branching that skipped a region and mapped its contact child's patterns, the deepest
//! branchings first; the group's orbits give the same patterns with one mechanism for both.)
//!
//! **Witnesses by orbit.** In 3D (a clamped body) the finishing step solves one cone program
//! per orbit of maximal patterns under the group the symmetries generate ([`Group`]): the
//! witness of the orbit's least pattern, mapped to the others and checked there like any
//! witness (a mapped witness that fails its check is solved for itself); `bnb`'s leaves do
//! the same with their realised patterns (`bnb.rs`, `Search::leaf`). On the 3D V-groove plug
//! (m = 30, 1.2 `mu*`, three symmetries) the two took the cone programs from 7,542 to 2,374
//! and the whole run from 21.1 s to 17.4 s (`BENCHMARKS.md`). (In 2D the witnesses are the
//! simplex method's, a few pivots each: left alone.)

use rayon::prelude::*;

use crate::conic::program::Formulation;
use crate::solution::ContactPattern;

/// The image of a pattern (or of any per-node values) under the permutation `s`: node `s(i)`
/// takes node `i`'s.
fn image<T: Clone>(s: &[usize], q: &[T]) -> Vec<T> {
    let mut p = q.to_vec();
    for (i, c) in q.iter().enumerate() {
        p[s[i]] = c.clone();
    }
    p
}

/// The group that the problem's symmetries generate (each element a permutation of the nodes
/// and the sign matrix `D` of its frames, the identity left out), for the finishing step: the
/// patterns of one orbit share one witness, solved for the orbit's least pattern and mapped to
/// the others ([`Group::representative`], [`Group::map_point`]). A pattern's witness is then
/// the same whichever patterns a run found directly and which it made as images, with or
/// without orbital branching, whole or split into shards.
#[derive(Debug, Default)]
pub(super) struct Group {
    elements: Vec<(Vec<usize>, Vec<f64>)>,
}

impl Group {
    /// The group of `generators` (involutions with their signs,
    /// [`crate::Problem::symmetries_with_signs`]), in a fixed order (breadth first from the
    /// generators as given).
    pub fn new(generators: Vec<(Vec<usize>, Vec<f64>)>) -> Group {
        let Some(m) = generators.first().map(|g| g.0.len()) else {
            return Group::default();
        };
        let d = generators[0].1.len();
        let identity = ((0..m).collect::<Vec<usize>>(), vec![1.0; d]);
        let mut all = vec![identity.clone()];
        let mut next = 0;
        while next < all.len() {
            let (p, sp) = all[next].clone();
            next += 1;
            for (g, sg) in &generators {
                // `g` after `p`: node `i` goes to `g(p(i))`, its frame turned by both signs.
                let q: Vec<usize> = p.iter().map(|&i| g[i]).collect();
                let sq: Vec<f64> = sp.iter().zip(sg).map(|(a, b)| a * b).collect();
                if !all.iter().any(|(x, sx)| *x == q && *sx == sq) {
                    all.push((q, sq));
                }
            }
        }
        all.retain(|e| *e != identity);
        Group { elements: all }
    }

    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// The group of `form`'s problem where the finishing step maps witnesses: 3D, a clamped
    /// body ([`finish_by_orbits`]); otherwise empty.
    pub fn of(form: &Formulation) -> Group {
        match form.dim == 3 && form.modes == 0 {
            true => Group::new(form.problem.symmetries_with_signs()),
            false => Group::default(),
        }
    }

    /// The least pattern of `q`'s orbit (contact before separated before grazing, node by
    /// node) and the first element that maps it to `q` (`None` when `q` is its own orbit's
    /// least).
    pub fn representative(&self, q: &[ContactPattern]) -> (Vec<ContactPattern>, Option<usize>) {
        let mut least = q.to_vec();
        for (s, _) in &self.elements {
            let p = image(s, q);
            if p < least {
                least = p;
            }
        }
        if least == q {
            return (least, None);
        }
        let by = (0..self.elements.len()).find(|&k| image(&self.elements[k].0, &least) == q);
        (least, by)
    }

    /// Adds to `found` every image of its patterns under the group and leaves it sorted, each
    /// pattern once; returns how many patterns that added (none without elements, `found`
    /// then untouched). Realised patterns map to realised patterns, so what it adds is
    /// realised: with orbital branching, the patterns of the regions the search skipped.
    pub fn complete(&self, found: &mut Vec<Vec<ContactPattern>>) -> u64 {
        if self.is_empty() {
            return 0;
        }
        found.sort();
        found.dedup();
        let before = found.len();
        let mut all: Vec<Vec<ContactPattern>> = found.iter().flat_map(|q| self.orbit(q)).collect();
        all.sort();
        all.dedup();
        *found = all;
        (found.len() - before) as u64
    }

    /// The orbit of `q`: `q` and its images under every element, sorted, each once.
    pub fn orbit(&self, q: &[ContactPattern]) -> Vec<Vec<ContactPattern>> {
        let mut all = vec![q.to_vec()];
        all.extend(self.elements.iter().map(|(s, _)| image(s, q)));
        all.sort();
        all.dedup();
        all
    }

    /// The image of a point (`dim` components per node) under element `k`.
    pub fn map_point(&self, k: usize, x: &[f64]) -> Vec<f64> {
        let (s, sign) = &self.elements[k];
        let d = sign.len();
        let mut y = vec![0.0; x.len()];
        for (i, &j) in s.iter().enumerate() {
            for c in 0..d {
                y[d * j + c] = sign[c] * x[d * i + c];
            }
        }
        y
    }

    /// The image of per-node values under element `k` (node `s(i)` takes node `i`'s).
    pub fn map_nodes<T: Clone>(&self, k: usize, x: &[T]) -> Vec<T> {
        image(&self.elements[k].0, x)
    }
}

/// How many answers of the finishing step are made at once (in parallel) before they are
/// handed on: so that a run with many pieces never holds all of its witnessed patterns.
const CHUNK: usize = 4096;

/// The finishing step over `pieces`: each orbit's least pattern finished once (`finish`),
/// every other pattern mapped from it (`map` with the element that maps it there) or, where
/// that fails, finished itself; one at a time when `sequential`, else in parallel. The answers
/// go to `take` in the order of `pieces`, [`CHUNK`] at a time, so that only the orbits' least
/// answers and one chunk are held at once (the V-groove plug at m = 40: 57,818 patterns, the
/// run's peak memory 364 MiB when every answer was collected first); returns how many were
/// mapped.
pub(super) fn finish_by_orbits<T, F, M>(
    group: &Group,
    pieces: &[Vec<ContactPattern>],
    sequential: bool,
    finish: F,
    map: M,
    mut take: impl FnMut(&[ContactPattern], Result<T, String>),
) -> u64
where
    T: Clone + Send + Sync,
    F: Fn(&[ContactPattern]) -> Result<T, String> + Sync + Send,
    M: Fn(&[ContactPattern], usize, &T) -> Result<T, String> + Sync + Send,
{
    // Without a group every piece is finished itself (no orbits to list).
    let reps: Vec<_> = match group.is_empty() {
        true => Vec::new(),
        false => pieces.iter().map(|q| group.representative(q)).collect(),
    };
    let mut least: Vec<Vec<ContactPattern>> = reps.iter().map(|r| r.0.clone()).collect();
    least.sort();
    least.dedup();
    let done = each(&least, sequential, |q| finish(q));
    let mapped = std::sync::atomic::AtomicU64::new(0);
    let answer = |&j: &usize| {
        let Some((rep, by)) = reps.get(j) else {
            return finish(&pieces[j]);
        };
        let at = least
            .binary_search(rep)
            .expect("every representative is listed");
        match (by, &done[at]) {
            (None, answer) => answer.clone(),
            (Some(k), Ok(t)) => match map(&pieces[j], *k, t) {
                Ok(t) => {
                    mapped.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    Ok(t)
                }
                Err(_) => finish(&pieces[j]),
            },
            (Some(_), Err(_)) => finish(&pieces[j]),
        }
    };
    for start in (0..pieces.len()).step_by(CHUNK) {
        let order: Vec<usize> = (start..(start + CHUNK).min(pieces.len())).collect();
        for (&j, answer) in order.iter().zip(each(&order, sequential, answer)) {
            take(&pieces[j], answer);
        }
    }
    mapped.into_inner()
}

/// `f` over `items`, in order: one at a time or in parallel.
fn each<A: Sync, B: Send>(
    items: &[A],
    sequential: bool,
    f: impl Fn(&A) -> B + Sync + Send,
) -> Vec<B> {
    if sequential {
        items.iter().map(f).collect()
    } else {
        items.par_iter().map(f).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ContactPattern::{Contact as C, Grazing as G, Separated as S};

    #[test]
    fn the_group_of_two_mirrors_has_three_elements_and_maps_back() {
        // The reversal of four nodes (one tangent turned) and the pairing 0 <-> 1, 2 <-> 3
        // (the other turned): with their product, three elements besides the identity.
        let gens = vec![
            (vec![3, 2, 1, 0], vec![1.0, 1.0, -1.0]),
            (vec![1, 0, 3, 2], vec![1.0, -1.0, 1.0]),
        ];
        let group = Group::new(gens);
        assert_eq!(group.elements.len(), 3);
        assert!(group
            .elements
            .contains(&(vec![2, 3, 0, 1], vec![1.0, -1.0, -1.0])));
        let q = vec![S, C, G, C];
        let (least, by) = group.representative(&q);
        // The orbit: S C G C, C G C S, C S C G, G C S C (contact < separated < grazing).
        assert_eq!(least, vec![C, S, C, G]);
        let k = by.expect("q is not its orbit's least");
        assert_eq!(group.map_nodes(k, &least), q);
        let x: Vec<f64> = (0..12).map(|a| a as f64 + 1.0).collect();
        let y = group.map_point(k, &x);
        let (s, sign) = &group.elements[k];
        for i in 0..4 {
            for c in 0..3 {
                assert_eq!(y[3 * s[i] + c], sign[c] * x[3 * i + c]);
            }
        }
        // A pattern that every element keeps is its own orbit's least.
        assert_eq!(
            group.representative(&[C, C, C, C]),
            (vec![C, C, C, C], None)
        );
        assert!(Group::new(Vec::new()).is_empty());
    }

    #[test]
    fn the_group_completes_the_patterns_found() {
        // Four nodes; the symmetries swap 0 with 1 and 2 with 3 (both at once, and 2 with 3
        // alone), so the group has three elements besides the identity.
        let both = (vec![1, 0, 3, 2], vec![1.0, -1.0, 1.0]);
        let low = (vec![0, 1, 3, 2], vec![1.0, 1.0, -1.0]);
        let group = Group::new(vec![both, low]);
        let mut found = vec![vec![C, S, C, S], vec![C, C, G, S], vec![C, S, C, S]];
        let added = group.complete(&mut found);
        // C S C S: four patterns (C or S first, C or S third); C C G S: two (G third or fourth).
        let mut want = vec![
            vec![C, S, C, S],
            vec![C, S, S, C],
            vec![S, C, C, S],
            vec![S, C, S, C],
            vec![C, C, G, S],
            vec![C, C, S, G],
        ];
        want.sort();
        assert_eq!(found, want);
        assert_eq!(added, 4);
        // Complete already: nothing added, nothing changed.
        assert_eq!(group.complete(&mut found), 0);
        assert_eq!(found, want);
        // No group: untouched, unsorted.
        let mut few = vec![vec![S, C], vec![C, S], vec![S, C]];
        assert_eq!(Group::default().complete(&mut few), 0);
        assert_eq!(few, vec![vec![S, C], vec![C, S], vec![S, C]]);
    }

    /// The finishing step hands every answer on in the order of the pieces, across several
    /// chunks: each orbit's least finished once, every other piece mapped from it (here the
    /// answer is the piece itself, so a wrong order or a wrong mapping shows), with and
    /// without a group.
    #[test]
    fn the_finishing_step_hands_on_every_answer_in_order() {
        // 13 nodes, every pattern of contact and separation with at most 7 contacts: 5,812
        // patterns, two chunks.
        let m = 13;
        let mut pieces: Vec<Vec<ContactPattern>> = Vec::new();
        for bits in 0u32..(1 << m) {
            if bits.count_ones() <= 7 {
                pieces.push(
                    (0..m)
                        .map(|i| if bits >> i & 1 == 1 { C } else { S })
                        .collect(),
                );
            }
        }
        pieces.sort();
        assert!(pieces.len() > CHUNK, "{} pieces", pieces.len());
        // Reversal of the nodes (an involution; the signs do not matter here).
        let reverse: Vec<usize> = (0..m).rev().collect();
        for group in [Group::default(), Group::new(vec![(reverse, vec![1.0; 3])])] {
            let finished = std::sync::atomic::AtomicU64::new(0);
            let mut seen = Vec::new();
            let mapped = finish_by_orbits(
                &group,
                &pieces,
                false,
                |q| {
                    finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    Ok(q.to_vec())
                },
                |q, k, least: &Vec<ContactPattern>| {
                    assert_eq!(group.map_nodes(k, least), q);
                    Ok(q.to_vec())
                },
                |q, answer| {
                    assert_eq!(answer.as_deref(), Ok(q));
                    seen.push(q.to_vec());
                },
            );
            assert_eq!(seen, pieces);
            let finished = finished.into_inner();
            assert_eq!(finished + mapped, pieces.len() as u64);
            if group.is_empty() {
                assert_eq!(mapped, 0);
            } else {
                // The patterns that the reversal keeps are their own least; every other orbit
                // has two patterns, one finished and one mapped.
                let fixed = pieces
                    .iter()
                    .filter(|q| q.iter().rev().eq(q.iter()))
                    .count() as u64;
                assert_eq!(finished, fixed + mapped);
                assert!(mapped > 1000, "{mapped} mapped");
            }
        }
    }
}
