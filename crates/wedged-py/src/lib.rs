//! `wedged._wedged`: the extension module behind the Python package `wedged` (issue 23).
//!
//! Thin by design: it turns NumPy arrays into the library's matrices, runs the same jobs as
//! the command (`wedged_cli::jobs`: options checked, the run, errors sorted into bad input and
//! internal failures) and hands back the command's report: for an enumeration its parts as
//! arrays taken from the report the JSON is written from (`EnumerationRun`, the JSON itself
//! on demand), for `critical` its JSON document (one witness: small). So the library, the
//! command and Python give the same answer, number for number.
//!
//! Every run leaves the GIL to a worker thread and polls Python's signals every
//! `POLL`: Ctrl-C sets the run's cancel flag, waits for it to stop, and raises
//! `KeyboardInterrupt`.

use std::collections::HashMap;
use std::panic::{self, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::{Duration, Instant};

use nalgebra::DMatrix;
use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};
use wedged::fe::{ElementKind, Model};
use wedged::Problem;
use wedged_cli::input::problem_file;
use wedged_cli::jobs::{
    self, CriticalMethodArg, CriticalOptions, EnumerateOptions, Enumerated, Failure, MethodArg,
    Show,
};
use wedged_cli::one_line;
use wedged_cli::report::answer::Choice;
use wedged_cli::report::files::JsonLines;
use wedged_cli::report::json::{Header, Report};
use wedged_cli::report::merge::Part;

create_exception!(
    _wedged,
    InputError,
    PyValueError,
    "Bad input: the same one-line message as the command's exit code 2."
);
create_exception!(
    _wedged,
    InternalError,
    PyRuntimeError,
    "A failed internal check (a bug in wedged): the command's exit code 1."
);

/// How often a run polls Python's signals (Ctrl-C).
const POLL: Duration = Duration::from_millis(50);

mod critical_run;
use critical_run::critical_json;

fn to_py(failure: Failure) -> PyErr {
    match failure {
        Failure::Input(m) => InputError::new_err(one_line(&m)),
        Failure::Internal(m) | Failure::Incomplete(m) => InternalError::new_err(one_line(&m)),
    }
}

/// Runs `work` on a worker thread without the GIL, polling Python's signals; on Ctrl-C the
/// run's cancel flag is set, the worker is waited for, and `KeyboardInterrupt` raised.
fn released<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> Result<T, Failure> + Send,
) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    // Set by the worker when it ends, panic or not.
    let finished = (Mutex::new(false), Condvar::new());
    std::thread::scope(|scope| {
        let (cancel, finished) = (&cancel, &finished);
        let worker = scope.spawn(move || {
            let out = panic::catch_unwind(AssertUnwindSafe(|| work(cancel)));
            if let Ok(mut done) = finished.0.lock() {
                *done = true;
            }
            finished.1.notify_all();
            out
        });
        loop {
            let done = py.detach(|| {
                let Ok(guard) = finished.0.lock() else {
                    return true;
                };
                finished
                    .1
                    .wait_timeout_while(guard, POLL, |done| !*done)
                    .map_or(true, |(done, _)| *done)
            });
            if done {
                break;
            }
            if let Err(interrupt) = py.check_signals() {
                cancel.store(true, Ordering::Relaxed);
                py.detach(|| {
                    let _ = worker.join();
                });
                return Err(interrupt);
            }
        }
        match worker.join() {
            Ok(Ok(result)) => result.map_err(to_py),
            _ => Err(InternalError::new_err(
                "internal failure (a bug in wedged, please report it): the run panicked",
            )),
        }
    })
}

/// The condensed stiffness of an array: square, `f64`, copied.
fn matrix(k: &PyReadonlyArray2<'_, f64>) -> PyResult<DMatrix<f64>> {
    let shape = k.shape();
    let (rows, cols) = (shape[0], shape[1]);
    if rows != cols {
        return Err(InputError::new_err(format!(
            "K: the stiffness must be square, got {rows} x {cols}"
        )));
    }
    let view = k.as_array();
    Ok(DMatrix::from_fn(rows, cols, |i, j| view[[i, j]]))
}

