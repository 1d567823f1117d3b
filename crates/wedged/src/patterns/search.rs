//! The 2D pattern method `pattern-search`: the contact-set search of the `search` ray method
//! ([`crate::rays::search::tree`]), without rays.
//!
//! The search's leaves are exactly the contact sets `J` that some solution presses exactly
//! (see the tree's docs); the relative interior of the cone `S_J` of `J` (contact on `J`,
//! separated elsewhere) has the pattern: contact on `J`, separated where some solution opens
//! the gap, grazing where none does (the set `G`), which the leaf's support program
//! ([`ContactLp::support`]) tells. Every realised pattern is the pattern of the relative
//! interior of its own cone, whose contact set is a leaf, so the maximal realised patterns are
//! among the leaves' patterns.
//!
//! **Each leaf is tested for maximality as it is found**, so that its piece can be handed on
//! at once (`enumerate --jsonl` streams them; nothing needs to hold every pattern). A pattern
//! `p` above the leaf's `q` (`F_q ⊆ F_p`, `p != q`) keeps `q`'s contact and separated nodes and
//! differs on the grazing set `G`; it cannot merely open gaps of `G` (its contact set would be
//! `J`, and `q` already opens every gap that a solution pressing within `J` can open), so it
//! presses a node of `G`. Conversely a solution that presses `J` and a node of `G`, keeps
//! `r = 0` off `J ∪ G` and is complementary on `G` has a pattern above `q`. So the piece is
//! maximal exactly when the subtree of the search rooted at (`J` contact, `G` free, the rest
//! separated) has no leaf that presses a node of `G` ([`presses_a_free_node`]; nothing to
//! search when `G` is empty, as on a generic problem). The test is global: in a sharded run the
//! larger leaf may be another shard's, and each shard still hands on only maximal pieces.
//! (A first version asked whether one program with all of `G` shut, `S_{J ∪ G}`, presses a node
//! of `G`; it kept a piece below one whose pattern opens some gaps of `G` and presses others,
//! which the block problems of `tests/search.rs` caught.)
//!
//! The work is the tree (measured in `info.nodes_visited`, `pruned_infeasible`, `leaves`) and
//! one or two support programs per leaf: it follows the number of pieces, not of their extreme
//! rays.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use super::{Found, PatternInfo, Undecided};
use crate::conic::contact_lp::{ContactLp, Entry2, LeafSupport};
use crate::conic::program::{leaf_classes, Class, Formulation, Support, POSITIVE};
use crate::rays::search::tree::{presses_a_free_node, search};
use crate::rays::Progress;
use crate::run::Control;
use crate::shard::Shard;
use crate::solution::ContactPattern;

/// Whether some solution presses node `i` (one of its friction edges is in the support).
fn presses(s: &LeafSupport, i: usize) -> bool {
    s.positive.contains(&Entry2::Edge(2 * i)) || s.positive.contains(&Entry2::Edge(2 * i + 1))
}

/// The pattern of a leaf's piece, whether it is maximal and perhaps its witness ([`finish`]'s);
/// `None` when the leaf's cone is `{0}` after all (its program was decided the other way),
/// `Err` when a support program cannot be decided.
///
/// [`finish`]: super::finish
type Piece = Option<(Vec<ContactPattern>, bool, Option<Support>)>;

