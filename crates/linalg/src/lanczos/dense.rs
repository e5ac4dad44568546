//! The dense fallback: a count whose Lanczos basis would fill the model
//! goes to [`crate::eigen::generalized_symmetric`] on `K` and `M` formed
//! from the pencil.

use super::run::basis_for;
use super::LanczosParams;
use crate::eigen::{EigenPairs, Wanted};
use crate::pencil::Pencil;
use crate::progress::{Progress, Stage};
use crate::LinalgError;

/// Whether a Lanczos basis for `nev` eigenpairs would fill the `free`
/// dimensions: a Krylov space that exhausts the space leaves nothing to
/// restart with, and its last blocks, round-off after the projections,
/// gave spurious pairs (the 6 x 6 x 6 cube's 900 lowest of 1029: residuals
/// of 0.7 and 750 eigenvalues more than the Sturm count). The dense solver
/// takes such a problem.
pub(super) fn spans_the_space(nev: usize, free: usize, params: &LanczosParams) -> bool {
    nev > 0 && basis_for(nev, params.block_size.max(1), params) >= free
}

/// The wanted pairs from dense `K` and `M` (formed by the pencil's
/// products with the identity) and [`crate::eigen::generalized_symmetric`],
/// for a count [`spans_the_space`], with their residuals. For a band, the
/// eigenvalues below the bound are the dense solver's (at most the count of
/// [`Wanted::LowestBelow`]).
pub(super) fn dense_pairs(
    pencil: &Pencil,
    wanted: Wanted,
    nev: usize,
    progress: &dyn Progress,
) -> Result<(EigenPairs, Vec<f64>), LinalgError> {
    let n = pencil.dim();
    crate::eigen::ensure_dense_room(n, 2, pencil.budget()).map_err(|err| {
        LinalgError::Unservable(format!(
            "{nev} eigenpairs of a {n}-equation model are too many for Lanczos (its \
             basis would span the model), and the dense solver does not fit: {err}"
        ))
    })?;
    progress.report(&Stage::DenseEigen {
        equations: n,
        wanted: nev,
    });
    let (k, m) = pencil.to_dense();
    let all = crate::eigen::generalized_symmetric(k.as_ref(), m.as_ref())?;
    drop((k, m));
    // A count alone asks for that many; with a bound, for those below it.
    let keep = match wanted {
        Wanted::Lowest(count) => count,
        band => band.kept(&all.values),
    };
    if keep > all.values.len() {
        return Err(LinalgError::Unservable(format!(
            "{keep} eigenpairs wanted of a {n}-equation model with {} finite ones",
            all.values.len()
        )));
    }
    let pairs = all.slice(0, keep);
    drop(all);
    let residuals = pencil.residuals(&pairs);
    Ok((pairs, residuals))
}
