//! A 2D elastic plug pressed into a V-notch, modelled as a spring lattice and condensed onto its
//! contact nodes: a discrete elastic body standing in for a finite-element model.
//!
//! # Geometry
//!
//! The plug is the trapezoid with bottom edge `y = 0`, `-0.5 <= x <= 0.5` (width 1) and top edge
//! `y = 1.5`, `-1 <= x <= 1` (width 2): its half-width at height `y` is `w(y) = 0.5 + y / 3`. It
//! sits in a V-notch whose two walls coincide with the plug's slanted sides `x = -w(y)` (left) and
//! `x = +w(y)` (right); each wall makes the angle `atan(0.5 / 1.5) ≈ 18.4°` with the vertical.
//! The bottom edge does not touch the notch (the walls meet below it, at `y = -1.5`).
//!
//! # Lattice
//!
//! With `n = contact_per_side`, the nodes form a structured `(n + 1) x (n + 1)` grid mapped onto
//! the trapezoid: row `j = 0..=n` at height `y_j = 1.5 j / n`, column `i = 0..=n` at
//! `x = -w(y_j) + 2 w(y_j) i / n`. The vertical spacing is `1.5 / n` and the horizontal spacing
//! goes from `1 / n` (bottom) to `2 / n` (top), so the cells are roughly square. Each cell
//! (a small trapezoid) has springs on its four edges and both diagonals (so the lattice is not a
//! mechanism); every spring has axial stiffness `EA / L` with `EA = 1` and `L` its length. A spring
//! from `p` to `q` with unit direction `d` adds `(EA / L) [d d^T, -d d^T; -d d^T, d d^T]`.
//!
//! The top row `j = n` is clamped (its displacements are zero), which makes the stiffness of the
//! remaining `n (n + 1)` nodes symmetric positive definite. The contact nodes are the end nodes of
//! rows `0..n`: `n` on the left wall and `n` on the right wall, `m = 2n` in all. The bottom corners
//! each lie on one wall only (the bottom edge is not in contact), so each belongs to its own side.
//! The remaining `n (n - 1)` nodes are free and are condensed out.
//!
//! # Frames and order
//!
//! Contact nodes are numbered left wall bottom to top (`0..n`), then right wall bottom to top
//! (`n..2n`). Each node's normal is the unit inward normal of its wall (from the obstacle into the
//! plug): `n_L = (3, 1) / sqrt(10)` on the left, `n_R = (-3, 1) / sqrt(10)` on the right. The
//! tangent is the normal turned by +90° (counter-clockwise): `t_L = (-1, 3) / sqrt(10)` (up the
//! left wall), `t_R = (-1, -3) / sqrt(10)` (down the right wall). The mirror `x -> -x` maps left
//! node `k` to right node `k` and `t` to `-t`, so mirror images of solutions swap left and right
//! nodes and `slip+` with `slip-`.
//!
//! # Physics
//!
//! A *free* plug in this notch wedges once `mu > tan 18.4° = 1/3` (the walls' normal forces have an
//! upward component that only friction can balance). The clamp changes that: it carries the
//! vertical load, and a wedged state must hold the lattice's elastic forces, which act mostly
//! along the walls, by friction alone. Measured on a `0.05` grid of `mu`, the first wedged `mu` is
//! 2.3, 2.9, 2.35, 2.3, 2.2, 2.15, 2.15, 2.1 for `contact_per_side = 1..=8` (for
//! `contact_per_side = 1`, by hand: the symmetric slide of the two corners down the walls needs
//! `mu >= 0.927 / 0.411 ≈ 2.25`). Replacing the clamp by soft grounding springs (`1e-2`, a nearly
//! free plug) moves the first wedged `mu` to `0.35` for every size, as the rigid argument says.

use nalgebra::DMatrix;

use crate::problem::Problem;

/// Height of the plug.
const HEIGHT: f64 = 1.5;
/// Half-width of the bottom edge.
const HALF_BOTTOM: f64 = 0.5;
/// Half-width of the top edge.
const HALF_TOP: f64 = 1.0;
/// Axial stiffness `EA` of every spring.
const EA: f64 = 1.0;

