//! The one eigen entry point: `K phi = lambda M phi` (report eq. 21,
//! undamped) by the solver that suits the request, chosen here.
//!
//! Two solvers stand behind [`eigen`] and [`Pencil::eigen`]:
//! - up to [`SPARSE_FROM`] equations (and whenever more than a quarter of
//!   all pairs is asked for, up to [`DENSE_LIMIT`]), the dense shift-invert
//!   solver of [`crate::eigen`], which is the faster and, for the low modes,
//!   the more accurate one there;
//! - from [`SPARSE_FROM`] equations on, the sparse shift-invert block
//!   Lanczos solver of [`crate::lanczos`] (one sparse `LDL^T` of
//!   `K - sigma M`, a Sturm check of the count).
//!
//! Either way the answer is a [`EigenSolution`]: the pairs, each pair's
//! residual `||K phi - lambda M phi|| / ||K phi||` (as
//! [`crate::lanczos::residuals`] defines it) and the work done.

use crate::eigen::{ensure_dense_room, generalized_symmetric, EigenPairs, Wanted};
use crate::lanczos::{lanczos_on, EigenSolution, Held, LanczosParams, LanczosStats};
use crate::ldlt::Factor;
use crate::memory::Budget;
use crate::pencil::Pencil;
use crate::progress::Progress;
use crate::{LinalgError, SparseMat};
use faer::Mat;

/// Largest pencil the dense solver takes.
pub const DENSE_LIMIT: usize = 6000;

/// Size from which [`Solver::Auto`] takes the sparse Lanczos solver. The
/// dense solver's work grows with the cube of the equations, the sparse
/// one's about linearly on meshes; the ignored test
/// `time_dense_against_sparse` (`cargo test --release -p flexbody-reduce
/// --test large -- --ignored`) times both. Below this size both are quick
/// and the dense solver (two shifts) is the more accurate one for the low
/// modes, so it keeps that range.
pub const SPARSE_FROM: usize = 300;

/// Which eigen solver serves a request.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// Dense below [`SPARSE_FROM`] equations (and for more than a quarter
    /// of all pairs up to [`DENSE_LIMIT`]), sparse Lanczos above.
    #[default]
    Auto,
    /// The dense solver (up to [`DENSE_LIMIT`] equations).
    Dense,
    /// The sparse Lanczos solver.
    Sparse,
}

impl Solver {
    /// Whether this choice takes the dense solver for `wanted` of an
    /// `n`-equation pencil.
    pub fn is_dense(self, n: usize, wanted: Wanted) -> bool {
        match self {
            Solver::Dense => true,
            Solver::Sparse => false,
            // A count caps a band's pairs too.
            Solver::Auto => match wanted.count() {
                Some(count) => n < SPARSE_FROM || (4 * count > n && n <= DENSE_LIMIT),
                None => n < SPARSE_FROM,
            },
        }
    }
}

/// What an eigen solve on a pencil is to find, and how.
#[derive(Copy, Clone, Debug)]
pub struct EigenRequest<'a> {
    /// The pairs wanted: a count, every one below a bound, or both.
    pub wanted: Wanted,
    /// Which solver ([`Solver::Auto`] chooses by size and count).
    pub solver: Solver,
    /// The Lanczos operator's shift (`None`: just below the spectrum, see
    /// [`LanczosParams::shift`]); the dense solver needs none.
    pub shift: Option<f64>,
    /// A free body's operator on its statically determinate support
    /// ([`Held`]); the dense solver finds the rigid-body modes itself.
    pub held: Option<Held<'a>>,
}

impl<'a> EigenRequest<'a> {
    /// `wanted` by the solver [`Solver::Auto`] chooses, at the default shift.
    pub fn new(wanted: Wanted) -> Self {
        Self {
            wanted,
            solver: Solver::Auto,
            shift: None,
            held: None,
        }
    }

    /// The request with its solver chosen.
    pub fn solver(self, solver: Solver) -> Self {
        Self { solver, ..self }
    }

    /// The request with the Lanczos operator at `shift`.
    pub fn shift(self, shift: f64) -> Self {
        Self {
            shift: Some(shift),
            ..self
        }
    }

    /// The request on the held operator of a free body.
    pub fn held(self, held: Held<'a>) -> Self {
        Self {
            held: Some(held),
            ..self
        }
    }
}

