//! Gmsh's element types: their names and dimensions, the ones a body or its boundary may
//! have, and the errors for the others.

use wedged::fe::ElementKind;

/// Gmsh's name and dimension of an element type.
pub(super) fn type_info(t: i32) -> (&'static str, Option<i32>) {
    match t {
        1 => ("2-node line", Some(1)),
        2 => ("3-node triangle", Some(2)),
        3 => ("4-node quadrangle", Some(2)),
        4 => ("4-node tetrahedron", Some(3)),
        5 => ("8-node hexahedron", Some(3)),
        6 => ("6-node prism", Some(3)),
        7 => ("5-node pyramid", Some(3)),
        8 => ("3-node second-order line", Some(1)),
        9 => ("6-node second-order triangle", Some(2)),
        10 => ("9-node second-order quadrangle", Some(2)),
        11 => ("10-node second-order tetrahedron", Some(3)),
        12 => ("27-node second-order hexahedron", Some(3)),
        13 => ("18-node second-order prism", Some(3)),
        14 => ("14-node second-order pyramid", Some(3)),
        15 => ("1-node point", Some(0)),
        16 => ("8-node second-order quadrangle", Some(2)),
        17 => ("20-node second-order hexahedron", Some(3)),
        18 => ("15-node second-order prism", Some(3)),
        19 => ("13-node second-order pyramid", Some(3)),
        20 => ("9-node third-order incomplete triangle", Some(2)),
        21 => ("10-node third-order triangle", Some(2)),
        22 => ("12-node fourth-order incomplete triangle", Some(2)),
        23 => ("15-node fourth-order triangle", Some(2)),
        24 => ("15-node fifth-order incomplete triangle", Some(2)),
        25 => ("21-node fifth-order triangle", Some(2)),
        26 => ("4-node third-order line", Some(1)),
        27 => ("5-node fourth-order line", Some(1)),
        28 => ("6-node fifth-order line", Some(1)),
        29 => ("20-node third-order tetrahedron", Some(3)),
        30 => ("35-node fourth-order tetrahedron", Some(3)),
        31 => ("56-node fifth-order tetrahedron", Some(3)),
        92 => ("64-node third-order hexahedron", Some(3)),
        93 => ("125-node fourth-order hexahedron", Some(3)),
        _ => ("higher-order or special element", None),
    }
}

/// The error for an element type this reader does not take.
pub(super) fn unsupported(t: i32, mesh_dim: i32) -> String {
    let (name, _) = type_info(t);
    let hint = if matches!(t, 1..=11 | 15 | 16) {
        if mesh_dim == 3 {
            "3D bodies must be meshed with tetrahedra (4 or 10 nodes) or 8-node hexahedra"
        } else {
            "2D bodies must be meshed with triangles (3 or 6 nodes) or quadrangles (4, 8 or 9 \
             nodes)"
        }
    } else {
        "use first-order elements (Mesh.ElementOrder = 1), or second-order triangles, \
         quadrangles or tetrahedra (Mesh.ElementOrder = 2)"
    };
    format!("element type {t} ({name}) is not supported; {hint}")
}

/// The mesh's dimension from its elements' (Gmsh type, dimension) pairs: the highest, which
/// must be 2 or 3 (see the error for a file without a body).
pub(super) fn mesh_dim(types: impl Iterator<Item = (i32, i32)>) -> Result<i32, String> {
    let dim = types.map(|(_, d)| d).max().unwrap_or(-1);
    if dim < 2 {
        return Err(
            "the file has no 2D or 3D elements; Gmsh saves only the elements of physical \
             groups: add a physical surface (2D) or volume (3D) for the body, or set \
             Mesh.SaveAll = 1"
                .to_string(),
        );
    }
    if dim > 3 {
        return Err(format!("the file has elements of dimension {dim}"));
    }
    Ok(dim)
}

/// Checks that every element type (with its dimension) is one this reader takes in a
/// `dim`-dimensional mesh: body types first, so that a second-order mesh is reported by its
/// body element type; then the boundary's points, lines and (3D) faces, of the body's order
/// (2-node lines and 3- or 4-node faces with first-order bodies, 3-node lines and 6-node
/// triangles with second-order ones, as Gmsh writes them).
pub(super) fn check_types(
    types: impl Iterator<Item = (i32, i32)> + Clone,
    dim: i32,
) -> Result<(), String> {
    let mut orders = Vec::new();
    for (t, d) in types.clone().filter(|&(_, d)| d == dim) {
        let kind = body_kind(t, d).ok_or_else(|| unsupported(t, dim))?;
        let second = kind.linear() != kind;
        if !orders.contains(&second) {
            orders.push(second);
        }
    }
    if orders.len() > 1 {
        return Err(
            "the body mixes first- and second-order elements; mesh it with one \
                    Mesh.ElementOrder"
                .to_string(),
        );
    }
    let second = orders.first() == Some(&true);
    for (t, d) in types.filter(|&(_, d)| d != dim) {
        let ok = match (d, second) {
            (0, _) => t == 15,
            (1, false) => t == 1,
            (1, true) => t == 8,
            (2, false) => t == 2 || t == 3,
            (2, true) => t == 9,
            _ => false,
        };
        if !ok {
            if matches!(t, 1..=3 | 8 | 9) {
                let body = if second { "second" } else { "first" };
                return Err(format!(
                    "element type {t} ({}) is not of the order of the body's elements \
                     ({body} order); save the mesh after setting its order (Mesh.ElementOrder)",
                    type_info(t).0
                ));
            }
            return Err(unsupported(t, dim));
        }
    }
    Ok(())
}

/// The body element kind of Gmsh type `t` in a `dim`-dimensional block.
pub(super) fn body_kind(t: i32, dim: i32) -> Option<ElementKind> {
    match (dim, t) {
        (2, 2) => Some(ElementKind::Tri3),
        (2, 3) => Some(ElementKind::Quad4),
        (3, 4) => Some(ElementKind::Tet4),
        (3, 5) => Some(ElementKind::Hex8),
        (2, 9) => Some(ElementKind::Tri6),
        (2, 16) => Some(ElementKind::Quad8),
        (2, 10) => Some(ElementKind::Quad9),
        (3, 11) => Some(ElementKind::Tet10),
        _ => None,
    }
}