/// The problem of a matrix (`source` names it in messages), floating when `rigid_modes` are
/// given (`dim*m x k`, the free rigid motions at the contact nodes, `K R = 0`).
fn matrix_problem(
    k: &PyReadonlyArray2<'_, f64>,
    rigid_modes: Option<&PyReadonlyArray2<'_, f64>>,
    dim: usize,
    mu: f64,
) -> PyResult<Problem> {
    if dim != 2 && dim != 3 {
        return Err(InputError::new_err(format!(
            "dim must be 2 or 3, got {dim}"
        )));
    }
    let k = matrix(k)?;
    match rigid_modes {
        None => Problem::new(dim, k, mu).map_err(|e| match e {
            wedged::ProblemError::NotPositiveDefinite { .. } => InputError::new_err(format!(
                "K: {e} (a floating body: pass its rigid modes, rigid_modes=R, dim m x k in the \
                 same frames, K R = 0)"
            )),
            e => InputError::new_err(format!("K: {e}")),
        }),
        Some(r) => {
            let view = r.as_array();
            let (rows, cols) = (r.shape()[0], r.shape()[1]);
            let r = DMatrix::from_fn(rows, cols, |i, j| view[[i, j]]);
            Problem::floating(dim, k, r, mu)
                .map_err(|e| InputError::new_err(format!("K, rigid_modes: {e}")))
        }
    }
}

fn method_of(name: Option<&str>) -> PyResult<Option<MethodArg>> {
    name.map(|n| {
        MethodArg::named(n).ok_or_else(|| {
            InputError::new_err(format!(
                "method {n:?} is not a method of enumerate (pruned-dd, full-dd, faces, exact, \
                 search, bnb, pyramid, pattern-faces, pattern-search)"
            ))
        })
    })
    .transpose()
}

/// The `shard` argument (`"I/N"`), an `InputError` naming it where it does not parse.
fn shard_of(shard: Option<&str>) -> PyResult<Option<wedged::Shard>> {
    shard
        .map(wedged::Shard::parse)
        .transpose()
        .map_err(|e| InputError::new_err(format!("shard: {e}")))
}

fn critical_method_of(name: Option<&str>) -> PyResult<Option<wedged::CriticalMethod>> {
    name.map(|n| {
        CriticalMethodArg::named(n).ok_or_else(|| {
            InputError::new_err(format!(
                "method {n:?} is not a method of critical (bnb, enumerate, faces)"
            ))
        })
    })
    .transpose()
}

fn show(progress: bool) -> Show {
    if progress {
        Show::Always
    } else {
        Show::Never
    }
}

/// Enumerates `problem` as `wedged enumerate` does; `owner` is the loaded problem file of a
/// meshed body (for the JSON's `model`).
#[allow(clippy::too_many_arguments)]
fn enumerate_run(
    py: Python<'_>,
    problem: Problem,
    owner: Option<Py<LoadedProblem>>,
    source: &str,
    method: Option<&str>,
    time_limit: Option<f64>,
    certify: bool,
    zero_tol: Option<f64>,
    progress: bool,
    shard: Option<&str>,
    jsonl: Option<PathBuf>,
) -> PyResult<EnumerationRun> {
    let shard = shard_of(shard)?;
    let options = EnumerateOptions {
        method: method_of(method)?,
        zero_tol,
        time_limit,
        certify,
        shard,
        stream: jsonl.is_some(),
        ..EnumerateOptions::default()
    };
    let choice = jobs::plan_enumerate(&problem, source, &options).map_err(to_py)?;
    // The pieces streamed to a file as found, as `--jsonl` does.
    let lines = jsonl
        .as_deref()
        .map(JsonLines::create)
        .transpose()
        .map_err(|e| InputError::new_err(e.to_string()))?;
    let write_line = |p: wedged::Pattern| lines.iter().for_each(|l| l.write_pattern(&p));
    let (run, library_seconds) = released(py, |cancel| {
        let start = Instant::now();
        let run = jobs::enumerate(
            &problem,
            &choice,
            source,
            certify,
            cancel,
            show(progress),
            lines
                .is_some()
                .then_some(&write_line as wedged::PatternSink),
        )?;
        let seconds = start.elapsed().as_secs_f64();
        match run.certification_failure(source) {
            Some(failure) => Err(failure),
            None => Ok((run, seconds)),
        }
    })?;
    if let Some(lines) = lines {
        lines
            .finish()
            .map_err(|e| InputError::new_err(e.to_string()))?;
    }
    Ok(EnumerationRun {
        problem,
        choice,
        run,
        owner,
        library_seconds,
    })
}

