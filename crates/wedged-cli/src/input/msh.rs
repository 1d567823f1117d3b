//! Reader of Gmsh meshes in the MSH 4.1 format and the legacy MSH 2.2 format, ASCII or binary
//! (either byte order).
//!
//! An MSH 4.1 file is parsed by the `mshio` crate, completed by what `mshio` leaves out:
//!
//! - `$PhysicalNames` (always text, even in binary files) is read here;
//! - node tags: `mshio` keeps them only when they are sparse, so they are read here from the
//!   `$Nodes` section, after `mshio` has checked its structure;
//! - a few malformed headers on which `mshio` would panic (an empty `$Nodes` or `$Elements`
//!   section with a non-zero tag range, an odd `size_t` size) are rejected beforehand.
//!
//! The resulting [`Mesh`]:
//!
//! - its dimension is the highest dimension of the elements in the file (2 or 3);
//! - its body elements are all elements of that dimension, in file order, whether or not they
//!   belong to a physical group: triangles (3 or 6 nodes) and quadrangles (4, 8 or 9 nodes) in
//!   2D, tetrahedra (4 or 10 nodes) and 8-node hexahedra in 3D (any other element type is an
//!   error);
//! - its nodes are all nodes of the file, in file order (Gmsh tags may be sparse and in any
//!   order); in 2D the z coordinates must all be equal, and are set to 0;
//! - its groups are the physical groups, ordered by dimension then tag, each with the elements
//!   of the entities that carry it: points (1-node elements, or the point entity's node),
//!   lines (2 or 3 nodes), triangle (3 or 6 nodes) or quadrangle faces (3D), body elements. A group without a name in
//!   `$PhysicalNames` is named `<dim>:<tag>`, e.g. `1:7`.
//!
//! Gmsh saves only the elements that belong to a physical group unless `Mesh.SaveAll = 1`, so
//! the body needs a physical surface (2D) or volume (3D) when the boundary has physical groups.
//!
//! An MSH 2.2 file (Gmsh's `-format msh22`, still the default of many tools) has no entities:
//! each element carries its physical tag, and an element of several physical groups is written
//! once per group. It is read here (`v2`) into the same [`Mesh`]: the same nodes and groups as
//! the MSH 4.1 file of the same model, each body element once.

use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::path::Path;

use mshio::{MshFile, MshParserError};
use wedged::fe::{Element, Group, Mesh};

/// A Gmsh mesh file could not be read, parsed or converted.
///
/// Its `Display` form is one line: the file name and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MshError {
    /// The file name, as given to [`read`] or [`parse`].
    pub file: String,
    /// What is wrong, without the file name.
    pub message: String,
}

impl MshError {
    /// An error about `file`; control characters (line breaks) become spaces.
    fn new(file: &str, message: impl Into<String>) -> Self {
        let one_line = |s: &str| -> String {
            s.chars()
                .map(|c| if c.is_control() { ' ' } else { c })
                .collect()
        };
        MshError {
            file: one_line(file),
            message: one_line(&message.into()),
        }
    }
}

impl fmt::Display for MshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file, self.message)
    }
}

impl std::error::Error for MshError {}

/// Reads a Gmsh MSH 4.1 or 2.2 file (ASCII or binary).
pub fn read(path: &Path) -> Result<Mesh, MshError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| MshError::new(&name, format!("cannot read the file: {e}")))?;
    parse(&bytes, &name)
}

/// Parses the contents of a Gmsh MSH 4.1 or 2.2 file (ASCII or binary); `name` is used in
/// messages.
pub fn parse(bytes: &[u8], name: &str) -> Result<Mesh, MshError> {
    parse_inner(bytes).map_err(|message| MshError::new(name, message))
}

