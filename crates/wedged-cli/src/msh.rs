//! Reader of Gmsh meshes in the MSH 4.1 format, ASCII or binary (either byte order).
//!
//! The file is parsed by the `mshio` crate, completed by what `mshio` leaves out:
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
//!   belong to a physical group: 3-node triangles and 4-node quadrangles in 2D, 4-node
//!   tetrahedra and 8-node hexahedra in 3D (any other element type is an error);
//! - its nodes are all nodes of the file, in file order (Gmsh tags may be sparse and in any
//!   order); in 2D the z coordinates must all be equal, and are set to 0;
//! - its groups are the physical groups, ordered by dimension then tag, each with the elements
//!   of the entities that carry it: points (1-node elements, or the point entity's node),
//!   2-node lines, triangle or quadrangle faces (3D), body elements. A group without a name in
//!   `$PhysicalNames` is named `<dim>:<tag>`, e.g. `1:7`.
//!
//! Gmsh saves only the elements that belong to a physical group unless `Mesh.SaveAll = 1`, so
//! the body needs a physical surface (2D) or volume (3D) when the boundary has physical groups.

use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::path::Path;

use mshio::{MshFile, MshParserError};
use wedged::fe::{Element, ElementKind, Group, Mesh};

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

/// Reads a Gmsh MSH 4.1 file (ASCII or binary).
pub fn read(path: &Path) -> Result<Mesh, MshError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| MshError::new(&name, format!("cannot read the file: {e}")))?;
    parse(&bytes, &name)
}

/// Parses the contents of a Gmsh MSH 4.1 file (ASCII or binary); `name` is used in messages.
pub fn parse(bytes: &[u8], name: &str) -> Result<Mesh, MshError> {
    parse_inner(bytes).map_err(|message| MshError::new(name, message))
}

fn parse_inner(bytes: &[u8]) -> Result<Mesh, String> {
    let header = Header::read(bytes)?;
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
    binary: bool,
    size_t: usize,
    big_endian: bool,
}

