//! The leaf of a search over contact sets (`bnb`, a certified `pattern-search`): its realised
//! pattern, from the cone programs.

use super::{pattern_of, simplex_witness, whole_pattern, witness_entries};
use crate::conic::program::{
    describe, leaf_classes, Decision, Entry, Formulation, Goal, Norm, Support, POSITIVE,
};
use crate::solution::ContactPattern;

/// A leaf's realised pattern ([`leaf_pattern`]).
pub(crate) struct Leaf {
    pub pattern: Vec<ContactPattern>,
    /// Its witness for the finishing step ([`super::finish`]), when the leaf's program made
    /// one.
    pub witness: Option<Support>,
}

/// The search over contact sets: the classes of a leaf whose contact set is `contact`, and its
/// realised pattern (contact set pressed, separated nodes' gaps opened where they can be), or
/// `None` when not every node of the contact set can be pressed.
pub(crate) fn leaf_pattern(form: &Formulation, contact: &[bool]) -> Result<Option<Leaf>, String> {
    let classes = leaf_classes(contact);
    // One support program: a node of the contact set that no solution presses is missing
    // from the support, and then the leaf has no pattern of its own.
    let mut wanted: Vec<Entry> = (0..form.m)
        .filter(|&i| contact[i])
        .map(Entry::Press)
        .collect();
    let presses = wanted.len();
    wanted.extend((0..form.m).filter(|&i| !contact[i]).map(Entry::Gap));
    // Where the finishing step's witness is a cone program too, the leaf asks that program
    // first: every contact node pressed and sticking, every other gap open. A leaf realised
    // that way (3D V-groove plug, m = 20: 592 of its 592 realised leaves) has its pattern and
    // its witness from one program instead of two; one whose optimum is below zero is the
    // trivial leaf (there: the other 264, one program instead of two); any other goes on to
    // the support program.
    let first = if simplex_witness(form) {
        None
    } else {
        let pattern = whole_pattern(contact);
        let all = witness_entries(&pattern);
        match form.decide(&classes, Goal::MaxMin(&all)) {
            Decision::Yes { r, value } if value > POSITIVE => {
                let entries = all;
                let witness = Some(Support { entries, r, value });
                return Ok(Some(Leaf { pattern, witness }));
            }
            // Below zero: no solution keeps every entry at zero or above, so the cone is
            // trivial (its entries are the gaps, pressures and friction slacks of the leaf).
            Decision::Yes { value, .. } if value < -POSITIVE => Some(None),
            Decision::Yes { .. } => None,
            Decision::No => Some(None),
            Decision::Unsure(why) => return Err(why),
        }
    };
    // In a certified run, every entry left out is confirmed zero by a certificate (or the
    // decision is doubted).
    let support = match first {
        Some(none) => none,
        None => form.support(&classes, &wanted)?,
    };
    let Some(support) = support else {
        if let Err(e) = form.confirm(&classes, Norm::Sum) {
            form.doubt(format!("the trivial leaf [{}]: {e}", describe(&classes)));
        }
        return Ok(None);
    };
    let missing: Vec<Entry> = wanted
        .iter()
        .copied()
        .filter(|e| !support.entries.contains(e))
        .collect();
    let pressed = presses
        - missing
            .iter()
            .filter(|e| matches!(e, Entry::Press(_)))
            .count();
    if pressed < presses {
        // No solution presses the whole contact set: shown at once, or by one node that no
        // solution presses.
        let nodes: Vec<usize> = (0..form.m).filter(|&i| contact[i]).collect();
        if let Err(e) = form.confirm(&classes, Norm::Pressed(&nodes)) {
            let one = missing
                .iter()
                .filter(|e| matches!(e, Entry::Press(_)))
                .any(|&p| form.confirm_entry(&classes, p).is_ok());
            if !one {
                form.doubt(format!(
                    "the leaf [{}], whose contact nodes are not all pressed: {e}",
                    describe(&classes)
                ));
            }
        }
        return Ok(None);
    }
    for &e in &missing {
        if let Err(why) = form.confirm_entry(&classes, e) {
            form.doubt(format!(
                "{} not positive at the leaf [{}]: {why}",
                e.name(),
                describe(&classes)
            ));
        }
    }
    let pattern = pattern_of(form.m, &support.entries);
    Ok(Some(Leaf {
        pattern,
        witness: None,
    }))
}
