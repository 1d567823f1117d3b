//! Condensation onto the contact nodes (a Schur complement with a sparse Cholesky factor), and
//! recovery of the full fields from a contact displacement.
//!
//! Each used mesh node gets a basis of the displacements it may take: its local frame
//! `(n, t1[, t2])` at a contact node (these are the WP's unknowns, in WP order), nothing at a
//! clamped node, the plane orthogonal to the constrained directions at a roller, the coordinate
//! axes elsewhere. With `T` the block-diagonal matrix of these bases, the reduced stiffness is
//! `T^T K T`, assembled element by element. Splitting its unknowns into contact (`c`) and other
//! (`o`) ones,
//!
//! ```text
//! K_wp = K_cc - K_oc^T K_oo^{-1} K_oc          (dense, dim*m x dim*m)
//! u_o  = -K_oo^{-1} K_oc u_c                    (recovery)
//! ```
//!
//! `K_oo` is factorised once by faer's sparse Cholesky (fill-reducing ordering inside);
//! `K_oo^{-1} K_oc` is formed a block of columns at a time and never stored whole, and no dense
//! inverse is ever formed. The factor is kept for recovery.

use super::boundary::{Boundary, BoundarySpec};
use super::{element, material::von_mises, FeError, Material, Mesh};
use crate::problem::{Problem, ProblemError};
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::time::Instant;

/// Columns of `K_oc` solved for at once.
const SOLVE_BLOCK: usize = 64;

/// One state of the body mapped back to the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Configuration {
    /// Displacement of every mesh node, global frame (`z = 0` in 2D).
    pub displacement: Vec<[f64; 3]>,
    /// Nodal force `K u` of every mesh node, global frame: the reaction at contact, clamped and
    /// roller nodes, zero (to round-off) elsewhere.
    pub force: Vec<[f64; 3]>,
    /// Stress at each element's centroid, Voigt `[xx, yy, zz, yz, xz, xy]`.
    pub stress: Vec<[f64; 6]>,
    /// Von Mises stress at each element's centroid.
    pub von_mises: Vec<f64>,
}

impl Configuration {
    /// The mean of states of the same model: displacements, forces and stresses are linear in
    /// the contact displacement, so this is the state of the mean contact displacement; von
    /// Mises (not linear) is recomputed from the mean stress.
    pub fn mean(states: &[&Configuration]) -> Configuration {
        let w = 1.0 / states.len().max(1) as f64;
        fn average<const N: usize>(fields: Vec<&[[f64; N]]>, w: f64) -> Vec<[f64; N]> {
            let len = fields.first().map_or(0, |f| f.len());
            (0..len)
                .map(|i| {
                    let mut v = [0.0; N];
                    for f in &fields {
                        for (k, x) in f[i].iter().enumerate() {
                            v[k] += w * x;
                        }
                    }
                    v
                })
                .collect()
        }
        let displacement = average(states.iter().map(|s| &s.displacement[..]).collect(), w);
        let force = average(states.iter().map(|s| &s.force[..]).collect(), w);
        let stress = average(states.iter().map(|s| &s.stress[..]).collect(), w);
        let von_mises = stress.iter().map(von_mises).collect();
        Configuration {
            displacement,
            force,
            stress,
            von_mises,
        }
    }
}

/// Sizes and timings of a condensation.
#[derive(Debug, Clone, PartialEq)]
pub struct Condensed {
    /// Degrees of freedom of the mesh (`dim` per used node).
    pub dofs: usize,
    /// Unknowns eliminated (the `o` block).
    pub eliminated: usize,
    /// Contact nodes `m`.
    pub contact_nodes: usize,
    /// Nonzeros of the lower triangle of `K_oo`.
    pub nnz_oo: usize,
    /// Seconds spent on element matrices and assembly.
    pub seconds_assembly: f64,
    /// Seconds spent on the sparse Cholesky factorisation.
    pub seconds_factor: f64,
    /// Seconds spent on the Schur complement.
    pub seconds_schur: f64,
}

/// Where a mesh node's reduced unknowns live.
#[derive(Debug, Clone)]
enum NodeDofs {
    /// Not in any element, or clamped: no unknowns.
    Fixed,
    /// Contact node `i`: unknowns `dim*i ..` of `u_c`, along its frame.
    Contact(usize),
    /// Unknowns `first .. first + basis.len()` of `u_o`, along `basis` (global vectors);
    /// `identity` if `basis` is the coordinate axes.
    Other {
        first: usize,
        basis: Vec<[f64; 3]>,
        identity: bool,
    },
}

