//! The right-hand column (status legend with counts, symbols, colour bar) and the caption.

use std::fmt::Write as _;

use wedged::NodeStatus;

use super::body::{arrow, contact_circle, support_square, support_triangle};
use super::scene::Scene;
use super::{px, viridis, Svg, BOTTOM, HEIGHT, INK, MARGIN, P3, PANEL, TOP, VIRIDIS, WIDTH};
use crate::draw::vtk::View;
use crate::report::sig4;

/// The statuses in legend order.
pub(super) const STATUSES: [NodeStatus; 6] = [
    NodeStatus::Stick,
    NodeStatus::SlipPlus,
    NodeStatus::SlipMinus,
    NodeStatus::Slip,
    NodeStatus::Grazing,
    NodeStatus::Separated,
];

/// The statuses of the legend: those a configuration of this dimension can have (2D slips one
/// way or the other, 3D on the round friction cone), and any other one the view holds.
pub(super) fn legend_statuses(view: &View) -> Vec<NodeStatus> {
    let three_d = view.mesh.dim() == 3;
    STATUSES
        .into_iter()
        .filter(|&s| {
            view.status.contains(&s)
                || match s {
                    NodeStatus::SlipPlus | NodeStatus::SlipMinus => !three_d,
                    NodeStatus::Slip => three_d,
                    _ => true,
                }
        })
        .collect()
}

