//! The wedged problem (WP) in its condensed form: a stiffness `K` on the contact nodes, in local
//! frames, and a friction coefficient `mu`.
//!
//! ```text
//! WP   find u, r in R^{dm}:  K u = r,
//!      u_n >= 0, r_n >= 0, u_n . r_n = 0,   ||r_t_i|| <= mu r_n_i  (i = 1..m)
//! ```
//!
//! Node `i` owns rows `dim*i .. dim*i + dim` of `K`, normal component first (2D `(n, t)`, 3D
//! `(n, t1, t2)`). `u_n >= 0` is a move away from the obstacle; `r_n >= 0` is a push by the
//! obstacle on the body.
//!
//! A [`Problem`] is validated once, when it is built: afterwards `K` is known to be finite,
//! symmetric (it is symmetrised) and positive definite, and its inverse (the compliance) is at hand.

use nalgebra::DMatrix;

/// Relative asymmetry `|K_ij - K_ji| / max|K|` above which `K` is rejected as non-symmetric.
///
/// Matrices written by finite-element codes with 16 significant digits are symmetric far below
/// this; a matrix written with 8 digits still passes. Below it, `K` is replaced by `(K + K^T)/2`.
pub const SYMMETRY_TOLERANCE: f64 = 1e-8;

/// A Cholesky pivot `d_j` with `d_j <= PIVOT_TOLERANCE * K_jj` means `K` is not (numerically)
/// positive definite.
pub const PIVOT_TOLERANCE: f64 = 1e-13;

/// Why a stiffness matrix or friction coefficient was rejected. Row and column numbers in the
/// messages are 1-based, as in Matrix Market files; nodes are 1-based too.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProblemError {
    /// `dim` must be 2 or 3.
    #[error("dimension must be 2 or 3, got {0}")]
    InvalidDim(usize),
    /// `K` has no rows.
    #[error("the stiffness matrix is empty")]
    Empty,
    /// `K` is not square.
    #[error("the stiffness matrix is not square: {rows} rows, {cols} columns")]
    NotSquare { rows: usize, cols: usize },
    /// The size of `K` is not `dim * m`.
    #[error("the stiffness matrix has size {size}, which is not a multiple of dim = {dim}")]
    SizeNotMultiple { size: usize, dim: usize },
    /// An entry of `K` is NaN or infinite.
    #[error("the stiffness matrix has a non-finite entry {value} at row {row}, column {col}")]
    NonFinite { row: usize, col: usize, value: f64 },
    /// `K` is not symmetric within [`SYMMETRY_TOLERANCE`]; the worst entry is named.
    #[error(
        "the stiffness matrix is not symmetric: K[{row},{col}] = {value:e} but K[{col},{row}] = \
         {transpose:e} (relative difference {relative:.2e} > {SYMMETRY_TOLERANCE:e})"
    )]
    NotSymmetric {
        row: usize,
        col: usize,
        value: f64,
        transpose: f64,
        relative: f64,
    },
    /// The Cholesky factorisation of `K` failed at a pivot.
    #[error(
        "the stiffness matrix is not positive definite: Cholesky pivot {pivot} (node {node}, \
         component {component}) is {value:e}; is enough of the body clamped?"
    )]
    NotPositiveDefinite {
        pivot: usize,
        node: usize,
        component: &'static str,
        value: f64,
    },
    /// `mu` is not a finite positive number.
    #[error("the friction coefficient mu must be finite and > 0, got {0}")]
    InvalidMu(f64),
    /// The rigid modes of a floating body do not have `dim * m` rows.
    #[error(
        "the rigid modes have {rows} rows, but the stiffness matrix has {size}: one row per \
         contact degree of freedom, in the same local frames"
    )]
    RigidModesSize { rows: usize, size: usize },
    /// More rigid modes than a body has (3 in 2D, 6 in 3D), or none.
    #[error("a floating body has 1 to {most} rigid modes in {dim}D, got {count}")]
    RigidModesCount {
        count: usize,
        most: usize,
        dim: usize,
    },
    /// A rigid mode has a non-finite entry.
    #[error("the rigid modes have a non-finite entry {value} at row {row}, column {col}")]
    RigidModesNonFinite { row: usize, col: usize, value: f64 },
    /// The rigid modes are linearly dependent.
    #[error(
        "the rigid modes are linearly dependent: mode {mode} is (within {relative:.1e}) a \
         combination of the others"
    )]
    RigidModesDependent { mode: usize, relative: f64 },
    /// `K R != 0`: a declared rigid mode is not in the null space of `K`.
    #[error(
        "rigid mode {mode} is not in the null space of the stiffness: |K R| / (|K| |R|) = \
         {relative:.2e} > {RIGID_TOLERANCE:e} (K[{row}, :] R[:, {mode}] = {value:e})"
    )]
    NotRigid {
        mode: usize,
        row: usize,
        value: f64,
        relative: f64,
    },
    /// `K` is singular beyond the declared rigid modes (or not positive semidefinite).
    #[error(
        "the stiffness matrix is not positive definite off its {modes} rigid modes: pivot {pivot} \
         (node {node}, component {component}) is {value:e}; is a rigid motion missing from the \
         rigid modes, or the stiffness indefinite?"
    )]
    NotDefiniteOffRigid {
        modes: usize,
        pivot: usize,
        node: usize,
        component: &'static str,
        value: f64,
    },
}

