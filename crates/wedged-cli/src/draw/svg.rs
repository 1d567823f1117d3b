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

use std::collections::HashMap;
use std::fmt::Write as _;

use wedged::NodeStatus;

use crate::draw::vtk::{check_view, View};
use crate::report::{sig4, trim_zeros};

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

/// The statuses in legend order.
const STATUSES: [NodeStatus; 6] = [
    NodeStatus::Stick,
    NodeStatus::SlipPlus,
    NodeStatus::SlipMinus,
    NodeStatus::Slip,
    NodeStatus::Grazing,
    NodeStatus::Separated,
];

/// The statuses of the legend: those a configuration of this dimension can have (2D slips one
/// way or the other, 3D on the round friction cone), and any other one the view holds.
fn legend_statuses(view: &View) -> Vec<NodeStatus> {
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

fn finite3(v: &P3) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn add3(a: P3, b: P3, s: f64) -> P3 {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

fn dot3(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm3(a: P3) -> f64 {
    dot3(a, a).sqrt()
}

fn unit2(v: P2) -> Option<P2> {
    let n = (v[0] * v[0] + v[1] * v[1]).sqrt();
    (n > 0.0 && n.is_finite()).then(|| [v[0] / n, v[1] / n])
}

fn cross3(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit3(v: P3) -> Option<P3> {
    let n = norm3(v);
    (n > 0.0 && n.is_finite()).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

/// The area-weighted normal of a polygon (Newell's method; right-hand rule on the node order).
fn polygon_normal(ps: &[P3]) -> P3 {
    let mut n = [0.0; 3];
    for (k, p) in ps.iter().enumerate() {
        let q = ps[(k + 1) % ps.len()];
        n = add3(n, cross3(*p, q), 0.5);
    }
    n
}

fn mean3(ps: &[P3]) -> P3 {
    ps.iter()
        .fold([0.0; 3], |s, &p| add3(s, p, 1.0 / ps.len() as f64))
}

/// The outward (from the body into the obstacle) area-weighted normal of each 3D contact face,
/// undeformed, oriented against the inward normals of its contact nodes; `None` if that is not
/// possible (an edge, or no contact node with a frame).
fn contact_face_normals(view: &View) -> Vec<Option<P3>> {
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
            let n = polygon_normal(&f.iter().map(|&a| x[a]).collect::<Vec<_>>());
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
struct Projection {
    three_d: bool,
    /// The octant the 3D view looks from, e.g. `[1, 1, 1]`.
    from: [i8; 3],
    right: P3,
    up: P3,
    /// Unit vector towards the viewer.
    towards: P3,
}

impl Projection {
    fn flat() -> Projection {
        Projection {
            three_d: false,
            from: [0, 0, 1],
            right: [1.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            towards: [0.0, 0.0, 1.0],
        }
    }

    /// The isometric view from the octant `from`, z up on the page.
    fn isometric(from: [i8; 3]) -> Projection {
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
    fn choose(view: &View) -> Projection {
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

    fn project(self, p: P3) -> P2 {
        [dot3(p, self.right), dot3(p, self.up)]
    }

    /// Distance towards the viewer (3D), for painter's order.
    fn depth(self, p: P3) -> f64 {
        dot3(p, self.towards)
    }
}

/// Maps projected model coordinates to page pixels (y up in the model, down on the page).
struct Page {
    scale: f64,
    ox: f64,
    oy: f64,
}

impl Page {
    /// Fits the box `lo..hi` into the drawing area, centred.
    fn fit(lo: P2, hi: P2) -> Page {
        let (x0, x1) = (MARGIN + PAD, WIDTH - PANEL - PAD);
        let (y0, y1) = (TOP + PAD, HEIGHT - BOTTOM - PAD);
        let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
        let scale = match (w > 0.0, h > 0.0) {
            (true, true) => ((x1 - x0) / w).min((y1 - y0) / h),
            (true, false) => (x1 - x0) / w,
            (false, true) => (y1 - y0) / h,
            (false, false) => 1.0,
        };
        let scale = if scale.is_finite() && scale > 0.0 {
            scale
        } else {
            1.0
        };
        let cx = 0.5 * (lo[0] + hi[0]);
        let cy = 0.5 * (lo[1] + hi[1]);
        Page {
            scale,
            ox: 0.5 * (x0 + x1) - scale * cx,
            oy: 0.5 * (y0 + y1) + scale * cy,
        }
    }

    fn map(&self, p: P2) -> P2 {
        [self.ox + self.scale * p[0], self.oy - self.scale * p[1]]
    }

    /// A model direction (projected) on the page.
    fn dir(&self, v: P2) -> P2 {
        [v[0], -v[1]]
    }
}

/// Everything computed from the view before drawing.
struct Scene<'v, 'a> {
    view: &'v View<'a>,
    projection: Projection,
    /// Displacement magnification, `None` if there is no displacement.
    factor: Option<f64>,
    /// Deformed positions (3D), `None` where the displacement is not finite.
    deformed: Vec<Option<P3>>,
    /// Reaction arrows: contact index, start and end (model coordinates, 3D).
    arrows: Vec<(usize, P3, P3)>,
    /// The largest reaction magnitude at a contact node.
    force_max: f64,
    /// Range of the finite von Mises stresses.
    vm_range: Option<(f64, f64)>,
    /// 3D: the boundary faces that face the viewer (element, page polygon, depth, unit outward
    /// normal), far to near. Empty in 2D.
    faces: Vec<Face>,
    /// Whether each node is on the visible side (always in 2D; on a front face in 3D).
    visible: Vec<bool>,
    page: Page,
}

/// A visible boundary face in 3D.
struct Face {
    element: usize,
    polygon: Vec<P2>,
    depth: f64,
    normal: P3,
}

impl<'v, 'a> Scene<'v, 'a> {
    fn new(view: &'v View<'a>) -> Self {
        let mesh = view.mesh;
        let state = view.state;
        let coords = mesh.coords();
        let projection = if mesh.dim() == 3 {
            Projection::choose(view)
        } else {
            Projection::flat()
        };
        let size = mesh.size();
        let size = if size > 0.0 && size.is_finite() {
            size
        } else {
            1.0
        };

        let mut drawn = mesh.used_nodes();
        for &a in &view.boundary.contact_nodes {
            drawn[a] = true;
        }
        let u_max = state
            .displacement
            .iter()
            .zip(&drawn)
            .filter(|(u, &d)| d && finite3(u))
            .map(|(u, _)| norm3(*u))
            .fold(0.0, f64::max);
        let factor = (u_max > 0.0)
            .then(|| round3(DISPLACEMENT_FRACTION * size / u_max))
            .filter(|f| f.is_finite() && *f > 0.0);
        let deformed: Vec<Option<P3>> = coords
            .iter()
            .zip(&state.displacement)
            .map(|(x, u)| match factor {
                None => Some(*x),
                Some(f) => finite3(u).then(|| add3(*x, *u, f)),
            })
            .collect();

        let force_max = view
            .boundary
            .contact_nodes
            .iter()
            .map(|&a| state.force[a])
            .filter(finite3)
            .map(norm3)
            .fold(0.0, f64::max);
        let mut arrows = Vec::new();
        if force_max > 0.0 {
            let scale = ARROW_FRACTION * size / force_max;
            for (i, (&a, status)) in view
                .boundary
                .contact_nodes
                .iter()
                .zip(view.status)
                .enumerate()
            {
                let f = state.force[a];
                if !status.pressed() || !finite3(&f) || norm3(f) == 0.0 {
                    continue;
                }
                if let Some(p) = deformed[a] {
                    arrows.push((i, p, add3(p, f, scale)));
                }
            }
        }

        let vm_range = state.von_mises.iter().filter(|v| v.is_finite()).fold(
            None,
            |r: Option<(f64, f64)>, &v| match r {
                None => Some((v, v)),
                Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
            },
        );

        // Fit everything drawn: undeformed and deformed nodes, arrow tips.
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut extend = |p: P3| {
            let q = projection.project(p);
            if q.iter().all(|v| v.is_finite()) {
                for k in 0..2 {
                    lo[k] = lo[k].min(q[k]);
                    hi[k] = hi[k].max(q[k]);
                }
            }
        };
        for (a, x) in coords.iter().enumerate() {
            if drawn[a] {
                extend(*x);
                if let Some(p) = deformed[a] {
                    extend(p);
                }
            }
        }
        for &(_, _, tip) in &arrows {
            extend(tip);
        }
        if !(lo[0] <= hi[0] && lo[1] <= hi[1]) {
            lo = [0.0; 2];
            hi = [0.0; 2];
        }
        let page = Page::fit(lo, hi);
        let mut scene = Scene {
            view,
            projection,
            factor,
            deformed,
            arrows,
            force_max,
            vm_range,
            faces: Vec::new(),
            visible: vec![true; coords.len()],
            page,
        };
        if projection.three_d {
            scene.find_faces();
        }
        scene
    }

    /// 3D: the deformed boundary faces facing the viewer, sorted far to near, and the nodes on
    /// them.
    fn find_faces(&mut self) {
        let view = self.view;
        let mut faces = Vec::new();
        let mut visible = vec![false; self.visible.len()];
        for (e, f) in boundary_facets(view) {
            let ps: Option<Vec<P3>> = f.iter().map(|&a| self.deformed[a]).collect();
            let Some(ps) = ps else { continue };
            let element = &view.mesh.elements()[e].nodes;
            let all: Option<Vec<P3>> = element.iter().map(|&a| self.deformed[a]).collect();
            let Some(all) = all else { continue };
            let mut n = polygon_normal(&ps);
            if dot3(n, add3(mean3(&ps), mean3(&all), -1.0)) < 0.0 {
                n = add3([0.0; 3], n, -1.0);
            }
            let Some(n) = unit3(n) else { continue };
            if dot3(n, self.projection.towards) <= 1e-12 {
                continue;
            }
            for &a in &f {
                visible[a] = true;
            }
            let depth = self.projection.depth(mean3(&ps));
            faces.push(Face {
                element: e,
                polygon: ps.iter().map(|&p| self.at(p)).collect(),
                depth,
                normal: n,
            });
        }
        faces.sort_by(|a, b| a.depth.total_cmp(&b.depth));
        self.faces = faces;
        self.visible = visible;
    }

    /// Page position of a model point.
    fn at(&self, p: P3) -> P2 {
        self.page.map(self.projection.project(p))
    }

    /// Page position of a node, undeformed.
    fn undeformed(&self, a: usize) -> P2 {
        self.at(self.view.mesh.coords()[a])
    }

    /// Page position of a node, deformed.
    fn deformed(&self, a: usize) -> Option<P2> {
        self.deformed[a].map(|p| self.at(p))
    }

    /// The fill colour of an element, `None` for a NaN stress.
    fn fill(&self, e: usize, shade: f64) -> Option<String> {
        let v = self.view.state.von_mises[e];
        if !v.is_finite() {
            return None;
        }
        let (lo, hi) = self.vm_range?;
        let t = if hi - lo > 1e-12 * hi.abs().max(lo.abs()) {
            (v - lo) / (hi - lo)
        } else {
            0.5
        };
        Some(shaded(t, shade))
    }
}

/// The facets (2D edges, 3D faces) that belong to exactly one element, with that element, in
/// mesh order.
fn boundary_facets(view: &View) -> Vec<(usize, Vec<usize>)> {
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

fn centroid(view: &View, nodes: &[usize]) -> P3 {
    let mut c = [0.0; 3];
    for &a in nodes {
        c = add3(c, view.mesh.coords()[a], 1.0 / nodes.len() as f64);
    }
    c
}

/// The outward unit normal (model, 2D) of the boundary edge `a-b` of element `e`.
fn outward_2d(view: &View, e: usize, a: usize, b: usize) -> Option<P2> {
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

/// An arrow from `p` to `q` (page): a shaft and a filled head, with a white halo.
fn arrow(out: &mut String, class: &str, p: P2, q: P2, tooltip: Option<&str>) {
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
fn support_triangle(out: &mut String, p: P2, o: P2, filled: bool) {
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
fn support_square(out: &mut String, p: P2, filled: bool) {
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
fn contact_circle(out: &mut String, p: P2, r: f64, status: NodeStatus, tooltip: Option<&str>) {
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

/// 2D: deformed elements filled by von Mises, undeformed outline, obstacle.
fn draw_body_2d(svg: &mut Svg, scene: &Scene) {
    let view = scene.view;
    svg.raw("<g class=\"deformed\" stroke=\"#1a1a1a\" stroke-width=\"0.6\" stroke-opacity=\"0.55\" stroke-linejoin=\"round\">\n");
    for (e, element) in view.mesh.elements().iter().enumerate() {
        let ps: Option<Vec<P2>> = element.nodes.iter().map(|&a| scene.deformed(a)).collect();
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
fn draw_body_3d(svg: &mut Svg, scene: &Scene) {
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
        for (k, &a) in f.iter().enumerate() {
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
fn draw_supports(svg: &mut Svg, scene: &Scene) {
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
                for a in [f[0], f[1]] {
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
struct Layers {
    shown: String,
    hidden: String,
}

impl Layers {
    fn get(&mut self, visible: bool) -> &mut String {
        if visible {
            &mut self.shown
        } else {
            &mut self.hidden
        }
    }

    /// A group `class` with the hidden items (faded) below the shown ones.
    fn write(&self, svg: &mut Svg, class: &str) {
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
fn components(v: &P3, dim: usize) -> String {
    v[..dim]
        .iter()
        .map(|&x| sig4(x))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Reaction arrows at pressed contact nodes.
fn draw_reactions(svg: &mut Svg, scene: &Scene) {
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
fn draw_contacts(svg: &mut Svg, scene: &Scene) {
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

/// The legend, the colour bar and the axes, in the right column.
fn draw_legend(svg: &mut Svg, scene: &Scene) {
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
fn draw_caption(svg: &mut Svg, scene: &Scene) {
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

#[cfg(test)]
mod tests;
