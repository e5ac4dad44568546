//! Eigenmodes (report 5.3, eq. 21 undamped): `K phi = lambda M phi` of the
//! free body, of the body fixed at its interface DOFs, or of the body on
//! elastic supports (pass `K + C`).
//!
//! Two solvers stand behind these functions:
//! - up to [`SPARSE_FROM`] DOFs (and whenever more than a quarter of all
//!   modes is asked for, up to [`DENSE_LIMIT`]), the dense shift-invert
//!   solver of [`flexbody_linalg::eigen`], which is faster there;
//! - from [`SPARSE_FROM`] DOFs on, the sparse shift-invert block Lanczos
//!   solver of [`flexbody_linalg::lanczos`] (one sparse `LDL^T` of
//!   `K - sigma M`, a Sturm check of the count).
//!
//! The sparse solver reports its stages to the process-wide
//! [`flexbody_linalg::progress::global`] hook.

use super::{complement, expand};
use crate::products::{Matrices, Products};
use crate::ReduceError;
use faer::Mat;
use flexbody_linalg::eigen::{ensure_dense_room, generalized_symmetric};
use flexbody_linalg::lanczos::{lanczos, lanczos_on, Held, LanczosParams, SparseEigen};
use flexbody_linalg::ordering::Ordering;
use flexbody_linalg::shift_invert::{ShiftedFactor, ShiftedPencil};
use flexbody_linalg::{sparse, LinalgError, SparseMat};

/// Largest model the dense eigen path accepts.
pub const DENSE_LIMIT: usize = 6000;

/// Size from which [`EigenSolver::Auto`] takes the sparse Lanczos solver.
/// The dense solver's work grows with the cube of the DOFs, the sparse
/// one's about linearly on meshes; the ignored test
/// `time_dense_against_sparse` (`cargo test --release --test large --
/// --ignored`) times both. Below this size both take milliseconds and the
/// dense solver (two shifts) is the more accurate one for the low modes,
/// so it keeps that range.
pub const SPARSE_FROM: usize = 300;

/// The lowest eigenpairs, M-orthonormal (`Phi^T M Phi = I`), ascending;
/// eigenvalues lambda = omega^2 (rad^2/s^2).
pub use flexbody_linalg::eigen::EigenPairs as EigenModes;

/// Which eigen solver to use.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum EigenSolver {
    /// Dense below [`SPARSE_FROM`] DOFs, sparse Lanczos above.
    #[default]
    Auto,
    /// The dense solver (up to [`DENSE_LIMIT`] DOFs).
    Dense,
    /// The sparse Lanczos solver.
    Sparse,
}

/// Which eigenpairs a reduction takes: the lowest `n`, or every one below
/// a bound ([`Wanted::below_hz`]: the report's modes in the excitation
/// band, counted by the Sturm sequence).
pub use flexbody_linalg::eigen::Wanted;

/// The `wanted` eigenpairs of `K phi = lambda M phi`, by the solver
/// [`EigenSolver::Auto`] picks: one eigen solve either way (for a frequency
/// bound the sparse solver counts by the Sturm sequence first).
pub fn eigenmodes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    wanted: Wanted,
) -> Result<EigenModes, ReduceError> {
    eigenmodes_with(stiffness, mass, wanted, EigenSolver::Auto)
}

/// [`eigenmodes`] for a caller that needs `K` and `M` no more, with
/// each mode's residual `||K phi - lambda M phi|| / ||K phi||` (as
/// [`flexbody_linalg::lanczos::residuals`] defines it). The sparse solver
/// keeps a compact copy of both (their lower triangles on one pattern) and
/// drops `stiffness` and `mass` before it factorises: at 3e5 DOFs the peak
/// memory is 0.5 GB lower than with [`eigenmodes`].
pub fn eigenmodes_owned(
    stiffness: SparseMat,
    mass: SparseMat,
    band: Wanted,
) -> Result<(EigenModes, Vec<f64>), ReduceError> {
    let (modes, residuals, _) = eigenmodes_from(Matrices::given(stiffness, mass), band)?;
    Ok((modes, residuals))
}

/// [`eigenmodes_owned`] on `K` and `M` lent or handed over, with the
/// products a reduction needs afterwards (from the solver's compact copy
/// on the sparse path).
pub(crate) fn eigenmodes_from(
    matrices: Matrices<'_>,
    band: Wanted,
) -> Result<(EigenModes, Vec<f64>, Products<'_>), ReduceError> {
    let n = matrices.k().nrows();
    if dense_path(n, band) || band == Wanted::Lowest(0) {
        let (stiffness, mass) = (matrices.k(), matrices.m());
        let modes = eigenmodes(stiffness, mass, band)?;
        let residuals = flexbody_linalg::lanczos::residuals(
            stiffness,
            mass,
            &modes.values,
            modes.vectors.as_ref(),
            &sparse::diagonal(stiffness),
        );
        return Ok((modes, residuals, Products::Full(matrices)));
    }
    available(band, n)?;
    let progress = flexbody_linalg::progress::global();
    let pencil =
        ShiftedPencil::analyze_reporting(matrices.k(), matrices.m(), Ordering::Auto, &*progress)?;
    drop(matrices);
    let found = lanczos_band(&pencil, None, band, None, None)?;
    Ok((found.pairs, found.residuals, Products::Pencil(pencil)))
}