/// Relative size `|K R|_max / (|K|_max |R|_max)` (`R` with orthonormal columns) below which a
/// declared rigid mode counts as in the null space of `K`. A stiffness condensed by a finite-element
/// code in double precision meets it by orders of magnitude; one written with 8 significant
/// digits still does.
pub const RIGID_TOLERANCE: f64 = 1e-7;

/// How far, relative to the largest entry of `K`, [`Problem::mirror`] lets mirrored entries
/// differ: round-off of assembling and condensing a mirror mesh in another order (about
/// `1e-15`), far below any physical asymmetry.
pub const MIRROR_TOL: f64 = 1e-10;

/// A validated wedged problem: `dim`, the symmetric positive definite `K` (in local node frames)
/// and `mu`.
#[derive(Debug, Clone)]
pub struct Problem {
    dim: usize,
    k: DMatrix<f64>,
    /// `K^{-1}`, from the Cholesky factor; for a floating body the pseudo-inverse `K^+`.
    compliance: DMatrix<f64>,
    /// A floating body's rigid modes at the contact nodes (`dim*m` rows, one column per free
    /// rigid motion, `K R = 0`); no columns for a clamped body.
    rigid: DMatrix<f64>,
    mu: f64,
}

/// The name of component `c` of a node block in dimension `dim`.
pub fn component_name(dim: usize, c: usize) -> &'static str {
    match (dim, c) {
        (_, 0) => "n",
        (2, _) => "t",
        (_, 1) => "t1",
        _ => "t2",
    }
}

impl Problem {
    /// Validates `K` and `mu` and builds the problem. `K` is symmetrised.
    pub fn new(dim: usize, k: DMatrix<f64>, mu: f64) -> Result<Problem, ProblemError> {
        if dim != 2 && dim != 3 {
            return Err(ProblemError::InvalidDim(dim));
        }
        Problem::check_entries(dim, &k)?;
        check_mu(mu)?;
        let rows = k.nrows();
        let k = (&k + k.transpose()) * 0.5;
        let l = cholesky(&k).map_err(|(pivot, value)| ProblemError::NotPositiveDefinite {
            pivot: pivot + 1,
            node: pivot / dim + 1,
            component: component_name(dim, pivot % dim),
            value,
        })?;
        let compliance = inverse_from_cholesky(&l);
        Ok(Problem {
            dim,
            k,
            compliance,
            rigid: DMatrix::zeros(rows, 0),
            mu,
        })
    }

