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

use crate::eigen::EigenPairs;
use crate::eigen::Wanted;
use crate::ordering::Ordering;
use crate::progress::{Progress, Stage};
use crate::shift_invert::{ShiftedFactor, ShiftedPencil};
use crate::sparse::symmetric_mul;
use crate::tall;
use crate::{LinalgError, SparseMat};
use faer::{ColRef, Mat, MatMut, MatRef, Side};
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

/// The eigenpairs with their residuals and how they were obtained.
#[derive(Clone, Debug)]
pub struct SparseEigen {
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
/// positive definite).
pub fn lanczos(
    k: &SparseMat,
    m: &SparseMat,
    wanted: Wanted,
    params: &LanczosParams,
    progress: &dyn Progress,
) -> Result<SparseEigen, LinalgError> {
    let t = Instant::now();
    let pencil = ShiftedPencil::analyze_reporting(k, m, params.ordering, progress)?;
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
/// ([`ShiftedPencil::factorize_static`] of `held.support`), and a count
/// must ask for at least one elastic mode.
pub fn lanczos_on(
    pencil: &ShiftedPencil,
    factor: Option<ShiftedFactor>,
    wanted: Wanted,
    held: Option<Held<'_>>,
    params: &LanczosParams,
    progress: &dyn Progress,
) -> Result<SparseEigen, LinalgError> {
    let start = Instant::now();
    let n = pencil.dim();
    let mut stats = LanczosStats {
        ordering: pencil.ordering(),
        factor_len: pencil.factor_len(),
        ..Default::default()
    };
    let k_diag = pencil.stiffness_diagonal();
    let m_diag = pencil.mass_diagonal();
    let trace_k: f64 = k_diag.iter().map(|v| v.abs()).sum();
    let trace_m: f64 = m_diag.iter().map(|v| v.abs()).sum();
    if trace_m == 0.0 || n == 0 {
        return Err(LinalgError::NoMass);
    }
    let sigma = match held {
        Some(_) => 0.0,
        None => params
            .shift
            .unwrap_or(-1e-6 * (trace_k / trace_m).max(f64::MIN_POSITIVE)),
    };
    let (factor, spare) = match factor {
        Some(f) if held.is_some() && f.is_fixed() => (Some(f), Vec::new()),
        Some(f) if held.is_none() && !f.is_fixed() && f.shift() == sigma => (Some(f), Vec::new()),
        Some(f) => (None, f.into_storage()),
        None => (None, Vec::new()),
    };
    if let (Some(h), Wanted::Lowest(count)) = (&held, wanted) {
        // The Sturm check's bound lies just above the highest mode found:
        // with the rigid-body modes alone it would sit on them.
        if count <= h.rigid.ncols() {
            return Err(LinalgError::Dimension(format!(
                "{count} modes of a free body with {} rigid-body modes: the held \
                 operator needs at least one elastic mode",
                h.rigid.ncols()
            )));
        }
    }
    let held = held.map(|h| HeldState {
        m_rigid: pencil.mul_mass(h.rigid),
        held: h,
    });
    let mut op = Operator {
        pencil,
        sigma,
        sign: 1.0,
        held: held.as_ref(),
        factor,
        spare,
        progress,
        solves: 0,
        block_solves: 0,
        solve_seconds: 0.0,
        mass_seconds: 0.0,
        mass_products: 0,
        factorization_seconds: 0.0,
        sturm_seconds: 0.0,
    };
    // For a band, the Sturm count at its upper bound is the number wanted.
    let mut sturm: Option<(f64, usize)> = None;
    let nev = match wanted {
        Wanted::Lowest(count) => count,
        Wanted::Below(bound) => {
            let count = op.sturm_count(bound)?;
            sturm = Some((bound, count));
            count
        }
    };
    let known = held.as_ref().map_or(0, |h| h.held.rigid.ncols());
    if spans_the_space(nev.saturating_sub(known), n - known.min(n), params) {
        stats.factorization_seconds = op.factorization_seconds;
        stats.sturm_seconds = op.sturm_seconds;
        drop(op);
        return dense_pairs(pencil, wanted, nev, sturm, sigma, stats, progress, start);
    }
    op.ensure_room(nev.saturating_sub(known), params)?;
    op.factorize()?;
    if nev == 0 {
        stats.factorization_seconds = op.factorization_seconds;
        stats.sturm_seconds = op.sturm_seconds;
        return Ok(SparseEigen {
            pairs: EigenPairs {
                values: vec![],
                vectors: Mat::zeros(n, 0),
            },
            residuals: vec![],
            shift: sigma,
            sturm: sturm.map(|(bound, count)| SturmReport {
                bound,
                count,
                found_first: 0,
                found: 0,
            }),
            stats,
        });
    }
    let first_factorization = op.factorization_seconds;
    let band_count_seconds = op.sturm_seconds;
    let t = Instant::now();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    // The rigid-body modes of a held operator are known: lambda = 0.
    let mut locked = match &held {
        Some(h) => Locked {
            x: h.held.rigid.to_owned(),
            lambda: vec![0.0; h.held.rigid.ncols()],
        },
        None => Locked {
            x: Mat::zeros(n, 0),
            lambda: vec![],
        },
    };
    let checked = params.sturm_check || sturm.is_some();
    let left = nev.saturating_sub(locked.lambda.len());
    let mut stalled = None;
    if left > 0 {
        let run = krylov_schur(
            &mut op,
            &locked,
            left,
            params,
            progress,
            &mut rng,
            &mut stats,
            if checked { STALL_SWEEPS } else { 0 },
            None,
        )?;
        locked.append(run.converged);
        stalled = run.stalled;
    }
    let mut report = None;
    if checked {
        let below = |l: &Locked, bound: f64| l.lambda.iter().filter(|&&x| x < bound).count();
        // The first run's blocks are free now: their pages go back before
        // the Sturm factorisation takes its own.
        crate::memory::release_free_memory();
        let (mut bound, count) = match sturm {
            Some((bound, count)) => (bound, count),
            None => {
                let v =
                    found_and_ritz(&locked, stalled.as_ref().map_or(&[][..], |s| &s.lambda[..]));
                let top = v[nev.min(v.len()) - 1];
                let shift = if stalled.is_some() {
                    shift_above(&v, top, (top - sigma).abs())
                } else {
                    top + 1e-4 * (top - sigma).abs()
                };
                op.move_above(shift)?
            }
        };
        let found_first = below(&locked, bound);
        // The operator's shift above the wanted band (or, after a stall
        // there, below it: a slice of the band) and its count.
        let mut slice = (bound, count);
        let mut start = stalled.map(|s| s.start);
        let (mut attempts, mut moves) = (0, 0);
        loop {
            let have = below(&locked, bound);
            progress.report(&Stage::SturmCheck {
                bound,
                count,
                found: have,
            });
            // Eigenvalues within round-off of the bound (a band's bound on
            // a frequency) may fall on either side of the count.
            let tol = 1e-10 * bound.abs();
            let (surely, maybe) = (below(&locked, bound - tol), below(&locked, bound + tol));
            if surely > count {
                // More eigenvalues below the bound than it has: pairs found
                // twice or spurious ones (lost orthogonality). Never
                // returned as modes.
                return Err(LinalgError::SturmSpurious {
                    found: have,
                    count,
                    bound,
                });
            }
            if maybe >= count {
                report = Some(SturmReport {
                    bound,
                    count,
                    found_first,
                    found: have,
                });
                break;
            }
            if attempts == params.sturm_runs {
                return Err(LinalgError::SturmMissing {
                    found: have,
                    count,
                    bound,
                    runs: attempts,
                });
            }
            if op.sign > 0.0 || (slice.0 != bound && below(&locked, slice.0) >= slice.1) {
                // Back to the band's top: a band's count came first, or a
                // slice below it is complete.
                (bound, _) = op.move_above(bound)?;
                slice = (bound, count);
            }
            attempts += 1;
            let run = krylov_schur(
                &mut op,
                &locked,
                slice.1 - below(&locked, slice.0),
                params,
                progress,
                &mut rng,
                &mut stats,
                // A move below the band's top costs a factorisation more.
                if moves < MAX_MOVES {
                    2 * STALL_SWEEPS
                } else {
                    0
                },
                start.take().as_ref().map(|x| x.as_ref()),
            )?;
            locked.append(run.converged);
            if let Some(stalled) = run.stalled {
                // The rest lie farther below this shift: a slice below it,
                // just above the highest of them.
                moves += 1;
                let hi = stalled.lambda.iter().copied().fold(f64::MIN, f64::max);
                let v = found_and_ritz(&locked, &stalled.lambda);
                let shift = shift_above(&v, hi, (hi - sigma).abs()).min(slice.0);
                if shift < slice.0 {
                    slice = op.move_above(shift)?;
                } else {
                    moves = MAX_MOVES;
                }
                start = Some(stalled.start);
            }
        }
    }
    progress.report(&Stage::LanczosDone {
        solves: op.solves,
        block_solves: op.block_solves,
        solve_seconds: op.solve_seconds,
        products: op.mass_products,
        mass_seconds: op.mass_seconds,
        seconds: t.elapsed().as_secs_f64() - (op.sturm_seconds - band_count_seconds),
    });
    stats.solves = op.solves;
    stats.block_solves = op.block_solves;
    stats.solve_seconds = op.solve_seconds;
    stats.mass_seconds = op.mass_seconds;
    stats.mass_products = op.mass_products;
    stats.factorization_seconds = op.factorization_seconds;
    stats.sturm_seconds = op.sturm_seconds;
    stats.iteration_seconds = t.elapsed().as_secs_f64()
        - (stats.sturm_seconds - band_count_seconds)
        - (stats.factorization_seconds - first_factorization);
    drop(op);

    // Ascending lambda, the wanted ones.
    let mut order: Vec<usize> = (0..locked.lambda.len()).collect();
    order.sort_by(|&a, &b| locked.lambda[a].total_cmp(&locked.lambda[b]));
    let keep = match wanted {
        Wanted::Lowest(count) => count.min(order.len()),
        Wanted::Below(bound) => order.iter().filter(|&&i| locked.lambda[i] < bound).count(),
    };
    order.truncate(keep);
    let mut vectors = Mat::from_fn(n, order.len(), |i, j| locked.x[(i, order[j])]);
    drop(locked);
    let mut mx = pencil.mul_mass(vectors.as_ref());
    if stats.runs > 1 {
        // Runs after the first, on shifts above the band where the
        // operator's |theta| is large, leave their vectors M-orthogonal to
        // some 1e-10 only. Cholesky QR in ascending lambda restores it and
        // changes each vector by the ones below it only: a low mode takes
        // in no part of a high one (which would cost its residual that part
        // times lambda_high / lambda_low).
        let mut g = tall::gram(vectors.as_ref(), mx.as_ref());
        crate::sparse::symmetrize(&mut g);
        let l = g
            .llt(Side::Lower)
            .map_err(|err| LinalgError::Faer(format!("{err:?}")))?
            .L()
            .to_owned();
        for x in [vectors.as_mut(), mx.as_mut()] {
            tall::div_upper(x, l.transpose());
        }
    }
    let mut kx = pencil.mul_stiffness(vectors.as_ref());
    let mut values: Vec<f64> = (0..vectors.ncols())
        .map(|j| dot(vectors.col(j), kx.col(j)) / dot(vectors.col(j), mx.col(j)))
        .collect();
    // The Rayleigh quotients may swap neighbours the Ritz values ordered
    // (repeated eigenvalues, rigid-body modes at round-off): ascending again.
    for j in 1..values.len() {
        let mut i = j;
        while i > 0 && values[i - 1] > values[i] {
            values.swap(i - 1, i);
            for x in [&mut vectors, &mut mx, &mut kx] {
                swap_columns(x, i - 1, i);
            }
            i -= 1;
        }
    }
    let residuals = residuals_of(&kx, &mx, &values, vectors.as_ref(), &k_diag);
    progress.report(&Stage::Done {
        seconds: start.elapsed().as_secs_f64(),
    });
    Ok(SparseEigen {
        pairs: EigenPairs { values, vectors },
        residuals,
        shift: sigma,
        sturm: report,
        stats,
    })
}

/// Swaps columns `a < b` of `x`.
fn swap_columns(x: &mut Mat<f64>, a: usize, b: usize) {
    let (left, right) = x.as_mut().split_at_col_mut(b);
    let (mut p, mut q) = (left.col_mut(a), right.col_mut(0));
    for i in 0..p.nrows() {
        std::mem::swap(&mut p[i], &mut q[i]);
    }
}

/// The eigenvalues found and the Ritz values of a stalled run, ascending.
fn found_and_ritz(locked: &Locked, ritz: &[f64]) -> Vec<f64> {
    let mut v = [locked.lambda.as_slice(), ritz].concat();
    v.sort_by(f64::total_cmp);
    v
}

/// A shift just above `top` for an operator that is to converge the
/// eigenvalues below it, given the known eigenvalues and Ritz values `v`:
/// halfway to the next value above `top`, at most `0.05 span` and at least
/// `1e-4 span` above `top` (the count then includes any eigenvalue in
/// between). Its round-off is that of its largest `|theta| = 1 / |lambda -
/// shift|`: a shift in the gap, not on its edge, keeps the residuals of
/// the wanted eigenvalues farther below near the tolerance.
fn shift_above(v: &[f64], top: f64, span: f64) -> f64 {
    let next = v
        .iter()
        .copied()
        .filter(|&x| x > top)
        .fold(f64::INFINITY, f64::min);
    let half = (0.5 * (next - top)).min(0.05 * span);
    top + half.max(1e-4 * span)
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

/// [`residuals`] from the products `K x` and `M x`.
pub(crate) fn residuals_of(
    kx: &Mat<f64>,
    mx: &Mat<f64>,
    values: &[f64],
    vectors: MatRef<'_, f64>,
    k_diag: &[f64],
) -> Vec<f64> {
    let k_norm = k_diag.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    (0..values.len())
        .map(|j| {
            let r = kx.col(j) - mx.col(j) * faer::Scale(values[j]);
            let floor = k_norm * vectors.col(j).norm_l2();
            let scale = kx
                .col(j)
                .norm_l2()
                .max(mx.col(j).norm_l2() * values[j].abs());
            let scale = if scale < 1e-8 * floor { floor } else { scale };
            if scale > 0.0 {
                r.norm_l2() / scale
            } else {
                0.0
            }
        })
        .collect()
}

/// `OP = (K - sigma M)^-1 M` on the factor of `K - sigma M`, which it
/// factorises when first needed and again after a Sturm check has borrowed
/// its storage (one factor in memory at a time); counts the solves and times
/// the solves, the products with `M` and the factorisations. After
/// [`Operator::move_above`] the shift lies above the wanted eigenvalues and
/// the operator is `-(K - sigma M)^-1 M`: its positive `theta = 1 / (sigma -
/// lambda)` are the eigenvalues below the shift, the largest nearest it.
struct Operator<'p> {
    pencil: &'p ShiftedPencil,
    sigma: f64,
    /// 1 below the spectrum, -1 above the wanted eigenvalues:
    /// `theta = sign / (lambda - sigma)`.
    sign: f64,
    held: Option<&'p HeldState<'p>>,
    factor: Option<ShiftedFactor>,
    /// Storage of a factor no longer held, reused by the next one.
    spare: Vec<f64>,
    progress: &'p dyn Progress,
    solves: usize,
    block_solves: usize,
    solve_seconds: f64,
    mass_seconds: f64,
    mass_products: usize,
    factorization_seconds: f64,
    sturm_seconds: f64,
}

impl Operator<'_> {
    /// Factorises `K - sigma M` (if not held), checking that `sigma` lies
    /// below the spectrum.
    fn factorize(&mut self) -> Result<&ShiftedFactor, LinalgError> {
        if self.factor.is_none() {
            let t = Instant::now();
            let sigma = self.sigma;
            let f = match self.held {
                // Reports its own stages.
                Some(h) => self
                    .pencil
                    .factorize_static(h.held.support, self.progress)?,
                None => {
                    self.progress.report(&Stage::Factorization { shift: sigma });
                    let f = self
                        .pencil
                        .refactorize(sigma, std::mem::take(&mut self.spare))?;
                    self.progress.report(&Stage::Factorized {
                        shift: sigma,
                        seconds: t.elapsed().as_secs_f64(),
                    });
                    f
                }
            };
            self.factorization_seconds += t.elapsed().as_secs_f64();
            self.factor = Some(f);
        }
        let f = self.factor.as_ref().expect("factorised above");
        if self.sign > 0.0 && f.inertia().negative > 0 {
            return Err(LinalgError::NotSemiDefinite {
                count: f.inertia().negative,
                bound: self.sigma,
            });
        }
        Ok(f)
    }

    /// Refuses, before the factorisation, a run for `nev` eigenpairs whose
    /// basis (with the factor, if its storage is still to be taken)
    /// exceeds the memory left: many modes of a large model fail at once,
    /// not at the kernel's out-of-memory kill after the factorisation. The
    /// basis, its working blocks (4) and the converged vectors count.
    fn ensure_room(&self, nev: usize, params: &LanczosParams) -> Result<(), LinalgError> {
        let n = self.pencil.dim();
        let entries = self.pencil.factor_len();
        let resident = if self.factor.is_some() {
            entries
        } else {
            self.spare.len().min(entries)
        };
        crate::memory::ensure_factor_room(n, entries, resident)?;
        let (b, p_max) = basis_shape(nev, n, params);
        let vectors = p_max + 4 * b + nev;
        let size = std::mem::size_of::<f64>();
        let (basis, factor) = (n * vectors * size, (entries - resident) * size);
        if basis < 1 << 20 {
            return Ok(());
        }
        let with_factor = if factor > 0 {
            format!(
                ", with the LDL^T factor's {}",
                crate::memory::bytes_text(factor as u64)
            )
        } else {
            String::new()
        };
        crate::memory::ensure_room(
            (basis + factor) as u64,
            &format!(
                "a Lanczos run for {nev} modes ({vectors} vectors of {n} equations{with_factor})"
            ),
        )
    }

    /// Eigenvalues below `bound` by the inertia of `K - bound M`, in the
    /// storage of the operator's factor, which is given up.
    fn sturm_count(&mut self, bound: f64) -> Result<usize, LinalgError> {
        let (_, count, f) = self.factor_at(bound)?;
        self.spare = f.into_storage();
        Ok(count)
    }

    /// Makes the shift `bound` (moved up by a relative 1e-8 should it hit
    /// an eigenvalue) above the wanted eigenvalues the operator's:
    /// `-(K - s M)^-1 M` on the same factor that counts the eigenvalues
    /// below `s` (Sturm), so a shift near the top of the wanted band makes
    /// one factorisation both the check and the operator that converges
    /// the band's highest modes fastest. Returns `s` and the count.
    fn move_above(&mut self, bound: f64) -> Result<(f64, usize), LinalgError> {
        let (s, count, f) = self.factor_at(bound)?;
        self.factor = Some(f);
        self.sigma = s;
        self.sign = -1.0;
        self.held = None;
        Ok((s, count))
    }

    /// `lambda` of an eigenvalue `theta` of the operator.
    fn lambda(&self, theta: f64) -> f64 {
        self.sigma + self.sign / theta
    }

    /// The `LDL^T` of `K - s M` for `s` from `bound` up (a shift on an
    /// eigenvalue, a zero pivot, is moved up by a relative 1e-8), in the
    /// storage of the operator's factor, with its count of eigenvalues
    /// below `s`; counted as the Sturm check's time.
    fn factor_at(&mut self, bound: f64) -> Result<(f64, usize, ShiftedFactor), LinalgError> {
        let t = Instant::now();
        let mut storage = match self.factor.take() {
            Some(f) => f.into_storage(),
            None => std::mem::take(&mut self.spare),
        };
        let mut s = bound;
        for _ in 0..3 {
            self.progress.report(&Stage::Factorization { shift: s });
            match self.pencil.refactorize(s, storage) {
                Ok(f) => {
                    self.progress.report(&Stage::Factorized {
                        shift: s,
                        seconds: t.elapsed().as_secs_f64(),
                    });
                    self.sturm_seconds += t.elapsed().as_secs_f64();
                    let count = f.inertia().negative + f.inertia().zero;
                    return Ok((s, count, f));
                }
                Err(LinalgError::Singular { .. }) => {
                    storage = Vec::new();
                    s += 1e-8 * s.abs().max(f64::MIN_POSITIVE);
                }
                Err(e) => return Err(e),
            }
        }
        Err(LinalgError::NoSturmCount { bound })
    }

    /// `(K - sigma M)^-1 Y` for `Y = M V` given, in its storage.
    fn solve(&mut self, mut x: Mat<f64>) -> Result<Mat<f64>, LinalgError> {
        if let Some(h) = self.held {
            // P Y: the loads in equilibrium, none on the support.
            let c = tall::gram(h.held.rigid, x.as_ref());
            tall::add_product(x.as_mut(), h.m_rigid.as_ref(), c.as_ref(), -1.0);
            for &i in h.held.support {
                for j in 0..x.ncols() {
                    x[(i, j)] = 0.0;
                }
            }
        }
        let factor = self.factorize()?;
        let t = Instant::now();
        factor.solve_in_place(x.as_mut());
        if self.sign < 0.0 {
            x *= faer::Scale(-1.0);
        }
        self.solves += x.ncols();
        self.block_solves += 1;
        self.solve_seconds += t.elapsed().as_secs_f64();
        if let Some(h) = self.held {
            // T_perp: the held response has a rigid-body part; without it
            // the block need not lose half its norm to the basis
            // projection, which then takes a second pass and product.
            let c = tall::gram(h.m_rigid.as_ref(), x.as_ref());
            tall::add_product(x.as_mut(), h.held.rigid, c.as_ref(), -1.0);
        }
        Ok(x)
    }

    /// `M X`.
    fn mass(&mut self, x: MatRef<'_, f64>) -> Mat<f64> {
        let t = Instant::now();
        let mx = self.pencil.mul_mass(x);
        self.mass_seconds += t.elapsed().as_secs_f64();
        self.mass_products += x.ncols();
        mx
    }
}

/// [`Held`] with `M T`.
struct HeldState<'a> {
    held: Held<'a>,
    m_rigid: Mat<f64>,
}