/// A finished enumeration, kept whole: its parts as arrays ([`EnumerationRun::parts`]) and,
/// when asked, the command's JSON document ([`EnumerationRun::to_json`]), written from the same
/// report. (Writing and parsing the JSON of a few hundred rays took longer than the run.)
#[pyclass(frozen, module = "wedged._wedged")]
struct EnumerationRun {
    problem: Problem,
    choice: Choice,
    run: Enumerated,
    owner: Option<Py<LoadedProblem>>,
    /// Wall-clock seconds of the library's run, on the worker thread: what the bindings add to
    /// a call is the rest (scripts/bench_python.py).
    #[pyo3(get)]
    library_seconds: f64,
}

impl EnumerationRun {
    fn model(&self) -> Option<&Model> {
        self.owner.as_ref().and_then(|o| o.get().model.as_ref())
    }
}

#[pymethods]
impl EnumerationRun {
    /// The JSON document of `wedged enumerate --json` for this run.
    fn to_json(&self) -> String {
        self.run.json(&self.problem, &self.choice, self.model())
    }

    /// The report's scalars, as a dict: those of the JSON's top level and `info` (its JSON
    /// text). What a call hands back at once; the records come from [`EnumerationRun::parts`]
    /// when first asked for.
    fn header<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let report = Header::new(&self.problem, &self.choice, &self.run.answer);
        let out = PyDict::new(py);
        out.set_item("dim", report.dim)?;
        out.set_item("mu", report.mu)?;
        out.set_item("nodes", report.nodes)?;
        out.set_item("method", report.method)?;
        out.set_item("outcome", report.outcome)?;
        out.set_item("complete", report.complete)?;
        out.set_item("stopped", report.stopped.clone())?;
        out.set_item("certified", self.run.certificate().map(|c| c.certified()))?;
        let info = serde_json::to_string(&report.info)
            .map_err(|e| InternalError::new_err(format!("the run's info: {e}")))?;
        out.set_item("info", info)?;
        Ok(out)
    }

    /// The report's records, as a dict: the rays as arrays `ray_u`, `ray_r` (one row per ray)
    /// and `ray_status`, the cones' `cone_rays` and `cone_status`, and the pieces'
    /// `pattern_pattern`, `pattern_status`, `pattern_u`, `pattern_r`, `pattern_margin`.
    fn parts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let report = Report::new(&self.problem, &self.choice, &self.run.answer, self.model());
        let n = self.problem.dim() * self.problem.nodes();
        let rows = |vectors: Vec<&[f64]>| -> Bound<'py, PyArray2<f64>> {
            let flat: Vec<f64> = vectors.iter().flat_map(|v| v.iter().copied()).collect();
            PyArray1::from_vec(py, flat)
                .reshape([vectors.len(), n])
                .expect("n entries per row")
        };
        // Each status name made once and shared by every list (thousands of entries).
        let mut names: HashMap<&'static str, Bound<'py, PyString>> = HashMap::new();
        let mut names_of = |list: &[&'static str]| -> Vec<Bound<'py, PyString>> {
            list.iter()
                .map(|&name| {
                    names
                        .entry(name)
                        .or_insert_with(|| PyString::intern(py, name))
                        .clone()
                })
                .collect()
        };
        let mut statuses = |lists: Vec<&Vec<&'static str>>| -> Vec<Vec<Bound<'py, PyString>>> {
            lists.into_iter().map(|l| names_of(l)).collect()
        };
        let out = PyDict::new(py);
        out.set_item("ray_u", rows(report.rays.iter().map(|r| r.u).collect()))?;
        out.set_item("ray_r", rows(report.rays.iter().map(|r| r.r).collect()))?;
        out.set_item(
            "ray_status",
            statuses(report.rays.iter().map(|r| &r.status).collect()),
        )?;
        out.set_item(
            "cone_rays",
            report
                .cones
                .iter()
                .map(|c| c.rays.to_vec())
                .collect::<Vec<_>>(),
        )?;
        out.set_item(
            "cone_status",
            statuses(report.cones.iter().map(|c| &c.status).collect()),
        )?;
        let pieces: Vec<_> = report.patterns.iter().collect();
        out.set_item(
            "pattern_pattern",
            statuses(pieces.iter().map(|p| &p.pattern).collect()),
        )?;
        out.set_item(
            "pattern_status",
            statuses(pieces.iter().map(|p| &p.status).collect()),
        )?;
        out.set_item("pattern_u", rows(pieces.iter().map(|p| &p.u[..]).collect()))?;
        out.set_item("pattern_r", rows(pieces.iter().map(|p| &p.r[..]).collect()))?;
        out.set_item(
            "pattern_margin",
            pieces.iter().map(|p| p.margin).collect::<Vec<_>>(),
        )?;
        Ok(out)
    }
}

