//! The 2D pattern method `pattern-search`: the contact-set search of the `search` ray method
//! ([`crate::rays::search::tree`]), without rays.
//!
//! The search's leaves are exactly the contact sets `J` that some solution presses exactly
//! (see the tree's docs); the relative interior of the cone of `J` (contact on `J`, separated
//! elsewhere) has the pattern: contact on `J`, separated where some solution opens the gap,
//! grazing where none does, which the leaf's support program ([`ContactLp::support`]) tells.
//! Every realised pattern is the pattern of the relative interior of its own cone, whose contact
//! set is a leaf, so the maximal realised patterns are among the leaves' patterns; the common
//! finishing step keeps the maximal ones and finds each one's witness with Clarabel.
//!
//! The work is the tree (measured in `info.nodes_visited`, `pruned_infeasible`, `leaves`) and
//! one support program per leaf: it follows the number of pieces, not of their extreme rays.

use std::sync::atomic::Ordering;

use rayon::prelude::*;

use super::{Found, PatternInfo, Undecided};
use crate::conic::contact_lp::{ContactLp, Entry2};
use crate::conic::program::{leaf_classes, Formulation};
use crate::rays::search::tree::search;
use crate::rays::Progress;
use crate::run::Control;
use crate::shard::Shard;
use crate::solution::ContactPattern;

pub(super) fn run(
    form: &Formulation,
    info: &mut PatternInfo,
    shard: Option<Shard>,
    progress: &dyn Fn(Progress),
    control: &Control,
) -> Found {
    let m = form.m;
    let lp = ContactLp::new(form);
    let tree = search(&lp, control, shard, progress);
    info.nodes_visited = tree.nodes;
    info.nodes_inherited = tree.inherited;
    info.pruned_infeasible = tree.pruned;
    info.leaves = tree.leaves.len() as u64;
    info.bound_tightenings = tree.tightened;
    let decided: Vec<Result<Option<Vec<ContactPattern>>, String>> = tree
        .leaves
        .par_iter()
        .map(|contact| {
            let classes = leaf_classes(contact);
            let support = lp.support(&classes)?;
            Ok(support.map(|s| {
                (0..m)
                    .map(|i| {
                        let pressed = s.positive.contains(&Entry2::Edge(2 * i))
                            || s.positive.contains(&Entry2::Edge(2 * i + 1));
                        if contact[i] && pressed {
                            ContactPattern::Contact
                        } else if s.positive.contains(&Entry2::Gap(i)) {
                            ContactPattern::Separated
                        } else {
                            ContactPattern::Grazing
                        }
                    })
                    .collect()
            }))
        })
        .collect();
    let mut found = Found {
        patterns: Vec::new(),
        undecided: Vec::new(),
        shard: tree.shard,
    };
    let counters = &lp.counters;
    info.lp_solves = counters.solves.load(Ordering::Relaxed);
    info.lp_pivots = counters.pivots.load(Ordering::Relaxed);
    info.lp_fallbacks = counters.fallbacks.load(Ordering::Relaxed);
    for (contact, d) in tree.leaves.iter().zip(decided) {
        match d {
            Ok(Some(p)) => found.patterns.push(p),
            // The leaf's cone is {0} after all (its program was decided the other way).
            Ok(None) => {}
            Err(reason) => found.undecided.push(Undecided {
                contact: contact.clone(),
                reason: format!("the support program of the contact set: {reason}"),
            }),
        }
    }
    found
}
