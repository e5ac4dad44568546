//! Sparse generalized symmetric eigen solver for `K x = lambda M x` (report
//! eq. 21, undamped): shift-invert block Lanczos with thick (Krylov-Schur)
//! restart in the `M` inner product, on one sparse `LDL^T` of `K - sigma M`.
//!
//! # The method
//! With a shift `sigma` below the wanted eigenvalues (negative for a free
//! body, whose `K` is singular), the operator
//! `OP = (K - sigma M)^-1 M` is self-adjoint in the `M` inner product and has
//! the eigenvalues `theta = 1 / (lambda - sigma)`: the lowest `lambda` become
//! the largest, well separated `theta`. A block Krylov basis `V`
//! (`V^T M V = I`, built `b` vectors at a time, one block solve per step,
//! fully re-orthogonalised twice) satisfies
//! `OP V = V H + Q B E^T` with `H = V^T M OP V` symmetric. The Ritz pairs
//! `(theta_i, V y_i)` of `H` have the residual `||OP x - theta x||_M = ||B E^T y_i||`,
//! so convergence (`<= tolerance * theta_i`) is read off without touching
//! `K`. When the basis is full, it is contracted to the best Ritz vectors
//! plus `Q` (thick restart) and the Krylov relation continues with an
//! arrowhead `H`; the converged wanted Ritz vectors are locked there (their
//! couplings set to zero, out of the Rayleigh-Ritz problem), so that a run
//! for hundreds of modes does not lose converged ones to round-off while
//! it refines the rest. A block of `b` vectors finds eigenvalues of multiplicity up
//! to `b` (the 6 rigid-body modes of a free body, the pairs of a square
//! section) in one run.
//!
//! # The Sturm check, and shifts above the band
//! By Sylvester's law of inertia the number of negative pivots of the
//! `LDL^T` of `K - s M` is the number of eigenvalues below `s`. After the
//! run, `s` is placed just above the highest wanted eigenvalue; when the count
//! exceeds what was found (a multiplicity larger than the block, a missed
//! cluster), the solver reports it through [`Progress`], locks the found
//! vectors and runs again until it has them all, on the check's own factor:
//! `-(K - s M)^-1 M`, whose positive `theta = 1 / (s - lambda)` are exactly
//! the eigenvalues below `s`, the largest nearest it.
//!
//! A band ([`Wanted::Below`]) is counted at its bound before any run, and
//! the check sits on the bound. A count below a bound
//! ([`Wanted::LowestBelow`]) is counted there too: where no more than the
//! count lie below the bound it is that band; otherwise the count cuts
//! it, and the run and its check are those of the count alone, so no run
//! looks for the band's pairs above the lowest `count`.
//!
//! That factor also finishes a run that stalls: when four sweeps in a row
//! past the first restart converge no new wanted pair (with every wanted
//! Ritz value already close), the run stops. The sweeps that fill the
//! basis do not count: a large block, or a free body whose elastic modes
//! converge only after the rigid-body ones, reaches the first restart
//! with nothing new converged. A basis held small
//! ([`LanczosParams::basis_size`] a few blocks above the count) leaves each
//! restart little room to grow, and so do clusters at the band's top. The
//! Sturm shift then goes just above the `nev`-th Ritz value (an upper
//! bound of its eigenvalue), into the gap to the next one, and the run
//! continues there from the unconverged Ritz vectors, locked pairs
//! deflated. Near the shift the rest converge in a few sweeps. Should that
//! run stall too (modes still far below), the shift moves down, just above
//! the highest unconverged one, at most four times, each move one
//! factorisation more and a count of its own; the count at the band's top
//! decides when the solve is complete. The Rayleigh-Ritz step decomposes
//! `H` with [`crate::eigen::symmetric_eigen`], which scales it first: `H`
//! of a shift-invert operator has a norm near `1 / lambda` (1e-9 and
//! below), where an unscaled decomposition holds the residuals near 1e-6.
//!
//! # Counts too large for a basis
//! A run for `nev` pairs keeps a basis of `2 nev + 4 b` vectors. Where
//! that would fill the model (about half its modes or more, for a band
//! after its count), a Krylov space has nothing left to restart with and
//! its last blocks are round-off: the dense solver
//! ([`crate::eigen::generalized_symmetric`] on `K` and `M` formed from the
//! pencil) takes the problem instead, within the memory check
//! ([`crate::eigen::ensure_dense_room`]); [`LanczosStats::dense`] says so.
//! A Sturm check whose count differs from the eigenvalues found below its
//! bound, after the runs it allows, is an error: no mode set is returned
//! with a mode missing or found twice.
//!
//! # Residuals
//! Each mode's residual is `||K x - lambda M x|| / ||K x||`; for a rigid-body
//! mode, whose `K x` is itself round-off, the denominator is the floor
//! `||K|| ||x||` (with `||K||` the largest diagonal entry of `K`), used when
//! `max(||K x||, |lambda| ||M x||) < 1e-8 ||K|| ||x||`. This is the measure
//! `flexbody modes` prints.
//!
//! # The code
//! [`lanczos_on`] runs a small state machine (`solver.rs`): the count of
//! the pairs wanted, the first run, the Sturm check with the shift moves
//! after it (`sturm.rs`), and the finish (`finish.rs`: ordering,
//! orthonormality, residuals), or the dense fallback (`dense.rs`). A run
//! (`run.rs`) is one thick-restart block Lanczos iteration on the operator
//! of one factor (`operator.rs`), its blocks M-orthonormalised in
//! `block_qr.rs`.

