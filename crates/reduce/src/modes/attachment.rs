//! Attachment modes (report 5.2.2): `T_stat,a = K^-1 P_1` for a supported
//! body, with unit loads `P_1` at the interface DOFs.

use crate::ReduceError;
use faer::Mat;
use flexbody_fem::DofMap;
use flexbody_linalg::ldlt::Factor;
use flexbody_linalg::ordering::Ordering;
use flexbody_linalg::pencil::Pencil;
use flexbody_linalg::progress::{NoProgress, Progress, Stage};
use flexbody_linalg::{sparse, LinalgError, SparseMat};

/// What a singular `K` of a supported body is called in errors.
const SUPPORTED_BODY: &str = "the stiffness matrix of the supported body";

/// Unit-load matrix `P_1` (m x s): a unit force (or moment) at each of the
/// equations in `dofs`.
pub fn unit_loads(n: usize, dofs: &[usize]) -> Mat<f64> {
    Mat::from_fn(n, dofs.len(), |i, j| if dofs[j] == i { 1.0 } else { 0.0 })
}

/// Attachment modes `K^-1 P_1` (one factorisation, one block solve).
/// `K` must be regular (a supported body).
pub fn attachment_modes(
    stiffness: &SparseMat,
    loads: &Mat<f64>,
    dof_map: &DofMap,
) -> Result<Mat<f64>, ReduceError> {
    let no_mass = sparse::from_triplets(stiffness.nrows(), stiffness.nrows(), &[])?;
    let hook: &dyn Progress = &NoProgress;
    let pencil = Pencil::analyze(stiffness, &no_mass, None, Ordering::Auto, hook)?;
    Ok(attachment_modes_on(&pencil, loads, dof_map, hook)?.0)
}

/// [`attachment_modes`] on the factor of `K` from `pencil`, returned with
/// it: the Lanczos operator at shift 0 afterwards.
pub(crate) fn attachment_modes_on(
    pencil: &Pencil,
    loads: &Mat<f64>,
    dof_map: &DofMap,
    progress: &dyn Progress,
) -> Result<(Mat<f64>, Factor), ReduceError> {
    let factor = static_factor(pencil, &[], SUPPORTED_BODY, dof_map, progress)?;
    progress.report(&Stage::Solves {
        columns: loads.ncols(),
    });
    let mut t_a = loads.clone();
    factor.solve_in_place(t_a.as_mut());
    Ok((t_a, factor))
}

/// The pencil's factor of `K` held at the `fixed` equations
/// ([`Pencil::factorize_static`]); a vanishing pivot is
/// [`ReduceError::Singular`] naming `what` and the DOF.
pub(crate) fn static_factor(
    pencil: &Pencil,
    fixed: &[usize],
    what: &'static str,
    dof_map: &DofMap,
    progress: &dyn Progress,
) -> Result<Factor, ReduceError> {
    pencil
        .factorize_static(fixed, progress)
        .map_err(|e| match e {
            LinalgError::Singular { index, .. } => ReduceError::Singular {
                what,
                dof: dof_map.dof(index),
            },
            other => other.into(),
        })
}
