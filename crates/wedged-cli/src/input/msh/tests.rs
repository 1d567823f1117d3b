//! Tests of `msh.rs`.

use super::*;
use wedged::fe::ElementKind;

pub(super) fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/msh")).join(name)
}

pub(super) fn load(name: &str) -> Mesh {
    read(&fixture(name)).unwrap_or_else(|e| panic!("{e}"))
}

pub(super) fn group<'a>(mesh: &'a Mesh, name: &str) -> &'a Group {
    mesh.group(name)
        .unwrap_or_else(|| panic!("no group '{name}' in {}", mesh.group_names()))
}

/// The Gmsh-written plug and the generator's plug (same nodes, other numbering) condense to
/// the same `K`, up to the order of the contact nodes.
#[test]
fn gmsh_plug_condenses_like_the_generated_one() {
    use wedged::fe::generate::Plug2d;
    use wedged::fe::{BoundarySpec, ContactSpec, Material, Model, Plane};
    let spec = BoundarySpec {
        contact: vec![ContactSpec {
            group: "contact".into(),
            normal: None,
        }],
        clamp: vec!["top".into()],
        symmetry: vec![],
    };
    let material = Material::new(210e9, 0.3, Plane::Strain).unwrap();
    let generated = Plug2d {
        bottom_width: 1.0,
        top_width: 2.0,
        height: 1.0,
        nx: 6,
        ny: 4,
        simplices: false,
    }
    .mesh()
    .unwrap();
    let a = Model::build(generated, material, &spec).unwrap();
    for file in ["plug2d_quad.msh", "plug2d_quad_bin.msh"] {
        let b = Model::build(load(file), material, &spec).unwrap();
        let (ba, bb) = (a.boundary(), b.boundary());
        assert_eq!(ba.contact_nodes.len(), bb.contact_nodes.len());
        // Contact node i of `a` is node perm[i] of `b`: the one at the same place.
        let perm: Vec<usize> = ba
            .contact_nodes
            .iter()
            .map(|&p| {
                let x = a.mesh().coords()[p];
                bb.contact_nodes
                    .iter()
                    .position(|&q| {
                        let y = b.mesh().coords()[q];
                        (x[0] - y[0]).abs() < 1e-9 && (x[1] - y[1]).abs() < 1e-9
                    })
                    .expect("the same contact nodes")
            })
            .collect();
        let (ka, kb) = (a.k(), b.k());
        let scale = ka.amax();
        for (i, &pi) in perm.iter().enumerate() {
            assert!((ba.frames[i].n[0] - bb.frames[pi].n[0]).abs() < 1e-9);
            for (j, &pj) in perm.iter().enumerate() {
                for c in 0..2 {
                    for d in 0..2 {
                        let (x, y) = (ka[(2 * i + c, 2 * j + d)], kb[(2 * pi + c, 2 * pj + d)]);
                        assert!(
                            (x - y).abs() <= 1e-9 * scale,
                            "{file}: K differs: {x} vs {y}"
                        );
                    }
                }
            }
        }
    }
}

/// The one-line message for `bytes` parsed as a file called `name`, which must fail.
pub(super) fn error(bytes: &[u8], name: &str) -> String {
    let e = parse(bytes, name).expect_err("the file should be rejected");
    let shown = e.to_string();
    assert!(shown.starts_with(&format!("{name}: ")), "{shown}");
    assert!(!shown.contains('\n'), "{shown}");
    assert_eq!(e.file, name);
    assert_eq!(shown, format!("{name}: {}", e.message));
    shown
}

fn fixture_error(name: &str) -> String {
    let path = fixture(name);
    let e = read(&path).expect_err("the fixture should be rejected");
    let shown = e.to_string();
    assert!(shown.starts_with(&path.display().to_string()), "{shown}");
    assert!(shown.contains(name), "{shown}");
    assert!(!shown.contains('\n'), "{shown}");
    shown
}

/// (name, dim, entities, distinct nodes) of every group.
pub(super) fn counts(mesh: &Mesh) -> Vec<(String, usize, usize, usize)> {
    mesh.groups()
        .iter()
        .map(|g| (g.name.clone(), g.dim, g.entities.len(), g.nodes().len()))
        .collect()
}

pub(super) fn owned(list: &[(&str, usize, usize, usize)]) -> Vec<(String, usize, usize, usize)> {
    list.iter()
        .map(|&(n, d, e, v)| (n.to_string(), d, e, v))
        .collect()
}