mod block_qr;
mod dense;
mod finish;
mod operator;
mod run;
mod solver;
mod sturm;

use crate::eigen::EigenPairs;
use crate::eigen::Wanted;
use crate::ldlt::Factor;
use crate::ordering::Ordering;
use crate::pencil::Pencil;
use crate::progress::Progress;
use crate::sparse::symmetric_mul;
use crate::{LinalgError, SparseMat};
use faer::MatRef;
pub(crate) use finish::residuals_of;
use solver::Solver;
use std::time::Instant;

/// Tuning of [`lanczos`].
#[derive(Copy, Clone, Debug)]
pub struct LanczosParams {
    /// Vectors per Lanczos block: right-hand sides per sweep through `L`,
    /// and the largest multiplicity found without a Sturm restart.
    pub block_size: usize,
    /// Largest basis (vectors kept between restarts plus new ones); 0 takes
    /// `2 nev + 4 block_size`.
    pub basis_size: usize,
    /// A Ritz pair is converged when `||OP x - theta x||_M <= tolerance * theta`.
    pub tolerance: f64,
    /// The shift `sigma`; `None` takes `-1e-6 trace(K) / trace(M)`, below
    /// every eigenvalue and scaled to the model.
    pub shift: Option<f64>,
    /// Largest number of block expansions before giving up.
    pub max_steps: usize,
    /// Factorise `K - s M` once more above the highest wanted eigenvalue and
    /// compare the inertia with the modes found (costs one factorisation),
    /// continuing on that factor where modes are missing or where the run
    /// stalls (see the module docs). Without it a count is not checked and
    /// a stalled run goes on at its first shift.
    pub sturm_check: bool,
    /// Runs after the first that a Sturm check still missing eigenvalues
    /// allows before the solve is an error (0: the first run must find
    /// them all).
    pub sturm_runs: usize,
    /// Fill-reducing ordering of the factorisations.
    pub ordering: Ordering,
}

impl Default for LanczosParams {
    fn default() -> Self {
        Self {
            block_size: 8,
            basis_size: 0,
            tolerance: 1e-12,
            shift: None,
            max_steps: 1000,
            sturm_check: true,
            sturm_runs: 16,
            ordering: Ordering::Auto,
        }
    }
}

/// The operator of a free body on a statically determinate support (report
/// 5.2.2, eq. 20): `K` held at the `support` equations is regular, and on
/// loads in equilibrium (`P = I - M T T^T`, `T` the M-orthonormal
/// rigid-body modes) its inverse is the elastic flexibility, so
/// `OP = T_perp K_held^-1 P M` has `theta = 1 / lambda` on the elastic
/// modes: shift-invert at shift 0, on the factor the inertia-relief
/// attachment modes use. The rigid-body modes enter as known (`lambda =
/// 0`), the Lanczos run deflates them.
#[derive(Copy, Clone, Debug)]
pub struct Held<'a> {
    pub support: &'a [usize],
    pub rigid: MatRef<'a, f64>,
}

/// Outcome of the Sturm check.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SturmReport {
    /// The shift `s` of the check (rad^2/s^2).
    pub bound: f64,
    /// Eigenvalues below `bound` by the inertia of `K - bound M`.
    pub count: usize,
    /// Eigenvalues below `bound` the first Lanczos run found; less than
    /// `count` means the solver had to continue.
    pub found_first: usize,
    /// Eigenvalues below `bound` found in the end.
    pub found: usize,
}

