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

use crate::conic::program::Class;
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

/// The image of a pattern under the involution `s`.
fn image(s: &[usize], q: &[ContactPattern]) -> Vec<ContactPattern> {
    let mut p = q.to_vec();
    for (i, &c) in q.iter().enumerate() {
        p[s[i]] = c;
    }
    p
}

/// Adds to `found` the images of the patterns in the regions that the branchings `orbits`
/// skipped (the involutions `symmetries`), and returns how many it added (patterns not found
/// at a leaf; an image may repeat another, and `found` holds each pattern once). The images' witnesses are left to the
/// finishing step: its program for a pattern is the one a leaf of the pattern asks, so a
/// witness comes out the same whether its pattern was found or made (and the same as in a run
/// without symmetries, or one split into shards).
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

#[cfg(test)]
mod tests {
    use super::*;
    use ContactPattern::{Contact as C, Grazing as G, Separated as S};

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
}
