//! Rigid-body modes from geometry (report eq. 12-13).
//!
//! For a node at `x_j` and a reference point `x_sp`, the rigid motion
//! `(u, v, w, bx, by, bz)` of the reference point moves the node by
//! `u_j = u_sp + beta x (x_j - x_sp)` and rotates it by `beta` (eq. 12).
//! Stacking these rows for all DOFs gives six candidate modes (eq. 13); the
//! ones the model's DOFs can carry survive M-orthonormalisation
//! (`T_st^T M T_st = I`): 6 for a 3D body, 2 (heave, pitch) for a planar
//! bending beam.

use faer::Mat;
use flexbody_fem::{AxesChange, DofKind, Substructure};
use flexbody_linalg::orthonormal::m_orthonormalize;
use flexbody_linalg::SparseMat;

/// M-orthonormal rigid-body modes and which motion each came from.
#[derive(Clone, Debug)]
pub struct RigidModes {
    /// `T_st` (m x n_rigid), `T_st^T M T_st = I`.
    pub vectors: Mat<f64>,
    /// What each column is: `ux`..`rz`, the reference-point motion it
    /// started from, or `zero-energy mode k` when found from K's null space.
    pub motions: Vec<String>,
}

impl RigidModes {
    pub fn count(&self) -> usize {
        self.vectors.ncols()
    }
}

/// The `m x 6` matrix of eq. 13 about `reference` (no normalisation); rows
/// of nodes without coordinates are zero (check [`Substructure::has_geometry`]).
/// At nodes whose equations are along local axes
/// ([`Substructure::local_axes`]), the rows are the local components.
pub fn rigid_body_transformation(sub: &Substructure, reference: [f64; 3]) -> Mat<f64> {
    let map = &sub.dof_map;
    let mut t = Mat::from_fn(map.len(), 6, |i, col| {
        let dof = map.dof(i);
        let Some(x) = sub.node_coordinates(dof.node) else {
            return 0.0;
        };
        let r = [
            x[0] - reference[0],
            x[1] - reference[1],
            x[2] - reference[2],
        ];
        // Row of R_j (eq. 12) for this DOF kind, column `col`.
        match (dof.kind, col) {
            (DofKind::Ux, 0) | (DofKind::Uy, 1) | (DofKind::Uz, 2) => 1.0,
            (DofKind::Rx, 3) | (DofKind::Ry, 4) | (DofKind::Rz, 5) => 1.0,
            (DofKind::Ux, 4) => r[2],
            (DofKind::Ux, 5) => -r[1],
            (DofKind::Uy, 3) => -r[2],
            (DofKind::Uy, 5) => r[0],
            (DofKind::Uz, 3) => r[1],
            (DofKind::Uz, 4) => -r[0],
            _ => 0.0,
        }
    });
    if !sub.local_axes.is_empty() {
        // The axes were checked when the substructure was turned.
        if let Ok(change) = AxesChange::new(map, &sub.local_axes) {
            change.rows_to_local(&mut t);
        }
    }
    t
}

/// Rigid-body modes of a free substructure about `reference` (eq. 12-13),
/// M-orthonormalised; motions the DOFs cannot carry are dropped.
pub fn rigid_body_modes(sub: &Substructure, reference: [f64; 3]) -> RigidModes {
    let t = rigid_body_transformation(sub, reference);
    let o = m_orthonormalize(t.as_ref(), &sub.matrices.mass, 1e-8);
    RigidModes {
        motions: o
            .kept
            .iter()
            .map(|&j| DofKind::ALL[j].name().to_string())
            .collect(),
        vectors: o.vectors,
    }
}

/// How many rigid-body motions (eq. 12-13) the DOFs of `sub` can carry,
/// from geometry alone: the rank of `T^T T` about the node centroid
/// (eigenvalues above 1e-10 of the largest). Without M or K products, for
/// a count where [`rigid_body_modes`] is more than needed.
pub fn rigid_motion_count(sub: &Substructure) -> usize {
    let t = rigid_body_transformation(sub, sub.centroid());
    let gram = t.transpose() * &t;
    let Ok(s) = gram.self_adjoint_eigenvalues(faer::Side::Lower) else {
        return 0;
    };
    let largest = s.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    s.iter().filter(|&&l| l > 1e-10 * largest).count()
}

/// `||K T_st|| / (||K|| ||T_st||)` in max norms: zero (round-off) for a free
/// body.
pub fn strain_energy_ratio(stiffness: &SparseMat, rigid: &RigidModes) -> f64 {
    if rigid.count() == 0 {
        return 0.0;
    }
    let kt = flexbody_linalg::sparse::symmetric_mul(stiffness, rigid.vectors.as_ref());
    let k_max = flexbody_linalg::sparse::max_abs_diagonal(stiffness);
    let t_max = rigid.vectors.norm_max();
    if k_max == 0.0 || t_max == 0.0 {
        return 0.0;
    }
    kt.norm_max() / (k_max * t_max)
}
