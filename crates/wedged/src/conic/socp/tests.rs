//! Tests of `socp.rs`.

use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn optimal(p: &Program) -> (Vec<f64>, f64) {
    match solve(p).0 {
        Answer::Optimal { x, value } => (x, value),
        other => panic!("expected Optimal, got {other:?}"),
    }
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// maximise x + y s.t. x + 2y <= 4, 3x + y <= 6, x, y >= 0.
fn lp() -> Program {
    let mut p = Program::new(2);
    p.minimise(&[(0, -1.0), (1, -1.0)]);
    p.nonneg(Affine::new(vec![(0, -1.0), (1, -2.0)], 4.0));
    p.nonneg(Affine::new(vec![(0, -3.0), (1, -1.0)], 6.0));
    p.nonneg(Affine::var(0));
    p.nonneg(Affine::var(1));
    p
}

/// minimise t s.t. t >= ||(x - 1, y - 2)||, x + y = 0 (variables t, x, y).
fn socp() -> Program {
    let mut p = Program::new(3);
    p.minimise(&[(0, 1.0)]);
    p.soc(
        Affine::var(0),
        vec![
            Affine::new(vec![(1, 1.0)], -1.0),
            Affine::new(vec![(2, 1.0)], -2.0),
        ],
    );
    p.zero(Affine::new(vec![(1, 1.0), (2, 1.0)], 0.0));
    p
}

/// x >= 1, x <= 0.
fn infeasible_lp() -> Program {
    let mut p = Program::new(1);
    p.nonneg(Affine::new(vec![(0, 1.0)], -1.0));
    p.nonneg(Affine::new(vec![(0, -1.0)], 0.0));
    p
}

/// t >= ||(x, y)||, t = 1, x = 2 (variables t, x, y).
fn infeasible_socp() -> Program {
    let mut p = Program::new(3);
    p.soc(Affine::var(0), vec![Affine::var(1), Affine::var(2)]);
    p.zero(Affine::new(vec![(0, 1.0)], -1.0));
    p.zero(Affine::new(vec![(1, 1.0)], -2.0));
    p
}

#[test]
fn lp_known_optimum() {
    let (x, value) = optimal(&lp());
    assert!(close(x[0], 1.6, 1e-6) && close(x[1], 1.2, 1e-6), "{x:?}");
    assert!(close(value, -2.8, 1e-7), "{value}");
    assert_eq!(value, -x[0] - x[1]);
}

#[test]
fn socp_known_optimum() {
    let (x, value) = optimal(&socp());
    let t = 3.0 / 2f64.sqrt();
    assert!(close(value, t, 1e-7), "{value} vs {t}");
    assert!(close(x[1], -0.5, 1e-5) && close(x[2], 0.5, 1e-5), "{x:?}");
}

#[test]
fn infeasible_lp_and_socp() {
    assert!(matches!(
        solve(&infeasible_lp()).0,
        Answer::Infeasible { .. }
    ));
    assert!(matches!(
        solve(&infeasible_socp()).0,
        Answer::Infeasible { .. }
    ));
}

#[test]
fn certificate_sign_convention() {
    // Clarabel's y for x >= 1, x <= 0 (rows -x + s = -1, x + s = 0) is a positive multiple of
    // (1, 1): A^T y = 0, b . y < 0, y >= 0.
    let form = Form::new(&infeasible_lp()).unwrap();
    let (status, _, z) = run(&form, Mode::Default).unwrap();
    assert_eq!(status, SolverStatus::PrimalInfeasible);
    assert!(z[0] > 0.0 && close(z[0], z[1], 1e-9 * z[0]), "{z:?}");
    assert!(check_certificate(&form, &[1.0, 1.0]).is_ok());
    // The opposite sign, or a vector that does not cancel, is rejected.
    assert!(check_certificate(&form, &[-1.0, -1.0]).is_err());
    assert!(check_certificate(&form, &[1.0, 0.5]).is_err());
    assert!(check_certificate(&form, &[0.0, 0.0]).is_err());
    // A feasible program has no certificate: x >= 0, x <= 1.
    let mut p = Program::new(1);
    p.nonneg(Affine::var(0));
    p.nonneg(Affine::new(vec![(0, -1.0)], 1.0));
    let form = Form::new(&p).unwrap();
    for y in [[1.0, 1.0], [1.0, 0.0], [0.0, 1.0]] {
        assert!(check_certificate(&form, &y).is_err(), "{y:?}");
    }
}

#[test]
fn equalities_only_feasibility() {
    let mut p = Program::new(2);
    p.zero(Affine::new(vec![(0, 1.0), (1, 1.0)], -1.0));
    p.zero(Affine::new(vec![(0, 1.0), (1, -1.0)], 0.0));
    let (x, value) = optimal(&p);
    assert!(close(x[0], 0.5, 1e-9) && close(x[1], 0.5, 1e-9), "{x:?}");
    assert_eq!(value, 0.0);
}

#[test]
fn soc_with_one_tail_entry() {
    // |x| <= t, t = 1, maximise x.
    let mut p = Program::new(2);
    p.soc(Affine::var(0), vec![Affine::var(1)]);
    p.zero(Affine::new(vec![(0, 1.0)], -1.0));
    p.minimise(&[(1, -1.0)]);
    let (x, value) = optimal(&p);
    assert!(close(x[1], 1.0, 1e-7) && close(value, -1.0, 1e-7), "{x:?}");
    // Minimise instead: x = -1.
    p.minimise(&[(1, 1.0)]);
    let (x, _) = optimal(&p);
    assert!(close(x[1], -1.0, 1e-7), "{x:?}");
}

#[test]
fn single_point_on_the_cone_boundary() {
    // t >= ||(x, y)||, t = 1, x = 1: only y = 0.
    let mut p = Program::new(3);
    p.soc(Affine::var(0), vec![Affine::var(1), Affine::var(2)]);
    p.zero(Affine::new(vec![(0, 1.0)], -1.0));
    p.zero(Affine::new(vec![(1, 1.0)], -1.0));
    for objective in [vec![], vec![(2, 1.0)], vec![(2, -1.0)]] {
        p.minimise(&objective);
        match solve(&p).0 {
            Answer::Optimal { x, .. } => assert!(x[2].abs() < 1e-3, "{x:?}"),
            Answer::Uncertain { .. } => {}
            Answer::Infeasible { .. } => panic!("a feasible program called infeasible"),
        }
    }
}

#[test]
fn no_constraints_and_unused_variables() {
    let p = Program::new(3);
    assert_eq!(optimal(&p).1, 0.0);
    let mut p = Program::new(0);
    assert_eq!(optimal(&p), (vec![], 0.0));
    p.zero(Affine::new(vec![], 0.0));
    p.soc(
        Affine::new(vec![], 5.0),
        vec![Affine::new(vec![], 3.0), Affine::new(vec![], 4.0)],
    );
    assert_eq!(
        solve(&p),
        (
            Answer::Optimal {
                x: vec![],
                value: 0.0
            },
            SolveStats::default()
        )
    );
    p.nonneg(Affine::new(vec![], -1e-300));
    assert!(matches!(solve(&p).0, Answer::Infeasible { .. }));
    // x_0 >= 1, minimise x_0; x_1 appears nowhere.
    let mut p = Program::new(2);
    p.nonneg(Affine::new(vec![(0, 1.0)], -1.0));
    p.minimise(&[(0, 1.0)]);
    let (x, value) = optimal(&p);
    assert!(close(x[0], 1.0, 1e-7) && close(value, 1.0, 1e-7), "{x:?}");
    // An unbounded objective on the unused variable.
    p.minimise(&[(0, 1.0), (1, 1.0)]);
    let (answer, stats) = solve(&p);
    assert_eq!(
        answer,
        Answer::Uncertain {
            reason: "unbounded".to_string()
        }
    );
    assert_eq!(
        stats,
        SolveStats {
            solves: 2,
            retries: 1
        }
    );
    // A constant-only contradiction.
    let mut p = Program::new(1);
    p.zero(Affine::new(vec![], 1.0));
    assert!(matches!(solve(&p).0, Answer::Infeasible { .. }));
}

#[test]
fn malformed_programs_are_uncertain() {
    let bad = [
        Affine::new(vec![(0, f64::NAN)], 0.0),
        Affine::new(vec![(0, 1.0)], f64::INFINITY),
        Affine::new(vec![(2, 1.0)], 0.0),
        Affine::new(vec![(0, f64::MAX), (0, f64::MAX)], 0.0),
    ];
    for e in bad {
        let mut p = Program::new(2);
        p.nonneg(e.clone());
        let (answer, stats) = solve(&p);
        assert!(
            matches!(answer, Answer::Uncertain { .. }),
            "{e:?}: {answer:?}"
        );
        assert_eq!(stats.solves, 0);
    }
    let mut p = Program::new(2);
    p.soc(Affine::var(0), vec![]);
    assert!(matches!(solve(&p).0, Answer::Uncertain { .. }));
    let mut p = Program::new(2);
    p.minimise(&[(5, 1.0)]);
    assert!(matches!(solve(&p).0, Answer::Uncertain { .. }));
}

#[test]
fn assembly_sums_duplicates_and_orders_rows() {
    // Added in the order soc, nonneg, zero; rows come out zero, nonneg, soc.
    let mut p = Program::new(3);
    p.soc(
        Affine::new(vec![(2, 1.0), (0, 0.5)], 1.0),
        vec![Affine::new(vec![(1, 2.0), (1, 3.0)], 0.0)],
    );
    p.nonneg(Affine::new(vec![(2, 1.0), (0, 1.0), (2, -1.0)], 4.0));
    p.zero(Affine::new(vec![(1, -1.0)], 2.0));
    let form = Form::new(&p).unwrap();
    let (a, b, cones) = form.clarabel();
    assert!(a.check_format().is_ok());
    assert_eq!((a.m, a.n), (4, 3));
    let mut dense = [[0.0; 3]; 4];
    for (j, w) in a.colptr.windows(2).enumerate() {
        for k in w[0]..w[1] {
            dense[a.rowval[k]][j] += a.nzval[k];
        }
    }
    let want = [
        [0.0, 1.0, 0.0],  // zero: -(-x1)
        [-1.0, 0.0, 0.0], // nonneg: -(x0), the x2 terms cancel
        [-0.5, 0.0, -1.0],
        [0.0, -5.0, 0.0],
    ];
    assert_eq!(dense, want);
    assert_eq!(b, vec![2.0, 4.0, 1.0, 0.0]);
    assert_eq!(a.colptr, vec![0, 2, 4, 5]);
    assert_eq!(
        cones,
        vec![
            SupportedConeT::ZeroConeT(1),
            SupportedConeT::NonnegativeConeT(1),
            SupportedConeT::SecondOrderConeT(2)
        ]
    );
}

#[test]
fn checker_rejects_wrong_points() {
    let form = Form::new(&lp()).unwrap();
    assert!(check_point(&form, &[1.6, 1.2]).is_ok());
    assert!(check_point(&form, &[1.6 + 1e-12, 1.2]).is_ok());
    // x + 2y = 4.0002 > 4.
    let err = check_point(&form, &[1.6, 1.2001]).unwrap_err();
    assert!(err.contains("nonneg constraint #0"), "{err}");
    assert!(check_point(&form, &[-1e-6, 0.0]).is_err());
    // Right point, wrong value claim: the duality gap test needs a dual; a zero dual
    // leaves the dual residual q.
    assert!(check_optimal(&form, &[1.6, 1.2], &[0.0; 4]).is_err());
    assert!(check_optimal(&form, &[f64::NAN, 1.2], &[0.0; 4]).is_err());
    // The optimal dual (0.4, 0.2, 0, 0) certifies the optimum; a suboptimal point fails.
    assert_eq!(
        check_optimal(&form, &[1.6, 1.2], &[0.4, 0.2, 0.0, 0.0]),
        Ok(-2.8)
    );
    assert!(check_optimal(&form, &[1.0, 1.0], &[0.4, 0.2, 0.0, 0.0]).is_err());
    // Cones: t >= ||(x - 1, y - 2)||.
    let form = Form::new(&socp()).unwrap();
    let t = 3.0 / 2f64.sqrt();
    assert!(check_point(&form, &[t, -0.5, 0.5]).is_ok());
    assert!(check_point(&form, &[t * (1.0 - 1e-5), -0.5, 0.5]).is_err());
    assert!(check_point(&form, &[t, -0.5, 0.5 + 1e-5]).is_err());
}

#[test]
fn retry_settings_solve_the_basic_programs() {
    for mode in [Mode::Tight, Mode::Unequilibrated] {
        for p in [lp(), socp()] {
            let form = Form::new(&p).unwrap();
            assert!(matches!(
                attempt(&form, mode),
                Verdict::Verified(Answer::Optimal { .. })
            ));
        }
        for p in [infeasible_lp(), infeasible_socp()] {
            let form = Form::new(&p).unwrap();
            assert!(matches!(
                attempt(&form, mode),
                Verdict::Verified(Answer::Infeasible { .. })
            ));
        }
    }
}

#[test]
fn concurrent_solves_agree() {
    let serial = solve(&socp()).0;
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..4).map(|_| s.spawn(|| solve(&socp()).0)).collect();
        for h in handles {
            assert_eq!(h.join().unwrap(), serial);
        }
    });
}

