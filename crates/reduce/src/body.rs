//! The reduced flexible body: plain data, the output of every method.

use crate::method::Method;
use faer::{Mat, MatRef};
use flexbody_fem::local_axes::rows_along;
use flexbody_fem::transform::family;
use flexbody_fem::{Axes, Dof, DofMap, NodeId};
use flexbody_linalg::eigen::{frequency_hz, generalized_symmetric};
use flexbody_linalg::LinalgError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Natural frequencies (Hz) of `K x = w^2 M x` for small dense symmetric
/// matrices, ascending: those of a free reduced body for `K_red`, `M_red`
/// (eq. 5-7), or of the elastic modes for `Ke`, `Me`.
pub fn natural_frequencies_hz(
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
) -> Result<Vec<f64>, LinalgError> {
    Ok(generalized_symmetric(stiffness, mass)?.frequencies_hz())
}

/// What a column of the Ritz basis is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum ModeKind {
    /// Rigid-body mode (eq. 12-13); `motion` is `ux`..`rz` of the reference point.
    Rigid { motion: String },
    /// Constraint mode of an interface DOF (eq. 14-17).
    Constraint { dof: Dof },
    /// Residual constraint mode (eq. 23-24 applied to eq. 17).
    ResidualConstraint { dof: Dof },
    /// Residual inertia-relief attachment mode (eq. 20, 23-24).
    ResidualInertiaRelief { dof: Dof },
    /// Residual inertia-relief attachment mode of a force group (report 7).
    ResidualForceGroup { name: String },
    /// Eigenmode; `frequency_hz` of the problem it came from.
    Eigen { frequency_hz: f64 },
    /// Column of an orthonormalised basis with its frequency.
    Orthonormal { frequency_hz: f64 },
}

/// A reduced flexible body: `u = T q` with `r` Ritz coordinates `q`.
#[derive(Clone, Debug)]
pub struct ReducedBody {
    pub method: Method,
    /// DOFs of the full model (rows of the basis).
    pub dof_map: DofMap,
    /// The Ritz basis `T` (m x r).
    pub basis: Mat<f64>,
    /// `M_red = T^T M T` (r x r, kg-consistent).
    pub mass: Mat<f64>,
    /// `K_red = T^T K T` of the free body (r x r).
    pub stiffness: Mat<f64>,
    /// `D_red = T^T D T` if the model has damping.
    pub damping: Option<Mat<f64>>,
    /// What each column of `T` is.
    pub modes: Vec<ModeKind>,
    /// Interface DOFs (rows `T_j` for coupling).
    pub interface: Vec<Dof>,
    /// Interface nodes whose DOFs in [`ReducedBody::interface`] (and in the
    /// mode descriptions) are along local axes (a `*TRANSFORM`): there,
    /// [`ReducedBody::interface_rows`] are `R^T` times the global rows. The
    /// basis itself is over the global DOFs everywhere.
    pub local_axes: BTreeMap<NodeId, Axes>,
}

impl ReducedBody {
    /// Number of Ritz coordinates r.
    pub fn r(&self) -> usize {
        self.basis.ncols()
    }

    /// Rows of `T` for the given equation numbers (`T_j`, `T_e`).
    pub fn rows(&self, equations: &[usize]) -> Mat<f64> {
        Mat::from_fn(equations.len(), self.r(), |i, j| {
            self.basis[(equations[i], j)]
        })
    }

    /// The row of `T` of one DOF, if it is a DOF of the model.
    pub fn row_of(&self, dof: Dof) -> Option<Vec<f64>> {
        let i = self.dof_map.index_of(dof)?;
        Some((0..self.r()).map(|j| self.basis[(i, j)]).collect())
    }

    /// The row of `T` of an interface DOF: the global row, or at a node
    /// with local axes `R` the local component `sum_j R_ji row_j` of the
    /// global rows of its family (translations or rotations).
    pub fn interface_row(&self, dof: Dof) -> Option<Vec<f64>> {
        let Some(r) = self.local_axes.get(&dof.node) else {
            return self.row_of(dof);
        };
        let rows = family(dof.kind).map(|k| self.row_of(Dof::new(dof.node, k)));
        let [Some(x), Some(y), Some(z)] = rows else {
            return None;
        };
        let local = rows_along(r, [&x, &y, &z]);
        Some(local[dof.kind.index() % 3].clone())
    }

