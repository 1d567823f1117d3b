//! Condensation onto the contact nodes and recovery of the full fields (to be written).

/// One state of the body mapped back to the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Configuration {
    /// Displacement of every mesh node, global frame (`z = 0` in 2D).
    pub displacement: Vec<[f64; 3]>,
    /// Nodal force `K u` of every mesh node, global frame: the reaction at contact, clamped and
    /// roller nodes, zero (to round-off) elsewhere.
    pub force: Vec<[f64; 3]>,
    /// Stress at each element's centroid, Voigt `[xx, yy, zz, yz, xz, xy]`.
    pub stress: Vec<[f64; 6]>,
    /// Von Mises stress at each element's centroid.
    pub von_mises: Vec<f64>,
}

/// The FE model (to be written).
pub struct Model;

/// The condensed WP (to be written).
pub struct Condensed;