impl Header {
    /// Checks the `$MeshFormat` section: version 4.1, file type 0 or 1, a usable `size_t` size
    /// and, in binary files, a recognisable byte order.
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
        if version.parse::<f64>().map_err(|_| invalid())? != 4.1 {
            return Err(format!(
                "MSH {version} is not supported; save as MSH 4.1 (gmsh -format msh41)"
            ));
        }
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
// Element types

/// Gmsh's name and dimension of an element type.
fn type_info(t: i32) -> (&'static str, Option<i32>) {
    match t {
        1 => ("2-node line", Some(1)),
        2 => ("3-node triangle", Some(2)),
        3 => ("4-node quadrangle", Some(2)),
        4 => ("4-node tetrahedron", Some(3)),
        5 => ("8-node hexahedron", Some(3)),
        6 => ("6-node prism", Some(3)),
        7 => ("5-node pyramid", Some(3)),
        8 => ("3-node second-order line", Some(1)),
        9 => ("6-node second-order triangle", Some(2)),
        10 => ("9-node second-order quadrangle", Some(2)),
        11 => ("10-node second-order tetrahedron", Some(3)),
        12 => ("27-node second-order hexahedron", Some(3)),
        13 => ("18-node second-order prism", Some(3)),
        14 => ("14-node second-order pyramid", Some(3)),
        15 => ("1-node point", Some(0)),
        16 => ("8-node second-order quadrangle", Some(2)),
        17 => ("20-node second-order hexahedron", Some(3)),
        18 => ("15-node second-order prism", Some(3)),
        19 => ("13-node second-order pyramid", Some(3)),
        20 => ("9-node third-order incomplete triangle", Some(2)),
        21 => ("10-node third-order triangle", Some(2)),
        22 => ("12-node fourth-order incomplete triangle", Some(2)),
        23 => ("15-node fourth-order triangle", Some(2)),
        24 => ("15-node fifth-order incomplete triangle", Some(2)),
        25 => ("21-node fifth-order triangle", Some(2)),
        26 => ("4-node third-order line", Some(1)),
        27 => ("5-node fourth-order line", Some(1)),
        28 => ("6-node fifth-order line", Some(1)),
        29 => ("20-node third-order tetrahedron", Some(3)),
        30 => ("35-node fourth-order tetrahedron", Some(3)),
        31 => ("56-node fifth-order tetrahedron", Some(3)),
        92 => ("64-node third-order hexahedron", Some(3)),
        93 => ("125-node fourth-order hexahedron", Some(3)),
        _ => ("higher-order or special element", None),
    }
}

/// The error for an element type this reader does not take.
fn unsupported(t: i32, mesh_dim: i32) -> String {
    let (name, _) = type_info(t);
    let hint = if matches!(t, 1..=7 | 15) {
        if mesh_dim == 3 {
            "3D bodies must be meshed with 4-node tetrahedra or 8-node hexahedra"
        } else {
            "2D bodies must be meshed with 3-node triangles or 4-node quadrangles"
        }
    } else {
        "use first-order elements (Mesh.ElementOrder = 1)"
    };
    format!("element type {t} ({name}) is not supported; {hint}")
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
    let dim = blocks.iter().map(|&(_, _, d)| d).max().unwrap_or(-1);
    if dim < 2 {
        return Err(
            "the file has no 2D or 3D elements; Gmsh saves only the elements of physical \
             groups: add a physical surface (2D) or volume (3D) for the body, or set \
             Mesh.SaveAll = 1"
                .to_string(),
        );
    }
    if dim > 3 {
        return Err(format!("the file has elements of dimension {dim}"));
    }
    // Body blocks first, so that a second-order mesh is reported by its body element type.
    for &(_, t, d) in blocks.iter().filter(|b| b.2 == dim) {
        body_kind(t, d).ok_or_else(|| unsupported(t, dim))?;
    }
    for &(_, t, d) in blocks.iter().filter(|b| b.2 != dim) {
        let ok = match d {
            0 => t == 15,
            1 => t == 1,
            2 => t == 2 || t == 3,
            _ => false,
        };
        if !ok {
            return Err(unsupported(t, dim));
        }
    }

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

    // 2D meshes: planar in z, then z = 0.
    if dim == 2 {
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
        for x in &mut coords {
            x[2] = 0.0;
        }
    }

    let groups = physical_groups(msh, names, dim, &blocks, &converted, &point_nodes);
    Mesh::new(dim as usize, coords, body, groups).map_err(|e| format!("invalid mesh: {e}"))
}

/// The body element kind of Gmsh type `t` in a `dim`-dimensional block.
fn body_kind(t: i32, dim: i32) -> Option<ElementKind> {
    match (dim, t) {
        (2, 2) => Some(ElementKind::Tri3),
        (2, 3) => Some(ElementKind::Quad4),
        (3, 4) => Some(ElementKind::Tet4),
        (3, 5) => Some(ElementKind::Hex8),
        _ => None,
    }
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
mod tests {
    use super::*;

    fn fixture(name: &str) -> std::path::PathBuf {
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/msh")).join(name)
    }

    fn load(name: &str) -> Mesh {
        read(&fixture(name)).unwrap_or_else(|e| panic!("{e}"))
    }

    fn group<'a>(mesh: &'a Mesh, name: &str) -> &'a Group {
        mesh.group(name)
            .unwrap_or_else(|| panic!("no group '{name}' in {}", mesh.group_names()))
    }