/// The legend, the colour bar and the axes, in the right column.
pub(super) fn draw_legend(svg: &mut Svg, scene: &Scene) {
    let view = scene.view;
    let x0 = WIDTH - PANEL + 6.0;
    let tx = x0 + 26.0;
    let mut y = TOP + 14.0;
    svg.raw("<g class=\"legend\">\n");
    svg.text(
        "legend-heading",
        x0,
        y,
        " font-weight=\"bold\"",
        "Contact nodes",
    );
    for status in legend_statuses(view) {
        y += 19.0;
        let count = view.status.iter().filter(|&&s| s == status).count();
        let mut out = String::new();
        contact_circle(&mut out, [x0 + 10.0, y - 4.0], 4.5, status, None);
        // Legend markers must not count as contact nodes.
        let out = out.replace("class=\"contact status-", "class=\"legend-swatch status-");
        svg.raw(&out);
        svg.text(
            "legend-label",
            tx,
            y,
            "",
            &format!("{} ({count})", status.name()),
        );
    }
    y += 26.0;
    svg.text("legend-heading", x0, y, " font-weight=\"bold\"", "Symbols");
    y += 19.0;
    arrow(
        &mut svg.out,
        "legend-arrow",
        [x0, y - 4.0],
        [x0 + 20.0, y - 4.0],
        None,
    );
    svg.text("legend-label", tx, y, "", "reaction on the body");
    y += 19.0;
    if scene.projection.three_d {
        let _ = writeln!(
            svg.out,
            "<rect x=\"{}\" y=\"{}\" width=\"20\" height=\"10\" fill=\"url(#hatch)\" \
             stroke=\"{INK}\" stroke-width=\"1.1\" stroke-opacity=\"0.7\" \
             stroke-dasharray=\"4 2\"/>",
            px(x0),
            px(y - 9.0)
        );
        svg.text("legend-label", tx, y, "", "rigid obstacle");
    } else {
        let mut hatch = String::new();
        for k in 0..4 {
            let hx = x0 + 2.5 + 5.0 * k as f64;
            let _ = write!(hatch, "M{} {}l4.8 6", px(hx), px(y - 2.0));
        }
        let _ = writeln!(
            svg.out,
            "<path d=\"{hatch}\" stroke=\"{INK}\" stroke-width=\"1\"/><path d=\"M{} {}h20\" \
             stroke=\"{INK}\" stroke-width=\"3\" stroke-linecap=\"round\"/>",
            px(x0),
            px(y - 4.0)
        );
        svg.text("legend-label", tx, y, "", "rigid obstacle");
    }
    // Supports: filled for clamps, hollow for rollers.
    for (present, filled, label) in [
        (!view.boundary.clamped.is_empty(), true, "clamped"),
        (
            !view.boundary.rollers.is_empty(),
            false,
            "roller (symmetry)",
        ),
    ] {
        if !present {
            continue;
        }
        y += 19.0;
        if scene.projection.three_d {
            support_square(&mut svg.out, [x0 + 10.0, y - 4.0], filled);
        } else {
            support_triangle(&mut svg.out, [x0 + 10.0, y - 8.0], [0.0, 1.0], filled);
        }
        svg.text("legend-label", tx, y, "", label);
    }
    if !scene.projection.three_d {
        y += 19.0;
        let _ = writeln!(
            svg.out,
            "<path d=\"M{} {}h20\" stroke=\"#9a9a9a\" stroke-width=\"1.2\" \
             stroke-dasharray=\"5 3\"/>",
            px(x0),
            px(y - 4.0)
        );
        svg.text("legend-label", tx, y, "", "undeformed outline");
    }
    svg.raw("</g>\n");

    // Colour bar.
    y += 30.0;
    svg.raw("<g class=\"colorbar\">\n");
    svg.text(
        "legend-heading",
        x0,
        y,
        " font-weight=\"bold\"",
        "von Mises stress",
    );
    let bar_top = y + 10.0;
    let bar_height = 130.0f64.min(HEIGHT - BOTTOM - 90.0 - bar_top).max(40.0);
    match scene.vm_range {
        Some((lo, hi)) => {
            let uniform = hi - lo <= 1e-12 * hi.abs().max(lo.abs());
            svg.raw("<defs><linearGradient id=\"viridis\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">");
            for (k, _) in VIRIDIS.iter().enumerate() {
                let t = k as f64 / (VIRIDIS.len() - 1) as f64;
                let c = if uniform { viridis(0.5) } else { viridis(t) };
                let _ = write!(svg.out, "<stop offset=\"{}\" stop-color=\"{c}\"/>", sig4(t));
            }
            svg.raw("</linearGradient></defs>\n");
            let _ = writeln!(
                svg.out,
                "<rect x=\"{}\" y=\"{}\" width=\"16\" height=\"{}\" fill=\"url(#viridis)\" \
                 stroke=\"{INK}\" stroke-width=\"0.8\"/>",
                px(x0 + 2.0),
                px(bar_top),
                px(bar_height)
            );
            let lx = x0 + 24.0;
            if uniform {
                svg.text(
                    "colorbar-label",
                    lx,
                    bar_top + 0.5 * bar_height + 4.0,
                    "",
                    &format!("{} (uniform)", sig4(hi)),
                );
            } else {
                svg.text(
                    "colorbar-label",
                    lx,
                    bar_top + 9.0,
                    "",
                    &format!("max {}", sig4(hi)),
                );
                svg.text(
                    "colorbar-label",
                    lx,
                    bar_top + bar_height,
                    "",
                    &format!("min {}", sig4(lo)),
                );
            }
        }
        None => {
            svg.text("colorbar-label", x0, bar_top + 12.0, "", "not available");
        }
    }
    svg.raw("</g>\n");

    // Axes.
    let origin = [x0 + 14.0, HEIGHT - BOTTOM - 14.0];
    svg.raw("<g class=\"axes\" font-size=\"11\">\n");
    let axes: Vec<(&str, P3)> = if scene.projection.three_d {
        vec![
            ("x", [1.0, 0.0, 0.0]),
            ("y", [0.0, 1.0, 0.0]),
            ("z", [0.0, 0.0, 1.0]),
        ]
    } else {
        vec![("x", [1.0, 0.0, 0.0]), ("y", [0.0, 1.0, 0.0])]
    };
    for (name, e) in axes {
        let d = scene.page.dir(scene.projection.project(e));
        let q = [origin[0] + 26.0 * d[0], origin[1] + 26.0 * d[1]];
        arrow(&mut svg.out, "axis", origin, q, None);
        svg.text(
            "axis-label",
            q[0] + 9.0 * d[0] - 3.5,
            q[1] + 9.0 * d[1] + 4.0,
            "",
            name,
        );
    }
    svg.raw("</g>\n");
}

/// The caption: what is drawn and the magnification factors.
pub(super) fn draw_caption(svg: &mut Svg, scene: &Scene) {
    let magnification = match scene.factor {
        Some(f) => format!("displacements x {}", sig4(f)),
        None => "no displacement".to_string(),
    };
    let line1 = if scene.projection.three_d {
        let [a, b, c] = scene.projection.from;
        format!(
            "Isometric view from ({a}, {b}, {c}), z up: deformed boundary faces ({magnification}) \
             coloured by von Mises stress."
        )
    } else if scene.view.boundary.clamped.is_empty() {
        // A body that nothing clamps floats: its displacement includes the rigid motion the
        // witness found (u = K^+ r + R a), not only its deformation.
        format!(
            "Deformed mesh ({magnification}) coloured by von Mises stress; nothing clamps the \
             body: drawn where the witness moves it."
        )
    } else {
        format!(
            "Deformed mesh ({magnification}) coloured by von Mises stress at element centroids."
        )
    };
    let line2 = if scene.arrows.is_empty() {
        "No reaction at the contact nodes.".to_string()
    } else {
        format!(
            "Arrows: reaction of the obstacle on the body, longest |r| = {} (normal reactions sum \
             to 1).",
            sig4(scene.force_max),
        )
    };
    let y = HEIGHT - BOTTOM + 20.0;
    svg.raw("<g class=\"caption\" font-size=\"12\">\n");
    svg.text("caption", MARGIN, y, "", &line1);
    svg.text("caption", MARGIN, y + 17.0, "", &line2);
    svg.raw("</g>\n");
}
