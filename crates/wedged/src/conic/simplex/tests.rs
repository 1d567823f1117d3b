//! Tests of `simplex.rs`.

use super::*;
use crate::conic::socp;
use crate::conic::socp::{Affine, Program};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `lp`'s entries at random: each nonzero with probability `dense`, then uniform in
/// `(-size, size)`.
fn fill(lp: &mut Lp, rng: &mut ChaCha8Rng, dense: f64, size: f64) {
    for a in lp.a_mut() {
        *a = if rng.gen_bool(dense) {
            rng.gen_range(-size..size)
        } else {
            0.0
        };
    }
}

/// A random program shaped like the search's: `n` columns `>= 0` (some fixed at zero),
/// rows with bounds `[0, inf)`, `[0, 0]`, free or `[1, 1]` / `[1, inf)`, dense entries of
/// both signs, and a random cost.
fn random_lp(rng: &mut ChaCha8Rng) -> Lp {
    let n = rng.gen_range(2..10);
    let rows = rng.gen_range(1..10);
    let mut lp = Lp::new(n, rows);
    fill(&mut lp, rng, 0.8, 1.0);
    for j in 0..n {
        lp.lo[j] = 0.0;
        lp.hi[j] = match rng.gen_range(0..6) {
            0 => 0.0,
            1 => rng.gen_range(0.5..2.0),
            _ => f64::INFINITY,
        };
    }
    for k in 0..rows {
        let j = n + k;
        (lp.lo[j], lp.hi[j]) = match rng.gen_range(0..6) {
            0 | 1 => (0.0, f64::INFINITY),
            2 => (0.0, 0.0),
            3 => (f64::NEG_INFINITY, f64::INFINITY),
            4 => (1.0, 1.0),
            _ => (1.0, f64::INFINITY),
        };
    }
    // A normalisation keeps most programs bounded: the columns sum to one.
    if rng.gen_bool(0.8) {
        for k in 0..rows.min(1) {
            for j in 0..n {
                lp.a_mut()[k * n + j] = 1.0;
            }
            (lp.lo[n + k], lp.hi[n + k]) = (1.0, 1.0);
        }
    }
    for c in &mut lp.cost {
        *c = if rng.gen_bool(0.7) {
            rng.gen_range(-1.0..1.0)
        } else {
            0.0
        };
    }
    lp
}

/// The same program for Clarabel (columns, then row activities, as variables).
fn reference(lp: &Lp) -> socp::Answer {
    let total = lp.n + lp.rows;
    let mut p = Program::new(total);
    for k in 0..lp.rows {
        let mut terms: Vec<(usize, f64)> = (0..lp.n)
            .map(|j| (j, lp.row(k)[j]))
            .filter(|t| t.1 != 0.0)
            .collect();
        terms.push((lp.n + k, -1.0));
        p.zero(Affine::new(terms, 0.0));
    }
    for j in 0..total {
        if lp.lo[j] == lp.hi[j] {
            p.zero(Affine::new(vec![(j, 1.0)], -lp.lo[j]));
            continue;
        }
        if lp.lo[j].is_finite() {
            p.nonneg(Affine::new(vec![(j, 1.0)], -lp.lo[j]));
        }
        if lp.hi[j].is_finite() {
            p.nonneg(Affine::new(vec![(j, -1.0)], lp.hi[j]));
        }
    }
    let cost: Vec<(usize, f64)> = (0..total)
        .map(|j| (j, lp.cost[j]))
        .filter(|t| t.1 != 0.0)
        .collect();
    p.minimise(&cost);
    socp::solve(&p).0
}

/// Whether the simplex answer agrees with Clarabel's (when Clarabel decides).
fn agree(lp: &Lp, ours: &Answer, what: &str) -> bool {
    match (ours, reference(lp)) {
        (Answer::Optimal { value, .. }, socp::Answer::Optimal { value: v, .. }) => {
            assert!(
                (value - v).abs() <= 1e-6 * (1.0 + v.abs()),
                "{what}: value {value} against Clarabel's {v}"
            );
            true
        }
        (Answer::Infeasible { .. }, socp::Answer::Infeasible { .. }) => true,
        (_, socp::Answer::Uncertain { .. }) | (Answer::Failed(_), _) => false,
        (a, b) => panic!("{what}: {a:?} against Clarabel's {b:?}"),
    }
}

