//! The marks of the body on the page: the deformed mesh (2D elements or 3D boundary faces), the
//! obstacle, supports, reaction arrows and contact circles.

use std::collections::HashMap;
use std::fmt::Write as _;

use wedged::NodeStatus;

use super::geometry::{
    add3, around, boundary_facets, contact_face_normals, dot3, outward_2d, unit2, unit3,
};
use super::scene::Scene;
use super::{escape, points, px, status_style, Svg, ARROW, INK, P2, P3};
use crate::report::sig4;

/// An arrow from `p` to `q` (page): a shaft and a filled head, with a white halo.
pub(super) fn arrow(out: &mut String, class: &str, p: P2, q: P2, tooltip: Option<&str>) {
    let d = [q[0] - p[0], q[1] - p[1]];
    let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let t = unit2(d).unwrap_or([1.0, 0.0]);
    let n = [-t[1], t[0]];
    let head = 9.0f64.min(0.45 * len).max(3.0);
    let half = 0.42 * head;
    let base = [q[0] - head * t[0], q[1] - head * t[1]];
    let tip = [
        base,
        q,
        [base[0] + half * n[0], base[1] + half * n[1]],
        [base[0] - half * n[0], base[1] - half * n[1]],
    ];
    let _ = write!(out, "<g class=\"{class}\">");
    if let Some(tooltip) = tooltip {
        let _ = write!(out, "<title>{}</title>", escape(tooltip));
    }
    let shaft = format!("M{} {}L{} {}", px(p[0]), px(p[1]), px(base[0]), px(base[1]));
    let head = points(&[tip[1], tip[2], tip[3]]);
    let _ = writeln!(
        out,
        "<path d=\"{shaft}\" stroke=\"#ffffff\" stroke-width=\"4\" stroke-opacity=\"0.85\" \
         fill=\"none\"/><polygon points=\"{head}\" fill=\"#ffffff\" stroke=\"#ffffff\" \
         stroke-width=\"2.5\" stroke-opacity=\"0.85\"/>\
         <path d=\"{shaft}\" stroke=\"{ARROW}\" stroke-width=\"1.8\" fill=\"none\"/>\
         <polygon points=\"{head}\" fill=\"{ARROW}\"/></g>"
    );
}

/// A support symbol at node position `p`: a triangle pointing at the node from direction `o`
/// (page, unit), filled for a clamp, hollow for a roller.
pub(super) fn support_triangle(out: &mut String, p: P2, o: P2, filled: bool) {
    let h = 8.0;
    let w = 4.5;
    let b = [p[0] + h * o[0], p[1] + h * o[1]];
    let n = [-o[1], o[0]];
    let tri = [
        p,
        [b[0] + w * n[0], b[1] + w * n[1]],
        [b[0] - w * n[0], b[1] - w * n[1]],
    ];
    let fill = if filled { INK } else { "#ffffff" };
    let _ = writeln!(
        out,
        "<polygon points=\"{}\" fill=\"{fill}\" stroke=\"{INK}\" stroke-width=\"1\"/>",
        points(&tri)
    );
}

/// A small square symbol at `p`.
pub(super) fn support_square(out: &mut String, p: P2, filled: bool) {
    let s = 3.0;
    let fill = if filled { INK } else { "#ffffff" };
    let _ = writeln!(
        out,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{fill}\" stroke=\"{INK}\" \
         stroke-width=\"1\"/>",
        px(p[0] - s),
        px(p[1] - s),
        px(2.0 * s),
        px(2.0 * s)
    );
}

/// A contact node marker.
pub(super) fn contact_circle(
    out: &mut String,
    p: P2,
    r: f64,
    status: NodeStatus,
    tooltip: Option<&str>,
) {
    let (class, fill, stroke) = status_style(status);
    let _ = write!(
        out,
        "<circle class=\"contact status-{class}\" cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{fill}\" \
         stroke=\"{stroke}\" stroke-width=\"1.3\"",
        px(p[0]),
        px(p[1]),
        px(r)
    );
    match tooltip {
        Some(t) => {
            let _ = writeln!(out, "><title>{}</title></circle>", escape(t));
        }
        None => out.push_str("/>\n"),
    }
}