fn parse_inner(bytes: &[u8]) -> Result<Mesh, String> {
    let header = Header::read(bytes)?;
    if header.legacy {
        return v2::parse(bytes, &header);
    }
    precheck_sections(bytes, &header)?;
    // `mshio` has no known panic left on the inputs that pass the checks above; should one
    // remain, it becomes an error rather than a crash.
    let msh = match crate::contain_panic(|| mshio::parse_msh_bytes(bytes)) {
        Some(Ok(msh)) => msh,
        Some(Err(e)) => return Err(describe_parser_error(&e, bytes, header.binary)),
        None => return Err("malformed MSH file: the MSH parser failed".to_string()),
    };
    let names = physical_names(bytes)?;
    build(&msh, &names, bytes, &header)
}

// ---------------------------------------------------------------------------------------------
// Header and low-level reading

/// What the `$MeshFormat` section says.
struct Header {
    /// MSH 2.2 (else 4.1).
    legacy: bool,
    binary: bool,
    size_t: usize,
    big_endian: bool,
}

impl Header {
    /// Checks the `$MeshFormat` section: version 4.1 or 2.2, file type 0 or 1, a usable
    /// `size_t` size (MSH 2.2: the size of a double, 8) and, in binary files, a recognisable
    /// byte order.
    fn read(bytes: &[u8]) -> Result<Header, String> {
        if bytes.iter().all(|b| b.is_ascii_whitespace()) {
            return Err("the file is empty".to_string());
        }
        let Some(rest) = strip_line(bytes, b"$MeshFormat") else {
            return Err("not a Gmsh MSH file (it does not begin with $MeshFormat)".to_string());
        };
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        let line = String::from_utf8_lossy(&rest[..end]);
        let fields: Vec<&str> = line.split_whitespace().collect();
        let invalid = || {
            let shown: String = line.trim().chars().take(40).collect();
            format!("invalid $MeshFormat header '{shown}'")
        };
        let version = fields.first().ok_or_else(invalid)?;
        let number = version.parse::<f64>().map_err(|_| invalid())?;
        if number != 4.1 && number != 2.2 {
            return Err(format!(
                "MSH {version} is not supported; save as MSH 4.1 (gmsh -format msh41) or 2.2"
            ));
        }
        let legacy = number == 2.2;
        if fields.len() != 3 {
            return Err(invalid());
        }
        let binary = match fields[1] {
            "0" => false,
            "1" => true,
            _ => return Err(invalid()),
        };
        let size_t: usize = match fields[2].parse::<u8>() {
            Ok(n) if fields[2].bytes().all(|b| b.is_ascii_digit()) => n.into(),
            _ => return Err(invalid()),
        };
        let mut big_endian = false;
        if binary {
            if legacy && size_t != 8 {
                return Err(format!(
                    "binary MSH 2.2 files with {size_t}-byte doubles are not supported \
                     (only 8 bytes)"
                ));
            }
            if size_t != 4 && size_t != 8 {
                return Err(format!(
                    "binary MSH files with {size_t}-byte size_t are not supported \
                     (only 4 or 8 bytes)"
                ));
            }
            let one = rest
                .get(end + 1..end + 5)
                .ok_or("the binary MSH file is truncated in its $MeshFormat section")?;
            let one: [u8; 4] = one.try_into().expect("4 bytes");
            if i32::from_le_bytes(one) == 1 {
                big_endian = false;
            } else if i32::from_be_bytes(one) == 1 {
                big_endian = true;
            } else {
                return Err(
                    "cannot detect the byte order of the binary MSH file (no integer 1 \
                     after the $MeshFormat header)"
                        .to_string(),
                );
            }
        }
        Ok(Header {
            legacy,
            binary,
            size_t,
            big_endian,
        })
    }
}

/// If `bytes` begins with the line `tag` (ended by `\n` or `\r\n`), the bytes after it.
fn strip_line<'a>(bytes: &'a [u8], tag: &[u8]) -> Option<&'a [u8]> {
    let rest = bytes.strip_prefix(tag)?;
    rest.strip_prefix(b"\n")
        .or_else(|| rest.strip_prefix(b"\r\n"))
}

