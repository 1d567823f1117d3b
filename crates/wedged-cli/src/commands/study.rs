//! `wedged study`: `mu*` at every point of a grid of the problem file's parameters, written as
//! `study.csv` (after each point, so that a stopped study loses at most the point it was on),
//! `study.svg` and, with `--vtk`, a VTU file of each point's witness and their collection
//! `study.pvd`. A rerun with the same grid and output directory takes the complete points from
//! `study.csv` and computes the others (resuming). The grid, the CSV and the extrapolation are
//! `wedged_cli::study`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use wedged::{CriticalMethod, CriticalStatus, Stop};

use super::*;
use crate::draw::export::collection;
use crate::draw::export::write_witness_vtu;
use crate::draw::study_svg::{study_svg, Point, Series};
use crate::report::critical::mu_text;
use crate::report::files::write_atomic;
use crate::report::sig4;
use crate::report::upper_text;
use wedged_cli::input::problem_file;
use wedged_cli::input::start::Earlier;
use wedged_cli::jobs::{plan_critical, run_critical_library, CriticalOptions};
use wedged_cli::study::{self, Parameter, Row};

/// The CSV, plot and collection names in the output directory.
const CSV: &str = "study.csv";
const PLOT: &str = "study.svg";
const COLLECTION: &str = "study.pvd";

