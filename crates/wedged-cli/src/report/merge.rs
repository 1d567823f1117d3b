//! `wedged merge`: the parts of a sharded run (`wedged enumerate --shard I/N --json part.json`,
//! or `wedged critical`) merged into the JSON that one run writes.
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
//!
//! The parts of `critical` merge by [`wedged::critical::merge_shards`]'s rule: the least
//! `upper` with its witness, the least `lower` of the shards that found a leaf, `never` when
//! none did.

use std::fmt;
use std::io::{self, Write};

use serde::de::{Deserializer, IgnoredAny, MapAccess, Visitor};
use serde::ser::{SerializeMap, Serializer};
use serde::{Deserialize, Serialize};
use serde_json::value::RawValue;
use serde_json::{Map, Value};
use wedged::patterns::{check_shards, keep_maximal, missing_text};
use wedged::{ContactPattern, Stop};

use crate::report::json::{layout, layout_into};

/// The merge of some parts (its pieces' texts borrowed from theirs).
#[derive(Debug)]
pub struct Merged<'a> {
    /// The merged document, its `patterns` (if any) written from `pieces`.
    doc: Map<String, Value>,
    pieces: Vec<&'a RawValue>,
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

struct Read<'a> {
    name: String,
    /// The part's document, its `patterns` (if any) left as `null`: they are `pieces`.
    doc: Map<String, Value>,
    /// The pieces as the part's text has them (a piece is written compact, as one run writes
    /// it, so the merge copies its text: a part's pieces are most of it, and as values they
    /// took some fifteen times its size).
    pieces: Option<Vec<&'a RawValue>>,
    index: usize,
    count: usize,
    units: u64,
    depth: u64,
}

/// A document with its `patterns` skipped (left `null`), the other keys in order.
struct WithoutPieces(Map<String, Value>);

impl<'de> Deserialize<'de> for WithoutPieces {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Keys;
        impl<'de> Visitor<'de> for Keys {
            type Value = WithoutPieces;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("an object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<WithoutPieces, A::Error> {
                let mut doc = Map::new();
                while let Some(key) = map.next_key::<String>()? {
                    let value = if key == "patterns" {
                        map.next_value::<IgnoredAny>()?;
                        Value::Null
                    } else {
                        map.next_value::<Value>()?
                    };
                    doc.insert(key, value);
                }
                Ok(WithoutPieces(doc))
            }
        }
        deserializer.deserialize_map(Keys)
    }
}

/// A document's `patterns` as text (none: no such key).
#[derive(Deserialize)]
struct PiecesOf<'a> {
    #[serde(borrow, default)]
    patterns: Option<Vec<&'a RawValue>>,
}

/// A piece's `pattern`.
#[derive(Deserialize)]
struct PatternOf<'a> {
    #[serde(borrow)]
    pattern: Vec<&'a str>,
}

/// The merged document: `doc` with its `patterns` written from `pieces`' texts.
impl Serialize for Merged<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.doc.len()))?;
        for (key, value) in &self.doc {
            if key == "patterns" {
                map.serialize_entry(key, &self.pieces)?;
            } else {
                map.serialize_entry(key, value)?;
            }
        }
        map.end()
    }
}