/// Offsets of the contents of every section `tag` (e.g. `$Nodes`): just after a line that
/// consists of `tag` alone. In a binary file a match could in principle lie inside binary
/// data, so callers check what they read.
fn section_starts<'a>(bytes: &'a [u8], tag: &'a [u8]) -> impl Iterator<Item = usize> + 'a {
    (0..bytes.len()).filter_map(move |i| {
        if i > 0 && bytes[i - 1] != b'\n' {
            return None;
        }
        let rest = strip_line(&bytes[i..], tag)?;
        Some(bytes.len() - rest.len())
    })
}

/// Reads the numbers of a section, ASCII or binary.
struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
    header: &'a Header,
}

impl<'a> Reader<'a> {
    fn new(bytes: &'a [u8], pos: usize, header: &'a Header) -> Self {
        Reader { bytes, pos, header }
    }

    /// The next whitespace-separated token (ASCII files).
    fn token(&mut self) -> Option<&'a str> {
        let bytes = self.bytes;
        while bytes.get(self.pos)?.is_ascii_whitespace() {
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < bytes.len() && !bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        std::str::from_utf8(&bytes[start..self.pos]).ok()
    }

    /// The next `n` bytes, reversed to little-endian order if the file is big-endian.
    fn raw(&mut self, n: usize) -> Option<[u8; 8]> {
        let slice = self.bytes.get(self.pos..self.pos + n)?;
        self.pos += n;
        let mut out = [0; 8];
        out[..n].copy_from_slice(slice);
        if self.header.big_endian {
            out[..n].reverse();
        }
        Some(out)
    }

    fn size_t(&mut self) -> Option<u64> {
        if self.header.binary {
            let n = self.header.size_t;
            self.raw(n).map(u64::from_le_bytes)
        } else {
            self.token()?.parse().ok()
        }
    }

    fn int(&mut self) -> Option<i64> {
        if self.header.binary {
            let b = self.raw(4)?;
            Some(i32::from_le_bytes([b[0], b[1], b[2], b[3]]).into())
        } else {
            self.token()?.parse().ok()
        }
    }

    fn skip_doubles(&mut self, n: usize) -> Option<()> {
        if self.header.binary {
            let end = self.pos.checked_add(n.checked_mul(8)?)?;
            (end <= self.bytes.len()).then(|| self.pos = end)
        } else {
            for _ in 0..n {
                self.token()?;
            }
            Some(())
        }
    }
}

/// Rejects empty `$Nodes` and `$Elements` sections, on which `mshio` may panic (it computes
/// `count - 1`).
fn precheck_sections(bytes: &[u8], header: &Header) -> Result<(), String> {
    for (tag, what) in [(&b"$Nodes"[..], "nodes"), (&b"$Elements"[..], "elements")] {
        let section = String::from_utf8_lossy(tag);
        for start in section_starts(bytes, tag) {
            let mut r = Reader::new(bytes, start, header);
            let _blocks = r.size_t();
            if r.size_t() == Some(0) {
                return Err(format!(
                    "the file has no {what} (its {section} section is empty; \
                     was the mesh generated?)"
                ));
            }
        }
    }
    Ok(())
}

