//! `wedged study`: `mu*` over a grid of a problem file's parameters. This module holds what is
//! not the command's own running, so that it can be tested alone: the grid (`--vary`), a grid
//! point applied to the problem file's TOML, the CSV rows (written, and read back to resume),
//! the mesh size `h` of a model, and the extrapolation of a mesh-convergence series.
//!
//! A parameter is a key of the problem file, dotted (`material.poisson`,
//! `mesh.generate.ny`), which must already be in the file (so that a misspelt key is an error,
//! not a silent no-op), or one of two derived parameters of a generated body:
//!
//! - `half_angle`: the notch half-angle in degrees, from the vertical; it sets `top_width =
//!   bottom_width + 2 height tan(half_angle)` (`plug2d`, `vgroove3d`, `frustum3d`);
//! - `refine`: a whole factor multiplying every division count of `[mesh.generate]` (`nx`,
//!   `ny`, `nz`, `n`), for mesh-convergence studies; for a Gmsh script (`gmsh = "body.geo"`),
//!   any factor from 1 up dividing its `size_factor` (every mesh size of the script, Gmsh's
//!   `Mesh.MeshSizeFactor`; 1 where the file gives none).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use toml::{Table, Value};
use wedged::fe::Mesh;

/// One `--vary` option: a key and its values, in the order given.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// The dotted key, or `half_angle` or `refine`.
    pub key: String,
    /// The values, as written (integers stay integers in the file when the key is one).
    pub values: Vec<f64>,
}

/// The derived parameters (module docs).
pub const HALF_ANGLE: &str = "half_angle";
/// The refinement factor (module docs).
pub const REFINE: &str = "refine";
/// The division counts `refine` multiplies.
const DIVISIONS: [&str; 4] = ["nx", "ny", "nz", "n"];
/// A Gmsh script's factor of every mesh size (`[mesh] size_factor`).
const SIZE_FACTOR: &str = "size_factor";

/// Whether varying `key` changes the mesh size: `refine`, a division count of
/// `[mesh.generate]` or a Gmsh script's `mesh.size_factor`.
pub fn refines(key: &str) -> bool {
    key == REFINE
        || key == "mesh.size_factor"
        || key
            .strip_prefix("mesh.generate.")
            .is_some_and(|d| DIVISIONS.contains(&d))
}

/// The most points a grid may have (a typo such as `0:1:10000` should not start a week's run).
pub const MAX_POINTS: usize = 10_000;

/// Parses `KEY=V1,V2,...` or `KEY=A:B:N` (`N` values from `A` to `B`, both included).
pub fn parse_vary(spec: &str) -> Result<Parameter, String> {
    let (key, values) = spec
        .split_once('=')
        .ok_or_else(|| format!("--vary {spec:?}: expected KEY=V1,V2,... or KEY=FROM:TO:COUNT"))?;
    let key = key.trim();
    if key.is_empty()
        || !key
            .split('.')
            .all(|part| !part.is_empty() && part.chars().all(|c| c.is_alphanumeric() || c == '_'))
    {
        return Err(format!(
            "--vary {spec:?}: {key:?} is not a key (dotted words, such as material.poisson)"
        ));
    }
    let number = |text: &str| -> Result<f64, String> {
        match text.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!(
                "--vary {key}: {:?} is not a finite number",
                text.trim()
            )),
        }
    };
    let values = if values.contains(':') {
        let parts: Vec<&str> = values.split(':').collect();
        if parts.len() != 3 {
            return Err(format!(
                "--vary {key}: a range is FROM:TO:COUNT, got {values:?}"
            ));
        }
        let (from, to) = (number(parts[0])?, number(parts[1])?);
        let count: usize = parts[2]
            .trim()
            .parse()
            .ok()
            .filter(|&c| c >= 1)
            .ok_or_else(|| {
                format!(
                    "--vary {key}: the count {:?} is not a positive whole number",
                    parts[2]
                )
            })?;
        if count > MAX_POINTS {
            return Err(format!(
                "--vary {key}: {count} values; at most {MAX_POINTS}"
            ));
        }
        if count == 1 {
            if from != to {
                return Err(format!(
                    "--vary {key}: one value from {from} to {to}; give COUNT >= 2 or one value"
                ));
            }
            vec![from]
        } else {
            (0..count)
                .map(|k| {
                    let t = k as f64 / (count - 1) as f64;
                    // The ends exactly as written.
                    if k == count - 1 {
                        to
                    } else {
                        from + t * (to - from)
                    }
                })
                .collect()
        }
    } else {
        values
            .split(',')
            .map(number)
            .collect::<Result<Vec<_>, _>>()?
    };
    for (k, v) in values.iter().enumerate() {
        if values[..k].contains(v) {
            return Err(format!("--vary {key}: the value {v} is given twice"));
        }
    }
    Ok(Parameter {
        key: key.to_string(),
        values,
    })
}

