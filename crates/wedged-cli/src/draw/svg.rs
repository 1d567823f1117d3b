//! SVG picture of one wedged configuration, for a quick look without ParaView.
//!
//! [`svg_string`] draws, on a 900 x 700 px page:
//!
//! - 2D: the deformed mesh (every element, thin edges) with the displacement magnified so that
//!   the largest displacement is about 8 % of the body's size, elements filled by the von Mises
//!   stress at their centroid (viridis, colour bar with min/max); the undeformed outline (the
//!   element edges that belong to one element only) in grey dashes; the rigid obstacle: each
//!   contact facet as a thick dark line at its undeformed position, hatched on the obstacle side
//!   (opposite to the inward normal `frames[i].n`); the reaction of the obstacle on the body
//!   (`state.force` at pressed contact nodes) as arrows from the node, the longest about 12 % of
//!   the body's size; contact nodes as circles coloured by status; clamped nodes as black
//!   triangles (roller nodes as hollow ones) pointing at the node from outside the body; y up.
//! - 3D: an isometric projection (viewed from `(1, 1, 1)`, z up) of the deformed boundary faces
//!   (faces of one element only) filled by von Mises stress, drawn far to near (painter's
//!   order); the contact faces' undeformed outlines; clamped nodes as black squares; contact
//!   nodes and reaction arrows as in 2D, projected.
//!
//! A title line (`view.title`), a caption with the magnification, a legend (statuses with
//! counts, symbols) and the colour bar complete the picture. Contact circles carry a tooltip
//! (`<title>`) with the node number (1-based), status and reaction. Elements are tagged with
//! classes (`contact status-stick`, `reaction`, `legend`, ...) so that tests and style sheets can
//! find them.
//!
//! Degenerate input does not panic: zero displacement draws the undeformed shape (factor 1,
//! "no displacement"), zero reactions draw no arrows, items with NaN values are skipped, and
//! arrays whose sizes do not match the mesh give a picture with the error message.
//!
//! The unit tests write sample pictures when `WEDGED_SVG_SAMPLE_DIR` is set:
//! `WEDGED_SVG_SAMPLE_DIR=/tmp cargo test -p wedged-cli --bin wedged svg` writes
//! `/tmp/svg-sample-2d.svg` (a trapezoidal plug) and `/tmp/svg-sample-3d.svg` (a frustum).
//!
//! Files: this one holds the page (constants, colours, the `Svg` writer) and [`svg_string`];
//! `geometry` the vector helpers and the 3D projection; `scene` the mesh laid out on the page;
//! `body` the marks of the body (elements or faces, supports, reactions, contacts); `legend` the
//! legend, colour bar and caption.

mod body;
mod geometry;
mod legend;
mod scene;

use std::fmt::Write as _;

use wedged::NodeStatus;

use crate::draw::vtk::{check_view, View};
use crate::report::trim_zeros;

use body::{draw_body_2d, draw_body_3d, draw_contacts, draw_reactions, draw_supports};
use legend::{draw_caption, draw_legend};
use scene::Scene;

const WIDTH: f64 = 900.0;
const HEIGHT: f64 = 700.0;
const MARGIN: f64 = 24.0;
/// Width of the right column (legend, colour bar, axes).
const PANEL: f64 = 190.0;
/// Top of the drawing area (below the title).
const TOP: f64 = 48.0;
/// Height reserved for the caption at the bottom.
const BOTTOM: f64 = 50.0;
/// Free space around the body inside the drawing area, for hatches and symbols.
const PAD: f64 = 18.0;
/// The largest displacement is drawn as this fraction of the body's size.
const DISPLACEMENT_FRACTION: f64 = 0.08;
/// The longest reaction arrow is this fraction of the body's size.
const ARROW_FRACTION: f64 = 0.12;
pub(crate) const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";
pub(crate) const INK: &str = "#222222";
/// Reaction arrows.
const ARROW: &str = "#111111";

/// Viridis at 0, 1/16, ..., 1 (matplotlib).
const VIRIDIS: [u32; 17] = [
    0x440154, 0x48186a, 0x472d7b, 0x424086, 0x3b528b, 0x33638d, 0x2c728e, 0x26828e, 0x21918c,
    0x1fa088, 0x28ae80, 0x3fbc73, 0x5ec962, 0x84d44b, 0xaddc30, 0xd8e219, 0xfde725,
];

type P2 = [f64; 2];
type P3 = [f64; 3];

/// The viridis colour at `t` in `[0, 1]`, as `#rrggbb`.
fn viridis(t: f64) -> String {
    shaded(t, 1.0)
}