/// One line from a `mshio` error: its line (ASCII) or byte offset (binary), the problem, and
/// where the parser was (the innermost few of its contexts).
fn describe_parser_error(error: &MshParserError<&[u8]>, bytes: &[u8], binary: bool) -> String {
    use mshio::error::MshParserErrorKind as Kind;
    let mut message = "malformed MSH file".to_string();
    let mut at_end = false;
    if let Some((rest, _)) = error.backtrace.first() {
        let start = bytes.as_ptr() as usize;
        let at = rest.as_ptr() as usize;
        if at >= start && at <= start + bytes.len() {
            let offset = at - start;
            at_end = bytes[offset..].iter().all(u8::is_ascii_whitespace);
            if binary {
                message += &format!(" at byte {offset}");
            } else {
                let line = 1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count();
                message += &format!(" at line {line}");
            }
        }
    }
    // A file whose last section has no `$End...` line is cut.
    at_end |= bytes
        .rsplit(|&b| b == b'\n')
        .map(<[u8]>::trim_ascii_start)
        .find(|line| line.starts_with(b"$"))
        .is_some_and(|line| !line.starts_with(b"$End"));
    let backtrace = error.filtered_backtrace();
    let problem = backtrace
        .iter()
        .map(|(_, kind)| kind)
        .find(|kind| kind.context().is_none());
    message += ": ";
    match problem {
        _ if at_end => message += "the file ends too early (is it truncated?)",
        Some(Kind::UnsupportedMshVersion) => message += "unsupported MSH version",
        Some(kind) => {
            let what = kind.to_string();
            let what = what.trim_end_matches('.');
            let mut chars = what.chars();
            if let Some(first) = chars.next() {
                message.extend(first.to_lowercase());
                message.push_str(chars.as_str());
            }
        }
        None => message += "invalid syntax",
    }
    let mut contexts: Vec<&str> = backtrace
        .iter()
        .rev()
        .filter_map(|(_, kind)| kind.context())
        .collect();
    contexts.dedup();
    if !contexts.is_empty() {
        let skip = contexts.len().saturating_sub(4);
        message += " (in ";
        message += &contexts[skip..].join(" > ");
        message += ")";
    }
    if message.chars().count() > 300 {
        message.chars().take(297).collect::<String>() + "..."
    } else {
        message
    }
}

// ---------------------------------------------------------------------------------------------
// Sections mshio does not read

/// The `$PhysicalNames` section: `(dim, tag) -> name`.
fn physical_names(bytes: &[u8]) -> Result<HashMap<(i64, i64), String>, String> {
    let mut names = HashMap::new();
    let Some(start) = section_starts(bytes, b"$PhysicalNames").next() else {
        return Ok(names);
    };
    // The section is text even in binary files; read no further than its end.
    let end_tag = b"$EndPhysicalNames";
    let end = bytes[start..]
        .windows(end_tag.len())
        .position(|w| w == end_tag)
        .map_or(bytes.len(), |i| start + i + end_tag.len());
    let text = String::from_utf8_lossy(&bytes[start..end]);
    let mut lines = text.lines();
    let bad = |line: &str| {
        let shown: String = line.trim().chars().take(60).collect();
        format!("malformed $PhysicalNames section at '{shown}'")
    };
    let first = lines.next().unwrap_or("");
    let count: usize = first.trim().parse().map_err(|_| bad(first))?;
    for _ in 0..count {
        let line = lines.next().ok_or_else(|| bad("(end of file)"))?;
        let mut fields = line.split_whitespace();
        let dim = fields.next().and_then(|s| s.parse::<i64>().ok());
        let tag = fields.next().and_then(|s| s.parse::<i64>().ok());
        let (Some(dim), Some(tag)) = (dim, tag) else {
            return Err(bad(line));
        };
        let (Some(open), Some(close)) = (line.find('"'), line.rfind('"')) else {
            return Err(bad(line));
        };
        if close <= open {
            return Err(bad(line));
        }
        names.insert((dim, tag), line[open + 1..close].to_string());
    }
    match lines.next() {
        Some(l) if l.trim() == "$EndPhysicalNames" => Ok(names),
        Some(l) => Err(bad(l)),
        None => Err(bad("(end of file)")),
    }
}