    /// The Gmsh-written plug and the generator's plug (same nodes, other numbering) condense to
    /// the same `K`, up to the order of the contact nodes.
    #[test]
    fn gmsh_plug_condenses_like_the_generated_one() {
        use wedged::fe::generate::Plug2d;
        use wedged::fe::{BoundarySpec, ContactSpec, Material, Model, Plane};
        let spec = BoundarySpec {
            contact: vec![ContactSpec {
                group: "contact".into(),
                normal: None,
            }],
            clamp: vec!["top".into()],
            symmetry: vec![],
        };
        let material = Material::new(210e9, 0.3, Plane::Strain).unwrap();
        let generated = Plug2d {
            bottom_width: 1.0,
            top_width: 2.0,
            height: 1.0,
            nx: 6,
            ny: 4,
            simplices: false,
        }
        .mesh()
        .unwrap();
        let a = Model::build(generated, material, &spec).unwrap();
        for file in ["plug2d_quad.msh", "plug2d_quad_bin.msh"] {
            let b = Model::build(load(file), material, &spec).unwrap();
            let (ba, bb) = (a.boundary(), b.boundary());
            assert_eq!(ba.contact_nodes.len(), bb.contact_nodes.len());
            // Contact node i of `a` is node perm[i] of `b`: the one at the same place.
            let perm: Vec<usize> = ba
                .contact_nodes
                .iter()
                .map(|&p| {
                    let x = a.mesh().coords()[p];
                    bb.contact_nodes
                        .iter()
                        .position(|&q| {
                            let y = b.mesh().coords()[q];
                            (x[0] - y[0]).abs() < 1e-9 && (x[1] - y[1]).abs() < 1e-9
                        })
                        .expect("the same contact nodes")
                })
                .collect();
            let (ka, kb) = (a.k(), b.k());
            let scale = ka.amax();
            for (i, &pi) in perm.iter().enumerate() {
                assert!((ba.frames[i].n[0] - bb.frames[pi].n[0]).abs() < 1e-9);
                for (j, &pj) in perm.iter().enumerate() {
                    for c in 0..2 {
                        for d in 0..2 {
                            let (x, y) = (ka[(2 * i + c, 2 * j + d)], kb[(2 * pi + c, 2 * pj + d)]);
                            assert!(
                                (x - y).abs() <= 1e-9 * scale,
                                "{file}: K differs: {x} vs {y}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// The one-line message for `bytes` parsed as a file called `name`, which must fail.
    fn error(bytes: &[u8], name: &str) -> String {
        let e = parse(bytes, name).expect_err("the file should be rejected");
        let shown = e.to_string();
        assert!(shown.starts_with(&format!("{name}: ")), "{shown}");
        assert!(!shown.contains('\n'), "{shown}");
        assert_eq!(e.file, name);
        assert_eq!(shown, format!("{name}: {}", e.message));
        shown
    }

    fn fixture_error(name: &str) -> String {
        let path = fixture(name);
        let e = read(&path).expect_err("the fixture should be rejected");
        let shown = e.to_string();
        assert!(shown.starts_with(&path.display().to_string()), "{shown}");
        assert!(shown.contains(name), "{shown}");
        assert!(!shown.contains('\n'), "{shown}");
        shown
    }

    /// (name, dim, entities, distinct nodes) of every group.
    fn counts(mesh: &Mesh) -> Vec<(String, usize, usize, usize)> {
        mesh.groups()
            .iter()
            .map(|g| (g.name.clone(), g.dim, g.entities.len(), g.nodes().len()))
            .collect()
    }

    fn owned(list: &[(&str, usize, usize, usize)]) -> Vec<(String, usize, usize, usize)> {
        list.iter()
            .map(|&(n, d, e, v)| (n.to_string(), d, e, v))
            .collect()
    }

    fn body_as_group(mesh: &Mesh) -> Vec<Vec<usize>> {
        mesh.elements().iter().map(|e| e.nodes.clone()).collect()
    }

    // --- Gmsh fixtures -------------------------------------------------------------------------

    #[test]
    fn plug2d_quad_counts() {
        let mesh = load("plug2d_quad.msh");
        assert_eq!(mesh.dim(), 2);
        assert_eq!(mesh.node_count(), 35);
        assert_eq!(mesh.elements().len(), 24);
        assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Quad4));
        assert_eq!(
            counts(&mesh),
            owned(&[
                ("bottom", 1, 6, 7),
                ("top", 1, 6, 7),
                ("left", 1, 4, 5),
                ("right", 1, 4, 5),
                ("contact", 1, 8, 10),
                ("body", 2, 24, 35),
            ])
        );
        assert_eq!(group(&mesh, "body").entities, body_as_group(&mesh));
        assert!(group(&mesh, "contact")
            .entities
            .iter()
            .all(|e| e.len() == 2));
    }

    #[test]
    fn plug2d_quad_nodes_follow_the_bilinear_map() {
        let mesh = load("plug2d_quad.msh");
        let mut expected = Vec::new();
        for j in 0..=4 {
            let y = j as f64 / 4.0;
            let w = (1.0 + y) / 2.0;
            for i in 0..=6 {
                expected.push([-w + 2.0 * w * i as f64 / 6.0, y]);
            }
        }
        let mut matched = vec![false; expected.len()];
        for x in mesh.coords() {
            assert_eq!(x[2], 0.0);
            let k = expected
                .iter()
                .position(|e| (e[0] - x[0]).abs() < 1e-9 && (e[1] - x[1]).abs() < 1e-9)
                .unwrap_or_else(|| panic!("node {x:?} is not on the grid"));
            assert!(!matched[k], "two nodes at {x:?}");
            matched[k] = true;
        }
        assert!(matched.iter().all(|&m| m));
        // The contact nodes are those of the slanted sides, |x| = w(y).
        for &a in &group(&mesh, "contact").nodes() {
            let [x, y, _] = mesh.coords()[a];
            assert!((x.abs() - (1.0 + y) / 2.0).abs() < 1e-9, "({x}, {y})");
        }
        // Quadrilaterals are counterclockwise.
        for e in mesh.elements() {
            let p = mesh.element_coords(e);
            let area2: f64 = (0..4)
                .map(|k| p[k][0] * p[(k + 1) % 4][1] - p[(k + 1) % 4][0] * p[k][1])
                .sum();
            assert!((area2 / 2.0 - 1.5 / 24.0).abs() < 0.05, "{area2}");
        }
    }

    #[test]
    fn binary_and_ascii_give_the_same_mesh() {
        let ascii = load("plug2d_quad.msh");
        let binary = load("plug2d_quad_bin.msh");
        assert_eq!(ascii.dim(), binary.dim());
        // The ASCII file has 16 significant digits: the last bit may differ.
        assert_eq!(ascii.node_count(), binary.node_count());
        for (a, b) in ascii.coords().iter().zip(binary.coords()) {
            for k in 0..3 {
                assert!((a[k] - b[k]).abs() <= 1e-15, "{a:?} vs {b:?}");
            }
        }
        assert_eq!(ascii.elements(), binary.elements());
        assert_eq!(ascii.groups(), binary.groups());
    }

    #[test]
    fn plug2d_tri_counts() {
        // Counts as reported by Gmsh itself for this file.
        let mesh = load("plug2d_tri.msh");
        assert_eq!(mesh.dim(), 2);
        assert_eq!(mesh.node_count(), 44);
        assert_eq!(mesh.elements().len(), 64);
        assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Tri3));
        assert_eq!(
            counts(&mesh),
            owned(&[
                ("bottom", 1, 4, 5),
                ("top", 1, 8, 9),
                ("left", 1, 5, 6),
                ("right", 1, 5, 6),
                ("contact", 1, 10, 12),
                ("body", 2, 64, 44),
            ])
        );
        assert_eq!(group(&mesh, "body").entities, body_as_group(&mesh));
    }

    #[test]
    fn box3d_tet_counts() {
        // Counts as reported by Gmsh itself for this file.
        let mesh = load("box3d_tet.msh");
        assert_eq!(mesh.dim(), 3);
        assert_eq!(mesh.node_count(), 45);
        assert_eq!(mesh.elements().len(), 100);
        assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Tet4));
        assert_eq!(
            counts(&mesh),
            owned(&[
                ("bottom", 2, 14, 12),
                ("top", 2, 14, 12),
                ("sides", 2, 56, 36),
                ("body", 3, 100, 45),
            ])
        );
        assert!(group(&mesh, "sides").entities.iter().all(|e| e.len() == 3));
        for &a in &group(&mesh, "bottom").nodes() {
            assert_eq!(mesh.coords()[a][2], 0.0);
        }
        for &a in &group(&mesh, "top").nodes() {
            assert_eq!(mesh.coords()[a][2], 1.0);
        }
    }

    #[test]
    fn box3d_hex_counts() {
        let mesh = load("box3d_hex.msh");
        assert_eq!(mesh.dim(), 3);
        assert_eq!(mesh.node_count(), 27);
        assert_eq!(mesh.elements().len(), 8);
        assert!(mesh.elements().iter().all(|e| e.kind == ElementKind::Hex8));
        assert_eq!(
            counts(&mesh),
            owned(&[
                ("bottom", 2, 4, 9),
                ("top", 2, 4, 9),
                ("sides", 2, 16, 24),
                ("body", 3, 8, 27),
            ])
        );
        assert!(group(&mesh, "sides").entities.iter().all(|e| e.len() == 4));
    }

    #[test]
    fn fixture_errors() {
        let e = fixture_error("second_order.msh");
        assert!(
            e.contains(
                "element type 9 (6-node second-order triangle) is not supported; \
                 use first-order elements (Mesh.ElementOrder = 1)"
            ),
            "{e}"
        );
        let e = fixture_error("msh22.msh");
        assert!(
            e.contains("MSH 2.2 is not supported; save as MSH 4.1 (gmsh -format msh41)"),
            "{e}"
        );
        let e = fixture_error("truncated.msh");
        assert!(
            e.contains("malformed MSH file at line 78: the file ends too early"),
            "{e}"
        );
        let e = fixture_error("garbage.msh");
        assert!(e.contains("not a Gmsh MSH file"), "{e}");
        let e = fixture_error("does_not_exist.msh");
        assert!(e.contains("cannot read the file"), "{e}");
    }

    /// No prefix and no single-byte corruption of a fixture makes the reader panic, and the
    /// MSH parser never panics on them either.
    #[test]
    fn damaged_files_do_not_panic() {
        for name in ["plug2d_quad.msh", "plug2d_quad_bin.msh", "box3d_hex.msh"] {
            let bytes = std::fs::read(fixture(name)).unwrap();
            let check = |data: &[u8]| {
                if let Err(e) = parse(data, name) {
                    let shown = e.to_string();
                    assert!(!shown.contains('\n'), "{shown}");
                    assert!(!shown.contains("the MSH parser failed"), "{shown}");
                }
            };
            for cut in 0..bytes.len() {
                check(&bytes[..cut]);
            }
            let mut data = bytes.clone();
            for k in 0..bytes.len() {
                for b in [0u8, 0xff, b'9', b' '] {
                    data[k] = b;
                    check(&data);
                }
                data[k] = bytes[k];
            }
        }
    }

    // --- Hand-made files ------------------------------------------------------------------------

    /// Two triangles on the unit square, nodes tagged `t` = [(0,0), (1,0), (1,1), (0,1)] (in
    /// three node blocks, in that order), a line on the bottom, a physical point at the origin
    /// (no point element), no `$PhysicalNames`.
    fn square(t: [u64; 4]) -> String {
        let min = t.iter().min().unwrap();
        let max = t.iter().max().unwrap();
        format!(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
             $Entities\n2 1 1 0\n1 0 0 0 1 5\n2 1 0 0 0\n\
             1 0 0 0 1 0 0 1 3 2 1 -2\n1 0 0 0 1 1 0 1 7 0\n$EndEntities\n\
             $Nodes\n3 4 {min} {max}\n\
             0 1 0 1\n{a}\n0 0 0\n\
             0 2 0 1\n{b}\n1 0 0\n\
             2 1 0 2\n{c}\n{d}\n1 1 0\n0 1 0\n$EndNodes\n\
             $Elements\n2 3 5 9\n\
             1 1 1 1\n5 {a} {b}\n\
             2 1 2 2\n9 {a} {b} {c}\n7 {a} {c} {d}\n$EndElements\n",
            a = t[0],
            b = t[1],
            c = t[2],
            d = t[3],
        )
    }

    fn check_square(mesh: &Mesh) {
        assert_eq!(mesh.dim(), 2);
        assert_eq!(
            mesh.coords(),
            [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.0]
            ]
        );
        assert_eq!(body_as_group(mesh), [vec![0, 1, 2], vec![0, 2, 3]]);
        assert_eq!(
            mesh.groups(),
            [
                Group {
                    name: "0:5".into(),
                    dim: 0,
                    entities: vec![vec![0]],
                },
                Group {
                    name: "1:3".into(),
                    dim: 1,
                    entities: vec![vec![0, 1]],
                },
                Group {
                    name: "2:7".into(),
                    dim: 2,
                    entities: vec![vec![0, 1, 2], vec![0, 2, 3]],
                },
            ]
        );
    }