/// A warm solve of `lp` from `basis` and a cold one.
struct Warmed {
    answer: Answer,
    basis: Basis,
    /// Whether Clarabel decided, so that the warm answer was compared with it.
    compared: bool,
    warm_pivots: u64,
    cold_pivots: u64,
}

/// Solves `lp` from `basis` and cold: the warm answer agrees with Clarabel's (when Clarabel
/// decides) and with the cold one (the same optimal value, both infeasible, or both
/// unbounded).
fn warm_and_cold(lp: &Lp, basis: &Basis, what: &str) -> Warmed {
    let (answer, next, ws) = solve(lp, Some(basis));
    let (cold, _, cs) = solve(lp, None);
    let compared = agree(lp, &answer, what);
    match (&answer, &cold) {
        (Answer::Optimal { value: a, .. }, Answer::Optimal { value: b, .. }) => {
            assert!((a - b).abs() <= 1e-9 * (1.0 + b.abs()), "{what}: {a} {b}")
        }
        (Answer::Infeasible { .. }, Answer::Infeasible { .. }) => {}
        (Answer::Failed(a), Answer::Failed(b))
            if a.contains("unbounded") && b.contains("unbounded") => {}
        (a, b) => panic!("{what}: warm {a:?}, cold {b:?}"),
    }
    Warmed {
        answer,
        basis: next,
        compared,
        warm_pivots: ws.pivots,
        cold_pivots: cs.pivots,
    }
}

/// Cold solves of random programs agree with Clarabel; then each is changed the way the
/// search changes its programs (a bound, a row's bounds, the costs) and solved again from
/// the first basis, which agrees with Clarabel too and takes fewer pivots than a cold
/// solve on the whole.
#[test]
fn random_programs_cold_and_warm_agree_with_clarabel() {
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let (mut compared, mut optimal, mut infeasible, mut failed) = (0, 0, 0, 0);
    let (mut warm_pivots, mut cold_pivots) = (0, 0);
    for case in 0..400 {
        let lp = random_lp(&mut rng);
        let (answer, basis, _) = solve(&lp, None);
        if agree(&lp, &answer, &format!("case {case}")) {
            compared += 1;
        }
        match &answer {
            Answer::Optimal { .. } => optimal += 1,
            Answer::Infeasible { .. } => infeasible += 1,
            Answer::Failed(why) if why.contains("unbounded") => {}
            Answer::Failed(_) => failed += 1,
        }
        let mut next = lp.clone();
        match rng.gen_range(0..3) {
            0 => {
                let j = rng.gen_range(0..lp.n);
                (next.lo[j], next.hi[j]) = (0.0, 0.0);
            }
            1 => {
                let j = lp.n + rng.gen_range(0..lp.rows);
                (next.lo[j], next.hi[j]) = (0.0, 0.0);
            }
            _ => {
                for c in &mut next.cost {
                    *c = rng.gen_range(-1.0..1.0);
                }
            }
        }
        let warmed = warm_and_cold(&next, &basis, &format!("case {case}, warm"));
        compared += usize::from(warmed.compared);
        warm_pivots += warmed.warm_pivots;
        cold_pivots += warmed.cold_pivots;
    }
    assert_eq!(failed, 0);
    assert!(
        compared > 700 && optimal > 80 && infeasible > 80,
        "{compared} {optimal} {infeasible}"
    );
    assert!(warm_pivots < cold_pivots, "{warm_pivots} {cold_pivots}");
}