pub(super) fn body_as_group(mesh: &Mesh) -> Vec<Vec<usize>> {
    mesh.elements().iter().map(|e| e.nodes.clone()).collect()
}

// --- Gmsh fixtures -------------------------------------------------------------------------

#[test]
fn plug2d_quad_counts() {
    let mesh = load("plug2d_quad.msh");
    assert_eq!(mesh.dim(), 2);
    assert_eq!(mesh.node_count(), 35);
    assert_eq!(mesh.elements().len(), 24);
    assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Quad4));
    assert_eq!(
        counts(&mesh),
        owned(&[
            ("bottom", 1, 6, 7),
            ("top", 1, 6, 7),
            ("left", 1, 4, 5),
            ("right", 1, 4, 5),
            ("contact", 1, 8, 10),
            ("body", 2, 24, 35),
        ])
    );
    assert_eq!(group(&mesh, "body").entities, body_as_group(&mesh));
    assert!(group(&mesh, "contact")
        .entities
        .iter()
        .all(|e| e.len() == 2));
}

#[test]
fn plug2d_quad_nodes_follow_the_bilinear_map() {
    let mesh = load("plug2d_quad.msh");
    let mut expected = Vec::new();
    for j in 0..=4 {
        let y = j as f64 / 4.0;
        let w = (1.0 + y) / 2.0;
        for i in 0..=6 {
            expected.push([-w + 2.0 * w * i as f64 / 6.0, y]);
        }
    }
    let mut matched = vec![false; expected.len()];
    for x in mesh.coords() {
        assert_eq!(x[2], 0.0);
        let k = expected
            .iter()
            .position(|e| (e[0] - x[0]).abs() < 1e-9 && (e[1] - x[1]).abs() < 1e-9)
            .unwrap_or_else(|| panic!("node {x:?} is not on the grid"));
        assert!(!matched[k], "two nodes at {x:?}");
        matched[k] = true;
    }
    assert!(matched.iter().all(|&m| m));
    // The contact nodes are those of the slanted sides, |x| = w(y).
    for &a in &group(&mesh, "contact").nodes() {
        let [x, y, _] = mesh.coords()[a];
        assert!((x.abs() - (1.0 + y) / 2.0).abs() < 1e-9, "({x}, {y})");
    }
    // Quadrilaterals are counterclockwise.
    for e in mesh.elements() {
        let p = mesh.element_coords(e);
        let area2: f64 = (0..4)
            .map(|k| p[k][0] * p[(k + 1) % 4][1] - p[(k + 1) % 4][0] * p[k][1])
            .sum();
        assert!((area2 / 2.0 - 1.5 / 24.0).abs() < 0.05, "{area2}");
    }
}

/// `a` and `b` (the mesh of file `what`) are the same mesh: dimension, nodes in order (to
/// 1e-15: an ASCII file has 16 significant digits, so the last bit may differ from a binary
/// file's), elements and groups.
pub(super) fn assert_same_mesh(a: &Mesh, b: &Mesh, what: &str) {
    assert_eq!(a.dim(), b.dim(), "{what}");
    assert_eq!(a.node_count(), b.node_count(), "{what}");
    for (x, y) in a.coords().iter().zip(b.coords()) {
        for k in 0..3 {
            assert!((x[k] - y[k]).abs() <= 1e-15, "{what}: {x:?} vs {y:?}");
        }
    }
    assert_eq!(a.elements(), b.elements(), "{what}");
    assert_eq!(a.groups(), b.groups(), "{what}");
}

#[test]
fn binary_and_ascii_give_the_same_mesh() {
    let ascii = load("plug2d_quad.msh");
    let binary = load("plug2d_quad_bin.msh");
    assert_same_mesh(&ascii, &binary, "plug2d_quad_bin.msh");
}

#[test]
fn plug2d_tri_counts() {
    // Counts as reported by Gmsh itself for this file.
    let mesh = load("plug2d_tri.msh");
    assert_eq!(mesh.dim(), 2);
    assert_eq!(mesh.node_count(), 44);
    assert_eq!(mesh.elements().len(), 64);
    assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Tri3));
    assert_eq!(
        counts(&mesh),
        owned(&[
            ("bottom", 1, 4, 5),
            ("top", 1, 8, 9),
            ("left", 1, 5, 6),
            ("right", 1, 5, 6),
            ("contact", 1, 10, 12),
            ("body", 2, 64, 44),
        ])
    );
    assert_eq!(group(&mesh, "body").entities, body_as_group(&mesh));
}

