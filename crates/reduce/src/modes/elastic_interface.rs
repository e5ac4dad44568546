//! The elastic-residual method's two mode sets (report 6.5) from one
//! factorisation: the eigenmodes of the body on its springs,
//! `(K + C) phi = lambda M phi`, and the constraint modes of the free `K`
//! (eq. 14-17), which the reduction then makes residual.
//!
//! The springs `C = sum_n C_n` act on interface equations only (eq.
//! 26-29), so `K + C` and `K` differ only in the interface block. For unit
//! forces at the interface of the body on its springs,
//! `X = (K + C)^-1 [0; I]`, the interior rows read
//! `K_NN X_N + K_NH X_H = 0`, and `X X_H^-1 = [-K_NN^-1 K_NH; I]` are the
//! constraint modes. When the springs support the body, `K + C` is regular
//! and one ordering and one factorisation of it serve both the constraint
//! modes and the Lanczos operator at shift 0, plus the Sturm check's; the
//! separate solvers paid two orderings and three factorisations. When they
//! do not, the same pencil held at the interface gives `K_NN` (equal to
//! `(K + C)_NN`) for the constraint modes, and the Lanczos runs at a
//! negative shift; without eigenmodes it is the one factorisation. A small
//! model, whose eigen solve is the dense one ([`flexbody_linalg::solver`]),
//! takes the constraint modes from `K_NN` too. Springs off the interface
//! take a separate factorisation of `K_NN` for the constraint modes.
//!
//! The free body's products are the pencil's less the springs' (eq. 28:
//! `T^T K T = T^T (K + C) T - T^T C T`).

use super::attachment::unit_loads;
use super::constraint::{
    constraint_columns, constraint_modes_reporting, mechanism_check, mechanism_error,
};
use super::eigen::{eigenmodes_on, Wanted};
use super::{complement, EigenModes, RigidModes};
use crate::products::{Matrices, Products, Sprung};
use crate::ReduceError;
use faer::linalg::solvers::Solve;
use faer::Mat;
use flexbody_fem::DofMap;
use flexbody_linalg::ldlt::Factor;
use flexbody_linalg::pencil::Pencil;
use flexbody_linalg::progress::{NoProgress, Progress, Stage};
use flexbody_linalg::solver::{EigenRequest, Solver};
use flexbody_linalg::{sparse, LinalgError, SparseMat};

/// Constraint modes of `stiffness` (m x s) and the eigenmodes of `band` of
/// the body on its `springs` (`C`, acting on the `boundary` equations).
pub fn elastic_residual_modes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    springs: &SparseMat,
    boundary: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
    band: Wanted,
) -> Result<(Mat<f64>, EigenModes), ReduceError> {
    let matrices = Matrices::lent(stiffness, mass);
    let (psi, phi, _) = elastic_residual_modes_from(
        matrices,
        springs.clone(),
        boundary,
        dof_map,
        rigid,
        band,
        &NoProgress,
    )?;
    Ok((psi, phi))
}