/// 2D: deformed elements filled by von Mises, undeformed outline, obstacle.
pub(super) fn draw_body_2d(svg: &mut Svg, scene: &Scene) {
    let view = scene.view;
    svg.raw("<g class=\"deformed\" stroke=\"#1a1a1a\" stroke-width=\"0.6\" stroke-opacity=\"0.55\" stroke-linejoin=\"round\">\n");
    for (e, element) in view.mesh.elements().iter().enumerate() {
        let ps: Option<Vec<P2>> = element
            .kind
            .outline()
            .iter()
            .map(|&i| scene.deformed(element.nodes[i]))
            .collect();
        let Some(ps) = ps else { continue };
        let fill = scene.fill(e, 1.0).unwrap_or_else(|| "none".to_string());
        let _ = writeln!(
            svg.out,
            "<polygon points=\"{}\" fill=\"{fill}\"/>",
            points(&ps)
        );
    }
    svg.raw("</g>\n");

    let facets = boundary_facets(view);
    let mut d = String::new();
    for (_, f) in &facets {
        let (p, q) = (scene.undeformed(f[0]), scene.undeformed(f[1]));
        let _ = write!(d, "M{} {}L{} {}", px(p[0]), px(p[1]), px(q[0]), px(q[1]));
    }
    let _ = writeln!(
        svg.out,
        "<path class=\"undeformed\" d=\"{d}\" fill=\"none\" stroke=\"#9a9a9a\" \
         stroke-width=\"1.2\" stroke-dasharray=\"5 3\"/>"
    );

    // The obstacle: each contact facet, hatched on the side opposite to the inward normal.
    let index: HashMap<usize, usize> = view
        .boundary
        .contact_nodes
        .iter()
        .enumerate()
        .map(|(i, &a)| (a, i))
        .collect();
    let element_of: HashMap<(usize, usize), usize> = facets
        .iter()
        .map(|(e, f)| ((f[0].min(f[1]), f[0].max(f[1])), *e))
        .collect();
    let mut lines = String::new();
    let mut hatches = String::new();
    for f in &view.boundary.contact_facets {
        if f.len() < 2 {
            continue;
        }
        let (a, b) = (f[0], f[1]);
        let x = view.mesh.coords();
        let perp = [x[b][1] - x[a][1], -(x[b][0] - x[a][0])];
        // Inward normal from the frames of the facet's contact nodes, else from the geometry.
        let inward = f
            .iter()
            .filter_map(|n| index.get(n))
            .fold([0.0; 2], |s, &i| {
                let n = view.boundary.frames[i].n;
                [s[0] + n[0], s[1] + n[1]]
            });
        let outward = match unit2(inward) {
            Some(n) => {
                let s = if perp[0] * n[0] + perp[1] * n[1] > 0.0 {
                    -1.0
                } else {
                    1.0
                };
                unit2([s * perp[0], s * perp[1]])
            }
            None => element_of
                .get(&(a.min(b), a.max(b)))
                .and_then(|&e| outward_2d(view, e, a, b)),
        };
        let (p, q) = (scene.undeformed(a), scene.undeformed(b));
        let _ = write!(
            lines,
            "M{} {}L{} {}",
            px(p[0]),
            px(p[1]),
            px(q[0]),
            px(q[1])
        );
        let (Some(o), Some(t)) = (
            outward.map(|o| scene.page.dir(o)),
            unit2([q[0] - p[0], q[1] - p[1]]),
        ) else {
            continue;
        };
        let len = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        let count = (len / 7.0).round().max(1.0) as usize;
        for k in 0..count {
            let s = (k as f64 + 0.5) * len / count as f64;
            let h0 = [p[0] + s * t[0] + 2.0 * o[0], p[1] + s * t[1] + 2.0 * o[1]];
            let h1 = [
                h0[0] + 6.0 * (o[0] + 0.8 * t[0]),
                h0[1] + 6.0 * (o[1] + 0.8 * t[1]),
            ];
            let _ = write!(
                hatches,
                "M{} {}L{} {}",
                px(h0[0]),
                px(h0[1]),
                px(h1[0]),
                px(h1[1])
            );
        }
    }
    if !lines.is_empty() {
        let _ = writeln!(
            svg.out,
            "<g class=\"obstacle\"><path class=\"hatch\" d=\"{hatches}\" stroke=\"{INK}\" \
             stroke-width=\"1\" fill=\"none\"/><path class=\"wall\" d=\"{lines}\" \
             stroke=\"{INK}\" stroke-width=\"3\" stroke-linecap=\"round\" fill=\"none\"/></g>"
        );
    }
}