/// Merges the parts of one sharded run. An error (bad input) names the part at fault.
pub fn merge(parts: &[Part]) -> Result<Merged<'_>, String> {
    if parts.is_empty() {
        return Err("no parts to merge".to_string());
    }
    let read = parts.iter().map(read).collect::<Result<Vec<_>, _>>()?;
    let first = &read[0];
    let command = |r: &Read| {
        r.doc["shard"]["command"]
            .as_str()
            .unwrap_or("enumerate")
            .to_string()
    };
    if let Some(other) = read.iter().find(|r| command(r) != command(first)) {
        return Err(format!(
            "{} is a part of `wedged {}`, {} of `wedged {}`",
            other.name,
            command(other),
            first.name,
            command(first)
        ));
    }
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
    if command(first) == "critical" {
        return merge_critical(&read, &missing);
    }
    let count = first.count;

    // The pieces: the maximal patterns of the union, sorted by pattern.
    let mut pieces: Vec<(Vec<ContactPattern>, &RawValue)> = Vec::new();
    for r in &read {
        let own = r
            .pieces
            .as_ref()
            .ok_or_else(|| format!("{}: no \"patterns\" list", r.name))?;
        for &piece in own {
            let names = serde_json::from_str::<PatternOf>(piece.get())
                .map_err(|_| format!("{}: a piece without its \"pattern\" list", r.name))?
                .pattern;
            let pattern = names
                .iter()
                .map(|n| ContactPattern::from_name(n))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| format!("{}: a pattern with an unknown entry", r.name))?;
            pieces.push((pattern, piece));
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
    doc.insert("certified".into(), all_true(&read, "certified", &missing));
    doc.insert(
        "certified_complete".into(),
        all_true(&read, "certified_complete", &missing),
    );
    let n_pieces = pieces.len();
    let pieces: Vec<&RawValue> = pieces.into_iter().map(|p| p.1).collect();
    doc.insert("patterns".into(), Value::Null);
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
        doc,
        pieces,
        complete,
        summary,
    })
}

impl Merged<'_> {
    /// The JSON text, as one run writes it (see the module docs).
    pub fn json(&self) -> String {
        layout(self)
    }

    /// [`Merged::json`] written to `out` as it is made (a file's writer).
    pub fn write_json(&self, out: &mut dyn Write) -> io::Result<()> {
        layout_into(self, out)
    }
}