/// A meshed body with its boundary conditions, condensed onto its contact nodes.
pub struct Model {
    mesh: Mesh,
    material: Material,
    boundary: Boundary,
    nodes: Vec<NodeDofs>,
    eliminated: usize,
    factor: Option<faer::sparse::linalg::solvers::Llt<usize, f64>>,
    k_oc: SparseColMat<usize, f64>,
    k: DMatrix<f64>,
    /// The rigid motions that no clamp or roller stops, at the contact nodes in their frames
    /// (no columns when the body is held).
    rigid: DMatrix<f64>,
    stats: Condensed,
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model")
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

/// A reduced unknown: contact (`c`) or other (`o`).
#[derive(Debug, Clone, Copy)]
enum Dof {
    C(usize),
    O(usize),
}

impl Model {
    /// Resolves the boundary, assembles, factorises and condenses.
    pub fn build(mesh: Mesh, material: Material, spec: &BoundarySpec) -> Result<Model, FeError> {
        let boundary = Boundary::new(&mesh, spec)?;
        Model::with_boundary(mesh, material, boundary)
    }

    /// As [`Model::build`], with the boundary already resolved.
    pub fn with_boundary(
        mesh: Mesh,
        material: Material,
        boundary: Boundary,
    ) -> Result<Model, FeError> {
        let dim = mesh.dim();
        let t0 = Instant::now();
        let used = mesh.used_nodes();
        let mut nodes = vec![NodeDofs::Fixed; mesh.node_count()];
        let identity: Vec<[f64; 3]> = (0..dim)
            .map(|k| {
                let mut e = [0.0; 3];
                e[k] = 1.0;
                e
            })
            .collect();
        for (a, slot) in nodes.iter_mut().enumerate() {
            if used[a] {
                *slot = NodeDofs::Other {
                    first: 0,
                    basis: identity.clone(),
                    identity: true,
                };
            }
        }
        for &a in &boundary.clamped {
            nodes[a] = NodeDofs::Fixed;
        }
        for (a, dirs) in &boundary.rollers {
            nodes[*a] = NodeDofs::Other {
                first: 0,
                basis: complement(dirs, dim),
                identity: false,
            };
        }
        for (i, &a) in boundary.contact_nodes.iter().enumerate() {
            nodes[a] = NodeDofs::Contact(i);
        }
        let mut eliminated = 0;
        for slot in nodes.iter_mut() {
            if let NodeDofs::Other { first, basis, .. } = slot {
                *first = eliminated;
                eliminated += basis.len();
            }
        }
        check_held(&mesh, &nodes)?;
        let rigid = free_rigid_modes(&mesh, &boundary)?;
        let m = boundary.contact_nodes.len();
        let nc = dim * m;

        // Element matrices in reduced unknowns, in parallel; scattered into triplets.
        let chunks: Vec<Result<Scatter, FeError>> = mesh
            .elements()
            .par_chunks(2048)
            .enumerate()
            .map(|(chunk, elements)| {
                let mut s = Scatter::default();
                for (k, e) in elements.iter().enumerate() {
                    let index = chunk * 2048 + k;
                    let x = mesh.element_coords(e);
                    let ke = element::stiffness(e.kind, &x, &material).map_err(|detail| {
                        FeError::DegenerateElement {
                            element: index + 1,
                            kind: e.kind.name(),
                            detail,
                        }
                    })?;
                    let (t, dofs) = element_transform(&nodes, &e.nodes, dim, &boundary);
                    let kr = match &t {
                        Some(t) => t.transpose() * &ke * t,
                        None => ke,
                    };
                    for (p, &dp) in dofs.iter().enumerate() {
                        for (q, &dq) in dofs.iter().enumerate() {
                            let v = kr[(p, q)];
                            match (dp, dq) {
                                (Dof::O(i), Dof::O(j)) if i >= j => {
                                    s.oo.push(Triplet::new(i, j, v))
                                }
                                (Dof::O(i), Dof::C(j)) => s.oc.push(Triplet::new(i, j, v)),
                                (Dof::C(i), Dof::C(j)) => s.cc.push((i, j, v)),
                                _ => {}
                            }
                        }
                    }
                }
                Ok(s)
            })
            .collect();
        let mut oo = Vec::new();
        let mut oc = Vec::new();
        let mut k = DMatrix::zeros(nc, nc);
        for chunk in chunks {
            let s = chunk?;
            oo.extend(s.oo);
            oc.extend(s.oc);
            for (i, j, v) in s.cc {
                k[(i, j)] += v;
            }
        }
        let oom = |_| FeError::OutOfMemory(eliminated);
        let k_oc =
            SparseColMat::<usize, f64>::try_new_from_triplets(eliminated, nc, &oc).map_err(oom)?;
        drop(oc);
        let seconds_assembly = t0.elapsed().as_secs_f64();

        let t1 = Instant::now();
        let (factor, nnz_oo) = if eliminated > 0 {
            let k_oo =
                SparseColMat::<usize, f64>::try_new_from_triplets(eliminated, eliminated, &oo)
                    .map_err(oom)?;
            drop(oo);
            let nnz = k_oo.compute_nnz();
            let factor = k_oo.sp_cholesky(Side::Lower).map_err(|e| match e {
                faer::sparse::linalg::LltError::Numeric(_) => FeError::NotHeld(
                    "a pivot of the Cholesky factorisation is not positive".to_string(),
                ),
                faer::sparse::linalg::LltError::Generic(_) => FeError::OutOfMemory(eliminated),
            })?;
            (Some(factor), nnz)
        } else {
            (None, 0)
        };
        let seconds_factor = t1.elapsed().as_secs_f64();

        // K -= K_oc^T K_oo^{-1} K_oc, a block of columns at a time, the blocks on the threads
        // (as many blocks of about equal width as fill the threads evenly). (Measured on the
        // 2D plug with triangles, 2 threads, `wedged condense`: the Schur complement at m = 100
        // 29.7 -> 14.9 ms, at m = 400 3.23 -> 1.12 s; the same matrix to the last bit, each
        // entry being summed in the same order.)
        let t2 = Instant::now();
        if let Some(factor) = &factor {
            let col_ptr = k_oc.symbolic().col_ptr();
            let row_idx = k_oc.symbolic().row_idx();
            let values = k_oc.val();
            let threads = rayon::current_num_threads().max(1);
            let blocks = nc.div_ceil(SOLVE_BLOCK).div_ceil(threads) * threads;
            let width = nc.div_ceil(blocks.max(1)).max(1);
            let starts: Vec<usize> = (0..nc).step_by(width).collect();
            let parts: Vec<(usize, Vec<Vec<f64>>)> = starts
                .into_par_iter()
                .map(|start| {
                    let width = width.min(nc - start);
                    let mut x = Mat::<f64>::zeros(eliminated, width);
                    for b in 0..width {
                        for p in col_ptr[start + b]..col_ptr[start + b + 1] {
                            x[(row_idx[p], b)] = values[p];
                        }
                    }
                    factor.solve_in_place(x.as_mut());
                    let rows: Vec<Vec<f64>> = (0..nc)
                        .map(|i| {
                            (0..width)
                                .map(|b| {
                                    (col_ptr[i]..col_ptr[i + 1])
                                        .map(|p| values[p] * x[(row_idx[p], b)])
                                        .sum::<f64>()
                                })
                                .collect()
                        })
                        .collect();
                    (start, rows)
                })
                .collect();
            for (start, rows) in parts {
                for (i, row) in rows.iter().enumerate() {
                    for (b, v) in row.iter().enumerate() {
                        k[(i, start + b)] -= v;
                    }
                }
            }
        }
        // Symmetrise away the round-off of the two triangles.
        let k = (&k + k.transpose()) * 0.5;
        let seconds_schur = t2.elapsed().as_secs_f64();

        let stats = Condensed {
            dofs: dim * used.iter().filter(|&&u| u).count(),
            eliminated,
            contact_nodes: m,
            nnz_oo,
            seconds_assembly,
            seconds_factor,
            seconds_schur,
        };
        Ok(Model {
            mesh,
            material,
            boundary,
            nodes,
            eliminated,
            factor,
            k_oc,
            k,
            rigid,
            stats,
        })
    }