/// The grid: every combination of the parameters' values, the first parameter varying
/// slowest. Checks that no key is given twice and that the grid is not absurdly large.
pub fn points(parameters: &[Parameter]) -> Result<Vec<Vec<f64>>, String> {
    for (k, p) in parameters.iter().enumerate() {
        if parameters[..k].iter().any(|q| q.key == p.key) {
            return Err(format!("--vary {}: the key is given twice", p.key));
        }
    }
    let total = parameters
        .iter()
        .try_fold(1usize, |n, p| n.checked_mul(p.values.len()))
        .filter(|&n| n <= MAX_POINTS)
        .ok_or_else(|| format!("the grid has more than {MAX_POINTS} points"))?;
    let mut out = Vec::with_capacity(total);
    for mut index in 0..total {
        let mut point = vec![0.0; parameters.len()];
        for (j, p) in parameters.iter().enumerate().rev() {
            point[j] = p.values[index % p.values.len()];
            index /= p.values.len();
        }
        out.push(point);
    }
    Ok(out)
}

/// A value as the CSV and the messages write it: the shortest text that reads back as the same
/// `f64` (`0.3`, `16`).
pub fn value_text(v: f64) -> String {
    format!("{v}")
}

/// The problem file's table with one grid point applied. Errors name the key and the reason
/// (the key is not in the file, a whole number was expected, a derived parameter does not
/// apply to this body).
pub fn apply(base: &Table, parameters: &[Parameter], point: &[f64]) -> Result<Table, String> {
    let mut table = base.clone();
    for (p, &v) in parameters.iter().zip(point) {
        match p.key.as_str() {
            HALF_ANGLE => set_half_angle(&mut table, v)?,
            REFINE => refine(&mut table, v)?,
            key => set_key(&mut table, key, v)?,
        }
    }
    Ok(table)
}

fn generate_table<'t>(table: &'t mut Table, what: &str) -> Result<&'t mut Table, String> {
    table
        .get_mut("mesh")
        .and_then(Value::as_table_mut)
        .and_then(|m| m.get_mut("generate"))
        .and_then(Value::as_table_mut)
        .ok_or_else(|| {
            format!(
                "--vary {what}: applies to a generated body ([mesh.generate]); this file has none"
            )
        })
}

fn set_half_angle(table: &mut Table, degrees: f64) -> Result<(), String> {
    if !(degrees > -90.0 && degrees < 90.0) {
        return Err(format!(
            "--vary {HALF_ANGLE} = {degrees}: a half-angle in degrees must lie strictly between -90 and 90"
        ));
    }
    let generate = generate_table(table, HALF_ANGLE)?;
    let number = |g: &Table, key: &str| -> Result<f64, String> {
        g.get(key)
            .and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
            .ok_or_else(|| format!("--vary {HALF_ANGLE}: [mesh.generate] has no number {key}"))
    };
    let bottom = number(generate, "bottom_width")?;
    let height = number(generate, "height")?;
    let top = bottom + 2.0 * height * degrees.to_radians().tan();
    if top <= 0.0 {
        return Err(format!(
            "--vary {HALF_ANGLE} = {degrees}: the top width would be {top} (not positive)"
        ));
    }
    generate.insert("top_width".to_string(), Value::Float(top));
    Ok(())
}

/// Whether a problem file's mesh is a Gmsh script (`gmsh = "body.geo"`).
fn is_script(table: &Table) -> bool {
    table
        .get("mesh")
        .and_then(|m| m.get("gmsh"))
        .and_then(Value::as_str)
        .and_then(|p| p.rsplit_once('.'))
        .is_some_and(|(_, e)| e.eq_ignore_ascii_case("geo"))
}

