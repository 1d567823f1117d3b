//! Built-in example problems (no I/O): the demo and deterministic test families.

use nalgebra::DMatrix;

use crate::problem::Problem;

/// The demo: four contact nodes of a small elastic block pressed into a notch, modelled as a
/// discrete system. Each node has a normal and a tangential spring, the tangential spring is
/// inclined to the wall (normal-tangential coupling, the source of wedging), and neighbouring
/// nodes are joined by shear springs. At `mu = 1.0` it has wedged configurations.
pub fn demo() -> Problem {
    let m = 4;
    let mut k = DMatrix::<f64>::zeros(2 * m, 2 * m);
    for i in 0..m {
        // A spring of stiffness s at angle theta to the wall adds s d d^T, d = (sin, cos).
        let theta: f64 = if i < m / 2 { 0.35 } else { -0.35 };
        let (s, c) = theta.sin_cos();
        let stiff = 2.0;
        k[(2 * i, 2 * i)] += 1.0 + stiff * s * s;
        k[(2 * i, 2 * i + 1)] += stiff * s * c;
        k[(2 * i + 1, 2 * i)] += stiff * s * c;
        k[(2 * i + 1, 2 * i + 1)] += 0.5 + stiff * c * c;
    }
    for i in 0..m - 1 {
        // Shear springs between neighbouring nodes, on both components.
        for (c, w) in [(0, 0.6), (1, 0.3)] {
            let (a, b) = (2 * i + c, 2 * (i + 1) + c);
            k[(a, a)] += w;
            k[(b, b)] += w;
            k[(a, b)] -= w;
            k[(b, a)] -= w;
        }
    }
    Problem::new(2, k, 1.0).expect("the demo stiffness is symmetric positive definite")
}
