//! # wedged
//!
//! Every wedged configuration of a linear elastic body in frictional contact with a rigid
//! obstacle ([`enumerate`] in 2D, [`enumerate_patterns`] in 2D and 3D), and the critical
//! friction coefficient below which none exists ([`critical()`]).
//!
//! The condensed wedged problem (WP), with `K` symmetric positive definite in local node frames
//! (normal first) and `mu > 0`:
//!
//! ```text
//! find u, r in R^{dm}:   K u = r,
//!                        u_n >= 0,  r_n >= 0,  u_n . r_n = 0,
//!                        ||r_t_i|| <= mu r_n_i    (i = 1..m)
//! ```
//!
//! In 2D the solution set `S` is the union of finitely many polyhedral cones `C_B`, each spanned by
//! complementary extreme rays of the cone `C` (WP without complementarity). [`enumerate`] lists
//! those rays and the maximal index sets `B`.
//!
//! ```
//! use wedged::{enumerate, Problem, Settings};
//! use nalgebra::DMatrix;
//! // One node: K_nn = 2, K_nt = 1, K_tt = 1. Wedging needs mu >= K_tt/|K_nt| = 1.
//! let k = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 1.0]);
//! let below = enumerate(&Problem::new(2, k.clone(), 0.9).unwrap(), &Settings::default()).unwrap();
//! assert!(below.rays.is_empty());
//! let above = enumerate(&Problem::new(2, k, 1.1).unwrap(), &Settings::default()).unwrap();
//! assert_eq!(above.rays.len(), 1);
//! // u = (0, u_t), r = (1, 1) u_t: |r_t| < mu r_n, the node sticks.
//! assert_eq!(above.rays[0].status[0].name(), "stick");
//! ```
//!
//! ```
//! use wedged::{critical, CriticalSettings, Problem};
//! use nalgebra::DMatrix;
//! // The same node: mu* = K_tt / |K_nt| = 1, bracketed with a witness at the upper end.
//! let k = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 1.0]);
//! let c = critical(&Problem::new(2, k, 1.1).unwrap(), &CriticalSettings::default()).unwrap();
//! let (lower, upper) = (c.lower.unwrap(), c.upper.unwrap());
//! // (`upper` is the ratio of a computed solution: exact up to round-off.)
//! assert!(lower < 1.0 && (upper - 1.0).abs() < 1e-12, "[{lower}, {upper}]");
//! ```
//!
//! The core does no file I/O and knows no file format; those live in the `wedged` binary.

pub mod cliques;
pub(crate) mod conic;
pub mod critical;
pub mod examples;
pub mod fe;
pub(crate) mod groups;
pub(crate) mod linalg;
pub mod patterns;
pub mod problem;
pub(crate) mod rational;
pub mod rays;
pub mod run;
pub mod shard;
pub mod solution;

/// The exact certificate of a 2D ray enumeration ([`rays::certify`]).
pub use rays::certify;
/// The exact 2D enumeration ([`rays::exact`]).
pub use rays::exact;
/// The check of every reported ray ([`rays::verify`]).
pub use rays::verify;

pub use critical::{
    critical, critical_with_control, Critical, CriticalInfo, CriticalMethod, CriticalProgress,
    CriticalSettings, CriticalStatus, CriticalWitness, PatternThreshold,
};
pub use patterns::{
    enumerate_patterns, enumerate_patterns_streaming, enumerate_patterns_with_control, Pattern,
    PatternCertificate, PatternInfo, PatternMethod, PatternSettings, PatternSink, Patterns,
};
pub use problem::{Problem, ProblemError};
pub use rays::{
    enumerate, enumerate_with_control, Enumeration, Info, Method, Progress, Settings, RAYS_MU_MAX,
};
#[doc(hidden)]
pub use run::Fault;
pub use run::{EnumerateError, Error, Limits, Outcome, Stop};
pub use shard::{Shard, ShardReport};
pub use solution::{Cone, ContactPattern, NodeStatus, Ray};

/// The README's Rust example, run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeDoctests;