/// Feasibility programs (no costs at all, which the dual method perturbs, see the module
/// docs) agree with Clarabel, cold and warm-started from another program's basis, and none
/// fails; a feasible one's point is checked like any optimum.
#[test]
fn feasibility_programs_agree_with_clarabel() {
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    let (mut compared, mut feasible, mut infeasible) = (0, 0, 0);
    for case in 0..400 {
        let first = random_lp(&mut rng);
        let (_, basis, _) = solve(&first, None);
        let mut lp = first.clone();
        lp.cost.iter_mut().for_each(|c| *c = 0.0);
        if rng.gen_bool(0.5) {
            let j = rng.gen_range(0..lp.n);
            (lp.lo[j], lp.hi[j]) = (0.0, 0.0);
        }
        for (start, what) in [(None, "cold"), (Some(&basis), "warm")] {
            let (answer, _, _) = solve(&lp, start);
            if agree(&lp, &answer, &format!("case {case}, {what}")) {
                compared += 1;
            }
            match answer {
                Answer::Optimal { value, .. } => {
                    assert_eq!(value, 0.0, "case {case}: the perturbation left a cost");
                    feasible += 1;
                }
                Answer::Infeasible { .. } => infeasible += 1,
                Answer::Failed(why) => panic!("case {case}, {what}: {why}"),
            }
        }
    }
    assert!(
        compared > 700 && feasible > 150 && infeasible > 150,
        "{compared} {feasible} {infeasible}"
    );
}

/// A program whose only point is known, and an infeasible one whose certificate is the
/// obvious one.
#[test]
fn small_known_programs() {
    // x0 + x1 = 1, x0 - x1 >= 0.5, minimise x0: x = (0.75, 0.25).
    let mut lp = Lp::new(2, 2);
    lp.a_mut().copy_from_slice(&[1.0, 1.0, 1.0, -1.0]);
    (lp.lo, lp.hi) = (
        vec![0.0, 0.0, 1.0, 0.5],
        vec![f64::INFINITY, f64::INFINITY, 1.0, f64::INFINITY],
    );
    lp.cost = vec![1.0, 0.0, 0.0, 0.0];
    let (answer, basis, _) = solve(&lp, None);
    let Answer::Optimal { x, value } = answer else {
        panic!("{answer:?}")
    };
    assert!(
        (x[0] - 0.75).abs() < 1e-12 && (value - 0.75).abs() < 1e-12,
        "{x:?}"
    );
    // Then x0 - x1 >= 2 cannot hold with x1 >= 0 and x0 + x1 = 1.
    lp.lo[3] = 2.0;
    let (answer, _, _) = solve(&lp, Some(&basis));
    let Answer::Infeasible { y } = answer else {
        panic!("{answer:?}")
    };
    // y = (1, -1) up to scale and sign: (x0 + x1) - (x0 - x1) = 2 x1 >= 0, but 1 - 2 < 0.
    assert!((y[0] + y[1]).abs() < 1e-12 && y[0] != 0.0, "{y:?}");
}

/// An infeasibility certificate may drop a tiny term only against an infinite bound: one row
/// `s = a x >= 1` with `a = 1e-13`, certificate `y = -1` (so `c = (-a, 1)`). With `x`
/// unbounded the term `-a x` is dropped and the certificate passes (a feasible point would need
/// `x = 1e13`, beyond what the check admits); with `x <= 1e14` the term counts and it fails
/// (`x = 1e13` is feasible); with `x <= 1e7` it passes, and rightly (`a x <= 1e-6 < 1`). The
/// bound of a row activity that its columns imply counts the same way.
#[test]
fn certificate_terms_count_against_finite_bounds() {
    let verdict = |x_hi: f64| {
        let mut lp = Lp::new(1, 1);
        lp.a_mut()[0] = 1e-13;
        (lp.lo[0], lp.hi[0]) = (0.0, x_hi);
        (lp.lo[1], lp.hi[1]) = (1.0, f64::INFINITY);
        matches!(
            check_certificate(&lp, &[-1.0]),
            Ok(Answer::Infeasible { .. })
        )
    };
    assert!(verdict(f64::INFINITY), "dropped against an infinite bound");
    assert!(!verdict(1e14), "a feasible program refuted");
    assert!(verdict(1e7), "a clear certificate refused");
    // The row's implied bound: s = x - 1e-13 z <= 0 with x >= 1 fixed, z <= 1e14, so that
    // s >= 1 - 10 is possible... and s = 0 needs z = 1e13: feasible. Certificate y = 1 on
    // `s <= 0` (c = (1, -1e-13, -1)): least over the box is 1 - 1e-13 * 1e14 - 0 < 0.
    let mut lp = Lp::new(2, 1);
    lp.a_mut().copy_from_slice(&[1.0, -1e-13]);
    (lp.lo[0], lp.hi[0]) = (1.0, 1.0);
    (lp.lo[1], lp.hi[1]) = (0.0, 1e14);
    (lp.lo[2], lp.hi[2]) = (f64::NEG_INFINITY, 0.0);
    assert!(!matches!(
        check_certificate(&lp, &[1.0]),
        Ok(Answer::Infeasible { .. })
    ));
    lp.hi[1] = 1e7;
    assert!(matches!(
        check_certificate(&lp, &[1.0]),
        Ok(Answer::Infeasible { .. })
    ));
}

