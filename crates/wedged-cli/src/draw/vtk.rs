//! VTK XML output: one wedged configuration as an UnstructuredGrid (`.vtu`) for ParaView.
//!
//! The file is written with `vtkio` (binary base64 data arrays, `UInt64` headers, no
//! compression) and holds:
//!
//! - the points: every mesh node, `[x, y, z]` (`z = 0` in 2D);
//! - the cells: the body elements, VTK types triangle (5), quad (9), tetra (10) and
//!   hexahedron (12), with the mesh's node order unchanged (see [`cell_type`]);
//! - point data:
//!   - `displacement` (3 components, the active vector, ready for *Warp By Vector*),
//!   - `force` (3 components: the nodal force `K u`, i.e. the reaction of the obstacle at contact
//!     nodes and of the supports at clamped and roller nodes, zero elsewhere),
//!   - `contact_status` (`Int32`, the active scalar), coded as
//!
//!     | code | meaning                                  |
//!     |------|------------------------------------------|
//!     | -1   | not a contact node                       |
//!     | 0    | separated (`u_n > 0`, `r = 0`)           |
//!     | 1    | stick (`|r_t| < mu r_n`)                 |
//!     | 2    | slip+ (2D, `r_t = +mu r_n`)              |
//!     | 3    | slip- (2D, `r_t = -mu r_n`)              |
//!     | 4    | grazing (`u_n = 0`, `r = 0`)             |
//!     | 5    | slip (3D, `||r_t|| = mu r_n > 0`)        |
//!
//!     (codes 0 to 4 are those of the 2D files; 5 was added for 3D sign patterns),
//!
//!   - `normal` (3 components: the unit inward normal of the body at contact nodes, zero
//!     elsewhere; stored as a generic array so that ParaView does not use it for shading),
//!   - `ray_<k>_displacement` (3 components) for each extreme ray `k` of the cone (a cone of a
//!     ray method; a pattern's file shows its witness and has none);
//! - cell data: `von_mises` (the active scalar) and `stress` (6 components, Voigt order
//!   `xx, yy, zz, yz, xz, xy`, named so in the file: ParaView lists `stress_xx` ...), both at
//!   the element centroid;
//! - field data: `title`, a one-tuple string array with [`View::title`] (shown in ParaView's
//!   *Information* panel), also repeated in an XML comment at the top of the file.
//!
//! `vtkio` 0.6 has no XML field data nor component names, so the `FieldData` element, the
//! `ComponentName<i>` attributes and the comment are spliced into the text it writes. The result
//! was checked with VTK 9's own `vtkXMLUnstructuredGridReader` (cell types, positive volumes,
//! arrays, title, component names). Set `WEDGED_VTK_SAMPLE_DIR` when running the tests to keep
//! the files `vtk-sample-2d.vtu` and `vtk-sample-3d.vtu` they write.

use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};
use wedged::fe::boundary::Boundary;
use wedged::fe::{Configuration, ElementKind, Mesh};
use wedged::NodeStatus;

/// Everything needed to draw or export one wedged configuration.
pub struct View<'a> {
    /// The mesh of the body.
    pub mesh: &'a Mesh,
    /// Its boundary conditions (contact nodes and frames, contact facets, clamps, rollers).
    pub boundary: &'a Boundary,
    /// Status of each contact node, in the order of `boundary.contact_nodes`.
    pub status: &'a [NodeStatus],
    /// The representative state of the piece: a cone's centroid or a pattern's witness
    /// (normalised: sum of normal reactions = 1).
    pub state: &'a Configuration,
    /// The cone's extreme rays: (ray number, state), each normalised the same way; empty for a
    /// pattern.
    pub rays: &'a [(usize, &'a Configuration)],
    /// One line describing the configuration, e.g. `cone 2 of 3, mu = 0.8: 2 rays, ...`.
    pub title: String,
}

/// The `contact_status` code of a contact node's status (see the module documentation).
pub fn status_code(status: NodeStatus) -> i32 {
    match status {
        NodeStatus::Separated => 0,
        NodeStatus::Stick => 1,
        NodeStatus::SlipPlus => 2,
        NodeStatus::SlipMinus => 3,
        NodeStatus::Grazing => 4,
        NodeStatus::Slip => 5,
    }
}

