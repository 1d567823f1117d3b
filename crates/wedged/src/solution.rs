//! The vocabulary of solutions, shared by every method: the status of a node in one solution
//! ([`NodeStatus`]), the pattern of a node over a convex piece ([`ContactPattern`]), a 2D extreme
//! ray ([`Ray`]), a maximal set of cross-complementary rays ([`Cone`]), how such sets are formed
//! from statuses (`pieces`, `piece_patterns`), and the one check of a solution against WP
//! ([`check_solution`]).

use crate::cliques::maximal_cliques;
use crate::problem::Problem;

/// The status of one contact node in one solution (MISSION section 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum NodeStatus {
    /// `u_n > 0`, `r = 0`.
    Separated,
    /// `u_n = 0`, `|r_t| < mu r_n`.
    Stick,
    /// `u_n = 0`, `r_t = +mu r_n > 0`.
    SlipPlus,
    /// `u_n = 0`, `r_t = -mu r_n < 0`.
    SlipMinus,
    /// 3D: `u_n = 0`, `||r_t|| = mu r_n > 0` (on the boundary of the round friction cone).
    Slip,
    /// `u_n = 0`, `r = 0`.
    Grazing,
}

impl NodeStatus {
    /// The name used in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            NodeStatus::Separated => "separated",
            NodeStatus::Stick => "stick",
            NodeStatus::SlipPlus => "slip+",
            NodeStatus::SlipMinus => "slip-",
            NodeStatus::Slip => "slip",
            NodeStatus::Grazing => "grazing",
        }
    }

    /// `u_n > 0` in this status.
    pub fn gap_open(self) -> bool {
        self == NodeStatus::Separated
    }

    /// `r_n > 0` in this status.
    pub fn pressed(self) -> bool {
        matches!(
            self,
            NodeStatus::Stick | NodeStatus::SlipPlus | NodeStatus::SlipMinus | NodeStatus::Slip
        )
    }
}

/// The contact pattern of one node over a whole convex piece `C_B`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ContactPattern {
    /// `u_n = 0` throughout, `r_n > 0` in the relative interior.
    Contact,
    /// `r = 0` throughout, `u_n > 0` in the relative interior.
    Separated,
    /// `u_n = 0` and `r = 0` throughout.
    Grazing,
}

impl ContactPattern {
    /// The name used in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            ContactPattern::Contact => "contact",
            ContactPattern::Separated => "separated",
            ContactPattern::Grazing => "grazing",
        }
    }

    /// The pattern of a node of this status: separated, grazing, or (pressed) contact.
    pub fn of(status: NodeStatus) -> ContactPattern {
        match status {
            NodeStatus::Separated => ContactPattern::Separated,
            NodeStatus::Grazing => ContactPattern::Grazing,
            _ => ContactPattern::Contact,
        }
    }

    /// The pattern of a [`ContactPattern::name`].
    pub fn from_name(name: &str) -> Option<ContactPattern> {
        [
            ContactPattern::Contact,
            ContactPattern::Separated,
            ContactPattern::Grazing,
        ]
        .into_iter()
        .find(|p| p.name() == name)
    }
}

/// A complementary extreme ray of `C`: a wedged configuration, normalised to `sum r_n = 1`.
#[derive(Debug, Clone, PartialEq)]
pub struct Ray {
    /// Displacements, `dim*m`, in the local node frames.
    pub u: Vec<f64>,
    /// Reactions, `dim*m`, in the local node frames; `sum r_n = 1`.
    pub r: Vec<f64>,
    /// Per-node status.
    pub status: Vec<NodeStatus>,
}

/// A maximal cross-complementary set of rays: every nonnegative combination of them is a
/// solution, with the same contact pattern.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cone {
    /// Indices into [`crate::Enumeration::rays`], increasing.
    pub rays: Vec<usize>,
    /// Per-node pattern of the piece.
    pub pattern: Vec<ContactPattern>,
}