/// `enumerate(K, mu, dim, method, time_limit, certify, zero_tol, progress, rigid_modes,
/// shard, jsonl)`: the run of `wedged enumerate` on the condensed stiffness `K` (`shard` is
/// `"I/N"`; `jsonl` a path, as `--jsonl`).
#[pyfunction]
#[pyo3(signature = (k, mu, dim=2, method=None, time_limit=None, certify=false, zero_tol=None, progress=false, rigid_modes=None, shard=None, jsonl=None))]
#[allow(clippy::too_many_arguments)]
fn enumerate(
    py: Python<'_>,
    k: PyReadonlyArray2<'_, f64>,
    mu: f64,
    dim: usize,
    method: Option<&str>,
    time_limit: Option<f64>,
    certify: bool,
    zero_tol: Option<f64>,
    progress: bool,
    rigid_modes: Option<PyReadonlyArray2<'_, f64>>,
    shard: Option<&str>,
    jsonl: Option<PathBuf>,
) -> PyResult<EnumerationRun> {
    let problem = matrix_problem(&k, rigid_modes.as_ref(), dim, mu)?;
    enumerate_run(
        py, problem, None, "K", method, time_limit, certify, zero_tol, progress, shard, jsonl,
    )
}

/// `merge(parts)`: the JSON texts of a sharded run's parts merged as `wedged merge` merges
/// them; returns `(json, complete, summary)`.
#[pyfunction]
fn merge(parts: Vec<(String, String)>) -> PyResult<(String, bool, String)> {
    let parts: Vec<Part> = parts
        .into_iter()
        .map(|(name, text)| Part { name, text })
        .collect();
    let merged = wedged_cli::report::merge::merge(&parts).map_err(InputError::new_err)?;
    Ok((merged.json(), merged.complete, merged.summary))
}

/// `critical(K, dim, method, time_limit, certify, tol, progress, rigid_modes, shard, start,
/// start_file, start_json, chain)`: the JSON of `wedged critical` on the condensed stiffness
/// `K` (`shard` is `"I/N"`; `start` a contact set, `start_file` an earlier result, as
/// `--start`, `start_json` one's text; `chain` false as `--no-chain`).
#[pyfunction]
#[pyo3(signature = (k, dim=2, method=None, time_limit=None, certify=false, tol=None, progress=false, rigid_modes=None, shard=None, start=None, start_file=None, start_json=None, chain=true))]
#[allow(clippy::too_many_arguments)]
fn critical(
    py: Python<'_>,
    k: PyReadonlyArray2<'_, f64>,
    dim: usize,
    method: Option<&str>,
    time_limit: Option<f64>,
    certify: bool,
    tol: Option<f64>,
    progress: bool,
    rigid_modes: Option<PyReadonlyArray2<'_, f64>>,
    shard: Option<&str>,
    start: Option<Vec<bool>>,
    start_file: Option<PathBuf>,
    start_json: Option<String>,
    chain: bool,
) -> PyResult<String> {
    // mu plays no part in mu*; 1 passes the check of mu.
    let problem = matrix_problem(&k, rigid_modes.as_ref(), dim, 1.0)?;
    critical_json(
        py,
        &problem,
        None,
        "K",
        method,
        time_limit,
        certify,
        tol,
        progress,
        shard,
        (start, start_file, start_json),
        chain,
    )
}

/// A problem file (TOML: a condensed stiffness or a meshed body), loaded.
#[pyclass(frozen, module = "wedged._wedged")]
struct LoadedProblem {
    problem: Problem,
    model: Option<Model>,
    /// Whether the file gives `mu`.
    mu_given: bool,
    source: String,
}

