//! Mirror symmetry (issue 20: exploit structure where it is present): `Problem::mirror` finds
//! the involution of a body symmetric about a plane (node images with tangents reversed) and
//! only then, and `critical`'s `bnb` separates a branch node's image with it on the nodes the
//! mirror keeps (orbital branching), which must not change `mu*`: on seeded mirror-symmetric
//! problems it equals the brute force over contact sets, certified (which uses no mirror).

use nalgebra::DMatrix;
use wedged::examples::{plug2d, plug2d_tri, random_spd_problem};
use wedged::{critical, CriticalMethod, CriticalSettings, CriticalStatus, Problem};

/// `K + P K P^T` for the signed permutation of the node reversal `i -> m - 1 - i` with every
/// image's tangent reversed: invariant under it.
fn mirrored(k: &DMatrix<f64>) -> (DMatrix<f64>, Vec<usize>) {
    let n = k.nrows();
    let m = n / 2;
    let image: Vec<usize> = (0..m).map(|i| m - 1 - i).collect();
    let mut p = DMatrix::<f64>::zeros(n, n);
    for (i, &j) in image.iter().enumerate() {
        p[(2 * j, 2 * i)] = 1.0;
        p[(2 * j + 1, 2 * i + 1)] = -1.0;
    }
    (k + &p * k * p.transpose(), image)
}

#[test]
fn a_mirror_is_found_exactly_when_present() {
    for seed in 0..20 {
        let m = 2 + (seed % 6) as usize;
        let p = random_spd_problem(m, 1.5, seed);
        assert_eq!(p.mirror(), None, "seed {seed}");
        let (k, image) = mirrored(p.stiffness());
        let q = Problem::new(2, k, 1.5).unwrap();
        assert_eq!(q.mirror(), Some(image), "seed {seed}");
    }
    // The quadrilateral plug is mirror-symmetric (nodes of one height on the two walls); the
    // triangle plug is not (its diagonals all lean one way).
    let quad = plug2d(8, 6).unwrap().problem(1.8).unwrap();
    let s = quad.mirror().expect("the quadrilateral plug's mirror");
    assert!((0..quad.nodes()).all(|i| s[i] != i && s[s[i]] == i));
    let tri = plug2d_tri(8).unwrap().problem(2.0).unwrap();
    assert_eq!(tri.mirror(), None);
    // 3D: not looked for.
    let p3 = wedged::examples::random_spd_problem_dim(3, 4, 1.0, 1);
    assert_eq!(p3.mirror(), None);
}

#[test]
fn orbital_branching_keeps_mu_star() {
    let (mut mirrored_branchings, mut wedged) = (0, 0);
    for seed in 0..30u64 {
        let m = 2 + (seed % 6) as usize;
        let base = random_spd_problem(m, 3.0, 500 + seed);
        let (k, _) = mirrored(base.stiffness());
        let p = Problem::new(2, k, 3.0).unwrap();
        let what = format!("seed {seed}, m = {m}");
        let fast = critical(&p, &CriticalSettings::default()).unwrap();
        let brute = critical(
            &p,
            &CriticalSettings {
                method: CriticalMethod::Faces,
                certify: true,
                ..CriticalSettings::default()
            },
        )
        .unwrap();
        assert_eq!(fast.status, brute.status, "{what}");
        mirrored_branchings += fast.info.mirrored;
        if fast.status != CriticalStatus::Wedged {
            continue;
        }
        wedged += 1;
        let (a, b) = (fast.upper.unwrap(), brute.upper.unwrap());
        let tol = 1e-6_f64.max(brute.info.tol_achieved);
        assert!((a - b).abs() <= tol * b, "{what}: {a} against {b}");
        assert!(fast.lower.unwrap() <= b * (1.0 + 1e-9), "{what}");
    }
    assert!(wedged >= 15, "{wedged} wedged");
    assert!(
        mirrored_branchings >= 30,
        "{mirrored_branchings} mirrored branchings"
    );
}