/// The lattice before condensation: node positions, the clamped flags and the contact nodes.
struct Lattice {
    /// `n = contact_per_side`; the grid is `(n + 1) x (n + 1)`.
    n: usize,
    /// Position of node `(row j, column i)` at index `j * (n + 1) + i`.
    pos: Vec<[f64; 2]>,
    /// Springs as pairs of node indices.
    springs: Vec<(usize, usize)>,
    /// Contact nodes in problem order, with their inward normal.
    contacts: Vec<(usize, [f64; 2])>,
}

impl Lattice {
    fn new(n: usize) -> Lattice {
        assert!(
            n >= 1,
            "lattice_plug needs at least one contact node per side"
        );
        let cols = n + 1;
        let idx = |j: usize, i: usize| j * cols + i;
        let mut pos = Vec::with_capacity(cols * cols);
        for j in 0..=n {
            let y = HEIGHT * j as f64 / n as f64;
            let w = HALF_BOTTOM + (HALF_TOP - HALF_BOTTOM) * y / HEIGHT;
            for i in 0..=n {
                pos.push([-w + 2.0 * w * i as f64 / n as f64, y]);
            }
        }
        let mut springs = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                if i < n {
                    springs.push((idx(j, i), idx(j, i + 1)));
                }
                if j < n {
                    springs.push((idx(j, i), idx(j + 1, i)));
                }
                if i < n && j < n {
                    springs.push((idx(j, i), idx(j + 1, i + 1)));
                    springs.push((idx(j, i + 1), idx(j + 1, i)));
                }
            }
        }
        // Inward normals: perpendicular to the wall direction, pointing into the plug.
        let slope = (HALF_TOP - HALF_BOTTOM) / HEIGHT; // dx/dy of the right wall
        let len = (1.0 + slope * slope).sqrt();
        let n_left = [1.0 / len, slope / len];
        let n_right = [-1.0 / len, slope / len];
        let mut contacts = Vec::with_capacity(2 * n);
        contacts.extend((0..n).map(|j| (idx(j, 0), n_left)));
        contacts.extend((0..n).map(|j| (idx(j, n), n_right)));
        Lattice {
            n,
            pos,
            springs,
            contacts,
        }
    }

    fn clamped(&self, node: usize) -> bool {
        node / (self.n + 1) == self.n
    }

    /// The condensed stiffness on the contact nodes, in global `(x, y)` components.
    fn condensed_global(&self) -> DMatrix<f64> {
        // Dof numbering: contact nodes first (problem order), then the other free nodes.
        let nodes = self.pos.len();
        let mut slot = vec![usize::MAX; nodes];
        let mut next = 0;
        for &(node, _) in &self.contacts {
            slot[node] = next;
            next += 1;
        }
        for (node, s) in slot.iter_mut().enumerate() {
            if *s == usize::MAX && !self.clamped(node) {
                *s = next;
                next += 1;
            }
        }
        let ndof = 2 * next;
        let mut k0 = DMatrix::<f64>::zeros(ndof, ndof);
        for &(p, q) in &self.springs {
            let dx = self.pos[q][0] - self.pos[p][0];
            let dy = self.pos[q][1] - self.pos[p][1];
            let l = (dx * dx + dy * dy).sqrt();
            let d = [dx / l, dy / l];
            let k = EA / l;
            for (a, sa) in [(p, 1.0), (q, -1.0)] {
                for (b, sb) in [(p, 1.0), (q, -1.0)] {
                    if self.clamped(a) || self.clamped(b) {
                        continue;
                    }
                    for r in 0..2 {
                        for c in 0..2 {
                            k0[(2 * slot[a] + r, 2 * slot[b] + c)] += sa * sb * k * d[r] * d[c];
                        }
                    }
                }
            }
        }
        let nc = 2 * self.contacts.len();
        let no = ndof - nc;
        let kcc = k0.view((0, 0), (nc, nc)).into_owned();
        if no == 0 {
            return kcc;
        }
        let koc = k0.view((nc, 0), (no, nc)).into_owned();
        let koo = k0.view((nc, nc), (no, no)).into_owned();
        let chol = koo
            .cholesky()
            .expect("the free-node stiffness of a clamped braced lattice is positive definite");
        let x = chol.solve(&koc); // K_oo^{-1} K_oc
        kcc - koc.transpose() * x
    }
}

