//! The finite-element front end: from a meshed elastic body to the condensed wedged problem, and
//! from a solution of the WP back to full displacement and stress fields.
//!
//! ```text
//! Mesh (nodes, body elements, named boundary groups) + Material
//!   └─ boundary::Boundary::new     contact nodes and their frames, clamps, rollers
//!        └─ condense::Model::build  element stiffness (element.rs) in reduced dofs, sparse
//!             │                      Cholesky of the eliminated block, Schur complement
//!             ├─ Condensed.k         the WP's K (dim*m x dim*m, local frames, normal first)
//!             └─ Model::recover      u_c -> full displacement, nodal forces, element stresses
//! ```
//!
//! Conventions:
//! - Coordinates are always `[x, y, z]`; in 2D `z = 0`.
//! - Global degrees of freedom are node-major: node `a` owns `dim*a .. dim*a + dim`.
//! - Element node orders are Gmsh's: triangles and quadrilaterals counterclockwise, the
//!   hexahedron's bottom face `0-1-2-3` then the top face `4-5-6-7` above it, the tetrahedron with
//!   `((x1-x0) x (x2-x0)) . (x3-x0) > 0`. A mirrored element (every Jacobian negative) is accepted
//!   and integrated with `|det J|`; a Jacobian that changes sign or vanishes is an error.
//! - Stresses are in Voigt order `[xx, yy, zz, yz, xz, xy]`; in plane strain
//!   `zz = nu (xx + yy)`, in plane stress `zz = 0`.
//!
//! Nothing here reads or writes files: meshes come from the generators in [`generate`] or from a
//! reader in the binary.

pub mod boundary;
pub mod condense;
pub mod element;
pub mod generate;
pub mod material;

pub use boundary::{Boundary, BoundarySpec, ContactSpec, Frame};
pub use condense::{Condensed, Configuration, Model};
pub use material::{Material, Plane};

/// A body element type. Node orders are Gmsh's: the corners, then (second order) the
/// mid-edge nodes, edge by edge, then the centre (`Quad9`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ElementKind {
    /// 3-node triangle (2D).
    Tri3,
    /// 4-node quadrilateral (2D), bilinear, 2x2 Gauss points.
    Quad4,
    /// 4-node tetrahedron (3D).
    Tet4,
    /// 8-node hexahedron (3D), trilinear, 2x2x2 Gauss points.
    Hex8,
    /// 6-node triangle (2D), quadratic; mid-edge nodes on `0-1`, `1-2`, `2-0`.
    Tri6,
    /// 8-node quadrilateral (2D), quadratic serendipity, 3x3 Gauss points; mid-edge nodes on
    /// `0-1`, `1-2`, `2-3`, `3-0`.
    Quad8,
    /// 9-node quadrilateral (2D), biquadratic, 3x3 Gauss points: `Quad8` and the centre.
    Quad9,
    /// 10-node tetrahedron (3D), quadratic; mid-edge nodes on `0-1`, `1-2`, `0-2`, `0-3`,
    /// `2-3`, `1-3` (Gmsh's order; VTK's swaps the last two).
    Tet10,
}

impl ElementKind {
    /// Spatial dimension of the element.
    pub fn dim(self) -> usize {
        match self {
            ElementKind::Tri3
            | ElementKind::Quad4
            | ElementKind::Tri6
            | ElementKind::Quad8
            | ElementKind::Quad9 => 2,
            ElementKind::Tet4 | ElementKind::Hex8 | ElementKind::Tet10 => 3,
        }
    }

    /// Number of nodes.
    pub fn node_count(self) -> usize {
        match self {
            ElementKind::Tri3 => 3,
            ElementKind::Quad4 | ElementKind::Tet4 => 4,
            ElementKind::Tri6 => 6,
            ElementKind::Hex8 | ElementKind::Quad8 => 8,
            ElementKind::Quad9 => 9,
            ElementKind::Tet10 => 10,
        }
    }