    /// A floating body: `K` positive semidefinite with null space spanned by the columns of
    /// `rigid` (its free rigid motions at the contact nodes, in the local frames). The wedged
    /// problem of a floating body (README, "Floating bodies"):
    ///
    /// ```text
    /// WP   find u, r:  K u = r,  the sign, complementarity and friction conditions of WP;
    ///      K u = r has a solution only when R^T r = 0 (r does no work on a rigid motion: the
    ///      walls' reactions balance), and then u = K^+ r + R a for any a.
    /// ```
    ///
    /// `K` is checked as in [`Problem::new`]; `rigid` for its size, finiteness and rank, `K R = 0`
    /// relative to [`RIGID_TOLERANCE`], and `K` for definiteness off the modes. `K` is then
    /// projected (`P K P`, `P = I - R R^T` with `R` orthonormalised) so that the modes are its
    /// null space to round-off.
    pub fn floating(
        dim: usize,
        k: DMatrix<f64>,
        rigid: DMatrix<f64>,
        mu: f64,
    ) -> Result<Problem, ProblemError> {
        if dim != 2 && dim != 3 {
            return Err(ProblemError::InvalidDim(dim));
        }
        Problem::check_entries(dim, &k)?;
        check_mu(mu)?;
        let n = k.nrows();
        let most = if dim == 2 { 3 } else { 6 };
        if rigid.nrows() != n {
            return Err(ProblemError::RigidModesSize {
                rows: rigid.nrows(),
                size: n,
            });
        }
        let count = rigid.ncols();
        if count == 0 || count > most {
            return Err(ProblemError::RigidModesCount { count, most, dim });
        }
        for j in 0..count {
            for i in 0..n {
                let v = rigid[(i, j)];
                if !v.is_finite() {
                    return Err(ProblemError::RigidModesNonFinite {
                        row: i + 1,
                        col: j + 1,
                        value: v,
                    });
                }
            }
        }
        let k = (&k + k.transpose()) * 0.5;
        // Orthonormalise the modes (modified Gram-Schmidt, twice), naming a dependent one.
        let mut q = rigid.clone();
        for j in 0..count {
            let size = rigid.column(j).norm();
            for _ in 0..2 {
                for p in 0..j {
                    let dot = q.column(p).dot(&q.column(j));
                    let qp = q.column(p).clone_owned();
                    q.column_mut(j).axpy(-dot, &qp, 1.0);
                }
            }
            let left = q.column(j).norm();
            let relative = if size > 0.0 { left / size } else { 0.0 };
            if relative <= 1e-8 {
                return Err(ProblemError::RigidModesDependent {
                    mode: j + 1,
                    relative,
                });
            }
            q.column_mut(j).scale_mut(1.0 / left);
        }
        let kq = &k * &q;
        let k_max = k.amax().max(f64::MIN_POSITIVE);
        let q_max = q.amax();
        let mut worst: Option<(usize, usize, f64)> = None;
        for j in 0..count {
            for i in 0..n {
                let rel = kq[(i, j)].abs() / (k_max * q_max);
                if rel > RIGID_TOLERANCE && worst.is_none_or(|w| rel > w.2) {
                    worst = Some((i, j, rel));
                }
            }
        }
        if let Some((i, j, relative)) = worst {
            return Err(ProblemError::NotRigid {
                mode: j + 1,
                row: i + 1,
                value: kq[(i, j)],
                relative,
            });
        }
        // P K P with P = I - Q Q^T: the modes exactly (to round-off) in the null space.
        let p = DMatrix::identity(n, n) - &q * q.transpose();
        let k = &p * k * &p;
        let k = (&k + k.transpose()) * 0.5;
        // (K + s Q Q^T)^-1 = K^+ + Q Q^T / s, for s of K's size: definite exactly when K is
        // definite off the modes.
        let s = (0..n).map(|i| k[(i, i)]).fold(0.0f64, f64::max);
        let shifted = &k + &q * q.transpose() * s;
        let l = cholesky(&shifted).map_err(|(pivot, value)| ProblemError::NotDefiniteOffRigid {
            modes: count,
            pivot: pivot + 1,
            node: pivot / dim + 1,
            component: component_name(dim, pivot % dim),
            value,
        })?;
        let inverse = inverse_from_cholesky(&l);
        let compliance = &p * (inverse - &q * q.transpose() / s) * &p;
        let compliance = (&compliance + compliance.transpose()) * 0.5;
        Ok(Problem {
            dim,
            k,
            compliance,
            rigid: q,
            mu,
        })
    }