/// 3D: the visible deformed boundary faces far to near, lightly shaded, then the obstacle: the
/// visible contact faces at their undeformed position, hatched.
pub(super) fn draw_body_3d(svg: &mut Svg, scene: &Scene) {
    let view = scene.view;
    // Light from the viewer's upper left.
    let light = unit3(add3(
        add3(scene.projection.towards, scene.projection.up, 0.6),
        scene.projection.right,
        -0.4,
    ))
    .unwrap_or(scene.projection.towards);
    svg.raw("<g class=\"deformed\" stroke=\"#1a1a1a\" stroke-width=\"0.6\" stroke-opacity=\"0.6\" stroke-linejoin=\"round\">\n");
    for face in &scene.faces {
        let shade = 0.72 + 0.28 * dot3(face.normal, light).max(0.0);
        let fill = scene
            .fill(face.element, shade)
            .unwrap_or_else(|| "#eeeeee".to_string());
        let _ = writeln!(
            svg.out,
            "<polygon points=\"{}\" fill=\"{fill}\"/>",
            points(&face.polygon)
        );
    }
    svg.raw("</g>\n");
    let mut d = String::new();
    let x = view.mesh.coords();
    let normals = contact_face_normals(view);
    for (f, n) in view.boundary.contact_facets.iter().zip(normals) {
        let visible = match n {
            Some(n) => dot3(n, scene.projection.towards) > 0.0,
            None => f.iter().all(|&a| scene.visible[a]),
        };
        if f.len() < 3 || !visible {
            continue;
        }
        for (k, &a) in around(f).iter().enumerate() {
            let p = scene.at(x[a]);
            let _ = write!(
                d,
                "{}{} {}",
                if k == 0 { "M" } else { "L" },
                px(p[0]),
                px(p[1])
            );
        }
        d.push('Z');
    }
    let _ = writeln!(
        svg.out,
        "<defs><pattern id=\"hatch\" width=\"6\" height=\"6\" \
         patternUnits=\"userSpaceOnUse\" patternTransform=\"rotate(45)\">\
         <path d=\"M0 0V6\" stroke=\"{INK}\" stroke-width=\"0.8\" stroke-opacity=\"0.45\"/>\
         </pattern></defs>"
    );
    if !d.is_empty() {
        let _ = writeln!(
            svg.out,
            "<g class=\"obstacle\"><path class=\"wall\" d=\"{d}\" fill=\"url(#hatch)\" \
             stroke=\"{INK}\" stroke-width=\"1.1\" stroke-opacity=\"0.7\" \
             stroke-dasharray=\"4 2\"/></g>"
        );
    }
}