    /// The condensed stiffness: the WP's `K` (`dim*m x dim*m`, local frames, normal first).
    pub fn k(&self) -> &DMatrix<f64> {
        &self.k
    }

    /// The wedged problem of this model at friction coefficient `mu`: its condensed stiffness
    /// in the mesh's dimension, and for a floating body (rigid motions that no clamp or roller
    /// stops, [`Model::rigid_modes`]) those motions at the contact nodes
    /// ([`Problem::floating`]). The one `Model -> Problem` conversion; `Err` as
    /// [`Problem::new`] or [`Problem::floating`].
    pub fn problem(&self, mu: f64) -> Result<Problem, ProblemError> {
        if self.rigid.ncols() > 0 {
            Problem::floating(self.mesh.dim(), self.k.clone(), self.rigid.clone(), mu)
        } else {
            Problem::new(self.mesh.dim(), self.k.clone(), mu)
        }
    }

    /// The rigid motions of the body that no clamp or roller stops, at the contact nodes in
    /// their local frames (`dim*m` rows; no columns when the body is held): 3 in 2D and 6 in 3D
    /// for a body with neither, fewer where rollers stop some.
    pub fn rigid_modes(&self) -> &DMatrix<f64> {
        &self.rigid
    }

    /// Sizes and timings.
    pub fn stats(&self) -> &Condensed {
        &self.stats
    }