#[test]
fn box3d_tet_counts() {
    // Counts as reported by Gmsh itself for this file.
    let mesh = load("box3d_tet.msh");
    assert_eq!(mesh.dim(), 3);
    assert_eq!(mesh.node_count(), 45);
    assert_eq!(mesh.elements().len(), 100);
    assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Tet4));
    assert_eq!(
        counts(&mesh),
        owned(&[
            ("bottom", 2, 14, 12),
            ("top", 2, 14, 12),
            ("sides", 2, 56, 36),
            ("body", 3, 100, 45),
        ])
    );
    assert!(group(&mesh, "sides").entities.iter().all(|e| e.len() == 3));
    for &a in &group(&mesh, "bottom").nodes() {
        assert_eq!(mesh.coords()[a][2], 0.0);
    }
    for &a in &group(&mesh, "top").nodes() {
        assert_eq!(mesh.coords()[a][2], 1.0);
    }
}

#[test]
fn box3d_hex_counts() {
    let mesh = load("box3d_hex.msh");
    assert_eq!(mesh.dim(), 3);
    assert_eq!(mesh.node_count(), 27);
    assert_eq!(mesh.elements().len(), 8);
    assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Hex8));
    assert_eq!(
        counts(&mesh),
        owned(&[
            ("bottom", 2, 4, 9),
            ("top", 2, 4, 9),
            ("sides", 2, 16, 24),
            ("body", 3, 8, 27),
        ])
    );
    assert!(group(&mesh, "sides").entities.iter().all(|e| e.len() == 4));
}

#[test]
fn fixture_errors() {
    let e = fixture_error("third_order.msh");
    assert!(
        e.contains(
            "element type 21 (10-node third-order triangle) is not supported; \
             use first-order elements (Mesh.ElementOrder = 1), or second-order triangles, \
             quadrangles or tetrahedra (Mesh.ElementOrder = 2)"
        ),
        "{e}"
    );
    let e = fixture_error("truncated.msh");
    assert!(
        e.contains("malformed MSH file at line 78: the file ends too early"),
        "{e}"
    );
    let e = fixture_error("garbage.msh");
    assert!(e.contains("not a Gmsh MSH file"), "{e}");
    let e = fixture_error("does_not_exist.msh");
    assert!(e.contains("cannot read the file"), "{e}");
}

/// No prefix and no single-byte corruption of a fixture makes the reader panic, and the
/// MSH parser never panics on them either.
#[test]
fn damaged_files_do_not_panic() {
    for name in [
        "plug2d_quad.msh",
        "plug2d_quad_bin.msh",
        "box3d_hex.msh",
        "plug2d_quad_22.msh",
        "plug2d_quad_22_bin.msh",
    ] {
        let bytes = std::fs::read(fixture(name)).unwrap();
        let check = |data: &[u8]| {
            if let Err(e) = parse(data, name) {
                let shown = e.to_string();
                assert!(!shown.contains('\n'), "{shown}");
                assert!(!shown.contains("the MSH parser failed"), "{shown}");
            }
        };
        for cut in 0..bytes.len() {
            check(&bytes[..cut]);
        }
        let mut data = bytes.clone();
        for k in 0..bytes.len() {
            for b in [0u8, 0xff, b'9', b' '] {
                data[k] = b;
                check(&data);
            }
            data[k] = bytes[k];
        }
    }
}

// --- Hand-made files ------------------------------------------------------------------------

/// Two triangles on the unit square, nodes tagged `t` = [(0,0), (1,0), (1,1), (0,1)] (in
/// three node blocks, in that order), a line on the bottom, a physical point at the origin
/// (no point element), no `$PhysicalNames`.
fn square(t: [u64; 4]) -> String {
    let min = t.iter().min().unwrap();
    let max = t.iter().max().unwrap();
    format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
         $Entities\n2 1 1 0\n1 0 0 0 1 5\n2 1 0 0 0\n\
         1 0 0 0 1 0 0 1 3 2 1 -2\n1 0 0 0 1 1 0 1 7 0\n$EndEntities\n\
         $Nodes\n3 4 {min} {max}\n\
         0 1 0 1\n{a}\n0 0 0\n\
         0 2 0 1\n{b}\n1 0 0\n\
         2 1 0 2\n{c}\n{d}\n1 1 0\n0 1 0\n$EndNodes\n\
         $Elements\n2 3 5 9\n\
         1 1 1 1\n5 {a} {b}\n\
         2 1 2 2\n9 {a} {b} {c}\n7 {a} {c} {d}\n$EndElements\n",
        a = t[0],
        b = t[1],
        c = t[2],
        d = t[3],
    )
}

