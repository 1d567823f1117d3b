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
//! to be alike in size, so the snake spreads the big ones. Then it decides the top's ends
//! (leaves and prunes above `D`) again, now recording them, and searches its own units'
//! subtrees. The nodes above `D` are visited by every shard: a leaf among them is found by
//! each, and the merge keeps one. The top is decided before any unit is searched, so what the
//! units find (a better incumbent of `critical`) cannot change it from one shard to another.
//!
//! The union of the shards' subtrees and the top is the one-run tree node for node, so the
//! union of their answers is the one-run answer: a piece found in one shard may be contained
//! in another shard's piece, and the merge removes it (as the one run's maximal filter would).
//!
//! **One split per process.** A process that runs several shards of the same tree one after
//! the other (a Dask worker, which runs task after task in one process) walks the top once:
//! the last split is kept (`Tree::split_key` names what it depends on) and the next shard of
//! the same tree starts from its units. A split is kept only when its walks raised no alarm
//! (`Tree::alarms`: an undecided program, a doubt, a stop), so a reused split reports the
//! same as one walked again.
//!
//! Without a shard (or with `1/1`) the search is the plain depth-first one, the two children of
//! a node in parallel (`rayon::join`).

use std::any::{Any, TypeId};
use std::collections::HashMap;

use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

/// Units of the split per shard: more units balance the shards better (the largest unit's
/// subtree bounds the largest shard) at the cost of a deeper top, which every shard solves.
pub const UNITS_PER_SHARD: usize = 32;

/// The least units per shard at which a split may stop deepening when the open nodes stop
/// growing (`PLATEAU`).
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
    /// Search nodes this shard decided to find the split (the top of the tree, every shard's
    /// work: the nodes above `Tree::keep_depth` once, the deeper ones again at each
    /// deepening).
    pub split_nodes: u64,
}

/// A binary search tree whose nodes are decided one at a time.
pub(crate) trait Tree: Sync {
    /// A node (cloned when a split walks the top of the tree more than once).
    type Node: Send + Sync + Clone + 'static;

    /// A digest of everything the decisions of the top depend on (the program's data, the
    /// tree's settings), when a split may be kept for the next shard of the same tree in this
    /// process; `None` (the default) walks the top for every shard. A tree that keeps exact
    /// records of its decisions (`--certify`) or whose decisions depend on what other nodes
    /// found (an incumbent) must answer `None`.
    fn split_key(&self) -> Option<u64> {
        None
    }

    /// A count of what a run must report and a reused split would not (undecided programs,
    /// doubts, a stop): a split during whose walks it grew is not kept.
    fn alarms(&self) -> u64 {
        0
    }

    /// Nodes above this depth are decided once per run even when the split walks them again
    /// (their children kept): the ones whose decision is dear (the 2D search's tightening
    /// nodes, two programs per free node). 0: none kept.
    fn keep_depth(&self) -> usize {
        0
    }

    /// `node`, to be kept until its subtree is searched (a unit of the split): without what
    /// is large and can be made again (a basis's dense inverse).
    fn shelve(&self, node: Self::Node) -> Self::Node {
        node
    }

    /// The root.
    fn root(&self) -> Self::Node;

    /// Whether `node` is a leaf (every contact node decided): what its visit finds is recorded,
    /// so a split decides such a node of the top again; a prune is not (nothing to record).
    fn is_leaf(&self, node: &Self::Node) -> bool;

    /// Decides `node` at `depth` and records what it finds (a leaf, an undecided set) unless
    /// this is a `rehearsal` (the split's walks over the top, whose leaves the shard decides
    /// again); returns its two children, or `None` when its subtree ends here (or the run must
    /// stop).
    fn visit(
        &self,
        node: Self::Node,
        depth: usize,
        rehearsal: bool,
    ) -> Option<(Self::Node, Self::Node)>;
}

/// The explored share of a search, for progress reports: in units of `2^-FRACTION_BITS` of the
/// whole tree, the part explored and the part this run searches (all of it unless sharded).
pub(crate) struct Explored {
    explored: AtomicU64,
    share: AtomicU64,
}

impl Explored {
    pub(crate) fn new() -> Explored {
        Explored {
            explored: AtomicU64::new(0),
            share: AtomicU64::new(1 << FRACTION_BITS),
        }
    }

    /// The explored part of this run's share of the tree, in `[0, 1]`.
    pub(crate) fn fraction(&self) -> f64 {
        let share = self.share.load(Ordering::Relaxed).max(1) as f64;
        (self.explored.load(Ordering::Relaxed) as f64 / share).min(1.0)
    }