/// Converged vectors and their eigenvalues `lambda` (rad^2/s^2): the runs
/// of one solve may use operators of different shifts.
struct Locked {
    x: Mat<f64>,
    lambda: Vec<f64>,
}

impl Locked {
    fn append(&mut self, other: Locked) {
        let n = self.x.nrows();
        let (a, b) = (self.x.ncols(), other.x.ncols());
        let (p, q) = (&self.x, &other.x);
        self.x = Mat::from_fn(
            n,
            a + b,
            |i, j| if j < a { p[(i, j)] } else { q[(i, j - a)] },
        );
        self.lambda.extend(other.lambda);
    }
}

/// Deterministic start vectors (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (v >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

fn dot(a: ColRef<'_, f64>, b: ColRef<'_, f64>) -> f64 {
    a.transpose() * b
}

/// `W -= X (X^T MW)` for `MW = M W` (stale afterwards); returns `X^T MW`.
/// With `X` the M-orthonormal union of blocks that are M-orthogonal to
/// each other, the blocks may be projected one after the other with the
/// same `MW`.
fn project_out(w: MatMut<'_, f64>, mw: MatRef<'_, f64>, x: MatRef<'_, f64>) -> Mat<f64> {
    let c = tall::gram(x, mw);
    if x.ncols() > 0 {
        tall::add_product(w, x, c.as_ref(), -1.0);
    }
    c
}