#[pymethods]
impl LoadedProblem {
    /// The condensed stiffness, local frames, normal first.
    #[getter(K)]
    fn k<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let k = self.problem.stiffness();
        let rows: Vec<Vec<f64>> = (0..k.nrows())
            .map(|i| k.row(i).iter().copied().collect())
            .collect();
        PyArray2::from_vec2(py, &rows).expect("rows of equal length")
    }

    /// A floating body's free rigid motions at the contact nodes (`dim*m x k`, local frames);
    /// `None` for a held body.
    #[getter]
    fn rigid_modes<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray2<f64>>> {
        let r = self.problem.rigid_modes();
        (r.ncols() > 0).then(|| {
            let rows: Vec<Vec<f64>> = (0..r.nrows())
                .map(|i| r.row(i).iter().copied().collect())
                .collect();
            PyArray2::from_vec2(py, &rows).expect("rows of equal length")
        })
    }

    /// The file's `mu`, `None` when it gives none.
    #[getter]
    fn mu(&self) -> Option<f64> {
        self.mu_given.then(|| self.problem.mu())
    }

    #[getter]
    fn dim(&self) -> usize {
        self.problem.dim()
    }

    #[getter]
    fn source(&self) -> &str {
        &self.source
    }

    #[getter]
    fn is_mesh(&self) -> bool {
        self.model.is_some()
    }

    /// The run of `wedged enumerate FILE [--mu MU] [--shard I/N] [--jsonl PATH]`.
    #[pyo3(signature = (mu=None, method=None, time_limit=None, certify=false, zero_tol=None, progress=false, shard=None, jsonl=None))]
    #[allow(clippy::too_many_arguments)]
    fn enumerate(
        slf: &Bound<'_, Self>,
        mu: Option<f64>,
        method: Option<&str>,
        time_limit: Option<f64>,
        certify: bool,
        zero_tol: Option<f64>,
        progress: bool,
        shard: Option<&str>,
        jsonl: Option<PathBuf>,
    ) -> PyResult<EnumerationRun> {
        let this = slf.get();
        let problem = match (mu, this.mu_given) {
            (Some(mu), _) => this
                .problem
                .with_mu(mu)
                .map_err(|e| InputError::new_err(format!("mu: {e}")))?,
            (None, true) => this.problem.clone(),
            (None, false) => {
                return Err(InputError::new_err(format!(
                    "{}: the file gives no mu; pass mu=...",
                    this.source
                )))
            }
        };
        enumerate_run(
            slf.py(),
            problem,
            Some(slf.clone().unbind()),
            &this.source,
            method,
            time_limit,
            certify,
            zero_tol,
            progress,
            shard,
            jsonl,
        )
    }

    /// The JSON of `wedged critical FILE [--shard I/N] [--start PREVIOUS.json] [--no-chain]`
    /// (`start` a contact set, `start_file` an earlier result, `start_json` one's text; `chain`
    /// false as `--no-chain`).
    #[pyo3(signature = (method=None, time_limit=None, certify=false, tol=None, progress=false, shard=None, start=None, start_file=None, start_json=None, chain=true))]
    #[allow(clippy::too_many_arguments)]
    fn critical(
        &self,
        py: Python<'_>,
        method: Option<&str>,
        time_limit: Option<f64>,
        certify: bool,
        tol: Option<f64>,
        progress: bool,
        shard: Option<&str>,
        start: Option<Vec<bool>>,
        start_file: Option<PathBuf>,
        start_json: Option<String>,
        chain: bool,
    ) -> PyResult<String> {
        critical_json(
            py,
            &self.problem,
            self.model.as_ref(),
            &self.source,
            method,
            time_limit,
            certify,
            tol,
            progress,
            shard,
            (start, start_file, start_json),
            chain,
        )
    }

    /// The mesh of a meshed body, as a dict: `points` (`N x 3`), `cells` (meshio blocks
    /// `[(type, array of node indices)]`, consecutive elements of one kind in one block),
    /// `contact_nodes` (the mesh node of each contact node, in the order of `K`), `frames`
    /// (`m x dim x dim`: each contact node's axes, normal first, the inward normal of the
    /// body, in global coordinates: the rows that take a global vector to its local
    /// components) and `clamped` (the mesh nodes held fixed).
    fn mesh<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let model = self.model_or_err()?;
        let mesh = model.mesh();
        let boundary = model.boundary();
        let dim = self.problem.dim();
        let points: Vec<Vec<f64>> = mesh.coords().iter().map(|p| p.to_vec()).collect();
        let mut blocks: Vec<(&'static str, Vec<Vec<u64>>)> = Vec::new();
        for element in mesh.elements() {
            let name = meshio_type(element.kind);
            // meshio orders a cell's nodes as VTK does.
            let cell: Vec<u64> = element
                .kind
                .vtk_order(&element.nodes)
                .into_iter()
                .map(|n| n as u64)
                .collect();
            match blocks.last_mut() {
                Some((last, cells)) if *last == name => cells.push(cell),
                _ => blocks.push((name, vec![cell])),
            }
        }
        let cells = PyList::empty(py);
        for (name, block) in blocks {
            let array = PyArray2::from_vec2(py, &block).expect("cells of one kind");
            cells.append((name, array))?;
        }
        let nodes = |v: &[usize]| PyArray1::from_vec(py, v.iter().map(|&n| n as u64).collect());
        let frames: Vec<Vec<Vec<f64>>> = boundary
            .frames
            .iter()
            .map(|f| f.axes()[..dim].iter().map(|a| a[..dim].to_vec()).collect())
            .collect();
        let out = PyDict::new(py);
        out.set_item(
            "points",
            PyArray2::from_vec2(py, &points).expect("3 coordinates per point"),
        )?;
        out.set_item("cells", cells)?;
        out.set_item("contact_nodes", nodes(&boundary.contact_nodes))?;
        out.set_item(
            "frames",
            PyArray3::from_vec3(py, &frames).expect("dim axes of dim components"),
        )?;
        out.set_item("clamped", nodes(&boundary.clamped))?;
        Ok(out)
    }

    /// The whole body's state for the contact displacements `u` (local frames, as in the
    /// JSON): displacement and nodal force (the reaction at the contact nodes) per mesh node
    /// (`N x 3`), and per element the stress (`E x 6`: xx, yy, zz, xy, yz, zx) and its von
    /// Mises value.
    #[allow(clippy::type_complexity)]
    fn recover<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<(
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray1<f64>>,
    )> {
        let model = self.model_or_err()?;
        let u = u.as_slice()?;
        let expected = self.problem.stiffness().nrows();
        if u.len() != expected || u.iter().any(|x| !x.is_finite()) {
            return Err(InputError::new_err(format!(
                "u must hold {expected} finite numbers (the contact displacements), got {}",
                u.len()
            )));
        }
        let state = model.recover(u);
        let rows3 = |v: &[[f64; 3]]| v.iter().map(|p| p.to_vec()).collect::<Vec<_>>();
        let stress: Vec<Vec<f64>> = state.stress.iter().map(|s| s.to_vec()).collect();
        Ok((
            PyArray2::from_vec2(py, &rows3(&state.displacement)).expect("3 per node"),
            PyArray2::from_vec2(py, &rows3(&state.force)).expect("3 per node"),
            PyArray2::from_vec2(py, &stress).expect("6 per element"),
            PyArray1::from_vec(py, state.von_mises),
        ))
    }
}

