//! The legacy MSH 2.2 format, ASCII or binary (either byte order), read into the same [`Mesh`]
//! as an MSH 4.1 file of the same model (the parent module's docs).
//!
//! The format: `$PhysicalNames` (text), `$Nodes` (a count, then per node its tag and three
//! coordinates), `$Elements` (a count, then per element its tag, Gmsh type, tags and nodes; in
//! a binary file the elements come in blocks of one type, each after a header of three
//! integers: type, count, number of tags). An element's first tag is its physical group (0:
//! none), the second its elementary entity; an element of several physical groups is written
//! once per group, under different tags. So:
//!
//! - nodes: all of `$Nodes`, in file order;
//! - body elements: the elements of the highest dimension, in file order, each set of nodes
//!   once (its other copies are the same element in another physical group);
//! - groups: one per physical tag and dimension, with its elements in file order, named from
//!   `$PhysicalNames` (else `<dim>:<tag>`); a named group without elements is kept, empty, so
//!   that asking for it says so rather than that it does not exist.

use std::collections::{BTreeMap, HashMap, HashSet};

use wedged::fe::{Element, Group, Mesh};

use super::{
    body_kind, check_types, flatten, mesh_dim, physical_names, section_starts, type_info, Header,
    Reader,
};

/// Parses an MSH 2.2 file whose header has been read.
pub(super) fn parse(bytes: &[u8], header: &Header) -> Result<Mesh, String> {
    let names = physical_names(bytes)?;
    let (coords, index) = nodes(bytes, header)?;
    let elements = elements(bytes, header, &index)?;
    let dim = mesh_dim(elements.iter().map(|e| (e.kind, e.dim)))?;
    check_types(elements.iter().map(|e| (e.kind, e.dim)), dim)?;

    let mut body = Vec::new();
    let mut seen = HashSet::new();
    for e in elements.iter().filter(|e| e.dim == dim) {
        if seen.insert(e.nodes.as_slice()) {
            body.push(Element {
                kind: body_kind(e.kind, dim).expect("checked above"),
                nodes: e.nodes.clone(),
            });
        }
    }

    let mut groups: BTreeMap<(i32, i64), Vec<Vec<usize>>> = BTreeMap::new();
    for (&(d, p), _) in names.iter().filter(|(&(d, p), _)| d <= dim.into() && p > 0) {
        groups.entry((d as i32, p)).or_default();
    }
    for e in elements.iter().filter(|e| e.physical > 0) {
        groups
            .entry((e.dim, e.physical))
            .or_default()
            .push(e.nodes.clone());
    }
    let groups = groups
        .into_iter()
        .map(|((d, p), entities)| Group {
            name: names
                .get(&(d.into(), p))
                .cloned()
                .unwrap_or_else(|| format!("{d}:{p}")),
            dim: d as usize,
            entities,
        })
        .collect();

    let mut coords = coords;
    if dim == 2 {
        flatten(&mut coords)?;
    }
    Mesh::new(dim as usize, coords, body, groups).map_err(|e| format!("invalid mesh: {e}"))
}

/// An element as read: its Gmsh type and that type's dimension, its physical tag (0: none)
/// and its nodes as indices.
struct Read {
    kind: i32,
    dim: i32,
    physical: i64,
    nodes: Vec<usize>,
}

/// The number of nodes of a Gmsh element type (the types of [`type_info`]).
fn node_count(t: i32) -> Option<usize> {
    Some(match t {
        15 => 1,
        1 => 2,
        2 | 8 => 3,
        3 | 4 | 26 => 4,
        7 | 27 => 5,
        6 | 9 | 28 => 6,
        5 | 16 => 8,
        10 | 20 => 9,
        11 | 21 => 10,
        22 => 12,
        19 => 13,
        14 => 14,
        18 | 23 | 24 => 15,
        13 => 18,
        17 | 29 => 20,
        25 => 21,
        12 => 27,
        30 => 35,
        31 => 56,
        92 => 64,
        93 => 125,
        _ => return None,
    })
}