/// The `[mesh]` table of a problem file whose mesh is a Gmsh script.
fn script_table(table: &mut Table) -> Option<&mut Table> {
    if !is_script(table) {
        return None;
    }
    table.get_mut("mesh")?.as_table_mut()
}

/// A Gmsh script's mesh sizes times `factor` (its `size_factor`, 1 where it has none); `None`
/// where the file's mesh is not a script or its `size_factor` is not a number.
fn scale_script(table: &mut Table, factor: f64) -> Option<()> {
    let mesh = script_table(table)?;
    let now = match mesh.get(SIZE_FACTOR) {
        None => 1.0,
        Some(v) => v.as_float().or_else(|| v.as_integer().map(|i| i as f64))?,
    };
    mesh.insert(SIZE_FACTOR.to_string(), Value::Float(now * factor));
    Some(())
}

fn refine(table: &mut Table, factor: f64) -> Result<(), String> {
    if script_table(table).is_some() {
        if !(1.0..=1e6).contains(&factor) {
            return Err(format!(
                "--vary {REFINE} = {factor}: the refinement factor is a number >= 1"
            ));
        }
        return scale_script(table, 1.0 / factor)
            .ok_or_else(|| format!("--vary {REFINE}: [mesh] {SIZE_FACTOR} is not a number"));
    }
    if factor < 1.0 || factor.fract() != 0.0 || factor > 1e6 {
        return Err(format!(
            "--vary {REFINE} = {factor}: the refinement factor is a whole number >= 1"
        ));
    }
    let generate = generate_table(table, REFINE)?;
    let mut any = false;
    for key in DIVISIONS {
        if let Some(Value::Integer(n)) = generate.get(key) {
            let refined = n.saturating_mul(factor as i64);
            generate.insert(key.to_string(), Value::Integer(refined));
            any = true;
        }
    }
    if any {
        Ok(())
    } else {
        Err(format!(
            "--vary {REFINE}: [mesh.generate] has no division counts"
        ))
    }
}

/// The dotted names of the numbers a problem file's table sets (not inside arrays), in order.
fn number_keys(table: &Table, prefix: &str, out: &mut Vec<String>) {
    for (name, value) in table {
        let dotted = format!("{prefix}{name}");
        match value {
            Value::Integer(_) | Value::Float(_) => out.push(dotted),
            Value::Table(inner) => number_keys(inner, &format!("{dotted}."), out),
            _ => {}
        }
    }
}

/// The end of the message for a key the file does not set: the keys it sets that end the same
/// way (`poisson`: `material.poisson`), or else every number it sets.
fn key_hint(table: &Table, key: &str) -> String {
    let mut known = Vec::new();
    number_keys(table, "", &mut known);
    let last = key.rsplit('.').next().unwrap_or(key);
    let like: Vec<&str> = known
        .iter()
        .map(String::as_str)
        .filter(|k| k.rsplit('.').next() == Some(last))
        .collect();
    if !like.is_empty() {
        format!("did you mean {}?", like.join(" or "))
    } else {
        format!("the numbers it sets: {}", known.join(", "))
    }
}

fn set_key(table: &mut Table, key: &str, v: f64) -> Result<(), String> {
    let hint = key_hint(table, key);
    let mut parts = key.split('.').peekable();
    let mut here = table;
    while let Some(part) = parts.next() {
        if parts.peek().is_none() {
            let slot = here.get_mut(part).ok_or_else(|| {
                format!(
                    "--vary {key}: the problem file has no such key (a study changes keys the \
                     file sets, dotted; {hint})"
                )
            })?;
            *slot = match slot {
                Value::Integer(_) if v.fract() == 0.0 && v.abs() < 9e15 => Value::Integer(v as i64),
                Value::Integer(_) => {
                    return Err(format!(
                    "--vary {key} = {v}: the file's value is a whole number, and so must this be"
                ))
                }
                Value::Float(_) => Value::Float(v),
                other => {
                    return Err(format!(
                        "--vary {key}: the file's value is {}, not a number",
                        other.type_str()
                    ))
                }
            };
            return Ok(());
        }
        here = here
            .get_mut(part)
            .and_then(Value::as_table_mut)
            .ok_or_else(|| {
                format!("--vary {key}: the problem file has no table {part:?} there ({hint})")
            })?;
    }
    unreachable!("a key has at least one part")
}

