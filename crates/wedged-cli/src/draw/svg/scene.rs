//! The picture's layout: the page's drawing area and the mesh projected onto it (`Scene`).

use super::geometry::{
    add3, around, boundary_facets, dot3, finite3, mean3, norm3, polygon_normal, unit3, Projection,
};
use super::{
    round3, shaded, ARROW_FRACTION, BOTTOM, DISPLACEMENT_FRACTION, HEIGHT, MARGIN, P2, P3, PAD,
    PANEL, TOP, WIDTH,
};
use crate::draw::vtk::View;

/// Maps projected model coordinates to page pixels (y up in the model, down on the page).
pub(super) struct Page {
    pub(super) scale: f64,
    pub(super) ox: f64,
    pub(super) oy: f64,
}

impl Page {
    /// Fits the box `lo..hi` into the drawing area, centred.
    pub(super) fn fit(lo: P2, hi: P2) -> Page {
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

    pub(super) fn map(&self, p: P2) -> P2 {
        [self.ox + self.scale * p[0], self.oy - self.scale * p[1]]
    }

    /// A model direction (projected) on the page.
    pub(super) fn dir(&self, v: P2) -> P2 {
        [v[0], -v[1]]
    }
}

/// Everything computed from the view before drawing.
pub(super) struct Scene<'v, 'a> {
    pub(super) view: &'v View<'a>,
    pub(super) projection: Projection,
    /// Displacement magnification, `None` if there is no displacement.
    pub(super) factor: Option<f64>,
    /// Deformed positions (3D), `None` where the displacement is not finite.
    pub(super) deformed: Vec<Option<P3>>,
    /// Reaction arrows: contact index, start and end (model coordinates, 3D).
    pub(super) arrows: Vec<(usize, P3, P3)>,
    /// The largest reaction magnitude at a contact node.
    pub(super) force_max: f64,
    /// Range of the finite von Mises stresses.
    pub(super) vm_range: Option<(f64, f64)>,
    /// 3D: the boundary faces that face the viewer (element, page polygon, depth, unit outward
    /// normal), far to near. Empty in 2D.
    pub(super) faces: Vec<Face>,
    /// Whether each node is on the visible side (always in 2D; on a front face in 3D).
    pub(super) visible: Vec<bool>,
    pub(super) page: Page,
}

/// A visible boundary face in 3D.
pub(super) struct Face {
    pub(super) element: usize,
    pub(super) polygon: Vec<P2>,
    pub(super) depth: f64,
    pub(super) normal: P3,
}

impl<'v, 'a> Scene<'v, 'a> {
    pub(super) fn new(view: &'v View<'a>) -> Self {
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
    pub(super) fn find_faces(&mut self) {
        let view = self.view;
        let mut faces = Vec::new();
        let mut visible = vec![false; self.visible.len()];
        for (e, f) in boundary_facets(view) {
            let f = around(&f);
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
    pub(super) fn at(&self, p: P3) -> P2 {
        self.page.map(self.projection.project(p))
    }

    /// Page position of a node, undeformed.
    pub(super) fn undeformed(&self, a: usize) -> P2 {
        self.at(self.view.mesh.coords()[a])
    }

    /// Page position of a node, deformed.
    pub(super) fn deformed(&self, a: usize) -> Option<P2> {
        self.deformed[a].map(|p| self.at(p))
    }

    /// The fill colour of an element, `None` for a NaN stress.
    pub(super) fn fill(&self, e: usize, shade: f64) -> Option<String> {
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
