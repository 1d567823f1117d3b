//! The polyhedral approximation (MISSION section 5, first method): the 2D algorithm, run with the
//! friction cone replaced by the circumscribed pyramid with `k` faces (`crate::rays::dd`
//! with [`Friction::pyramid`]). The pyramid contains the cone, so every realised pattern is
//! realised in the approximation too, and lies below one of its maximal patterns (the
//! *candidates*). Each candidate `c` is then checked exactly: the support of the true cone
//! `F_c` is the largest truly realised pattern below `c`, and every maximal realised pattern is
//! the support of some candidate's cone. In 2D the friction law is already polyhedral and the
//! candidates are the exact cones.

use super::{classes_of, pattern_of, positives, Found, PatternInfo, Undecided};
use crate::conic::program::Formulation;
use crate::problem::Problem;
use crate::rays::dd;
use crate::rays::dd::{Friction, Variant};
use crate::rays::{Info, Progress, Settings};
use crate::run::Control;
use crate::solution::{piece_patterns, ContactPattern};

/// The maximal patterns of the approximation, and the number of its complementary rays.
pub(super) fn candidates(
    problem: &Problem,
    faces: usize,
    zero_tol: f64,
    progress: &dyn Fn(Progress),
    control: &Control,
) -> (Vec<Vec<ContactPattern>>, usize) {
    let friction = if problem.dim() == 2 {
        Friction::planar(problem.mu())
    } else {
        Friction::pyramid(problem.mu(), faces)
    };
    let settings = Settings {
        zero_tol,
        ..Settings::default()
    };
    let mut dd_info = Info::default();
    let rays = dd::run(
        problem,
        &friction,
        &settings,
        &mut dd_info,
        Variant::Pruned,
        progress,
        control,
    );
    let statuses: Vec<_> = rays.into_iter().map(|r| r.status).collect();
    (piece_patterns(&statuses), statuses.len())
}

pub(super) fn run(
    form: &Formulation,
    faces: usize,
    zero_tol: f64,
    info: &mut PatternInfo,
    progress: &dyn Fn(Progress),
    control: &Control,
) -> Found {
    let (candidates, rays) = candidates(form.problem, faces, zero_tol, progress, control);
    let mut found = Found::default();
    if control.stopped().is_some() {
        return found;
    }
    info.pyramid_rays = rays as u64;
    for candidate in candidates {
        info.candidates += 1;
        let classes = classes_of(&candidate);
        match form.support(&classes, &positives(&candidate)) {
            Ok(None) => info.spurious += 1,
            Ok(Some(support)) => {
                let q = pattern_of(form.m, &support.entries);
                if q != candidate {
                    info.spurious += 1;
                }
                if q.contains(&ContactPattern::Contact) {
                    found.patterns.push(q);
                }
            }
            Err(reason) => found.undecided.push(Undecided {
                contact: super::contact_set(&candidate),
                reason,
            }),
        }
    }
    found
}