pub(crate) fn run_study(args: StudyArgs) -> Result<(), Failure> {
    let input = |m: String| Failure::Input(m);
    let parameters = args.vary;
    let grid = study::points(&parameters).map_err(input)?;
    let settings = plan_critical(&CriticalOptions {
        method: Some(args.method.map_or(CriticalMethod::Bnb, |m| m.0)),
        tol: args.common.tol,
        time_limit: args.common.time_limit,
        certify: args.certify,
        shard: None,
    })?;
    let x_key = x_axis(&parameters, args.x.as_deref()).map_err(input)?;
    let source = args.problem.display().to_string();
    let text = std::fs::read_to_string(&args.problem)
        .map_err(|e| Failure::Input(format!("{source}: cannot read the problem file: {e}")))?;
    let base: toml::Table = match text.parse() {
        Ok(table) => table,
        // The problem file's own reader words the error (with its line).
        Err(_) => {
            return Err(
                match problem_file::parse_str_for_critical(&text, &args.problem) {
                    Err(e) => Failure::Input(e.to_string()),
                    Ok(_) => Failure::Input(format!("{source}: not a TOML table")),
                },
            )
        }
    };
    let dir = &args.out;
    crate::report::files::create_output_dir(dir, "--out").map_err(input)?;
    let csv_path = dir.join(CSV);
    let mut earlier: BTreeMap<Vec<String>, Row> = match std::fs::read_to_string(&csv_path) {
        Ok(text) => study::read_csv(&text, &parameters)
            .map_err(|e| input(format!("{}: {e}", csv_path.display())))?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => BTreeMap::new(),
        Err(e) => return Err(input(format!("{}: cannot read: {e}", csv_path.display()))),
    };

    let total = grid.len();
    let width = total.saturating_sub(1).to_string().len();
    let mut rows: Vec<Option<Row>> = vec![None; total];
    let mut vtus: Vec<PathBuf> = Vec::new();
    // The answers computed in this run, by grid position: a finer point's start ([`chained`]).
    let mut answers: Vec<Option<Earlier>> = vec![None; total];
    // Only where the search uses a start: `bnb`, not certified (`critical --start`).
    let chain = !args.no_chain
        && !settings.certify
        && settings.method == CriticalMethod::Bnb
        && parameters.iter().any(|p| study::refines(&p.key));
    let mut interrupted = false;
    let mut reused = 0;
    write_stdout(&format!(
        "study of {source}: {total} {} ({}), critical friction by {}, results in {}\n",
        if total == 1 { "point" } else { "points" },
        parameters
            .iter()
            .map(|p| format!("{} x {}", p.values.len(), p.key))
            .collect::<Vec<_>>()
            .join(", "),
        settings.method.name(),
        csv_path.display()
    ))?;
    for (k, point) in grid.iter().enumerate() {
        let values: Vec<String> = point.iter().map(|&v| study::value_text(v)).collect();
        let label = point_label(&parameters, &values);
        let vtu = dir.join(format!("point-{k:0width$}.vtu"));
        if let Some(row) = earlier.remove(&values).filter(|r| r.complete) {
            write_stdout(&format!(
                "  [{:>w$}/{total}] {label}: {} (from {CSV})\n",
                k + 1,
                row_text(&row),
                w = total.to_string().len()
            ))?;
            if args.vtk && vtu.exists() {
                vtus.push(vtu);
            }
            rows[k] = Some(row);
            reused += 1;
            continue;
        }
        let start = Instant::now();
        let table = study::apply(&base, &parameters, point)
            .map_err(|e| input(format!("{source}, point {label}: {e}")))?;
        let edited = toml::to_string(&table).map_err(|e| {
            Failure::Internal(format!(
                "{source}, point {label}: cannot write the TOML: {e}"
            ))
        })?;
        let (loaded, _) = problem_file::parse_str_for_critical(&edited, &args.problem)
            .map_err(|e| input(format!("point {label}: {e}")))?;
        let point_source = format!("{source} [{label}]");
        let mut settings = settings.clone();
        // --no-chain: neither a coarser point nor the condensed problem starts a point.
        settings.condense = !args.no_chain;
        if chain {
            settings.start = chained(&parameters, &grid, &answers, k).and_then(|earlier| {
                let model = loaded.model.as_ref();
                let start = earlier.onto(loaded.problem.nodes(), model, &point_source);
                start.ok().filter(|s| s.contains(&true))
            });
        }
        // A point with no coarser point before it starts, as `critical` does on a large
        // problem, from its problem condensed onto about half its nodes (the library's).
        let chained_from = settings.start.is_some();
        let result = run_critical_library(
            &loaded.problem,
            &settings,
            &point_source,
            &INTERRUPTED,
            Show::Terminal,
        )?;
        if let Some(failure) =
            wedged_cli::jobs::critical_certification_failure(&point_source, &result)
        {
            return Err(failure);
        }
        if let Some(witness) = &result.witness {
            answers[k] = Some(Earlier::of(&witness.pattern, loaded.model.as_ref()));
        }
        let complete = !matches!(result.status, CriticalStatus::Incomplete(_));
        let row = Row {
            values: values.clone(),
            m: loaded.problem.nodes(),
            h: loaded.model.as_ref().map(|m| study::mesh_size(m.mesh())),
            status: result.status.name().to_string(),
            mu_star: result.mu_critical.filter(|_| complete),
            lower: result.lower,
            upper: result.upper,
            complete,
            seconds: start.elapsed().as_secs_f64(),
        };
        if let (true, Some(model), Some(witness)) = (args.vtk, &loaded.model, &result.witness) {
            let title = format!(
                "{source}, {label}: {}",
                match (complete, result.upper) {
                    (true, Some(mu)) => format!("mu* = {}, witness at mu*", sig4(mu)),
                    (_, Some(mu)) => format!("incomplete, wedged at mu = {}", sig4(mu)),
                    _ => "no witness".to_string(),
                }
            );
            write_witness_vtu(model, &witness.u, &witness.status, title, &vtu)?;
            vtus.push(vtu);
        }
        write_stdout(&format!(
            "  [{:>w$}/{total}] {label}: {}{}\n",
            k + 1,
            row_text(&row),
            match (chained_from, result.info.condensed_nodes) {
                (true, _) => ", started from the coarser answer".to_string(),
                (false, 0) => String::new(),
                (false, n) => format!(", started from its problem condensed onto {n} nodes"),
            },
            w = total.to_string().len()
        ))?;
        rows[k] = Some(row);
        // After every point: a stopped study keeps what it computed.
        write_csv(&csv_path, &parameters, &rows, &earlier)?;
        if result.status == CriticalStatus::Incomplete(Stop::Interrupted) {
            interrupted = true;
            break;
        }
    }
    write_csv(&csv_path, &parameters, &rows, &earlier)?;

    // The plot, from every computed point of this grid.
    let done: Vec<(&Vec<f64>, &Row)> = grid
        .iter()
        .zip(&rows)
        .filter_map(|(p, r)| r.as_ref().map(|r| (p, r)))
        .collect();
    let x_index = parameters.iter().position(|p| p.key == x_key);
    // Against h, the keys that refine the mesh are the x axis, not a line's label: `refine`
    // and the division counts, and a Gmsh script's parameter varied first (its mesh size, as
    // `--x h` says: which of a script's numbers sets its mesh size only the user knows).
    let on_x = |j: usize| {
        let key = &parameters[j].key;
        Some(j) == x_index
            || (x_key == "h"
                && (study::refines(key) || (j == 0 && key.starts_with("mesh.parameters."))))
    };
    let mut series: Vec<Series> = Vec::new();
    for (point, row) in &done {
        let label: Vec<String> = parameters
            .iter()
            .zip(&row.values)
            .enumerate()
            .filter(|(j, _)| !on_x(*j))
            .map(|(_, (p, v))| format!("{} {v}", p.key))
            .collect();
        let label = label.join(", ");
        let x = match x_index {
            Some(j) => Some(point[j]),
            None => row.h,
        };
        let Some(x) = x else { continue };
        let p = Point {
            x,
            mu: if row.complete { row.mu_star } else { row.upper },
            complete: row.complete,
        };
        match series.iter_mut().find(|s| s.label == label) {
            Some(s) => s.points.push(p),
            None => series.push(Series {
                label,
                points: vec![p],
            }),
        }
    }
    let mut summary = String::new();
    let mut limit = None;
    let mut note: Option<String> = None;
    if x_key == "h" {
        for s in &series {
            let converged: Vec<(f64, f64)> = s
                .points
                .iter()
                .filter(|p| p.complete)
                .filter_map(|p| p.mu.map(|mu| (p.x, mu)))
                .collect();
            let name = if s.label.is_empty() {
                String::new()
            } else {
                format!(" ({})", s.label)
            };
            match study::extrapolate(&converged) {
                Some(e) => {
                    let order = if e.order.is_finite() {
                        format!(", observed order {}", sig4(e.order))
                    } else {
                        String::new()
                    };
                    summary.push_str(&format!(
                        "extrapolated to h = 0{name}: mu* = {:.6} (Richardson through the three \
                         finest meshes{order})\n",
                        e.limit
                    ));
                    if series.len() == 1 {
                        limit = Some(e);
                    }
                }
                None if converged.len() >= 3 => match study::logarithmic(&converged) {
                    Some(g) => {
                        let text = format!(
                            "mu* grows like {} ln(1/h) through the three finest meshes: no \
                             finite limit in sight",
                            sig4(g.slope)
                        );
                        summary.push_str(&format!(
                            "no extrapolation{name}: {text} (the two steps' slopes differ by \
                             {:.0}%; a power law does not fit)\n",
                            100.0 * g.spread
                        ));
                        if series.len() == 1 {
                            note = Some(text);
                        }
                    }
                    None => summary.push_str(&format!(
                        "no extrapolation{name}: the three finest meshes are not in the \
                         asymptotic range (their differences do not shrink like a power of h)\n"
                    )),
                },
                None => {}
            }
        }
    }
    let plot_path = dir.join(PLOT);
    let title = format!(
        "Critical friction coefficient of {} over {}",
        Path::new(&source)
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or(&source),
        parameters
            .iter()
            .map(|p| p.key.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let x_label = if x_key == "h" {
        "mesh size h (largest element diameter)".to_string()
    } else {
        x_key.clone()
    };
    write_atomic(
        &plot_path,
        study_svg(&title, &x_label, &series, limit, note.as_deref()).as_bytes(),
        "SVG file",
    )
    .map_err(|e| input(e.to_string()))?;
    let mut written = vec![
        csv_path.display().to_string(),
        plot_path.display().to_string(),
    ];
    if args.vtk && !vtus.is_empty() {
        let path = dir.join(COLLECTION);
        let steps: Vec<(f64, &Path)> = vtus
            .iter()
            .enumerate()
            .map(|(step, p)| (step as f64, p.as_path()))
            .collect();
        write_atomic(&path, collection(&steps).as_bytes(), "ParaView collection")
            .map_err(|e| input(e.to_string()))?;
        written.push(format!(
            "{} ({} point-N.vtu, point N at time step N)",
            path.display(),
            vtus.len()
        ));
    }
    let computed = done.len() - reused;
    let incomplete = done.iter().filter(|(_, r)| !r.complete).count();
    summary.push_str(&format!(
        "{} of {total} points done ({computed} computed now, {reused} from {CSV}); written: {}\n",
        done.len(),
        written.join(", ")
    ));
    write_stdout(&summary)?;
    if interrupted || incomplete > 0 || done.len() < total {
        return Err(Failure::Incomplete(format!(
            "{source}: the study is incomplete ({} of {total} points complete{}); run the same \
             command again to compute the rest (complete points are kept in {})",
            done.len() - incomplete,
            if interrupted { ", interrupted" } else { "" },
            csv_path.display()
        )));
    }
    Ok(())
}

/// The x axis: `--x` (a varied key or `h`); by default `h` when the first varied parameter
/// refines the mesh (`refine` or a division count of `[mesh.generate]`), else the first.
fn x_axis(parameters: &[Parameter], asked: Option<&str>) -> Result<String, String> {
    match asked {
        Some("h") => Ok("h".to_string()),
        Some(key) if parameters.iter().any(|p| p.key == key) => Ok(key.to_string()),
        Some(key) => Err(format!(
            "--x {key}: expected h or one of the varied keys ({})",
            parameters
                .iter()
                .map(|p| p.key.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )),
        None => {
            let first = parameters.first().map(|p| p.key.as_str()).unwrap_or("h");
            Ok(if study::refines(first) { "h" } else { first }.to_string())
        }
    }
}

/// The answer that grid point `k` starts from: that of the last point before it computed in
/// this run that differs from it in refining keys only ([`study::refines`]: the same body on
/// another mesh), `None` when there is none. (On the plug's mesh-convergence study the finer
/// meshes then skip the search's dive: `BENCHMARKS.md`.)
fn chained<'a>(
    parameters: &[Parameter],
    grid: &[Vec<f64>],
    answers: &'a [Option<Earlier>],
    k: usize,
) -> Option<&'a Earlier> {
    let same_body = |j: usize| {
        parameters
            .iter()
            .enumerate()
            .all(|(p, parameter)| study::refines(&parameter.key) || grid[j][p] == grid[k][p])
    };
    (0..k)
        .rev()
        .filter(|&j| same_body(j))
        .find_map(|j| answers[j].as_ref())
}

fn point_label(parameters: &[Parameter], values: &[String]) -> String {
    parameters
        .iter()
        .zip(values)
        .map(|(p, v)| format!("{} = {v}", p.key))
        .collect::<Vec<_>>()
        .join(", ")
}

fn row_text(row: &Row) -> String {
    let h = row
        .h
        .map(|h| format!(", h = {}", sig4(h)))
        .unwrap_or_default();
    let answer = match (row.status.as_str(), row.mu_star, row.upper) {
        ("never", _, _) => "never wedges".to_string(),
        // As many digits as the bracket certifies (`critical`'s answer line).
        (_, Some(mu), _) => format!("mu* = {}", mu_text(mu, row.lower)),
        (_, None, Some(upper)) => format!("incomplete, mu* <= {}", upper_text(upper)),
        _ => "incomplete, nothing found".to_string(),
    };
    format!("m = {}{h}: {answer} ({:.2} s)", row.m, row.seconds)
}

/// Writes `study.csv`: this grid's rows in grid order, then the earlier file's rows of points
/// outside this grid (kept, not lost).
fn write_csv(
    path: &Path,
    parameters: &[Parameter],
    rows: &[Option<Row>],
    earlier: &BTreeMap<Vec<String>, Row>,
) -> Result<(), Failure> {
    let all: Vec<Row> = rows
        .iter()
        .flatten()
        .cloned()
        .chain(earlier.values().cloned())
        .collect();
    write_atomic(path, study::csv(parameters, &all).as_bytes(), "CSV file")
        .map_err(|e| Failure::Input(e.to_string()))
}