    /// The checks of `K`'s shape and entries (a floating body's; [`Problem::new`] makes the
    /// same ones in its own order).
    fn check_entries(dim: usize, k: &DMatrix<f64>) -> Result<(), ProblemError> {
        let (rows, cols) = k.shape();
        if rows == 0 || cols == 0 {
            return Err(ProblemError::Empty);
        }
        if rows != cols {
            return Err(ProblemError::NotSquare { rows, cols });
        }
        if rows % dim != 0 {
            return Err(ProblemError::SizeNotMultiple { size: rows, dim });
        }
        for j in 0..cols {
            for i in 0..rows {
                let v = k[(i, j)];
                if !v.is_finite() {
                    return Err(ProblemError::NonFinite {
                        row: i + 1,
                        col: j + 1,
                        value: v,
                    });
                }
            }
        }
        let scale = k.amax();
        let mut worst: Option<(usize, usize, f64)> = None;
        for i in 0..rows {
            for j in (i + 1)..rows {
                let rel = (k[(i, j)] - k[(j, i)]).abs() / scale.max(f64::MIN_POSITIVE);
                if rel > SYMMETRY_TOLERANCE && worst.is_none_or(|w| rel > w.2) {
                    worst = Some((i, j, rel));
                }
            }
        }
        if let Some((i, j, relative)) = worst {
            return Err(ProblemError::NotSymmetric {
                row: i + 1,
                col: j + 1,
                value: k[(i, j)],
                transpose: k[(j, i)],
                relative,
            });
        }
        Ok(())
    }

    /// The point `(r, a)` of a floating body's programs for a solution `(u, r)`: `a` the least
    /// squares solution of `R a = u - G r` (exact for a solution). `r` alone when clamped.
    pub(crate) fn point_of(&self, u: &[f64], r: &[f64]) -> Vec<f64> {
        let n = self.k.nrows();
        let mut x = r[..n].to_vec();
        if self.is_floating() {
            let gr = &self.compliance * nalgebra::DVector::from_column_slice(&x);
            let rhs = nalgebra::DVector::from_fn(n, |i, _| u[i] - gr[i]);
            let svd = self.rigid.clone().svd(true, true);
            if let Ok(a) = svd.solve(&rhs, 1e-12 * svd.singular_values.max()) {
                x.extend(a.iter());
            }
        }
        x
    }

    /// Whether the body floats (has free rigid motions).
    pub fn is_floating(&self) -> bool {
        self.rigid.ncols() > 0
    }

    /// The free rigid motions at the contact nodes, orthonormal columns (none when clamped).
    pub fn rigid_modes(&self) -> &DMatrix<f64> {
        &self.rigid
    }

    /// The same body with another friction coefficient.
    pub fn with_mu(&self, mu: f64) -> Result<Problem, ProblemError> {
        check_mu(mu)?;
        Ok(Problem { mu, ..self.clone() })
    }

    /// Space dimension, 2 or 3.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of contact nodes `m`.
    pub fn nodes(&self) -> usize {
        self.k.nrows() / self.dim
    }

