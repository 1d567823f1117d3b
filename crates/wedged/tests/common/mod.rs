//! Helpers shared by the integration tests (`mod common;` in each test file that uses them).

use nalgebra::{DMatrix, DVector};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// A random symmetric positive definite `n x n` matrix: `A A^T + D`, with `A` of a random
/// rank-deficient-or-not width (1 to `n + 2` columns, entries in `[-1, 1)`) and `D` a diagonal
/// in `[0.05, 1)`, so that K is well enough conditioned for double precision and varied in
/// structure.
#[allow(dead_code)] // not every test file uses every helper
pub fn random_spd(rng: &mut ChaCha8Rng, n: usize) -> DMatrix<f64> {
    let cols = rng.gen_range(1..=n + 2);
    let a = DMatrix::from_fn(n, cols, |_, _| rng.gen_range(-1.0..1.0));
    let d = DMatrix::from_diagonal(&DVector::from_fn(n, |_, _| rng.gen_range(0.05..1.0)));
    &a * a.transpose() + d
}