/// The `wanted` eigenpairs of `K phi = lambda M phi` for sparse symmetric
/// `k` (positive semi-definite) and `m` (positive semi-definite, `K + M`
/// positive definite) by `solver`, within the memory `budget` leaves. A
/// request for more pairs than the pencil has finite ones returns those it
/// has.
pub fn eigen(
    k: &SparseMat,
    m: &SparseMat,
    wanted: Wanted,
    solver: Solver,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<EigenSolution, LinalgError> {
    let n = k.nrows();
    if wanted.is_none() {
        return Ok(nothing(n));
    }
    if !solver.is_dense(n, wanted) {
        let params = LanczosParams::default();
        let t = std::time::Instant::now();
        let pencil = Pencil::analyze(k, m, None, params.ordering, progress)?.with_budget(budget);
        let seconds = t.elapsed().as_secs_f64();
        let mut found = lanczos_on(&pencil, None, wanted, None, &params, progress)?;
        found.stats.analysis_seconds = seconds;
        return Ok(found);
    }
    dense_limit(n)?;
    ensure_dense_room(n, 2, budget)?;
    let pairs = dense_all(k.to_dense(), m.to_dense())?;
    let pairs = wanted_of(pairs, wanted);
    let residuals = crate::lanczos::residuals(
        k,
        m,
        &pairs.values,
        pairs.vectors.as_ref(),
        &crate::sparse::diagonal(k),
    );
    Ok(dense_answer(pairs, residuals))
}

impl Pencil {
    /// The eigenpairs `request` wants, by the solver it names or the one
    /// [`Solver::Auto`] chooses for this pencil's size. On the sparse path
    /// `factor`, a factor of this pencil the caller no longer needs,
    /// becomes the Lanczos operator or lends it its storage (see
    /// [`lanczos_on`]); the dense path drops it. With `request.held`, the
    /// rigid-body modes (M-orthonormal) are among the modes returned either
    /// way. A request for more pairs than the pencil has finite ones
    /// returns those it has.
    pub fn eigen(
        &self,
        factor: Option<Factor>,
        request: &EigenRequest<'_>,
        progress: &dyn Progress,
    ) -> Result<EigenSolution, LinalgError> {
        let n = self.dim();
        if request.wanted.is_none() {
            return Ok(nothing(n));
        }
        if !request.solver.is_dense(n, request.wanted) {
            let params = LanczosParams {
                shift: request.shift,
                ..Default::default()
            };
            return lanczos_on(
                self,
                factor,
                request.wanted,
                request.held,
                &params,
                progress,
            );
        }
        drop(factor);
        dense_limit(n)?;
        ensure_dense_room(n, 2, self.budget())?;
        let (k, m) = self.to_dense();
        let pairs = wanted_of(dense_all(k, m)?, request.wanted);
        let residuals = self.residuals(&pairs);
        Ok(dense_answer(pairs, residuals))
    }
}

/// No pairs, for a request of none.
fn nothing(n: usize) -> EigenSolution {
    dense_answer(
        EigenPairs {
            values: vec![],
            vectors: Mat::zeros(n, 0),
        },
        vec![],
    )
}

/// The dense solver's answer: no shift, no Sturm check, no Lanczos run.
fn dense_answer(pairs: EigenPairs, residuals: Vec<f64>) -> EigenSolution {
    EigenSolution {
        pairs,
        residuals,
        shift: 0.0,
        sturm: None,
        stats: LanczosStats {
            dense: true,
            ..Default::default()
        },
    }
}

/// [`LinalgError::TooLargeForDense`] beyond [`DENSE_LIMIT`].
fn dense_limit(n: usize) -> Result<(), LinalgError> {
    if n > DENSE_LIMIT {
        return Err(LinalgError::TooLargeForDense {
            dofs: n,
            limit: DENSE_LIMIT,
        });
    }
    Ok(())
}

/// The pairs of `all` (ascending) that `wanted` asks for, at most all.
fn wanted_of(all: EigenPairs, wanted: Wanted) -> EigenPairs {
    let count = wanted.kept(&all.values);
    if count == all.values.len() {
        all
    } else {
        all.slice(0, count)
    }
}

/// Every finite eigenpair of dense `k` and `m` (as many as equations,
/// less those that carry no mass), refusing clearly negative eigenvalues.
fn dense_all(k: Mat<f64>, m: Mat<f64>) -> Result<EigenPairs, LinalgError> {
    let pairs = generalized_symmetric(k.as_ref(), m.as_ref())?;
    drop((k, m));
    // Round-off zeros of rigid-body modes may be slightly negative; an
    // eigenvalue below -1e-8 of the largest is not round-off.
    let bound = crate::dense_check::round_off_zero(&pairs.values, 0.0);
    let count = pairs.values.iter().filter(|&&l| l < bound).count();
    if count > 0 {
        return Err(LinalgError::NotSemiDefinite { count, bound });
    }
    Ok(pairs)
}

#[cfg(test)]
mod tests;
