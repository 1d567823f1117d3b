//! Placeholder: a spring-lattice plug in a V-notch (being written).
use crate::problem::Problem;

/// Placeholder.
pub fn lattice_plug(_contact_per_side: usize, _mu: f64) -> Problem {
    unimplemented!()
}
