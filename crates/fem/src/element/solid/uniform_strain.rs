//! C3D8R: Flanagan and Belytschko's uniform-strain hexahedron with
//! CalculiX's hourglass stiffness and one-point mass (see the module docs
//! of [`super`]).

use super::quadrature::Rule;
use super::{
    add_mass, add_stiffness, add_stiffness_general, strain, stress, Geometry, Solid, MAX_NODES,
};
use crate::anisotropy::Voigt;
use crate::FemError;
use faer::Mat;

impl Solid {
    /// C3D8R's stiffness and mass in the form of [`Self::integrate`]: the
    /// uniform strain of the mean gradients at one point plus the hourglass
    /// stiffness, and the one-point mass (see the module docs).
    pub(super) fn integrate_uniform_strain(
        &self,
        geometry: &Geometry,
        mass: bool,
    ) -> Result<(Mat<f64>, Vec<f64>), FemError> {
        const NN: usize = 8;
        const ND: usize = 3 * NN;
        let mean = geometry.mean_gradients();
        let volume = mean.volume;
        let mut k = vec![0.0; ND * ND];
        // The hourglass stiffness scales with E, or with C_xxxx in global
        // axes for an anisotropic material, as in CalculiX.
        let modulus = match self.centre_elasticity(geometry)? {
            None => {
                let (lambda, mu) = self.lame();
                add_stiffness(&mut k, NN, &mean.gradients, lambda * volume, mu * volume);
                self.material.youngs_modulus
            }
            Some(c) => {
                add_stiffness_general(&mut k, NN, &mean.gradients, &c, volume);
                c[0][0]
            }
        };
        let hourglass = geometry.hourglass_vectors(&mean.gradients);
        // Flanagan-Belytschko's stiffness with CalculiX's scaling,
        // `E 0.0005 sum_a |V b_a|^2 / V` per hourglass mode.
        let squares: f64 = mean.gradients[..NN]
            .iter()
            .flatten()
            .map(|b| (b * volume).powi(2))
            .sum();
        let scale = modulus * HOURGLASS_STIFFNESS * squares / volume;
        for a in 0..NN {
            for b in a..NN {
                let g: f64 = (0..4).map(|m| hourglass[a][m] * hourglass[b][m]).sum();
                for i in 0..3 {
                    k[(3 * a + i) * ND + 3 * b + i] += scale * g;
                }
            }
        }
        let mut m = vec![0.0; if mass { NN * NN } else { 0 }];
        if mass {
            let mut centre = [0.0; MAX_NODES];
            centre[..NN].fill(1.0 / 8.0);
            add_mass(&mut m, NN, &centre, self.material.density * volume);
        }
        let k = Mat::from_fn(
            ND,
            ND,
            |r, c| {
                if r <= c {
                    k[r * ND + c]
                } else {
                    k[c * ND + r]
                }
            },
        );
        Ok((k, m))
    }

    /// C3D8R's nodal stresses in the form of [`Self::nodal_stress_columns`]:
    /// the uniform strain of the mean gradients, the same at every node
    /// (hourglass modes strain nothing).
    pub(super) fn uniform_strain_stresses(
        &self,
        geometry: &Geometry,
        u_e: &[f64],
    ) -> Result<Vec<[f64; 6]>, FemError> {
        const NN: usize = 8;
        let (lambda, mu) = self.lame();
        let mean = geometry.mean_gradients();
        let c = self.centre_elasticity(geometry)?;
        Ok(u_e
            .chunks_exact(3 * NN)
            .flat_map(|u| {
                let e = strain(&mean.gradients[..NN], u);
                let s = match &c {
                    None => stress(&e, lambda, mu),
                    Some(c) => std::array::from_fn(|i| (0..6).map(|j| c[i][j] * e[j]).sum()),
                };
                std::iter::repeat_n(s, NN)
            })
            .collect())
    }

