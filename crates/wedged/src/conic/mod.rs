//! Conic programming: the only place that knows a solver.
//!
//! - [`socp`]: the adapter around Clarabel (second-order cone programs; every answer checked).
//! - [`simplex`]: the in-house warm-started dense simplex method (linear programs; every answer
//!   checked the same way).
//! - [`contact_lp`]: the 2D programs of the contact-set search (`rays/search`) for the simplex
//!   method, one matrix for the whole search, warm-started from the parent's basis.
//! - [`program`]: the wedged problem with a class per node as a conic program (the
//!   formulations every search decides), and the refutations it keeps.
//! - [`refutation`]: a refutation checked exactly in rational arithmetic.

pub(crate) mod contact_lp;
pub(crate) mod program;
pub(crate) mod refutation;
pub(crate) mod simplex;
pub(crate) mod socp;
