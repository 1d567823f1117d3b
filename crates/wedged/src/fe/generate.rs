//! Built-in structured meshes of the standard test bodies, with their named groups.
//!
//! - [`Plug2d`]: a trapezoidal plug in a V-notch (2D). The trapezoid is symmetric about `x = 0`,
//!   its bottom edge (width `bottom_width`) at `y = 0`, its top edge (width `top_width`) at
//!   `y = height`. Node `(i, j)` sits at `y = height j/ny`, `x = w(y) (2i/nx - 1)` with the
//!   half-width `w` linear in `y`, the same nodes as a Gmsh transfinite mesh of the trapezoid.
//!   Groups: `contact` (both slanted sides), `left`, `right`, `bottom`, `top`, `body`.
//! - [`VGroove`]: the same trapezoid in the `x-z` plane (`z` up), extruded along `y` over
//!   `length`: a 3D plug in a V-groove. Groups: `contact` (both slanted faces), `left`, `right`,
//!   `bottom`, `top`, `front` (`y = 0`), `back` (`y = length`), `body`.
//! - [`Frustum`]: a square frustum (`z` up), side `bottom_width` at `z = 0` and `top_width` at
//!   `z = height`, in a pyramidal hole. Groups: `contact` (the four slanted faces), `xmin`,
//!   `xmax`, `ymin`, `ymax`, `bottom`, `top`, `body`.
//!
//! Quadrilaterals and hexahedra are the natural elements; with `simplices = true` each
//! quadrilateral is cut into two triangles and each hexahedron into six tetrahedra (Kuhn's
//! triangulation along the main diagonal, conforming across elements). Boundary groups then
//! consist of the triangles the tetrahedra actually expose.

use super::{Element, ElementKind, FeError, Group, Mesh};

/// Upper bound on the number of nodes of a generated mesh (a guard against typing one zero too
/// many).
pub const MAX_GENERATED_NODES: usize = 20_000_000;

/// A 2D trapezoidal plug in a V-notch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plug2d {
    /// Width at `y = 0`.
    pub bottom_width: f64,
    /// Width at `y = height`.
    pub top_width: f64,
    /// Height.
    pub height: f64,
    /// Divisions across.
    pub nx: usize,
    /// Divisions up (each slanted side has `ny + 1` nodes).
    pub ny: usize,
    /// Triangles instead of quadrilaterals.
    pub simplices: bool,
}

/// A 3D plug in a V-groove: [`Plug2d`]'s trapezoid in the `x-z` plane, extruded along `y`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VGroove {
    /// Width at `z = 0`.
    pub bottom_width: f64,
    /// Width at `z = height`.
    pub top_width: f64,
    /// Height.
    pub height: f64,
    /// Extent along `y`.
    pub length: f64,
    /// Divisions across (`x`).
    pub nx: usize,
    /// Divisions along the groove (`y`).
    pub ny: usize,
    /// Divisions up (`z`).
    pub nz: usize,
    /// Tetrahedra instead of hexahedra.
    pub simplices: bool,
}

/// A 3D square frustum plug in a pyramidal hole.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frustum {
    /// Side at `z = 0`.
    pub bottom_width: f64,
    /// Side at `z = height`.
    pub top_width: f64,
    /// Height.
    pub height: f64,
    /// Divisions along `x` and along `y`.
    pub n: usize,
    /// Divisions up (`z`).
    pub nz: usize,
    /// Tetrahedra instead of hexahedra.
    pub simplices: bool,
}

fn check_length(name: &str, value: f64) -> Result<(), FeError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(FeError::InvalidGeometry(format!(
            "{name} must be finite and > 0, got {value}"
        )))
    }
}

fn check_divisions(divisions: &[(&str, usize)]) -> Result<(), FeError> {
    let mut nodes: usize = 1;
    for &(name, n) in divisions {
        if n == 0 {
            return Err(FeError::InvalidGeometry(format!(
                "{name} must be at least 1, got 0"
            )));
        }
        nodes = nodes.saturating_mul(n.saturating_add(1));
    }
    if nodes > MAX_GENERATED_NODES {
        return Err(FeError::InvalidGeometry(format!(
            "the mesh would have {nodes} nodes, more than the limit of {MAX_GENERATED_NODES}"
        )));
    }
    Ok(())
}

