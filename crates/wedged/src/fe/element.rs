//! Element stiffness matrices and stresses (to be written).

use super::{ElementKind, Material};
use nalgebra::DMatrix;

/// The stiffness matrix of one element, `(n*dim) x (n*dim)`, dofs node-major in the element's
/// node order. `Err` carries a one-line reason for a degenerate or inverted element.
pub fn stiffness(
    kind: ElementKind,
    x: &[[f64; 3]],
    material: &Material,
) -> Result<DMatrix<f64>, String> {
    let _ = (kind, x, material);
    unimplemented!()
}

/// The stress at the element's centroid, Voigt `[xx, yy, zz, yz, xz, xy]`, for element
/// displacements `u` (node-major, `dim` per node).
pub fn centroid_stress(
    kind: ElementKind,
    x: &[[f64; 3]],
    material: &Material,
    u: &[f64],
) -> Result<[f64; 6], String> {
    let _ = (kind, x, material, u);
    unimplemented!()
}
