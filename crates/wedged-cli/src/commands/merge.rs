//! `wedged merge`: the parts of a sharded run into the JSON one run writes
//! ([`wedged_cli::report::merge`]).

use super::*;
use crate::report::files::JsonTarget;
use wedged_cli::report::merge::{merge, Part};

pub(crate) fn run_merge(args: MergeArgs) -> Result<(), Failure> {
    let json = args
        .json
        .json
        .as_deref()
        .map(JsonTarget::open)
        .transpose()
        .map_err(|e| Failure::Input(e.to_string()))?;
    let parts = args
        .parts
        .iter()
        .map(|path| {
            let name = path.display().to_string();
            std::fs::read_to_string(path)
                .map(|text| Part {
                    name: name.clone(),
                    text,
                })
                .map_err(|e| Failure::Input(format!("{name}: cannot read the part: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let merged = merge(&parts).map_err(Failure::Input)?;
    match json {
        Some(JsonTarget::Stdout) => write_stdout(&merged.json())?,
        Some(target) => {
            let path = match &target {
                JsonTarget::File { path, .. } => path.display().to_string(),
                JsonTarget::Stdout => String::new(),
            };
            target
                .commit_with(|out| merged.write_json(out))
                .map_err(|e| Failure::Input(e.to_string()))?;
            write_stdout(&format!("{}JSON written to {path}\n", merged.summary))?;
        }
        None => write_stdout(&merged.summary)?,
    }
    if merged.complete {
        Ok(())
    } else {
        Err(Failure::Incomplete(
            "the merged answer is incomplete (see the summary and the JSON's \"stopped\")"
                .to_string(),
        ))
    }
}