/// Idle rows (free, no cost) are left out of the basis ([`active`]): a chain of warm starts in
/// which rows go idle and come back (and costs, bounds change) agrees with cold solves and with
/// Clarabel at every step, and every adapted start's inverse equals the inverse refactored
/// from its basic columns (so that dropping and adding rows keeps it exact, not merely
/// repaired by the method's drift check).
#[test]
fn rows_going_idle_and_back_keep_warm_starts_exact() {
    let mut rng = ChaCha8Rng::seed_from_u64(43);
    let (mut compared, mut dropped, mut added) = (0, 0, 0);
    for case in 0..150 {
        let mut lp = random_lp(&mut rng);
        let (_, mut basis, _) = solve(&lp, None);
        for step in 0..6 {
            let what = format!("case {case}, step {step}");
            let k = rng.gen_range(0..lp.rows);
            let j = lp.n + k;
            match rng.gen_range(0..4) {
                // A row goes idle.
                0 => {
                    (lp.lo[j], lp.hi[j], lp.cost[j]) = (f64::NEG_INFINITY, f64::INFINITY, 0.0);
                }
                // A row gets bounds again.
                1 => (lp.lo[j], lp.hi[j]) = (0.0, f64::INFINITY),
                2 => (lp.lo[j], lp.hi[j]) = (0.0, 0.0),
                _ => {
                    let c = rng.gen_range(0..lp.n);
                    (lp.lo[c], lp.hi[c]) = (0.0, 0.0);
                }
            }
            if basis.fits(&lp) && basis.inv.is_some() {
                let adapted = active::adapt(&lp, &basis);
                dropped += basis
                    .rows
                    .iter()
                    .filter(|k| !adapted.rows.contains(k))
                    .count();
                added += adapted
                    .rows
                    .iter()
                    .filter(|k| !basis.rows.contains(k))
                    .count();
                let part = active::part(&lp, &adapted.rows);
                let reduced = active::into_part(&lp, adapted);
                if let Some(fresh) = invert(&part, &reduced.head) {
                    let inv = reduced.inv.as_deref().expect("adapted with its inverse");
                    let scale = fresh.iter().fold(1.0f64, |a, x| a.max(x.abs()));
                    for (a, b) in inv.iter().zip(&fresh) {
                        assert!((a - b).abs() <= 1e-9 * scale, "{what}: {a} against {b}");
                    }
                }
            }
            let warmed = warm_and_cold(&lp, &basis, &what);
            compared += usize::from(warmed.compared);
            basis = warmed.basis;
        }
    }
    assert!(
        compared > 600 && dropped > 100 && added > 40,
        "{compared} compared, {dropped} rows dropped, {added} added"
    );
}

