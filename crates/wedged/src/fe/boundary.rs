//! Boundary conditions by group: contact candidates with their local frames, clamps, rollers.
//!
//! Rules (each a decision a user can look up):
//! - A **contact** group is a boundary group: edges (2D) or faces (3D) of body elements, or
//!   points if `normal` is given. A node's inward normal is the area-weighted mean of the inward
//!   normals of the group facets around it (so corners get the average of their faces), unless
//!   one of its contact groups prescribes `normal`: then it is the normalised sum of the
//!   prescribed normals of its groups.
//! - **Tangents.** 2D: `t = (-n_y, n_x)`, the normal turned a quarter counterclockwise.
//!   3D: `t1` is the coordinate axis least aligned with `n` (the first such axis on a tie),
//!   made orthogonal to `n` and normalised; `t2 = n x t1`. So `(n, t1, t2)` is right-handed.
//! - A **clamp** fixes every displacement of its nodes. A node both in contact and clamped is
//!   clamped (a clamped node can neither separate nor slide); [`Boundary::clamped_contact`] says
//!   how many there were.
//! - A **symmetry** group is a roller: the displacement along the group's normal (prescribed, or
//!   the area-weighted facet normal at the node) is zero. A node on two symmetry planes loses
//!   both directions. A contact node cannot also be a roller: that is an error (model the full
//!   body, or move the symmetry plane).
//! - Contact nodes are numbered in increasing mesh-node order.

use super::{FeError, Group, Mesh};
use std::collections::BTreeMap;

/// A contact group, optionally with a prescribed inward normal.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSpec {
    /// The group's name.
    pub group: String,
    /// A prescribed inward normal of the body (need not be unit).
    pub normal: Option<[f64; 3]>,
}

/// The boundary conditions, by group name.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BoundarySpec {
    /// Contact candidate groups.
    pub contact: Vec<ContactSpec>,
    /// Zero-displacement groups.
    pub clamp: Vec<String>,
    /// Zero-normal-displacement (roller) groups, with an optional normal.
    pub symmetry: Vec<(String, Option<[f64; 3]>)>,
}

/// A contact node's local frame: the unit inward normal of the body `n` and the tangents
/// (2D: `t1` only, `t2 = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Unit inward normal (from the obstacle into the body).
    pub n: [f64; 3],
    /// First unit tangent.
    pub t1: [f64; 3],
    /// Second unit tangent (3D), zero in 2D.
    pub t2: [f64; 3],
}

impl Frame {
    /// The frame's axes in WP order: `n, t1, t2` (use the first `dim`).
    pub fn axes(&self) -> [[f64; 3]; 3] {
        [self.n, self.t1, self.t2]
    }

    /// A local vector (`dim` components, normal first) in global coordinates.
    pub fn to_global(&self, local: &[f64]) -> [f64; 3] {
        let mut g = [0.0; 3];
        let axes = [self.n, self.t1, self.t2];
        for (c, &v) in local.iter().enumerate() {
            for k in 0..3 {
                g[k] += v * axes[c][k];
            }
        }
        g
    }

    /// A global vector in local components (`dim` of them, normal first).
    pub fn to_local(&self, global: &[f64; 3], dim: usize) -> Vec<f64> {
        [self.n, self.t1, self.t2][..dim]
            .iter()
            .map(|a| dot(a, global))
            .collect()
    }
}