/// The mesh size `h`: the largest distance between two nodes of one element.
pub fn mesh_size(mesh: &Mesh) -> f64 {
    let coords = mesh.coords();
    let mut h: f64 = 0.0;
    for element in mesh.elements() {
        for (a, &i) in element.nodes.iter().enumerate() {
            for &j in &element.nodes[a + 1..] {
                let d: f64 = (0..3)
                    .map(|k| (coords[i][k] - coords[j][k]).powi(2))
                    .sum::<f64>()
                    .sqrt();
                h = h.max(d);
            }
        }
    }
    h
}

/// One computed grid point, a line of `study.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The parameters' values as [`value_text`] writes them (the key that finds a point again).
    pub values: Vec<String>,
    /// Contact nodes.
    pub m: usize,
    /// Mesh size ([`mesh_size`]); `None` for a `[stiffness]` problem.
    pub h: Option<f64>,
    /// `wedged`, `never` or `incomplete`.
    pub status: String,
    /// `mu*` (the bracket's upper end), when wedged.
    pub mu_star: Option<f64>,
    /// The certified lower end.
    pub lower: Option<f64>,
    /// The upper end (a checked wedged configuration).
    pub upper: Option<f64>,
    /// Whether the point's run completed.
    pub complete: bool,
    /// The run's seconds (condensation included).
    pub seconds: f64,
}

/// The columns after the parameters.
const RESULT_COLUMNS: [&str; 8] = [
    "m", "h", "status", "mu_star", "lower", "upper", "complete", "seconds",
];

/// The CSV's header line for these parameters.
pub fn header(parameters: &[Parameter]) -> String {
    let mut columns: Vec<&str> = parameters.iter().map(|p| p.key.as_str()).collect();
    columns.extend(RESULT_COLUMNS);
    columns.join(",")
}

fn opt(v: Option<f64>) -> String {
    v.map(|x| format!("{x}")).unwrap_or_default()
}

/// The whole CSV: the header, then the rows.
pub fn csv(parameters: &[Parameter], rows: &[Row]) -> String {
    let mut out = header(parameters);
    out.push('\n');
    for row in rows {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{:.3}",
            row.values.join(","),
            row.m,
            opt(row.h),
            row.status,
            opt(row.mu_star),
            opt(row.lower),
            opt(row.upper),
            row.complete,
            row.seconds
        );
    }
    out
}

/// Reads a `study.csv` back: its rows, by their parameter values. The header must be this
/// study's (same keys in the same order), so that a study never resumes from another's file.
pub fn read_csv(
    text: &str,
    parameters: &[Parameter],
) -> Result<BTreeMap<Vec<String>, Row>, String> {
    let mut lines = text.lines();
    let expected = header(parameters);
    match lines.next() {
        Some(h) if h.trim_end() == expected => {}
        Some(h) => {
            return Err(format!(
                "its header is {h:?}, and this study's would be {expected:?}; use another \
                 output directory or remove the file"
            ))
        }
        None => return Ok(BTreeMap::new()),
    }
    let k = parameters.len();
    let mut rows = BTreeMap::new();
    for (n, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let bad = |what: &str| format!("line {}: {what}", n + 2);
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != k + RESULT_COLUMNS.len() {
            return Err(bad(&format!(
                "{} fields, expected {}",
                fields.len(),
                k + RESULT_COLUMNS.len()
            )));
        }
        let number = |s: &str, what: &str| -> Result<Option<f64>, String> {
            if s.is_empty() {
                Ok(None)
            } else {
                s.parse::<f64>()
                    .map(Some)
                    .map_err(|_| bad(&format!("{what} {s:?} is not a number")))
            }
        };
        let values: Vec<String> = fields[..k].iter().map(|s| s.to_string()).collect();
        let r = &fields[k..];
        let row = Row {
            values: values.clone(),
            m: r[0].parse().map_err(|_| bad("m is not a whole number"))?,
            h: number(r[1], "h")?,
            status: r[2].to_string(),
            mu_star: number(r[3], "mu_star")?,
            lower: number(r[4], "lower")?,
            upper: number(r[5], "upper")?,
            complete: match r[6] {
                "true" => true,
                "false" => false,
                _ => return Err(bad("complete is neither true nor false")),
            },
            seconds: number(r[7], "seconds")?.unwrap_or(0.0),
        };
        rows.insert(values, row);
    }
    Ok(rows)
}

