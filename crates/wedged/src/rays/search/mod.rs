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
//!    finds its extreme rays (a face whose every edge and gap is clearly positive on some ray
//!    found without the program needs no program: [`leaf_face`]). Every complementary extreme
//!    ray of `C` is an extreme ray of the face of the contact set it presses, so the union over
//!    the leaves is all of them.
//!
//! The rays go to the common finishing step (recomputed from their status, verified, cliques).
//! A program that neither the simplex method nor Clarabel decides does not prune. A leaf whose
//! support neither decides has its face described without it (every edge and gap possibly
//! positive; counted in `info.near_degenerate`); a face whose double description fails makes
//! the run incomplete ([`crate::Stop::Undecided`]).

mod face;
pub(crate) mod tree;

use std::collections::HashSet;
use std::sync::Mutex;

use rayon::prelude::*;

use super::params::{Info, Progress, Settings};
use super::verify::VerifyError;
use crate::conic::contact_lp::{ContactLp, LeafSupport};
use crate::conic::program::{leaf_classes, Class, Formulation};
use crate::problem::Problem;
use crate::run::{Control, Stop};
use crate::solution::{NodeStatus, Ray};

/// The least share of a ray's total pressure that every inequality of a face described before
/// its support ([`leaf_face`]) must reach on some ray of it: twenty times the support
/// program's resolution (an entry that no solution makes `1 / (2 SUPPORT_SCALE)` = 5e-8 of
/// its total pressure is a zero there) and a thousand times the double description's zero
/// tolerance.
const SURE_SHARE: f64 = 1e-6;

/// The extreme rays of the face of a leaf (`classes`: contact or separated at every node).
///
/// **First without the support program**: every friction edge and every opening gap taken as
/// possibly positive ([`LeafSupport::everything`]). When every one of them then reaches
/// [`SURE_SHARE`] of the total pressure on some ray of the face, the face is full-dimensional
/// (the sum of those rays makes every inequality positive), the support program would have
/// found every entry positive, and the double description it would have started is this one:
/// the same rays, without the program. (On the random m = 9 problems every leaf is of that
/// kind; the support programs were half of the faces' time, and the process went from 9 to 7
/// ms on seed 0, `farm-bench --vs`, paired 0.78.) Otherwise, as before:
///
/// **With the support program** ([`ContactLp::support`]): the entries that no solution makes
/// positive are equalities, and the face is described in its own dimension. A support that
/// neither solver settles (an ill-conditioned face) is taken as everything, and the double
/// description, which needs no full-dimensional cone, decides the zeros by its tolerance (as
/// pruned-dd does everywhere); counted as a close call.
fn leaf_face(lp: &ContactLp, classes: &[Class], tol: f64) -> Described {
    let form = lp.form();
    let (first, kept) = without_support(form, classes, tol);
    if kept {
        return first;
    }
    match lp.support(classes) {
        Ok(None) => Ok((Vec::new(), face::FaceStats::default())),
        Ok(Some(support)) => face::rays(form, classes, &support, tol),
        Err(_) => first.map(|(rays, stats)| {
            (
                rays,
                face::FaceStats {
                    close: true,
                    ..stats
                },
            )
        }),
    }
}

/// A face's rays and what describing it cost, or why it could not be described.
type Described = Result<(Vec<face::FaceRay>, face::FaceStats), String>;

/// A face's rays not found before in other faces, each with its status and its check
/// ([`run`]), and what describing the face cost, or why it could not be described.
type Checked = Result<
    (
        Vec<(Vec<NodeStatus>, Result<Ray, VerifyError>)>,
        face::FaceStats,
    ),
    String,
>;

/// [`leaf_face`]'s first step: the face described with every edge and gap taken as possibly
/// positive, and whether it is kept (each of them reaches [`SURE_SHARE`] on some ray).
fn without_support(form: &Formulation, classes: &[Class], tol: f64) -> (Described, bool) {
    let first = face::rays(form, classes, &LeafSupport::everything(classes), tol);
    let kept = first
        .as_ref()
        .is_ok_and(|(_, stats)| stats.least_share >= SURE_SHARE);
    (first, kept)
}

/// The rays' check of the finishing step ([`super::enumerate_with_control`]): a ray in the
/// equilibrated units and its status to the verified ray in the problem's own units.
pub(crate) type Check<'a> = dyn Fn(&[f64], Vec<NodeStatus>) -> Result<Ray, VerifyError> + Sync + 'a;

/// A face's new rays are checked in parallel in runs of at least this many ([`run`]). (Random
/// m = 9 seed 0, whole process, `perf stat -r 80`, alternated: 4.73 and 4.38 ms against 5.27
/// and 4.55 ms with each face's rays checked in turn; `farm-bench -n 100 --vs`, paired wall
/// medians 0.97 and 0.98 on seeds 0 and 1.)
const CHECKED_TOGETHER: usize = 16;

