//! Brute force over the `2^m` contact sets, the baseline the other methods are tested against.
//!
//! For each contact set `A`, the cone `S_A` (contact on `A`, separated elsewhere) is convex, so
//! its realised pattern is the set of entries that *some* solution makes positive: each
//! pressure on `A` and each gap off `A` is maximised on its own (with `sum r_n = 1`). No
//! max-min program, no search, no pruning: it shares with the other methods only the
//! formulation of one conic program.

use super::{describe, pattern_of, Found, PatternInfo, Undecided};
use crate::conic::program::{leaf_classes, Decision, Entry, Formulation, Goal, Norm, POSITIVE};
use crate::run::Control;

pub(super) fn run(form: &Formulation, info: &mut PatternInfo, control: &Control) -> Found {
    let m = form.m;
    let mut found = Found::default();
    for set in 1u64..(1u64 << m) {
        if control.must_stop(0) {
            break;
        }
        let contact: Vec<bool> = (0..m).map(|i| set >> i & 1 == 1).collect();
        let classes = leaf_classes(&contact);
        let entries = (0..m).map(|i| {
            if contact[i] {
                Entry::Press(i)
            } else {
                Entry::Gap(i)
            }
        });
        let mut support = Vec::new();
        let mut trivial = false;
        let mut unsure = None;
        for e in entries {
            match form.decide(&classes, Goal::MaxMin(&[e])) {
                Decision::No => {
                    if let Err(e) = form.confirm(&classes, Norm::Sum) {
                        form.doubt(format!(
                            "the trivial contact set [{}]: {e}",
                            describe(&classes)
                        ));
                    }
                    trivial = true;
                    break;
                }
                Decision::Unsure(why) => {
                    unsure = Some(why);
                    break;
                }
                Decision::Yes { value, .. } if value > POSITIVE => support.push(e),
                Decision::Yes { value, .. } => {
                    if let Err(why) = form.confirm_entry(&classes, e) {
                        form.doubt(format!(
                            "{} not positive in [{}] (reached {value:e}): {why}",
                            e.name(),
                            describe(&classes)
                        ));
                    }
                }
            }
        }
        if let Some(reason) = unsure {
            found.undecided.push(Undecided { contact, reason });
            continue;
        }
        if trivial {
            continue;
        }
        info.candidates += 1;
        let q = pattern_of(m, &support);
        if q.contains(&crate::solution::ContactPattern::Contact) {
            found.patterns.push(q);
        }
    }
    found
}