    #[test]
    fn node_tags_sparse_or_permuted() {
        for tags in [[1, 2, 3, 4], [10, 30, 40, 20], [2, 4, 1, 3], [4, 3, 2, 1]] {
            let text = square(tags);
            let mesh = parse(text.as_bytes(), "square.msh").unwrap_or_else(|e| panic!("{e}"));
            check_square(&mesh);
        }
    }

    #[test]
    fn physical_names_and_point_elements() {
        let text = square([1, 2, 3, 4]).replace(
            "$Entities",
            "$PhysicalNames\n3\n0 5 \"origin\"\n1 3 \"the bottom\"\n2 7 \"body\"\n\
             $EndPhysicalNames\n$Entities",
        );
        let mesh = parse(text.as_bytes(), "square.msh").unwrap();
        let names: Vec<_> = mesh.groups().iter().map(|g| g.name.as_str()).collect();
        assert_eq!(names, ["origin", "the bottom", "body"]);
        // A point element, rather than the point entity's node (here, oddly, another node).
        let text = text.replace(
            "$Elements\n2 3 5 9\n",
            "$Elements\n3 4 5 10\n0 1 15 1\n10 2\n",
        );
        let mesh = parse(text.as_bytes(), "square.msh").unwrap();
        assert_eq!(group(&mesh, "origin").entities, [vec![1]]);
    }