/// The VTK cell type of an element kind.
///
/// Gmsh and VTK number the nodes of these linear elements identically: triangle and quad
/// counterclockwise; tetrahedron with `0-1-2` a face whose right-hand normal points towards node
/// `3`; hexahedron with the face `0-1-2-3` whose right-hand normal points towards the face
/// `4-5-6-7`, node `4 + i` above node `i`. The second-order triangle and quadrilaterals add
/// their mid-edge nodes (and centre) in the same order in both; the 10-node tetrahedron's last
/// two mid-edge nodes are swapped ([`ElementKind::vtk_order`]).
pub fn cell_type(kind: ElementKind) -> CellType {
    match kind {
        ElementKind::Tri3 => CellType::Triangle,
        ElementKind::Quad4 => CellType::Quad,
        ElementKind::Tet4 => CellType::Tetra,
        ElementKind::Hex8 => CellType::Hexahedron,
        ElementKind::Tri6 => CellType::QuadraticTriangle,
        ElementKind::Quad8 => CellType::QuadraticQuad,
        ElementKind::Quad9 => CellType::BiquadraticQuad,
        ElementKind::Tet10 => CellType::QuadraticTetra,
    }
}

/// Checks that the sizes of a view's arrays match its mesh and boundary.
pub fn check_view(view: &View) -> Result<(), String> {
    let nodes = view.mesh.node_count();
    let elements = view.mesh.elements().len();
    let contacts = view.boundary.contact_nodes.len();
    if view.boundary.frames.len() != contacts {
        return Err(format!(
            "{} contact nodes but {} contact frames",
            contacts,
            view.boundary.frames.len()
        ));
    }
    if view.status.len() != contacts {
        return Err(format!(
            "{} contact nodes but {} statuses",
            contacts,
            view.status.len()
        ));
    }
    let referenced = view
        .boundary
        .contact_nodes
        .iter()
        .chain(view.boundary.clamped.iter())
        .chain(view.boundary.rollers.iter().map(|(a, _)| a))
        .chain(view.boundary.contact_facets.iter().flatten());
    if let Some(&a) = referenced.into_iter().find(|&&a| a >= nodes) {
        return Err(format!(
            "the boundary refers to node {}, but the mesh has {} nodes",
            a + 1,
            nodes
        ));
    }
    let states = std::iter::once(("the state".to_string(), view.state))
        .chain(view.rays.iter().map(|(k, c)| (format!("ray {k}"), *c)));
    for (what, c) in states {
        let sizes = [
            ("displacements", c.displacement.len(), nodes, "nodes"),
            ("forces", c.force.len(), nodes, "nodes"),
            ("stresses", c.stress.len(), elements, "elements"),
            (
                "von Mises stresses",
                c.von_mises.len(),
                elements,
                "elements",
            ),
        ];
        for (name, got, expected, of) in sizes {
            if got != expected {
                return Err(format!(
                    "{what} has {got} {name}, but the mesh has {expected} {of}"
                ));
            }
        }
    }
    Ok(())
}

fn flatten<const N: usize>(values: &[[f64; N]]) -> Vec<f64> {
    values.iter().flatten().copied().collect()
}

fn vector(name: &str, values: &[[f64; 3]], active: bool) -> Attribute {
    let elem = if active {
        ElementType::Vectors
    } else {
        ElementType::Generic(3)
    };
    Attribute::DataArray(DataArray {
        name: name.to_string(),
        elem,
        data: IOBuffer::F64(flatten(values)),
    })
}

/// The `FieldData` element holding the title as a VTK string array (ASCII: the bytes as integers,
/// each string terminated by 0).
fn title_field_data(title: &str) -> String {
    let bytes: Vec<String> = title
        .bytes()
        .filter(|&b| b != 0)
        .chain(std::iter::once(0))
        .map(|b| b.to_string())
        .collect();
    format!(
        "<FieldData><DataArray type=\"String\" Name=\"title\" NumberOfTuples=\"1\" \
         format=\"ascii\">{}</DataArray></FieldData>",
        bytes.join(" ")
    )
}

/// The title as an XML comment (no `--` inside, no control characters).
fn title_comment(title: &str) -> String {
    let mut text: String = title
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    while text.contains("--") {
        text = text.replace("--", "- -");
    }
    format!("<!-- {} -->", text.trim_end_matches('-'))
}

