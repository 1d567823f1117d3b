//! Conic programming: the only place that knows a solver.
//!
//! - [`socp`]: the adapter around Clarabel (second-order cone programs; every answer checked).
//! - [`simplex`]: the in-house warm-started dense simplex method (linear programs; every answer
//!   checked the same way).
//! - [`node_lp`]: the 2D program of a search node over contact sets (the enumeration's search,
//!   `rays/search`, and `critical`'s branch and bound) for the simplex method, one matrix per
//!   friction level and set of cuts, warm-started from the parent's basis.
//! - [`cuts`]: drive cuts for those programs, from bounds on each undecided node's drive
//!   (bound tightening).
//! - [`contact_lp`]: the support of a leaf's cone (which entries some solution makes positive),
//!   one program for the simplex method.
//! - [`program`]: the wedged problem with a class per node as a conic program (the
//!   formulations every search decides), and the refutations it keeps.
//! - [`refutation`]: a refutation checked exactly in rational arithmetic.

pub(crate) mod contact_lp;
pub(crate) mod cuts;
pub(crate) mod node_lp;
pub(crate) mod program;
pub(crate) mod refutation;
pub(crate) mod simplex;
pub(crate) mod socp;
