//! [`Formulation::support`]: which entries some solution of a cone makes positive.

use super::{Class, Decision, Entry, Formulation, Goal, Support, POSITIVE};

impl Formulation<'_> {
    /// The support of the cone of `classes`: the entries among `wanted` that some solution makes
    /// positive (then one solution makes them all positive at once), with a witness that does.
    /// `None` when the cone is trivial; `Err` when the solver could not decide.
    ///
    /// First all of `wanted` are pushed up together; the entries that stay at zero are then
    /// tried one at a time (an interior-point solver tends to the relative interior of the
    /// optimal set, so few are left for this second round).
    pub(crate) fn support(
        &self,
        classes: &[Class],
        wanted: &[Entry],
    ) -> Result<Option<Support>, String> {
        let (r, value) = match self.decide(classes, Goal::MaxMin(wanted)) {
            Decision::No => return Ok(None),
            Decision::Unsure(why) => return Err(why),
            Decision::Yes { r, value } => (r, value),
        };
        if value > POSITIVE {
            return Ok(Some(Support {
                entries: wanted.to_vec(),
                r,
                value,
            }));
        }
        let (mut found, rest): (Vec<Entry>, Vec<Entry>) = wanted
            .iter()
            .partition(|&&e| self.entry_of(&r, e) > POSITIVE);
        for e in rest {
            match self.decide(classes, Goal::MaxMin(&[e])) {
                Decision::No => return Ok(None),
                Decision::Unsure(why) => return Err(why),
                Decision::Yes { value, .. } if value > POSITIVE => found.push(e),
                Decision::Yes { .. } => {}
            }
        }
        if found.is_empty() {
            return Ok(Some(Support {
                entries: found,
                r,
                value: 0.0,
            }));
        }
        // Each entry of `found` reaches `POSITIVE` in some solution; the mean of those
        // solutions makes all of them at least `POSITIVE / found.len()` at once, so together
        // they may legitimately stay below `POSITIVE`. Half of it is what the witness check
        // asks of each entry (`patterns::check_witness`); below that the pattern is too close
        // to the method's resolution to be shown, and is left undecided.
        match self.decide(classes, Goal::MaxMin(&found)) {
            Decision::Yes { r, value } if value > POSITIVE * 0.5 => Ok(Some(Support {
                entries: found,
                r,
                value,
            })),
            Decision::Yes { value, .. } => Err(format!(
                "entries positive one at a time reached only {value:e} together"
            )),
            Decision::No => Ok(None),
            Decision::Unsure(why) => Err(why),
        }
    }
}
