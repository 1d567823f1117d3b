//! `critical --start PREVIOUS.json`: the contact set that `critical`'s search starts from,
//! read from an earlier result of `wedged critical --json` (its witness's contact pattern) and
//! mapped onto this problem's contact nodes ([`wedged::CriticalSettings::start`]).
//!
//! A result on a mesh (its JSON's `model.contact`: each contact node's position and normal) is
//! mapped onto this problem's mesh node by node: each contact node takes the pattern of the
//! nearest earlier contact node on a face of about the same normal (within 60 degrees), so a
//! coarser mesh's answer of the same body gives the finer one's start. Without positions on
//! either side the two must have the same nodes, in the same order.

use std::path::Path;

use serde_json::Value;
use wedged::fe::Model;

/// An earlier result's answer as a start: its witness's contact pattern and, on a mesh, each
/// of its contact nodes' position and normal.
#[derive(Debug, Clone)]
pub struct Earlier {
    /// Whether each earlier contact node is in contact in the witness.
    pub pattern: Vec<bool>,
    /// Each earlier contact node's position and normal (`None` without a mesh).
    pub nodes: Option<Vec<(Vec<f64>, Vec<f64>)>>,
}

impl Earlier {
    /// The answer of a result computed just now: the witness's `pattern` on the contact nodes
    /// of `model` (if any), for `study`'s finer points ([`Earlier::onto`]).
    pub fn of(pattern: &[wedged::ContactPattern], model: Option<&Model>) -> Earlier {
        Earlier {
            pattern: pattern
                .iter()
                .map(|p| *p == wedged::ContactPattern::Contact)
                .collect(),
            nodes: model.map(contact_nodes),
        }
    }

    /// The earlier answer in the result at `path` (a `wedged critical --json` file), or a
    /// one-line reason why there is none.
    pub fn read(path: &Path) -> Result<Earlier, String> {
        let place = path.display();
        let text =
            std::fs::read_to_string(path).map_err(|e| format!("cannot read {place}: {e}"))?;
        Earlier::parse(&text, &place.to_string())
    }

    /// The earlier answer in the text of a `wedged critical --json` result (`place` names it in
    /// errors), or a one-line reason why there is none.
    pub fn parse(text: &str, place: &str) -> Result<Earlier, String> {
        let json: Value =
            serde_json::from_str(text).map_err(|e| format!("{place} is not JSON: {e}"))?;
        let pattern: Vec<bool> = json
            .pointer("/witness/pattern")
            .and_then(Value::as_array)
            .ok_or_else(|| {
                format!(
                    "{place} has no witness pattern (a result of `wedged critical --json` that \
                     found a wedged configuration is needed)"
                )
            })?
            .iter()
            .map(|p| p.as_str() == Some("contact"))
            .collect();
        let nodes = json
            .pointer("/model/contact")
            .and_then(Value::as_array)
            .map(|nodes| {
                nodes
                    .iter()
                    .map(|c| (numbers(c.get("x")), numbers(c.get("n"))))
                    .collect()
            });
        Ok(Earlier { pattern, nodes })
    }

    /// The start contact set for a problem of `nodes` contact nodes (with its mesh `model`,
    /// if any): each node takes the pattern of the nearest earlier node on its face, or, with
    /// no positions on either side, the same nodes in order. `Err` names why it does not fit
    /// (`place`: where the earlier result came from).
    pub fn onto(
        &self,
        nodes: usize,
        model: Option<&Model>,
        place: &str,
    ) -> Result<Vec<bool>, String> {
        let pattern = &self.pattern;
        match (&self.nodes, model) {
            (Some(earlier), Some(model)) if earlier.len() == pattern.len() => {
                let dim = model.mesh().dim();
                if let Some((x, _)) = earlier.iter().find(|(x, _)| x.len() != dim) {
                    return Err(format!(
                        "{place} is the result of a {}D body, and this problem's is {dim}D",
                        x.len()
                    ));
                }
                let mapped: Vec<bool> = contact_nodes(model)
                    .iter()
                    .map(|(x, n)| nearest(earlier, x, n).is_some_and(|k| pattern[k]))
                    .collect();
                if mapped.len() != nodes {
                    return Err(format!(
                        "{place}: {} contact nodes mapped for {nodes}",
                        mapped.len()
                    ));
                }
                Ok(mapped)
            }
            _ if pattern.len() == nodes => Ok(pattern.clone()),
            _ => Err(format!(
                "{place} has {} contact nodes and no mesh positions to map them onto this \
                 problem's {nodes}",
                pattern.len()
            )),
        }
    }
}

/// The start contact set for a problem of `nodes` contact nodes (with its mesh `model`, if
/// any) from the result at `path`, or a one-line reason why there is none.
pub fn start_contact(
    path: &Path,
    nodes: usize,
    model: Option<&Model>,
) -> Result<Vec<bool>, String> {
    Earlier::read(path)?.onto(nodes, model, &path.display().to_string())
}

/// Each contact node of `model`: its position and its inward normal (as the result JSON's
/// `model.contact` has them).
fn contact_nodes(model: &Model) -> Vec<(Vec<f64>, Vec<f64>)> {
    let mesh = model.mesh();
    let dim = mesh.dim();
    let b = model.boundary();
    b.contact_nodes
        .iter()
        .zip(&b.frames)
        .map(|(&a, f)| (mesh.coords()[a][..dim].to_vec(), f.n[..dim].to_vec()))
        .collect()
}

/// The numbers of a JSON array (none when it is not one).
fn numbers(v: Option<&Value>) -> Vec<f64> {
    v.and_then(Value::as_array)
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default()
}

/// The earlier node nearest to `x` among those whose normal is within 60 degrees of `n` (all of
/// them when none is), the first of equals.
fn nearest(earlier: &[(Vec<f64>, Vec<f64>)], x: &[f64], n: &[f64]) -> Option<usize> {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
    let distance = |y: &[f64]| x.iter().zip(y).map(|(p, q)| (p - q) * (p - q)).sum::<f64>();
    let closest = |same_face: bool| {
        earlier
            .iter()
            .enumerate()
            .filter(|(_, (y, m))| y.len() == x.len() && (!same_face || dot(m, n) > 0.5))
            .min_by(|a, b| distance(&a.1 .0).total_cmp(&distance(&b.1 .0)))
            .map(|(k, _)| k)
    };
    closest(true).or_else(|| closest(false))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A node takes the pattern of the nearest earlier node on its own face, not of a nearer
    /// one on the other face.
    #[test]
    fn nodes_take_the_nearest_on_their_face() {
        let earlier = vec![
            (vec![0.0, 0.0], vec![1.0, 0.0]),
            (vec![0.0, 1.0], vec![1.0, 0.0]),
            (vec![0.1, 0.5], vec![-1.0, 0.0]),
        ];
        assert_eq!(nearest(&earlier, &[0.0, 0.55], &[1.0, 0.0]), Some(1));
        assert_eq!(nearest(&earlier, &[0.0, 0.55], &[-1.0, 0.0]), Some(2));
        assert_eq!(nearest(&earlier, &[0.0, 0.2], &[0.0, 1.0]), Some(0));
    }
}
