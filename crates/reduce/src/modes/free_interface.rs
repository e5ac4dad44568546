//! The free-residual method's two mode sets (report 6.6) from one
//! analysis: the inertia-relief attachment modes (eq. 18-20) and the free
//! eigenmodes.
//!
//! On a large model both come from one factorisation: the pencil's
//! ordering and symbolic analysis serve the factorisation of `K` held on
//! the statically determinate support (those rows and columns decoupled,
//! same pattern), which solves the attachment modes and then is the
//! Lanczos operator itself: on loads in equilibrium its inverse is the
//! elastic flexibility, shift-invert at shift 0 with the rigid-body modes
//! deflated ([`flexbody_linalg::lanczos::Held`]). Only the Sturm check
//! factorises once more. A supported body (no rigid-body modes) takes plain
//! attachment modes and the Lanczos at shift 0 from the one factor of `K`.
//! On small models the pencil's eigen solve is the dense one
//! ([`flexbody_linalg::solver`]).

use super::attachment::attachment_modes_on;
use super::eigen::{eigenmodes_on, Wanted};
use super::inertia_relief::{check_support, inertia_relief_on};
use super::zero_modes::mechanism_or;
use super::{EigenModes, RigidModes};
use crate::products::{Matrices, Products};
use crate::ReduceError;
use faer::Mat;
use flexbody_fem::DofMap;
use flexbody_linalg::lanczos::Held;
use flexbody_linalg::progress::{NoProgress, Progress};
use flexbody_linalg::solver::EigenRequest;
use flexbody_linalg::SparseMat;

/// The inertia-relief attachment modes of `loads` on `support`, and the
/// free eigenmodes of `band` (rigid-body modes included) with at least
/// one elastic mode beyond the rigid ones, for the gap check.
pub fn inertia_relief_and_free_modes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    rigid: &RigidModes,
    loads: &Mat<f64>,
    support: &[usize],
    dof_map: &DofMap,
    band: Wanted,
) -> Result<(Mat<f64>, EigenModes), ReduceError> {
    let matrices = Matrices::lent(stiffness, mass);
    let (t_a, all, _) = inertia_relief_and_free_modes_from(
        matrices,
        rigid,
        loads,
        support,
        dof_map,
        band,
        &NoProgress,
    )?;
    Ok((t_a, all))
}

/// [`inertia_relief_and_free_modes`] on `K` and `M` lent or handed over
/// (dropped once the pencil holds its copy), with the products the
/// reduction needs afterwards.
pub(crate) fn inertia_relief_and_free_modes_from<'a>(
    matrices: Matrices<'a>,
    rigid: &RigidModes,
    loads: &Mat<f64>,
    support: &[usize],
    dof_map: &DofMap,
    band: Wanted,
    progress: &dyn Progress,
) -> Result<(Mat<f64>, EigenModes, Products<'a>), ReduceError> {
    let (n, nr) = (matrices.k().nrows(), rigid.count());
    let at_least = |band: Wanted| band.map_count(|count| count.max(nr + 1).min(n));
    if nr > 0 {
        check_support(rigid, support, dof_map)?;
    }
    let pencil = matrices.pencil(None, None, progress)?;
    let full = matrices.kept_if_small(n, at_least(band));
    if nr == 0 {
        // A supported body: K is regular, the attachment modes are K^-1 P
        // (eq. 18), and K's factor is the Lanczos operator at shift 0.
        let (t_a, factor) = attachment_modes_on(&pencil, loads, dof_map, progress)?;
        let request = EigenRequest::new(at_least(band)).shift(0.0);
        let all = eigenmodes_on(&pencil, Some(factor), &request, progress)?;
        return Ok((t_a, all, Products::full_or(full, Products::Pencil(pencil))));
    }
    let (t_a, held) = inertia_relief_on(&pencil, rigid, loads, support, dof_map, progress)
        .map_err(|e| match e {
            held @ ReduceError::Singular { .. } => mechanism_or(held, nr, n, |c| {
                Ok(eigenmodes_on(
                    &pencil,
                    None,
                    &EigenRequest::new(Wanted::Lowest(c)),
                    progress,
                )?
                .values)
            }),
            other => other,
        })?;
    let held_at = Held {
        support,
        rigid: rigid.vectors.as_ref(),
    };
    let request = EigenRequest::new(at_least(band)).held(held_at);
    let mut all = eigenmodes_on(&pencil, Some(held), &request, progress)?;
    if all.values.len() <= nr && all.values.len() < n {
        // A band without elastic modes: the gap check needs one.
        let one_more = EigenRequest::new(Wanted::Lowest(nr + 1));
        all = eigenmodes_on(&pencil, None, &one_more, progress)?.slice(0, nr);
    }
    Ok((t_a, all, Products::full_or(full, Products::Pencil(pencil))))
}
