//! The settings of `critical`'s branch and bound ([`super`]), each with the measurements that
//! chose it: how deep nodes tighten and settle their drive bounds, the first leaf's dive and
//! rounding, when a pass starts over, and the passes' bars; and the tests' hooks that override
//! them ([`Hooks`]).

use crate::run::Fault;

/// Search nodes down to this depth tighten the bounds of their undecided nodes' drives
/// ([`crate::conic::cuts::tighten`]); deeper ones inherit them. In 3D the depth grows with the
/// problem ([`crate::conic::cuts::tighten_depth_3d`]). Deeper tightening visits fewer nodes but
/// solves more programs. (Measured on the 2D plug with the simplex method, problem `mu` 2,
/// before the root settled its bounds: m = 40, depths 4, 5: 0.78, 1.35 s; m = 60, depths 3, 4,
/// 5, 6: 13.0, 8.9, 8.7, 10.5 s (74k, 31k, 16k, 7.8k nodes); m = 80, depths 4, 5, 6, 8: 85, 46,
/// 44, 137 s (278k, 107k, 52k, 24k nodes), which gave `max(4, m / 20)`. With Clarabel, at m =
/// 40, depths 2, 4, 6, 8 took 52, 30, 33, 35 s.)
pub(super) const TIGHTEN_DEPTH: usize = 4;

/// The depth that replaces [`TIGHTEN_DEPTH`] where the root settles its bounds
/// ([`SETTLE_FROM`]): below settled bounds, tightening pays only just under them. (Measured on
/// the 2D plug with the root's rounded leaf ([`ROUNDED`]), one run each: m = 100, depths 0, 1,
/// 2, 3, 5: 5.17, 4.98, 5.16, 6.25, 8.71 s (19.6k, 10.3k, 7.8k, 6.3k, 594 nodes); m = 120,
/// depths 0, 1, 3, 5: 21.5, 19.4, 18.9, 19.9 s; m = 40 to 80 the same within 5%.)
pub(super) const SETTLED_TIGHTEN_DEPTH: usize = 1;

/// Bounds computed at a level more than this factor above the current one are stale: the
/// incumbent has dropped since (the first nodes are visited before there is one), and nodes
/// down to [`RETIGHTEN_DEPTH`] tighten them again at the current level.
pub(super) const STALE: f64 = 1e-4;
pub(super) const RETIGHTEN_DEPTH: usize = 8;

/// The root settles its drive bounds ([`crate::conic::node_lp::tighten_node`]) on problems of
/// this many nodes or more. With the rounded first leaf ([`ROUNDED`]) at `mu*` a settled 2D
/// root often refutes the whole tree at once. (Measured on the 2D plug, `farm-bench --vs`,
/// paired wall medians of settled against tightened once: m = 10 1.29 (8 against 10 ms), m = 16
/// 1.02, m = 20 1.14, m = 24 0.96, m = 40 0.49 (0.20 against 0.41 s), m = 50 0.36 against 0.72
/// s. Before the rounded leaf: m = 20 1.10, m = 40 1.06, m = 60 1.03, m = 70 0.48, m = 80
/// 0.41.) In 3D since each node's bounds impose its own complementarity
/// ([`crate::conic::cuts::tighten`]; before, at m = 20, 1.4 s had become 1.6 s), with the 3D
/// tightening depth and no rounding: on the V-groove plug (`plug3d.toml`, `nx = 4`, `nz = 4`
/// but m = 30: `nz = 3`), paired wall medians m = 30 0.97 (`-n 5`), m = 40 0.80 (`-n 5`), m = 48
/// 0.73 (`-n 2`); one run each, m = 56 26.3 -> 18.8 s, m = 64 256 -> 60 s (70k -> 58k nodes), m
/// = 80 638 -> 444 s (631k -> 590k nodes); the clamped frustum (`frustum3d.toml`, m = 48) 455
/// -> 479 s (1.07M -> 1.15M nodes); the same `mu*` in all. (Tightening depths 6 and 20 instead
/// of `m / 5` = 12 below the settled root at m = 64: 108 and 86 s; the dive's settled root
/// rounded as in 2D: m = 40 15 s, m = 56 51 s.)
pub(super) const SETTLE_FROM: usize = 24;