    #[test]
    fn no_entities_means_no_groups() {
        let text = square([1, 2, 3, 4]);
        let start = text.find("$Entities").unwrap();
        let end = text.find("$Nodes").unwrap();
        let text = format!("{}{}", &text[..start], &text[end..]);
        let mesh = parse(text.as_bytes(), "square.msh").unwrap();
        assert_eq!(mesh.elements().len(), 2);
        assert!(mesh.groups().is_empty());
    }

    #[test]
    fn planarity_in_z() {
        // Changes the z coordinates of the nodes only.
        let with_z = |z: [&str; 4]| {
            let text = square([1, 2, 3, 4]);
            let (head, nodes) = text.split_at(text.find("$Nodes").unwrap());
            let nodes = nodes
                .replace("0 0 0\n", &format!("0 0 {}\n", z[0]))
                .replace("1 0 0\n", &format!("1 0 {}\n", z[1]))
                .replace("1 1 0\n", &format!("1 1 {}\n", z[2]))
                .replace("0 1 0\n", &format!("0 1 {}\n", z[3]));
            format!("{head}{nodes}")
        };
        let text = with_z(["0", "0", "0.5", "0"]);
        let e = error(text.as_bytes(), "bent.msh");
        assert!(e.contains("2D mesh is not planar in z"), "{e}");
        let text = with_z(["5", "5", "5", "5"]);
        assert!(text.contains("1 1 5\n"));
        let mesh = parse(text.as_bytes(), "lifted.msh").unwrap();
        check_square(&mesh);
    }