/// Where a reader is, for a message: the line (ASCII) or the byte offset (binary).
fn at(r: &Reader) -> String {
    if r.header.binary {
        format!("byte {}", r.pos)
    } else {
        let line = 1 + r.bytes[..r.pos.min(r.bytes.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        format!("line {line}")
    }
}

/// The error for a section that cannot be read where `r` stopped.
fn malformed(r: &Reader, section: &str, what: &str) -> String {
    if r.pos >= r.bytes.len() || r.bytes[r.pos..].iter().all(u8::is_ascii_whitespace) {
        return format!("malformed MSH file: the file ends too early in its {section} section (is it truncated?)");
    }
    format!("malformed MSH file at {}: {what} (in {section})", at(r))
}

/// A section's count, the text line after its tag; in a binary file the data then begins
/// after that line's single line break.
fn count(r: &mut Reader, section: &str) -> Result<usize, String> {
    let n = r
        .token()
        .and_then(|t| t.parse::<usize>().ok())
        .ok_or_else(|| malformed(r, section, "expected the number of entries"))?;
    if r.header.binary {
        match r.bytes.get(r.pos..) {
            Some([b'\n', ..]) => r.pos += 1,
            Some([b'\r', b'\n', ..]) => r.pos += 2,
            _ => {
                return Err(malformed(
                    r,
                    section,
                    "expected a line break after the count",
                ))
            }
        }
    }
    Ok(n)
}

/// A reader at the first entry of the file's first `section` (holding `what`), and the number
/// of entries its count line announces: an error when there is no such section or it is empty.
fn open<'a>(
    bytes: &'a [u8],
    header: &'a Header,
    section: &str,
    what: &str,
) -> Result<(Reader<'a>, usize), String> {
    let start = section_starts(bytes, section.as_bytes())
        .next()
        .ok_or_else(|| format!("the file has no {section} section"))?;
    let mut r = Reader::new(bytes, start, header);
    let n = count(&mut r, section)?;
    if n == 0 {
        return Err(format!(
            "the file has no {what} (its {section} section is empty; was the mesh generated?)"
        ));
    }
    Ok((r, n))
}

/// The section's end tag, next.
fn end(r: &mut Reader, section: &str) -> Result<(), String> {
    let tag = format!("$End{}", &section[1..]);
    match r.token() {
        Some(t) if t == tag => Ok(()),
        _ => Err(malformed(
            r,
            section,
            &format!("expected {tag} after the entries the count announced"),
        )),
    }
}

/// A double: a token, or eight bytes.
fn double(r: &mut Reader) -> Option<f64> {
    if r.header.binary {
        r.raw(8).map(f64::from_le_bytes)
    } else {
        r.token()?.parse().ok()
    }
}

/// Node coordinates in file order, and each node tag's index among them.
type Nodes = (Vec<[f64; 3]>, HashMap<i64, usize>);

/// The `$Nodes` section.
fn nodes(bytes: &[u8], header: &Header) -> Result<Nodes, String> {
    let section = "$Nodes";
    let (mut r, n) = open(bytes, header, section, "nodes")?;
    // A count beyond what the file can hold is caught by the reads; do not reserve for it.
    let room = n.min(bytes.len() / 16);
    let mut coords = Vec::with_capacity(room);
    let mut index = HashMap::with_capacity(room);
    for _ in 0..n {
        let tag = r
            .int()
            .ok_or_else(|| malformed(&r, section, "expected a node tag"))?;
        let mut x = [0.0; 3];
        for c in &mut x {
            *c = double(&mut r).ok_or_else(|| {
                malformed(&r, section, &format!("expected node {tag}'s coordinates"))
            })?;
        }
        if index.insert(tag, coords.len()).is_some() {
            return Err(format!("node tag {tag} is defined twice in $Nodes"));
        }
        coords.push(x);
    }
    end(&mut r, section)?;
    Ok((coords, index))
}

/// The `$Elements` section, in file order.
fn elements(
    bytes: &[u8],
    header: &Header,
    index: &HashMap<i64, usize>,
) -> Result<Vec<Read>, String> {
    let section = "$Elements";
    let (mut r, n) = open(bytes, header, section, "elements")?;
    let mut out = Vec::with_capacity(n.min(bytes.len() / 16));
    // Binary: the current block's type, elements left in it, and number of tags.
    let mut block = (0, 0usize, 0usize);
    while out.len() < n {
        let int = |r: &mut Reader, what: &str| {
            r.int()
                .ok_or_else(|| malformed(r, section, &format!("expected {what}")))
        };
        if header.binary && block.1 == 0 {
            let t = int(&mut r, "an element block's type")?;
            let following = int(&mut r, "an element block's size")?;
            let tags = int(&mut r, "an element block's number of tags")?;
            if following <= 0 || !(0..=64).contains(&tags) {
                return Err(malformed(&r, section, "invalid element block header"));
            }
            block = (t as i32, following as usize, tags as usize);
        }
        let tag = int(&mut r, "an element tag")?;
        let (t, tags) = if header.binary {
            block.1 -= 1;
            (block.0, block.2)
        } else {
            let t = int(&mut r, "an element type")?;
            let tags = int(&mut r, "the number of tags")?;
            if !(0..=64).contains(&tags) {
                return Err(malformed(
                    &r,
                    section,
                    &format!("element {tag} has {tags} tags"),
                ));
            }
            (t as i32, tags as usize)
        };
        let (Some(dim), Some(count)) = (type_info(t).1, node_count(t)) else {
            return Err(super::unsupported(t, 2));
        };
        let mut physical = 0;
        for k in 0..tags {
            let v = int(&mut r, "an element's tags")?;
            if k == 0 {
                physical = v;
            }
        }
        let nodes = (0..count)
            .map(|_| {
                let node = int(&mut r, &format!("element {tag}'s nodes"))?;
                index.get(&node).copied().ok_or_else(|| {
                    format!("element {tag} refers to node {node}, which is not in $Nodes")
                })
            })
            .collect::<Result<Vec<usize>, String>>()?;
        out.push(Read {
            kind: t,
            dim,
            physical,
            nodes,
        });
    }
    if block.1 != 0 {
        return Err(malformed(
            &r,
            section,
            "an element block runs past the number of elements",
        ));
    }
    end(&mut r, section)?;
    Ok(out)
}