    /// The mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The resolved boundary conditions.
    pub fn boundary(&self) -> &Boundary {
        &self.boundary
    }

    /// The full displacement of a contact displacement `u_c` (WP order, local frames), without
    /// stresses or forces: `u_o = -K_oo^{-1} K_oc u_c`, mapped to global node displacements.
    pub fn displacement(&self, u_c: &[f64]) -> Vec<[f64; 3]> {
        let dim = self.mesh.dim();
        assert_eq!(u_c.len(), dim * self.boundary.contact_nodes.len());
        let mut u_o = Mat::<f64>::zeros(self.eliminated, 1);
        if let Some(factor) = &self.factor {
            let col_ptr = self.k_oc.symbolic().col_ptr();
            let row_idx = self.k_oc.symbolic().row_idx();
            let values = self.k_oc.val();
            for (j, &uj) in u_c.iter().enumerate() {
                for p in col_ptr[j]..col_ptr[j + 1] {
                    u_o[(row_idx[p], 0)] -= values[p] * uj;
                }
            }
            factor.solve_in_place(u_o.as_mut());
        }
        self.nodes
            .iter()
            .map(|slot| match slot {
                NodeDofs::Fixed => [0.0; 3],
                NodeDofs::Contact(i) => self.boundary.frames[*i].to_global(&u_c[dim * i..][..dim]),
                NodeDofs::Other { first, basis, .. } => {
                    let mut g = [0.0; 3];
                    for (c, axis) in basis.iter().enumerate() {
                        for k in 0..3 {
                            g[k] += u_o[(first + c, 0)] * axis[k];
                        }
                    }
                    g
                }
            })
            .collect()
    }

