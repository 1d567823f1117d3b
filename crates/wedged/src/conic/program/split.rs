//! What the searches over a [`Formulation`] answer to the shard walker (`crate::shard::Tree`):
//! the key under which a split may be kept, and the alarms that forbid keeping it.

use super::Formulation;

impl Formulation<'_> {
    /// The key of a split of the tree tagged `tree` over this formulation: the problem, `mu`
    /// and the tree's own `extra` settings decide every node. `None` when the decisions are
    /// recorded as they are made (`--certify`: a reused split would skip them).
    pub(crate) fn split_key(&self, tree: u64, extra: &[u64]) -> Option<u64> {
        if self.refutations.is_some() || self.checker.is_some() {
            return None;
        }
        let mut parts = vec![tree, self.problem.fingerprint(), self.mu.to_bits()];
        parts.extend_from_slice(extra);
        Some(crate::problem::digest(&parts))
    }

    /// What a search must report and a reused split would not: its `undecided` programs, the
    /// formulation's doubts, and a stop.
    pub(crate) fn alarms(&self, undecided: u64, stopped: bool) -> u64 {
        let doubts = self.doubts.lock().map_or(1, |d| d.len() as u64);
        undecided + doubts + u64::from(stopped)
    }
}