/// `mu*(h) = limit + c h^order` through the three finest points of a convergence series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extrapolation {
    /// The extrapolated value at `h = 0`.
    pub limit: f64,
    /// The observed order of convergence.
    pub order: f64,
    /// `c`.
    pub coefficient: f64,
}

/// The three finest distinct sizes of a series (`(h, mu*)`, any order), coarsest first; `None`
/// with fewer.
fn finest_three(series: &[(f64, f64)]) -> Option<[(f64, f64); 3]> {
    let mut points: Vec<(f64, f64)> = series
        .iter()
        .copied()
        .filter(|(h, f)| h.is_finite() && *h > 0.0 && f.is_finite())
        .collect();
    points.sort_by(|a, b| b.0.total_cmp(&a.0));
    points.dedup_by(|a, b| a.0 == b.0);
    let n = points.len();
    (n >= 3).then(|| [points[n - 3], points[n - 2], points[n - 1]])
}

/// Richardson extrapolation through the three finest points (`(h, mu*)`, any order): the
/// order `p` solves `(f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p)` for `h1 > h2 > h3`
/// (bisection on `p` in `[MIN_ORDER, 10]`, where the right side grows with `p`). `None` when
/// there are fewer than three distinct sizes, or the values do not converge monotonically (the
/// differences change sign, or the observed order leaves that range).
/// The least observed order [`extrapolate`] accepts. The limit lies `d / (r^p - 1)` beyond the
/// finest value, for a last step `d` and a refinement ratio `r`; as `p` falls towards 0 that
/// grows without bound and a power law turns into `ln(1/h)` growth ([`logarithmic`]), which
/// three points cannot tell apart from it. (The plug refined 12, 14 and 16 times, `mu*` from
/// 1.8187 to 1.8230, fits `p` = 0.057, whose limit 2.087 lies 60 steps beyond the data, and
/// `ln(1/h)` growth within 1%; with a floor of 0.05 `study` printed that limit.)
pub const MIN_ORDER: f64 = 0.5;

pub fn extrapolate(series: &[(f64, f64)]) -> Option<Extrapolation> {
    let [(h1, f1), (h2, f2), (h3, f3)] = finest_three(series)?;
    let (d12, d23) = (f1 - f2, f2 - f3);
    if d23 == 0.0 {
        // Already converged to the last digit: the limit is the finest value.
        return (d12 == 0.0).then_some(Extrapolation {
            limit: f3,
            order: f64::NAN,
            coefficient: 0.0,
        });
    }
    let target = d12 / d23;
    if target <= 0.0 {
        return None;
    }
    let ratio = |p: f64| (h1.powf(p) - h2.powf(p)) / (h2.powf(p) - h3.powf(p));
    let (mut lo, mut hi) = (MIN_ORDER, 10.0_f64);
    if !(ratio(lo) <= target && target <= ratio(hi)) {
        return None;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if ratio(mid) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let order = 0.5 * (lo + hi);
    let coefficient = d23 / (h2.powf(order) - h3.powf(order));
    Some(Extrapolation {
        limit: f3 - coefficient * h3.powf(order),
        order,
        coefficient,
    })
}

/// `mu*(h) = a + slope ln(1/h)` through the three finest points: growth with no finite limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogGrowth {
    /// The growth of `mu*` per unit of `ln(1/h)`, from the two finest steps.
    pub slope: f64,
    /// How far the two steps' slopes differ, relative to the larger.
    pub spread: f64,
}

/// When [`extrapolate`] finds no power law: whether the three finest points grow like
/// `ln(1/h)` (the two steps' slopes per unit of `ln(1/h)` of one sign and within 15% of each
/// other), the signature of a value that follows a singularity the mesh resolves ever
/// better and has no finite limit.
pub fn logarithmic(series: &[(f64, f64)]) -> Option<LogGrowth> {
    let [(h1, f1), (h2, f2), (h3, f3)] = finest_three(series)?;
    let s12 = (f2 - f1) / (h1 / h2).ln();
    let s23 = (f3 - f2) / (h2 / h3).ln();
    let largest = s12.abs().max(s23.abs());
    let spread = (s12 - s23).abs() / largest;
    (s12 * s23 > 0.0 && spread <= 0.15).then_some(LogGrowth { slope: s23, spread })
}

#[cfg(test)]
mod tests;
