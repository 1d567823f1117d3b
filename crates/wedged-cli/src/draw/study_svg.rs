//! The plot of `wedged study`: `mu*` against one parameter (or the mesh size `h`), a line per
//! combination of the other parameters. A point whose run did not complete is drawn hollow at
//! its upper end (a checked wedged configuration: `mu*` is at most that); a point that never
//! wedges has no marker and is listed under the plot. With an extrapolation (a mesh-convergence
//! series), a dashed line marks the extrapolated limit and the x axis starts at 0.

use std::fmt::Write;

use crate::draw::svg::{escape, px, INK};
use crate::draw::sweep_svg::{nice_ticks, tick_label};
use crate::report::sig4;
use wedged_cli::study::Extrapolation;

const WIDTH: f64 = 760.0;
const HEIGHT: f64 = 480.0;
const LEFT: f64 = 86.0;
/// The plot's right edge with a legend beside it, and without.
const RIGHT_LEGEND: f64 = WIDTH - 200.0;
const RIGHT_ALONE: f64 = WIDTH - 40.0;
const TOP: f64 = 64.0;
const BOTTOM: f64 = HEIGHT - 84.0;
const GRID: &str = "#dddddd";
const LIMIT_COLOUR: &str = "#d62728";
/// Line colours, in turn (matplotlib's first six).
const COLOURS: [&str; 6] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2",
];

/// One point of a series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// The x value.
    pub x: f64,
    /// `mu*` (complete) or the upper end found so far (incomplete); `None`: never wedges, or
    /// nothing found.
    pub mu: Option<f64>,
    /// Whether the point's run completed.
    pub complete: bool,
}

/// A line of the plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// The other parameters' values (empty with one parameter).
    pub label: String,
    /// Its points, in any order (drawn sorted by x).
    pub points: Vec<Point>,
}

