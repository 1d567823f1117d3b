//! The plot of `wedged sweep --svg`: how many of the maximal patterns enumerated at
//! `mu_enumerated` are realised at each `mu`, a step function that rises by one at each pattern's
//! own threshold, from a little below `mu*` (where it is zero) to `mu_enumerated` (where it is
//! the number of patterns). A dashed vertical line marks `mu*`.
//!
//! A run with nothing to plot (the body never wedges, or the enumeration found nothing and the
//! branch and bound found `mu*`) gives a page that says so.

use std::fmt::Write;

use wedged::{Critical, CriticalStatus};

use crate::draw::svg::{escape, px, INK};
use crate::report::critical::bracket_text;
use crate::report::sig4;

const WIDTH: f64 = 760.0;
const HEIGHT: f64 = 460.0;
/// The plot area's edges.
const LEFT: f64 = 80.0;
const RIGHT: f64 = WIDTH - 30.0;
const TOP: f64 = 64.0;
const BOTTOM: f64 = HEIGHT - 64.0;
const STEP_COLOUR: &str = "#1f77b4";
const MU_STAR_COLOUR: &str = "#d62728";
const GRID: &str = "#dddddd";

/// The page: a step plot of a complete enumerate run, or a page with the reason there is none.
/// `source` names the problem in the title.
pub fn sweep_svg(source: &str, result: &Critical) -> String {
    // The file's name, not its whole path, keeps the title readable.
    let source = std::path::Path::new(source)
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or(source);
    let mu_star = result.mu_critical;
    match (result.status, mu_star, result.info.mu_enumerated) {
        (CriticalStatus::Wedged, Some(mu_star), Some(mu_enumerated))
            if !result.thresholds.is_empty() =>
        {
            step_plot(source, result, mu_star, mu_enumerated)
        }
        (CriticalStatus::Never, _, _) => message_page(
            &format!("Critical friction coefficient of {source}"),
            &[
                "No friction coefficient wedges this body",
                "(certified: the search is infeasible with friction unlimited),",
                "so no pattern has a threshold to plot.",
            ],
        ),
        (CriticalStatus::Wedged, Some(mu_star), _) => message_page(
            &format!("Critical friction coefficient of {source}"),
            &[
                &format!("mu* = {}", sig4(mu_star)),
                "The enumeration found no wedged configuration up to the largest mu it tried;",
                "mu* was found by branch and bound, which gives no per-pattern thresholds.",
            ],
        ),
        _ => message_page(
            &format!("Critical friction coefficient of {source}"),
            &["The run is incomplete: nothing to plot."],
        ),
    }
}

fn header(title: &str) -> String {
    crate::draw::svg::preamble(WIDTH, HEIGHT, title, 24.0, 32.0, 0.62)
}

fn message_page(title: &str, lines: &[&str]) -> String {
    let mut out = header(title);
    for (k, line) in lines.iter().enumerate() {
        let _ = writeln!(
            out,
            "<text class=\"message\" x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"15\" \
             fill=\"{INK}\">{}</text>",
            px(WIDTH / 2.0),
            px(HEIGHT / 2.0 - 20.0 + 24.0 * k as f64),
            escape(line)
        );
    }
    out.push_str("</svg>\n");
    out
}

/// Ticks at 1, 2 or 5 times a power of ten, about `target` of them, within `[lo, hi]`.
pub(crate) fn nice_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, f64) {
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite()) {
        return (vec![lo], 1.0);
    }
    let raw = span / target.max(1) as f64;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = magnitude
        * match raw / magnitude {
            x if x < 1.5 => 1.0,
            x if x < 3.0 => 2.0,
            x if x < 7.0 => 5.0,
            _ => 10.0,
        };
    let mut ticks = Vec::new();
    let mut k = (lo / step).ceil();
    while k * step <= hi + 1e-9 * span {
        ticks.push(k * step);
        k += 1.0;
    }
    (ticks, step)
}

/// A tick label with the decimals its step needs.
pub(crate) fn tick_label(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s.trim_start_matches(['-', '0', '.']).is_empty() {
        s[1..].to_string()
    } else {
        s
    }
}

