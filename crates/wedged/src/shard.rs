//! Shards: one search over contact sets split into `N` independent parts (issue 24), so that
//! `N` processes (a Slurm array, Dask workers) each run one and a merge gives the one-run answer.
//!
//! **The split.** Every search over contact sets here is a binary tree whose nodes are decided
//! one at a time by a deterministic computation (a node's program and its warm start depend on
//! the path to it only, never on timing or threads). So every shard can compute the same split
//! without talking to the others: it walks the top of the tree down to the **split depth** `D`,
//! the first depth at which at least [`UNITS_PER_SHARD`]` * N` nodes are still open (iterative
//! deepening from `log2` of that; each deepening solves the top again, at most about twice the
//! top's programs), numbers the open nodes at depth `D` (the **units**) in depth-first order,
//! and deals them out like cards in a snake: units `0..N` to shards `1..N`, units `N..2N` to
//! shards `N..1`, and so on. Neighbouring units are siblings and cousins, whose subtrees tend
//! to be alike in size, so the snake spreads the big ones. Then it searches its own units'
//! subtrees. The nodes above `D` are visited by every shard: a leaf among them is found by
//! each, and the merge keeps one.
//!
//! The union of the shards' subtrees and the top is the one-run tree node for node, so the
//! union of their answers is the one-run answer: a piece found in one shard may be contained
//! in another shard's piece, and the merge removes it (as the one run's maximal filter would).
//!
//! Without a shard (or with `1/1`) the search is the plain depth-first one, the two children of
//! a node in parallel (`rayon::join`).

use std::sync::atomic::{AtomicU64, Ordering};

/// Units of the split per shard: more units balance the shards better (the largest unit's
/// subtree bounds the largest shard) at the cost of a deeper top, which every shard solves.
pub const UNITS_PER_SHARD: usize = 32;

/// The least units per shard at which a split may stop deepening when the open nodes stop
/// growing ([`PLATEAU`]).
pub const MIN_UNITS_PER_SHARD: usize = 4;

/// Deepening stops (with at least [`MIN_UNITS_PER_SHARD`] units per shard) when the open nodes
/// grew by less than this factor since the last depth tried. (The plug at m = 40, 16 shards:
/// 176, 210, 226 open nodes at depths 9, 10, 11, and the largest shard's share of the work
/// 0.18, 0.11 (depth 11), 0.09 (depth 13) against the 1/16 = 0.0625 of a perfect split.)
const PLATEAU: f64 = 1.25;

/// The deepest split (paths are kept in the bits of a `u64`).
const MAX_SPLIT_DEPTH: usize = 60;

/// Explored fractions are counted in units of `2^-FRACTION_BITS` of the tree.
const FRACTION_BITS: usize = 62;

/// One shard of `count`: `index` from 1 to `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    index: usize,
    count: usize,
}

impl Shard {
    /// Shard `index` (1-based) of `count`.
    pub fn new(index: usize, count: usize) -> Result<Shard, String> {
        if count == 0 {
            return Err("the number of shards must be at least 1".to_string());
        }
        if index == 0 || index > count {
            return Err(format!(
                "shard {index} of {count}: the index must be from 1 to {count}"
            ));
        }
        Ok(Shard { index, count })
    }

    /// Reads `I/N`.
    pub fn parse(text: &str) -> Result<Shard, String> {
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| format!("'{text}': a shard is written I/N, e.g. 3/16"))?;
        let number = |s: &str| {
            s.trim()
                .parse::<usize>()
                .map_err(|_| format!("'{text}': a shard is written I/N with whole numbers"))
        };
        Shard::new(number(i)?, number(n)?)
    }

    pub fn index(&self) -> usize {
        self.index
    }

    pub fn count(&self) -> usize {
        self.count
    }

    /// The shard (1-based) that owns unit `k` (0-based, depth-first order) of a split into
    /// `count` shards: a snake, `0..N` to `1..N`, `N..2N` to `N..1`, ...
    pub fn owner(k: usize, count: usize) -> usize {
        let (round, place) = (k / count, k % count);
        if round % 2 == 0 {
            place + 1
        } else {
            count - place
        }
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// How a shard's search was split.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ShardReport {
    pub index: usize,
    pub count: usize,
    /// The split depth `D` (0: not split; the shard holds the whole tree).
    pub split_depth: usize,
    /// Open nodes at depth `D`, over all shards.
    pub units: usize,
    /// Of those, this shard's.
    pub own_units: usize,
    /// Search nodes this shard visited to find the split (the top of the tree, every shard's
    /// work, solved again at each deepening).
    pub split_nodes: u64,
}

/// A binary search tree whose nodes are decided one at a time.
pub(crate) trait Tree: Sync {
    type Node: Send;