/// Runs the method on `scaled`, the problem equilibrated ([`Problem::equilibrated`], the
/// finishing step's too); returns the rays found, each checked by `check` (one result per
/// status, in the order of the statuses), and, when some decision could not be made, that the
/// run is incomplete.
///
/// Each face's new rays are checked as the face is described, on the thread that found it
/// (a face's many rays in parallel, [`CHECKED_TOGETHER`] or more to a task, so that the other
/// thread helps with a large last face): the check shares the tree's parallel walk instead of
/// waiting for its end. (As a phase of its own, after the walk, the check of the 439 rays of
/// the random m = 9 problem of seed 0 often ran on one thread only: the other had gone to
/// sleep at the end of the walk and woke late or not at all, 0.65 ms on two threads, 1.2 ms
/// when one slept.) A ray found in several faces is checked once, by the first face to claim
/// its status; the polished ray and every verdict but the agreement with the raw ray depend
/// on the status only, and the raw rays of one status from different faces agree to
/// round-off.
pub(crate) fn run(
    scaled: &Problem,
    settings: &Settings,
    info: &mut Info,
    progress: &dyn Fn(Progress),
    control: &Control,
    check: &Check,
) -> (Vec<Result<Ray, VerifyError>>, Option<Stop>) {
    let form = Formulation::new(scaled);
    let lp = ContactLp::new(&form);
    // Each leaf's face is described as the leaf is found, on the thread that found it, so that
    // the faces share the tree's parallel walk instead of waiting for its end, and so is the
    // check of its rays. Once the run must stop (a limit, Ctrl-C), the faces not yet begun are
    // skipped: the run is then incomplete, with the rays of the faces finished (as `faces`
    // reports them).
    let tol = settings.zero_tol;
    let described: Mutex<Vec<(Vec<bool>, Checked)>> = Mutex::new(Vec::new());
    let claimed: Mutex<HashSet<Vec<NodeStatus>>> = Mutex::new(HashSet::new());
    let on_leaf = |contact: Vec<bool>| {
        let face = if control.must_stop(0) {
            Ok((Vec::new(), face::FaceStats::default()))
        } else {
            leaf_face(&lp, &leaf_classes(&contact), tol)
        };
        let face = face.map(|(found, stats)| {
            let new: Vec<face::FaceRay> = {
                let mut claimed = claimed.lock().expect("no panics while held");
                found
                    .into_iter()
                    .filter(|ray| {
                        !claimed.contains(&ray.status) && claimed.insert(ray.status.clone())
                    })
                    .collect()
            };
            // Once the run must stop, the rays not yet checked are left out (as the finishing
            // step leaves them): a large face's checks do not hold up a limit or Ctrl-C.
            let rays = new
                .into_par_iter()
                .with_min_len(CHECKED_TOGETHER)
                .filter(|_| !control.must_stop(0))
                .map(|ray| {
                    let status = ray.status.clone();
                    (status, check(&ray.r, ray.status))
                })
                .collect();
            (rays, stats)
        });
        described
            .lock()
            .expect("no panics while held")
            .push((contact, face));
    };
    let tree = tree::search(&lp, control, None, progress, &on_leaf);
    info.search_nodes = tree.nodes;
    info.search_inherited = tree.inherited;
    info.search_pruned = tree.pruned;
    info.search_leaves = tree.found;
    info.search_undecided = tree.undecided;
    info.search_tightenings = tree.tightened;
    let mut undecided = false;
    // In the order of their contact sets, whatever the threads did.
    let mut described = described.into_inner().expect("no panics while held");
    described.sort_by(|a, b| a.0.cmp(&b.0));
    let faces = described.into_iter().map(|(_, face)| face);
    let mut rays = Vec::new();
    for face in faces {
        match face {
            Ok((found, stats)) => {
                info.peak_rays = info.peak_rays.max(stats.peak);
                info.largest_face = info.largest_face.max(stats.dim);
                info.near_degenerate += u64::from(stats.close);
                rays.extend(found);
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
    // In the order of the statuses, whichever face claimed each: a failure reported is the
    // first in that order.
    rays.sort_by(|a, b| a.0.cmp(&b.0));
    let rays = rays.into_iter().map(|(_, checked)| checked).collect();
    (rays, undecided.then_some(Stop::Undecided))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::{banded_spd_problem, demo, plug2d_tri, random_spd_problem};
    use crate::run::Limits;
    use std::collections::BTreeSet;

    /// The search checks each status once, whichever faces share it, and hands the checks back
    /// in the order of the statuses: over 40 random problems (m = 4 to 9, many with several
    /// faces), every status the check saw is distinct, the results are its calls in status
    /// order, and the statuses are those of pruned double description, run independently. A
    /// check that fails on some rays makes those results failures in place (the finishing step
    /// then reports the first).
    #[test]
    fn each_status_is_checked_once_and_returned_in_order() {
        use crate::rays::verify::polish_and_verify;
        let mut shared = 0;
        for seed in 0..40u64 {
            let m = 4 + (seed % 6) as usize;
            let p = random_spd_problem(m, 1.0 + (seed % 3) as f64 * 0.5, 2_000 + seed);
            let (scaled, _) = p.equilibrated();
            let seen: Mutex<Vec<Vec<NodeStatus>>> = Mutex::new(Vec::new());
            // Fails on every third call's ray, so that failures come back in place.
            let check = |r: &[f64], status: Vec<NodeStatus>| {
                let mut seen = seen.lock().unwrap();
                seen.push(status.clone());
                let fail = seen.len() % 3 == 0;
                drop(seen);
                let ray = polish_and_verify(&scaled, r, status.clone(), 1e-9)?;
                if fail {
                    return Err(VerifyError::Mismatch {
                        status: format!("{status:?}"),
                        difference: 1.0,
                    });
                }
                Ok(ray)
            };
            let cancel = std::sync::atomic::AtomicBool::new(false);
            let control = Control::new(Limits::default(), &cancel);
            let mut info = Info::default();
            let settings = Settings::default();
            let (checked, stop) = run(&scaled, &settings, &mut info, &|_| {}, &control, &check);
            assert!(stop.is_none());
            let mut seen = seen.into_inner().unwrap();
            let calls = seen.len();
            seen.sort();
            seen.dedup();
            assert_eq!(seen.len(), calls, "seed {seed}: a status checked twice");
            assert_eq!(checked.len(), calls, "seed {seed}");
            for (result, status) in checked.iter().zip(&seen) {
                match result {
                    Ok(ray) => assert_eq!(&ray.status, status, "seed {seed}"),
                    Err(VerifyError::Mismatch { status: s, .. }) => {
                        assert_eq!(s, &format!("{status:?}"), "seed {seed}")
                    }
                    Err(e) => panic!("seed {seed}: {e}"),
                }
            }
            let reference = crate::rays::enumerate(&p, &Settings::default()).unwrap();
            let expected: Vec<Vec<NodeStatus>> =
                reference.rays.iter().map(|r| r.status.clone()).collect();
            assert_eq!(seen, expected, "seed {seed}");
            shared += usize::from(info.search_leaves > 1);
        }
        assert!(shared > 20, "{shared} problems with more than one face");
    }

    /// A face described before its support ([`leaf_face`]'s first step) is only kept where the
    /// support program, asked independently, finds every entry positive, and then it is the
    /// face that program's support gives, ray for ray and bit for bit. Over the leaves of 120
    /// random problems (m = 3 to 9), 30 banded ones (each node coupled to none, one or two of
    /// its neighbours), the demo and the plug at m = 12 and 16, both kinds occur:
    /// faces kept from the first step and faces that needed their support.
    #[test]
    fn a_face_kept_without_its_support_is_the_face_of_its_support() {
        let mut problems: Vec<Problem> = (0..120u64)
            .map(|seed| {
                let mu = 0.5 + (seed % 5) as f64 * 0.5;
                random_spd_problem(3 + (seed % 7) as usize, mu, 900 + seed)
            })
            .collect();
        // Decoupled and weakly coupled nodes: faces with a gap that never opens.
        for seed in 0..30u64 {
            let m = 3 + (seed % 4) as usize;
            problems.push(banded_spd_problem(m, (seed % 3) as usize, 1.5, 950 + seed));
        }
        problems.push(demo());
        for n in [6, 8] {
            problems.push(plug2d_tri(n).unwrap().problem(2.0).unwrap());
        }
        let (mut kept, mut needed) = (0, 0);
        for p in &problems {
            let scaled = p.equilibrated().0;
            let form = Formulation::new(&scaled);
            let lp = ContactLp::new(&form);
            let cancel = std::sync::atomic::AtomicBool::new(false);
            let control = Control::new(Limits::default(), &cancel);
            let tol = Settings::default().zero_tol;
            let leaves = Mutex::new(Vec::new());
            let keep = |leaf: Vec<bool>| leaves.lock().unwrap().push(leaf);
            tree::search(&lp, &control, None, &|_| {}, &keep);
            for contact in &leaves.into_inner().unwrap() {
                let classes = leaf_classes(contact);
                let (first, kept_here) = without_support(&form, &classes, tol);
                if !kept_here {
                    needed += 1;
                    continue;
                }
                kept += 1;
                let support = lp.support(&classes).unwrap().unwrap();
                let set = |s: &LeafSupport| -> BTreeSet<String> {
                    s.positive.iter().map(|e| format!("{e:?}")).collect()
                };
                let every = LeafSupport::everything(&classes);
                assert_eq!(set(&support), set(&every), "leaf {contact:?}");
                let (a, _) = first.unwrap();
                let (b, _) = face::rays(&form, &classes, &support, tol).unwrap();
                assert_eq!(a.len(), b.len());
                for (x, y) in a.iter().zip(&b) {
                    assert_eq!(x.status, y.status);
                    assert_eq!(x.r, y.r);
                }
            }
        }
        assert!(kept > 500 && needed > 0, "kept {kept}, needed {needed}");
    }
}
