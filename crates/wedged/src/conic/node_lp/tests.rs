//! Tests of the search nodes' programs ([`super`]).

use super::*;
use crate::examples::random_spd_problem;

/// An inner node's program decided normalised by the sum ([`decide_inner`] with its pressed
/// program made to fail) prunes only where the pressed program (Clarabel's, an independent
/// solver) has no solution either, and its point is a point of the node: `sum r_n = 1`,
/// nothing on the separated nodes, the contact nodes' gaps closed, the pressures
/// nonnegative. Unforced, it decides as [`decide`] does, and both agree with Clarabel.
#[test]
fn the_sum_relaxes_an_undecided_pressed_program_soundly() {
    let (mut pruned, mut kept) = (0, 0);
    for seed in 0..120u64 {
        let m = 2 + (seed % 5) as usize;
        let mu = [0.6, 1.2, 2.5][(seed % 3) as usize];
        let problem = random_spd_problem(m, mu, 9100 + seed);
        let form = Formulation::new(&problem);
        let mut lcg = seed.wrapping_mul(6364136223846793005).wrapping_add(7);
        for _ in 0..4 {
            let classes: Vec<Class> = (0..m)
                .map(|_| {
                    lcg = lcg
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    [Class::Contact, Class::Separated, Class::Free][(lcg >> 33) as usize % 3]
                })
                .collect();
            let contact: Vec<usize> = (0..m).filter(|&i| classes[i] == Class::Contact).collect();
            if contact.is_empty() || !classes.contains(&Class::Free) {
                continue;
            }
            let shape = Shape { mu, drive: None };
            let norm = Norm::Pressed(&contact);
            let reference = form.decide_cut(&classes, mu, norm, Goal::Feasible, &[]).0;
            let counters = LpCounters::default();
            let plain = decide(&form, &counters, &classes, shape, norm, None, None).0;
            let inner = decide_inner(&form, &counters, &classes, shape, norm, None, None).0;
            assert_eq!(counters.relaxed.load(Ordering::Relaxed), 0);
            assert_eq!(counters.fallbacks.load(Ordering::Relaxed), 0);
            for own in [&plain, &inner] {
                match (own, &reference) {
                    (Decision::No, Decision::No) | (Decision::Yes { .. }, Decision::Yes { .. }) => {
                    }
                    (a, b) => panic!("seed {seed} {classes:?}: {a:?} against {b:?}"),
                }
            }
            PRESSED_FAILS.with(|f| f.set(true));
            let relaxed = decide_inner(&form, &counters, &classes, shape, norm, None, None).0;
            PRESSED_FAILS.with(|f| f.set(false));
            assert_eq!(counters.relaxed.load(Ordering::Relaxed), 1);
            match relaxed {
                Decision::No => {
                    assert!(
                        matches!(reference, Decision::No),
                        "seed {seed}: pruned a solution"
                    );
                    pruned += 1;
                }
                Decision::Yes { r, .. } => {
                    let d = form.dim;
                    let total: f64 = (0..m).map(|i| r[d * i]).sum();
                    assert!((total - 1.0).abs() < 1e-9, "seed {seed}: total {total}");
                    for i in 0..m {
                        assert!(r[d * i] >= -1e-9, "seed {seed}: pressure {}", r[d * i]);
                        match classes[i] {
                            Class::Separated => assert!(r[d * i].abs() < 1e-12),
                            Class::Contact => assert!(form.gap_of(&r, i).abs() < 1e-8),
                            _ => {}
                        }
                    }
                    kept += 1;
                }
                Decision::Unsure(why) => panic!("seed {seed}: {why}"),
            }
        }
    }
    // Both ways, and some nodes the relaxation keeps that the pressed program prunes.
    assert!(pruned > 20 && kept > 20, "{pruned} {kept}");
}