/// Loose rows ([`active`]): a warm start leaves out the rows that have a finite bound and are
/// loose at its point; a program that then breaks some of them (a bound moved past the
/// start's activity) brings them back, and every answer agrees with a cold solve and with
/// Clarabel.
#[test]
fn loose_rows_are_left_out_and_brought_back_when_broken() {
    let mut rng = ChaCha8Rng::seed_from_u64(47);
    let (mut compared, mut left_out, mut broken, mut back) = (0, 0, 0, 0);
    for case in 0..2000 {
        // Row activities without costs, as in the searches' programs (a row with a cost is
        // never left out).
        let mut lp = random_lp(&mut rng);
        let n = lp.n;
        lp.cost[n..].iter_mut().for_each(|c| *c = 0.0);
        let (first, basis, _) = solve(&lp, None);
        let Answer::Optimal { x, .. } = first else {
            continue;
        };
        let loose: Vec<usize> = (0..lp.rows)
            .filter(|&k| lp.lo[n + k].is_finite() || lp.hi[n + k].is_finite())
            .filter(|&k| basis.at[n + k] == At::Basic && active::loose(&lp, &basis.activity, k))
            .collect();
        let adapted = active::adapt(&lp, &basis);
        left_out += loose.iter().filter(|k| !adapted.rows.contains(k)).count();
        let mut moved = Vec::new();
        for &k in &loose {
            if rng.gen_bool(0.5) {
                let (j, v, step) = (n + k, x[n + k], rng.gen_range(0.05..0.5));
                (lp.lo[j], lp.hi[j]) = if lp.lo[j].is_finite() {
                    (v + step, f64::INFINITY)
                } else {
                    (f64::NEG_INFINITY, v - step)
                };
                moved.push(k);
            }
        }
        broken += moved.len();
        let what = format!("case {case}");
        let warmed = warm_and_cold(&lp, &basis, &what);
        compared += usize::from(warmed.compared);
        if matches!(warmed.answer, Answer::Optimal { .. }) {
            back += moved
                .iter()
                .filter(|k| warmed.basis.rows.contains(k))
                .count();
        }
    }
    assert!(
        compared > 400 && left_out > 150 && broken > 70 && back > 25,
        "{compared} compared, {left_out} left out, {broken} broken, {back} brought back"
    );
}

/// `invert` eliminates on the structural columns only: on random bases that mix structural
/// columns and row activities (unit columns `-e_k`), `B B^-1 = I`; a basis with a singular
/// structural block, or the same row's activity twice, is refused.
#[test]
fn the_inverse_from_the_structural_block_inverts_the_whole_basis() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut checked = 0;
    for _ in 0..300 {
        let n = rng.gen_range(1..12);
        let rows = rng.gen_range(1..12);
        let mut lp = Lp::new(n, rows);
        fill(&mut lp, &mut rng, 0.7, 2.0);
        // A head: a random set of row activities, the rest structural columns.
        let slacks: Vec<usize> = (0..rows).filter(|_| rng.gen_bool(0.5)).collect();
        let need = rows - slacks.len();
        if need > n {
            continue;
        }
        let mut columns: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            columns.swap(i, rng.gen_range(0..=i));
        }
        let mut head: Vec<usize> = columns[..need].to_vec();
        head.extend(slacks.iter().map(|k| n + k));
        for i in (1..head.len()).rev() {
            head.swap(i, rng.gen_range(0..=i));
        }
        let Some(inv) = dense::invert(&lp, &head) else {
            continue;
        };
        let mut worst = 0.0f64;
        for k in 0..rows {
            for l in 0..rows {
                let bk: f64 = (0..rows)
                    .map(|c| lp.entry(k, head[c]) * inv[c * rows + l])
                    .sum();
                let want = if k == l { 1.0 } else { 0.0 };
                worst = worst.max((bk - want).abs());
            }
        }
        let size = inv.iter().fold(1.0f64, |a, x| a.max(x.abs()));
        assert!(
            worst <= 1e-10 * size,
            "B B^-1 off by {worst:e} (inverse up to {size:e})"
        );
        checked += 1;
    }
    assert!(checked > 100, "{checked} bases checked");
    // A zero structural column: singular.
    let mut lp = Lp::new(2, 2);
    lp.a_mut().copy_from_slice(&[1.0, 0.0, 1.0, 0.0]);
    assert!(dense::invert(&lp, &[0, 1]).is_none());
    assert!(dense::invert(&lp, &[0, 3]).is_some());
    // The same row's activity twice.
    assert!(dense::invert(&lp, &[2, 2]).is_none());
}
