//! One thick-restart (Krylov-Schur) block Lanczos run on an [`Operator`]:
//! block expansion with full re-orthogonalisation, Rayleigh-Ritz on `H`,
//! convergence read off the Krylov relation, locking of converged wanted
//! pairs at each restart, and the stall rule that hands a slow run over to
//! a shift nearer the rest (see the module docs of [`super`]).

use super::block_qr::{dot, orthonormalize_block, project_out};
use super::operator::Operator;
use super::{LanczosParams, LanczosStats};
use crate::progress::{Progress, Stage};
use crate::tall;
use crate::LinalgError;
use faer::{Mat, MatRef};

/// Converged vectors and their eigenvalues `lambda` (rad^2/s^2): the runs
/// of one solve may use operators of different shifts.
pub(super) struct Locked {
    pub(super) x: Mat<f64>,
    pub(super) lambda: Vec<f64>,
}

impl Locked {
    pub(super) fn append(&mut self, other: Locked) {
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

    /// How many of the eigenvalues lie below `bound`.
    pub(super) fn count_below(&self, bound: f64) -> usize {
        self.lambda.iter().filter(|&&x| x < bound).count()
    }
}

/// Deterministic start vectors (xorshift64*).
pub(super) struct Rng(pub(super) u64);

impl Rng {
    pub(super) fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (v >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// The residual floor of a Ritz pair in units of `eps theta_max`: the
/// round-off of `H`. (A rule that doubled it where estimates stopped
/// falling served while faer's unscaled eigen-decomposition of `H` held
/// them at a false floor; with a basis held small it let slow runs accept
/// modes with residuals of 1e-4, and is gone.)
const FLOOR: f64 = 64.0;

/// What one [`krylov_schur`] run found.
pub(super) struct Run {
    /// Every converged Ritz pair with `theta > 0`.
    pub(super) converged: Locked,
    /// Set when the run stopped before all wanted pairs converged.
    pub(super) stalled: Option<Stalled>,
}

/// The unconverged part of a run that stopped early.
pub(super) struct Stalled {
    /// `lambda` of the Ritz values not converged among the wanted ones and
    /// the block after them, in descending `theta`. Below the spectrum
    /// (ascending `lambda`) they bound their eigenvalues from above, above
    /// the band from below (Cauchy interlacing).
    pub(super) lambda: Vec<f64>,
    /// Ritz vectors of the first of them, a block at most: the start of
    /// the next run.
    pub(super) start: Mat<f64>,
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
pub(super) fn krylov_schur(
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

/// The block size and the largest basis of a run for `nev` eigenpairs in
/// `free` dimensions.
pub(super) fn basis_shape(nev: usize, free: usize, params: &LanczosParams) -> (usize, usize) {
    let b = params.block_size.max(1).min(free.max(1));
    (b, basis_for(nev, b, params).min(free))
}

/// The largest basis of a run for `nev` eigenpairs with blocks of `b`.
pub(super) fn basis_for(nev: usize, b: usize, params: &LanczosParams) -> usize {
    if params.basis_size > 0 {
        params.basis_size.max(nev + 2 * b)
    } else {
        2 * nev + 4 * b
    }
}