/// A spring-lattice plug in a V-notch (see the module documentation), condensed onto its
/// `2 * contact_per_side` contact nodes (left wall bottom to top, then right wall bottom to top)
/// in local `(n, t)` frames, with friction coefficient `mu`.
///
/// Panics if `contact_per_side == 0` or `mu` is not finite and positive.
pub fn lattice_plug(contact_per_side: usize, mu: f64) -> Problem {
    let lattice = Lattice::new(contact_per_side);
    let kg = lattice.condensed_global();
    let m = lattice.contacts.len();
    // R block-diagonal, R_i = [n_i t_i] (columns in global components), t = n turned by +90°.
    let mut rot = DMatrix::<f64>::zeros(2 * m, 2 * m);
    for (i, &(_, nrm)) in lattice.contacts.iter().enumerate() {
        let t = [-nrm[1], nrm[0]];
        rot[(2 * i, 2 * i)] = nrm[0];
        rot[(2 * i + 1, 2 * i)] = nrm[1];
        rot[(2 * i, 2 * i + 1)] = t[0];
        rot[(2 * i + 1, 2 * i + 1)] = t[1];
    }
    let kl = rot.transpose() * kg * &rot;
    let kl = (&kl + kl.transpose()) * 0.5;
    Problem::new(2, kl, mu).expect("the condensed lattice stiffness is symmetric positive definite")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rays::{enumerate, Settings};
    use crate::run::Outcome;
    use crate::solution::NodeStatus;

    #[test]
    fn lattice_counts_and_normals() {
        for n in 1..=6 {
            let l = Lattice::new(n);
            assert_eq!(l.pos.len(), (n + 1) * (n + 1));
            assert_eq!(l.contacts.len(), 2 * n);
            // Springs: (n+1) n horizontal + n (n+1) vertical + 2 n^2 diagonal.
            assert_eq!(l.springs.len(), 2 * n * (n + 1) + 2 * n * n);
            for (k, &(node, nrm)) in l.contacts.iter().enumerate() {
                let p = l.pos[node];
                let w = HALF_BOTTOM + p[1] / 3.0;
                // On its wall, not clamped, unit normal pointing into the plug (towards x = 0).
                assert!(!l.clamped(node));
                let side = if k < n { -1.0 } else { 1.0 };
                assert!((p[0] - side * w).abs() < 1e-12);
                assert!((nrm[0].hypot(nrm[1]) - 1.0).abs() < 1e-15);
                assert!(nrm[0] * p[0] < 0.0);
                // Normal perpendicular to the wall direction (side * 1/3, 1).
                assert!((nrm[0] * side / 3.0 + nrm[1]).abs() < 1e-15);
                // Bottom to top on each side.
                if k % n > 0 {
                    assert!(p[1] > l.pos[l.contacts[k - 1].0][1]);
                }
            }
        }
    }

    #[test]
    fn condensed_stiffness_is_spd_up_to_30() {
        for n in 1..=30 {
            let p = lattice_plug(n, 0.5);
            assert_eq!(p.nodes(), 2 * n);
            assert_eq!(p.dim(), 2);
            let k = p.stiffness();
            let scale = k.amax();
            for i in 0..k.nrows() {
                for j in 0..i {
                    assert!((k[(i, j)] - k[(j, i)]).abs() <= 1e-12 * scale);
                }
            }
        }
    }

    /// Mirror symmetry of the condensed stiffness: left node k <-> right node k, t -> -t.
    #[test]
    fn condensed_stiffness_is_mirror_symmetric() {
        for n in 1..=8 {
            let p = lattice_plug(n, 0.5);
            let k = p.stiffness();
            let m = 2 * n;
            let mirror = |a: usize| -> (usize, f64) {
                let node = a / 2;
                let other = if node < n { node + n } else { node - n };
                (2 * other + a % 2, if a % 2 == 1 { -1.0 } else { 1.0 })
            };
            for a in 0..2 * m {
                for b in 0..2 * m {
                    let (ma, sa) = mirror(a);
                    let (mb, sb) = mirror(b);
                    assert!((k[(a, b)] - sa * sb * k[(ma, mb)]).abs() <= 1e-10 * k.amax());
                }
            }
        }
    }

    fn mirrored(status: &[NodeStatus], n: usize) -> Vec<NodeStatus> {
        (0..2 * n)
            .map(|k| {
                let s = status[if k < n { k + n } else { k - n }];
                match s {
                    NodeStatus::SlipPlus => NodeStatus::SlipMinus,
                    NodeStatus::SlipMinus => NodeStatus::SlipPlus,
                    other => other,
                }
            })
            .collect()
    }

    /// Clamped at the top, the plug wedges only at high friction (module documentation): wedged
    /// at `mu = 3`, not at `mu = 1` nor `0.05`.
    #[test]
    fn wedges_at_high_friction_not_at_low() {
        for n in 2..=4 {
            let hi = enumerate(&lattice_plug(n, 3.0), &Settings::default()).unwrap();
            assert_eq!(hi.outcome, Outcome::Wedged, "n = {n}, mu = 3.0");
            assert!(!hi.rays.is_empty());
            for mu in [1.0, 0.05] {
                let lo = enumerate(&lattice_plug(n, mu), &Settings::default()).unwrap();
                assert_eq!(lo.outcome, Outcome::NotWedged, "n = {n}, mu = {mu}");
                assert!(lo.rays.is_empty());
            }
        }
    }

    /// Every wedged ray of the clamped plug presses on the walls (`r_n >= 0`, `sum r_n = 1`) and
    /// holds the in-contact nodes on them (`u_n = 0` where `r_n > 0`).
    #[test]
    fn wedged_rays_are_solutions() {
        let p = lattice_plug(3, 3.0);
        let e = enumerate(&p, &Settings::default()).unwrap();
        assert!(!e.rays.is_empty());
        for ray in &e.rays {
            let sum: f64 = (0..6).map(|k| ray.r[2 * k]).sum();
            assert!((sum - 1.0).abs() < 1e-9);
            let ku = p.stiffness() * nalgebra::DVector::from_column_slice(&ray.u);
            for k in 0..6 {
                assert!(ray.r[2 * k] >= -1e-12 && ray.u[2 * k] >= -1e-12);
                assert!(ray.r[2 * k] * ray.u[2 * k] <= 1e-12);
                assert!(ray.r[2 * k + 1].abs() <= 3.0 * ray.r[2 * k] + 1e-12);
                for c in 0..2 {
                    assert!((ku[2 * k + c] - ray.r[2 * k + c]).abs() < 1e-9);
                }
            }
        }
    }

    #[test]
    fn rays_come_in_mirror_pairs() {
        for n in 2..=4 {
            for mu in [2.5, 3.0, 5.0] {
                let e = enumerate(&lattice_plug(n, mu), &Settings::default()).unwrap();
                if mu >= 3.0 {
                    assert!(!e.rays.is_empty(), "n = {n}, mu = {mu}");
                }
                for ray in &e.rays {
                    let want = mirrored(&ray.status, n);
                    let twin = e
                        .rays
                        .iter()
                        .find(|r| r.status == want)
                        .unwrap_or_else(|| panic!("n = {n}, mu = {mu}: no mirror of {ray:?}"));
                    // The values mirror too: swap the nodes, flip the tangential components.
                    for k in 0..2 * n {
                        let mk = if k < n { k + n } else { k - n };
                        for c in 0..2 {
                            let s = if c == 1 { -1.0 } else { 1.0 };
                            assert!((ray.r[2 * k + c] - s * twin.r[2 * mk + c]).abs() < 1e-7);
                            let scale = ray.u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                            assert!(
                                (ray.u[2 * k + c] - s * twin.u[2 * mk + c]).abs() < 1e-7 * scale
                            );
                        }
                    }
                }
                // Cones mirror too, as sets of status vectors.
                let as_statuses = |cone: &crate::solution::Cone, flip: bool| {
                    let mut v: Vec<Vec<NodeStatus>> = cone
                        .rays
                        .iter()
                        .map(|&j| {
                            if flip {
                                mirrored(&e.rays[j].status, n)
                            } else {
                                e.rays[j].status.clone()
                            }
                        })
                        .collect();
                    v.sort();
                    v
                };
                for cone in &e.cones {
                    let want = as_statuses(cone, true);
                    assert!(
                        e.cones.iter().any(|c| as_statuses(c, false) == want),
                        "n = {n}, mu = {mu}: no mirror of cone {cone:?}"
                    );
                }
            }
        }
    }
}