/// Work and time spent.
#[derive(Clone, Debug, Default)]
pub struct LanczosStats {
    /// The ordering used.
    pub ordering: Ordering,
    /// Entries of the factor `L`.
    pub factor_len: usize,
    /// Right-hand sides solved with the shifted factor.
    pub solves: usize,
    /// Block solves (sweeps through `L`).
    pub block_solves: usize,
    /// Thick restarts.
    pub restarts: usize,
    /// Lanczos runs (more than one after a failed Sturm check).
    pub runs: usize,
    /// The wanted pairs were too many for a Lanczos basis (it would span
    /// the whole space) and came from the dense solver (see
    /// [`lanczos_on`]); no Lanczos run was made.
    pub dense: bool,
    pub analysis_seconds: f64,
    pub factorization_seconds: f64,
    /// Lanczos iterations (solves, products with `M`,
    /// orthogonalisation, Rayleigh-Ritz), without the Sturm check.
    pub iteration_seconds: f64,
    /// Of which the block solves with the shifted factor.
    pub solve_seconds: f64,
    /// Of which the products with `M`.
    pub mass_seconds: f64,
    /// Right-hand sides multiplied by `M` in the iterations.
    pub mass_products: usize,
    pub sturm_seconds: f64,
}

/// The eigenpairs with their residuals and how they were obtained, as
/// both solvers return them ([`crate::solver`]); the dense solver's has
/// shift 0, no Sturm check and [`LanczosStats::dense`] set.
#[derive(Clone, Debug)]
pub struct EigenSolution {
    /// Eigenvalues (ascending) and M-orthonormal eigenvectors.
    pub pairs: EigenPairs,
    /// `||K x - lambda M x|| / ||K x||` per mode (see the module docs for the
    /// floor of rigid-body modes).
    pub residuals: Vec<f64>,
    /// The shift `sigma` of the Lanczos operator.
    pub shift: f64,
    /// The Sturm check, if one was made.
    pub sturm: Option<SturmReport>,
    pub stats: LanczosStats,
}

/// The wanted eigenpairs of `K x = lambda M x` for sparse symmetric `K`
/// (positive semi-definite) and `M` (positive semi-definite, `K + M`
/// positive definite), within the machine's memory ([`Pencil::with_budget`]
/// and [`lanczos_on`] hold a run to a user's budget).
pub fn lanczos(
    k: &SparseMat,
    m: &SparseMat,
    wanted: Wanted,
    params: &LanczosParams,
    progress: &dyn Progress,
) -> Result<EigenSolution, LinalgError> {
    let t = Instant::now();
    let pencil = Pencil::analyze(k, m, None, params.ordering, progress)?;
    let seconds = t.elapsed().as_secs_f64();
    let mut found = lanczos_on(&pencil, None, wanted, None, params, progress)?;
    found.stats.analysis_seconds = seconds;
    Ok(found)
}

/// [`lanczos`] on a pencil the caller has analysed, e.g. to solve static
/// modes with the same analysis first. A `factor` of the pencil that the
/// caller no longer needs becomes the Lanczos operator when its shift is
/// `params.shift`; otherwise its storage is reused. With `held`, the
/// operator is the free body's on its support ([`Held`]) at shift 0, and
/// `factor`, if given, must be the held factor
/// ([`Pencil::factorize_static`] of `held.support`), and a count
/// must ask for at least one elastic mode.
pub fn lanczos_on(
    pencil: &Pencil,
    factor: Option<Factor>,
    wanted: Wanted,
    held: Option<Held<'_>>,
    params: &LanczosParams,
    progress: &dyn Progress,
) -> Result<EigenSolution, LinalgError> {
    Solver::new(pencil, factor, wanted, held, params, progress)?.solve()
}

/// `||K x - lambda M x|| / ||K x||` per column, with the rigid-body floor
/// `||K|| ||x||` of the module docs.
pub fn residuals(
    k: &SparseMat,
    m: &SparseMat,
    values: &[f64],
    vectors: MatRef<'_, f64>,
    k_diag: &[f64],
) -> Vec<f64> {
    let kx = symmetric_mul(k, vectors);
    let mx = symmetric_mul(m, vectors);
    residuals_of(&kx, &mx, values, vectors, k_diag)
}

#[cfg(test)]
mod tests;