/// [`elastic_residual_modes`] on `K` and `M` lent or handed over (dropped
/// once the pencil of `K + C` and `M` is copied), with the products of the
/// free body the reduction needs afterwards.
pub(crate) fn elastic_residual_modes_from<'a>(
    matrices: Matrices<'a>,
    springs: SparseMat,
    boundary: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
    band: Wanted,
    progress: &dyn Progress,
) -> Result<(Mat<f64>, EigenModes, Products<'a>), ReduceError> {
    let n = matrices.k().nrows();
    let interior = complement(boundary, n);
    if !on_equations(&springs, boundary) {
        // Springs off the interface: the constraint modes of K on their
        // own factorisation, the eigenmodes on the pencil of K + C.
        let psi = constraint_modes_reporting(
            matrices.k(),
            boundary,
            dof_map,
            rigid,
            matrices.budget(),
            progress,
        )?;
        let supported = sparse::add_scaled(matrices.k(), 1.0, &springs)?;
        let pencil = matrices.pencil(Some(&supported), None, progress)?;
        drop(supported);
        let full = matrices.kept_if_small(n, band);
        let phi = eigenmodes_on(&pencil, None, &EigenRequest::new(band), progress)?;
        let sprung = Products::Sprung(Box::new(Sprung { pencil, springs }));
        return Ok((psi, phi, Products::full_or(full, sprung)));
    }
    mechanism_check(boundary, &interior, dof_map, rigid)?;
    let pencil = {
        let supported = sparse::add_scaled(matrices.k(), 1.0, &springs)?;
        matrices.pencil(Some(&supported), None, progress)?
    };
    let full = matrices.kept_if_small(n, band);
    let sprung = Sprung { pencil, springs };
    let pencil = &sprung.pencil;
    if band.is_none() {
        // The constraint modes alone: K_NN is the one factorisation.
        let (psi, _) =
            held_constraint_modes(pencil, boundary, &interior, dof_map, rigid, progress)?;
        let phi = EigenModes {
            vectors: Mat::zeros(n, 0),
            values: vec![],
        };
        return Ok((
            psi,
            phi,
            Products::full_or(full, Products::Sprung(Box::new(sprung))),
        ));
    }
    // The factor of K + C serves the constraint modes only where it then
    // serves the Lanczos run too; beside the dense eigen solver, K_NN
    // gives them directly.
    let shared = !Solver::Auto.is_dense(n, band);
    let regular = if shared && supports_rigid_motion(&sprung.springs, rigid)? {
        regular_factor(pencil.factorize_static(&[], progress))?
    } else {
        None
    };
    let (psi, phi) = match regular {
        Some(factor) => {
            let psi =
                constraint_modes_by_flexibility(pencil, &factor, boundary, &interior, progress);
            let phi = eigenmodes_on(
                pencil,
                Some(factor),
                &EigenRequest::new(band).shift(0.0),
                progress,
            )?;
            let psi = match psi {
                Some(psi) => psi,
                // Springs so soft that the flexibility lost the interior
                // to round-off: K_NN after all.
                None => {
                    held_constraint_modes(pencil, boundary, &interior, dof_map, rigid, progress)?.0
                }
            };
            (psi, phi)
        }
        None => {
            let (psi, held) =
                held_constraint_modes(pencil, boundary, &interior, dof_map, rigid, progress)?;
            // The held factor lends its storage to the shifted one.
            (
                psi,
                eigenmodes_on(pencil, Some(held), &EigenRequest::new(band), progress)?,
            )
        }
    };
    Ok((
        psi,
        phi,
        Products::full_or(full, Products::Sprung(Box::new(sprung))),
    ))
}

/// The constraint modes from the factor of `K + C`: `X X_H^-1` for unit
/// forces `X = (K + C)^-1 [0; I]` at the interface, refined against the
/// interior equilibrium `K_NN Psi_N + K_NH = 0` (rows N of `K + C` are
/// those of `K`). `X` carries the body's motion on its springs, about
/// `1/c`, which `X_H^-1` cancels: soft springs cost digits, and each
/// refinement wins them back. `None` if they do not come back.
pub(crate) fn constraint_modes_by_flexibility(
    pencil: &Pencil,
    factor: &Factor,
    boundary: &[usize],
    interior: &[usize],
    progress: &dyn Progress,
) -> Option<Mat<f64>> {
    let (n, s) = (pencil.dim(), boundary.len());
    let solve = |mut x: Mat<f64>| {
        progress.report(&Stage::Solves { columns: s });
        factor.solve_in_place(x.as_mut());
        x
    };
    let rows = |x: &Mat<f64>, eq: &[usize]| Mat::from_fn(eq.len(), s, |k, j| x[(eq[k], j)]);
    let x = solve(unit_loads(n, boundary));
    let x_h = rows(&x, boundary);
    let x_h = Mat::from_fn(s, s, |i, j| 0.5 * (x_h[(i, j)] + x_h[(j, i)]));
    let llt = x_h.llt(faer::Side::Lower).ok()?;
    // (X_N X_H^-1)^T = X_H^-1 X_N^T, X_H symmetric.
    let mut u_n = llt
        .solve(rows(&x, interior).transpose())
        .transpose()
        .to_owned();
    // The loads of the interior equations, K_NH, set the scale.
    let scale = interior_max(
        &pencil.mul_stiffness(unit_loads(n, boundary).as_ref()),
        interior,
    );
    let equilibrium = |u_n: &Mat<f64>| {
        let psi = constraint_columns(n, boundary, interior, u_n);
        let mut r = pencil.mul_stiffness(psi.as_ref());
        for &b in boundary {
            for j in 0..s {
                r[(b, j)] = 0.0;
            }
        }
        let size = interior_max(&r, interior) / scale;
        (psi, r, size)
    };
    let (mut psi, mut r, mut size) = equilibrium(&u_n);
    for _ in 0..REFINEMENTS {
        if size <= EQUILIBRIUM {
            break;
        }
        // (K + C) y = [-r_N; 0] gives K_NN (y_N - Psi_N y_H) = -r_N: the
        // correction with the interface rows held at zero.
        let y = solve(-r);
        let refined = &u_n + rows(&y, interior) - &u_n * rows(&y, boundary);
        let next = equilibrium(&refined);
        if next.2 >= size {
            break;
        }
        let gain = size / next.2;
        (u_n, (psi, r, size)) = (refined, next);
        // Less than a digit won: round-off is reached.
        if gain < 10.0 {
            break;
        }
    }
    (size <= ACCEPTED).then_some(psi)
}