    /// The corners each mid-edge node lies between, in node order (a `Quad9`'s centre, its
    /// last node, is not one): Gmsh's numbering.
    pub fn mid_edges(self) -> &'static [[usize; 2]] {
        match self {
            ElementKind::Tri6 => &[[0, 1], [1, 2], [2, 0]],
            ElementKind::Quad8 | ElementKind::Quad9 => &[[0, 1], [1, 2], [2, 3], [3, 0]],
            ElementKind::Tet10 => &[[0, 1], [1, 2], [0, 2], [0, 3], [2, 3], [1, 3]],
            ElementKind::Tri3 | ElementKind::Quad4 | ElementKind::Tet4 | ElementKind::Hex8 => &[],
        }
    }

    /// The number of corner nodes (the first ones): the linear element's.
    pub fn corner_count(self) -> usize {
        self.linear().node_count()
    }

    /// The first-order element with the same corners.
    pub fn linear(self) -> ElementKind {
        match self {
            ElementKind::Tri3 | ElementKind::Tri6 => ElementKind::Tri3,
            ElementKind::Quad4 | ElementKind::Quad8 | ElementKind::Quad9 => ElementKind::Quad4,
            ElementKind::Tet4 | ElementKind::Tet10 => ElementKind::Tet4,
            ElementKind::Hex8 => ElementKind::Hex8,
        }
    }

    /// Name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            ElementKind::Tri3 => "3-node triangle",
            ElementKind::Quad4 => "4-node quadrilateral",
            ElementKind::Tet4 => "4-node tetrahedron",
            ElementKind::Hex8 => "8-node hexahedron",
            ElementKind::Tri6 => "6-node triangle",
            ElementKind::Quad8 => "8-node quadrilateral",
            ElementKind::Quad9 => "9-node quadrilateral",
            ElementKind::Tet10 => "10-node tetrahedron",
        }
    }

    /// The element's faces (3D) or edges (2D), as local node indices, each ordered so that its
    /// normal by the right-hand rule points out of the element (for a positively oriented
    /// element): the corners, then (second order) the mid-edge nodes, as Gmsh orders a 3-node
    /// line (`a, b, mid`) and a 6-node triangle (the corners, then the middles of `0-1`, `1-2`,
    /// `2-0`).
    pub fn facets(self) -> &'static [&'static [usize]] {
        match self {
            ElementKind::Tri3 => &[&[0, 1], &[1, 2], &[2, 0]],
            ElementKind::Quad4 => &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]],
            ElementKind::Tet4 => &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[0, 3, 2]],
            ElementKind::Hex8 => &[
                &[0, 3, 2, 1],
                &[4, 5, 6, 7],
                &[0, 1, 5, 4],
                &[1, 2, 6, 5],
                &[2, 3, 7, 6],
                &[3, 0, 4, 7],
            ],
            ElementKind::Tri6 => &[&[0, 1, 3], &[1, 2, 4], &[2, 0, 5]],
            ElementKind::Quad8 | ElementKind::Quad9 => {
                &[&[0, 1, 4], &[1, 2, 5], &[2, 3, 6], &[3, 0, 7]]
            }
            ElementKind::Tet10 => &[
                &[0, 2, 1, 6, 5, 4],
                &[0, 1, 3, 4, 9, 7],
                &[1, 2, 3, 5, 8, 9],
                &[0, 3, 2, 7, 8, 6],
            ],
        }
    }

    /// A 2D element's boundary as a closed polygon of local nodes, counterclockwise for a
    /// positively oriented element (corners and mid-edge nodes in turn); a 3D element's nodes.
    pub fn outline(self) -> &'static [usize] {
        match self {
            ElementKind::Tri3 => &[0, 1, 2],
            ElementKind::Quad4 | ElementKind::Tet4 => &[0, 1, 2, 3],
            ElementKind::Tri6 => &[0, 3, 1, 4, 2, 5],
            ElementKind::Quad8 | ElementKind::Quad9 => &[0, 4, 1, 5, 2, 6, 3, 7],
            ElementKind::Hex8 => &[0, 1, 2, 3, 4, 5, 6, 7],
            ElementKind::Tet10 => &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9],
        }
    }
}

