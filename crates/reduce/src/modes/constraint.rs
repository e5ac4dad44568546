//! Constraint modes by static condensation (report 5.2.1, eq. 14-17).
//!
//! Sorting the DOFs into boundary (H, the interface) and interior (N),
//! `K_NN u_N = -K_NH u_H` (eq. 15); a unit displacement of each boundary DOF,
//! the others held, gives one column `[I; -K_NN^-1 K_NH]` (eq. 16), with the
//! sorting undone (eq. 17). `K_NN` must be regular: the boundary DOFs must at
//! least support the body statically; if not, the error names the DOFs that
//! can still move.

use super::eigen::Wanted;
use super::fixed_interface::craig_bampton_modes_from;
use super::rigid::RigidModes;
use crate::products::Matrices;
use crate::ReduceError;
use faer::Mat;
use flexbody_fem::DofMap;
use flexbody_linalg::memory::Budget;
use flexbody_linalg::progress::{NoProgress, Progress};
use flexbody_linalg::{LinalgError, SparseMat};

/// Constraint modes `T_stat,c` (m x s), one per boundary equation in
/// `boundary`: Guyan's part of [`super::craig_bampton_modes`], on the same
/// factor of `K_NN`. `rigid` (possibly empty) serves to name the free DOFs
/// when the boundary does not support the body.
pub fn constraint_modes(
    stiffness: &SparseMat,
    boundary: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
) -> Result<Mat<f64>, ReduceError> {
    constraint_modes_reporting(
        stiffness,
        boundary,
        dof_map,
        rigid,
        Budget::MACHINE,
        &NoProgress,
    )
}

/// [`constraint_modes`] within the memory `budget` leaves, the stages of
/// its factorisation going to `progress`.
pub(crate) fn constraint_modes_reporting(
    stiffness: &SparseMat,
    boundary: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<Mat<f64>, ReduceError> {
    // The mass takes no part: an empty one of the same size.
    let n = stiffness.nrows();
    let no_mass = flexbody_linalg::sparse::from_triplets(n, n, &[])?;
    let matrices = Matrices::lent(stiffness, &no_mass).under(budget);
    let lowest = Wanted::Lowest(0);
    let (psi, _, _) =
        craig_bampton_modes_from(matrices, boundary, dof_map, rigid, lowest, progress)?;
    Ok(psi)
}

/// The columns `[I; u_N]` of eq. 16 with the sorting undone (eq. 17), from
/// the interior solution `u_N = -K_NN^-1 K_NH`.
pub(crate) fn constraint_columns(
    n: usize,
    boundary: &[usize],
    interior: &[usize],
    u_n: &Mat<f64>,
) -> Mat<f64> {
    let mut t = Mat::zeros(n, boundary.len());
    for (j, &h) in boundary.iter().enumerate() {
        t[(h, j)] = 1.0;
        for (k, &i) in interior.iter().enumerate() {
            t[(i, j)] = u_n[(k, j)];
        }
    }
    t
}

/// `e` from factorising `K_NN`, a vanishing pivot named as the mechanism
/// it is: the interface and the DOF, `equation(index)` being the model's
/// equation of the pivot's row. Called after [`mechanism_check`] passed:
/// the interface holds every one of the body's `rigid` rigid-body motions,
/// so the mechanism is the body's own.
pub(crate) fn mechanism_error(
    e: LinalgError,
    boundary: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
    equation: impl Fn(usize) -> usize,
) -> ReduceError {
    match e {
        LinalgError::Singular { index, .. } => ReduceError::BodyMechanism {
            interface: boundary.iter().map(|&i| dof_map.dof(i)).collect(),
            dof: dof_map.dof(equation(index)),
            rigid: rigid.count(),
        },
        other => other.into(),
    }
}

/// If the boundary rows of the rigid-body modes do not have full rank, some
/// rigid motion leaves the boundary at rest: K_NN is singular. Names the
/// interior DOFs that motion moves most.
pub(crate) fn mechanism_check(
    boundary: &[usize],
    interior: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
) -> Result<(), ReduceError> {
    let nr = rigid.count();
    if nr == 0 {
        return Ok(());
    }
    let rows = Mat::from_fn(boundary.len(), nr, |i, j| rigid.vectors[(boundary[i], j)]);
    // Null space of the boundary rows: right singular vectors of tiny
    // singular values (compare with the size of the modes themselves).
    let gram = rows.transpose() * &rows;
    let (s, u) = flexbody_linalg::eigen::symmetric_eigen(gram.as_ref())?;
    let scale = rigid.vectors.norm_max().powi(2);
    let free_motion = (0..nr).find(|&k| s[k] <= 1e-12 * scale * boundary.len().max(1) as f64);
    let Some(k) = free_motion else {
        return Ok(());
    };
    let shape = &rigid.vectors * u.col(k);
    let mut moving: Vec<(f64, usize)> = interior
        .iter()
        .map(|&i| (shape[i].abs(), i))
        .filter(|(a, _)| *a > 1e-8 * shape.norm_max())
        .collect();
    moving.sort_by(|a, b| b.0.total_cmp(&a.0));
    Err(ReduceError::Mechanism {
        interface: boundary.iter().map(|&i| dof_map.dof(i)).collect(),
        free: moving.into_iter().map(|(_, i)| dof_map.dof(i)).collect(),
    })
}