    /// The full state of a contact displacement `u_c`: displacements, nodal forces `K u` and
    /// element stresses.
    pub fn recover(&self, u_c: &[f64]) -> Configuration {
        let displacement = self.displacement(u_c);
        let dim = self.mesh.dim();
        let per_element: Vec<(Vec<f64>, [f64; 6])> = self
            .mesh
            .elements()
            .par_iter()
            .map(|e| {
                let x = self.mesh.element_coords(e);
                let u: Vec<f64> = e
                    .nodes
                    .iter()
                    .flat_map(|&a| displacement[a][..dim].to_vec())
                    .collect();
                // Elements were checked when the model was built.
                let ke = element::stiffness(e.kind, &x, &self.material)
                    .expect("element checked at assembly");
                let f = (ke * nalgebra::DVector::from_column_slice(&u))
                    .as_slice()
                    .to_vec();
                let s = element::centroid_stress(e.kind, &x, &self.material, &u)
                    .expect("element checked at assembly");
                (f, s)
            })
            .collect();
        let mut force = vec![[0.0; 3]; self.mesh.node_count()];
        let mut stress = Vec::with_capacity(per_element.len());
        for (e, (f, s)) in self.mesh.elements().iter().zip(per_element) {
            for (k, &a) in e.nodes.iter().enumerate() {
                for c in 0..dim {
                    force[a][c] += f[dim * k + c];
                }
            }
            stress.push(s);
        }
        let von_mises = stress.iter().map(von_mises).collect();
        Configuration {
            displacement,
            force,
            stress,
            von_mises,
        }
    }
}

#[derive(Default)]
struct Scatter {
    oo: Vec<Triplet<usize, usize, f64>>,
    oc: Vec<Triplet<usize, usize, f64>>,
    cc: Vec<(usize, usize, f64)>,
}

/// An orthonormal basis of the complement of orthonormal `dirs` in `R^dim`.
fn complement(dirs: &[[f64; 3]], dim: usize) -> Vec<[f64; 3]> {
    let mut basis: Vec<[f64; 3]> = dirs.to_vec();
    let mut free = Vec::new();
    for k in 0..dim {
        let mut v = [0.0; 3];
        v[k] = 1.0;
        for b in &basis {
            let p = v[0] * b[0] + v[1] * b[1] + v[2] * b[2];
            for c in 0..3 {
                v[c] -= p * b[c];
            }
        }
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if l > 1e-6 && basis.len() < dim {
            let v = [v[0] / l, v[1] / l, v[2] / l];
            basis.push(v);
            free.push(v);
        }
    }
    free
}

/// The element's reduced unknowns and the transform from them to its global dofs (`None` when
/// every node is unconstrained with the identity basis, and so the transform is the identity).
fn element_transform(
    nodes: &[NodeDofs],
    element_nodes: &[usize],
    dim: usize,
    boundary: &Boundary,
) -> (Option<DMatrix<f64>>, Vec<Dof>) {
    let mut dofs = Vec::with_capacity(element_nodes.len() * dim);
    let mut plain = true;
    for &a in element_nodes {
        match &nodes[a] {
            NodeDofs::Other {
                identity: true,
                first,
                ..
            } => dofs.extend((0..dim).map(|c| Dof::O(first + c))),
            _ => plain = false,
        }
    }
    if plain {
        return (None, dofs);
    }
    dofs.clear();
    let mut columns: Vec<(usize, [f64; 3])> = Vec::new(); // (element node, global vector)
    for (k, &a) in element_nodes.iter().enumerate() {
        match &nodes[a] {
            NodeDofs::Fixed => {}
            NodeDofs::Contact(i) => {
                let axes = boundary.frames[*i].axes();
                for (c, axis) in axes.iter().take(dim).enumerate() {
                    dofs.push(Dof::C(dim * i + c));
                    columns.push((k, *axis));
                }
            }
            NodeDofs::Other { first, basis, .. } => {
                for (c, axis) in basis.iter().enumerate() {
                    dofs.push(Dof::O(first + c));
                    columns.push((k, *axis));
                }
            }
        }
    }
    let mut t = DMatrix::zeros(element_nodes.len() * dim, columns.len());
    for (col, (k, axis)) in columns.iter().enumerate() {
        for c in 0..dim {
            t[(dim * k + c, col)] = axis[c];
        }
    }
    (Some(t), dofs)
}

/// Every connected piece of the mesh must touch a contact, clamped or roller node, or its
/// rigid motion makes `K_oo` singular. A combinatorial check with a clear message, before a
/// factorisation that might only see tiny pivots.
/// The rigid motions of `mesh` that its clamps and rollers leave free, at the contact nodes in
/// their frames (columns orthonormal in the space of motions, scaled so that rotations about
/// the centroid move the farthest node by about 1). A floating body must be one connected
/// part: several parts could each move on their own, which one body's modes do not describe.
fn free_rigid_modes(mesh: &Mesh, boundary: &Boundary) -> Result<DMatrix<f64>, FeError> {
    let dim = mesh.dim();
    let used = mesh.used_nodes();
    let coords = mesh.coords();
    let count = used.iter().filter(|&&u| u).count().max(1) as f64;
    let mut centre = [0.0; 3];
    for (x, _) in coords.iter().zip(&used).filter(|(_, &u)| u) {
        for k in 0..3 {
            centre[k] += x[k] / count;
        }
    }
    let size = mesh.size().max(f64::MIN_POSITIVE);
    // The candidate motions' velocity at x: translations, then rotations about the centre.
    let modes = if dim == 2 { 3 } else { 6 };
    let motion = |j: usize, x: &[f64; 3]| -> [f64; 3] {
        let mut v = [0.0; 3];
        if j < dim {
            v[j] = 1.0;
            return v;
        }
        let d = [
            (x[0] - centre[0]) / size,
            (x[1] - centre[1]) / size,
            (x[2] - centre[2]) / size,
        ];
        let axis = if dim == 2 { 2 } else { j - dim };
        let mut w = [0.0; 3];
        w[axis] = 1.0;
        [
            w[1] * d[2] - w[2] * d[1],
            w[2] * d[0] - w[0] * d[2],
            w[0] * d[1] - w[1] * d[0],
        ]
    };
    // What the clamps and rollers stop: one row per fixed direction.
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for &a in &boundary.clamped {
        for k in 0..dim {
            rows.push((0..modes).map(|j| motion(j, &coords[a])[k]).collect());
        }
    }
    for (a, dirs) in &boundary.rollers {
        for d in dirs {
            rows.push(
                (0..modes)
                    .map(|j| {
                        let v = motion(j, &coords[*a]);
                        v[0] * d[0] + v[1] * d[1] + v[2] * d[2]
                    })
                    .collect(),
            );
        }
    }
    // The free combinations: the null space of the rows (all motions when there are none).
    let free = if rows.is_empty() {
        DMatrix::identity(modes, modes)
    } else {
        let c = DMatrix::from_fn(rows.len(), modes, |i, j| rows[i][j]);
        let svd = (c.transpose() * &c).symmetric_eigen();
        let top = svd.eigenvalues.max().max(f64::MIN_POSITIVE);
        let keep: Vec<usize> = (0..modes)
            // Singular values below 1e-6 of the largest: free to round-off.
            .filter(|&j| svd.eigenvalues[j] <= 1e-12 * top)
            .collect();
        DMatrix::from_fn(modes, keep.len(), |i, j| svd.eigenvectors[(i, keep[j])])
    };
    let m = boundary.contact_nodes.len();
    if free.ncols() == 0 {
        return Ok(DMatrix::zeros(dim * m, 0));
    }
    if let Some((a, b)) = two_parts(mesh) {
        return Err(FeError::InvalidBoundary(format!(
            "the body floats (nothing clamps it) but the mesh has disconnected parts, one with \
             node {} and another with node {}: a floating body must be one connected part; \
             clamp each part, or mesh them as one",
            a + 1,
            b + 1
        )));
    }
    Ok(DMatrix::from_fn(dim * m, free.ncols(), |row, col| {
        let (i, c) = (row / dim, row % dim);
        let x = &coords[boundary.contact_nodes[i]];
        let axis = boundary.frames[i].axes()[c];
        (0..modes)
            .map(|j| {
                let v = motion(j, x);
                free[(j, col)] * (axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2])
            })
            .sum()
    }))
}

