//! `wedged merge`: the parts of a sharded run (`wedged enumerate --shard I/N --json part.json`)
//! merged into the JSON that one run writes.
//!
//! The merge works on the JSON documents, so that it needs neither the problem file nor the
//! mesh: every part carries the whole header (and the model of a meshed body), and its `shard`
//! key says which shard it is and the run's fingerprint (the problem and every setting that can
//! change the answer). It refuses parts of different runs, a shard given twice, and anything
//! that is not a part; a missing shard (lost, failed) is named, and the merge of the others is
//! then written marked incomplete (`"complete": false`, exit 3), never as the answer.
//!
//! The pieces are the maximal patterns of the union ([`wedged::patterns::keep_maximal`]),
//! sorted by pattern as one run sorts them; each comes with its shard's witness, which is the
//! one run's (a witness depends on its pattern alone). So the merged document equals one run's
//! except `info`: its counters are the sums of the shards' (the top of the tree, which every
//! shard solves, once per shard), `seconds` and `peak_rss_bytes` the largest shard's.

use serde_json::{Map, Value};
use wedged::patterns::{check_shards, keep_maximal, missing_text};
use wedged::{ContactPattern, Stop};

use crate::report::json::layout;

/// The merge of some parts.
#[derive(Debug)]
pub struct Merged {
    /// The JSON text, as one run writes it (see the module docs).
    pub json: String,
    /// False when a shard is missing or a part is incomplete.
    pub complete: bool,
    /// A few lines for stdout.
    pub summary: String,
}

/// One part: its name (the file, for messages) and its JSON text.
pub struct Part {
    pub name: String,
    pub text: String,
}

struct Read {
    name: String,
    doc: Map<String, Value>,
    index: usize,
    count: usize,
    units: u64,
    depth: u64,
}

/// Merges the parts of one sharded run. An error (bad input) names the part at fault.
pub fn merge(parts: &[Part]) -> Result<Merged, String> {
    if parts.is_empty() {
        return Err("no parts to merge".to_string());
    }
    let read = parts.iter().map(read).collect::<Result<Vec<_>, _>>()?;
    let first = &read[0];
    let fingerprint = |r: &Read| r.doc["shard"]["fingerprint"].clone();
    if let Some(other) = read.iter().find(|r| fingerprint(r) != fingerprint(first)) {
        return Err(format!(
            "{} is a part of another run than {} (fingerprints {} and {}: a different problem, \
             mu or setting)",
            other.name,
            first.name,
            fingerprint(other),
            fingerprint(first)
        ));
    }
    let shards: Vec<(usize, usize)> = read.iter().map(|r| (r.index, r.count)).collect();
    let missing = check_shards(&shards)?;
    let count = first.count;

    // The pieces: the maximal patterns of the union, sorted by pattern.
    let mut pieces: Vec<(Vec<ContactPattern>, Value)> = Vec::new();
    for r in &read {
        for piece in array(r, "patterns")? {
            let names = piece["pattern"]
                .as_array()
                .ok_or_else(|| format!("{}: a piece without its \"pattern\" list", r.name))?;
            let pattern = names
                .iter()
                .map(|n| n.as_str().and_then(ContactPattern::from_name))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| format!("{}: a pattern with an unknown entry", r.name))?;
            pieces.push((pattern, piece.clone()));
        }
    }
    let keep = keep_maximal(&pieces.iter().map(|p| &p.0[..]).collect::<Vec<_>>());
    let mut pieces: Vec<_> = pieces
        .into_iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(p))
        .collect();
    pieces.sort_by(|a, b| a.0.cmp(&b.0));
    let mut undecided: Vec<Value> = Vec::new();
    for r in &read {
        for u in array(r, "undecided")? {
            if !undecided.iter().any(|v| v["contact"] == u["contact"]) {
                undecided.push(u.clone());
            }
        }
    }

    // Complete only when every shard is there and complete.
    let mut stopped: Vec<String> = Vec::new();
    if !missing.is_empty() {
        stopped.push(format!(
            "{}, lost or failed: these are the other shards' pieces only",
            missing_text(&missing, count)
        ));
    }
    let undecided_text = Stop::Undecided.to_string();
    for r in &read {
        if r.doc["complete"] == Value::Bool(false) {
            let why = r.doc["stopped"].as_str().unwrap_or("stopped");
            if why != undecided_text {
                stopped.push(format!("shard {}/{}: {why}", r.index, r.count));
            }
        }
    }
    if stopped.is_empty() && !undecided.is_empty() {
        stopped.push(undecided_text);
    }
    let complete = stopped.is_empty();
    let outcome = if !complete {
        "incomplete"
    } else if pieces.is_empty() {
        "not-wedged"
    } else {
        "wedged"
    };
    let all = |key: &str| -> Value {
        let values: Vec<&Value> = read.iter().map(|r| &r.doc[key]).collect();
        if values.iter().any(|v| **v == Value::Bool(false)) {
            Value::Bool(false)
        } else if values.iter().all(|v| **v == Value::Bool(true)) && missing.is_empty() {
            Value::Bool(true)
        } else {
            Value::Null
        }
    };

    let mut doc = first.doc.clone();
    doc.insert("outcome".into(), outcome.into());
    doc.insert("complete".into(), complete.into());
    doc.insert(
        "stopped".into(),
        if complete {
            Value::Null
        } else {
            stopped.join("; ").into()
        },
    );
    doc.insert("certified".into(), all("certified"));
    doc.insert("certified_complete".into(), all("certified_complete"));
    let n_pieces = pieces.len();
    doc.insert(
        "patterns".into(),
        Value::Array(pieces.into_iter().map(|p| p.1).collect()),
    );
    doc.insert("undecided".into(), Value::Array(undecided));
    doc.insert("info".into(), merged_info(&read)?);
    doc.remove("shard");

    let summary = format!(
        "merged {} of {count} shards (split at depth {}, {} units) of a {}D problem with {} \
         nodes at mu = {}: {n_pieces} pieces, {outcome}{}\n",
        read.len(),
        first.depth,
        first.units,
        doc["dim"],
        doc["nodes"],
        doc["mu"],
        if complete {
            String::new()
        } else {
            format!(" ({})", stopped.join("; "))
        }
    );
    Ok(Merged {
        json: layout(&Value::Object(doc)),
        complete,
        summary,
    })
}