/// A random affine expression in some of the `n` variables with value `at_x0` at `x0`.
fn affine_at(rng: &mut ChaCha8Rng, x0: &[f64], at_x0: f64) -> Affine {
    let n = x0.len();
    let k = rng.gen_range(1..=n);
    let terms: Vec<(usize, f64)> = (0..k)
        .map(|_| (rng.gen_range(0..n), rng.gen_range(-2.0..2.0)))
        .collect();
    let cx: f64 = terms.iter().map(|&(j, c)| c * x0[j]).sum();
    Affine::new(terms, at_x0 - cx)
}

fn value_at(e: &Affine, x: &[f64]) -> f64 {
    e.constant + e.terms.iter().map(|&(j, c)| c * x[j]).sum::<f64>()
}

/// A random bounded program, feasible at `x0` with slack, plus a contradiction if asked.
fn random_program(rng: &mut ChaCha8Rng, infeasible: bool) -> (Program, Vec<f64>) {
    let n = rng.gen_range(2..=8);
    let x0: Vec<f64> = (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let mut p = Program::new(n);
    for _ in 0..rng.gen_range(0..n.min(3)) {
        p.zero(affine_at(rng, &x0, 0.0));
    }
    for _ in 0..rng.gen_range(0..=4) {
        let slack = rng.gen_range(0.1..1.0);
        p.nonneg(affine_at(rng, &x0, slack));
    }
    for _ in 0..rng.gen_range(0..=3) {
        let k = rng.gen_range(1..=3);
        let tail: Vec<Affine> = (0..k)
            .map(|_| {
                let v = rng.gen_range(-1.0..1.0);
                affine_at(rng, &x0, v)
            })
            .collect();
        let norm = tail
            .iter()
            .map(|e| value_at(e, &x0).powi(2))
            .sum::<f64>()
            .sqrt();
        let slack = rng.gen_range(0.1..1.0);
        p.soc(affine_at(rng, &x0, norm + slack), tail);
    }
    // Bounded: a box or a ball around x0.
    if rng.gen_bool(0.5) {
        for (j, &x) in x0.iter().enumerate() {
            p.nonneg(Affine::new(vec![(j, 1.0)], 2.0 - x));
            p.nonneg(Affine::new(vec![(j, -1.0)], 2.0 + x));
        }
    } else {
        let tail = (0..n)
            .map(|j| Affine::new(vec![(j, 1.0)], -x0[j]))
            .collect();
        p.soc(Affine::new(vec![], 3.0), tail);
    }
    if rng.gen_bool(0.8) {
        let q: Vec<(usize, f64)> = (0..n).map(|j| (j, rng.gen_range(-1.0..1.0))).collect();
        p.minimise(&q);
    }
    if infeasible {
        let delta = rng.gen_range(0.1..1.0);
        match rng.gen_range(0..3) {
            0 => {
                // a(x) >= 0 and a(x) <= -delta.
                let v = rng.gen_range(-1.0..1.0);
                let a = affine_at(rng, &x0, v);
                let minus: Vec<(usize, f64)> = a.terms.iter().map(|&(j, c)| (j, -c)).collect();
                p.nonneg(Affine::new(minus, -a.constant - delta));
                p.nonneg(a);
            }
            1 => {
                // a(x) = 0 and a(x) = delta.
                let v = rng.gen_range(-1.0..1.0);
                let a = affine_at(rng, &x0, v);
                p.zero(Affine::new(a.terms.clone(), a.constant - delta));
                p.zero(a);
            }
            _ => {
                // Two unit balls whose centres are 2 + delta apart.
                let d: Vec<f64> = (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect();
                let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-3);
                let c1: Vec<f64> = x0.clone();
                let c2: Vec<f64> = (0..n)
                    .map(|j| x0[j] + d[j] / norm * (2.0 + delta))
                    .collect();
                for c in [c1, c2] {
                    let tail = (0..n).map(|j| Affine::new(vec![(j, 1.0)], -c[j])).collect();
                    p.soc(Affine::new(vec![], 1.0), tail);
                }
            }
        }
    }
    (p, x0)
}

#[test]
fn random_programs_with_known_feasibility() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x50c9);
    let mut retries = 0;
    for case in 0..200 {
        let infeasible = case % 2 == 1;
        let (p, x0) = random_program(&mut rng, infeasible);
        let (answer, stats) = solve(&p);
        retries += stats.retries;
        if infeasible {
            assert!(
                matches!(answer, Answer::Infeasible { .. }),
                "case {case}: {p:?}"
            );
            continue;
        }
        let Answer::Optimal { x, value } = answer else {
            panic!("case {case}: {answer:?} for {p:?}");
        };
        let form = Form::new(&p).unwrap();
        assert!(check_point(&form, &x).is_ok());
        let at_x0: f64 = form.q.iter().zip(&x0).map(|(q, x)| q * x).sum();
        assert!(
            value <= at_x0 + 1e-7,
            "case {case}: {value} > {at_x0} at x0"
        );
        let qx: f64 = form.q.iter().zip(&x).map(|(q, x)| q * x).sum();
        assert_eq!(value, qx);
    }
    assert!(retries <= 20, "{retries} retries");
}