/// Every row's activity `A x` against its factor row times the gathered columns.
fn gathered_activities_match(a: &[f64], reduced: &Reduced, x: &[f64], what: &str) {
    let n = x.len();
    let mut gathered = vec![f64::NAN; reduced.width];
    (reduced.gather)(x, &mut gathered);
    for k in 0..a.len() / n {
        let row = &a[k * n..(k + 1) * n];
        let small = &reduced.a[k * reduced.width..(k + 1) * reduced.width];
        let direct: f64 = row.iter().zip(x).map(|(p, q)| p * q).sum();
        let terms: f64 = row.iter().zip(x).map(|(p, q)| (p * q).abs()).sum();
        let factored: f64 = small.iter().zip(&gathered).map(|(p, q)| p * q).sum();
        assert!(
            (direct - factored).abs() <= 1e-12 * (1.0 + terms),
            "{what}, row {k}: {factored} against {direct}"
        );
    }
}

/// The 3D programs' factors ([`Reduced`]) make their matrix: a combination of rows taken
/// through them (as the simplex method's row products are) equals the same combination of the
/// matrix's rows, at finite and infinite `mu`; 2D programs have none.
#[test]
fn the_factors_make_the_matrix() {
    for seed in 0..12u64 {
        let m = 2 + (seed % 4) as usize;
        let mu = match seed % 3 {
            0 => f64::INFINITY,
            _ => 0.4 + 0.3 * seed as f64,
        };
        let problem = crate::examples::random_spd_problem_dim(3, m, 1.5, 400 + seed);
        let form = Formulation::new(&problem);
        let (a, reduced) = matrix(&form, Shape { mu, drive: None });
        let reduced = reduced.expect("3D programs are factored");
        let rows = 3 * m + 1;
        let n = a.len() / rows;
        assert_eq!(reduced.a.len(), reduced.width * rows);
        let mut lcg = seed.wrapping_add(11);
        let v: Vec<f64> = (0..rows)
            .map(|_| {
                lcg = lcg
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (lcg >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        let mut dense = vec![0.0; n];
        let mut w = vec![0.0; reduced.width];
        for (k, &vk) in v.iter().enumerate() {
            let (row, small) = (
                &a[k * n..(k + 1) * n],
                &reduced.a[k * reduced.width..(k + 1) * reduced.width],
            );
            dense.iter_mut().zip(row).for_each(|(x, y)| *x += vk * y);
            w.iter_mut().zip(small).for_each(|(x, y)| *x += vk * y);
        }
        let mut through = vec![f64::NAN; n];
        (reduced.expand)(&w, &mut through);
        let size = dense.iter().fold(1.0f64, |s, x| s.max(x.abs()));
        for j in 0..n {
            assert!(
                (through[j] - dense[j]).abs() <= 1e-12 * size,
                "seed {seed}, mu {mu}, column {j}: {} against {}",
                through[j],
                dense[j]
            );
        }
        // Row activities: `A x` against the factor rows times the gathered columns.
        let x: Vec<f64> = (0..n)
            .map(|_| {
                lcg = lcg
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (lcg >> 11) as f64 / (1u64 << 53) as f64
            })
            .collect();
        gathered_activities_match(&a, &reduced, &x, &format!("seed {seed}, mu {mu}"));
    }
    // A floating body's amplitude columns: each mode's column, or none.
    for seed in 0..3u64 {
        let problem = crate::examples::floating_notch(3, 4, 20.0, 1.0, seed);
        let form = Formulation::new(&problem);
        assert!(
            form.amplitudes() > 0,
            "a floating body has amplitude columns"
        );
        let (a, reduced) = matrix(
            &form,
            Shape {
                mu: 1.0,
                drive: None,
            },
        );
        let reduced = reduced.expect("3D programs are factored");
        let n = a.len() / (3 * form.m + 1 + form.modes);
        let x: Vec<f64> = (0..n).map(|j| ((j * 7 + 3) % 11) as f64 - 5.0).collect();
        gathered_activities_match(&a, &reduced, &x, &format!("floating, seed {seed}"));
    }
    let flat = random_spd_problem(3, 1.0, 1);
    let form = Formulation::new(&flat);
    let shape = Shape {
        mu: 1.0,
        drive: None,
    };
    assert!(matrix(&form, shape).1.is_none());
}
