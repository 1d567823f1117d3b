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
//! patterns `q` of the contact child with `s(j)` not in contact. [`Orbit`] records such a
//! branching; [`add_images`] adds those images after the search, the deepest branchings first,
//! so that a branching's contact child is complete (its own skipped regions filled) before it
//! is mapped.
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

use crate::conic::program::{Class, Formulation};
use crate::solution::ContactPattern;

/// A branching that skipped a region ([`add_images`]).
#[derive(Debug, Clone)]
pub(super) struct Orbit {
    /// Its depth in the search tree.
    pub depth: usize,
    /// The classes of the search node (before the branching).
    pub classes: Vec<Class>,
    /// The node branched on.
    pub branch: usize,
    /// The symmetries (indices into the search's list) that kept the classes and moved
    /// `branch`.
    pub symmetries: Vec<usize>,
}

/// Whether the realised pattern `q` of a leaf lies in the subtree of a node of `classes` (a
/// leaf's pattern has its contact set in contact, every other node separated or grazing).
fn inside(classes: &[Class], q: &[ContactPattern]) -> bool {
    classes.iter().zip(q).all(|(c, p)| match c {
        Class::Contact => *p == ContactPattern::Contact,
        Class::Free => true,
        Class::Separated | Class::Grazing => *p != ContactPattern::Contact,
    })
}

/// The image of a pattern (or of any per-node values) under the permutation `s`: node `s(i)`
/// takes node `i`'s.
fn image<T: Clone>(s: &[usize], q: &[T]) -> Vec<T> {
    let mut p = q.to_vec();
    for (i, c) in q.iter().enumerate() {
        p[s[i]] = c.clone();
    }
    p
}

/// Adds to `found` the images of the patterns in the regions that the branchings `orbits`
/// skipped (the involutions `symmetries`), and returns how many it added (patterns not found
/// at a leaf; an image may repeat another, and `found` holds each pattern once). The images' witnesses are left to the
/// finishing step ([`finish_by_orbits`]): in 3D it maps the witness of each orbit's least
/// pattern, whose program is the one a leaf of that pattern asks, so a witness comes out the
/// same whether its pattern was found or made (and the same as in a run without orbital
/// branching, or one split into shards).
pub(super) fn add_images(
    symmetries: &[Vec<usize>],
    mut orbits: Vec<Orbit>,
    found: &mut Vec<Vec<ContactPattern>>,
) -> u64 {
    orbits.sort_by_key(|o| std::cmp::Reverse(o.depth));
    let before = found.len();
    for orbit in &orbits {
        let mut new = Vec::new();
        for q in found.iter() {
            if q[orbit.branch] != ContactPattern::Contact || !inside(&orbit.classes, q) {
                continue;
            }
            for &k in &orbit.symmetries {
                let s = &symmetries[k];
                if q[s[orbit.branch]] != ContactPattern::Contact {
                    new.push(image(s, q));
                }
            }
        }
        found.extend(new);
    }
    if found.len() > before {
        found.sort();
        found.dedup();
    }
    (found.len() - before) as u64
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
    fn images_of_the_contact_child_fill_the_skipped_region() {
        // Four nodes, the symmetry swapping 0 with 1 and 2 with 3; the root branches on 0, so
        // the region skipped is 0 separated with 1 in contact.
        let orbits = vec![Orbit {
            depth: 0,
            classes: vec![Class::Free; 4],
            branch: 0,
            symmetries: vec![0],
        }];
        let mut found = vec![vec![C, S, G, C], vec![C, C, S, S], vec![S, S, C, S]];
        let added = add_images(&[vec![1, 0, 3, 2]], orbits, &mut found);
        // Only the first pattern has 0 in contact and 1 not: its image is added.
        assert_eq!(added, 1);
        assert_eq!(found.len(), 4);
        assert!(found.contains(&vec![S, C, C, G]));
    }

    #[test]
    fn deeper_branchings_are_mapped_first() {
        // The root (depth 0) branched on 0 and, in its contact child, a node at depth 1 whose
        // classes the same symmetry kept... cannot: 0 in contact and 1 free are not kept. A
        // second symmetry (2 <-> 3 only) keeps them: its image must be made before the root's
        // mapping, which then maps it too.
        let both = vec![1, 0, 3, 2];
        let low = vec![0, 1, 3, 2];
        let mut contact_child = vec![Class::Free; 4];
        contact_child[0] = Class::Contact;
        let orbits = vec![
            Orbit {
                depth: 0,
                classes: vec![Class::Free; 4],
                branch: 0,
                symmetries: vec![0],
            },
            Orbit {
                depth: 1,
                classes: contact_child,
                branch: 2,
                symmetries: vec![1],
            },
        ];
        let mut found = vec![vec![C, S, C, S]];
        let added = add_images(&[both, low], orbits, &mut found);
        found.sort();
        assert_eq!(added, 3);
        assert_eq!(
            found,
            vec![
                vec![C, S, C, S],
                vec![C, S, S, C],
                vec![S, C, C, S],
                vec![S, C, S, C]
            ]
        );
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