    /// The friction coefficient.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// A 64-bit fingerprint of the problem (FNV-1a over `dim`, `mu`, every entry of `K` and of
    /// the rigid modes, as bits): the shards of one run carry it, so that a merge can tell parts
    /// of different problems apart. Equal problems built alike have equal fingerprints; it is
    /// not a cryptographic hash.
    pub fn fingerprint(&self) -> u64 {
        let words = [self.dim as u64, self.k.nrows() as u64, self.mu.to_bits()]
            .into_iter()
            .chain(self.k.iter().map(|x| x.to_bits()))
            .chain(std::iter::once(self.rigid.ncols() as u64))
            .chain(self.rigid.iter().map(|x| x.to_bits()));
        digest_of(words)
    }

    /// A mirror symmetry of the problem (a body symmetric about a plane, in a symmetric
    /// obstacle): the first of [`Problem::symmetries`], `None` when there is none.
    pub fn mirror(&self) -> Option<Vec<usize>> {
        self.symmetries().into_iter().next()
    }

    /// The symmetries of the problem that map nodes to nodes with their local frames turned
    /// by a sign: involutions `s` of the nodes, not the identity, under which `K` is invariant,
    /// `K[s(i), s(j)] = D K[i, j] D` for every pair of nodes, within [`MIRROR_TOL`] of the
    /// largest entry of `K` (a mirror mesh is assembled in another order, so its `K` is
    /// symmetric to round-off only). `D` keeps the normal and turns tangents: in 2D `D =
    /// diag(1, -1)` (a reflection reverses the tangent); in 3D each of `diag(1, 1, -1)`,
    /// `diag(1, -1, 1)` (reflections, which reverse one tangent of a frame whose other
    /// tangent lies in the mirror plane, as the V-groove plug's frames do for both of its
    /// mirrors) and `diag(1, -1, -1)` (a half turn about an axis in the normals' plane, or the
    /// two mirrors together) is tried, and each that holds gives one involution. A solution's
    /// image (node `s(i)` taking node `i`'s state, its frame turned by `D`) is then a solution
    /// with the same friction ratios. Images are found by the nodes' own blocks (`D K_ii D`);
    /// a `D` under which some node has more than one candidate, or the whole of `K` does not
    /// match, gives none.
    pub fn symmetries(&self) -> Vec<Vec<usize>> {
        self.symmetries_with_signs()
            .into_iter()
            .map(|(s, _)| s)
            .collect()
    }

    /// [`Problem::symmetries`] with each one's sign matrix `D` (its diagonal, `dim` entries):
    /// the image of a solution puts `D` times node `i`'s components at node `s(i)`.
    pub fn symmetries_with_signs(&self) -> Vec<(Vec<usize>, Vec<f64>)> {
        let signs: &[&[f64]] = match self.dim {
            2 => &[&[1.0, -1.0]],
            _ => &[&[1.0, 1.0, -1.0], &[1.0, -1.0, 1.0], &[1.0, -1.0, -1.0]],
        };
        signs
            .iter()
            .filter_map(|sign| Some((self.symmetry(sign)?, sign.to_vec())))
            .collect()
    }

    /// The involution under which `K` is invariant with the frames turned by `diag(sign)`.
    fn symmetry(&self, sign: &[f64]) -> Option<Vec<usize>> {
        let (k, m, d) = (&self.k, self.nodes(), self.dim);
        let tol = MIRROR_TOL * k.amax();
        let same = |a: f64, b: f64| (a - b).abs() <= tol;
        let image_of = |i: usize, j: usize| {
            (0..d).all(|a| {
                (a..d).all(|b| {
                    same(
                        k[(d * j + a, d * j + b)],
                        sign[a] * sign[b] * k[(d * i + a, d * i + b)],
                    )
                })
            })
        };
        let mut s = Vec::with_capacity(m);
        for i in 0..m {
            let others: Vec<usize> = (0..m).filter(|&j| j != i && image_of(i, j)).collect();
            match others[..] {
                [j] => s.push(j),
                [] if image_of(i, i) => s.push(i),
                _ => return None,
            }
        }
        let involution = (0..m).all(|i| s[s[i]] == i);
        if !involution || (0..m).all(|i| s[i] == i) {
            return None;
        }
        let invariant = (0..d * m).all(|a| {
            (0..d * m).all(|b| {
                let (sa, sb) = (d * s[a / d] + a % d, d * s[b / d] + b % d);
                same(k[(sa, sb)], sign[a % d] * sign[b % d] * k[(a, b)])
            })
        });
        invariant.then_some(s)
    }