/// A wedge-like program: `m` nodes with reactions `(r_n, r_t1, r_t2)` in the friction cone
/// `mu r_n >= ||r_t||`, eight random equality rows that vanish at a known `r0`, `sum r_n = 1`,
/// and maximise `t <= r_n_i` (all `i`), `t <= 1`. `kind` 0: `r0` interior; 1: node 0 of `r0`
/// at the apex, pinned there by `r_n_0 = 0` (degenerate, optimum `t = 0`); 2: plus a row that
/// is positive on every nonzero `r` of the cones (infeasible).
fn wedge_like(rng: &mut ChaCha8Rng, m: usize, kind: usize) -> Program {
    let mu = 0.5;
    let n = 3 * m;
    let mut r0 = vec![0.0; n];
    for i in (kind == 1) as usize..m {
        r0[3 * i] = rng.gen_range(0.5..1.5);
        let (angle, radius): (f64, f64) = (rng.gen_range(0.0..6.3), rng.gen_range(0.0..0.8));
        r0[3 * i + 1] = radius * mu * r0[3 * i] * angle.cos();
        r0[3 * i + 2] = radius * mu * r0[3 * i] * angle.sin();
    }
    let sum: f64 = (0..m).map(|i| r0[3 * i]).sum();
    r0.iter_mut().for_each(|v| *v /= sum);
    let norm2: f64 = r0.iter().map(|v| v * v).sum();
    let t = n;
    let mut p = Program::new(n + 1);
    for _ in 0..8 {
        let mut c: Vec<f64> = (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect();
        let d = c.iter().zip(&r0).map(|(a, b)| a * b).sum::<f64>() / norm2;
        c.iter_mut().zip(&r0).for_each(|(a, b)| *a -= d * b);
        p.zero(Affine::new(c.into_iter().enumerate().collect(), 0.0));
    }
    if kind == 1 {
        p.zero(Affine::var(0));
    }
    if kind == 2 {
        let mut c = Vec::new();
        for i in 0..m {
            let (b1, b2): (f64, f64) = (rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0));
            c.extend([
                (3 * i, mu * b1.hypot(b2) + 0.01),
                (3 * i + 1, b1),
                (3 * i + 2, b2),
            ]);
        }
        p.zero(Affine::new(c, 0.0));
    }
    for i in 0..m {
        p.soc(
            Affine::new(vec![(3 * i, mu)], 0.0),
            vec![Affine::var(3 * i + 1), Affine::var(3 * i + 2)],
        );
        p.nonneg(Affine::new(vec![(3 * i, 1.0), (t, -1.0)], 0.0));
    }
    p.zero(Affine::new((0..m).map(|i| (3 * i, 1.0)).collect(), -1.0));
    p.nonneg(Affine::new(vec![(t, -1.0)], 1.0));
    p.minimise(&[(t, -1.0)]);
    p
}