/// The tags of the nodes of every node block, read from the `$Nodes` section whose structure
/// matches what `mshio` parsed.
fn node_tags(
    bytes: &[u8],
    header: &Header,
    nodes: &mshio::Nodes<u64, i32, f64>,
) -> Result<Vec<Vec<u64>>, String> {
    let read_at = |start: usize| -> Option<Vec<Vec<u64>>> {
        let mut r = Reader::new(bytes, start, header);
        let blocks = r.size_t()?;
        let count = r.size_t()?;
        let min = r.size_t()?;
        let max = r.size_t()?;
        if blocks != nodes.node_blocks.len() as u64
            || (count, min, max) != (nodes.num_nodes, nodes.min_node_tag, nodes.max_node_tag)
        {
            return None;
        }
        let mut tags = Vec::with_capacity(nodes.node_blocks.len());
        for block in &nodes.node_blocks {
            let dim = r.int()?;
            let entity = r.int()?;
            let parametric = r.int()?;
            let n = r.size_t()?;
            if (dim, entity, parametric, n)
                != (
                    block.entity_dim.into(),
                    block.entity_tag.into(),
                    0,
                    block.nodes.len() as u64,
                )
            {
                return None;
            }
            let block_tags = (0..n).map(|_| r.size_t()).collect::<Option<Vec<u64>>>()?;
            if let Some(map) = &block.node_tags {
                // mshio kept the (sparse) tags: they must agree.
                if block_tags
                    .iter()
                    .enumerate()
                    .any(|(i, t)| map.get(t) != Some(&i))
                {
                    return None;
                }
            }
            r.skip_doubles(3 * block.nodes.len())?;
            tags.push(block_tags);
        }
        Some(tags)
    };
    section_starts(bytes, b"$Nodes")
        .find_map(read_at)
        .ok_or_else(|| "malformed $Nodes section (cannot read the node tags)".to_string())
}

// ---------------------------------------------------------------------------------------------
// Conversion

fn build(
    msh: &MshFile<u64, i32, f64>,
    names: &HashMap<(i64, i64), String>,
    bytes: &[u8],
    header: &Header,
) -> Result<Mesh, String> {
    let nodes = msh
        .data
        .nodes
        .as_ref()
        .ok_or("the file has no $Nodes section")?;
    let elements = msh
        .data
        .elements
        .as_ref()
        .ok_or("the file has no $Elements section")?;

    // Nodes, in file order.
    let tags = node_tags(bytes, header, nodes)?;
    let count = nodes.node_blocks.iter().map(|b| b.nodes.len()).sum();
    let mut index: HashMap<u64, usize> = HashMap::with_capacity(count);
    let mut coords = Vec::with_capacity(count);
    let mut point_nodes: HashMap<i32, Vec<usize>> = HashMap::new();
    for (block, block_tags) in nodes.node_blocks.iter().zip(&tags) {
        for (node, &tag) in block.nodes.iter().zip(block_tags) {
            let a = coords.len();
            if index.insert(tag, a).is_some() {
                return Err(format!("node tag {tag} is defined twice in $Nodes"));
            }
            coords.push([node.x, node.y, node.z]);
            if block.entity_dim == 0 {
                point_nodes.entry(block.entity_tag).or_default().push(a);
            }
        }
    }

    // The dimension of each element block, and of the mesh.
    let blocks: Vec<_> = elements
        .element_blocks
        .iter()
        .filter(|b| !b.elements.is_empty())
        .map(|b| {
            let t = b.element_type as i32;
            (b, t, type_info(t).1.unwrap_or(b.entity_dim))
        })
        .collect();
    let dim = mesh_dim(blocks.iter().map(|&(_, t, d)| (t, d)))?;
    check_types(blocks.iter().map(|&(_, t, d)| (t, d)), dim)?;

    // Every element, as node indices.
    let convert = |element: &mshio::Element<u64>| -> Result<Vec<usize>, String> {
        element
            .nodes
            .iter()
            .map(|tag| {
                index.get(tag).copied().ok_or_else(|| {
                    format!(
                        "element {} refers to node {tag}, which is not in $Nodes",
                        element.element_tag
                    )
                })
            })
            .collect()
    };
    let mut converted = Vec::with_capacity(blocks.len());
    for &(block, _, _) in &blocks {
        let list = block
            .elements
            .iter()
            .map(convert)
            .collect::<Result<Vec<_>, _>>()?;
        converted.push(list);
    }

    let mut body = Vec::new();
    for (&(_, t, d), list) in blocks.iter().zip(&converted) {
        if d == dim {
            let kind = body_kind(t, d).expect("checked above");
            body.extend(list.iter().map(|nodes| Element {
                kind,
                nodes: nodes.clone(),
            }));
        }
    }

    if dim == 2 {
        flatten(&mut coords)?;
    }
    let groups = physical_groups(msh, names, dim, &blocks, &converted, &point_nodes);
    Mesh::new(dim as usize, coords, body, groups).map_err(|e| format!("invalid mesh: {e}"))
}