/// Builds the `vtkio` model of a view.
fn model(view: &View) -> Vtk {
    let mesh = view.mesh;
    let boundary = view.boundary;
    let state = view.state;
    let nodes = mesh.node_count();

    let mut connectivity = Vec::new();
    let mut offsets = Vec::new();
    let mut types = Vec::new();
    for element in mesh.elements() {
        connectivity.extend(
            element
                .kind
                .vtk_order(&element.nodes)
                .into_iter()
                .map(|a| a as u64),
        );
        offsets.push(connectivity.len() as u64);
        types.push(cell_type(element.kind));
    }

    let mut status = vec![-1i32; nodes];
    let mut normal = vec![[0.0; 3]; nodes];
    for ((&a, &s), frame) in boundary
        .contact_nodes
        .iter()
        .zip(view.status)
        .zip(&boundary.frames)
    {
        status[a] = status_code(s);
        normal[a] = frame.n;
    }

    let mut point = vec![
        vector("displacement", &state.displacement, true),
        vector("force", &state.force, false),
        Attribute::DataArray(DataArray {
            name: "contact_status".to_string(),
            elem: ElementType::Scalars {
                num_comp: 1,
                lookup_table: None,
            },
            data: IOBuffer::I32(status),
        }),
        vector("normal", &normal, false),
    ];
    for (k, ray) in view.rays {
        point.push(vector(
            &format!("ray_{k}_displacement"),
            &ray.displacement,
            false,
        ));
    }
    let cell = vec![
        Attribute::DataArray(DataArray {
            name: "von_mises".to_string(),
            elem: ElementType::Scalars {
                num_comp: 1,
                lookup_table: None,
            },
            data: IOBuffer::F64(state.von_mises.clone()),
        }),
        Attribute::DataArray(DataArray {
            name: "stress".to_string(),
            elem: ElementType::Generic(6),
            data: IOBuffer::F64(flatten(&state.stress)),
        }),
    ];

    Vtk {
        version: Version::new((1, 0)),
        title: view.title.clone(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(flatten(mesh.coords())),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types,
            },
            data: Attributes { point, cell },
        }),
    }
}

