//! Solves with the matrices of the MBS equations: the dynamic stiffness
//! `K - Omega^2 M (+ i Omega D)` of a harmonic response and the Jacobian
//! of a time step, both symmetric. A full FE model makes them as large as
//! the model, so they take the sparse `LDL^T` of the eigen solver (nested
//! dissection on large models), which needs no pivoting where the matrix
//! is definite and mostly none where it is not. Where a pivot vanishes, or
//! the solution misses its residual check, faer's sparse LU with pivoting
//! takes over; on a large model the LU, without the ordering for nested
//! dissection, takes far more time and memory than the `LDL^T`.

use crate::MbsError;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Lu;
use faer::{Mat, MatRef};
use flexbody_linalg::ldlt;
use flexbody_linalg::SparseMat;

/// A factorisation for repeated solves with one matrix.
pub(crate) enum Factor {
    /// The symmetric `LDL^T` without pivoting.
    Symmetric(ldlt::Factor),
    /// faer's sparse LU with pivoting.
    General(Box<Lu<usize, f64>>),
}

impl Factor {
    /// `a`'s `LDL^T` if it exists and solves a probe `a z` back to `z`
    /// within the residual check (a matrix that is not symmetric fails
    /// there: only one triangle is read); else its LU. A singular `a` is
    /// an error at `omega` (rad/s).
    pub(crate) fn new(a: &SparseMat, omega: f64) -> Result<Self, MbsError> {
        if let Ok(f) = ldlt::Factor::of(a) {
            let z = Mat::from_fn(a.nrows(), 1, |i, _| 1.0 + (i % 7) as f64);
            let rhs = a * &z;
            if accurate(a, &f.solve(rhs.as_ref()), &rhs) {
                return Ok(Factor::Symmetric(f));
            }
        }
        let lu = a.sp_lu().map_err(|_| MbsError::Singular { omega })?;
        Ok(Factor::General(Box::new(lu)))
    }

    pub(crate) fn solve(&self, b: MatRef<'_, f64>) -> Mat<f64> {
        match self {
            Factor::Symmetric(f) => f.solve(b),
            Factor::General(lu) => lu.solve(b),
        }
    }
}

/// Solves the symmetric `a x = b` for each right-hand side in `b`, with
/// the residual check (a singular matrix shows up as a non-finite or
/// inaccurate solution): by the `LDL^T`, or where that misses the check,
/// by the LU.
pub(crate) fn solve(a: &SparseMat, b: &[Vec<f64>], omega: f64) -> Result<Vec<Vec<f64>>, MbsError> {
    let rhs = Mat::from_fn(a.nrows(), b.len(), |i, j| b[j][i]);
    let by_ldlt = ldlt::Factor::of(a)
        .ok()
        .map(|f| f.solve(rhs.as_ref()))
        .filter(|x| accurate(a, x, &rhs));
    let x = match by_ldlt {
        Some(x) => x,
        None => solve_lu(a, &rhs, omega)?,
    };
    Ok((0..b.len())
        .map(|j| x.col(j).iter().copied().collect())
        .collect())
}

/// `a x = rhs` by faer's sparse LU, with the residual check.
pub(crate) fn solve_lu(a: &SparseMat, rhs: &Mat<f64>, omega: f64) -> Result<Mat<f64>, MbsError> {
    let lu = a.sp_lu().map_err(|_| MbsError::Singular { omega })?;
    let x = lu.solve(rhs.as_ref());
    if accurate(a, &x, rhs) {
        Ok(x)
    } else {
        Err(MbsError::Singular { omega })
    }
}

/// Whether `x` is finite and solves `a x = rhs` to 1e-8 of the scale of
/// its terms.
fn accurate(a: &SparseMat, x: &Mat<f64>, rhs: &Mat<f64>) -> bool {
    let r = a * x - rhs;
    let a_max = a.as_ref().val().iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let scale = a_max * x.norm_max() + rhs.norm_max();
    let finite = x.col_iter().all(|c| c.iter().all(|v| v.is_finite()));
    finite && r.norm_max() <= 1e-8 * scale
}