impl Plug2d {
    /// Builds the mesh.
    pub fn mesh(&self) -> Result<Mesh, FeError> {
        check_length("bottom_width", self.bottom_width)?;
        check_length("top_width", self.top_width)?;
        check_length("height", self.height)?;
        check_divisions(&[("nx", self.nx), ("ny", self.ny)])?;
        let (nx, ny) = (self.nx, self.ny);
        let id = |i: usize, j: usize| j * (nx + 1) + i;
        let mut coords = Vec::with_capacity((nx + 1) * (ny + 1));
        for j in 0..=ny {
            let y = self.height * j as f64 / ny as f64;
            let w = half_width(self.bottom_width, self.top_width, j, ny);
            for i in 0..=nx {
                coords.push([w * (2.0 * i as f64 / nx as f64 - 1.0), y, 0.0]);
            }
        }
        let mut elements = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let quad = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
                if self.simplices {
                    elements.push(element(ElementKind::Tri3, &[quad[0], quad[1], quad[2]]));
                    elements.push(element(ElementKind::Tri3, &[quad[0], quad[2], quad[3]]));
                } else {
                    elements.push(element(ElementKind::Quad4, &quad));
                }
            }
        }
        let left: Vec<Vec<usize>> = (0..ny).map(|j| vec![id(0, j), id(0, j + 1)]).collect();
        let right: Vec<Vec<usize>> = (0..ny).map(|j| vec![id(nx, j), id(nx, j + 1)]).collect();
        let bottom: Vec<Vec<usize>> = (0..nx).map(|i| vec![id(i, 0), id(i + 1, 0)]).collect();
        let top: Vec<Vec<usize>> = (0..nx).map(|i| vec![id(i, ny), id(i + 1, ny)]).collect();
        let groups = vec![
            group("contact", 1, [left.clone(), right.clone()].concat()),
            group("left", 1, left),
            group("right", 1, right),
            group("bottom", 1, bottom),
            group("top", 1, top),
            body_group(2, &elements),
        ];
        Mesh::new(2, coords, elements, groups)
    }
}

/// Half the width at level `k` of `n`, linear from `bottom/2` to `top/2`.
fn half_width(bottom: f64, top: f64, k: usize, n: usize) -> f64 {
    let s = k as f64 / n as f64;
    0.5 * (bottom + (top - bottom) * s)
}

fn element(kind: ElementKind, nodes: &[usize]) -> Element {
    Element {
        kind,
        nodes: nodes.to_vec(),
    }
}

fn group(name: &str, dim: usize, entities: Vec<Vec<usize>>) -> Group {
    Group {
        name: name.to_string(),
        dim,
        entities,
    }
}

fn body_group(dim: usize, elements: &[Element]) -> Group {
    group(
        "body",
        dim,
        elements.iter().map(|e| e.nodes.clone()).collect(),
    )
}

/// A structured hexahedral block: node `(i, j, k)` at `place(i, j, k)`, with `place`
/// orientation-preserving, so hexahedra `(i..i+1, j..j+1, k..k+1)` are positively oriented.
struct Block {
    n: [usize; 3],
    simplices: bool,
}

impl Block {
    fn id(&self, i: usize, j: usize, k: usize) -> usize {
        (k * (self.n[1] + 1) + j) * (self.n[0] + 1) + i
    }

    fn coords(&self, place: impl Fn(usize, usize, usize) -> [f64; 3]) -> Vec<[f64; 3]> {
        let mut coords = Vec::with_capacity((self.n[0] + 1) * (self.n[1] + 1) * (self.n[2] + 1));
        for k in 0..=self.n[2] {
            for j in 0..=self.n[1] {
                for i in 0..=self.n[0] {
                    coords.push(place(i, j, k));
                }
            }
        }
        coords
    }

    /// The node at corner `c` (bits: x, y, z) of cell `(i, j, k)`.
    fn corner(&self, cell: [usize; 3], c: [usize; 3]) -> usize {
        self.id(cell[0] + c[0], cell[1] + c[1], cell[2] + c[2])
    }

    fn elements(&self) -> Vec<Element> {
        let mut elements = Vec::new();
        for k in 0..self.n[2] {
            for j in 0..self.n[1] {
                for i in 0..self.n[0] {
                    let cell = [i, j, k];
                    if self.simplices {
                        // Kuhn: one tetrahedron per path 000 -> 111 along the axes in the order
                        // of a permutation; odd permutations are mirrored, so two nodes swap.
                        for (perm, even) in PERMUTATIONS {
                            let mut c = [0usize; 3];
                            let mut tet = vec![self.corner(cell, c)];
                            for axis in perm {
                                c[axis] = 1;
                                tet.push(self.corner(cell, c));
                            }
                            if !even {
                                tet.swap(1, 2);
                            }
                            elements.push(element(ElementKind::Tet4, &tet));
                        }
                    } else {
                        let hex: Vec<usize> =
                            HEX_CORNERS.iter().map(|&c| self.corner(cell, c)).collect();
                        elements.push(element(ElementKind::Hex8, &hex));
                    }
                }
            }
        }
        elements
    }