/// The `.vtu` file of one wedged configuration (see the module documentation for its contents).
///
/// Fails if the view's arrays do not match its mesh, or if `vtkio` fails.
pub fn vtu_bytes(view: &View) -> Result<Vec<u8>, String> {
    check_view(view)?;
    let mut raw = Vec::new();
    model(view)
        .write_xml(&mut raw)
        .map_err(|e| format!("cannot write the VTK file: {e}"))?;
    let text = String::from_utf8(raw).map_err(|e| format!("vtkio wrote invalid UTF-8: {e}"))?;
    // Splice in the title: a comment after the XML declaration, field data before the piece.
    let tag = "<UnstructuredGrid>";
    let at = text
        .find(tag)
        .ok_or_else(|| "vtkio wrote no <UnstructuredGrid> element".to_string())?
        + tag.len();
    let mut out = String::with_capacity(text.len() + 4 * view.title.len() + 300);
    out.push_str("<?xml version=\"1.0\"?>\n");
    out.push_str(&title_comment(&view.title));
    out.push('\n');
    out.push_str(&text[..at]);
    out.push_str(&title_field_data(&view.title));
    // Name the stress components, so that ParaView lists `stress xx` ... rather than `stress 0`.
    let stress = "Name=\"stress\"";
    let rest = &text[at..];
    match rest.find(stress) {
        Some(s) => {
            let names: String = ["xx", "yy", "zz", "yz", "xz", "xy"]
                .iter()
                .enumerate()
                .map(|(i, c)| format!(" ComponentName{i}=\"{c}\""))
                .collect();
            out.push_str(&rest[..s + stress.len()]);
            out.push_str(&names);
            out.push_str(&rest[s + stress.len()..]);
        }
        None => out.push_str(rest),
    }
    out.push('\n');
    Ok(out.into_bytes())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use wedged::fe::boundary::Frame;
    use wedged::fe::Element;

    /// A configuration with recognisable values: displacement of node `a` is
    /// `[a, 10 a, 100 a] * scale`, force `[-a, 0, a]`, stress of element `e` is `e + [1..6]`.
    pub(crate) fn configuration(nodes: usize, elements: usize, scale: f64) -> Configuration {
        Configuration {
            displacement: (0..nodes)
                .map(|a| {
                    let a = a as f64 * scale;
                    [a, 10.0 * a, 100.0 * a]
                })
                .collect(),
            force: (0..nodes).map(|a| [-(a as f64), 0.0, a as f64]).collect(),
            stress: (0..elements)
                .map(|e| {
                    let e = e as f64;
                    [e + 1.0, e + 2.0, e + 3.0, e + 4.0, e + 5.0, e + 6.0]
                })
                .collect(),
            von_mises: (0..elements).map(|e| 7.0 + e as f64).collect(),
        }
    }

    fn frame(n: [f64; 3]) -> Frame {
        Frame {
            n,
            t1: [n[1], -n[0], 0.0],
            t2: [0.0; 3],
        }
    }

    /// 2D: a unit square of one quad (nodes 0..4) with a triangle on top (node 4).
    fn mesh_2d() -> (Mesh, Boundary) {
        let coords = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 1.5, 0.0],
        ];
        let elements = vec![
            Element {
                kind: ElementKind::Quad4,
                nodes: vec![0, 1, 2, 3],
            },
            Element {
                kind: ElementKind::Tri3,
                nodes: vec![3, 2, 4],
            },
        ];
        let mesh = Mesh::new(2, coords, elements, vec![]).unwrap();
        let boundary = Boundary {
            contact_nodes: vec![0, 1],
            frames: vec![frame([0.0, 1.0, 0.0]), frame([0.0, 1.0, 0.0])],
            contact_facets: vec![vec![0, 1]],
            clamped: vec![4],
            rollers: vec![],
            clamped_contact: 0,
        };
        (mesh, boundary)
    }

    /// 3D: a unit cube hex (nodes 0..8) with a tetrahedron on its top face (node 8).
    fn mesh_3d() -> (Mesh, Boundary) {
        let coords = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
            [0.5, 0.5, 2.0],
        ];
        let elements = vec![
            Element {
                kind: ElementKind::Hex8,
                nodes: (0..8).collect(),
            },
            Element {
                kind: ElementKind::Tet4,
                nodes: vec![4, 5, 6, 8],
            },
        ];
        let mesh = Mesh::new(3, coords, elements, vec![]).unwrap();
        let boundary = Boundary {
            contact_nodes: vec![0, 1, 2, 3],
            frames: vec![frame([0.0, 0.0, 1.0]); 4],
            contact_facets: vec![vec![0, 3, 2, 1]],
            clamped: vec![8],
            rollers: vec![],
            clamped_contact: 0,
        };
        (mesh, boundary)
    }

    fn parse(bytes: &[u8]) -> UnstructuredGridPiece {
        let vtk = Vtk::parse_xml(bytes).expect("vtkio parses its own output back");
        match vtk.data {
            DataSet::UnstructuredGrid { mut pieces, .. } => {
                assert_eq!(pieces.len(), 1);
                pieces
                    .remove(0)
                    .into_loaded_piece_data(None)
                    .expect("inline piece")
            }
            other => panic!("not an unstructured grid: {other:?}"),
        }
    }

    fn array<'p>(attributes: &'p [Attribute], name: &str) -> &'p DataArray {
        attributes
            .iter()
            .find_map(|a| match a {
                Attribute::DataArray(d) if d.name == name => Some(d),
                _ => None,
            })
            .unwrap_or_else(|| panic!("no array '{name}'"))
    }

    fn f64s(d: &DataArray) -> Vec<f64> {
        d.data.clone().cast_into::<f64>().expect("numeric array")
    }

    fn names(attributes: &[Attribute]) -> Vec<String> {
        attributes.iter().map(|a| a.name().to_string()).collect()
    }

    fn round_trip(mesh: &Mesh, boundary: &Boundary, status: &[NodeStatus], types: &[CellType]) {
        let nodes = mesh.node_count();
        let elements = mesh.elements().len();
        let state = configuration(nodes, elements, 1.0);
        let ray1 = configuration(nodes, elements, 2.0);
        let ray3 = configuration(nodes, elements, 3.0);
        let rays = [(1, &ray1), (3, &ray3)];
        let view = View {
            mesh,
            boundary,
            status,
            state: &state,
            rays: &rays,
            title: "cone 1 of 1, mu = 0.8: 2 rays <&>".to_string(),
        };
        let bytes = vtu_bytes(&view).unwrap();
        if let Some(dir) = std::env::var_os("WEDGED_VTK_SAMPLE_DIR") {
            let path = std::path::Path::new(&dir).join(format!("vtk-sample-{}d.vtu", mesh.dim()));
            std::fs::write(path, &bytes).unwrap();
        }
        let text = String::from_utf8(bytes.clone()).unwrap();
        assert!(text.starts_with("<?xml"));
        assert!(text.contains("<!-- cone 1 of 1, mu = 0.8: 2 rays <&> -->"));
        assert!(text.contains("<FieldData><DataArray type=\"String\" Name=\"title\""));
        assert!(text.contains("type=\"UnstructuredGrid\""));
        assert!(text.contains("Name=\"stress\" ComponentName0=\"xx\""));
        assert!(text.contains("ComponentName5=\"xy\""));

        let piece = parse(&bytes);
        assert_eq!(piece.num_points(), nodes);
        assert_eq!(
            piece.points.clone().cast_into::<f64>().unwrap(),
            flatten(mesh.coords())
        );
        assert_eq!(piece.cells.types, types);
        let (connectivity, offsets) = piece.cells.cell_verts.clone().into_xml();
        let expected: Vec<u64> = mesh
            .elements()
            .iter()
            .flat_map(|e| e.nodes.iter().map(|&a| a as u64))
            .collect();
        assert_eq!(connectivity, expected);
        assert_eq!(offsets.len(), elements);
        assert_eq!(*offsets.last().unwrap() as usize, expected.len());

        let point = &piece.data.point;
        assert_eq!(
            names(point),
            [
                "displacement",
                "force",
                "contact_status",
                "normal",
                "ray_1_displacement",
                "ray_3_displacement"
            ]
        );
        for name in ["displacement", "force", "normal", "ray_1_displacement"] {
            let d = array(point, name);
            assert_eq!(d.num_comp(), 3, "{name}");
            assert_eq!(d.len(), nodes * 3, "{name}");
            assert_eq!(d.scalar_type(), vtkio::model::ScalarType::F64, "{name}");
        }
        assert_eq!(
            f64s(array(point, "displacement")),
            flatten(&state.displacement)
        );
        assert_eq!(f64s(array(point, "force")), flatten(&state.force));
        assert_eq!(
            f64s(array(point, "ray_3_displacement")),
            flatten(&ray3.displacement)
        );
        let code = array(point, "contact_status");
        assert_eq!(code.num_comp(), 1);
        assert_eq!(code.scalar_type(), vtkio::model::ScalarType::I32);
        let codes = code.data.clone().into_vec::<i32>().unwrap();
        assert_eq!(codes.len(), nodes);
        let normals = f64s(array(point, "normal"));
        for a in 0..nodes {
            match boundary.contact_nodes.iter().position(|&c| c == a) {
                Some(i) => {
                    assert_eq!(codes[a], status_code(status[i]));
                    assert_eq!(normals[3 * a..3 * a + 3], boundary.frames[i].n);
                }
                None => {
                    assert_eq!(codes[a], -1);
                    assert_eq!(normals[3 * a..3 * a + 3], [0.0; 3]);
                }
            }
        }

        let cell = &piece.data.cell;
        assert_eq!(names(cell), ["von_mises", "stress"]);
        let vm = array(cell, "von_mises");
        assert_eq!(vm.num_comp(), 1);
        assert_eq!(f64s(vm), state.von_mises);
        let stress = array(cell, "stress");
        assert_eq!(stress.num_comp(), 6);
        assert_eq!(f64s(stress), flatten(&state.stress));
    }

    #[test]
    fn vtk_round_trip_2d_quad_and_triangle() {
        let (mesh, boundary) = mesh_2d();
        round_trip(
            &mesh,
            &boundary,
            &[NodeStatus::Stick, NodeStatus::SlipMinus],
            &[CellType::Quad, CellType::Triangle],
        );
    }

    #[test]
    fn vtk_round_trip_3d_hex_and_tet() {
        let (mesh, boundary) = mesh_3d();
        round_trip(
            &mesh,
            &boundary,
            &[
                NodeStatus::Separated,
                NodeStatus::Slip,
                NodeStatus::Grazing,
                NodeStatus::Stick,
            ],
            &[CellType::Hexahedron, CellType::Tetra],
        );
    }

    #[test]
    fn vtk_status_codes_are_distinct_and_documented() {
        let all = [
            NodeStatus::Separated,
            NodeStatus::Stick,
            NodeStatus::SlipPlus,
            NodeStatus::SlipMinus,
            NodeStatus::Grazing,
            NodeStatus::Slip,
        ];
        let codes: Vec<i32> = all.iter().map(|&s| status_code(s)).collect();
        assert_eq!(codes, [0, 1, 2, 3, 4, 5]);
    }

    #[test]
    fn vtk_cell_type_codes() {
        assert_eq!(cell_type(ElementKind::Tri3) as u8, 5);
        assert_eq!(cell_type(ElementKind::Quad4) as u8, 9);
        assert_eq!(cell_type(ElementKind::Tet4) as u8, 10);
        assert_eq!(cell_type(ElementKind::Hex8) as u8, 12);
        let (mesh, boundary) = mesh_3d();
        let state = configuration(9, 2, 1.0);
        let view = View {
            mesh: &mesh,
            boundary: &boundary,
            status: &[NodeStatus::Stick; 4],
            state: &state,
            rays: &[],
            title: String::new(),
        };
        let text = String::from_utf8(vtu_bytes(&view).unwrap()).unwrap();
        // The raw types array: UInt8 12 and 10 after an 8-byte length header.
        let types = text
            .split("Name=\"types\"")
            .nth(1)
            .and_then(|rest| rest.split('>').nth(1))
            .and_then(|rest| rest.split('<').next())
            .unwrap()
            .trim()
            .to_string();
        assert_eq!(types, "AgAAAAAAAAAMCg==");
    }

    /// The orientation conventions that make Gmsh and VTK node orders coincide: the mesh's
    /// outward facets put the hexahedron's face `0-1-2-3` with its normal towards `4-7` (reversed
    /// first facet `0-3-2-1`), and the tetrahedron's `0-1-2` with its normal towards `3`.
    #[test]
    fn vtk_node_orders_match_gmsh() {
        assert_eq!(ElementKind::Hex8.facets()[0], &[0, 3, 2, 1]);
        assert_eq!(ElementKind::Hex8.facets()[1], &[4, 5, 6, 7]);
        assert_eq!(ElementKind::Tet4.facets()[0], &[0, 2, 1]);
        let (mesh, _) = mesh_3d();
        let x = mesh.coords();
        let sub = |a: usize, b: usize| [x[a][0] - x[b][0], x[a][1] - x[b][1], x[a][2] - x[b][2]];
        let cross = |u: [f64; 3], v: [f64; 3]| {
            [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ]
        };
        let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        // Hex: (x1-x0) x (x3-x0) points towards node 4 (VTK's hexahedron convention).
        assert!(dot(cross(sub(1, 0), sub(3, 0)), sub(4, 0)) > 0.0);
        // Tet 4,5,6,8: (x5-x4) x (x6-x4) . (x8-x4) > 0 (VTK's tetra convention).
        assert!(dot(cross(sub(5, 4), sub(6, 4)), sub(8, 4)) > 0.0);
    }

    #[test]
    fn vtk_rejects_mismatched_sizes() {
        let (mesh, boundary) = mesh_2d();
        let state = configuration(4, 2, 1.0);
        let view = View {
            mesh: &mesh,
            boundary: &boundary,
            status: &[NodeStatus::Stick; 2],
            state: &state,
            rays: &[],
            title: String::new(),
        };
        let err = vtu_bytes(&view).unwrap_err();
        assert!(err.contains("4 displacements"), "{err}");
        let state = configuration(5, 2, 1.0);
        let view = View {
            status: &[NodeStatus::Stick],
            state: &state,
            ..view
        };
        assert!(vtu_bytes(&view).unwrap_err().contains("1 statuses"));
    }

    #[test]
    fn vtk_title_comment_is_safe() {
        assert_eq!(title_comment("a--b-"), "<!-- a- -b -->");
        assert_eq!(title_field_data("AB"), "<FieldData><DataArray type=\"String\" Name=\"title\" NumberOfTuples=\"1\" format=\"ascii\">65 66 0</DataArray></FieldData>");
    }
}