/// Nodes down to this depth settle their bounds where the root does ([`SETTLE_FROM`]); the
/// root's children start from its settled bounds. (Measured on the 2D plug, one run each,
/// depths 0, 1, 2 (3): m = 100 4.38, 4.37, 4.44 s (11.7k, 4, 4 nodes); m = 120 17.2, 7.8, 7.7
/// s (69.7k, 4, 4 nodes); m = 140 243, 164, (157) s (1.51M, 836k, (803k) nodes). From m = 40 to
/// 80 the settled root refutes the whole tree, and the depth makes no difference.)
pub(super) const SETTLE_DEPTH: usize = 1;

/// A pass's settling nodes (not the dive's root, whose point is rounded to the first leaf)
/// settle in this many parts ([`crate::conic::node_lp::Settle::InParts`]): each part's
/// programs carry the cuts the parts before it found. At `mu*` the pass's root then often
/// refutes the whole tree by itself. (Measured on the 2D plug, one run each, 2026-11-28: parts
/// 1, 2, 3, 4: m = 100 4.66, 4.23, 3.49, 3.26 s (4, 4, 2, 2 nodes); m = 120 7.53, 7.98, 7.25,
/// 9.22 s; m = 80 2.27 and 1.55 s with 1 and 3; m = 140 34.1 and 32.9 s (56k and 674 nodes).
/// Settling the dive's root in three parts too changed its rounded leaf, and its improvement
/// stopped above `mu*` at m = 120: 31 s, 77.7k nodes.)
pub(super) const SETTLE_PARTS: usize = 3;

/// A pass's settling nodes stop settling when no bound interval shrinks by more than this
/// share of its width in a round (other settled tightenings: [`crate::conic::node_lp::SETTLED`],
/// 0.05). At `mu*` the pass's root shrinks every interval by a few percent a part for dozens of
/// parts before they collapse; stopped at 5% it had left the refutation to its children.
/// (Measured on the 2D plug with the block moves' local search, `farm-bench --vs` on one
/// build, 0.01 against 0.05, paired wall medians, 2026-11-28: m = 100 1.02 (`-n 5`), m = 120
/// 0.99 (`-n 5`), m = 140 **0.77** (13.0 against 16.8 s, `-n 3`; the root refutes alone, 2
/// nodes against 4), m = 160 0.98 (`-n 2`); one run each, m = 200 105 against 102 to 104 s.)
pub(super) const PASS_SETTLED: f64 = 0.01;

/// The dive's root (whose point is rounded to the first leaf, [`ROUNDED`]) stops settling when
/// no bound interval shrinks by more than this share of its width in a round (a pass's root:
/// [`PASS_SETTLED`]; other settled tightenings: [`crate::conic::node_lp::SETTLED`], 0.05). The
/// rounded leaf only needs the root's point near its settled one; the rounds below 10% cost a
/// third of the dive. (Measured on the 2D plug, `farm-bench --vs` on one build, 0.1 against
/// 0.05, paired wall medians, 2026-11-29: m = 50 0.94 (`-n 7`), m = 100 0.95 (`-n 5`), m = 140
/// 0.91 (4.02 against 4.48 s, `-n 3`); one run each, m = 200 32.6 against 33.1 s; 0.2: m = 140
/// 19.4 s (the rounded leaf's improvement stopped above `mu*`); the 3D V-groove at m = 40 1.01;
/// the same `mu*` in all.)
pub(super) const DIVE_SETTLED: f64 = 0.1;

