use super::*;
use crate::conic::program::Formulation;
use crate::examples::{plug2d_tri, random_spd_problem};
use crate::problem::Problem;
use crate::run::Limits;
use std::sync::Mutex;

/// The leaves (contact sets pressed exactly) of the whole search of `p` with the depths given,
/// sorted, and the nodes it visited.
fn leaves(p: &Problem, depths: Depths) -> (Vec<Vec<bool>>, u64) {
    let scaled = p.equilibrated().0;
    let form = Formulation::new(&scaled);
    let lp = ContactLp::new(&form);
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let control = Control::new(Limits::default(), &cancel);
    let found = Mutex::new(Vec::new());
    let keep = |leaf: Vec<bool>| found.lock().unwrap().push(leaf);
    let search = Search::with_depths(&lp, &control, &keep, vec![Class::Free; form.m], depths);
    let explored = Explored::new();
    Walk::new(&search, &explored).run(None);
    let tree = search.finish();
    assert_eq!(tree.undecided, 0);
    let mut found = found.into_inner().unwrap();
    found.sort();
    (found, tree.nodes)
}

/// Settling deeper in the tree loses no leaf: the plain search (no cuts at all, complete by its
/// prune alone) and searches that settle every node down to depth 2 or 6 find the same leaves
/// on the triangle plug at m = 26 and 40 and on 30 random problems (m = 6 to 9, `mu` 1 to 2,
/// small enough that they would not even tighten by default), and the deeper settling visits
/// fewer nodes on the plug (so it ran).
#[test]
fn settling_below_the_root_loses_no_leaf() {
    let mut problems: Vec<(String, Problem)> = [13, 20]
        .iter()
        .map(|&n| {
            let p = plug2d_tri(n).unwrap().problem(2.0).unwrap();
            (format!("plug m = {}", 2 * n), p)
        })
        .collect();
    for seed in 0..30u64 {
        let m = 6 + (seed % 4) as usize;
        let mu = 1.0 + (seed % 3) as f64 * 0.5;
        problems.push((
            format!("seed {seed}"),
            random_spd_problem(m, mu, 7_300 + seed),
        ));
    }
    let plain = Depths {
        tighten: 0,
        settle: 0,
    };
    for (name, p) in &problems {
        let (reference, plain_nodes) = leaves(p, plain);
        assert!(!reference.is_empty() || !name.starts_with("plug"), "{name}");
        for deep in [2, 6] {
            let depths = Depths {
                tighten: deep,
                settle: deep,
            };
            let (found, nodes) = leaves(p, depths);
            assert_eq!(found, reference, "{name}, settled to depth {deep}");
            if name.starts_with("plug") {
                assert!(nodes < plain_nodes, "{name}: {nodes} against {plain_nodes}");
            }
        }
    }
}

/// The whole search settles from [`SETTLE_FROM`] nodes on, deeper as the problem grows, never
/// below the tightening depth; a subtree's search (the maximality test) settles nowhere.
#[test]
fn the_settling_depth_grows_with_the_problem() {
    assert_eq!(settle_depth(39), 0);
    assert_eq!(settle_depth(40), 1);
    assert_eq!(settle_depth(79), 1);
    assert_eq!(settle_depth(80), 2);
    assert_eq!(settle_depth(100), 3);
    assert_eq!(settle_depth(119), 3);
    assert_eq!(settle_depth(160), 3);
    for m in 0..400 {
        assert!(settle_depth(m) <= tighten_depth(m), "m = {m}");
    }
    let p = plug2d_tri(20).unwrap().problem(2.0).unwrap();
    let scaled = p.equilibrated().0;
    let form = Formulation::new(&scaled);
    let lp = ContactLp::new(&form);
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let control = Control::new(Limits::default(), &cancel);
    let keep = |_: Vec<bool>| {};
    let whole = Search::new(&lp, &control, &keep, vec![Class::Free; form.m]);
    assert_eq!((whole.tighten_depth, whole.settle_depth), (3, 1));
    let mut root = vec![Class::Free; form.m];
    root[0] = Class::Separated;
    let part = Search::new(&lp, &control, &keep, root);
    assert_eq!((part.tighten_depth, part.settle_depth), (3, 0));
}