/// The parts of a sharded `critical` run (see the module docs).
fn merge_critical<'a>(read: &[Read<'a>], missing: &[usize]) -> Result<Merged<'a>, String> {
    let first = &read[0];
    let count = first.count;
    let number = |v: &Value| v.as_f64();
    let mut stopped: Vec<String> = Vec::new();
    if !missing.is_empty() {
        stopped.push(format!(
            "{}, lost or failed: the other shards' bracket only",
            missing_text(missing, count)
        ));
    }
    for r in read {
        if r.doc["status"] == "incomplete" {
            let why = r.doc["stopped"].as_str().unwrap_or("stopped");
            stopped.push(format!("shard {}/{}: {why}", r.index, r.count));
        }
    }
    let best = read
        .iter()
        .filter(|r| number(&r.doc["upper"]).is_some())
        .min_by(|a, b| {
            let (x, y) = (number(&a.doc["upper"]), number(&b.doc["upper"]));
            x.unwrap_or(f64::INFINITY)
                .total_cmp(&y.unwrap_or(f64::INFINITY))
        });
    let complete = stopped.is_empty();
    let status = if !complete {
        "incomplete"
    } else if read.iter().any(|r| r.doc["status"] == "wedged") {
        "wedged"
    } else {
        "never"
    };
    let lower = (status == "wedged")
        .then(|| {
            read.iter()
                .filter(|r| r.doc["status"] == "wedged")
                .filter_map(|r| number(&r.doc["lower"]))
                .min_by(f64::total_cmp)
        })
        .flatten();
    let upper = best.and_then(|b| number(&b.doc["upper"]));
    let tol_achieved = match (lower, upper) {
        (Some(l), Some(u)) => Value::from((u - l) / u),
        _ => Value::Null,
    };
    let mut doc = first.doc.clone();
    let from_best = |key: &str| best.map_or(Value::Null, |b| b.doc[key].clone());
    doc.insert("status".into(), status.into());
    doc.insert("complete".into(), complete.into());
    doc.insert(
        "stopped".into(),
        if complete {
            Value::Null
        } else {
            stopped.join("; ").into()
        },
    );
    doc.insert(
        "mu_critical".into(),
        if status == "wedged" {
            upper.map_or(Value::Null, Value::from)
        } else {
            Value::Null
        },
    );
    doc.insert("lower".into(), lower.map_or(Value::Null, Value::from));
    doc.insert("upper".into(), upper.map_or(Value::Null, Value::from));
    doc.insert("tol_achieved".into(), tol_achieved.clone());
    doc.insert("witness".into(), from_best("witness"));
    doc.insert("pattern".into(), from_best("pattern"));
    let mut thresholds = Vec::new();
    let mut undecided = Vec::new();
    for r in read {
        thresholds.extend(array(r, "thresholds")?.iter().cloned());
        undecided.extend(array(r, "undecided")?.iter().cloned());
    }
    doc.insert("thresholds".into(), Value::Array(thresholds));
    doc.insert("undecided".into(), Value::Array(undecided));
    let mut info = merged_info(read)?;
    if let Value::Object(map) = &mut info {
        map.insert("tol_achieved".into(), tol_achieved);
    }
    doc.insert("info".into(), info);
    doc.insert("certified".into(), all_true(read, "certified", missing));
    let certificates: Option<Vec<&Map<String, Value>>> = read
        .iter()
        .map(|r| r.doc["certificate"].as_object())
        .collect();
    doc.insert(
        "certificate".into(),
        match certificates {
            Some(all) => {
                let mut merged = all[0].clone();
                for key in ["refutations_checked", "refutations_failed", "resolved"] {
                    let sum: u64 = all.iter().filter_map(|c| c[key].as_u64()).sum();
                    merged.insert(key.into(), sum.into());
                }
                let failures: Vec<Value> = all
                    .iter()
                    .filter_map(|c| c["failures"].as_array())
                    .flatten()
                    .cloned()
                    .collect();
                merged.insert("failures".into(), Value::Array(failures));
                merged.insert(
                    "upper".into(),
                    best.map_or(Value::Null, |b| b.doc["certificate"]["upper"].clone()),
                );
                Value::Object(merged)
            }
            None => Value::Null,
        },
    );
    doc.remove("shard");
    // As `critical` prints them: to the digits the bracket certifies (the JSON keeps every
    // digit).
    let bracket = match (lower, upper) {
        (Some(l), Some(u)) => {
            let (mu, lo, up) = crate::report::critical::bracket_text(l, u);
            format!("mu* = {mu} (certified bracket [{lo}, {up}])")
        }
        (None, Some(u)) => format!("mu* <= {}", crate::report::upper_text(u)),
        _ => "no bracket".to_string(),
    };
    let summary = format!(
        "merged {} of {count} shards (split at depth {}, {} units) of a {}D problem with {} \
         nodes: {status}, {bracket}{}\n",
        read.len(),
        first.depth,
        first.units,
        doc["dim"],
        doc["nodes"],
        if complete {
            String::new()
        } else {
            format!(" ({})", stopped.join("; "))
        }
    );
    Ok(Merged {
        doc,
        pieces: Vec::new(),
        complete,
        summary,
    })
}

/// A `--certify` verdict of the merge: `false` when a part's `key` is false, `true` when every
/// part's is true and no shard is missing, else `null` (not asked, or not all there).
fn all_true(read: &[Read], key: &str, missing: &[usize]) -> Value {
    let values: Vec<&Value> = read.iter().map(|r| &r.doc[key]).collect();
    if values.iter().any(|v| **v == Value::Bool(false)) {
        Value::Bool(false)
    } else if values.iter().all(|v| **v == Value::Bool(true)) && missing.is_empty() {
        Value::Bool(true)
    } else {
        Value::Null
    }
}

fn read(part: &Part) -> Result<Read<'_>, String> {
    let name = part.name.clone();
    let doc = match serde_json::from_str::<WithoutPieces>(&part.text) {
        Ok(WithoutPieces(doc)) => doc,
        // Read again as any value, for the message: not JSON, or JSON but not an object.
        Err(_) => {
            serde_json::from_str::<Value>(&part.text)
                .map_err(|e| format!("{name}: not a JSON document of wedged ({e})"))?;
            return Err(format!(
                "{name}: not a JSON document of wedged (not an object)"
            ));
        }
    };
    let pieces = serde_json::from_str::<PiecesOf>(&part.text)
        .map_err(|e| format!("{name}: not a JSON document of wedged ({e})"))?
        .patterns;
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
        pieces,
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
