//! Small vector helpers, contact-face normals, the 2D/3D projection onto the page and the mesh's
//! boundary facets.

use std::collections::HashMap;

use super::{P2, P3};
use crate::draw::vtk::View;

pub(super) fn finite3(v: &P3) -> bool {
    v.iter().all(|x| x.is_finite())
}

pub(super) fn add3(a: P3, b: P3, s: f64) -> P3 {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

pub(super) fn dot3(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn norm3(a: P3) -> f64 {
    dot3(a, a).sqrt()
}

pub(super) fn unit2(v: P2) -> Option<P2> {
    let n = (v[0] * v[0] + v[1] * v[1]).sqrt();
    (n > 0.0 && n.is_finite()).then(|| [v[0] / n, v[1] / n])
}

pub(super) fn cross3(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(super) fn unit3(v: P3) -> Option<P3> {
    let n = norm3(v);
    (n > 0.0 && n.is_finite()).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

/// The area-weighted normal of a polygon (Newell's method; right-hand rule on the node order).
pub(super) fn polygon_normal(ps: &[P3]) -> P3 {
    let mut n = [0.0; 3];
    for (k, p) in ps.iter().enumerate() {
        let q = ps[(k + 1) % ps.len()];
        n = add3(n, cross3(*p, q), 0.5);
    }
    n
}

pub(super) fn mean3(ps: &[P3]) -> P3 {
    ps.iter()
        .fold([0.0; 3], |s, &p| add3(s, p, 1.0 / ps.len() as f64))
}

/// The outward (from the body into the obstacle) area-weighted normal of each 3D contact face,
/// undeformed, oriented against the inward normals of its contact nodes; `None` if that is not
/// possible (an edge, or no contact node with a frame).
pub(super) fn contact_face_normals(view: &View) -> Vec<Option<P3>> {
    let x = view.mesh.coords();
    let index: HashMap<usize, usize> = view
        .boundary
        .contact_nodes
        .iter()
        .enumerate()
        .map(|(i, &a)| (a, i))
        .collect();
    view.boundary
        .contact_facets
        .iter()
        .map(|f| {
            if f.len() < 3 {
                return None;
            }
            let n = polygon_normal(&around(f).iter().map(|&a| x[a]).collect::<Vec<_>>());
            let inward = f
                .iter()
                .filter_map(|a| index.get(a))
                .fold([0.0; 3], |s, &i| add3(s, view.boundary.frames[i].n, 1.0));
            let d = dot3(n, inward);
            (d != 0.0 && d.is_finite()).then(|| if d > 0.0 { add3([0.0; 3], n, -1.0) } else { n })
        })
        .collect()
}

/// The projection of the model onto the page plane (before scaling): identity in 2D, an
/// isometric view with z up in 3D.
#[derive(Clone, Copy)]
pub(super) struct Projection {
    pub(super) three_d: bool,
    /// The octant the 3D view looks from, e.g. `[1, 1, 1]`.
    pub(super) from: [i8; 3],
    pub(super) right: P3,
    pub(super) up: P3,
    /// Unit vector towards the viewer.
    pub(super) towards: P3,
}

impl Projection {
    pub(super) fn flat() -> Projection {
        Projection {
            three_d: false,
            from: [0, 0, 1],
            right: [1.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            towards: [0.0, 0.0, 1.0],
        }
    }

    /// The isometric view from the octant `from`, z up on the page.
    pub(super) fn isometric(from: [i8; 3]) -> Projection {
        let d = [from[0] as f64, from[1] as f64, from[2] as f64];
        let towards = unit3(d).unwrap_or([0.0, 0.0, 1.0]);
        let up = unit3(add3([0.0, 0.0, 1.0], towards, -towards[2])).unwrap_or([0.0, 1.0, 0.0]);
        Projection {
            three_d: true,
            from,
            right: cross3(up, towards),
            up,
            towards,
        }
    }

    /// 3D: the isometric view (of the 8 octants, z up) that shows the most contact-face area,
    /// `(1, 1, 1)` on ties.
    pub(super) fn choose(view: &View) -> Projection {
        let normals: Vec<P3> = contact_face_normals(view).into_iter().flatten().collect();
        let mut best = ([1, 1, 1], 0.0);
        for from in [
            [1, 1, 1],
            [-1, 1, 1],
            [-1, -1, 1],
            [1, -1, 1],
            [1, 1, -1],
            [-1, 1, -1],
            [-1, -1, -1],
            [1, -1, -1],
        ] {
            let t = Projection::isometric(from).towards;
            let score: f64 = normals.iter().map(|&n| dot3(n, t).max(0.0)).sum();
            if score > best.1 * (1.0 + 1e-9) {
                best = (from, score);
            }
        }
        Projection::isometric(best.0)
    }

    pub(super) fn project(self, p: P3) -> P2 {
        [dot3(p, self.right), dot3(p, self.up)]
    }

    /// Distance towards the viewer (3D), for painter's order.
    pub(super) fn depth(self, p: P3) -> f64 {
        dot3(p, self.towards)
    }
}

/// A 3D facet's nodes around its boundary: a second-order face (corners, then the middles of
/// its edges, [`wedged::fe::ElementKind::facets`]) with each middle between its corners; other
/// facets as they are.
pub(super) fn around(f: &[usize]) -> Vec<usize> {
    match f.len() {
        6 => vec![f[0], f[3], f[1], f[4], f[2], f[5]],
        _ => f.to_vec(),
    }
}

/// The facets (2D edges, 3D faces) that belong to exactly one element, with that element, in
/// mesh order.
pub(super) fn boundary_facets(view: &View) -> Vec<(usize, Vec<usize>)> {
    let mut count: HashMap<Vec<usize>, usize> = HashMap::new();
    let facets = |e: &wedged::fe::Element| -> Vec<Vec<usize>> {
        e.kind
            .facets()
            .iter()
            .map(|f| f.iter().map(|&i| e.nodes[i]).collect())
            .collect()
    };
    let key = |f: &[usize]| {
        let mut k = f.to_vec();
        k.sort_unstable();
        k
    };
    for element in view.mesh.elements() {
        for f in facets(element) {
            *count.entry(key(&f)).or_insert(0) += 1;
        }
    }
    let mut out = Vec::new();
    for (e, element) in view.mesh.elements().iter().enumerate() {
        for f in facets(element) {
            if count.get(&key(&f)) == Some(&1) {
                out.push((e, f));
            }
        }
    }
    out
}

pub(super) fn centroid(view: &View, nodes: &[usize]) -> P3 {
    let mut c = [0.0; 3];
    for &a in nodes {
        c = add3(c, view.mesh.coords()[a], 1.0 / nodes.len() as f64);
    }
    c
}

/// The outward unit normal (model, 2D) of the boundary edge `a-b` of element `e`.
pub(super) fn outward_2d(view: &View, e: usize, a: usize, b: usize) -> Option<P2> {
    let x = view.mesh.coords();
    let d = [x[b][0] - x[a][0], x[b][1] - x[a][1]];
    let p = [d[1], -d[0]];
    let c = centroid(view, &view.mesh.elements()[e].nodes);
    let m = [
        0.5 * (x[a][0] + x[b][0]) - c[0],
        0.5 * (x[a][1] + x[b][1]) - c[1],
    ];
    let s = if p[0] * m[0] + p[1] * m[1] < 0.0 {
        -1.0
    } else {
        1.0
    };
    unit2([s * p[0], s * p[1]])
}