    #[test]
    fn content_errors() {
        let text = square([1, 2, 3, 4]).replace("7 1 3 4\n", "7 1 3 99\n");
        let e = error(text.as_bytes(), "holes.msh");
        assert!(e.contains("element 7 refers to node 99"), "{e}");

        let text = square([1, 2, 3, 4]).replace("1 2\n2 1 2 2\n9 1 2 3\n7 1 3 4\n", "1 2\n");
        let text = text.replace("$Elements\n2 3 5 9\n", "$Elements\n1 1 5 5\n");
        let e = error(text.as_bytes(), "lines.msh");
        assert!(e.contains("no 2D or 3D elements"), "{e}");
        assert!(e.contains("Mesh.SaveAll = 1"), "{e}");

        let text = square([1, 2, 3, 4]).replace("2 1 0 2\n3\n4\n", "2 1 0 2\n3\n2\n");
        let e = error(text.as_bytes(), "twice.msh");
        assert!(e.contains("node tag 2 is defined twice"), "{e}");

        let start = square([1, 2, 3, 4]).find("$Nodes").unwrap();
        let text = format!(
            "{}$Nodes\n0 0 1 1\n$EndNodes\n",
            &square([1, 2, 3, 4])[..start]
        );
        let e = error(text.as_bytes(), "empty.msh");
        assert!(e.contains("the file has no nodes"), "{e}");

        let text = square([1, 2, 3, 4]).replace(
            "$Entities",
            "$PhysicalNames\n2\n1 3 \"x\"\n2 7 \"x\"\n$EndPhysicalNames\n$Entities",
        );
        let e = error(text.as_bytes(), "dup.msh");
        assert!(e.contains("two groups are named 'x'"), "{e}");

        let text = square([1, 2, 3, 4]).replace(
            "$Entities",
            "$PhysicalNames\n2\n1 3 x\n$EndPhysicalNames\n$Entities",
        );
        let e = error(text.as_bytes(), "names.msh");
        assert!(e.contains("malformed $PhysicalNames section"), "{e}");

        // A prism in a 3D mesh.
        let prism = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 6 1 6\n3 1 0 6\n\
                     1\n2\n3\n4\n5\n6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 1\n0 1 1\n$EndNodes\n\
                     $Elements\n1 1 1 1\n3 1 6 1\n1 1 2 3 4 5 6\n$EndElements\n";
        let e = error(prism.as_bytes(), "prism.msh");
        assert!(
            e.contains("element type 6 (6-node prism) is not supported; 3D bodies must be"),
            "{e}"
        );
        // The same nodes as a tetrahedron and a 3-node line (second order) in a group.
        let tet = prism
            .replace("3 1 6 1\n1 1 2 3 4 5 6\n", "3 1 4 1\n1 1 2 3 4\n")
            .replace(
                "$Elements\n1 1 1 1\n",
                "$Elements\n2 2 1 2\n1 1 8 1\n2 1 2 3\n",
            );
        let e = error(tet.as_bytes(), "tet.msh");
        assert!(
            e.contains("element type 8 (3-node second-order line) is not supported"),
            "{e}"
        );
    }