/// `V[:, ..k] = V[:, ..e] Y` for `Y` of `e x k`, `k <= e`, by blocks of
/// rows in parallel: no `n x k` temporary (0.3 GB at 3e5 DOFs).
fn rotate_in_place(v: &mut Mat<f64>, e: usize, y: MatRef<'_, f64>) {
    use rayon::prelude::*;
    let k = y.ncols();
    v.as_mut().par_row_chunks_mut(2048).for_each(|rows| {
        let rotated = rows.as_ref().subcols(0, e) * y;
        rows.subcols_mut(0, k).copy_from(&rotated);
    });
}

/// M-orthonormalises the columns of `w` (with `mw = M w`) in place by
/// Cholesky QR twice, or by Gram-Schmidt twice when the block is too
/// ill-conditioned for that; returns the upper-triangular `B` with
/// `W_in = Q B`. A column that vanishes against the earlier ones (to 1e-10
/// of `before`, its M-norm before the projection on the basis) is replaced
/// by a random vector orthogonal to `locked`, the basis and the earlier
/// columns, which enters `B` with a zero diagonal entry.
fn orthonormalize_block(
    w: &mut Mat<f64>,
    mw: &mut Mat<f64>,
    before: &[f64],
    others: &[MatRef<'_, f64>],
    pencil: &ShiftedPencil,
    rng: &mut Rng,
) -> Mat<f64> {
    cholesky_qr2(w, mw, others, pencil, rng)
        .unwrap_or_else(|| gram_schmidt_block(w, mw, before, others, pencil, rng))
}

/// Cholesky QR twice in the `M` inner product: `G = W^T M W = R^T R`,
/// `W <- W R^-1`, once more for orthogonality to round-off; returns `B`
/// with `W_in = Q B`. Two small Gram matrices and BLAS-3 updates of the
/// `n x b` block in place, where Gram-Schmidt column by column costs `b^2`
/// passes over `n`. `None` (nothing changed) when `W` is too
/// ill-conditioned for it (the ratio of the extreme diagonal entries of
/// `R` below 1e-6, the point where `G` has lost half the digits); should
/// the second pass fail, Gram-Schmidt finishes what the first began.
fn cholesky_qr2(
    w: &mut Mat<f64>,
    mw: &mut Mat<f64>,
    others: &[MatRef<'_, f64>],
    pencil: &ShiftedPencil,
    rng: &mut Rng,
) -> Option<Mat<f64>> {
    let b = w.ncols();
    let mut total = Mat::<f64>::identity(b, b);
    for pass in 0..2 {
        let mut g = tall::gram(w.as_ref(), mw.as_ref());
        crate::sparse::symmetrize(&mut g);
        let factor = g.llt(Side::Lower).ok().map(|f| f.L().to_owned());
        let conditioned = factor.as_ref().is_some_and(|l| {
            let (lo, hi) = (0..b).fold((f64::INFINITY, 0.0_f64), |(lo, hi), i| {
                (lo.min(l[(i, i)]), hi.max(l[(i, i)]))
            });
            lo > 1e-6 * hi && hi.is_finite()
        });
        let l = match factor {
            Some(l) if conditioned => l,
            _ if pass == 0 => return None,
            _ => {
                // The columns have unit M-norm after the first pass.
                let unit = vec![1.0; b];
                let r = gram_schmidt_block(w, mw, &unit, others, pencil, rng);
                return Some(r * &total);
            }
        };
        // W R^-1 with R = L^T, in place.
        for x in [w.as_mut(), mw.as_mut()] {
            tall::div_upper(x, l.transpose());
        }
        total = l.transpose() * &total;
    }
    Some(total)
}

/// Gram-Schmidt column by column, twice, with breakdown handling (the
/// fallback of [`cholesky_qr2`]).
fn gram_schmidt_block(
    w: &mut Mat<f64>,
    mw: &mut Mat<f64>,
    before: &[f64],
    others: &[MatRef<'_, f64>],
    pencil: &ShiftedPencil,
    rng: &mut Rng,
) -> Mat<f64> {
    let (n, b) = (w.nrows(), w.ncols());
    let mut r = Mat::<f64>::zeros(b, b);
    for i in 0..b {
        for _pass in 0..2 {
            for j in 0..i {
                let c = dot(w.col(j), mw.col(i));
                r[(j, i)] += c;
                for p in 0..n {
                    w[(p, i)] -= c * w[(p, j)];
                    mw[(p, i)] -= c * mw[(p, j)];
                }
            }
        }
        let norm = dot(w.col(i), mw.col(i)).max(0.0).sqrt();
        if norm > 1e-10 * before[i] && norm.is_finite() {
            r[(i, i)] = norm;
            for p in 0..n {
                w[(p, i)] /= norm;
                mw[(p, i)] /= norm;
            }
            continue;
        }
        // Breakdown: an invariant subspace; continue with a fresh direction.
        let mut z = Mat::from_fn(n, 1, |_, _| rng.next());
        let mut mz = pencil.mul_mass(z.as_ref());
        for _pass in 0..2 {
            for x in others {
                project_out(z.as_mut(), mz.as_ref(), *x);
            }
            mz = pencil.mul_mass(z.as_ref());
            for j in 0..i {
                let c = dot(w.col(j), mz.col(0));
                for p in 0..n {
                    z[(p, 0)] -= c * w[(p, j)];
                    mz[(p, 0)] -= c * mw[(p, j)];
                }
            }
        }
        let norm = dot(z.col(0), mz.col(0)).max(0.0).sqrt();
        for p in 0..n {
            w[(p, i)] = z[(p, 0)] / norm;
            mw[(p, i)] = mz[(p, 0)] / norm;
        }
        // Column i of W was a combination of the earlier columns (their
        // coefficients stay in B); the new direction enters with 0.
    }
    r
}

/// The block size and the largest basis of a run for `nev` eigenpairs in
/// `free` dimensions.
fn basis_shape(nev: usize, free: usize, params: &LanczosParams) -> (usize, usize) {
    let b = params.block_size.max(1).min(free.max(1));
    (b, basis_for(nev, b, params).min(free))
}

/// The largest basis of a run for `nev` eigenpairs with blocks of `b`.
fn basis_for(nev: usize, b: usize, params: &LanczosParams) -> usize {
    if params.basis_size > 0 {
        params.basis_size.max(nev + 2 * b)
    } else {
        2 * nev + 4 * b
    }
}

/// Whether a Lanczos basis for `nev` eigenpairs would fill the `free`
/// dimensions: a Krylov space that exhausts the space leaves nothing to
/// restart with, and its last blocks, round-off after the projections,
/// gave spurious pairs (the 6 x 6 x 6 cube's 900 lowest of 1029: residuals
/// of 0.7 and 750 eigenvalues more than the Sturm count). The dense solver
/// takes such a problem.
fn spans_the_space(nev: usize, free: usize, params: &LanczosParams) -> bool {
    nev > 0 && basis_for(nev, params.block_size.max(1), params) >= free
}

/// The wanted pairs from dense `K` and `M` (formed by the pencil's
/// products with the identity) and [`crate::eigen::generalized_symmetric`],
/// for a count [`spans_the_space`]. A band's Sturm count, made before,
/// goes into the report as the count; the eigenvalues below the bound are
/// the dense solver's.
#[allow(clippy::too_many_arguments)]
fn dense_pairs(
    pencil: &ShiftedPencil,
    wanted: Wanted,
    nev: usize,
    sturm: Option<(f64, usize)>,
    sigma: f64,
    mut stats: LanczosStats,
    progress: &dyn Progress,
    start: Instant,
) -> Result<SparseEigen, LinalgError> {
    let n = pencil.dim();
    crate::eigen::ensure_dense_room(n, 2).map_err(|err| {
        LinalgError::Dimension(format!(
            "{nev} eigenpairs of a {n}-equation model are too many for Lanczos (its \
             basis would span the model), and the dense solver does not fit: {err}"
        ))
    })?;
    progress.report(&Stage::DenseEigen {
        equations: n,
        wanted: nev,
    });
    let eye = Mat::<f64>::identity(n, n);
    let k = pencil.mul_stiffness(eye.as_ref());
    let m = pencil.mul_mass(eye.as_ref());
    drop(eye);
    let all = crate::eigen::generalized_symmetric(k.as_ref(), m.as_ref())?;
    drop((k, m));
    let keep = match wanted {
        Wanted::Lowest(count) => count,
        Wanted::Below(bound) => all.values.iter().filter(|&&l| l < bound).count(),
    };
    if keep > all.values.len() {
        return Err(LinalgError::Dimension(format!(
            "{keep} eigenpairs wanted of a {n}-equation model with {} finite ones",
            all.values.len()
        )));
    }
    let pairs = all.slice(0, keep);
    drop(all);
    let kx = pencil.mul_stiffness(pairs.vectors.as_ref());
    let mx = pencil.mul_mass(pairs.vectors.as_ref());
    let residuals = residuals_of(
        &kx,
        &mx,
        &pairs.values,
        pairs.vectors.as_ref(),
        &pencil.stiffness_diagonal(),
    );
    stats.dense = true;
    progress.report(&Stage::Done {
        seconds: start.elapsed().as_secs_f64(),
    });
    Ok(SparseEigen {
        pairs,
        residuals,
        shift: sigma,
        sturm: sturm.map(|(bound, count)| SturmReport {
            bound,
            count,
            found_first: keep,
            found: keep,
        }),
        stats,
    })
}

/// Sweeps without a new converged wanted pair after which the first run
/// hands over to a shift above the wanted band (twice as many for a move
/// below the band's top, which costs a factorisation more).
const STALL_SWEEPS: usize = 4;

/// The residual floor of a Ritz pair in units of `eps theta_max`: the
/// round-off of `H`. (A rule that doubled it where estimates stopped
/// falling served while faer's unscaled eigen-decomposition of `H` held
/// them at a false floor; with a basis held small it let slow runs accept
/// modes with residuals of 1e-4, and is gone.)
const FLOOR: f64 = 64.0;

/// Moves of the shift below the band's top after stalls.
const MAX_MOVES: usize = 4;

/// What one [`krylov_schur`] run found.
struct Run {
    /// Every converged Ritz pair with `theta > 0`.
    converged: Locked,
    /// Set when the run stopped before all wanted pairs converged.
    stalled: Option<Stalled>,
}

/// The unconverged part of a run that stopped early.
struct Stalled {
    /// `lambda` of the Ritz values not converged among the wanted ones and
    /// the block after them, in descending `theta`. Below the spectrum
    /// (ascending `lambda`) they bound their eigenvalues from above, above
    /// the band from below (Cauchy interlacing).
    lambda: Vec<f64>,
    /// Ritz vectors of the first of them, a block at most: the start of
    /// the next run.
    start: Mat<f64>,
}

/// One thick-restart block Lanczos run for the `nev` largest `theta` of
/// `OP` deflated by `locked`, from `start` (completed with random vectors
/// to a block) if given; returns every converged Ritz pair (at least the
/// `nev` wanted ones). With `stall_sweeps > 0` it returns early when that
/// many sweeps in a row converge no new wanted pair: the remaining wanted
/// eigenvalues then lie where this shift resolves them slowly (clustered,
/// or so far below `theta_max` that round-off holds their residuals near
/// the tolerance), and a shift above them does better.
#[allow(clippy::too_many_arguments)]
fn krylov_schur(
    op: &mut Operator<'_>,
    locked: &Locked,
    nev: usize,
    params: &LanczosParams,
    progress: &dyn Progress,
    rng: &mut Rng,
    stats: &mut LanczosStats,
    stall_sweeps: usize,
    start: Option<MatRef<'_, f64>>,
) -> Result<Run, LinalgError> {
    stats.runs += 1;
    let pencil = op.pencil;
    let n = pencil.dim();
    let free = n - locked.x.ncols();
    let (b, p_max) = basis_shape(nev, free, params);
    if p_max < nev + b && p_max < free {
        return Err(LinalgError::Dimension(format!(
            "{nev} eigenpairs of a {n}-equation model: too many for Lanczos"
        )));
    }
    let restart_size = ((nev + p_max - b) / 2)
        .min(p_max.saturating_sub(2 * b))
        .max(nev)
        .min(p_max.saturating_sub(b));
    // The basis only: `M V` is not kept (0.2 GB at 3e5 DOFs); each
    // projection pass takes one product `M W` of the new block instead.
    // Columns are written (by `tall::copy`, both threads touching their
    // fresh pages) before they are read: a zeroing pass here would touch
    // all 0.2 GB at 3e5 DOFs on one thread first.
    let mut v = Mat::<f64>::with_capacity(n, p_max);
    // SAFETY: f64 has no invalid values; only columns `..c` are read, and
    // each is written when `c` moves past it.
    unsafe { v.set_dims(n, p_max) };
    let mut h = Mat::<f64>::zeros(p_max, p_max);
    // The first `nl` columns hold converged wanted Ritz vectors since the
    // last restart (locking): their couplings in `H` are exactly zero and
    // they leave the Rayleigh-Ritz problem, so that round-off of later
    // steps (some eps theta_max, near the tolerance of modes far below
    // theta_max) and mixing with close unconverged values cannot take them
    // out of convergence again. Every new block is still projected
    // against them.
    let mut nl = 0usize;
    let lk = locked.x.as_ref();

    // Start block: OP applied to random vectors (in the range of OP).
    // `pending` is `M` times the block `[e, c)` that the next step expands.
    let mut pending = {
        let given = start.map_or(0, |x| x.ncols().min(b));
        let z = Mat::from_fn(n, b, |i, j| match start {
            Some(x) if j < given => x[(i, j)],
            _ => rng.next(),
        });
        let mz = pencil.mul_mass(z.as_ref());
        let mut w = op.solve(mz)?;
        let mut mw = op.mass(w.as_ref());
        let before: Vec<f64> = (0..b)
            .map(|j| dot(w.col(j), mw.col(j)).max(0.0).sqrt())
            .collect();
        if lk.ncols() > 0 {
            for _ in 0..2 {
                project_out(w.as_mut(), mw.as_ref(), lk);
                mw = op.mass(w.as_ref());
            }
        }
        orthonormalize_block(&mut w, &mut mw, &before, &[lk], pencil, rng);
        tall::copy(v.subcols_mut(0, b), w.as_ref());
        mw
    };
    let (mut e, mut c) = (0usize, b);
    let mut step = 0;
    // The most wanted pairs converged at once so far, and the sweeps since.
    let (mut record, mut since, mut restarts) = (0usize, 0usize, 0usize);
    loop {
        step += 1;
        if step > params.max_steps {
            return Err(LinalgError::NotConverged {
                steps: params.max_steps,
                wanted: nev,
            });
        }
        // Expand the pending block [e, c).
        let blk = c - e;
        let m_block = pending.clone();
        let mut w = op.solve(pending)?;
        // First pass, without a product with M: by the Krylov relation the
        // coefficients of W = OP V_blk on the earlier basis vectors are
        // known, V_i^T M OP V_blk = (OP V_i)^T M V_blk = H[i, blk] (the
        // previous block's B^T, or the arrow after a restart), and the new
        // diagonal block is A = (M V_blk)^T W.
        let lo = (0..e)
            .find(|&i| (0..blk).any(|j| h[(i, e + j)] != 0.0))
            .unwrap_or(e);
        let mut coef = Mat::<f64>::zeros(c, blk);
        coef.subrows_mut(lo, e - lo)
            .copy_from(h.submatrix(lo, e, e - lo, blk));
        tall::add_product(
            w.as_mut(),
            v.subcols(lo, e - lo),
            coef.subrows(lo, e - lo),
            -1.0,
        );
        let a = tall::gram(m_block.as_ref(), w.as_ref());
        drop(m_block);
        tall::add_product(w.as_mut(), v.subcols(e, blk), a.as_ref(), -1.0);
        coef.subrows_mut(e, blk).copy_from(&a);
        let mut mw = op.mass(w.as_ref());
        let mut norms: Vec<f64> = (0..blk)
            .map(|j| dot(w.col(j), mw.col(j)).max(0.0).sqrt())
            .collect();
        // The M-norms of W as solved: the pass took M-orthogonal parts away.
        let before: Vec<f64> = (0..blk)
            .map(|j| (norms[j].powi(2) + coef.col(j).squared_norm_l2()).sqrt())
            .collect();
        // Then classical Gram-Schmidt on the whole basis, repeated while a
        // pass cancels more than half of a column (at most 4 passes).
        for _ in 0..4 {
            // The locked vectors are M-orthogonal to the basis: one `M W`
            // serves both projections.
            project_out(w.as_mut(), mw.as_ref(), lk);
            coef += project_out(w.as_mut(), mw.as_ref(), v.subcols(0, c));
            mw = op.mass(w.as_ref());
            let after: Vec<f64> = (0..blk)
                .map(|j| dot(w.col(j), mw.col(j)).max(0.0).sqrt())
                .collect();
            let again = (0..blk).any(|j| after[j] < 0.5 * norms[j] && after[j] > 1e-12 * before[j]);
            norms = after;
            if !again {
                break;
            }
        }
        for j in 0..blk {
            for i in 0..c {
                let x = if i < nl { 0.0 } else { coef[(i, j)] };
                h[(i, e + j)] = x;
                h[(e + j, i)] = x;
            }
        }
        for j in 0..blk {
            for i in 0..j {
                let s = 0.5 * (h[(e + i, e + j)] + h[(e + j, e + i)]);
                h[(e + i, e + j)] = s;
                h[(e + j, e + i)] = s;
            }
        }
        let bmat = {
            let others = [lk, v.subcols(0, c)];
            orthonormalize_block(&mut w, &mut mw, &before, &others, pencil, rng)
        };
        let e_prev = e;
        e = c;
        let full = c + blk > p_max || e >= free;
        if !full {
            tall::copy(v.subcols_mut(c, blk), w.as_ref());
            for j in 0..blk {
                for i in 0..blk {
                    h[(c + i, e_prev + j)] = bmat[(i, j)];
                    h[(e_prev + j, c + i)] = bmat[(i, j)];
                }
            }
            c += blk;
        }
        // Rayleigh-Ritz on the expanded part past the locked columns;
        // those are Ritz pairs themselves (unit vectors, `theta = H_jj`).
        let (ritz, ritz_u) = crate::eigen::symmetric_eigen(h.submatrix(nl, nl, e - nl, e - nl))?;
        let u = Mat::from_fn(e, e, |r, j| match (r < nl, j < nl) {
            (true, true) => f64::from(r == j),
            (false, false) => ritz_u[(r - nl, j - nl)],
            _ => 0.0,
        });
        let value = |j: usize| if j < nl { h[(j, j)] } else { ritz[j - nl] };
        // Descending theta.
        let mut idx: Vec<usize> = (0..e).collect();
        idx.sort_by(|&a, &b| value(b).total_cmp(&value(a)));
        let theta: Vec<f64> = idx.iter().map(|&i| value(i)).collect();
        let last = u.subrows(e_prev, blk);
        let estimate: Vec<f64> = idx
            .iter()
            .map(|&i| {
                if e >= free || i < nl {
                    0.0
                } else {
                    (bmat.as_ref() * last.col(i)).norm_l2()
                }
            })
            .collect();
        // Round-off in H is about eps theta_max (the rigid-body modes' theta
        // when the shift is small): no residual gets below that.
        // Above the wanted band, the unwanted eigenvalues just above the
        // shift have the largest |theta| (negative).
        let theta_max = theta
            .first()
            .map_or(0.0, |t| t.abs())
            .max(theta.last().map_or(0.0, |t| t.abs()));
        let floor = FLOOR * f64::EPSILON * theta_max;
        let conv: Vec<bool> = (0..e)
            .map(|i| estimate[i] <= (params.tolerance * theta[i].abs()).max(floor))
            .collect();
        let wanted_conv = conv.iter().take(nev).filter(|&&x| x).count();
        progress.report(&Stage::Iteration {
            step,
            solves: op.solves,
            converged: wanted_conv.min(nev),
            wanted: nev,
            basis: e,
        });
        // Sweeps before the first restart, while the basis still grows,
        // are no stall (see the module docs).
        if wanted_conv > record {
            (record, since) = (wanted_conv, 0);
        } else if restarts > 0 {
            since += 1;
        }
        let done = wanted_conv >= nev.min(e) && e >= nev;
        // Only past the first restart (the basis no longer grows), and
        // only once every wanted Ritz value is within about 1e-6 of its
        // eigenvalue (the error is the squared estimate over the gap), so
        // that the shift above them lands just above the wanted band.
        let stop = !done
            && stall_sweeps > 0
            && restarts > 0
            && since >= stall_sweeps
            && e >= nev
            && (0..nev).all(|i| estimate[i] <= 1e-3 * theta[i].abs());
        if done || stop {
            let ritz = |pick: &[usize]| {
                let y = Mat::from_fn(e, pick.len(), |r, j| u[(r, idx[pick[j]])]);
                v.subcols(0, e) * &y
            };
            let pick: Vec<usize> = (0..e).filter(|&i| conv[i] && theta[i] > 0.0).collect();
            let x = ritz(&pick);
            let converged = Locked {
                x,
                lambda: pick.iter().map(|&i| op.lambda(theta[i])).collect(),
            };
            let stalled = stop.then(|| {
                // Descending theta is ascending lambda.
                let open: Vec<usize> = (0..e.min(nev + b))
                    .filter(|&i| !conv[i] && theta[i] > 0.0)
                    .collect();
                Stalled {
                    lambda: open.iter().map(|&i| op.lambda(theta[i])).collect(),
                    start: ritz(&open[..open.len().min(b)]),
                }
            });
            return Ok(Run { converged, stalled });
        }
        if full {
            // Thick restart: the best Ritz vectors plus the residual block,
            // the converged wanted ones first and locked.
            let kk = restart_size.min(e);
            stats.restarts += 1;
            restarts += 1;
            let mut keep: Vec<usize> = (0..kk).filter(|&j| j < nev && conv[j]).collect();
            nl = keep.len();
            keep.extend((0..kk).filter(|&j| !(j < nev && conv[j])));
            let y = Mat::from_fn(e, kk, |r, j| u[(r, idx[keep[j]])]);
            rotate_in_place(&mut v, e, y.as_ref());
            tall::copy(v.subcols_mut(kk, blk), w.as_ref());
            h.fill(0.0);
            let coupling = bmat.as_ref() * y.subrows(e_prev, blk);
            for j in 0..kk {
                h[(j, j)] = theta[keep[j]];
                for i in 0..blk {
                    let x = if j < nl { 0.0 } else { coupling[(i, j)] };
                    h[(kk + i, j)] = x;
                    h[(j, kk + i)] = x;
                }
            }
            e = kk;
            c = kk + blk;
        }
        pending = mw;
    }
}

#[cfg(test)]
mod tests;