    /// The (symmetrised) stiffness `K`, `dim*m` square.
    pub fn stiffness(&self) -> &DMatrix<f64> {
        &self.k
    }

    /// The compliance `K^{-1}`: `u = K^{-1} r`. For a floating body a generalised inverse
    /// `G` (`K G r = r` whenever `R^T r = 0`): `u = G r + R a`.
    pub fn compliance(&self) -> &DMatrix<f64> {
        &self.compliance
    }

    /// `u = K^{-1} r`, with two steps of iterative refinement, so that `K u = r` holds to
    /// round-off relative to `|K| |u|` even when `K` is ill-conditioned (the product with the
    /// explicit inverse alone is not backward stable).
    ///
    /// For a floating body `x` is a point of the conic programs, the reactions `r` followed by
    /// the rigid amplitudes `a`: `u = G r + R a`.
    pub fn displacement(&self, x: &[f64]) -> Vec<f64> {
        let (g, k) = (&self.compliance, &self.k);
        let n = g.nrows();
        let r = &x[..n];
        // `M x` column by column (the storage order), each entry summed over `j` in order as
        // a row's dot product would be: the same bits, without striding across the columns
        // (one ray's check called this five times; 6% of a random m = 9 enumeration).
        let apply = |m: &DMatrix<f64>, x: &[f64], out: &mut [f64]| {
            out.iter_mut().for_each(|o| *o = 0.0);
            for (column, &xj) in m.as_slice().chunks_exact(n).zip(x) {
                for (o, a) in out.iter_mut().zip(column) {
                    *o += a * xj;
                }
            }
        };
        let mut u = vec![0.0; n];
        apply(g, r, &mut u);
        if x.len() > n {
            let a = &x[n..];
            for (i, ui) in u.iter_mut().enumerate() {
                *ui += a
                    .iter()
                    .enumerate()
                    .map(|(j, aj)| self.rigid[(i, j)] * aj)
                    .sum::<f64>();
            }
        }
        let mut buffer = vec![0.0; 2 * n];
        let (residual, du) = buffer.split_at_mut(n);
        for _ in 0..2 {
            apply(k, &u, residual);
            residual
                .iter_mut()
                .zip(r)
                .for_each(|(ku, ri)| *ku = ri - *ku);
            apply(g, residual, du);
            u.iter_mut().zip(du.iter()).for_each(|(x, d)| *x += d);
        }
        u
    }