    #[test]
    fn header_errors() {
        let cases: [(&[u8], &str); 9] = [
            (b"", "the file is empty"),
            (b"hello\n", "not a Gmsh MSH file"),
            (b"\x00\x01\x02\xff\xfe", "not a Gmsh MSH file"),
            (
                b"$MeshFormat\n4 0 8\n$EndMeshFormat\n",
                "MSH 4 is not supported",
            ),
            (
                b"$MeshFormat\n4.0 1 8\n$EndMeshFormat\n",
                "MSH 4.0 is not supported",
            ),
            (
                b"$MeshFormat\n4.1 2 8\n$EndMeshFormat\n",
                "invalid $MeshFormat header",
            ),
            (
                b"$MeshFormat\n4.1 0 99999999999\n",
                "invalid $MeshFormat header",
            ),
            (b"$MeshFormat\n4.1 1 3\n", "3-byte size_t are not supported"),
            (b"$MeshFormat\n4.1 1 8\n\x02\x00\x00\x00\n", "byte order"),
        ];
        for (bytes, expected) in cases {
            let e = error(bytes, "h.msh");
            assert!(e.contains(expected), "{e}");
        }
        let e = error(
            b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2",
            "cut.msh",
        );
        assert!(e.contains("malformed MSH file"), "{e}");
    }