    /// The root.
    fn root(&self) -> Self::Node;

    /// Decides `node` at `depth` and records what it finds (a leaf, an undecided set) unless
    /// this is a `rehearsal` (the split's walks over the top, which the shard walks again);
    /// returns its two children, or `None` when its subtree ends here (or the run must stop).
    fn visit(
        &self,
        node: Self::Node,
        depth: usize,
        rehearsal: bool,
    ) -> Option<(Self::Node, Self::Node)>;
}

/// Runs a [`Tree`]'s search, whole or one shard of it, and keeps the explored share.
pub(crate) struct Walk<'t, T: Tree> {
    tree: &'t T,
    /// The explored share, in units of `2^-FRACTION_BITS` of the whole tree.
    explored: AtomicU64,
    /// This run's share of the tree, in the same units (all of it unless sharded).
    share: AtomicU64,
    /// Nodes visited while finding the split.
    split_nodes: AtomicU64,
}

impl<'t, T: Tree> Walk<'t, T> {
    pub(crate) fn new(tree: &'t T) -> Walk<'t, T> {
        Walk {
            tree,
            explored: AtomicU64::new(0),
            share: AtomicU64::new(1 << FRACTION_BITS),
            split_nodes: AtomicU64::new(0),
        }
    }

    /// The explored part of this run's share of the tree, in `[0, 1]`.
    pub(crate) fn explored(&self) -> f64 {
        let share = self.share.load(Ordering::Relaxed).max(1) as f64;
        (self.explored.load(Ordering::Relaxed) as f64 / share).min(1.0)
    }

    fn close(&self, depth: usize) {
        if depth <= FRACTION_BITS {
            self.explored
                .fetch_add(1u64 << (FRACTION_BITS - depth), Ordering::Relaxed);
        }
    }

    /// The search: the whole tree, or `shard`'s part of it (see the module docs).
    pub(crate) fn run(&self, shard: Option<Shard>) -> Option<ShardReport> {
        let Some(shard) = shard else {
            self.dive(self.tree.root(), 0);
            return None;
        };
        let mut report = ShardReport {
            index: shard.index,
            count: shard.count,
            split_depth: 0,
            units: 1,
            own_units: 1,
            split_nodes: 0,
        };
        if shard.count == 1 {
            self.dive(self.tree.root(), 0);
            return Some(report);
        }
        let (depth, units) = self.split(shard.count);
        report.split_nodes = self.split_nodes.load(Ordering::Relaxed);
        report.split_depth = depth;
        report.units = units.len();
        if units.is_empty() {
            // The tree ends above any split: the whole of it is the top, which every shard
            // searches (the merge keeps one copy of each piece).
            report.own_units = 0;
            self.dive(self.tree.root(), 0);
            return Some(report);
        }
        let own = (0..units.len())
            .filter(|&k| Shard::owner(k, shard.count) == shard.index)
            .count();
        report.own_units = own;
        // This shard's share: the top's ends (everything but the units) and its own units.
        let unit = 1u64 << (FRACTION_BITS - depth);
        let top = (1u64 << FRACTION_BITS) - units.len() as u64 * unit;
        self.share.store(top + own as u64 * unit, Ordering::Relaxed);
        self.walk(self.tree.root(), 0, 0, depth, &units, shard);
        Some(report)
    }

    /// The whole subtree of `node`, children in parallel.
    fn dive(&self, node: T::Node, depth: usize) {
        match self.tree.visit(node, depth, false) {
            None => self.close(depth),
            Some((a, b)) => {
                rayon::join(|| self.dive(a, depth + 1), || self.dive(b, depth + 1));
            }
        }
    }

    /// The top down to `split`, then the subtrees of `shard`'s units. `path` holds the
    /// branches taken (bit 0 the first child), so that at depth `split` it is the unit's key.
    fn walk(
        &self,
        node: T::Node,
        depth: usize,
        path: u64,
        split: usize,
        units: &[u64],
        shard: Shard,
    ) {
        if depth == split {
            let own = units
                .binary_search(&path)
                .is_ok_and(|k| Shard::owner(k, shard.count) == shard.index);
            if own {
                self.dive(node, depth);
            }
            return;
        }
        match self.tree.visit(node, depth, false) {
            None => self.close(depth),
            Some((a, b)) => {
                rayon::join(
                    || self.walk(a, depth + 1, path << 1, split, units, shard),
                    || self.walk(b, depth + 1, (path << 1) | 1, split, units, shard),
                );
            }
        }
    }

    /// The split depth for `count` shards and the units' paths there, in depth-first order
    /// (which is their numeric order). Empty when the tree ends above every depth tried.
    ///
    /// Deepens until [`UNITS_PER_SHARD`] units per shard are open, or, once there are
    /// [`MIN_UNITS_PER_SHARD`] per shard, until the open nodes stop growing (by less than
    /// [`PLATEAU`] since the last depth tried): a narrow tree (the plug at m = 40 keeps about 200
    /// open nodes from depth 10 to 40) would otherwise be walked almost whole by every shard.
    fn split(&self, count: usize) -> (usize, Vec<u64>) {
        let target = UNITS_PER_SHARD.saturating_mul(count);
        let least = MIN_UNITS_PER_SHARD.saturating_mul(count);
        let mut depth = levels(target);
        let mut best: (usize, Vec<u64>) = (0, Vec::new());
        while depth <= MAX_SPLIT_DEPTH {
            let units = self.frontier(self.tree.root(), 0, 0, depth);
            if units.is_empty() {
                break;
            }
            let before = best.1.len();
            let n = units.len();
            best = (depth, units);
            if n >= target || (n >= least && (n as f64) < PLATEAU * before as f64) {
                break;
            }
            // The open nodes at most double per level: skip the levels that cannot reach the
            // least number of units.
            depth += levels(least.div_ceil(n)).max(1);
        }
        best
    }

    /// The paths of the open nodes at depth `split` below `node`, in depth-first order.
    fn frontier(&self, node: T::Node, depth: usize, path: u64, split: usize) -> Vec<u64> {
        if depth == split {
            return vec![path];
        }
        self.split_nodes.fetch_add(1, Ordering::Relaxed);
        match self.tree.visit(node, depth, true) {
            None => Vec::new(),
            Some((a, b)) => {
                let (mut left, right) = rayon::join(
                    || self.frontier(a, depth + 1, path << 1, split),
                    || self.frontier(b, depth + 1, (path << 1) | 1, split),
                );
                left.extend(right);
                left
            }
        }
    }
}

/// The levels of a binary tree that hold `n` nodes: `ceil(log2 n)`.
fn levels(n: usize) -> usize {
    (usize::BITS - n.saturating_sub(1).leading_zeros()) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// A tree of depth-varying width: node `(id, depth)` has children until a pseudo-random
    /// depth; it records the leaves it reaches.
    struct Toy {
        leaves: Mutex<Vec<u64>>,
        visits: AtomicU64,
    }

    impl Tree for Toy {
        type Node = u64;
        fn root(&self) -> u64 {
            1
        }
        fn visit(&self, node: u64, depth: usize, rehearsal: bool) -> Option<(u64, u64)> {
            self.visits.fetch_add(1, Ordering::Relaxed);
            let h = node.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 59;
            if depth >= 14 || (depth >= 3 && h < 3) {
                if !rehearsal {
                    self.leaves.lock().unwrap().push(node);
                }
                return None;
            }
            Some((2 * node, 2 * node + 1))
        }
    }

    fn toy() -> Toy {
        Toy {
            leaves: Mutex::new(Vec::new()),
            visits: AtomicU64::new(0),
        }
    }

    #[test]
    fn shards_cover_the_tree_once_below_the_split() {
        let whole = toy();
        Walk::new(&whole).run(None);
        let mut all = whole.leaves.into_inner().unwrap();
        all.sort();
        for count in [1, 2, 3, 5, 16] {
            let mut union = Vec::new();
            let mut tops = 0;
            for index in 1..=count {
                let part = toy();
                let walk = Walk::new(&part);
                let report = walk.run(Some(Shard::new(index, count).unwrap())).unwrap();
                assert!((walk.explored() - 1.0).abs() < 1e-12, "{index}/{count}");
                assert!(count == 1 || report.units >= MIN_UNITS_PER_SHARD * count);
                tops = report.split_depth;
                union.extend(part.leaves.into_inner().unwrap());
            }
            union.sort();
            // Leaves above the split are found by every shard.
            let above = all.iter().filter(|&&l| (l.ilog2() as usize) < tops).count();
            assert_eq!(union.len(), all.len() + (count - 1) * above, "N = {count}");
            union.dedup();
            assert_eq!(union, all, "N = {count}");
        }
    }

    #[test]
    fn the_snake_deals_evenly() {
        let count = 4;
        let owners: Vec<usize> = (0..10).map(|k| Shard::owner(k, count)).collect();
        assert_eq!(owners, [1, 2, 3, 4, 4, 3, 2, 1, 1, 2]);
    }

    #[test]
    fn shards_are_read_and_checked() {
        assert_eq!(Shard::parse("3/16").unwrap(), Shard::new(3, 16).unwrap());
        assert_eq!(Shard::parse(" 1 / 1 ").unwrap().to_string(), "1/1");
        for bad in ["0/4", "5/4", "1/0", "3", "a/b", "-1/2"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }
}