fn step_plot(source: &str, result: &Critical, mu_star: f64, mu_enumerated: f64) -> String {
    let thresholds: Vec<f64> = result.thresholds.iter().map(|t| t.threshold).collect();
    let n = thresholds.len();
    let last = thresholds.iter().copied().fold(mu_enumerated, f64::max);
    let x0 = 0.9 * mu_star.min(thresholds[0]);
    // A little room right of the last step, so that the top level shows.
    let x1 = last + 0.04 * (last - x0).max(0.1 * last);
    let title = format!(
        "Maximal patterns of {source} (enumerated at mu = {}) realised at mu",
        sig4(mu_enumerated)
    );
    let mut out = header(&title);
    let x = |mu: f64| LEFT + (mu - x0) / (x1 - x0) * (RIGHT - LEFT);
    let y_top = n as f64 * 1.08;
    let y = |count: f64| BOTTOM - count / y_top * (BOTTOM - TOP);

    // Grid, ticks and labels.
    let (xticks, xstep) = nice_ticks(x0, x1, 8);
    // Whole numbers of patterns: the step is at least 1, since there are at most n ticks.
    let (yticks, ystep) = nice_ticks(0.0, n as f64, 8.min(n.max(1)));
    out.push_str("<g class=\"grid\" stroke=\"");
    out.push_str(GRID);
    out.push_str("\" stroke-width=\"1\">\n");
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
            px(RIGHT)
        );
    }
    out.push_str("</g>\n");
    let _ = writeln!(
        out,
        "<g class=\"axes\" stroke=\"{INK}\" stroke-width=\"1.2\" fill=\"none\">\n\
         <polyline points=\"{l},{t} {l},{b} {r},{b}\"/>",
        l = px(LEFT),
        t = px(TOP),
        b = px(BOTTOM),
        r = px(RIGHT)
    );
    for &t in &xticks {
        let _ = writeln!(
            out,
            "<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\"/>",
            px(x(t)),
            px(BOTTOM),
            px(BOTTOM + 5.0)
        );
    }
    for &t in &yticks {
        let _ = writeln!(
            out,
            "<line x1=\"{1}\" y1=\"{0}\" x2=\"{2}\" y2=\"{0}\"/>",
            px(y(t)),
            px(LEFT - 5.0),
            px(LEFT)
        );
    }
    out.push_str("</g>\n<g class=\"tick-labels\" fill=\"");
    out.push_str(INK);
    out.push_str("\">\n");
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
            tick_label(t, ystep.max(1.0))
        );
    }
    out.push_str("</g>\n");
    let _ = writeln!(
        out,
        "<text class=\"axis-label\" x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"13\" \
         fill=\"{INK}\">friction coefficient mu</text>",
        px((LEFT + RIGHT) / 2.0),
        px(BOTTOM + 42.0)
    );
    let _ = writeln!(
        out,
        "<text class=\"axis-label\" x=\"{0}\" y=\"{1}\" text-anchor=\"middle\" font-size=\"13\" \
         fill=\"{INK}\" transform=\"rotate(-90 {0} {1})\">maximal patterns realised (of {n})</text>",
        px(LEFT - 50.0),
        px((TOP + BOTTOM) / 2.0)
    );

    // The step function: 0 left of the first threshold, +1 at each.
    let mut path = format!("M{},{}", px(x(x0)), px(y(0.0)));
    for (k, &t) in thresholds.iter().enumerate() {
        let _ = write!(path, " H{} V{}", px(x(t)), px(y((k + 1) as f64)));
    }
    let _ = write!(path, " H{}", px(x(x1)));
    let _ = writeln!(
        out,
        "<path class=\"steps\" d=\"{path}\" fill=\"none\" stroke=\"{STEP_COLOUR}\" \
         stroke-width=\"2\"/>"
    );
    out.push_str("<g class=\"thresholds\" fill=\"");
    out.push_str(STEP_COLOUR);
    out.push_str("\">\n");
    for (k, (&t, p)) in thresholds.iter().zip(&result.thresholds).enumerate() {
        let pattern: String = p
            .pattern
            .iter()
            .map(|&c| crate::report::summary::pattern_code(c))
            .collect();
        let _ = writeln!(
            out,
            "<circle cx=\"{}\" cy=\"{}\" r=\"3\"><title>pattern {k}: {}, threshold {}</title></circle>",
            px(x(t)),
            px(y((k + 1) as f64)),
            escape(&pattern),
            sig4(t)
        );
    }
    out.push_str("</g>\n");

    // mu*: a dashed line and its label.
    let label = match (result.lower, result.upper) {
        (Some(lower), Some(upper)) => {
            let (mu, lo, up) = bracket_text(lower, upper);
            format!("mu* = {mu}  [{lo}, {up}]")
        }
        _ => format!("mu* = {}", sig4(mu_star)),
    };
    let xs = x(mu_star);
    let _ = writeln!(
        out,
        "<line class=\"mu-star\" x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" \
         stroke=\"{MU_STAR_COLOUR}\" stroke-width=\"1.5\" stroke-dasharray=\"6 4\"/>",
        px(xs),
        px(TOP - 6.0),
        px(BOTTOM)
    );
    let anchor_left = xs < (LEFT + RIGHT) / 2.0;
    let _ = writeln!(
        out,
        "<text class=\"mu-star-label\" x=\"{}\" y=\"{}\" text-anchor=\"{}\" font-size=\"13\" \
         fill=\"{MU_STAR_COLOUR}\">{}</text>",
        px(if anchor_left { xs + 6.0 } else { xs - 6.0 }),
        px(TOP + 8.0),
        if anchor_left { "start" } else { "end" },
        escape(&label)
    );
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use wedged::{ContactPattern, CriticalInfo, PatternThreshold};

    fn run(thresholds: &[f64]) -> Critical {
        Critical {
            status: CriticalStatus::Wedged,
            mu_critical: Some(thresholds[0]),
            lower: Some(thresholds[0] * (1.0 - 1e-7)),
            upper: Some(thresholds[0]),
            witness: None,
            thresholds: thresholds
                .iter()
                .map(|&t| PatternThreshold {
                    pattern: vec![ContactPattern::Contact, ContactPattern::Separated],
                    threshold: t,
                    lower: t * (1.0 - 1e-7),
                    witness: None,
                })
                .collect(),
            undecided: Vec::new(),
            certificate: None,
            shard: None,
            info: CriticalInfo {
                mu_enumerated: Some(3.2),
                tol_achieved: 1e-7,
                ..CriticalInfo::default()
            },
        }
    }

    #[test]
    fn the_plot_has_a_step_per_threshold_and_marks_mu_star() {
        let svg = sweep_svg("p.toml", &run(&[1.5, 1.5, 2.0, 3.1]));
        assert!(svg.starts_with("<svg "), "{svg}");
        assert!(svg.trim_end().ends_with("</svg>"), "{svg}");
        assert_eq!(svg.matches("<circle").count(), 4, "{svg}");
        assert_eq!(svg.matches(" V").count(), 4, "{svg}");
        assert!(svg.contains("mu* = 1.5  [1.4999998, 1.5]"), "{svg}");
        assert!(svg.contains("stroke-dasharray"), "{svg}");
        assert!(svg.contains("friction coefficient mu"), "{svg}");
        assert!(svg.contains("(of 4)"), "{svg}");
        assert!(svg.contains("enumerated at mu = 3.2"), "{svg}");
    }

    #[test]
    fn never_gives_a_page_that_says_so() {
        let mut result = run(&[1.0]);
        result.status = CriticalStatus::Never;
        result.mu_critical = None;
        result.thresholds.clear();
        let svg = sweep_svg("p.toml", &result);
        assert!(
            svg.contains("No friction coefficient wedges this body"),
            "{svg}"
        );
    }

    #[test]
    fn ticks_are_round() {
        let (ticks, step) = nice_ticks(1.35, 3.3, 8);
        assert_eq!(step, 0.2);
        assert_eq!(tick_label(ticks[0], step), "1.4");
        assert_eq!(tick_label(*ticks.last().unwrap(), step), "3.2");
        let (ticks, step) = nice_ticks(0.0, 4.0, 4);
        assert_eq!((ticks.len(), step), (5, 1.0));
    }
}