    /// The same problem in other units per node: `T K T`, with `T` scaling node `i`'s block by a
    /// power of two `t_i` chosen so that the node's largest diagonal entry of `K` comes near 1.
    /// Returns it and the `t_i`. A solution `(u', r')` of it is `(T^-1 u, T r)` of this one
    /// (signs, complementarity and the friction cones are per node, so they are unchanged), and
    /// every friction coefficient, threshold and `mu*` is the same. Powers of two make `T K T`
    /// exact in floating point, so an exact certificate of it is one of this problem; when an
    /// entry would underflow, no scaling is done (all `t_i = 1`).
    ///
    /// The conic methods run on it: a mesh whose stiffness varies by orders of magnitude from
    /// node to node would otherwise give the solver badly scaled programs.
    pub fn equilibrated(&self) -> (Problem, Vec<f64>) {
        let d = self.dim;
        let m = self.nodes();
        let t: Vec<f64> = (0..m)
            .map(|i| {
                let top = (0..d)
                    .map(|c| self.k[(d * i + c, d * i + c)])
                    .fold(0.0f64, f64::max);
                // 2^round(-log2(top) / 2): t^2 top is within a factor 2 of 1.
                let e = (-top.log2() / 2.0).round().clamp(-500.0, 500.0) as i32;
                2f64.powi(e)
            })
            .collect();
        let n = self.k.nrows();
        let f = |a: usize| t[a / d];
        let k = DMatrix::from_fn(n, n, |a, b| self.k[(a, b)] * f(a) * f(b));
        let exact = (0..n).all(|a| {
            (0..n).all(|b| {
                let x = k[(a, b)];
                x.is_finite() && x / f(a) / f(b) == self.k[(a, b)]
            })
        });
        if !exact {
            return (self.clone(), vec![1.0; m]);
        }
        let compliance = DMatrix::from_fn(n, n, |a, b| self.compliance[(a, b)] / f(a) / f(b));
        // u' = T^-1 u = T^-1 K^+ T^-1 r' + T^-1 R a: the modes scale like displacements.
        let mut rigid = DMatrix::from_fn(n, self.rigid.ncols(), |a, j| self.rigid[(a, j)] / f(a));
        // Any basis of the modes will do: each column scaled by a power of two to a largest
        // entry near 1, so that the rigid amplitudes are numbers of the reactions' size in the
        // programs (a mesh's stiffness in pascals would make them 1e3 times smaller).
        for mut column in rigid.column_iter_mut() {
            let top = column.amax();
            if top > 0.0 && top.is_finite() {
                column.scale_mut(2f64.powi(-top.log2().round() as i32));
            }
        }
        (
            Problem {
                dim: d,
                k,
                compliance,
                rigid,
                mu: self.mu,
            },
            t,
        )
    }

    /// `(u, r)` of [`Problem::equilibrated`]'s problem (scales `t`) in this problem's units,
    /// renormalised to `sum r_n = 1`.
    pub fn unscale(&self, t: &[f64], u: &[f64], r: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let d = self.dim;
        let mut r: Vec<f64> = r.iter().enumerate().map(|(a, x)| x / t[a / d]).collect();
        let mut u: Vec<f64> = u.iter().enumerate().map(|(a, x)| x * t[a / d]).collect();
        let total: f64 = r.iter().step_by(d).sum();
        if total > 0.0 {
            r.iter_mut().for_each(|x| *x /= total);
            u.iter_mut().for_each(|x| *x /= total);
        }
        (u, r)
    }

    /// The problem with its nodes reordered: new node `a` is old node `order[a]`.
    pub fn permuted(&self, order: &[usize]) -> Problem {
        let d = self.dim;
        let n = self.k.nrows();
        assert_eq!(order.len() * d, n, "order must list every node once");
        let idx = |a: usize| order[a / d] * d + a % d;
        let k = DMatrix::from_fn(n, n, |i, j| self.k[(idx(i), idx(j))]);
        let compliance = DMatrix::from_fn(n, n, |i, j| self.compliance[(idx(i), idx(j))]);
        let rigid = DMatrix::from_fn(n, self.rigid.ncols(), |i, j| self.rigid[(idx(i), j)]);
        Problem {
            dim: d,
            k,
            compliance,
            rigid,
            mu: self.mu,
        }
    }
}

fn check_mu(mu: f64) -> Result<(), ProblemError> {
    if mu.is_finite() && mu > 0.0 {
        Ok(())
    } else {
        Err(ProblemError::InvalidMu(mu))
    }
}

