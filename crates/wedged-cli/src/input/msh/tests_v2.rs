//! Tests of `msh/v2.rs`: the legacy MSH 2.2 format.

use super::tests::{assert_same_mesh, body_as_group, counts, error, fixture, group, load, owned};
use super::*;
use wedged::fe::ElementKind;

// --- MSH 2.2 --------------------------------------------------------------------------------

/// Gmsh's MSH 2.2 files of a model (ASCII and binary) read as its MSH 4.1 file: the same nodes
/// in the same order, the same body elements (each once, though the 2.2 file writes a line
/// element of two groups twice) and the same groups.
#[test]
fn msh22_reads_as_its_msh41_twin() {
    for (v41, v22) in [
        ("plug2d_quad.msh", "plug2d_quad_22.msh"),
        ("plug2d_quad.msh", "plug2d_quad_22_bin.msh"),
        ("box3d_tet.msh", "box3d_tet_22.msh"),
    ] {
        assert_same_mesh(&load(v41), &load(v22), v22);
    }
    // The unit square of the fixtures: 3-node triangles, a bottom line and the body.
    let mesh = load("msh22.msh");
    assert_eq!(mesh.dim(), 2);
    assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Tri3));
    let names: Vec<&str> = mesh.groups().iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["bottom", "body"]);
    assert_eq!(group(&mesh, "body").entities, body_as_group(&mesh));
}

/// An ASCII MSH 2.2 file of two triangles on the unit square, with `elements` (each line
/// `type ntags tags... nodes...`, numbered here) and `names` (`dim tag "name"` lines).
fn square22(names: &[&str], elements: &[&str]) -> String {
    let mut text = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
    if !names.is_empty() {
        text += &format!("$PhysicalNames\n{}\n", names.len());
        for n in names {
            text += &format!("{n}\n");
        }
        text += "$EndPhysicalNames\n";
    }
    text += "$Nodes\n4\n7 0 0 0\n3 1 0 0\n9 1 1 0\n1 0 1 0\n$EndNodes\n";
    text += &format!("$Elements\n{}\n", elements.len());
    for (k, e) in elements.iter().enumerate() {
        text += &format!("{} {e}\n", k + 1);
    }
    text + "$EndElements\n"
}

const TRIANGLES: [&str; 2] = ["2 2 5 1 7 3 9", "2 2 5 1 7 9 1"];

#[test]
fn msh22_groups_points_and_copies() {
    // The body in two physical surfaces (each triangle written twice), a physical point, a
    // line without a physical group, a named group without elements, an unnamed group.
    let text = square22(
        &[
            r#"2 5 "body""#,
            r#"2 6 "also""#,
            r#"1 4 "unused""#,
            r#"0 2 "origin""#,
        ],
        &[
            "15 2 2 1 7",
            "1 2 0 1 7 3",
            "1 2 8 2 3 9",
            TRIANGLES[0],
            "2 2 6 1 7 3 9",
            TRIANGLES[1],
            "2 2 6 1 7 9 1",
        ],
    );
    let mesh = parse(text.as_bytes(), "s.msh").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        body_as_group(&mesh),
        [vec![0, 1, 2], vec![0, 2, 3]],
        "each triangle once, nodes by their place in $Nodes"
    );
    assert_eq!(
        counts(&mesh),
        owned(&[
            ("origin", 0, 1, 1),
            ("unused", 1, 0, 0),
            ("1:8", 1, 1, 2),
            ("body", 2, 2, 4),
            ("also", 2, 2, 4),
        ])
    );
}

#[test]
fn msh22_errors() {
    let cases: Vec<(String, &str)> = vec![
        (
            square22(&[], &[TRIANGLES[0], "2 2 5 1 7 9 4"]),
            "element 2 refers to node 4, which is not in $Nodes",
        ),
        (
            square22(&[], &["21 2 5 1 7 3 9 1 1 1 1 1 1 1"]),
            "element type 21 (10-node third-order triangle) is not supported; use first-order",
        ),
        (
            square22(&[], &[TRIANGLES[0], "9 2 5 1 7 9 1 1 1 1"]),
            "the body mixes first- and second-order elements",
        ),
        (
            square22(&[], &["1 2 5 1 7 3"]),
            "the file has no 2D or 3D elements",
        ),
        (
            square22(&[], &["99 2 5 1 7 3"]),
            "element type 99 (higher-order or special element) is not supported",
        ),
        (
            square22(&[], &["2 80 5 1 7 3 9"]),
            "malformed MSH file at line 13: element 1 has 80 tags (in $Elements)",
        ),
        (
            square22(&[], &TRIANGLES).replace("3 1 0 0", "7 1 0 0"),
            "node tag 7 is defined twice in $Nodes",
        ),
        (
            square22(&[], &TRIANGLES).replace("1 0 1 0", "1 0 1 x"),
            "malformed MSH file at line 9: expected node 1's coordinates (in $Nodes)",
        ),
        (
            square22(&[], &TRIANGLES).replace("$Elements\n2", "$Elements\n3"),
            "the file ends too early in its $Elements section",
        ),
        (
            square22(&[], &TRIANGLES).replace("$Elements\n2", "$Elements\n1"),
            "expected $EndElements after the entries the count announced",
        ),
        (
            square22(&[], &TRIANGLES).replace("$Nodes\n4", "$Nodes\n0"),
            "the file has no nodes",
        ),
        (
            square22(&[], &TRIANGLES).replace("9 1 1 0", "9 1 1 0.5"),
            "2D mesh is not planar in z",
        ),
        (
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n".to_string(),
            "the file has no $Nodes section",
        ),
    ];
    for (text, expected) in cases {
        let e = error(text.as_bytes(), "s.msh");
        assert!(e.contains(expected), "{e}\nexpected: {expected}");
    }
}

/// The binary MSH 2.2 fixture with every number's bytes reversed (a big-endian machine's
/// file) reads as the little-endian one.
#[test]
fn msh22_binary_either_byte_order() {
    let bytes = std::fs::read(fixture("plug2d_quad_22_bin.msh")).unwrap();
    let mut swapped = bytes.clone();
    // Little-endian 32-bit integers and 64-bit doubles between the count lines and the end
    // tags of $Nodes and $Elements, and the integer 1 of the header.
    let find = |tag: &[u8], from: usize| {
        from + bytes[from..]
            .windows(tag.len())
            .position(|w| w == tag)
            .unwrap()
    };
    let one = find(b"2.2 1 8\n", 0) + 8;
    swapped[one..one + 4].reverse();
    let after_count = |tag: &[u8]| {
        let at = find(tag, 0) + tag.len();
        at + bytes[at..].iter().position(|&b| b == b'\n').unwrap() + 1
    };
    let mut at = after_count(b"$Nodes\n");
    while at < find(b"\n$EndNodes", 0) {
        swapped[at..at + 4].reverse();
        for k in 0..3 {
            swapped[at + 4 + 8 * k..at + 12 + 8 * k].reverse();
        }
        at += 28;
    }
    let end = find(b"\n$EndElements", 0);
    let mut at = after_count(b"$Elements\n");
    while at < end {
        swapped[at..at + 4].reverse();
        at += 4;
    }
    let a = parse(&bytes, "le.msh").unwrap();
    let b = parse(&swapped, "be.msh").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(a.coords(), b.coords());
    assert_eq!(a.elements(), b.elements());
    assert_eq!(a.groups(), b.groups());
}