    /// The boundary face `axis = side` (`side` 0 or `n[axis]`), as quadrilaterals, or as the
    /// two triangles of Kuhn's triangulation (diagonal from the low corner to the high one).
    fn face(&self, axis: usize, side: usize) -> Vec<Vec<usize>> {
        let (p, q) = match axis {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        let mut facets = Vec::new();
        for b in 0..self.n[q] {
            for a in 0..self.n[p] {
                let node = |da: usize, db: usize| {
                    let mut ijk = [0usize; 3];
                    ijk[axis] = side;
                    ijk[p] = a + da;
                    ijk[q] = b + db;
                    self.id(ijk[0], ijk[1], ijk[2])
                };
                let quad = [node(0, 0), node(1, 0), node(1, 1), node(0, 1)];
                if self.simplices {
                    facets.push(vec![quad[0], quad[1], quad[2]]);
                    facets.push(vec![quad[0], quad[2], quad[3]]);
                } else {
                    facets.push(quad.to_vec());
                }
            }
        }
        facets
    }
}

/// The six permutations of the axes, with their parity.
const PERMUTATIONS: [([usize; 3], bool); 6] = [
    ([0, 1, 2], true),
    ([1, 2, 0], true),
    ([2, 0, 1], true),
    ([0, 2, 1], false),
    ([2, 1, 0], false),
    ([1, 0, 2], false),
];

/// Gmsh's hexahedron corner order as (x, y, z) bits.
const HEX_CORNERS: [[usize; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [1, 1, 0],
    [0, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [1, 1, 1],
    [0, 1, 1],
];

impl VGroove {
    /// Builds the mesh.
    pub fn mesh(&self) -> Result<Mesh, FeError> {
        check_length("bottom_width", self.bottom_width)?;
        check_length("top_width", self.top_width)?;
        check_length("height", self.height)?;
        check_length("length", self.length)?;
        check_divisions(&[("nx", self.nx), ("ny", self.ny), ("nz", self.nz)])?;
        let block = Block {
            n: [self.nx, self.ny, self.nz],
            simplices: self.simplices,
        };
        let coords = block.coords(|i, j, k| {
            let w = half_width(self.bottom_width, self.top_width, k, self.nz);
            [
                w * (2.0 * i as f64 / self.nx as f64 - 1.0),
                self.length * j as f64 / self.ny as f64,
                self.height * k as f64 / self.nz as f64,
            ]
        });
        let elements = block.elements();
        let left = block.face(0, 0);
        let right = block.face(0, self.nx);
        let groups = vec![
            group("contact", 2, [left.clone(), right.clone()].concat()),
            group("left", 2, left),
            group("right", 2, right),
            group("front", 2, block.face(1, 0)),
            group("back", 2, block.face(1, self.ny)),
            group("bottom", 2, block.face(2, 0)),
            group("top", 2, block.face(2, self.nz)),
            body_group(3, &elements),
        ];
        Mesh::new(3, coords, elements, groups)
    }
}

impl Frustum {
    /// Builds the mesh.
    pub fn mesh(&self) -> Result<Mesh, FeError> {
        check_length("bottom_width", self.bottom_width)?;
        check_length("top_width", self.top_width)?;
        check_length("height", self.height)?;
        check_divisions(&[("n", self.n), ("n", self.n), ("nz", self.nz)])?;
        let block = Block {
            n: [self.n, self.n, self.nz],
            simplices: self.simplices,
        };
        let coords = block.coords(|i, j, k| {
            let w = half_width(self.bottom_width, self.top_width, k, self.nz);
            [
                w * (2.0 * i as f64 / self.n as f64 - 1.0),
                w * (2.0 * j as f64 / self.n as f64 - 1.0),
                self.height * k as f64 / self.nz as f64,
            ]
        });
        let elements = block.elements();
        let sides = [
            ("xmin", block.face(0, 0)),
            ("xmax", block.face(0, self.n)),
            ("ymin", block.face(1, 0)),
            ("ymax", block.face(1, self.n)),
        ];
        let contact: Vec<Vec<usize>> = sides.iter().flat_map(|(_, f)| f.clone()).collect();
        let mut groups = vec![group("contact", 2, contact)];
        for (name, facets) in sides {
            groups.push(group(name, 2, facets));
        }
        groups.push(group("bottom", 2, block.face(2, 0)));
        groups.push(group("top", 2, block.face(2, self.nz)));
        groups.push(body_group(3, &elements));
        Mesh::new(3, coords, elements, groups)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signed_measure(mesh: &Mesh, e: &Element) -> f64 {
        let x = mesh.element_coords(e);
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        match e.kind {
            ElementKind::Tri3 | ElementKind::Quad4 => {
                // Shoelace.
                let n = x.len();
                (0..n)
                    .map(|a| x[a][0] * x[(a + 1) % n][1] - x[(a + 1) % n][0] * x[a][1])
                    .sum::<f64>()
                    / 2.0
            }
            ElementKind::Tet4 => {
                let (a, b, c) = (sub(x[1], x[0]), sub(x[2], x[0]), sub(x[3], x[0]));
                (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                    + a[2] * (b[0] * c[1] - b[1] * c[0]))
                    / 6.0
            }
            ElementKind::Hex8 => {
                // Sum of the Kuhn tetrahedra of the corners.
                let tets = [
                    [0, 1, 2, 6],
                    [0, 2, 3, 6],
                    [0, 3, 7, 6],
                    [0, 7, 4, 6],
                    [0, 4, 5, 6],
                    [0, 5, 1, 6],
                ];
                tets.iter()
                    .map(|t| {
                        let e = Element {
                            kind: ElementKind::Tet4,
                            nodes: t.iter().map(|&k| e.nodes[k]).collect(),
                        };
                        signed_measure(mesh, &e)
                    })
                    .sum()
            }
            _ => unreachable!("the generator makes first-order elements"),
        }
    }

    fn total(mesh: &Mesh) -> f64 {
        mesh.elements()
            .iter()
            .map(|e| {
                let v = signed_measure(mesh, e);
                assert!(v > 0.0, "element {:?} has measure {v}", e);
                v
            })
            .sum()
    }

    #[test]
    fn plug2d_area_and_groups() {
        for simplices in [false, true] {
            let p = Plug2d {
                bottom_width: 1.0,
                top_width: 2.0,
                height: 1.0,
                nx: 6,
                ny: 4,
                simplices,
            };
            let mesh = p.mesh().unwrap();
            assert_eq!(mesh.node_count(), 35);
            assert!((total(&mesh) - 1.5).abs() < 1e-12);
            let contact = mesh.group("contact").unwrap();
            assert_eq!(contact.entities.len(), 8);
            assert_eq!(contact.nodes().len(), 10);
        }
    }

    #[test]
    fn vgroove_and_frustum_volumes() {
        for simplices in [false, true] {
            let g = VGroove {
                bottom_width: 1.0,
                top_width: 2.0,
                height: 1.0,
                length: 3.0,
                nx: 3,
                ny: 2,
                nz: 2,
                simplices,
            };
            let mesh = g.mesh().unwrap();
            assert!((total(&mesh) - 4.5).abs() < 1e-12);
            // Frustum volume h/3 (A1 + A2 + sqrt(A1 A2)) = (1 + 4 + 2)/3.
            let f = Frustum {
                bottom_width: 1.0,
                top_width: 2.0,
                height: 1.0,
                n: 3,
                nz: 2,
                simplices,
            };
            let mesh = f.mesh().unwrap();
            assert!((total(&mesh) - 7.0 / 3.0).abs() < 1e-12);
            let faces = if simplices { 2 } else { 1 };
            assert_eq!(
                mesh.group("contact").unwrap().entities.len(),
                4 * 3 * 2 * faces
            );
        }
    }

    #[test]
    fn boundary_triangles_are_faces_of_tetrahedra() {
        let f = Frustum {
            bottom_width: 1.0,
            top_width: 2.0,
            height: 1.0,
            n: 2,
            nz: 2,
            simplices: true,
        };
        let mesh = f.mesh().unwrap();
        for g in mesh.groups().iter().filter(|g| g.dim == 2) {
            for facet in &g.entities {
                assert!(
                    mesh.elements()
                        .iter()
                        .any(|e| facet.iter().all(|a| e.nodes.contains(a))),
                    "facet {facet:?} of {} is no tetrahedron's face",
                    g.name
                );
            }
        }
    }

    #[test]
    fn rejects_bad_parameters() {
        let p = Plug2d {
            bottom_width: 1.0,
            top_width: -2.0,
            height: 1.0,
            nx: 6,
            ny: 4,
            simplices: false,
        };
        assert!(p.mesh().unwrap_err().to_string().contains("top_width"));
        let p = Plug2d { nx: 0, ..p };
        assert!(p.mesh().is_err());
        let f = Frustum {
            bottom_width: 1.0,
            top_width: 2.0,
            height: 1.0,
            n: 100_000,
            nz: 100_000,
            simplices: false,
        };
        assert!(f.mesh().unwrap_err().to_string().contains("limit"));
    }
}