/// The status vector as text, for messages.
pub fn status_text(status: &[NodeStatus]) -> String {
    status
        .iter()
        .map(|s| s.name())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Two rays are cross-complementary when their sum is complementary at every node.
pub fn cross_complementary(a: &[NodeStatus], b: &[NodeStatus]) -> bool {
    a.iter().zip(b).all(|(&x, &y)| {
        let gap = x.gap_open() || y.gap_open();
        let pressed = x.pressed() || y.pressed();
        !(gap && pressed)
    })
}

/// The patterns of the maximal cross-complementary sets of rays with these statuses (the
/// pyramid method's candidates), sorted. [`pieces`] groups the rays by sign first, so a piece of
/// a fine pyramid with thousands of rays costs one vertex of the graph per sign class.
pub(crate) fn piece_patterns(statuses: &[Vec<NodeStatus>]) -> Vec<Vec<ContactPattern>> {
    let statuses: Vec<&[NodeStatus]> = statuses.iter().map(Vec::as_slice).collect();
    let mut patterns: Vec<Vec<ContactPattern>> =
        pieces(&statuses).into_iter().map(|c| c.pattern).collect();
    patterns.sort();
    patterns
}

/// The maximal cross-complementary sets of rays with these statuses, each with its pattern,
/// in canonical order (the indices are into `statuses`).
///
/// Cross-complementarity depends only on which entries are positive: rays with the same signs
/// (twins: the same nodes pressed, the same gaps open) are compatible with each other and with
/// the same other rays, so a maximal set holds all of a sign class or none of it. The cliques
/// are found on the graph of the classes, one vertex each, and each class stands for its rays.
/// (On a random 2D problem with m = 12 and 24,556 rays, the graph of the rays themselves,
/// 600 million adjacency entries, took most of a 97 s run.)
pub(crate) fn pieces(statuses: &[&[NodeStatus]]) -> Vec<Cone> {
    let sign = |s: &[NodeStatus]| -> Vec<NodeStatus> {
        s.iter()
            .map(|&x| if x.pressed() { NodeStatus::Stick } else { x })
            .collect()
    };
    let mut classes: std::collections::BTreeMap<Vec<NodeStatus>, Vec<usize>> =
        std::collections::BTreeMap::new();
    for (i, s) in statuses.iter().enumerate() {
        classes.entry(sign(s)).or_default().push(i);
    }
    let classes: Vec<(Vec<NodeStatus>, Vec<usize>)> = classes.into_iter().collect();
    let m = statuses.first().map_or(0, |s| s.len());
    // Each class's pressed nodes and open gaps as bits: two classes are cross-complementary
    // ([`cross_complementary`]) when no node of the one is pressed where either opens, which
    // is `(pressed_a | pressed_b) & (open_a | open_b) == 0` word by word. (Status by status,
    // the graph had been a twentieth of a random m = 9 enumeration.)
    let words = m.div_ceil(64).max(1);
    let mut pressed = vec![0u64; classes.len() * words];
    let mut open = vec![0u64; classes.len() * words];
    for (c, (sign, _)) in classes.iter().enumerate() {
        for (k, s) in sign.iter().enumerate() {
            let (word, bit) = (c * words + k / 64, 1u64 << (k % 64));
            if s.pressed() {
                pressed[word] |= bit;
            }
            if s.gap_open() {
                open[word] |= bit;
            }
        }
    }
    let range = |c: usize| c * words..(c + 1) * words;
    let mut cones: Vec<Cone> = maximal_cliques(classes.len(), |i, j| {
        let (a, b) = (range(i), range(j));
        pressed[a.clone()]
            .iter()
            .zip(&pressed[b.clone()])
            .zip(open[a].iter().zip(&open[b]))
            .all(|((pa, pb), (oa, ob))| (pa | pb) & (oa | ob) == 0)
    })
    .into_iter()
    .map(|members| {
        let pattern = (0..m)
            .map(|k| {
                if members.iter().any(|&c| classes[c].0[k].pressed()) {
                    ContactPattern::Contact
                } else if members.iter().any(|&c| classes[c].0[k].gap_open()) {
                    ContactPattern::Separated
                } else {
                    ContactPattern::Grazing
                }
            })
            .collect();
        let mut rays: Vec<usize> = members
            .iter()
            .flat_map(|&c| classes[c].1.iter().copied())
            .collect();
        rays.sort_unstable();
        Cone { rays, pattern }
    })
    .collect();
    cones.sort_by(|a, b| a.rays.cmp(&b.rays));
    cones
}

/// The relative accuracy of a witness's check.
const CHECK_TOL: f64 = 1e-8;

/// The part of a solution's check that every check shares: equilibrium `K u = r` row by row
/// within `tol` of the row's terms, and the normalisation `sum r_n = 1` within `tol`.
pub(crate) fn check_balance(
    problem: &Problem,
    u: &[f64],
    r: &[f64],
    tol: f64,
) -> Result<(), String> {
    let (d, m) = (problem.dim(), problem.nodes());
    let k = problem.stiffness();
    let n = d * m;
    for a in 0..n {
        let (mut v, mut s) = (-r[a], r[a].abs());
        for b in 0..n {
            v += k[(a, b)] * u[b];
            s += (k[(a, b)] * u[b]).abs();
        }
        if v.abs() > tol * s.max(f64::MIN_POSITIVE) {
            return Err(format!(
                "equilibrium fails in row {a}: residual {v:e} of {s:e}"
            ));
        }
    }
    let total: f64 = (0..m).map(|i| r[d * i]).sum();
    if (total - 1.0).abs() > tol {
        return Err(format!("sum r_n = {total}, not 1"));
    }
    Ok(())
}

/// Checks `(u, r)` against WP at friction coefficient `mu`: `K u = r`, `sum r_n = 1`, `u_n >= 0`,
/// `r_n >= 0`, `u_n r_n = 0` and `||r_t_i|| <= mu r_n_i`, relative to the terms involved.
pub fn check_solution(problem: &Problem, mu: f64, u: &[f64], r: &[f64]) -> Result<(), String> {
    let (d, m) = (problem.dim(), problem.nodes());
    check_balance(problem, u, r, CHECK_TOL)?;
    let u_scale = u.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    for i in 0..m {
        let (un, rn) = (u[d * i], r[d * i]);
        let rt = tangential(r, d, i);
        let node = i + 1;
        if un < -CHECK_TOL * u_scale {
            return Err(format!(
                "node {node} penetrates the obstacle (u_n = {un:e})"
            ));
        }
        if rn < 0.0 {
            return Err(format!("node {node} pulls on the obstacle (r_n = {rn:e})"));
        }
        if rn > 0.0 && un.abs() > CHECK_TOL * u_scale {
            return Err(format!(
                "node {node} is pressed with an open gap (u_n = {un:e}, r_n = {rn:e})"
            ));
        }
        if rt > mu * rn * (1.0 + 1e-12) + 1e-15 {
            return Err(format!(
                "node {node} is outside the friction cone at mu = {mu} (|r_t| = {rt:e}, r_n = {rn:e})"
            ));
        }
    }
    Ok(())
}

/// `||r_t_i||`.
pub(crate) fn tangential(r: &[f64], d: usize, i: usize) -> f64 {
    r[d * i + 1..d * i + d]
        .iter()
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The cones on the graph of the rays themselves, as they were found before the rays were
    /// merged into sign classes.
    fn pieces_of_every_ray(statuses: &[&[NodeStatus]]) -> Vec<Cone> {
        let m = statuses.first().map_or(0, |s| s.len());
        let mut cones: Vec<Cone> = maximal_cliques(statuses.len(), |i, j| {
            cross_complementary(statuses[i], statuses[j])
        })
        .into_iter()
        .map(|members| {
            let pattern = (0..m)
                .map(|k| {
                    if members.iter().any(|&i| statuses[i][k].pressed()) {
                        ContactPattern::Contact
                    } else if members.iter().any(|&i| statuses[i][k].gap_open()) {
                        ContactPattern::Separated
                    } else {
                        ContactPattern::Grazing
                    }
                })
                .collect();
            Cone {
                rays: members,
                pattern,
            }
        })
        .collect();
        cones.sort_by(|a, b| a.rays.cmp(&b.rays));
        cones
    }

    /// Random ray statuses, with twins (the same signs, other friction states) and repeats:
    /// the cones by sign classes (adjacency by bit words) are the cones of the rays' own graph
    /// (adjacency by [`cross_complementary`]); every fiftieth trial has 60 to 71 nodes, more
    /// than one word.
    #[test]
    fn cones_by_sign_classes_are_the_cones_of_the_rays() {
        use NodeStatus::*;
        let all = [Separated, Grazing, Stick, SlipPlus, SlipMinus];
        let mut rng = ChaCha8Rng::seed_from_u64(150);
        let mut several = 0;
        for trial in 0..400 {
            let m = if trial % 50 == 49 {
                60 + trial % 13
            } else {
                1 + trial % 6
            };
            let n = rng.gen_range(0..40);
            // Few distinct sign vectors for many rays: many twins.
            let kinds = rng.gen_range(1..=5);
            let statuses: Vec<Vec<NodeStatus>> = (0..n)
                .map(|_| (0..m).map(|_| all[rng.gen_range(0..kinds)]).collect())
                .collect();
            let refs: Vec<&[NodeStatus]> = statuses.iter().map(|s| s.as_slice()).collect();
            let by_classes = pieces(&refs);
            assert_eq!(by_classes, pieces_of_every_ray(&refs), "trial {trial}");
            several += by_classes.iter().filter(|c| c.rays.len() > 1).count();
        }
        assert!(several > 100, "{several} cones of several rays");
    }
}
