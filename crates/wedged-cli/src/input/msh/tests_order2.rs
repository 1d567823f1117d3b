//! Tests of `msh.rs` on second-order meshes (Gmsh's, `tools/gmsh/make_fixtures.py`).

use super::tests::{body_as_group, counts, group, load, owned};
use wedged::fe::ElementKind;

/// The second-order twins of the plug and box fixtures: the same corners, the middles of the
/// edges added (and the quadrangles' centres), 3-node lines and 6-node triangles on the
/// boundary, every element's extra nodes at the middles of its (straight) edges.
#[test]
fn second_order_fixtures_read_with_their_mid_edge_nodes() {
    for (file, linear, kind, nodes) in [
        ("plug2d_tri6.msh", "plug2d_tri.msh", ElementKind::Tri6, None),
        (
            "plug2d_quad8.msh",
            "plug2d_quad.msh",
            ElementKind::Quad8,
            Some(35 + 58),
        ),
        (
            "plug2d_quad9.msh",
            "plug2d_quad.msh",
            ElementKind::Quad9,
            Some(35 + 58 + 24),
        ),
        ("box3d_tet10.msh", "box3d_tet.msh", ElementKind::Tet10, None),
    ] {
        let (mesh, first) = (load(file), load(linear));
        assert_eq!(mesh.dim(), first.dim(), "{file}");
        assert!(mesh.elements().iter().all(|e| e.kind == kind), "{file}");
        assert_eq!(mesh.elements().len(), first.elements().len(), "{file}");
        if let Some(n) = nodes {
            assert_eq!(mesh.node_count(), n, "{file}");
        }
        // The corners are the first-order mesh's elements, place for place (Gmsh numbers the
        // nodes anew).
        let (x, y) = (mesh.coords(), first.coords());
        for (e, f) in mesh.elements().iter().zip(first.elements()) {
            for (&a, &b) in e.nodes[..kind.corner_count()].iter().zip(&f.nodes) {
                assert!((0..3).all(|k| (x[a][k] - y[b][k]).abs() < 1e-12), "{file}");
            }
        }
        // Each extra node is the middle of two corners of its element (or their centre).
        for e in mesh.elements() {
            let corners = &e.nodes[..kind.corner_count()];
            for &a in &e.nodes[kind.corner_count()..] {
                let middle = corners.iter().enumerate().any(|(i, &p)| {
                    corners[i + 1..].iter().any(|&q| {
                        (0..3).all(|k| (x[a][k] - (x[p][k] + x[q][k]) / 2.0).abs() < 1e-12)
                    })
                });
                let centre = (0..3).all(|k| {
                    (x[a][k] - corners.iter().map(|&p| x[p][k]).sum::<f64>() / 4.0).abs() < 1e-12
                });
                assert!(middle || (kind == ElementKind::Quad9 && centre), "{file}");
            }
        }
        // The same groups, each facet with its middle: 3 nodes a line, 6 a triangle.
        let names: Vec<_> = counts(&first)
            .into_iter()
            .map(|c| (c.0, c.1, c.2))
            .collect();
        let ours: Vec<_> = counts(&mesh).into_iter().map(|c| (c.0, c.1, c.2)).collect();
        assert_eq!(names, ours, "{file}");
        for g in mesh.groups().iter().filter(|g| g.dim + 1 == mesh.dim()) {
            let want = if mesh.dim() == 2 { 3 } else { 6 };
            assert!(
                g.entities.iter().all(|f| f.len() == want),
                "{file}: {}",
                g.name
            );
        }
        assert_eq!(
            group(&mesh, "body").entities,
            body_as_group(&mesh),
            "{file}"
        );
    }
    let _ = owned;
}
