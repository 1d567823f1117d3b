//! The output-sensitive 2D method ([`super::Method::Search`]): a depth-first search over contact
//! sets decided by a warm-started simplex method, then the extreme rays of each leaf's face by
//! double description in the face's own dimension.
//!
//! 1. The problem is equilibrated ([`Problem::equilibrated`]: node scales by powers of two), so
//!    that the programs are well scaled whatever the units of each node.
//! 2. [`tree`]: the search; its leaves are the contact sets `J` pressed exactly by some
//!    solution. Its size is reported (`info.search_nodes`, `info.search_leaves`).
//! 3. [`face`]: for each leaf, the support program tells which friction edges and gaps can be
//!    positive; the face lives in the null space of the rest, where a plain double description
//!    finds its extreme rays. Every complementary extreme ray of `C` is an extreme ray of the face
//!    of the contact set it presses, so the union over the leaves is all of them.
//!
//! The rays go to the common finishing step (recomputed from their status, verified, cliques).
//! A program that neither the simplex method nor Clarabel decides does not prune. A leaf whose
//! support neither decides has its face described without it (every edge and gap possibly
//! positive; counted in `info.near_degenerate`); a face whose double description fails makes
//! the run incomplete ([`crate::Stop::Undecided`]).

mod face;
pub(crate) mod tree;

use std::collections::HashSet;

use rayon::prelude::*;

use super::params::{Info, Progress, RawRay, Settings};
use crate::conic::contact_lp::{ContactLp, LeafSupport};
use crate::conic::program::{leaf_classes, Formulation};
use crate::problem::Problem;
use crate::run::{Control, Stop};
use crate::solution::NodeStatus;

/// Runs the method; returns the rays found and, when some decision could not be made, that
/// the run is incomplete.
pub(crate) fn run(
    problem: &Problem,
    settings: &Settings,
    info: &mut Info,
    progress: &dyn Fn(Progress),
    control: &Control,
) -> (Vec<RawRay>, Option<Stop>) {
    let (scaled, scales) = problem.equilibrated();
    let form = Formulation::new(&scaled);
    let lp = ContactLp::new(&form);
    let tree = tree::search(&lp, control, None, progress, None);
    info.search_nodes = tree.nodes;
    info.search_inherited = tree.inherited;
    info.search_pruned = tree.pruned;
    info.search_leaves = tree.leaves.len() as u64;
    info.search_undecided = tree.undecided;
    info.search_tightenings = tree.tightened;
    let mut undecided = false;
    // The faces of the leaves, in parallel; once the run must stop (a limit, Ctrl-C), the
    // faces not yet begun are skipped: the run is then incomplete, with the rays of the faces
    // finished (as `faces` reports them).
    let tol = settings.zero_tol;
    let faces: Vec<Result<(Vec<face::FaceRay>, face::FaceStats), String>> =
        tree.leaves
            .par_iter()
            .map(|contact| {
                if control.must_stop(0) {
                    return Ok((Vec::new(), face::FaceStats::default()));
                }
                let classes = leaf_classes(contact);
                match lp.support(&classes) {
                    Ok(None) => Ok((Vec::new(), face::FaceStats::default())),
                    Ok(Some(support)) => face::rays(&form, &classes, &support, tol),
                    // Neither solver settles the support (an ill-conditioned face): every edge and
                    // gap is taken as possibly positive, and the double description, which needs
                    // no full-dimensional cone, decides the zeros by its tolerance (as pruned-dd
                    // does everywhere). Counted as a close call.
                    Err(_) => face::rays(&form, &classes, &LeafSupport::everything(&classes), tol)
                        .map(|(rays, stats)| {
                            (
                                rays,
                                face::FaceStats {
                                    close: true,
                                    ..stats
                                },
                            )
                        }),
                }
            })
            .collect();
    let mut seen: HashSet<Vec<NodeStatus>> = HashSet::new();
    let mut rays = Vec::new();
    for face in faces {
        match face {
            Ok((found, stats)) => {
                info.peak_rays = info.peak_rays.max(stats.peak);
                info.largest_face = info.largest_face.max(stats.dim);
                info.near_degenerate += u64::from(stats.close);
                for ray in found {
                    if seen.insert(ray.status.clone()) {
                        // Back to the problem's own units (the status is unchanged).
                        let r: Vec<f64> = ray
                            .r
                            .iter()
                            .enumerate()
                            .map(|(a, x)| x / scales[a / 2])
                            .collect();
                        rays.push(RawRay {
                            r,
                            status: ray.status,
                        });
                    }
                }
            }
            Err(why) => {
                info.search_undecided_faces.push(why);
                undecided = true;
            }
        }
    }
    info.lp_solves = lp
        .counters
        .solves
        .load(std::sync::atomic::Ordering::Relaxed);
    info.lp_pivots = lp
        .counters
        .pivots
        .load(std::sync::atomic::Ordering::Relaxed);
    info.lp_fallbacks = lp
        .counters
        .fallbacks
        .load(std::sync::atomic::Ordering::Relaxed);
    (rays, undecided.then_some(Stop::Undecided))
}
