//! Eigenmodes (report 5.3, eq. 21 undamped): `K phi = lambda M phi` of the
//! free body, of the body fixed at its interface DOFs, or of the body on
//! elastic supports (pass `K + C`).
//!
//! The functions take sparse matrices; the solver behind them is, for now,
//! the dense shift-invert one of [`flexbody_linalg::eigen`], up to
//! [`DENSE_LIMIT`] DOFs.

use super::{complement, expand};
use crate::ReduceError;
use faer::Mat;
use flexbody_linalg::eigen::generalized_symmetric;
use flexbody_linalg::{sparse, SparseMat};

/// Largest model the dense eigen path accepts.
pub const DENSE_LIMIT: usize = 6000;

/// The lowest eigenpairs, M-orthonormal (`Phi^T M Phi = I`), ascending;
/// eigenvalues lambda = omega^2 (rad^2/s^2).
pub use flexbody_linalg::eigen::EigenPairs as EigenModes;

/// The lowest `count` eigenpairs of `K phi = lambda M phi`.
pub fn eigenmodes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    count: usize,
) -> Result<EigenModes, ReduceError> {
    let n = stiffness.nrows();
    if n > DENSE_LIMIT {
        return Err(ReduceError::TooLargeForDense {
            dofs: n,
            limit: DENSE_LIMIT,
        });
    }
    if count == 0 {
        return Ok(EigenModes {
            values: vec![],
            vectors: Mat::zeros(n, 0),
        });
    }
    let pairs = generalized_symmetric(stiffness.to_dense().as_ref(), mass.to_dense().as_ref())?;
    let available = pairs.values.len();
    if count > available {
        return Err(ReduceError::NotEnoughModes {
            requested: count,
            available,
        });
    }
    Ok(EigenModes {
        values: pairs.values[..count].to_vec(),
        vectors: pairs.vectors.subcols(0, count).to_owned(),
    })
}

/// Eigenmodes of the body held at the `boundary` equations (zero there).
pub fn fixed_interface_eigenmodes(
    stiffness: &SparseMat,
    mass: &SparseMat,
    boundary: &[usize],
    count: usize,
) -> Result<EigenModes, ReduceError> {
    let n = stiffness.nrows();
    let interior = complement(boundary, n);
    let k = sparse::submatrix(stiffness, &interior, &interior);
    let m = sparse::submatrix(mass, &interior, &interior);
    let modes = eigenmodes(&k, &m, count)?;
    Ok(EigenModes {
        vectors: expand(&modes.vectors, &interior, n),
        values: modes.values,
    })
}
