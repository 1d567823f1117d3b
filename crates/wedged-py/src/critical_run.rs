//! `critical` as the command runs it, for the module function and `LoadedProblem.critical`.

use super::*;

/// Where a Python `critical` starts ([`wedged::CriticalSettings::start`]): a contact set, the
/// path of an earlier result, or an earlier result's JSON text (a `Critical` in memory).
pub(crate) type Start = (Option<Vec<bool>>, Option<PathBuf>, Option<String>);

/// Computes `mu*` as `wedged critical` does and returns its JSON document.
#[allow(clippy::too_many_arguments)]
pub(crate) fn critical_json(
    py: Python<'_>,
    problem: &Problem,
    model: Option<&Model>,
    source: &str,
    method: Option<&str>,
    time_limit: Option<f64>,
    certify: bool,
    tol: Option<f64>,
    progress: bool,
    shard: Option<&str>,
    start: Start,
    chain: bool,
) -> PyResult<String> {
    let shard = shard_of(shard)?;
    let mut settings = jobs::plan_critical(&CriticalOptions {
        method: critical_method_of(method)?,
        tol,
        time_limit,
        certify,
        shard,
    })
    .map_err(to_py)?;
    // As `critical --start`: a contact set, or an earlier result's mapped onto this problem.
    let (nodes, earlier) = (problem.nodes(), wedged_cli::input::start::Earlier::parse);
    settings.start = match start {
        (Some(start), _, _) => Some(start),
        (None, Some(path), _) => Some(
            wedged_cli::input::start::start_contact(&path, nodes, model)
                .map_err(InputError::new_err)?,
        ),
        (None, None, Some(text)) => Some(
            earlier(&text, "the start result")
                .and_then(|e| e.onto(nodes, model, "the start result"))
                .map_err(InputError::new_err)?,
        ),
        (None, None, None) => None,
    };
    // `chain = False`, as `--no-chain`: no condensed problem starts the search.
    settings.condense = chain;
    released(py, |cancel| {
        let result =
            jobs::run_critical_library(problem, &settings, source, cancel, show(progress))?;
        if let Some(failure) = jobs::critical_certification_failure(source, &result) {
            return Err(failure);
        }
        Ok(wedged_cli::report::critical::to_json(
            problem, &settings, source, &result, model,
        ))
    })
}
