//! `wedged condense`: a mesh problem condensed onto its contact nodes, written as Matrix Market.

use super::*;
use crate::args::*;
use crate::report::files;
use crate::report::summary;
use wedged_cli::input::{mtx, problem_file};

pub(crate) fn run_condense(args: CondenseArgs) -> Result<(), Failure> {
    let source = args.problem.display().to_string();
    let model =
        problem_file::load_model(&args.problem).map_err(|e| Failure::Input(e.to_string()))?;
    let mut text = summary::model(&source, &model);
    // `--mtx -`: stdout holds the matrix only (as `--json -` holds its JSON).
    if args
        .mtx
        .as_deref()
        .is_some_and(files::JsonTarget::is_stdout)
    {
        return write_stdout(&mtx::write_condensed(&model, &source));
    }
    if let Some(path) = &args.mtx {
        let bytes = mtx::write_condensed(&model, &source);
        files::write_atomic(path, bytes.as_bytes(), "Matrix Market file")
            .map_err(|e| Failure::Input(e.to_string()))?;
        text.push_str(&format!(
            "condensed stiffness ({n} x {n}) written to {}\n",
            path.display(),
            n = model.k().nrows()
        ));
    }
    write_stdout(&text)
}