fn check_square(mesh: &Mesh) {
    assert_eq!(mesh.dim(), 2);
    assert_eq!(
        mesh.coords(),
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0]
        ]
    );
    assert_eq!(body_as_group(mesh), [vec![0, 1, 2], vec![0, 2, 3]]);
    assert_eq!(
        mesh.groups(),
        [
            Group {
                name: "0:5".into(),
                dim: 0,
                entities: vec![vec![0]],
            },
            Group {
                name: "1:3".into(),
                dim: 1,
                entities: vec![vec![0, 1]],
            },
            Group {
                name: "2:7".into(),
                dim: 2,
                entities: vec![vec![0, 1, 2], vec![0, 2, 3]],
            },
        ]
    );
}

#[test]
fn node_tags_sparse_or_permuted() {
    for tags in [[1, 2, 3, 4], [10, 30, 40, 20], [2, 4, 1, 3], [4, 3, 2, 1]] {
        let text = square(tags);
        let mesh = parse(text.as_bytes(), "square.msh").unwrap_or_else(|e| panic!("{e}"));
        check_square(&mesh);
    }
}

#[test]
fn physical_names_and_point_elements() {
    let text = square([1, 2, 3, 4]).replace(
        "$Entities",
        "$PhysicalNames\n3\n0 5 \"origin\"\n1 3 \"the bottom\"\n2 7 \"body\"\n\
         $EndPhysicalNames\n$Entities",
    );
    let mesh = parse(text.as_bytes(), "square.msh").unwrap();
    let names: Vec<_> = mesh.groups().iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["origin", "the bottom", "body"]);
    // A point element, rather than the point entity's node (here, oddly, another node).
    let text = text.replace(
        "$Elements\n2 3 5 9\n",
        "$Elements\n3 4 5 10\n0 1 15 1\n10 2\n",
    );
    let mesh = parse(text.as_bytes(), "square.msh").unwrap();
    assert_eq!(group(&mesh, "origin").entities, [vec![1]]);
}

#[test]
fn no_entities_means_no_groups() {
    let text = square([1, 2, 3, 4]);
    let start = text.find("$Entities").unwrap();
    let end = text.find("$Nodes").unwrap();
    let text = format!("{}{}", &text[..start], &text[end..]);
    let mesh = parse(text.as_bytes(), "square.msh").unwrap();
    assert_eq!(mesh.elements().len(), 2);
    assert!(mesh.groups().is_empty());
}

#[test]
fn planarity_in_z() {
    // Changes the z coordinates of the nodes only.
    let with_z = |z: [&str; 4]| {
        let text = square([1, 2, 3, 4]);
        let (head, nodes) = text.split_at(text.find("$Nodes").unwrap());
        let nodes = nodes
            .replace("0 0 0\n", &format!("0 0 {}\n", z[0]))
            .replace("1 0 0\n", &format!("1 0 {}\n", z[1]))
            .replace("1 1 0\n", &format!("1 1 {}\n", z[2]))
            .replace("0 1 0\n", &format!("0 1 {}\n", z[3]));
        format!("{head}{nodes}")
    };
    let text = with_z(["0", "0", "0.5", "0"]);
    let e = error(text.as_bytes(), "bent.msh");
    assert!(e.contains("2D mesh is not planar in z"), "{e}");
    let text = with_z(["5", "5", "5", "5"]);
    assert!(text.contains("1 1 5\n"));
    let mesh = parse(text.as_bytes(), "lifted.msh").unwrap();
    check_square(&mesh);
}

