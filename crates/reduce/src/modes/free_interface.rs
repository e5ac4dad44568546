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
//! Small models take the separate dense path.

use super::attachment::SUPPORTED_BODY;
use super::eigen::{dense_path, eigenmodes, eigenmodes_on, Wanted};
use super::inertia_relief::{
    check_support, inertia_relief_attachment_modes, relieved_modes, SUPPORTED,
};
use super::zero_modes::mechanism_or;
use super::{EigenModes, RigidModes};
use crate::products::{Matrices, Products};
use crate::ReduceError;
use faer::Mat;
use flexbody_fem::DofMap;
use flexbody_linalg::lanczos::Held;
use flexbody_linalg::ordering::Ordering;
use flexbody_linalg::progress::{self, Stage};
use flexbody_linalg::shift_invert::ShiftedPencil;
use flexbody_linalg::{LinalgError, SparseMat};

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
    let (t_a, all, _) =
        inertia_relief_and_free_modes_from(matrices, rigid, loads, support, dof_map, band)?;
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
) -> Result<(Mat<f64>, EigenModes, Products<'a>), ReduceError> {
    let (n, nr) = (matrices.k().nrows(), rigid.count());
    let at_least = |band: Wanted| match band {
        Wanted::Lowest(count) => Wanted::Lowest(count.max(nr + 1).min(n)),
        within => within,
    };
    // Small models, and a quarter of all modes or more: dense.
    if dense_path(n, at_least(band)) {
        let (stiffness, mass) = (matrices.k(), matrices.m());
        let t_a = inertia_relief_attachment_modes(stiffness, mass, rigid, loads, support, dof_map)
            .map_err(|e| match e {
                held @ ReduceError::Singular { .. } => mechanism_or(held, nr, n, |c| {
                    Ok(eigenmodes(stiffness, mass, Wanted::Lowest(c))?.values)
                }),
                other => other,
            })?;
        let mut all = eigenmodes(stiffness, mass, at_least(band))?;
        if all.values.len() <= nr && all.values.len() < n {
            // A band without elastic modes: the gap check needs one.
            all = eigenmodes(stiffness, mass, Wanted::Lowest((nr + 1).min(n)))?.slice(0, nr);
        }
        return Ok((t_a, all, Products::Full(matrices)));
    }
    if nr > 0 {
        check_support(rigid, support, dof_map)?;
    }
    let hook = progress::global();
    let pencil =
        ShiftedPencil::analyze_reporting(matrices.k(), matrices.m(), Ordering::Auto, &*hook)?;
    drop(matrices);
    if nr == 0 {
        // A supported body: K is regular, the attachment modes are K^-1 P
        // (eq. 18), and K's factor is the Lanczos operator at shift 0.
        let factor = pencil.factorize_static(&[], &*hook).map_err(|e| match e {
            LinalgError::Singular { index, .. } => ReduceError::Singular {
                what: SUPPORTED_BODY,
                dof: dof_map.dof(index),
            },
            other => other.into(),
        })?;
        hook.report(&Stage::Solves {
            columns: loads.ncols(),
        });
        let mut t_a = loads.clone();
        factor.solve_in_place(t_a.as_mut());
        let all = eigenmodes_on(&pencil, Some(factor), at_least(band), Some(0.0), None)?;
        return Ok((t_a, all, Products::Pencil(pencil)));
    }
    let held = pencil
        .factorize_static(support, &*hook)
        .map_err(|e| match e {
            LinalgError::Singular { index, .. } => {
                let held = ReduceError::Singular {
                    what: SUPPORTED,
                    dof: dof_map.dof(index),
                };
                mechanism_or(held, nr, n, |c| {
                    Ok(eigenmodes_on(&pencil, None, Wanted::Lowest(c), None, None)?.values)
                })
            }
            other => other.into(),
        })?;
    hook.report(&Stage::Solves {
        columns: loads.ncols(),
    });
    let t_a = relieved_modes(
        |x| pencil.mul_mass(x),
        rigid,
        loads,
        |mut p_g| {
            for &i in support {
                for j in 0..p_g.ncols() {
                    p_g[(i, j)] = 0.0;
                }
            }
            held.solve_in_place(p_g.as_mut());
            p_g
        },
    )?;
    let held_at = Held {
        support,
        rigid: rigid.vectors.as_ref(),
    };
    let mut all = eigenmodes_on(&pencil, Some(held), at_least(band), None, Some(held_at))?;
    if all.values.len() <= nr && all.values.len() < n {
        // A band without elastic modes: the gap check needs one.
        all = eigenmodes_on(&pencil, None, Wanted::Lowest(nr + 1), None, None)?.slice(0, nr);
    }
    Ok((t_a, all, Products::Pencil(pencil)))
}
