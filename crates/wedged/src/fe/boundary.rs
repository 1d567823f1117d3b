//! Boundary conditions: contact nodes and frames, clamps, rollers (to be written).

/// A contact group, optionally with a prescribed inward normal.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSpec {
    /// The group's name.
    pub group: String,
    /// A prescribed inward normal of the body (need not be unit).
    pub normal: Option<[f64; 3]>,
}

/// The boundary conditions, by group name.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BoundarySpec {
    /// Contact candidate groups.
    pub contact: Vec<ContactSpec>,
    /// Zero-displacement groups.
    pub clamp: Vec<String>,
    /// Zero-normal-displacement (roller) groups, with an optional normal.
    pub symmetry: Vec<(String, Option<[f64; 3]>)>,
}

/// A contact node's local frame: the unit inward normal of the body `n` and the tangents
/// (2D: `t1` only, `t2 = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Unit inward normal (from the obstacle into the body).
    pub n: [f64; 3],
    /// First unit tangent.
    pub t1: [f64; 3],
    /// Second unit tangent (3D), zero in 2D.
    pub t2: [f64; 3],
}

/// The resolved boundary conditions of a mesh.
#[derive(Debug, Clone)]
pub struct Boundary {
    /// Mesh node of each contact node, in WP order.
    pub contact_nodes: Vec<usize>,
    /// Local frame of each contact node.
    pub frames: Vec<Frame>,
    /// The contact groups' facets (edges in 2D, faces in 3D), for drawing the obstacle.
    pub contact_facets: Vec<Vec<usize>>,
    /// Clamped mesh nodes.
    pub clamped: Vec<usize>,
    /// Roller nodes with their constrained unit directions.
    pub rollers: Vec<(usize, Vec<[f64; 3]>)>,
}