fn read(part: &Part) -> Result<Read, String> {
    let name = part.name.clone();
    let value: Value = serde_json::from_str(&part.text)
        .map_err(|e| format!("{name}: not a JSON document of wedged ({e})"))?;
    let Value::Object(doc) = value else {
        return Err(format!(
            "{name}: not a JSON document of wedged (not an object)"
        ));
    };
    let shard = doc.get("shard").ok_or_else(|| {
        format!(
            "{name}: not a part of a sharded run (no \"shard\" key; parts are written by \
             `wedged enumerate FILE --shard I/N --json PART`)"
        )
    })?;
    let number = |key: &str| {
        shard[key]
            .as_u64()
            .ok_or_else(|| format!("{name}: the shard's \"{key}\" is not a whole number"))
    };
    let (index, count) = (number("index")? as usize, number("count")? as usize);
    let (units, depth) = (number("units")?, number("split_depth")?);
    if !shard["fingerprint"].is_string() {
        return Err(format!("{name}: the shard has no fingerprint"));
    }
    Ok(Read {
        name,
        doc,
        index,
        count,
        units,
        depth,
    })
}

fn array<'a>(r: &'a Read, key: &str) -> Result<&'a Vec<Value>, String> {
    r.doc
        .get(key)
        .and_then(Value::as_array)
        .ok_or_else(|| format!("{}: no \"{key}\" list", r.name))
}

/// The shards' counters summed; `seconds` and `peak_rss_bytes` the largest; `method` and
/// `pyramid_faces` the first part's.
fn merged_info(read: &[Read]) -> Result<Value, String> {
    let mut info = Map::new();
    for r in read {
        let Some(Value::Object(part)) = r.doc.get("info") else {
            return Err(format!("{}: no \"info\" object", r.name));
        };
        for (key, value) in part {
            let merged = match (info.get(key), value) {
                (None, v) => v.clone(),
                (Some(Value::Number(a)), Value::Number(b)) => {
                    if key == "seconds" || key == "peak_rss_bytes" {
                        let (x, y) = (a.as_f64().unwrap_or(0.0), b.as_f64().unwrap_or(0.0));
                        if x >= y {
                            Value::Number(a.clone())
                        } else {
                            Value::Number(b.clone())
                        }
                    } else {
                        match (a.as_u64(), b.as_u64()) {
                            (Some(x), Some(y)) => (x + y).into(),
                            _ => Value::Number(a.clone()),
                        }
                    }
                }
                (Some(Value::Null), v) if key == "peak_rss_bytes" => v.clone(),
                (Some(a), _) => a.clone(),
            };
            info.insert(key.clone(), merged);
        }
    }
    Ok(Value::Object(info))
}
