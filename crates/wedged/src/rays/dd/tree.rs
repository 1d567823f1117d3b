//! The bit-pattern tree of `dd.rs`: held rays grouped by their bit sets, so that a whole
//! group of pairs can be skipped when no ray in it can combine.

use super::{bit, Rays};

/// A bit-pattern tree over a set of rays (after Terzer & Stelling, 2008): a binary tree whose
/// leaves hold at most [`PatternTree::LEAF`] rays, split on a zero-set bit, where every node keeps
/// the OR of its rays' zero sets and the AND of their `gap` and `press` masks. A query skips a
/// subtree when no ray in it can share enough tight constraints, or every ray in it breaks
/// filter (a).
pub(super) struct PatternTree {
    pub(super) nodes: Vec<TreeNode>,
    /// The rays, permuted so that each node's rays are `items[start..end]`.
    pub(super) items: Vec<usize>,
    pub(super) words: usize,
    pub(super) node_words: usize,
    pub(super) or_z: Vec<u64>,
    pub(super) and_gap: Vec<u64>,
    pub(super) and_press: Vec<u64>,
}

pub(super) struct TreeNode {
    pub(super) start: usize,
    pub(super) end: usize,
    pub(super) children: Option<(usize, usize)>,
}

impl PatternTree {
    const LEAF: usize = 12;

    pub(super) fn build(rays: &Rays, items: &[usize]) -> PatternTree {
        let mut tree = PatternTree {
            nodes: Vec::new(),
            items: items.to_vec(),
            words: rays.words,
            node_words: rays.node_words,
            or_z: Vec::new(),
            and_gap: Vec::new(),
            and_press: Vec::new(),
        };
        tree.node(rays, 0, items.len());
        tree
    }

    pub(super) fn or_z(&self, t: usize) -> &[u64] {
        &self.or_z[t * self.words..(t + 1) * self.words]
    }
    pub(super) fn and_gap(&self, t: usize) -> &[u64] {
        &self.and_gap[t * self.node_words..(t + 1) * self.node_words]
    }
    pub(super) fn and_press(&self, t: usize) -> &[u64] {
        &self.and_press[t * self.node_words..(t + 1) * self.node_words]
    }

    /// Some ray of the tree other than `a` and `b` is tight on every constraint in `common`.
    /// A subtree is skipped when the union of its zero sets misses a constraint of `common`.
    pub(super) fn has_superset(&self, rays: &Rays, common: &[u64], a: usize, b: usize) -> bool {
        let mut stack = vec![0usize];
        while let Some(t) = stack.pop() {
            if self.or_z(t).iter().zip(common).any(|(o, c)| c & !o != 0) {
                continue;
            }
            let node = &self.nodes[t];
            if let Some((left, right)) = node.children {
                stack.push(right);
                stack.push(left);
                continue;
            }
            let contains = |c: usize| rays.z(c).iter().zip(common).all(|(z, w)| w & !z == 0);
            if self.items[node.start..node.end]
                .iter()
                .any(|&c| c != a && c != b && contains(c))
            {
                return true;
            }
        }
        false
    }

    /// Builds the node for `items[start..end]` and returns its index.
    pub(super) fn node(&mut self, rays: &Rays, start: usize, end: usize) -> usize {
        let t = self.nodes.len();
        self.nodes.push(TreeNode {
            start,
            end,
            children: None,
        });
        let (mut or_z, mut and_z) = (vec![0u64; self.words], vec![!0u64; self.words]);
        let (mut and_gap, mut and_press) =
            (vec![!0u64; self.node_words], vec![!0u64; self.node_words]);
        for &a in &self.items[start..end] {
            for (w, x) in rays.z(a).iter().enumerate() {
                or_z[w] |= x;
                and_z[w] &= x;
            }
            for (w, x) in rays.gap(a).iter().enumerate() {
                and_gap[w] &= x;
            }
            for (w, x) in rays.press(a).iter().enumerate() {
                and_press[w] &= x;
            }
        }
        if start == end {
            and_gap.fill(0);
            and_press.fill(0);
        }
        self.or_z.extend(&or_z);
        self.and_gap.extend(&and_gap);
        self.and_press.extend(&and_press);
        if end - start <= Self::LEAF {
            return t;
        }
        // Split on the zero-set bit that varies and divides the rays most evenly. The ones of
        // every bit are counted in one pass over (about 1024 of) the rays.
        let len = end - start;
        // Rays sit in creation order, so the sample is strided, not a prefix.
        let stride = len.div_ceil(1024);
        let sample = len.div_ceil(stride);
        let mut ones = vec![0usize; self.words * 64];
        for &a in self.items[start..end].iter().step_by(stride) {
            for (w, x) in rays.z(a).iter().enumerate() {
                let mut v = x & or_z[w] & !and_z[w];
                while v != 0 {
                    ones[w * 64 + v.trailing_zeros() as usize] += 1;
                    v &= v - 1;
                }
            }
        }
        let mut best: Option<(usize, usize)> = None;
        for w in 0..self.words {
            let varying = or_z[w] & !and_z[w];
            for b in (0..64).filter(|b| varying >> b & 1 == 1) {
                let count = ones[w * 64 + b];
                let balance = count.min(sample - count);
                if best.is_none_or(|(_, bb)| balance > bb) {
                    best = Some((w * 64 + b, balance));
                }
            }
        }
        let Some((split, _)) = best else { return t };
        let slice = &mut self.items[start..end];
        let mut lo = 0;
        for k in 0..slice.len() {
            if !bit(rays.z(slice[k]), split) {
                slice.swap(lo, k);
                lo += 1;
            }
        }
        let left = self.node(rays, start, start + lo);
        let right = self.node(rays, start + lo, end);
        self.nodes[t].children = Some((left, right));
        t
    }
}