    /// The anisotropic elasticity in global axes at the mean of the nodes
    /// (C3D8R's one integration point), `None` for an isotropic material.
    fn centre_elasticity(&self, geometry: &Geometry) -> Result<Option<Voigt>, FemError> {
        let Some(a) = self.material.anisotropy.as_deref() else {
            return Ok(None);
        };
        a.global_at(geometry.node_mean())
            .map(Some)
            .map_err(|e| self.invalid(e.to_string()))
    }
}

/// A hexahedron's mean shape-function gradients (m^-1, first 8 entries)
/// and its volume (m^3).
struct MeanGradients {
    gradients: [[f64; 3]; MAX_NODES],
    volume: f64,
}

/// The hourglass base vectors of the 8-node hexahedron, `h_a^k` for node
/// `a` at natural corner `(xi, eta, zeta)`: `eta zeta`, `zeta xi`,
/// `xi eta`, `xi eta zeta`.
const HOURGLASS_BASE: [[f64; 4]; 8] = [
    [1.0, 1.0, 1.0, -1.0],
    [1.0, -1.0, -1.0, 1.0],
    [-1.0, -1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0, 1.0],
    [-1.0, -1.0, 1.0, 1.0],
    [-1.0, 1.0, -1.0, -1.0],
    [1.0, 1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0, -1.0],
];

/// The hourglass stiffness coefficient of C3D8R, CalculiX's
/// (`shape8hr.f`).
const HOURGLASS_STIFFNESS: f64 = 0.0005;

impl Geometry {
    /// The mean shape-function gradients of a hexahedron, `b_a = (1/V)
    /// int grad N_a dV`, and its volume `V` (Flanagan and Belytschko, eqs.
    /// 15-16): integrated with 2x2x2 points, which is exact for the
    /// trilinear hexahedron (`det J grad N_a` is at most quadratic in each
    /// natural coordinate).
    fn mean_gradients(&self) -> MeanGradients {
        let mut gradients = [[0.0; 3]; MAX_NODES];
        let mut volume = 0.0;
        let rule = Rule::Hex2;
        for (xi, w) in rule.points().iter().zip(rule.weights()) {
            let point = self.point(*xi);
            let wd = w * point.det_j;
            volume += wd;
            for (b, g) in gradients.iter_mut().zip(&point.grad).take(8) {
                for (bi, gi) in b.iter_mut().zip(g) {
                    *bi += wd * gi;
                }
            }
        }
        for b in gradients.iter_mut().take(8) {
            *b = b.map(|v| v / volume);
        }
        MeanGradients { gradients, volume }
    }

    /// Flanagan and Belytschko's hourglass vectors of a hexahedron,
    /// `gamma_a^k = h_a^k - b_a . sum_l x_l h_l^k` (their eq. 43) for the
    /// four base vectors `h^k` ([`HOURGLASS_BASE`]), from the mean gradients
    /// `b`: orthogonal to every linear displacement field, so that the
    /// hourglass stiffness leaves constant strains alone.
    fn hourglass_vectors(&self, b: &[[f64; 3]; MAX_NODES]) -> [[f64; 4]; 8] {
        let mut projection = [[0.0; 3]; 4];
        for (p, k) in projection.iter_mut().zip(0..4) {
            for (x, h) in self.rel.iter().zip(&HOURGLASS_BASE) {
                for (pj, xj) in p.iter_mut().zip(x) {
                    *pj += xj * h[k];
                }
            }
        }
        std::array::from_fn(|a| {
            std::array::from_fn(|k| {
                HOURGLASS_BASE[a][k] - (0..3).map(|j| b[a][j] * projection[k][j]).sum::<f64>()
            })
        })
    }

    /// The mean of the nodes' global positions.
    fn node_mean(&self) -> [f64; 3] {
        let nn = self.kind.node_count();
        let mut x = self.origin;
        for r in self.rel.iter().take(nn) {
            for (xi, ri) in x.iter_mut().zip(r) {
                *xi += ri / nn as f64;
            }
        }
        x
    }
}
