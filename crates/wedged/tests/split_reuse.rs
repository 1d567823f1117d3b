//! One split per process (issue 24): a process that runs several shards of the same search
//! (the 2D contact-set search, `bnb` in 2D and 3D) one after the other walks the top of the
//! tree once, and a shard that starts from the kept split finds exactly what it finds when it
//! walks the top itself. A split of another tree (another `mu`, another number of shards,
//! another method) or of a certified run is not reused.
//!
//! The kept split is the process's, so this file holds one test: run alone in its process,
//! nothing else replaces the split between its steps.

use wedged::patterns::{
    enumerate_patterns, merge_shards, PatternMethod, PatternSettings, Patterns,
};
use wedged::{Problem, Shard};

fn shard(problem: &Problem, i: usize, n: usize, certify: bool) -> Patterns {
    shard_of(problem, PatternMethod::Search, i, n, certify)
}

fn shard_of(
    problem: &Problem,
    method: PatternMethod,
    i: usize,
    n: usize,
    certify: bool,
) -> Patterns {
    enumerate_patterns(
        problem,
        &PatternSettings {
            method,
            shard: Some(Shard::new(i, n).unwrap()),
            certify,
            ..PatternSettings::default()
        },
    )
    .unwrap()
}

fn split_nodes(p: &Patterns) -> u64 {
    p.shard.expect("a shard's report").split_nodes
}

fn same(a: &Patterns, b: &Patterns, what: &str) {
    assert_eq!(a.outcome, b.outcome, "{what}");
    assert_eq!(a.patterns, b.patterns, "{what}");
    assert_eq!(a.undecided, b.undecided, "{what}");
    let (x, y) = (a.shard.unwrap(), b.shard.unwrap());
    assert_eq!(
        (x.split_depth, x.units, x.own_units),
        (y.split_depth, y.units, y.own_units),
        "{what}"
    );
}

#[test]
fn a_process_walks_the_top_once_per_tree() {
    let plug = wedged::examples::plug2d_tri(13).unwrap();
    let p = plug.problem(2.0).unwrap();
    let n = 4;

    // Shard 2 walking the top itself, then every shard in turn: only the first walks it.
    let cold = shard(&p, 2, n, false);
    assert!(split_nodes(&cold) > 0);
    let parts: Vec<Patterns> = (1..=n).map(|i| shard(&p, i, n, false)).collect();
    for part in &parts {
        assert_eq!(split_nodes(part), 0, "the split of shard 2 is reused");
    }
    same(&parts[1], &cold, "shard 2 from the kept split");
    let whole = enumerate_patterns(
        &p,
        &PatternSettings {
            method: PatternMethod::Search,
            ..PatternSettings::default()
        },
    )
    .unwrap();
    let merged = merge_shards(parts).unwrap();
    assert_eq!(merged.patterns, whole.patterns);
    assert!(whole.patterns.len() >= 5, "{}", whole.patterns.len());

    // Another number of shards, another mu: another tree, walked again.
    assert!(split_nodes(&shard(&p, 1, n + 1, false)) > 0);
    let other = plug.problem(2.5).unwrap();
    assert!(split_nodes(&shard(&other, 1, n, false)) > 0);
    assert_eq!(split_nodes(&shard(&other, 3, n, false)), 0);
    // The first tree again: its split was replaced, so it is walked again, and found the same.
    let again = shard(&p, 2, n, false);
    assert!(split_nodes(&again) > 0);
    same(&again, &cold, "shard 2 walked again");

    // A certified run records its refutations as it makes them: never from a kept split. (Its
    // tree has no drive cuts, so its units need not be the uncertified run's: its shards
    // together find the whole.)
    let certified: Vec<Patterns> = (1..=n).map(|i| shard(&p, i, n, true)).collect();
    assert!(certified.iter().all(|part| split_nodes(part) > 0));
    assert_eq!(merge_shards(certified).unwrap().patterns, whole.patterns);

    // bnb, 2D and 3D: the same, and the 2D search's split is not bnb's.
    let two = wedged::examples::random_spd_problem(8, 1.5, 2404);
    let three = wedged::examples::random_spd_problem_dim(3, 5, 2.0, 2503);
    for (problem, what) in [(&two, "2D"), (&three, "3D")] {
        let bnb = |i: usize| shard_of(problem, PatternMethod::Bnb, i, 3, false);
        let cold = bnb(2);
        assert!(split_nodes(&cold) > 0, "{what}");
        let parts: Vec<Patterns> = (1..=3).map(bnb).collect();
        for part in &parts {
            assert_eq!(split_nodes(part), 0, "{what}: bnb's split is reused");
        }
        same(
            &parts[1],
            &cold,
            &format!("{what}: bnb shard 2 from the kept split"),
        );
        let whole = enumerate_patterns(
            problem,
            &PatternSettings {
                method: PatternMethod::Bnb,
                ..PatternSettings::default()
            },
        )
        .unwrap();
        assert_eq!(
            merge_shards(parts).unwrap().patterns,
            whole.patterns,
            "{what}"
        );
    }
    assert!(
        split_nodes(&shard(&p, 1, 3, false)) > 0,
        "another method, another tree"
    );
}