/// Lower Cholesky factor of a symmetric matrix, or the 0-based index and value of the first pivot
/// that is not safely positive.
fn cholesky(a: &DMatrix<f64>) -> Result<DMatrix<f64>, (usize, f64)> {
    let n = a.nrows();
    let mut l = DMatrix::<f64>::zeros(n, n);
    for j in 0..n {
        let mut d = a[(j, j)];
        for k in 0..j {
            d -= l[(j, k)] * l[(j, k)];
        }
        if d.is_nan() || d <= PIVOT_TOLERANCE * a[(j, j)].abs() {
            return Err((j, d));
        }
        let ljj = d.sqrt();
        l[(j, j)] = ljj;
        for i in (j + 1)..n {
            let mut s = a[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = s / ljj;
        }
    }
    Ok(l)
}

/// `(L L^T)^{-1}`, symmetric by construction.
fn inverse_from_cholesky(l: &DMatrix<f64>) -> DMatrix<f64> {
    let n = l.nrows();
    // Columns of L^{-1} by forward substitution, then G = L^{-T} L^{-1}.
    let mut linv = DMatrix::<f64>::zeros(n, n);
    for c in 0..n {
        for i in c..n {
            let mut s = if i == c { 1.0 } else { 0.0 };
            for k in c..i {
                s -= l[(i, k)] * linv[(k, c)];
            }
            linv[(i, c)] = s / l[(i, i)];
        }
    }
    let g = linv.transpose() * &linv;
    (&g + g.transpose()) * 0.5
}

/// The 64-bit FNV-1a digest of `words` (little-endian bytes): [`Problem::fingerprint`], and the
/// keys under which a process keeps a search's split (`shard`).
pub(crate) fn digest(words: &[u64]) -> u64 {
    digest_of(words.iter().copied())
}

fn digest_of(words: impl Iterator<Item = u64>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for word in words {
        for byte in word.to_le_bytes() {
            h ^= u64::from(byte);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd2() -> DMatrix<f64> {
        DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0])
    }

    #[test]
    fn accepts_spd_and_inverts() {
        let p = Problem::new(2, spd2(), 0.5).unwrap();
        let prod = p.stiffness() * p.compliance();
        assert!((prod - DMatrix::identity(2, 2)).amax() < 1e-14);
        assert_eq!(p.nodes(), 1);
    }

    #[test]
    fn each_error_is_named() {
        use ProblemError::*;
        assert_eq!(Problem::new(4, spd2(), 1.0).unwrap_err(), InvalidDim(4));
        assert_eq!(
            Problem::new(2, DMatrix::zeros(0, 0), 1.0).unwrap_err(),
            Empty
        );
        assert_eq!(
            Problem::new(2, DMatrix::zeros(2, 3), 1.0).unwrap_err(),
            NotSquare { rows: 2, cols: 3 }
        );
        assert_eq!(
            Problem::new(2, DMatrix::identity(3, 3), 1.0).unwrap_err(),
            SizeNotMultiple { size: 3, dim: 2 }
        );
        let mut k = spd2();
        k[(1, 0)] = f64::NAN;
        assert!(matches!(
            Problem::new(2, k, 1.0),
            Err(NonFinite { row: 2, col: 1, .. })
        ));
        let mut k = DMatrix::identity(4, 4);
        k[(0, 3)] = 0.1;
        k[(1, 2)] = 0.3;
        k[(2, 1)] = 0.1;
        k[(3, 0)] = 0.1;
        assert!(matches!(
            Problem::new(2, k, 1.0),
            Err(NotSymmetric { row: 2, col: 3, .. })
        ));
        let k = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert!(matches!(
            Problem::new(2, k, 1.0),
            Err(NotPositiveDefinite {
                pivot: 2,
                node: 1,
                component: "t",
                ..
            })
        ));
        for mu in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(Problem::new(2, spd2(), mu), Err(InvalidMu(_))));
        }
    }

    #[test]
    fn permutation_moves_blocks() {
        let k = DMatrix::from_fn(4, 4, |i, j| if i == j { 3.0 + i as f64 } else { 0.1 });
        let p = Problem::new(2, k, 1.0).unwrap().permuted(&[1, 0]);
        assert_eq!(p.stiffness()[(0, 0)], 5.0);
        assert_eq!(p.stiffness()[(3, 3)], 4.0);
        let prod = p.stiffness() * p.compliance();
        assert!((prod - DMatrix::identity(4, 4)).amax() < 1e-14);
    }
}