#[test]
fn wedge_like_programs() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut uncertain = 0;
    for case in 0..20 {
        let interior = solve(&wedge_like(&mut rng, 10, 0)).0;
        assert!(
            matches!(interior, Answer::Optimal { value, .. } if value < -1e-3),
            "case {case}: {interior:?}"
        );
        match solve(&wedge_like(&mut rng, 10, 1)).0 {
            Answer::Optimal { value, .. } => {
                assert!(value.abs() < 1e-8, "case {case}: {value}")
            }
            Answer::Uncertain { .. } => uncertain += 1,
            Answer::Infeasible { .. } => {
                panic!("case {case}: a feasible program called infeasible")
            }
        }
        assert!(
            matches!(
                solve(&wedge_like(&mut rng, 10, 2)).0,
                Answer::Infeasible { .. }
            ),
            "case {case}"
        );
    }
    assert!(
        uncertain <= 2,
        "{uncertain} of 20 degenerate programs uncertain"
    );
}

/// The simplex fallback decides the linear programs (with the same optimum as Clarabel) and
/// leaves cone programs to Clarabel.
#[test]
fn the_simplex_fallback_decides_linear_programs() {
    let form = Form::new(&lp()).unwrap();
    let Some(Ok(Answer::Optimal { value, .. })) = by_simplex(&form) else {
        panic!("the simplex method should solve the LP");
    };
    let Verdict::Verified(Answer::Optimal {
        value: clarabel, ..
    }) = attempt(&form, Mode::Default)
    else {
        panic!("Clarabel should solve the LP");
    };
    assert!((value - clarabel).abs() <= 1e-7 * (1.0 + clarabel.abs()));
    let form = Form::new(&infeasible_lp()).unwrap();
    assert!(matches!(
        by_simplex(&form),
        Some(Ok(Answer::Infeasible { ref y })) if y.is_empty()
    ));
    assert!(by_simplex(&Form::new(&socp()).unwrap()).is_none());
}