/// The resolved boundary conditions of a mesh.
#[derive(Debug, Clone)]
pub struct Boundary {
    /// Mesh node of each contact node, in WP order.
    pub contact_nodes: Vec<usize>,
    /// Local frame of each contact node.
    pub frames: Vec<Frame>,
    /// The contact groups' facets (edges in 2D, faces in 3D), for drawing the obstacle.
    pub contact_facets: Vec<Vec<usize>>,
    /// Clamped mesh nodes.
    pub clamped: Vec<usize>,
    /// Roller nodes with their constrained unit directions.
    pub rollers: Vec<(usize, Vec<[f64; 3]>)>,
    /// How many nodes of contact groups were clamped, and so are not contact nodes.
    pub clamped_contact: usize,
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: &[f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn scaled(a: &[f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn add_to(acc: &mut [f64; 3], a: &[f64; 3]) {
    for k in 0..3 {
        acc[k] += a[k];
    }
}

/// The right-handed frame of a unit inward normal, by the rules in the module documentation.
pub fn frame_of_normal(n: [f64; 3], dim: usize) -> Frame {
    if dim == 2 {
        return Frame {
            n,
            t1: [-n[1], n[0], 0.0],
            t2: [0.0; 3],
        };
    }
    let mut axis = 0;
    for k in 1..3 {
        if n[k].abs() < n[axis].abs() {
            axis = k;
        }
    }
    let mut e = [0.0; 3];
    e[axis] = 1.0;
    let d = dot(&e, &n);
    let t = [e[0] - d * n[0], e[1] - d * n[1], e[2] - d * n[2]];
    let t1 = scaled(&t, 1.0 / norm(&t));
    let t2 = cross(&n, &t1);
    Frame { n, t1, t2 }
}

/// Element adjacency of the nodes, for finding the element behind a facet.
struct Adjacency {
    elements_of_node: Vec<Vec<usize>>,
}

impl Adjacency {
    fn new(mesh: &Mesh) -> Adjacency {
        let mut elements_of_node = vec![Vec::new(); mesh.node_count()];
        for (e, element) in mesh.elements().iter().enumerate() {
            for &a in &element.nodes {
                elements_of_node[a].push(e);
            }
        }
        Adjacency { elements_of_node }
    }

    /// An element having every node of `facet`.
    fn element_with(&self, mesh: &Mesh, facet: &[usize]) -> Option<usize> {
        self.elements_of_node[facet[0]]
            .iter()
            .copied()
            .find(|&e| facet.iter().all(|a| mesh.elements()[e].nodes.contains(a)))
    }
}

fn centroid(mesh: &Mesh, nodes: &[usize]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &a in nodes {
        add_to(&mut c, &mesh.coords()[a]);
    }
    scaled(&c, 1.0 / nodes.len() as f64)
}

/// The normal of a facet weighted by its length (2D) or area (3D), pointing into the element
/// behind it, or `None` if no element has all of its nodes.
fn inward_facet_normal(mesh: &Mesh, adjacency: &Adjacency, facet: &[usize]) -> Option<[f64; 3]> {
    let e = adjacency.element_with(mesh, facet)?;
    // A second-order facet's normal from its corners (its first nodes): the straight facet.
    let corners = &facet[..super::facet_corners(mesh.dim(), facet.len())];
    let x: Vec<[f64; 3]> = corners.iter().map(|&a| mesh.coords()[a]).collect();
    let raw = if mesh.dim() == 2 {
        // Perpendicular to the edge, |raw| = length.
        let d = [x[1][0] - x[0][0], x[1][1] - x[0][1], 0.0];
        [-d[1], d[0], 0.0]
    } else {
        // Newell's method: |raw| = area for a planar polygon.
        let mut nrm = [0.0; 3];
        for a in 0..x.len() {
            let (p, q) = (x[a], x[(a + 1) % x.len()]);
            nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
            nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
            nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
        }
        scaled(&nrm, 0.5)
    };
    let inside = centroid(mesh, &mesh.elements()[e].nodes);
    let here = centroid(mesh, corners);
    let towards = [
        inside[0] - here[0],
        inside[1] - here[1],
        inside[2] - here[2],
    ];
    Some(if dot(&raw, &towards) < 0.0 {
        scaled(&raw, -1.0)
    } else {
        raw
    })
}

fn find_group<'m>(mesh: &'m Mesh, role: &'static str, name: &str) -> Result<&'m Group, FeError> {
    mesh.group(name).ok_or_else(|| FeError::UnknownGroup {
        role,
        name: name.to_string(),
        available: mesh.group_names(),
    })
}

fn unit(v: [f64; 3], what: impl FnOnce() -> String) -> Result<[f64; 3], FeError> {
    let l = norm(&v);
    if !(l.is_finite() && l > 0.0) {
        return Err(FeError::InvalidBoundary(what()));
    }
    Ok(scaled(&v, 1.0 / l))
}

/// Per-node area-weighted inward normals of a boundary group's facets.
fn group_normals(
    mesh: &Mesh,
    adjacency: &Adjacency,
    role: &'static str,
    group: &Group,
) -> Result<BTreeMap<usize, [f64; 3]>, FeError> {
    let facet_dim = mesh.dim() - 1;
    if group.dim != facet_dim {
        return Err(FeError::InvalidBoundary(format!(
            "{role} group '{}' is a group of {}D entities; its normal can only be computed for a \
             group of {} (give `normal = [...]` to use its nodes)",
            group.name,
            group.dim,
            if facet_dim == 1 { "edges" } else { "faces" }
        )));
    }
    let mut normals: BTreeMap<usize, [f64; 3]> = BTreeMap::new();
    for facet in &group.entities {
        let ok = matches!(
            (mesh.dim(), facet.len()),
            (2, 2) | (2, 3) | (3, 3) | (3, 4) | (3, 6)
        );
        if !ok {
            return Err(FeError::InvalidBoundary(format!(
                "{role} group '{}' has a facet with {} nodes",
                group.name,
                facet.len()
            )));
        }
        let normal = inward_facet_normal(mesh, adjacency, facet).ok_or_else(|| {
            FeError::InvalidBoundary(format!(
                "{role} group '{}' has a facet (nodes {}) that is not a side of any element",
                group.name,
                facet
                    .iter()
                    .map(|a| (a + 1).to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
        for &a in facet {
            add_to(normals.entry(a).or_insert([0.0; 3]), &normal);
        }
    }
    Ok(normals)
}

fn check_on_body(
    used: &[bool],
    role: &'static str,
    group: &Group,
    dim: usize,
) -> Result<(), FeError> {
    match group.nodes().into_iter().find(|&a| !used[a]) {
        Some(a) => Err(FeError::GroupNodeNotOnBody {
            role,
            name: group.name.clone(),
            node: a + 1,
            dim,
        }),
        None => Ok(()),
    }
}

fn given_normal(dim: usize, v: [f64; 3], what: &str) -> Result<[f64; 3], FeError> {
    if v.iter().any(|x| !x.is_finite()) || (dim == 2 && v[2] != 0.0) {
        return Err(FeError::InvalidBoundary(format!(
            "the normal of {what} must be finite{}",
            if dim == 2 { " with z = 0 in 2D" } else { "" }
        )));
    }
    unit(v, || format!("the normal of {what} is the zero vector"))
}

impl Boundary {
    /// Resolves the boundary specification against the mesh.
    pub fn new(mesh: &Mesh, spec: &BoundarySpec) -> Result<Boundary, FeError> {
        let dim = mesh.dim();
        if spec.contact.is_empty() {
            return Err(FeError::InvalidBoundary(
                "no contact group is given: add a [[contact]] group".to_string(),
            ));
        }
        let used = mesh.used_nodes();
        let adjacency = Adjacency::new(mesh);

        // Clamps.
        let mut clamped = vec![false; mesh.node_count()];
        for name in &spec.clamp {
            let group = find_group(mesh, "clamp", name)?;
            check_on_body(&used, "clamp", group, dim)?;
            for a in group.nodes() {
                clamped[a] = true;
            }
        }

        // Contact normals.
        let mut computed: BTreeMap<usize, [f64; 3]> = BTreeMap::new();
        let mut prescribed: BTreeMap<usize, [f64; 3]> = BTreeMap::new();
        let mut contact_facets = Vec::new();
        let mut contact_group_of: BTreeMap<usize, String> = BTreeMap::new();
        for c in &spec.contact {
            let group = find_group(mesh, "contact", &c.group)?;
            check_on_body(&used, "contact", group, dim)?;
            if group.dim == dim {
                return Err(FeError::InvalidBoundary(format!(
                    "contact group '{}' is a group of {dim}D elements, not of boundary {}",
                    group.name,
                    if dim == 2 { "edges" } else { "faces" }
                )));
            }
            if group.dim == dim - 1 {
                contact_facets.extend(group.entities.iter().cloned());
            }
            match c.normal {
                Some(v) => {
                    let n = given_normal(dim, v, &format!("contact group '{}'", c.group))?;
                    for a in group.nodes() {
                        add_to(prescribed.entry(a).or_insert([0.0; 3]), &n);
                    }
                }
                None => {
                    for (a, n) in group_normals(mesh, &adjacency, "contact", group)? {
                        add_to(computed.entry(a).or_insert([0.0; 3]), &n);
                    }
                }
            }
            for a in group.nodes() {
                contact_group_of.entry(a).or_insert_with(|| c.group.clone());
            }
        }

        // Rollers.
        let mut roller_dirs: BTreeMap<usize, Vec<[f64; 3]>> = BTreeMap::new();
        for (name, normal) in &spec.symmetry {
            let group = find_group(mesh, "symmetry", name)?;
            check_on_body(&used, "symmetry", group, dim)?;
            let per_node: Vec<(usize, [f64; 3])> = match normal {
                Some(v) => {
                    let n = given_normal(dim, *v, &format!("symmetry group '{name}'"))?;
                    group.nodes().into_iter().map(|a| (a, n)).collect()
                }
                None => group_normals(mesh, &adjacency, "symmetry", group)?
                    .into_iter()
                    .map(|(a, n)| {
                        let n = unit(n, || {
                            format!("symmetry group '{name}' has no normal at node {}", a + 1)
                        })?;
                        Ok((a, n))
                    })
                    .collect::<Result<_, FeError>>()?,
            };
            for (a, n) in per_node {
                if clamped[a] {
                    continue;
                }
                if let Some(contact) = contact_group_of.get(&a) {
                    return Err(FeError::InvalidBoundary(format!(
                        "node {} is both a contact node (group '{contact}') and on symmetry \
                         group '{name}'; a contact node cannot also be a roller: model the \
                         full body or move the symmetry plane",
                        a + 1
                    )));
                }
                roller_dirs.entry(a).or_default().push(n);
            }
        }

        // Contact nodes and frames.
        let mut contact_nodes = Vec::new();
        let mut frames = Vec::new();
        let mut clamped_contact = 0;
        for (&a, group) in &contact_group_of {
            if clamped[a] {
                clamped_contact += 1;
                continue;
            }
            let v = match prescribed.get(&a) {
                Some(v) => *v,
                None => computed.get(&a).copied().unwrap_or([0.0; 3]),
            };
            let n = unit(v, || {
                format!(
                    "the inward normal of contact node {} (group '{group}') is undefined: its \
                     facets' normals cancel out; give `normal = [...]`",
                    a + 1
                )
            })?;
            contact_nodes.push(a);
            frames.push(frame_of_normal(n, dim));
        }
        if contact_nodes.is_empty() {
            return Err(FeError::InvalidBoundary(
                "every node of the contact groups is clamped: there is no contact node left"
                    .to_string(),
            ));
        }

        // Orthonormalise roller directions (Gram-Schmidt, dropping dependent ones).
        let rollers = roller_dirs
            .into_iter()
            .map(|(a, dirs)| {
                let mut basis: Vec<[f64; 3]> = Vec::new();
                for d in dirs {
                    let mut v = d;
                    for b in &basis {
                        let p = dot(&v, b);
                        v = [v[0] - p * b[0], v[1] - p * b[1], v[2] - p * b[2]];
                    }
                    let l = norm(&v);
                    if l > 1e-6 {
                        basis.push(scaled(&v, 1.0 / l));
                    }
                }
                (a, basis)
            })
            .collect();

        Ok(Boundary {
            contact_nodes,
            frames,
            contact_facets,
            clamped: (0..mesh.node_count()).filter(|&a| clamped[a]).collect(),
            rollers,
            clamped_contact,
        })
    }
}