    /// A binary MSH 4.1 file of `square([3, 1, 4, 2])` with `$PhysicalNames`, in either byte
    /// order.
    fn binary_square(big_endian: bool) -> Vec<u8> {
        let mut out = Vec::new();
        let size_t = |out: &mut Vec<u8>, v: u64| {
            out.extend(if big_endian {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            })
        };
        let int = |out: &mut Vec<u8>, v: i32| {
            out.extend(if big_endian {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            })
        };
        let double = |out: &mut Vec<u8>, v: f64| {
            out.extend(if big_endian {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            })
        };
        out.extend(b"$MeshFormat\n4.1 1 8\n");
        int(&mut out, 1);
        out.extend(b"\n$EndMeshFormat\n");
        out.extend(b"$PhysicalNames\n2\n1 3 \"bottom\"\n2 7 \"body\"\n$EndPhysicalNames\n");
        out.extend(b"$Entities\n");
        for n in [2, 1, 1, 0] {
            size_t(&mut out, n);
        }
        // Points 1 (physical 5) and 2.
        for (tag, x, physical) in [(1, 0.0, Some(5)), (2, 1.0, None)] {
            int(&mut out, tag);
            for v in [x, 0.0, 0.0] {
                double(&mut out, v);
            }
            size_t(&mut out, physical.iter().count() as u64);
            for &p in physical.iter() {
                int(&mut out, p);
            }
        }
        // Curve 1 (physical 3) from point 1 to 2; surface 1 (physical 7).
        for (physical, bounds) in [(3, vec![1, -2]), (7, vec![])] {
            int(&mut out, 1);
            for v in [0.0, 0.0, 0.0, 1.0, 1.0, 0.0] {
                double(&mut out, v);
            }
            size_t(&mut out, 1);
            int(&mut out, physical);
            size_t(&mut out, bounds.len() as u64);
            for b in bounds {
                int(&mut out, b);
            }
        }
        out.extend(b"\n$EndEntities\n$Nodes\n");
        for n in [3, 4, 1, 4] {
            size_t(&mut out, n);
        }
        type NodeBlock<'a> = (i32, i32, &'a [(u64, [f64; 3])]);
        let blocks: [NodeBlock; 3] = [
            (0, 1, &[(3, [0.0, 0.0, 0.0])]),
            (0, 2, &[(1, [1.0, 0.0, 0.0])]),
            (2, 1, &[(4, [1.0, 1.0, 0.0]), (2, [0.0, 1.0, 0.0])]),
        ];
        for (dim, tag, nodes) in blocks {
            int(&mut out, dim);
            int(&mut out, tag);
            int(&mut out, 0);
            size_t(&mut out, nodes.len() as u64);
            for (t, _) in nodes {
                size_t(&mut out, *t);
            }
            for (_, x) in nodes {
                for &v in x {
                    double(&mut out, v);
                }
            }
        }
        out.extend(b"\n$EndNodes\n$Elements\n");
        for n in [2, 3, 5, 9] {
            size_t(&mut out, n);
        }
        let blocks: [(i32, i32, &[&[u64]]); 2] = [
            (1, 1, &[&[5, 3, 1]]),
            (2, 2, &[&[9, 3, 1, 4], &[7, 3, 4, 2]]),
        ];
        for (dim, t, elements) in blocks {
            int(&mut out, dim);
            int(&mut out, 1);
            int(&mut out, t);
            size_t(&mut out, elements.len() as u64);
            for element in elements {
                for &v in element.iter() {
                    size_t(&mut out, v);
                }
            }
        }
        out.extend(b"\n$EndElements\n");
        out
    }

    #[test]
    fn binary_either_byte_order() {
        let text = square([3, 1, 4, 2]).replace(
            "$Entities",
            "$PhysicalNames\n2\n1 3 \"bottom\"\n2 7 \"body\"\n$EndPhysicalNames\n$Entities",
        );
        let ascii = parse(text.as_bytes(), "a.msh").unwrap();
        for big_endian in [false, true] {
            let mesh = parse(&binary_square(big_endian), "b.msh").unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(mesh.coords(), ascii.coords());
            assert_eq!(mesh.elements(), ascii.elements());
            assert_eq!(mesh.groups(), ascii.groups());
        }
        let names: Vec<_> = ascii.groups().iter().map(|g| g.name.as_str()).collect();
        assert_eq!(names, ["0:5", "bottom", "body"]);
    }
}