    /// [`Explored::fraction`] in thousandths, rounded down: 1000 only once the whole share is
    /// explored, so that a progress line never shows 100% while the search still runs.
    /// (In integers: the units are `2^-62` of the tree, finer than an `f64` can tell from 1.)
    pub(crate) fn permille(&self) -> usize {
        let share = u128::from(self.share.load(Ordering::Relaxed).max(1));
        let explored = u128::from(self.explored.load(Ordering::Relaxed));
        (explored * 1000 / share).min(1000) as usize
    }

    /// Starts over (a new pass over the tree).
    pub(crate) fn reset(&self) {
        self.explored.store(0, Ordering::Relaxed);
        self.share.store(1 << FRACTION_BITS, Ordering::Relaxed);
    }
}

/// The children of decided nodes, by depth and path.
type Kept<N> = HashMap<(usize, u64), (N, N)>;

/// Runs a [`Tree`]'s search, whole or one shard of it, and keeps the explored share.
pub(crate) struct Walk<'t, T: Tree> {
    tree: &'t T,
    explored: &'t Explored,
    /// Nodes visited while finding the split.
    split_nodes: AtomicU64,
    /// The children of the nodes above [`Tree::keep_depth`], by depth and path, once decided.
    kept: Mutex<Kept<T::Node>>,
}

