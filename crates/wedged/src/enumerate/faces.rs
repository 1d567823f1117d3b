//! Placeholder while the method is written.
use super::{Info, RawRay, Settings};
use crate::problem::Problem;

pub(crate) fn run(_p: &Problem, _s: &Settings, _i: &mut Info) -> Vec<RawRay> {
    unimplemented!()
}