/// The viridis colour at `t` darkened by the factor `shade` (`1` for none).
fn shaded(t: f64, shade: f64) -> String {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.5
    };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let channel = |c: u32, shift: u32| ((c >> shift) & 0xff) as f64;
    let mix = |shift: u32| {
        let a = channel(VIRIDIS[i], shift);
        let b = channel(VIRIDIS[i + 1], shift);
        ((a + (b - a) * f) * shade.clamp(0.0, 1.0)).round() as u8
    };
    format!("#{:02x}{:02x}{:02x}", mix(16), mix(8), mix(0))
}

/// CSS class suffix, fill and stroke of a status marker.
fn status_style(status: NodeStatus) -> (&'static str, &'static str, &'static str) {
    match status {
        NodeStatus::Separated => ("separated", "#ffffff", "#7f7f7f"),
        NodeStatus::Stick => ("stick", "#1f77b4", "#0d3a5c"),
        NodeStatus::SlipPlus => ("slip-plus", "#ff7f0e", "#8a4100"),
        NodeStatus::SlipMinus => ("slip-minus", "#d62728", "#6e1010"),
        NodeStatus::Grazing => ("grazing", "#9467bd", "#4a2c66"),
        NodeStatus::Slip => ("slip", "#ff7f0e", "#8a4100"),
    }
}

/// A pixel coordinate, to 0.1 px.
pub(crate) fn px(v: f64) -> String {
    let s = trim_zeros(&format!("{v:.1}"));
    if s == "-0" {
        "0".to_string()
    } else {
        s
    }
}

/// `v` rounded to 3 significant digits.
fn round3(v: f64) -> f64 {
    if !(v.is_finite() && v > 0.0) {
        return v;
    }
    let m = 10f64.powi(v.log10().floor() as i32 - 2);
    let r = (v / m).round() * m;
    if r.is_finite() && r > 0.0 {
        r
    } else {
        v
    }
}

/// Escapes text for XML content and attribute values.
pub(crate) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Writes an SVG document.
struct Svg {
    out: String,
}

/// The start of an SVG page `width x height` (pixels): the root element, its `<title>`, a white
/// background, and the title in bold at `(x, baseline)`, shrunk to fit the width between margins
/// `x` on either side when it is long (`em`: the width of a bold character in ems, for this
/// page's font). The caller closes the root element.
pub fn preamble(width: f64, height: f64, title: &str, x: f64, baseline: f64, em: f64) -> String {
    let mut out = String::with_capacity(64 * 1024);
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\" font-family=\"{FONT}\" font-size=\"12\">\n\
         <title>{t}</title>\n\
         <rect class=\"background\" width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>\n",
        w = width,
        h = height,
        t = escape(title),
    );
    let chars = title.chars().count().max(1) as f64;
    let font = (16.0f64).min((width - 2.0 * x) / (em * chars)).max(8.0);
    let _ = writeln!(
        out,
        "<text class=\"title\" x=\"{}\" y=\"{}\" font-size=\"{}\" font-weight=\"bold\" \
         fill=\"{INK}\">{}</text>",
        px(x),
        px(baseline),
        px(font),
        escape(title)
    );
    out
}

impl Svg {
    fn new(title: &str) -> Svg {
        let out = preamble(WIDTH, HEIGHT, title, MARGIN, 30.0, 0.56);
        Svg { out }
    }

    fn raw(&mut self, s: &str) {
        self.out.push_str(s);
    }

    fn text(&mut self, class: &str, x: f64, y: f64, extra: &str, text: &str) {
        let _ = writeln!(
            self.out,
            "<text class=\"{class}\" x=\"{}\" y=\"{}\" fill=\"{INK}\"{extra}>{}</text>",
            px(x),
            px(y),
            escape(text)
        );
    }

    fn finish(mut self) -> String {
        self.out.push_str("</svg>\n");
        self.out
    }
}

/// `points` attribute of a polygon.
fn points(ps: &[P2]) -> String {
    ps.iter()
        .map(|p| format!("{},{}", px(p[0]), px(p[1])))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The picture of one wedged configuration (see the module documentation).
pub fn svg_string(view: &View) -> String {
    let mut svg = Svg::new(&view.title);
    if let Err(e) = check_view(view) {
        svg.text(
            "error",
            MARGIN,
            TOP + 30.0,
            " font-size=\"14\"",
            &format!("cannot draw this configuration: {e}"),
        );
        return svg.finish();
    }
    let scene = Scene::new(view);
    if scene.projection.three_d {
        draw_body_3d(&mut svg, &scene);
    } else {
        draw_body_2d(&mut svg, &scene);
    }
    draw_supports(&mut svg, &scene);
    draw_reactions(&mut svg, &scene);
    draw_contacts(&mut svg, &scene);
    draw_legend(&mut svg, &scene);
    draw_caption(&mut svg, &scene);
    svg.finish()
}

#[cfg(test)]
mod tests;