/// Clamped and roller nodes.
pub(super) fn draw_supports(svg: &mut Svg, scene: &Scene) {
    let view = scene.view;
    let boundary = view.boundary;
    if boundary.clamped.is_empty() && boundary.rollers.is_empty() {
        return;
    }
    // 2D: outward direction at each boundary node, from its boundary edges.
    let mut outward: HashMap<usize, P2> = HashMap::new();
    if !scene.projection.three_d {
        for (e, f) in boundary_facets(view) {
            if let Some(o) = outward_2d(view, e, f[0], f[1]) {
                // The edge's ends, and its middle on a second-order mesh.
                for &a in &f {
                    let s = outward.entry(a).or_insert([0.0; 2]);
                    s[0] += o[0];
                    s[1] += o[1];
                }
            }
        }
    }
    let mut layers = Layers::default();
    let mut symbol = |a: usize, filled: bool| {
        // Supports on the far side of a 3D body are left out.
        let Some(p) = scene.deformed(a).filter(|_| scene.visible[a]) else {
            return;
        };
        let out = layers.get(scene.visible[a]);
        if scene.projection.three_d {
            support_square(out, p, filled);
        } else {
            let o = outward
                .get(&a)
                .and_then(|&o| unit2(o))
                .unwrap_or([0.0, -1.0]);
            support_triangle(out, p, scene.page.dir(o), filled);
        }
    };
    for &a in &boundary.clamped {
        symbol(a, true);
    }
    for (a, _) in &boundary.rollers {
        symbol(*a, false);
    }
    layers.write(svg, "supports");
}

/// Items on the visible side, and faded ones on the far side of a 3D body.
#[derive(Default)]
pub(super) struct Layers {
    pub(super) shown: String,
    pub(super) hidden: String,
}

impl Layers {
    pub(super) fn get(&mut self, visible: bool) -> &mut String {
        if visible {
            &mut self.shown
        } else {
            &mut self.hidden
        }
    }

    /// A group `class` with the hidden items (faded) below the shown ones.
    pub(super) fn write(&self, svg: &mut Svg, class: &str) {
        let _ = writeln!(svg.out, "<g class=\"{class}\">");
        if !self.hidden.is_empty() {
            let _ = writeln!(
                svg.out,
                "<g class=\"far-side\" opacity=\"0.28\">\n{}</g>",
                self.hidden
            );
        }
        svg.raw(&self.shown);
        svg.raw("</g>\n");
    }
}

/// The components of a vector, for tooltips.
pub(super) fn components(v: &P3, dim: usize) -> String {
    v[..dim]
        .iter()
        .map(|&x| sig4(x))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Reaction arrows at pressed contact nodes.
pub(super) fn draw_reactions(svg: &mut Svg, scene: &Scene) {
    if scene.arrows.is_empty() {
        return;
    }
    let dim = scene.view.mesh.dim();
    let mut layers = Layers::default();
    for &(i, p, q) in &scene.arrows {
        let a = scene.view.boundary.contact_nodes[i];
        let f = scene.view.state.force[a];
        let tooltip = format!("reaction at node {}: ({})", a + 1, components(&f, dim));
        let out = layers.get(scene.visible[a]);
        arrow(out, "reaction", scene.at(p), scene.at(q), Some(&tooltip));
    }
    layers.write(svg, "reactions");
}

/// Contact nodes coloured by status.
pub(super) fn draw_contacts(svg: &mut Svg, scene: &Scene) {
    let view = scene.view;
    let dim = view.mesh.dim();
    let r = if scene.projection.three_d { 3.5 } else { 4.5 };
    let mut layers = Layers::default();
    for (&a, &status) in view.boundary.contact_nodes.iter().zip(view.status) {
        let Some(p) = scene.deformed(a) else { continue };
        let f = view.state.force[a];
        let tooltip = format!(
            "node {}: {}, reaction ({})",
            a + 1,
            status.name(),
            components(&f, dim)
        );
        contact_circle(layers.get(scene.visible[a]), p, r, status, Some(&tooltip));
    }
    layers.write(svg, "contacts");
}