impl LoadedProblem {
    fn model_or_err(&self) -> PyResult<&Model> {
        self.model.as_ref().ok_or_else(|| {
            InputError::new_err(format!(
                "{}: a condensed stiffness has no mesh ([mesh] in the problem file)",
                self.source
            ))
        })
    }
}

/// meshio's name of an element kind.
fn meshio_type(kind: ElementKind) -> &'static str {
    match kind {
        ElementKind::Tri3 => "triangle",
        ElementKind::Quad4 => "quad",
        ElementKind::Tet4 => "tetra",
        ElementKind::Hex8 => "hexahedron",
        ElementKind::Tri6 => "triangle6",
        ElementKind::Quad8 => "quad8",
        ElementKind::Quad9 => "quad9",
        ElementKind::Tet10 => "tetra10",
    }
}

/// `load(path)`: a problem file, read as `wedged critical` reads it (`mu` optional).
#[pyfunction]
fn load(py: Python<'_>, path: PathBuf) -> PyResult<LoadedProblem> {
    let source = path.display().to_string();
    let (loaded, mu_given) = py
        .detach(|| problem_file::load_for_critical(&path))
        .map_err(|e| InputError::new_err(one_line(&e.to_string())))?;
    Ok(LoadedProblem {
        problem: loaded.problem,
        model: loaded.model,
        mu_given,
        source,
    })
}

#[pymodule]
fn _wedged(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("InputError", m.py().get_type::<InputError>())?;
    m.add("InternalError", m.py().get_type::<InternalError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(enumerate, m)?)?;
    m.add_function(wrap_pyfunction!(critical, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_class::<LoadedProblem>()?;
    m.add_class::<EnumerationRun>()?;
    Ok(())
}
