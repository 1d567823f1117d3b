//! Isotropic linear elastic material.

use super::FeError;
use nalgebra::DMatrix;

/// The 2D idealisation: plane strain (`eps_zz = 0`, a long body) or plane stress (`sigma_zz = 0`,
/// a thin plate). Ignored in 3D.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Plane {
    /// `eps_zz = 0`.
    #[default]
    Strain,
    /// `sigma_zz = 0`.
    Stress,
}

/// Isotropic linear elasticity: Young's modulus `young > 0`, Poisson's ratio
/// `-1 < poisson < 1/2`, and the 2D idealisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    young: f64,
    poisson: f64,
    plane: Plane,
}

impl Material {
    /// Checks and builds a material.
    pub fn new(young: f64, poisson: f64, plane: Plane) -> Result<Material, FeError> {
        if !(young.is_finite() && young > 0.0) {
            return Err(FeError::InvalidMaterial(format!(
                "Young's modulus must be finite and > 0, got {young}"
            )));
        }
        if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
            return Err(FeError::InvalidMaterial(format!(
                "Poisson's ratio must lie in (-1, 0.5), got {poisson}"
            )));
        }
        Ok(Material {
            young,
            poisson,
            plane,
        })
    }

    /// Young's modulus.
    pub fn young(&self) -> f64 {
        self.young
    }

    /// Poisson's ratio.
    pub fn poisson(&self) -> f64 {
        self.poisson
    }

    /// The 2D idealisation.
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// Lamé's first parameter `lambda` and the shear modulus `G`.
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.young, self.poisson);
        (
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            e / (2.0 * (1.0 + nu)),
        )
    }

    /// The elasticity matrix `D` with `sigma = D eps`, engineering shear strains.
    /// 2D (3x3): `[xx, yy, xy]`; 3D (6x6): `[xx, yy, zz, yz, xz, xy]`.
    pub fn d_matrix(&self, dim: usize) -> DMatrix<f64> {
        let (lambda, g) = self.lame();
        if dim == 3 {
            let mut d = DMatrix::zeros(6, 6);
            for i in 0..3 {
                for j in 0..3 {
                    d[(i, j)] = lambda;
                }
                d[(i, i)] += 2.0 * g;
                d[(i + 3, i + 3)] = g;
            }
            return d;
        }
        let (e, nu) = (self.young, self.poisson);
        match self.plane {
            Plane::Strain => DMatrix::from_row_slice(
                3,
                3,
                &[
                    lambda + 2.0 * g,
                    lambda,
                    0.0,
                    lambda,
                    lambda + 2.0 * g,
                    0.0,
                    0.0,
                    0.0,
                    g,
                ],
            ),
            Plane::Stress => {
                let c = e / (1.0 - nu * nu);
                DMatrix::from_row_slice(
                    3,
                    3,
                    &[
                        c,
                        c * nu,
                        0.0,
                        c * nu,
                        c,
                        0.0,
                        0.0,
                        0.0,
                        c * (1.0 - nu) / 2.0,
                    ],
                )
            }
        }
    }

    /// `sigma_zz` of a 2D state from the in-plane stresses: `nu (xx + yy)` in plane strain, 0 in
    /// plane stress.
    pub fn sigma_zz(&self, sxx: f64, syy: f64) -> f64 {
        match self.plane {
            Plane::Strain => self.poisson * (sxx + syy),
            Plane::Stress => 0.0,
        }
    }
}

/// The von Mises equivalent stress of a Voigt stress `[xx, yy, zz, yz, xz, xy]`.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, yz, xz, xy] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (yz * yz + xz * xz + xy * xy))
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_parameters() {
        assert!(Material::new(0.0, 0.3, Plane::Strain).is_err());
        assert!(Material::new(f64::NAN, 0.3, Plane::Strain).is_err());
        assert!(Material::new(1.0, 0.5, Plane::Strain).is_err());
        assert!(Material::new(1.0, -1.0, Plane::Stress).is_err());
        assert!(Material::new(1.0, 0.3, Plane::Stress).is_ok());
    }

    #[test]
    fn plane_stress_uniaxial() {
        // sigma_xx = E eps_xx when sigma_yy = 0: eps_yy = -nu eps_xx.
        let m = Material::new(200.0, 0.25, Plane::Stress).unwrap();
        let d = m.d_matrix(2);
        let eps = nalgebra::DVector::from_vec(vec![1e-3, -0.25e-3, 0.0]);
        let s = &d * eps;
        assert!((s[0] - 0.2).abs() < 1e-14 && s[1].abs() < 1e-14);
    }

    #[test]
    fn three_d_uniaxial_and_von_mises() {
        let m = Material::new(10.0, 0.3, Plane::Strain).unwrap();
        let d = m.d_matrix(3);
        let eps = nalgebra::DVector::from_vec(vec![1.0, -0.3, -0.3, 0.0, 0.0, 0.0]);
        let s = &d * eps;
        assert!((s[0] - 10.0).abs() < 1e-12 && s[1].abs() < 1e-12 && s[2].abs() < 1e-12);
        assert!((von_mises(&[10.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 10.0).abs() < 1e-12);
        // Pure shear tau: von Mises = sqrt(3) tau.
        assert!((von_mises(&[0.0, 0.0, 0.0, 0.0, 0.0, 2.0]) - 2.0 * 3f64.sqrt()).abs() < 1e-12);
    }
}
