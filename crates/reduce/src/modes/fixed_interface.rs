//! Craig-Bampton's two mode sets (report 6.4) from one factorisation:
//! the constraint modes `[I; -K_NN^-1 K_NH]` (eq. 14-17) and the eigenmodes
//! of the body fixed at its interface, `K_NN phi = lambda M_NN phi`.
//!
//! `K_NN` is regular (the interface supports the body), so the Lanczos
//! solver can work at shift 0 on the very factor of `K_NN` that gave the
//! constraint modes: one ordering and one factorisation of `K_NN` serve
//! both (plus the Sturm check's), where two separate solvers would pay for
//! two. Guyan's static condensation (no eigenmodes) takes the same path
//! without the eigen solve. On small interiors the pencil's eigen solve is
//! the dense one ([`flexbody_linalg::solver`]).

use super::constraint::{constraint_columns, mechanism_check, mechanism_error};
use super::eigen::{eigenmodes_on, Wanted};
use super::{complement, expand, EigenModes, RigidModes};
use crate::products::{Bordered, Matrices, Products};
use crate::ReduceError;
use faer::Mat;
use flexbody_fem::DofMap;
use flexbody_linalg::progress::{NoProgress, Progress, Stage};
use flexbody_linalg::solver::EigenRequest;
use flexbody_linalg::SparseMat;

/// Constraint modes (m x s) and the fixed-interface eigenmodes of `band`
/// (zero at the `boundary` equations).
pub fn craig_bampton_modes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    boundary: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
    band: Wanted,
) -> Result<(Mat<f64>, EigenModes), ReduceError> {
    let matrices = Matrices::lent(stiffness, mass);
    let (psi, phi, _) =
        craig_bampton_modes_from(matrices, boundary, dof_map, rigid, band, &NoProgress)?;
    Ok((psi, phi))
}

/// [`craig_bampton_modes`] on `K` and `M` lent or handed over (dropped
/// once the pencil of the interior and the interface's coupling blocks
/// are copied), with the products the reduction needs afterwards.
pub(crate) fn craig_bampton_modes_from<'a>(
    matrices: Matrices<'a>,
    boundary: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
    band: Wanted,
    progress: &dyn Progress,
) -> Result<(Mat<f64>, EigenModes, Products<'a>), ReduceError> {
    let n = matrices.k().nrows();
    let interior = complement(boundary, n);
    mechanism_check(boundary, &interior, dof_map, rigid)?;
    let pencil = matrices.pencil(None, Some(&interior), progress)?;
    let bordered = Bordered::new(
        pencil,
        matrices.k(),
        matrices.m(),
        interior,
        boundary.to_vec(),
    );
    let full = matrices.kept_if_small(bordered.interior.len(), band);
    let pencil = &bordered.pencil;
    let interior = &bordered.interior;
    let k_factor = pencil
        .factorize_static(&[], progress)
        .map_err(|e| mechanism_error(e, boundary, dof_map, rigid, |k| interior[k]))?;
    let mut u_n = -bordered.k_nb.to_dense();
    progress.report(&Stage::Solves {
        columns: boundary.len(),
    });
    k_factor.solve_in_place(u_n.as_mut());
    let psi = constraint_columns(n, boundary, interior, &u_n);
    // Guyan's static condensation takes the constraint modes alone.
    let phi = if band.is_none() {
        EigenModes {
            vectors: Mat::zeros(n, 0),
            values: vec![],
        }
    } else {
        let found = eigenmodes_on(
            pencil,
            Some(k_factor),
            &EigenRequest::new(band).shift(0.0),
            progress,
        )?;
        EigenModes {
            vectors: expand(&found.vectors, interior, n),
            values: found.values,
        }
    };
    let products = Products::full_or(full, Products::Bordered(Box::new(bordered)));
    Ok((psi, phi, products))
}