pub(super) fn leaf_piece(
    lp: &ContactLp,
    control: &Control,
    contact: &[bool],
) -> Result<Piece, String> {
    let m = contact.len();
    let classes = leaf_classes(contact);
    // First the witness's own program for the leaf's whole pattern (contact on the leaf's
    // set, every other gap open, every contact node sticking; [`ContactLp::max_min`], a
    // clamped body's): when it reaches `POSITIVE` the pattern has no grazing node, so it is
    // maximal, and its witness is found (random m = 9 problems: every leaf, 82 of 82).
    // Otherwise the support program says which entries can be positive.
    if lp.form().modes == 0 {
        let full = super::whole_pattern(contact);
        let all = super::witness_entries(&full);
        if let Ok(Some((r, value))) = lp.max_min(&classes, &all) {
            if value > POSITIVE {
                let witness = Support {
                    entries: all,
                    r,
                    value,
                };
                return Ok(Some((full, true, Some(witness))));
            }
        }
    }
    let Some(s) = lp.support(&classes)? else {
        return Ok(None);
    };
    let pattern: Vec<ContactPattern> = (0..m)
        .map(|i| {
            if contact[i] && presses(&s, i) {
                ContactPattern::Contact
            } else if s.positive.contains(&Entry2::Gap(i)) {
                ContactPattern::Separated
            } else {
                ContactPattern::Grazing
            }
        })
        .collect();
    let grazing: Vec<usize> = (0..m)
        .filter(|&i| pattern[i] == ContactPattern::Grazing)
        .collect();
    if grazing.is_empty() {
        return Ok(Some((pattern, true, None)));
    }
    // Some solution complementary on G that presses a node of G?
    let classes: Vec<Class> = pattern
        .iter()
        .map(|q| match q {
            ContactPattern::Contact => Class::Contact,
            ContactPattern::Separated => Class::Separated,
            ContactPattern::Grazing => Class::Free,
        })
        .collect();
    let above = presses_a_free_node(lp, control, &classes)
        .map_err(|why| format!("the maximality test: {why}"))?;
    Ok(Some((pattern, !above, None)))
}

/// Runs the search; each maximal pattern goes to `emit` as soon as its leaf is decided (from a
/// worker thread). The returned [`Found`] holds the undecided leaves only, and in a certified
/// run (refutations kept) every leaf's pattern, none emitted.
pub(super) fn run(
    form: &Formulation,
    info: &mut PatternInfo,
    shard: Option<Shard>,
    progress: &dyn Fn(Progress),
    control: &Control,
    emit: &(dyn Fn(Vec<ContactPattern>, Option<Support>) + Sync),
) -> Found {
    let lp = ContactLp::new(form);
    let undecided = Mutex::new(Vec::new());
    let realised = AtomicU64::new(0);
    let certified = form.refutations.is_some();
    let leaves = Mutex::new(Vec::new());
    let undecided_leaf = |contact: Vec<bool>, reason: String| {
        undecided
            .lock()
            .expect("no panics while held")
            .push(Undecided {
                contact,
                reason: format!("the support program of the contact set: {reason}"),
            })
    };
    let on_leaf = |contact: Vec<bool>| match leaf_piece(&lp, control, &contact) {
        Ok(Some((p, maximal, witness))) => {
            realised.fetch_add(1, Ordering::Relaxed);
            if maximal {
                emit(p, witness)
            }
        }
        Ok(None) => {}
        Err(reason) => undecided_leaf(contact, reason),
    };
    // A certified run takes each leaf's pattern from the cone program, whose zero entries are
    // backed by refutations (`super::leaf_pattern`, as `bnb`'s leaves), and keeps every leaf's
    // pattern: the maximal ones are then found by comparison, not by the maximality search.
    let on_certified_leaf = |contact: Vec<bool>| match super::leaf_pattern(form, &contact) {
        Ok(Some(leaf)) => {
            realised.fetch_add(1, Ordering::Relaxed);
            leaves
                .lock()
                .expect("no panics while held")
                .push(leaf.pattern);
        }
        Ok(None) => {}
        Err(reason) => undecided_leaf(contact, reason),
    };
    let on_leaf: &(dyn Fn(Vec<bool>) + Sync) = if certified {
        &on_certified_leaf
    } else {
        &on_leaf
    };
    let tree = search(&lp, control, shard, progress, on_leaf);
    info.nodes_visited = tree.nodes;
    info.nodes_inherited = tree.inherited;
    info.pruned_infeasible = tree.pruned;
    info.leaves = tree.found;
    info.bound_tightenings = tree.tightened;
    info.realised = realised.into_inner();
    let counters = &lp.counters;
    info.lp_solves = counters.solves.load(Ordering::Relaxed);
    info.lp_pivots = counters.pivots.load(Ordering::Relaxed);
    info.lp_fallbacks = counters.fallbacks.load(Ordering::Relaxed);
    let mut undecided = undecided.into_inner().unwrap_or_default();
    undecided.sort_by(|a, b| a.contact.cmp(&b.contact));
    Found {
        patterns: leaves.into_inner().unwrap_or_default(),
        undecided,
        shard: tree.shard,
        ..Found::default()
    }
}