impl<'t, T: Tree> Walk<'t, T> {
    pub(crate) fn new(tree: &'t T, explored: &'t Explored) -> Walk<'t, T> {
        Walk {
            tree,
            explored,
            split_nodes: AtomicU64::new(0),
            kept: Mutex::new(HashMap::new()),
        }
    }

    /// [`Tree::visit`] for the split's walks, which visit the top of the tree more than once:
    /// the children of a node above [`Tree::keep_depth`] are kept and handed out again. (Only
    /// nodes with children are kept.)
    fn visit_top(
        &self,
        node: T::Node,
        depth: usize,
        path: u64,
        rehearsal: bool,
    ) -> Option<(T::Node, T::Node)> {
        if depth >= self.tree.keep_depth() {
            self.split_nodes.fetch_add(1, Ordering::Relaxed);
            return self.tree.visit(node, depth, rehearsal);
        }
        let key = (depth, path);
        if let Some(children) = self.kept.lock().expect("no panics while held").get(&key) {
            return Some(children.clone());
        }
        self.split_nodes.fetch_add(1, Ordering::Relaxed);
        let children = self.tree.visit(node, depth, rehearsal)?;
        self.kept
            .lock()
            .expect("no panics while held")
            .insert(key, children.clone());
        Some(children)
    }

    fn close(&self, depth: usize) {
        if depth <= FRACTION_BITS {
            self.explored
                .explored
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
        let Top {
            depth,
            units,
            ends,
            leaves,
        } = self.split_once(shard.count);
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
        let own: Vec<T::Node> = units
            .into_iter()
            .enumerate()
            .filter(|(k, _)| Shard::owner(*k, shard.count) == shard.index)
            .map(|(_, node)| node)
            .collect();
        report.own_units = own.len();
        // This shard's share: the top's ends (everything but the units) and its own units.
        let unit = 1u64 << (FRACTION_BITS - depth);
        let top = (1u64 << FRACTION_BITS) - report.units as u64 * unit;
        self.explored
            .share
            .store(top + own.len() as u64 * unit, Ordering::Relaxed);
        // The top's prunes are done; its leaves decided again, now recording what they find;
        // only then the units, so that nothing they find (a `critical` incumbent) changes how
        // the top was decided.
        ends.into_iter().for_each(|d| self.close(d));
        leaves
            .into_par_iter()
            .for_each(|(d, node)| self.dive(node, d));
        own.into_par_iter().for_each(|node| self.dive(node, depth));
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

    /// [`Walk::split`], or the split this process kept from an earlier shard of the same tree
    /// (see the module docs).
    fn split_once(&self, count: usize) -> Top<T::Node> {
        let Some(key) = self.tree.split_key() else {
            return self.split(count);
        };
        let key = (TypeId::of::<Top<T::Node>>(), key, count);
        let kept = LAST_SPLIT.lock().ok().and_then(|last| {
            let (k, top) = last.as_ref()?;
            (*k == key).then(|| top.downcast_ref::<Top<T::Node>>().cloned())?
        });
        if let Some(top) = kept {
            return top;
        }
        let alarms = self.tree.alarms();
        let top = self.split(count);
        if self.tree.alarms() == alarms {
            if let Ok(mut last) = LAST_SPLIT.lock() {
                *last = Some((key, Box::new(top.clone())));
            }
        }
        top
    }

    /// The split depth for `count` shards and the units there, in depth-first order,
    /// with the top's ends. No units when the tree ends above every depth tried.
    ///
    /// Deepens until [`UNITS_PER_SHARD`] units per shard are open, or, once there are
    /// [`MIN_UNITS_PER_SHARD`] per shard, until the open nodes stop growing (by less than
    /// [`PLATEAU`] since the last depth tried): a narrow tree (the plug at m = 40 keeps about 200
    /// open nodes from depth 10 to 40) would otherwise be walked almost whole by every shard.
    fn split(&self, count: usize) -> Top<T::Node> {
        let target = UNITS_PER_SHARD.saturating_mul(count);
        let least = MIN_UNITS_PER_SHARD.saturating_mul(count);
        let mut depth = levels(target);
        let mut best = Top {
            depth: 0,
            units: Vec::new(),
            ends: Vec::new(),
            leaves: Vec::new(),
        };
        while depth <= MAX_SPLIT_DEPTH {
            let top = self.top(self.tree.root(), 0, 0, depth);
            if top.units.is_empty() {
                break;
            }
            let before = best.units.len();
            let n = top.units.len();
            best = top;
            if n >= target || (n >= least && (n as f64) < PLATEAU * before as f64) {
                break;
            }
            // The open nodes at most double per level: skip the levels that cannot reach the
            // least number of units.
            depth += levels(least.div_ceil(n)).max(1);
        }
        best
    }

    /// The top of the subtree of `node` down to depth `split`: the open nodes there (shelved),
    /// the depths of the nodes above it whose subtrees end, and those of them that are leaves
    /// (a rehearsal records nothing, so they are decided again), in depth-first order.
    fn top(&self, node: T::Node, depth: usize, path: u64, split: usize) -> Top<T::Node> {
        let mut top = Top {
            depth: split,
            units: Vec::new(),
            ends: Vec::new(),
            leaves: Vec::new(),
        };
        if depth == split {
            top.units.push(self.tree.shelve(node));
            return top;
        }
        let leaf = self.tree.is_leaf(&node).then(|| node.clone());
        match self.visit_top(node, depth, path, true) {
            None => {
                top.ends.push(depth);
                top.leaves.extend(leaf.map(|n| (depth, n)));
                top
            }
            Some((a, b)) => {
                let (mut left, right) = rayon::join(
                    || self.top(a, depth + 1, path << 1, split),
                    || self.top(b, depth + 1, (path << 1) | 1, split),
                );
                left.units.extend(right.units);
                left.ends.extend(right.ends);
                left.leaves.extend(right.leaves);
                left
            }
        }
    }
}

/// The last split this process made that may be reused: the node type, the tree's
/// [`Tree::split_key`] and the number of shards, and the [`Top`]. (One split: a process runs
/// the shards of one tree at a time; the units hold no basis inverse, a few MiB at m = 80.)
type LastSplit = Option<((TypeId, u64, usize), Box<dyn Any + Send>)>;
static LAST_SPLIT: Mutex<LastSplit> = Mutex::new(None);

/// The top of a tree above a split depth: the open nodes at the depth (the units), the depths
/// of the nodes above it whose subtrees end, and the leaves among those, with their depths.
#[derive(Clone)]
struct Top<N> {
    depth: usize,
    units: Vec<N>,
    ends: Vec<usize>,
    leaves: Vec<(usize, N)>,
}

/// The levels of a binary tree that hold `n` nodes: `ceil(log2 n)`.
fn levels(n: usize) -> usize {
    (usize::BITS - n.saturating_sub(1).leading_zeros()) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// The thousandths explored reach 1000 only with the last unit of the tree, although an
    /// `f64` rounds `1 - 2^-62` to 1.
    #[test]
    fn the_permille_is_1000_only_when_all_is_explored() {
        let explored = Explored::new();
        let whole = 1u64 << FRACTION_BITS;
        for (units, permille) in [(0, 0), (whole / 2, 500), (whole - 1, 999), (whole, 1000)] {
            explored.explored.store(units, Ordering::Relaxed);
            assert_eq!(explored.permille(), permille, "{units} units");
        }
        // A shard's share: half the tree, a quarter of it explored.
        explored.share.store(whole / 2, Ordering::Relaxed);
        explored.explored.store(whole / 8, Ordering::Relaxed);
        assert_eq!(explored.permille(), 250);
    }

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
        fn is_leaf(&self, node: &u64) -> bool {
            let depth = node.ilog2() as usize;
            let h = node.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 59;
            depth >= 14 || (depth >= 3 && h < 3)
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
        Walk::new(&whole, &Explored::new()).run(None);
        let mut all = whole.leaves.into_inner().unwrap();
        all.sort();
        for count in [1, 2, 3, 5, 16] {
            let mut union = Vec::new();
            let mut tops = 0;
            for index in 1..=count {
                let part = toy();
                let explored = Explored::new();
                let walk = Walk::new(&part, &explored);
                let report = walk.run(Some(Shard::new(index, count).unwrap())).unwrap();
                assert!((explored.fraction() - 1.0).abs() < 1e-12, "{index}/{count}");
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