/// The dive's first leaf in 2D is the root's relaxed solution rounded: the contact set of the
/// nodes pressed by more than this fraction of the most pressed, its leaf by [`super::leaf_of`]
/// (a few linear programs), then improved ([`super::improve`]). On the 2D plug the dive finds
/// no leaf of its own from m = 80 on, and the improvement from the all-contact set stops above
/// `mu*`; from the rounded set it reaches `mu*` (m = 100: 31 steps from 4.12 with 1e-2; 70
/// steps from 2.78 with 1e-6), where the settled root of the next pass often refutes the whole
/// tree. Only from a settled root ([`SETTLE_FROM`]): from a root tightened once the improvement
/// stopped at 2.38 (m = 100) and the run took 43 s against 5 s. Measured with the settling from
/// 24 nodes and [`SETTLED_TIGHTEN_DEPTH`], `farm-bench -n 5 --vs`, paired wall medians against
/// the root settled from 60 nodes with no rounding: m = 40 0.61, m = 60 0.51, m = 80 0.62 (2.09
/// s), m = 100 0.38 (5.33 against 14.0 s); m = 120 19.3 s (one run; 162 s before).
pub(super) const ROUNDED: f64 = 1e-2;

/// A pass (where the root settles, 2D or 3D) starts over when a leaf it found has lowered the level
/// by more than this share below the level its root settled at: the root then settles again
/// at the new level, which refutes more of the tree than the old bounds. (On the 2D plug at m
/// = 140, with every new best improved: 121 s and 382k nodes, most of them the proof under the
/// stale root, against 33 s and 58k nodes with the restart.)
pub(super) const RESTART: f64 = 1e-3;

/// The first leaf's dive (see [`super::run`]) gives up after this many nodes per contact node.
pub(super) const DIVE_NODES_PER_NODE: u64 = 10;

/// The ratio of successive bars ([`bars`]).
pub(super) const BAR_RATIO: f64 = 1.25;

/// The bars of the successive passes: the problem's own `mu`, then up by [`BAR_RATIO`] to 16
/// times it, then no bar. A pass tests every node at `min(bar, incumbent (1 - tol))`; a pass
/// that finds no leaf has certified the whole tree infeasible at its bar, so `mu* > bar`, and
/// the next pass starts over with the next bar. The last pass, at `mu = infinity`, finding
/// nothing certifies that no friction coefficient wedges the body. (A bar near `mu*` saves most
/// of the work of the first dive: on the 2D plug with m = 16, 0.3 s against 1.0 s with no bar.
/// A pass below `mu*` costs about a final proof, cheaper the further below; a pass above it
/// crawls down from leaves up to its bar. On the 2D plug with m = 60 and `mu` = 1.8, 0.26%
/// below `mu*`: ratios 4, 1.5, 1.25 took 166 s, 58 s, 43 s.)
pub(super) fn bars(mu: f64) -> Vec<f64> {
    let mut out = vec![mu];
    while out.len() < 64 && out[out.len() - 1] < 16.0 * mu / BAR_RATIO.sqrt() {
        out.push(out[out.len() - 1] * BAR_RATIO);
    }
    out.push(f64::INFINITY);
    out
}

/// The test hooks of a run ([`crate::run::Fault`]).
#[derive(Debug, Clone, Copy, Default)]
pub(in crate::critical) struct Hooks {
    /// Stop as an interruption would after the first pass that finds no leaf at or below its
    /// bar ([`crate::run::Fault::HaltAfterPass`]).
    pub halt: bool,
    /// Settle the root's bounds whatever the problem's size ([`crate::run::Fault::SettleRoot`]).
    pub settle_always: bool,
}

impl Hooks {
    /// The hooks a run's injected fault asks for.
    pub(in crate::critical) fn of(fault: Option<Fault>) -> Hooks {
        Hooks {
            halt: fault == Some(Fault::HaltAfterPass),
            settle_always: fault == Some(Fault::SettleRoot),
        }
    }
}