impl ElementKind {
    /// The element's nodes in VTK's (and meshio's) order, from the mesh's (Gmsh's): the same but
    /// for the 10-node tetrahedron, whose mid-edge nodes are on `0-1, 1-2, 0-2, 0-3, 2-3, 1-3`
    /// in Gmsh and `0-1, 1-2, 0-2, 0-3, 1-3, 2-3` in VTK.
    pub fn vtk_order(self, nodes: &[usize]) -> Vec<usize> {
        let mut out = nodes.to_vec();
        if self == ElementKind::Tet10 && out.len() == 10 {
            out.swap(8, 9);
        }
        out
    }
}

/// The number of corners of a facet (an edge or a face) with `len` nodes in a `dim`-dimensional
/// mesh: its first nodes ([`ElementKind::facets`]).
pub fn facet_corners(dim: usize, len: usize) -> usize {
    match (dim, len) {
        (2, _) => 2,
        (_, 6) => 3,
        (_, 8 | 9) => 4,
        _ => len,
    }
}

/// One body element: its type and its node indices (0-based, into [`Mesh::coords`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    /// Element type.
    pub kind: ElementKind,
    /// Node indices in the element's (Gmsh) order.
    pub nodes: Vec<usize>,
}

/// A named set of mesh entities of one dimension, as a Gmsh physical group: points (`dim = 0`,
/// one node each), edges (`dim = 1`, 2 nodes), faces (`dim = 2`, 3 or 4 nodes), or body elements
/// (`dim` = mesh dim). Boundary conditions refer to groups by name.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// The name (Gmsh physical name).
    pub name: String,
    /// Dimension of the entities.
    pub dim: usize,
    /// The entities, each a list of node indices.
    pub entities: Vec<Vec<usize>>,
}

impl Group {
    /// The distinct nodes of the group, sorted.
    pub fn nodes(&self) -> Vec<usize> {
        let mut nodes: Vec<usize> = self.entities.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }
}

/// A mesh of an elastic body: node coordinates, body elements and named groups.
#[derive(Debug, Clone)]
pub struct Mesh {
    dim: usize,
    coords: Vec<[f64; 3]>,
    elements: Vec<Element>,
    groups: Vec<Group>,
}

/// Why a mesh, a material or a boundary specification was rejected, or condensation failed.
/// Node and element numbers in messages are 1-based.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FeError {
    /// The mesh dimension is not 2 or 3.
    #[error("mesh dimension must be 2 or 3, got {0}")]
    InvalidDim(usize),
    /// The mesh has no body elements.
    #[error("the mesh has no {0}D elements")]
    NoElements(usize),
    /// An element's type does not match the mesh dimension.
    #[error("element {element} is a {kind}, but the mesh is {dim}D")]
    WrongElementDim {
        element: usize,
        kind: &'static str,
        dim: usize,
    },
    /// An element has the wrong number of nodes.
    #[error("element {element} ({kind}) has {got} nodes, expected {expected}")]
    WrongNodeCount {
        element: usize,
        kind: &'static str,
        got: usize,
        expected: usize,
    },
    /// A node index is out of range.
    #[error("{what} refers to node {node}, but the mesh has {count} nodes")]
    NodeOutOfRange {
        what: String,
        node: usize,
        count: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("node {node} has a non-finite coordinate {value}")]
    NonFiniteCoordinate { node: usize, value: f64 },
    /// Two groups share a name.
    #[error("two groups are named '{0}'")]
    DuplicateGroup(String),
    /// A bad material parameter.
    #[error("{0}")]
    InvalidMaterial(String),
    /// An element whose Jacobian vanishes or changes sign.
    #[error("element {element} ({kind}) is degenerate or inverted: {detail}")]
    DegenerateElement {
        element: usize,
        kind: &'static str,
        detail: String,
    },
    /// A boundary condition names a group that does not exist.
    #[error("{role} group '{name}' does not exist in the mesh; its groups are: {available}")]
    UnknownGroup {
        role: &'static str,
        name: String,
        available: String,
    },
    /// A boundary group has nodes that belong to no body element.
    #[error("{role} group '{name}' has node {node}, which belongs to no {dim}D element")]
    GroupNodeNotOnBody {
        role: &'static str,
        name: String,
        node: usize,
        dim: usize,
    },
    /// Bad parameters of a built-in mesh generator.
    #[error("{0}")]
    InvalidGeometry(String),
    /// A bad boundary specification (no contact group, a zero normal, ...).
    #[error("{0}")]
    InvalidBoundary(String),
    /// The stiffness of the eliminated nodes is singular: the body is not held.
    #[error(
        "the body is not held: the stiffness with the contact nodes fixed is singular ({0}); \
         add a [[clamp]] or [[symmetry]] group, or check that the mesh is connected"
    )]
    NotHeld(String),
    /// Memory could not be allocated for the factorisation.
    #[error("out of memory while factorising the stiffness of {0} degrees of freedom")]
    OutOfMemory(usize),
}

