//! Eigenmodes (report 5.3, eq. 21 undamped): `K phi = lambda M phi` of the
//! free body, of the body fixed at its interface DOFs, or of the body on
//! elastic supports (pass `K + C`), by the solver
//! [`flexbody_linalg::solver`] chooses (dense for small models, sparse
//! shift-invert Lanczos for large ones). A count beyond the modes the model
//! has is [`ReduceError::NotEnoughModes`].
//!
//! The solvers report their stages to the `progress` hook a caller hands
//! in ([`eigenmodes`] and [`eigenmodes_with`] report nothing).

use crate::products::{Matrices, Products};
use crate::ReduceError;
use flexbody_linalg::lanczos::EigenSolution;
use flexbody_linalg::ldlt::Factor;
use flexbody_linalg::memory::Budget;
use flexbody_linalg::pencil::Pencil;
use flexbody_linalg::progress::{NoProgress, Progress};
use flexbody_linalg::solver::{eigen, EigenRequest};
use flexbody_linalg::SparseMat;

pub use flexbody_linalg::solver::{Solver, DENSE_LIMIT, SPARSE_FROM};

/// The lowest eigenpairs, M-orthonormal (`Phi^T M Phi = I`), ascending;
/// eigenvalues lambda = omega^2 (rad^2/s^2).
pub use flexbody_linalg::eigen::EigenPairs as EigenModes;

/// Which eigenpairs a reduction takes: the lowest `n`, every one below a
/// bound ([`Wanted::below_hz`]: the report's modes in the excitation band,
/// counted by the Sturm sequence), or the lowest `n` below a bound
/// ([`Wanted::lowest_below_hz`]).
pub use flexbody_linalg::eigen::Wanted;

/// The `wanted` eigenpairs of `K phi = lambda M phi`, by the solver
/// [`Solver::Auto`] picks: one eigen solve either way (for a frequency
/// bound the sparse solver counts by the Sturm sequence first).
pub fn eigenmodes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    wanted: Wanted,
) -> Result<EigenModes, ReduceError> {
    eigenmodes_with(stiffness, mass, wanted, Solver::Auto)
}

/// [`eigenmodes`] for a caller that needs `K` and `M` no more, with
/// each mode's residual `||K phi - lambda M phi|| / ||K phi||` (as
/// [`flexbody_linalg::lanczos::residuals`] defines it), within the memory
/// `budget` leaves. The pencil keeps a compact copy of both (their lower
/// triangles on one pattern) and drops `stiffness` and `mass` before it
/// factorises, which lowers the peak memory by about their size.
pub fn eigenmodes_owned(
    stiffness: SparseMat,
    mass: SparseMat,
    band: Wanted,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<(EigenModes, Vec<f64>), ReduceError> {
    let matrices = Matrices::given(stiffness, mass).under(budget);
    let (modes, residuals, _) = eigenmodes_from(matrices, band, progress)?;
    Ok((modes, residuals))
}

/// [`eigenmodes_owned`] for a caller that keeps `K` and `M`: no copy of
/// them is made (the pencil's compact copy is all the solver adds), but
/// they stay in memory through the factorisation.
pub fn eigenmodes_lent(
    stiffness: &SparseMat,
    mass: &SparseMat,
    band: Wanted,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<(EigenModes, Vec<f64>), ReduceError> {
    let matrices = Matrices::lent(stiffness, mass).under(budget);
    let (modes, residuals, _) = eigenmodes_from(matrices, band, progress)?;
    Ok((modes, residuals))
}

/// [`eigenmodes_owned`] on `K` and `M` lent or handed over, with the
/// products a reduction needs afterwards (from the pencil's compact copy
/// on a large model).
pub(crate) fn eigenmodes_from<'a>(
    matrices: Matrices<'a>,
    band: Wanted,
    progress: &dyn Progress,
) -> Result<(EigenModes, Vec<f64>, Products<'a>), ReduceError> {
    available(band, matrices.k().nrows())?;
    let pencil = matrices.pencil(None, None, progress)?;
    let full = matrices.kept_if_small(pencil.dim(), band);
    let found = solve_on(&pencil, None, &EigenRequest::new(band), progress)?;
    let products = Products::full_or(full, Products::Pencil(pencil));
    Ok((found.pairs, found.residuals, products))
}

/// [`eigenmodes`] with the solver chosen.
pub fn eigenmodes_with(
    stiffness: &SparseMat,
    mass: &SparseMat,
    wanted: Wanted,
    solver: Solver,
) -> Result<EigenModes, ReduceError> {
    available(wanted, stiffness.nrows())?;
    let progress: &dyn Progress = &NoProgress;
    let found = eigen(stiffness, mass, wanted, solver, Budget::MACHINE, progress)?;
    available(wanted, found.pairs.values.len())?;
    Ok(found.pairs)
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

/// The eigenpairs `request` wants on a pencil the caller has analysed (and
/// may have used for static modes), by the solver the request names or
/// [`Solver::Auto`] picks for the pencil's size: `factor`, a factor of it
/// no longer needed, becomes the Lanczos operator or lends its storage.
///
/// For a free body, `request.held` gives the operator on a statically
/// determinate support ([`flexbody_linalg::lanczos::Held`]): `factor` is
/// then the held factor the inertia-relief attachment modes were solved
/// with, which serves the Lanczos run too (shift 0), and the rigid-body
/// modes (M-orthonormal) are among the modes returned.
pub fn eigenmodes_on(
    pencil: &Pencil,
    factor: Option<Factor>,
    request: &EigenRequest<'_>,
    progress: &dyn Progress,
) -> Result<EigenModes, ReduceError> {
    Ok(solve_on(pencil, factor, request, progress)?.pairs)
}

/// The solve of [`eigenmodes_on`] with its residuals; fewer modes than a
/// count asks for is an error.
fn solve_on(
    pencil: &Pencil,
    factor: Option<Factor>,
    request: &EigenRequest<'_>,
    progress: &dyn Progress,
) -> Result<EigenSolution, ReduceError> {
    available(request.wanted, pencil.dim())?;
    let found = pencil.eigen(factor, request, progress)?;
    available(request.wanted, found.pairs.values.len())?;
    Ok(found)
}