/// A 2D mesh's nodes: planar in z, then set to z = 0.
fn flatten(coords: &mut [[f64; 3]]) -> Result<(), String> {
    let z0 = coords.first().map_or(0.0, |x| x[2]);
    let scale = coords
        .iter()
        .flat_map(|x| [x[0].abs(), x[1].abs()])
        .fold(1.0_f64, f64::max);
    if let Some(x) = coords.iter().find(|x| (x[2] - z0).abs() > 1e-9 * scale) {
        return Err(format!(
            "2D mesh is not planar in z (nodes at z = {z0} and z = {})",
            x[2]
        ));
    }
    for x in coords.iter_mut() {
        x[2] = 0.0;
    }
    Ok(())
}

/// The physical groups of dimension up to `dim`, ordered by dimension then tag.
fn physical_groups(
    msh: &MshFile<u64, i32, f64>,
    names: &HashMap<(i64, i64), String>,
    dim: i32,
    blocks: &[(&mshio::ElementBlock<u64, i32>, i32, i32)],
    converted: &[Vec<Vec<usize>>],
    point_nodes: &HashMap<i32, Vec<usize>>,
) -> Vec<Group> {
    // (dim, entity tag) -> physical tags
    let mut physicals: HashMap<(i32, i32), &[i32]> = HashMap::new();
    if let Some(entities) = &msh.data.entities {
        for p in &entities.points {
            physicals.insert((0, p.tag), &p.physical_tags);
        }
        for c in &entities.curves {
            physicals.insert((1, c.tag), &c.physical_tags);
        }
        for s in &entities.surfaces {
            physicals.insert((2, s.tag), &s.physical_tags);
        }
        for v in &entities.volumes {
            physicals.insert((3, v.tag), &v.physical_tags);
        }
    }
    let mut groups: BTreeMap<(i32, i32), Vec<Vec<usize>>> = BTreeMap::new();
    for (&(d, _), tags) in &physicals {
        if d > dim {
            continue;
        }
        for &p in tags.iter() {
            groups.entry((d, p.abs())).or_default();
        }
    }
    // Elements, in file order.
    let mut points_with_elements = Vec::new();
    for (&(block, _, d), list) in blocks.iter().zip(converted) {
        let Some(tags) = physicals.get(&(d, block.entity_tag)) else {
            continue;
        };
        if d == 0 {
            points_with_elements.push(block.entity_tag);
        }
        for &p in tags.iter() {
            if let Some(group) = groups.get_mut(&(d, p.abs())) {
                group.extend(list.iter().cloned());
            }
        }
    }
    // Point entities without a point element: their node.
    let mut points: Vec<_> = physicals.keys().filter(|k| k.0 == 0).collect();
    points.sort();
    for &(_, tag) in points {
        if points_with_elements.contains(&tag) {
            continue;
        }
        let Some(nodes) = point_nodes.get(&tag) else {
            continue;
        };
        for &p in physicals[&(0, tag)] {
            if let Some(group) = groups.get_mut(&(0, p.abs())) {
                group.extend(nodes.iter().map(|&a| vec![a]));
            }
        }
    }
    groups
        .into_iter()
        .map(|((d, p), entities)| Group {
            name: names
                .get(&(d.into(), p.into()))
                .cloned()
                .unwrap_or_else(|| format!("{d}:{p}")),
            dim: d as usize,
            entities,
        })
        .collect()
}

#[cfg(test)]
mod tests;
mod types;
use types::{body_kind, check_types, mesh_dim, type_info, unsupported};
#[cfg(test)]
mod tests_order2;
#[cfg(test)]
mod tests_v2;
mod v2;