#[test]
fn content_errors() {
    let text = square([1, 2, 3, 4]).replace("7 1 3 4\n", "7 1 3 99\n");
    let e = error(text.as_bytes(), "holes.msh");
    assert!(e.contains("element 7 refers to node 99"), "{e}");

    let text = square([1, 2, 3, 4]).replace("1 2\n2 1 2 2\n9 1 2 3\n7 1 3 4\n", "1 2\n");
    let text = text.replace("$Elements\n2 3 5 9\n", "$Elements\n1 1 5 5\n");
    let e = error(text.as_bytes(), "lines.msh");
    assert!(e.contains("no 2D or 3D elements"), "{e}");
    assert!(e.contains("Mesh.SaveAll = 1"), "{e}");

    let text = square([1, 2, 3, 4]).replace("2 1 0 2\n3\n4\n", "2 1 0 2\n3\n2\n");
    let e = error(text.as_bytes(), "twice.msh");
    assert!(e.contains("node tag 2 is defined twice"), "{e}");

    let start = square([1, 2, 3, 4]).find("$Nodes").unwrap();
    let text = format!(
        "{}$Nodes\n0 0 1 1\n$EndNodes\n",
        &square([1, 2, 3, 4])[..start]
    );
    let e = error(text.as_bytes(), "empty.msh");
    assert!(e.contains("the file has no nodes"), "{e}");

    let text = square([1, 2, 3, 4]).replace(
        "$Entities",
        "$PhysicalNames\n2\n1 3 \"x\"\n2 7 \"x\"\n$EndPhysicalNames\n$Entities",
    );
    let e = error(text.as_bytes(), "dup.msh");
    assert!(e.contains("two groups are named 'x'"), "{e}");

    let text = square([1, 2, 3, 4]).replace(
        "$Entities",
        "$PhysicalNames\n2\n1 3 x\n$EndPhysicalNames\n$Entities",
    );
    let e = error(text.as_bytes(), "names.msh");
    assert!(e.contains("malformed $PhysicalNames section"), "{e}");

    // A prism in a 3D mesh.
    let prism = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 6 1 6\n3 1 0 6\n\
                 1\n2\n3\n4\n5\n6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 1\n0 1 1\n$EndNodes\n\
                 $Elements\n1 1 1 1\n3 1 6 1\n1 1 2 3 4 5 6\n$EndElements\n";
    let e = error(prism.as_bytes(), "prism.msh");
    assert!(
        e.contains("element type 6 (6-node prism) is not supported; 3D bodies must be"),
        "{e}"
    );
    // The same nodes as a tetrahedron and a 3-node line (second order) in a group.
    let tet = prism
        .replace("3 1 6 1\n1 1 2 3 4 5 6\n", "3 1 4 1\n1 1 2 3 4\n")
        .replace(
            "$Elements\n1 1 1 1\n",
            "$Elements\n2 2 1 2\n1 1 8 1\n2 1 2 3\n",
        );
    let e = error(tet.as_bytes(), "tet.msh");
    assert!(
        e.contains(
            "element type 8 (3-node second-order line) is not of the order of the body's \
             elements (first order)"
        ),
        "{e}"
    );
}

#[test]
fn header_errors() {
    let cases: [(&[u8], &str); 11] = [
        (b"", "the file is empty"),
        (b"hello\n", "not a Gmsh MSH file"),
        (b"\x00\x01\x02\xff\xfe", "not a Gmsh MSH file"),
        (
            b"$MeshFormat\n4 0 8\n$EndMeshFormat\n",
            "MSH 4 is not supported",
        ),
        (
            b"$MeshFormat\n4.0 1 8\n$EndMeshFormat\n",
            "MSH 4.0 is not supported; save as MSH 4.1 (gmsh -format msh41) or 2.2",
        ),
        (
            b"$MeshFormat\n3.0 0 8\n$EndMeshFormat\n",
            "MSH 3.0 is not supported",
        ),
        (
            b"$MeshFormat\n2.2 1 4\n\x01\x00\x00\x00\n",
            "binary MSH 2.2 files with 4-byte doubles are not supported",
        ),
        (
            b"$MeshFormat\n4.1 2 8\n$EndMeshFormat\n",
            "invalid $MeshFormat header",
        ),
        (
            b"$MeshFormat\n4.1 0 99999999999\n",
            "invalid $MeshFormat header",
        ),
        (b"$MeshFormat\n4.1 1 3\n", "3-byte size_t are not supported"),
        (b"$MeshFormat\n4.1 1 8\n\x02\x00\x00\x00\n", "byte order"),
    ];
    for (bytes, expected) in cases {
        let e = error(bytes, "h.msh");
        assert!(e.contains(expected), "{e}");
    }
    let e = error(
        b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2",
        "cut.msh",
    );
    assert!(e.contains("malformed MSH file"), "{e}");
}