/// Refinements of [`constraint_modes_by_flexibility`] at most.
const REFINEMENTS: usize = 3;
/// Interior equilibrium, relative to `K_NH`, that needs no refinement
/// (round-off: 4e-16 on a 54-DOF frame, 2e-14 on a 3e5-DOF beam).
const EQUILIBRIUM: f64 = 1e-13;
/// Interior equilibrium the constraint modes must reach.
const ACCEPTED: f64 = 1e-12;

/// The constraint modes by `K_NN`: the pencil of `K + C` held at the
/// interface, with the factor (to lend its storage).
fn held_constraint_modes(
    pencil: &Pencil,
    boundary: &[usize],
    interior: &[usize],
    dof_map: &DofMap,
    rigid: &RigidModes,
    progress: &dyn Progress,
) -> Result<(Mat<f64>, Factor), ReduceError> {
    let (n, s) = (pencil.dim(), boundary.len());
    let held = pencil
        .factorize_static(boundary, progress)
        .map_err(|e| mechanism_error(e, boundary, dof_map, rigid, |i| i))?;
    // -K_NH: the interface columns of K + C, interior rows.
    let mut rhs = pencil.mul_stiffness(unit_loads(n, boundary).as_ref());
    for j in 0..s {
        for &b in boundary {
            rhs[(b, j)] = 0.0;
        }
        for &i in interior {
            rhs[(i, j)] = -rhs[(i, j)];
        }
    }
    progress.report(&Stage::Solves { columns: s });
    held.solve_in_place(rhs.as_mut());
    let u_n = Mat::from_fn(interior.len(), s, |k, j| rhs[(interior[k], j)]);
    Ok((constraint_columns(n, boundary, interior, &u_n), held))
}

/// The largest magnitude in the `interior` rows of `a`.
fn interior_max(a: &Mat<f64>, interior: &[usize]) -> f64 {
    let mut m = 0.0_f64;
    for j in 0..a.ncols() {
        for &i in interior {
            m = m.max(a[(i, j)].abs());
        }
    }
    m
}

/// Whether every nonzero of `c` lies in rows and columns of `equations`.
fn on_equations(c: &SparseMat, equations: &[usize]) -> bool {
    let mut mask = vec![false; c.nrows()];
    for &i in equations {
        mask[i] = true;
    }
    let a = c.as_ref();
    (0..c.ncols()).all(|j| {
        a.row_idx_of_col(j)
            .zip(a.val_of_col(j))
            .all(|(i, &v)| v == 0.0 || (mask[i] && mask[j]))
    })
}

/// Whether the springs hold every rigid-body motion of `rigid` (none: `K`
/// is regular already).
fn supports_rigid_motion(springs: &SparseMat, rigid: &RigidModes) -> Result<bool, ReduceError> {
    Ok(free_rigid_motions(springs, rigid)? == 0)
}

/// How many rigid-body motions of `rigid` the springs `C` leave free: the
/// null space of `R^T C R` (eigenvalues at most 1e-10 of the largest; all
/// of them without springs). They are zero-frequency eigenmodes of
/// `K + C`.
pub(crate) fn free_rigid_motions(
    springs: &SparseMat,
    rigid: &RigidModes,
) -> Result<usize, ReduceError> {
    let r = &rigid.vectors;
    if r.ncols() == 0 {
        return Ok(0);
    }
    let g = sparse::project(springs, r.as_ref());
    let s = g
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
    let largest = s.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    Ok(s.iter().filter(|&&l| l <= 1e-10 * largest).count())
}

/// The factor of `K + C` at shift 0 if it is positive definite; `None` if
/// a pivot vanishes or turns negative (the springs leave a mechanism).
fn regular_factor(factor: Result<Factor, LinalgError>) -> Result<Option<Factor>, ReduceError> {
    match factor {
        Ok(f) if f.inertia().negative == 0 => Ok(Some(f)),
        Ok(_) | Err(LinalgError::Singular { .. }) => Ok(None),
        Err(e) => Err(e.into()),
    }
}