impl Mesh {
    /// Builds and checks a mesh: `dim` is 2 or 3, every body element has the mesh's dimension
    /// and its number of nodes, node indices are in range, coordinates are finite, group names
    /// are distinct.
    pub fn new(
        dim: usize,
        coords: Vec<[f64; 3]>,
        elements: Vec<Element>,
        groups: Vec<Group>,
    ) -> Result<Mesh, FeError> {
        if dim != 2 && dim != 3 {
            return Err(FeError::InvalidDim(dim));
        }
        if elements.is_empty() {
            return Err(FeError::NoElements(dim));
        }
        for (a, x) in coords.iter().enumerate() {
            if let Some(&value) = x.iter().find(|v| !v.is_finite()) {
                return Err(FeError::NonFiniteCoordinate { node: a + 1, value });
            }
        }
        let count = coords.len();
        for (e, element) in elements.iter().enumerate() {
            if element.kind.dim() != dim {
                return Err(FeError::WrongElementDim {
                    element: e + 1,
                    kind: element.kind.name(),
                    dim,
                });
            }
            if element.nodes.len() != element.kind.node_count() {
                return Err(FeError::WrongNodeCount {
                    element: e + 1,
                    kind: element.kind.name(),
                    got: element.nodes.len(),
                    expected: element.kind.node_count(),
                });
            }
            if let Some(&node) = element.nodes.iter().find(|&&a| a >= count) {
                return Err(FeError::NodeOutOfRange {
                    what: format!("element {}", e + 1),
                    node: node + 1,
                    count,
                });
            }
        }
        for (g, group) in groups.iter().enumerate() {
            if groups[..g].iter().any(|other| other.name == group.name) {
                return Err(FeError::DuplicateGroup(group.name.clone()));
            }
            if let Some(&node) = group.entities.iter().flatten().find(|&&a| a >= count) {
                return Err(FeError::NodeOutOfRange {
                    what: format!("group '{}'", group.name),
                    node: node + 1,
                    count,
                });
            }
        }
        Ok(Mesh {
            dim,
            coords,
            elements,
            groups,
        })
    }

    /// Spatial dimension (2 or 3).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Node coordinates `[x, y, z]` (`z = 0` in 2D).
    pub fn coords(&self) -> &[[f64; 3]] {
        &self.coords
    }

    /// Body elements.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Named groups.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// The group with this name.
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.coords.len()
    }

    /// The names of the groups, comma-separated, for messages.
    pub fn group_names(&self) -> String {
        if self.groups.is_empty() {
            return "(none)".to_string();
        }
        self.groups
            .iter()
            .map(|g| format!("'{}' ({}D)", g.name, g.dim))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The coordinates of an element's nodes.
    pub fn element_coords(&self, element: &Element) -> Vec<[f64; 3]> {
        element.nodes.iter().map(|&a| self.coords[a]).collect()
    }

    /// Which nodes belong to at least one body element.
    pub fn used_nodes(&self) -> Vec<bool> {
        let mut used = vec![false; self.coords.len()];
        for element in &self.elements {
            for &a in &element.nodes {
                used[a] = true;
            }
        }
        used
    }

    /// A length scale: the diagonal of the bounding box.
    pub fn size(&self) -> f64 {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for x in &self.coords {
            for k in 0..3 {
                lo[k] = lo[k].min(x[k]);
                hi[k] = hi[k].max(x[k]);
            }
        }
        (0..3)
            .map(|k| (hi[k] - lo[k]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}