/// A binary MSH 4.1 file of `square([3, 1, 4, 2])` with `$PhysicalNames`, in either byte
/// order.
fn binary_square(big_endian: bool) -> Vec<u8> {
    let mut out = Vec::new();
    let size_t = |out: &mut Vec<u8>, v: u64| {
        out.extend(if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        })
    };
    let int = |out: &mut Vec<u8>, v: i32| {
        out.extend(if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        })
    };
    let double = |out: &mut Vec<u8>, v: f64| {
        out.extend(if big_endian {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        })
    };
    out.extend(b"$MeshFormat\n4.1 1 8\n");
    int(&mut out, 1);
    out.extend(b"\n$EndMeshFormat\n");
    out.extend(b"$PhysicalNames\n2\n1 3 \"bottom\"\n2 7 \"body\"\n$EndPhysicalNames\n");
    out.extend(b"$Entities\n");
    for n in [2, 1, 1, 0] {
        size_t(&mut out, n);
    }
    // Points 1 (physical 5) and 2.
    for (tag, x, physical) in [(1, 0.0, Some(5)), (2, 1.0, None)] {
        int(&mut out, tag);
        for v in [x, 0.0, 0.0] {
            double(&mut out, v);
        }
        size_t(&mut out, physical.iter().count() as u64);
        for &p in physical.iter() {
            int(&mut out, p);
        }
    }
    // Curve 1 (physical 3) from point 1 to 2; surface 1 (physical 7).
    for (physical, bounds) in [(3, vec![1, -2]), (7, vec![])] {
        int(&mut out, 1);
        for v in [0.0, 0.0, 0.0, 1.0, 1.0, 0.0] {
            double(&mut out, v);
        }
        size_t(&mut out, 1);
        int(&mut out, physical);
        size_t(&mut out, bounds.len() as u64);
        for b in bounds {
            int(&mut out, b);
        }
    }
    out.extend(b"\n$EndEntities\n$Nodes\n");
    for n in [3, 4, 1, 4] {
        size_t(&mut out, n);
    }
    type NodeBlock<'a> = (i32, i32, &'a [(u64, [f64; 3])]);
    let blocks: [NodeBlock; 3] = [
        (0, 1, &[(3, [0.0, 0.0, 0.0])]),
        (0, 2, &[(1, [1.0, 0.0, 0.0])]),
        (2, 1, &[(4, [1.0, 1.0, 0.0]), (2, [0.0, 1.0, 0.0])]),
    ];
    for (dim, tag, nodes) in blocks {
        int(&mut out, dim);
        int(&mut out, tag);
        int(&mut out, 0);
        size_t(&mut out, nodes.len() as u64);
        for (t, _) in nodes {
            size_t(&mut out, *t);
        }
        for (_, x) in nodes {
            for &v in x {
                double(&mut out, v);
            }
        }
    }
    out.extend(b"\n$EndNodes\n$Elements\n");
    for n in [2, 3, 5, 9] {
        size_t(&mut out, n);
    }
    let blocks: [(i32, i32, &[&[u64]]); 2] = [
        (1, 1, &[&[5, 3, 1]]),
        (2, 2, &[&[9, 3, 1, 4], &[7, 3, 4, 2]]),
    ];
    for (dim, t, elements) in blocks {
        int(&mut out, dim);
        int(&mut out, 1);
        int(&mut out, t);
        size_t(&mut out, elements.len() as u64);
        for element in elements {
            for &v in element.iter() {
                size_t(&mut out, v);
            }
        }
    }
    out.extend(b"\n$EndElements\n");
    out
}

#[test]
fn binary_either_byte_order() {
    let text = square([3, 1, 4, 2]).replace(
        "$Entities",
        "$PhysicalNames\n2\n1 3 \"bottom\"\n2 7 \"body\"\n$EndPhysicalNames\n$Entities",
    );
    let ascii = parse(text.as_bytes(), "a.msh").unwrap();
    for big_endian in [false, true] {
        let mesh = parse(&binary_square(big_endian), "b.msh").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(mesh.coords(), ascii.coords());
        assert_eq!(mesh.elements(), ascii.elements());
        assert_eq!(mesh.groups(), ascii.groups());
    }
    let names: Vec<_> = ascii.groups().iter().map(|g| g.name.as_str()).collect();
    assert_eq!(names, ["0:5", "bottom", "body"]);
}