/// Whether [`eigenmodes`] takes the dense solver for `band` of an
/// `n`-DOF model.
pub(crate) fn dense_path(n: usize, band: Wanted) -> bool {
    match band {
        Wanted::Lowest(count) => dense_for(n, count),
        Wanted::Below(_) => n < SPARSE_FROM,
    }
}

/// Whether [`EigenSolver::Auto`] takes the dense solver for `count` modes
/// of an `n`-DOF model.
fn dense_for(n: usize, count: usize) -> bool {
    n < SPARSE_FROM || (4 * count > n && n <= DENSE_LIMIT)
}

/// [`eigenmodes`] with the solver chosen.
pub fn eigenmodes_with(
    stiffness: &SparseMat,
    mass: &SparseMat,
    wanted: Wanted,
    solver: EigenSolver,
) -> Result<EigenModes, ReduceError> {
    let n = stiffness.nrows();
    if wanted == Wanted::Lowest(0) {
        return Ok(EigenModes {
            values: vec![],
            vectors: Mat::zeros(n, 0),
        });
    }
    let dense = match solver {
        EigenSolver::Dense => true,
        EigenSolver::Sparse => false,
        EigenSolver::Auto => dense_path(n, wanted),
    };
    if !dense {
        available(wanted, n)?;
        let progress = flexbody_linalg::progress::global();
        let found = lanczos(
            stiffness,
            mass,
            wanted,
            &LanczosParams::default(),
            &*progress,
        )?;
        available(wanted, found.pairs.values.len())?;
        return Ok(found.pairs);
    }
    // Every finite eigenvalue: fewer than n where DOFs carry no mass.
    let pairs = dense_all(stiffness, mass)?;
    available(wanted, pairs.values.len())?;
    let count = match wanted {
        Wanted::Lowest(count) => count,
        Wanted::Below(limit) => pairs.values.iter().filter(|l| **l < limit).count(),
    };
    Ok(pairs.slice(0, count))
}

/// A count of eigenpairs above the `available` ones is an error.
fn available(wanted: Wanted, available: usize) -> Result<(), ReduceError> {
    match wanted {
        Wanted::Lowest(count) if count > available => Err(ReduceError::NotEnoughModes {
            requested: count,
            available,
        }),
        _ => Ok(()),
    }
}

/// Every finite eigenpair by the dense solver (up to [`DENSE_LIMIT`] DOFs):
/// as many as the model has DOFs, less those that carry no mass.
fn dense_all(stiffness: &SparseMat, mass: &SparseMat) -> Result<EigenModes, ReduceError> {
    let n = stiffness.nrows();
    if n > DENSE_LIMIT {
        return Err(ReduceError::TooLargeForDense {
            dofs: n,
            limit: DENSE_LIMIT,
        });
    }
    ensure_dense_room(n, 2)?;
    let pairs = generalized_symmetric(stiffness.to_dense().as_ref(), mass.to_dense().as_ref())?;
    // Round-off zeros of rigid-body modes may be slightly negative; an
    // eigenvalue below -1e-8 of the largest is not round-off.
    let top = pairs.values.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    let bound = -1e-8 * top;
    let count = pairs.values.iter().filter(|&&l| l < bound).count();
    if count > 0 {
        return Err(LinalgError::NotSemiDefinite { count, bound }.into());
    }
    Ok(pairs)
}

/// The eigenpairs of `band` by the Lanczos solver on a pencil the caller
/// has analysed (and may have used for static modes): `factor`, a factor
/// of it no longer needed, becomes the operator or lends its storage.
///
/// For a free body, `held` gives the operator on a statically determinate
/// support ([`Held`]): `factor` is then the held factor the inertia-relief
/// attachment modes were solved with, which serves the Lanczos run too
/// (shift 0), and the rigid-body modes (M-orthonormal) are among the modes
/// returned.
pub fn eigenmodes_on(
    pencil: &ShiftedPencil,
    factor: Option<ShiftedFactor>,
    band: Wanted,
    shift: Option<f64>,
    held: Option<Held<'_>>,
) -> Result<EigenModes, ReduceError> {
    Ok(lanczos_band(pencil, factor, band, shift, held)?.pairs)
}

/// The Lanczos solve of [`eigenmodes_on`] with its residuals; fewer modes
/// than a count asks for is an error.
fn lanczos_band(
    pencil: &ShiftedPencil,
    factor: Option<ShiftedFactor>,
    band: Wanted,
    shift: Option<f64>,
    held: Option<Held<'_>>,
) -> Result<SparseEigen, ReduceError> {
    let params = LanczosParams {
        shift,
        ..Default::default()
    };
    let progress = flexbody_linalg::progress::global();
    let found = lanczos_on(pencil, factor, band, held, &params, &*progress)?;
    available(band, found.pairs.values.len())?;
    Ok(found)
}

/// Eigenmodes of the body held at the `boundary` equations (zero there).
pub fn fixed_interface_eigenmodes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    boundary: &[usize],
    band: Wanted,
) -> Result<EigenModes, ReduceError> {
    let n = stiffness.nrows();
    if band == Wanted::Lowest(0) {
        return Ok(EigenModes {
            values: vec![],
            vectors: Mat::zeros(n, 0),
        });
    }
    let interior = complement(boundary, n);
    let k = sparse::submatrix(stiffness, &interior, &interior);
    let m = sparse::submatrix(mass, &interior, &interior);
    let modes = eigenmodes(&k, &m, band)?;
    Ok(EigenModes {
        vectors: expand(&modes.vectors, &interior, n),
        values: modes.values,
    })
}