    /// Interface rows `T_j` (s x r), in the order of [`ReducedBody::interface`]
    /// ([`ReducedBody::interface_row`]).
    pub fn interface_rows(&self) -> Mat<f64> {
        let rows: Vec<Vec<f64>> = self
            .interface
            .iter()
            .filter_map(|d| self.interface_row(*d))
            .collect();
        Mat::from_fn(rows.len(), self.r(), |i, j| rows[i][j])
    }

    /// FE displacements `u = T q`.
    pub fn displacements(&self, q: &[f64]) -> Vec<f64> {
        (0..self.basis.nrows())
            .map(|i| (0..self.r()).map(|j| self.basis[(i, j)] * q[j]).sum())
            .collect()
    }

    /// Natural frequencies (Hz) of the free reduced body, ascending.
    pub fn frequencies_hz(&self) -> Result<Vec<f64>, LinalgError> {
        natural_frequencies_hz(self.stiffness.as_ref(), self.mass.as_ref())
    }

    /// The body with modal damping added: damping ratios `ratios` (one for
    /// all modes, or one per mode of the reduced body in ascending
    /// frequency) give `D_red += M_red X diag(2 zeta_i omega_i) X^T M_red`
    /// with `X` the M_red-orthonormal eigenvectors of the reduced body, so
    /// that mode i of the free reduced body has ratio zeta_i (rigid-body
    /// modes, omega = 0, stay undamped). Directions of `M_red` with a mass
    /// at round-off have no mode and stay undamped; then only one ratio
    /// for all can be given.
    pub fn with_modal_damping(&self, ratios: &[f64]) -> Result<ReducedBody, LinalgError> {
        let r = self.r();
        if ratios.len() != 1 && ratios.len() != r {
            return Err(LinalgError::Dimension(format!(
                "{} modal damping ratios for {r} modes (give 1 or {r})",
                ratios.len()
            )));
        }
        if let Some(z) = ratios.iter().find(|z| !(z.is_finite() && **z >= 0.0)) {
            return Err(LinalgError::Dimension(format!(
                "damping ratio {z} must be >= 0"
            )));
        }
        let pairs = generalized_symmetric(self.stiffness.as_ref(), self.mass.as_ref())?;
        let modes = pairs.values.len();
        if ratios.len() != 1 && modes != r {
            return Err(LinalgError::MasslessDirections {
                modes,
                coordinates: r,
            });
        }
        let x = &pairs.vectors;
        let mx = &self.mass * x;
        let diag = Mat::from_fn(modes, modes, |i, j| {
            if i == j {
                let zeta = if ratios.len() == 1 {
                    ratios[0]
                } else {
                    ratios[i]
                };
                2.0 * zeta * pairs.values[i].max(0.0).sqrt()
            } else {
                0.0
            }
        });
        let mut modal = &mx * &diag * mx.transpose();
        flexbody_linalg::sparse::symmetrize(&mut modal);
        let mut body = self.clone();
        body.damping = Some(match &self.damping {
            Some(d) => d + &modal,
            None => modal,
        });
        Ok(body)
    }

    /// The same body in an orthonormal basis: `M_red = I`, `K_red` diagonal
    /// (the reduced eigenproblem `K_red x = w^2 M_red x` solved and `T`
    /// rotated by its eigenvectors). The span, and so every response, is
    /// unchanged; each column keeps its frequency. A basis with directions
    /// of no mass has no such form: an error.
    pub fn orthonormalized(&self) -> Result<ReducedBody, LinalgError> {
        let pairs = generalized_symmetric(self.stiffness.as_ref(), self.mass.as_ref())?;
        let x = &pairs.vectors;
        let r = x.ncols();
        if r != self.r() {
            return Err(LinalgError::MasslessDirections {
                modes: r,
                coordinates: self.r(),
            });
        }
        let basis = &self.basis * x;
        let mass = Mat::from_fn(r, r, |i, j| if i == j { 1.0 } else { 0.0 });
        let stiffness = Mat::from_fn(r, r, |i, j| if i == j { pairs.values[i] } else { 0.0 });
        let damping = self.damping.as_ref().map(|d| {
            let mut p = x.transpose() * d * x;
            flexbody_linalg::sparse::symmetrize(&mut p);
            p
        });
        Ok(ReducedBody {
            method: self.method,
            dof_map: self.dof_map.clone(),
            basis,
            mass,
            stiffness,
            damping,
            modes: pairs
                .values
                .iter()
                .map(|l| ModeKind::Orthonormal {
                    frequency_hz: frequency_hz(*l),
                })
                .collect(),
            interface: self.interface.clone(),
            local_axes: self.local_axes.clone(),
        })
    }
}