/// The connected part of each node of the mesh: a representative node, the same for every node
/// of a part (union-find over the elements, paths fully compressed).
fn parts(mesh: &Mesh) -> Vec<usize> {
    let n = mesh.node_count();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut a: usize) -> usize {
        while parent[a] != a {
            parent[a] = parent[parent[a]];
            a = parent[a];
        }
        a
    }
    for e in mesh.elements() {
        let r0 = find(&mut parent, e.nodes[0]);
        for &a in &e.nodes[1..] {
            let r = find(&mut parent, a);
            parent[r] = r0;
        }
    }
    (0..n).map(|a| find(&mut parent, a)).collect()
}

/// Two used nodes in different connected parts of the mesh, if it has more than one.
fn two_parts(mesh: &Mesh) -> Option<(usize, usize)> {
    let part = parts(mesh);
    let used = mesh.used_nodes();
    let mut nodes = (0..part.len()).filter(|&a| used[a]);
    let first = nodes.next()?;
    nodes
        .find(|&a| part[a] != part[first])
        .map(|other| (first, other))
}

fn check_held(mesh: &Mesh, nodes: &[NodeDofs]) -> Result<(), FeError> {
    let n = mesh.node_count();
    let part = parts(mesh);
    let mut held = vec![false; n];
    for (a, slot) in nodes.iter().enumerate() {
        // Every node but a free one (axes basis) holds its part: contact, clamped (Fixed),
        // roller. An unused node is Fixed too, but it is alone in its part.
        let anchored = !matches!(slot, NodeDofs::Other { identity: true, .. });
        if anchored {
            held[part[a]] = true;
        }
    }
    let used = mesh.used_nodes();
    if let Some(a) = (0..n).find(|&a| used[a] && !held[part[a]]) {
        return Err(FeError::NotHeld(format!(
            "the part of the mesh containing node {} touches no contact, clamp or symmetry group",
            a + 1
        )));
    }
    Ok(())
}