/// The page (module docs). `x_label` names the x axis.
pub fn study_svg(
    title: &str,
    x_label: &str,
    series: &[Series],
    limit: Option<Extrapolation>,
    note: Option<&str>,
) -> String {
    let mut out = crate::draw::svg::preamble(WIDTH, HEIGHT, title, 24.0, 32.0, 0.62);
    let right = if series.iter().any(|s| !s.label.is_empty()) {
        RIGHT_LEGEND
    } else {
        RIGHT_ALONE
    };
    let plotted: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter_map(|p| p.mu.map(|mu| (p.x, mu)))
        .collect();
    if plotted.is_empty() {
        let _ = writeln!(
            out,
            "<text class=\"message\" x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"15\" \
             fill=\"{INK}\">No point of the study has a wedged configuration yet: nothing to \
             plot.</text>\n</svg>",
            px(WIDTH / 2.0),
            px(HEIGHT / 2.0)
        );
        return out;
    }
    let (mut x0, mut x1) = plotted
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    let (mut y0, mut y1) = plotted
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    if let Some(e) = limit {
        x0 = 0.0;
        y0 = y0.min(e.limit);
        y1 = y1.max(e.limit);
    }
    let pad = |lo: f64, hi: f64| {
        let span = hi - lo;
        let margin = if span > 0.0 {
            0.06 * span
        } else {
            0.05 * lo.abs().max(1.0)
        };
        (lo - margin, hi + margin)
    };
    if limit.is_none() {
        (x0, x1) = pad(x0, x1);
    } else {
        x1 = pad(x0, x1).1;
    }
    (y0, y1) = pad(y0, y1);
    let x = |v: f64| LEFT + (v - x0) / (x1 - x0) * (right - LEFT);
    let y = |v: f64| BOTTOM - (v - y0) / (y1 - y0) * (BOTTOM - TOP);

    let (xticks, xstep) = nice_ticks(x0, x1, 7);
    let (yticks, ystep) = nice_ticks(y0, y1, 7);
    let _ = writeln!(
        out,
        "<g class=\"grid\" stroke=\"{GRID}\" stroke-width=\"1\">"
    );
    for &t in &xticks {
        let _ = writeln!(
            out,
            "<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\"/>",
            px(x(t)),
            px(TOP),
            px(BOTTOM)
        );
    }
    for &t in &yticks {
        let _ = writeln!(
            out,
            "<line x1=\"{1}\" y1=\"{0}\" x2=\"{2}\" y2=\"{0}\"/>",
            px(y(t)),
            px(LEFT),
            px(right)
        );
    }
    let _ = writeln!(
        out,
        "</g>\n<g class=\"axes\" stroke=\"{INK}\" stroke-width=\"1.2\" fill=\"none\">\n\
         <polyline points=\"{l},{t} {l},{b} {r},{b}\"/>\n</g>",
        l = px(LEFT),
        t = px(TOP),
        b = px(BOTTOM),
        r = px(right)
    );
    let _ = writeln!(out, "<g class=\"tick-labels\" fill=\"{INK}\">");
    for &t in &xticks {
        let _ = writeln!(
            out,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>",
            px(x(t)),
            px(BOTTOM + 19.0),
            tick_label(t, xstep)
        );
    }
    for &t in &yticks {
        let _ = writeln!(
            out,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>",
            px(LEFT - 9.0),
            px(y(t) + 4.0),
            tick_label(t, ystep)
        );
    }
    let _ = writeln!(
        out,
        "</g>\n<text class=\"axis-label\" x=\"{}\" y=\"{}\" text-anchor=\"middle\" \
         font-size=\"13\" fill=\"{INK}\">{}</text>",
        px((LEFT + right) / 2.0),
        px(BOTTOM + 42.0),
        escape(x_label)
    );
    let _ = writeln!(
        out,
        "<text class=\"axis-label\" x=\"{0}\" y=\"{1}\" text-anchor=\"middle\" font-size=\"13\" \
         fill=\"{INK}\" transform=\"rotate(-90 {0} {1})\">critical friction coefficient mu*</text>",
        px(LEFT - 60.0),
        px((TOP + BOTTOM) / 2.0)
    );

    if let Some(e) = limit {
        let order = if e.order.is_finite() {
            format!(", order {}", sig4(e.order))
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "<line class=\"limit\" x1=\"{l}\" y1=\"{y}\" x2=\"{r}\" y2=\"{y}\" \
             stroke=\"{LIMIT_COLOUR}\" stroke-width=\"1.5\" stroke-dasharray=\"6 4\"/>\n\
             <text class=\"limit-label\" x=\"{tx}\" y=\"{ty}\" font-size=\"12\" \
             fill=\"{LIMIT_COLOUR}\">extrapolated h = 0: {v}{order}</text>",
            l = px(LEFT),
            r = px(right),
            y = px(y(e.limit)),
            tx = px(LEFT + 8.0),
            ty = px(y(e.limit) - 6.0),
            v = sig4(e.limit)
        );
    }

    if let Some(note) = note {
        let _ = writeln!(
            out,
            "<text class=\"note\" x=\"{}\" y=\"{}\" font-size=\"12\" fill=\"{LIMIT_COLOUR}\">{}</text>",
            px(LEFT),
            px(TOP - 12.0),
            escape(note)
        );
    }
    let mut never = Vec::new();
    for (k, s) in series.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        let mut points: Vec<Point> = s.points.clone();
        points.sort_by(|a, b| a.x.total_cmp(&b.x));
        let line: Vec<String> = points
            .iter()
            .filter_map(|p| p.mu.map(|mu| format!("{},{}", px(x(p.x)), px(y(mu)))))
            .collect();
        let _ = writeln!(out, "<g class=\"series\" stroke=\"{colour}\">");
        if line.len() > 1 {
            let _ = writeln!(
                out,
                "<polyline points=\"{}\" fill=\"none\" stroke-width=\"1.8\"/>",
                line.join(" ")
            );
        }
        for p in &points {
            match p.mu {
                Some(mu) => {
                    let fill = if p.complete { colour } else { "#ffffff" };
                    let note = if p.complete {
                        ""
                    } else {
                        " (incomplete: at most this)"
                    };
                    let _ = writeln!(
                        out,
                        "<circle cx=\"{}\" cy=\"{}\" r=\"3.5\" fill=\"{fill}\" \
                         stroke-width=\"1.5\"><title>{}: mu* = {}{note}</title></circle>",
                        px(x(p.x)),
                        px(y(mu)),
                        escape(&format!("{x_label} {}", sig4(p.x))),
                        sig4(mu)
                    );
                }
                None => never.push(format!("{} {}", s.label, sig4(p.x))),
            }
        }
        out.push_str("</g>\n");
        // The legend, right of the plot.
        let ly = TOP + 10.0 + 20.0 * k as f64;
        if !s.label.is_empty() && ly < BOTTOM {
            let _ = writeln!(
                out,
                "<line x1=\"{x1}\" y1=\"{y}\" x2=\"{x2}\" y2=\"{y}\" stroke=\"{colour}\" \
                 stroke-width=\"2\"/>\n<text x=\"{tx}\" y=\"{ty}\" fill=\"{INK}\">{label}</text>",
                x1 = px(right + 16.0),
                y = px(ly),
                x2 = px(right + 36.0),
                tx = px(right + 42.0),
                ty = px(ly + 4.0),
                label = escape(&s.label)
            );
        }
    }
    if !never.is_empty() {
        let _ = writeln!(
            out,
            "<text class=\"never\" x=\"{}\" y=\"{}\" fill=\"{INK}\">not plotted (never wedges, \
             or nothing found before a limit): {}</text>",
            px(LEFT),
            px(HEIGHT - 14.0),
            escape(&never.join("; "))
        );
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_per_series_and_a_marker_per_point() {
        let series = vec![
            Series {
                label: "poisson 0.2".into(),
                points: vec![
                    Point {
                        x: 0.2,
                        mu: Some(1.8),
                        complete: true,
                    },
                    Point {
                        x: 0.1,
                        mu: Some(1.79),
                        complete: false,
                    },
                    Point {
                        x: 0.05,
                        mu: None,
                        complete: true,
                    },
                ],
            },
            Series {
                label: "poisson 0.3".into(),
                points: vec![Point {
                    x: 0.2,
                    mu: Some(1.7),
                    complete: true,
                }],
            },
        ];
        let svg = study_svg(
            "mu* of plug",
            "h",
            &series,
            None,
            Some("grows like ln(1/h)"),
        );
        assert!(svg.contains("grows like ln(1/h)"));
        assert_eq!(
            svg.matches("<polyline points=").count(),
            2,
            "axes and one line"
        );
        assert_eq!(svg.matches("<circle").count(), 3);
        assert!(
            svg.contains("fill=\"#ffffff\" stroke-width"),
            "the incomplete point is hollow"
        );
        assert!(svg.contains("not plotted"));
        assert!(svg.ends_with("</svg>\n"));
        let limit = Extrapolation {
            limit: 1.75,
            order: 1.0,
            coefficient: 0.3,
        };
        let svg = study_svg("mu* of plug", "h", &series, Some(limit), None);
        assert!(svg.contains("extrapolated h = 0: 1.75, order 1"));
        let empty = study_svg("t", "h", &[], None, None);
        assert!(empty.contains("nothing to plot"));
    }
}
