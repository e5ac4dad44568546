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
///
/// Each sweep expands the pending block ([`Basis::expand`]), solves the
/// Rayleigh-Ritz problem of `H` ([`Basis::rayleigh_ritz`]), reads the
/// converged pairs off the Krylov relation ([`Ritz::converged`]), and
/// either returns ([`Basis::run`]) or, with the basis full, restarts it on
/// the best Ritz vectors with the converged wanted ones locked
/// ([`Basis::restart`]).
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
    let n = op.pencil.dim();
    let free = n - locked.x.ncols();
    let shape = RunShape::new(nev, free, n, params)?;
    let mut basis = Basis::new(n, shape.p_max, free, locked.x.as_ref());
    // `pending` is `M` times the block `[e, c)` that the next step expands.
    let mut pending = basis.start(op, shape.b, start, rng)?;
    let mut sweeps = Sweeps::default();
    loop {
        sweeps.step += 1;
        if sweeps.step > params.max_steps {
            return Err(LinalgError::NotConverged {
                steps: params.max_steps,
                wanted: nev,
            });
        }
        let block = basis.expand(op, pending, rng)?;
        let ritz = basis.rayleigh_ritz(&block)?;
        let conv = ritz.converged(params.tolerance);
        let wanted_conv = conv.iter().take(nev).filter(|&&x| x).count();
        progress.report(&Stage::Iteration {
            step: sweeps.step,
            solves: op.solves,
            converged: wanted_conv.min(nev),
            wanted: nev,
            basis: basis.e,
        });
        sweeps.count(wanted_conv);
        let done = wanted_conv >= nev.min(basis.e) && basis.e >= nev;
        let stop = !done && sweeps.stalled(stall_sweeps) && ritz.close(nev, basis.e);
        if done || stop {
            return Ok(basis.run(op, &ritz, &conv, nev, shape.b, stop));
        }
        if block.full {
            stats.restarts += 1;
            sweeps.restarts += 1;
            basis.restart(&ritz, &conv, nev, shape.restart_size, &block);
        }
        pending = block.mw;
    }
}

/// The sizes of one run: the block `b`, the largest basis `p_max` and the
/// basis kept at a restart.
struct RunShape {
    b: usize,
    p_max: usize,
    restart_size: usize,
}

impl RunShape {
    /// The shape of a run for `nev` pairs in `free` of `n` dimensions; an
    /// error where the basis cannot hold them and a block more.
    fn new(nev: usize, free: usize, n: usize, params: &LanczosParams) -> Result<Self, LinalgError> {
        let (b, p_max) = basis_shape(nev, free, params);
        if p_max < nev + b && p_max < free {
            return Err(LinalgError::Unservable(format!(
                "{nev} eigenpairs of a {n}-equation model: too many for Lanczos"
            )));
        }
        let restart_size = ((nev + p_max - b) / 2)
            .min(p_max.saturating_sub(2 * b))
            .max(nev)
            .min(p_max.saturating_sub(b));
        Ok(Self {
            b,
            p_max,
            restart_size,
        })
    }
}

/// The Krylov basis of a run and the projected operator on it: the
/// M-orthonormal `V` (`V^T M V = I`, M-orthogonal to the locked vectors
/// `lk` of earlier runs) and `H = V^T M OP V`, with the Krylov relation
/// `OP V[.., ..e] = V[.., ..c] H[..c, ..e]` plus the residual block of the
/// last expansion.
struct Basis<'l> {
    /// `n x p_max`, columns `..c` written.
    v: Mat<f64>,
    /// `p_max x p_max`, symmetric.
    h: Mat<f64>,
    /// The converged vectors of earlier runs, which every block is
    /// projected against.
    lk: MatRef<'l, f64>,
    /// The first `nl` columns hold converged wanted Ritz vectors since the
    /// last restart (locking): their couplings in `H` are exactly zero and
    /// they leave the Rayleigh-Ritz problem, so that round-off of later
    /// steps (some eps theta_max, near the tolerance of modes far below
    /// theta_max) and mixing with close unconverged values cannot take them
    /// out of convergence again. Every new block is still projected
    /// against them.
    nl: usize,
    /// Columns `..e` are expanded; `[e, c)` is the block pending.
    e: usize,
    c: usize,
    p_max: usize,
    /// Dimensions left beside the locked vectors.
    free: usize,
}

/// One expansion of the basis: the new block `W` (M-orthonormal, `M W`)
/// with `W_in = W B`, and where it went.
struct Block {
    w: Mat<f64>,
    mw: Mat<f64>,
    /// The upper-triangular `B` of the block (`blk x blk`).
    bmat: Mat<f64>,
    /// The expanded block was `[e_prev, e_prev + blk)`.
    e_prev: usize,
    blk: usize,
    /// The basis has no room for `W`: it is kept for the restart.
    full: bool,
}

impl<'l> Basis<'l> {
    /// An empty basis of up to `p_max` vectors of `n` equations.
    fn new(n: usize, p_max: usize, free: usize, lk: MatRef<'l, f64>) -> Self {
        // The basis only: `M V` is not kept (0.2 GB at 3e5 DOFs); each
        // projection pass takes one product `M W` of the new block instead.
        // Columns are written (by `tall::copy`, both threads touching their
        // fresh pages) before they are read: a zeroing pass here would touch
        // all 0.2 GB at 3e5 DOFs on one thread first.
        let mut v = Mat::<f64>::with_capacity(n, p_max);
        // SAFETY: f64 has no invalid values; only columns `..c` are read, and
        // each is written when `c` moves past it.
        unsafe { v.set_dims(n, p_max) };
        Self {
            v,
            h: Mat::<f64>::zeros(p_max, p_max),
            lk,
            nl: 0,
            e: 0,
            c: 0,
            p_max,
            free,
        }
    }

    /// The start block: `OP` applied to `start` (its first `b` columns)
    /// completed with random vectors, so in the range of `OP`, projected
    /// off the locked vectors and M-orthonormalised into columns `..b`.
    /// Returns `M` times it, the block the first step expands.
    fn start(
        &mut self,
        op: &mut Operator<'_>,
        b: usize,
        start: Option<MatRef<'_, f64>>,
        rng: &mut Rng,
    ) -> Result<Mat<f64>, LinalgError> {
        let (n, lk) = (self.v.nrows(), self.lk);
        let given = start.map_or(0, |x| x.ncols().min(b));
        let z = Mat::from_fn(n, b, |i, j| match start {
            Some(x) if j < given => x[(i, j)],
            _ => rng.next(),
        });
        let mz = op.pencil.mul_mass(z.as_ref());
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
        orthonormalize_block(&mut w, &mut mw, &before, &[lk], op.pencil, rng);
        tall::copy(self.v.subcols_mut(0, b), w.as_ref());
        (self.e, self.c) = (0, b);
        Ok(mw)
    }

    /// Expands the pending block `[e, c)` (`m_block` = `M` times it): `W =
    /// OP V_blk`, M-orthogonalised against the locked vectors and the
    /// basis, its coefficients the new column of `H`, then M-orthonormal
    /// (`W = Q B`). The expanded columns move to `..c`; `Q` becomes the
    /// next pending block, with `B` below the diagonal block of `H`, unless
    /// the basis is full.
    fn expand(
        &mut self,
        op: &mut Operator<'_>,
        m_block: Mat<f64>,
        rng: &mut Rng,
    ) -> Result<Block, LinalgError> {
        let blk = self.c - self.e;
        let mut w = op.solve(m_block.clone())?;
        let mut coef = self.known_coefficients(&mut w, m_block, blk);
        let (mut mw, before) = self.reorthogonalize(op, &mut w, &mut coef, blk);
        self.store_coefficients(&coef, blk);
        let bmat = {
            let others = [self.lk, self.v.subcols(0, self.c)];
            orthonormalize_block(&mut w, &mut mw, &before, &others, op.pencil, rng)
        };
        let e_prev = self.e;
        self.e = self.c;
        let full = self.c + blk > self.p_max || self.e >= self.free;
        if !full {
            self.append(&w, &bmat, e_prev, blk);
        }
        Ok(Block {
            w,
            mw,
            bmat,
            e_prev,
            blk,
            full,
        })
    }

    /// The first pass of the projection of `W = OP V_blk`, without a
    /// product with `M`: by the Krylov relation the coefficients of `W` on
    /// the earlier basis vectors are known, `V_i^T M OP V_blk = (OP V_i)^T M
    /// V_blk = H[i, blk]` (the previous block's `B^T`, or the arrow after a
    /// restart), and the new diagonal block is `A = (M V_blk)^T W`. Takes
    /// them out of `W` and returns them (`c x blk`).
    fn known_coefficients(&self, w: &mut Mat<f64>, m_block: Mat<f64>, blk: usize) -> Mat<f64> {
        let (h, e) = (&self.h, self.e);
        let lo = (0..e)
            .find(|&i| (0..blk).any(|j| h[(i, e + j)] != 0.0))
            .unwrap_or(e);
        let mut coef = Mat::<f64>::zeros(self.c, blk);
        coef.subrows_mut(lo, e - lo)
            .copy_from(h.submatrix(lo, e, e - lo, blk));
        tall::add_product(
            w.as_mut(),
            self.v.subcols(lo, e - lo),
            coef.subrows(lo, e - lo),
            -1.0,
        );
        let a = tall::gram(m_block.as_ref(), w.as_ref());
        drop(m_block);
        tall::add_product(w.as_mut(), self.v.subcols(e, blk), a.as_ref(), -1.0);
        coef.subrows_mut(e, blk).copy_from(&a);
        coef
    }

    /// Classical Gram-Schmidt of `W` against the locked vectors and the
    /// whole basis, repeated while a pass cancels more than half of a
    /// column (at most 4 passes), its coefficients added to `coef`.
    /// Returns `M W` and the M-norms of `W` as solved (the first pass took
    /// M-orthogonal parts away).
    fn reorthogonalize(
        &self,
        op: &mut Operator<'_>,
        w: &mut Mat<f64>,
        coef: &mut Mat<f64>,
        blk: usize,
    ) -> (Mat<f64>, Vec<f64>) {
        let mut mw = op.mass(w.as_ref());
        let mut norms: Vec<f64> = (0..blk)
            .map(|j| dot(w.col(j), mw.col(j)).max(0.0).sqrt())
            .collect();
        let before: Vec<f64> = (0..blk)
            .map(|j| (norms[j].powi(2) + coef.col(j).squared_norm_l2()).sqrt())
            .collect();
        for _ in 0..4 {
            // The locked vectors are M-orthogonal to the basis: one `M W`
            // serves both projections.
            project_out(w.as_mut(), mw.as_ref(), self.lk);
            *coef += project_out(w.as_mut(), mw.as_ref(), self.v.subcols(0, self.c));
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
        (mw, before)
    }

    /// `coef` as the columns (and rows) `[e, e + blk)` of `H`, zero on the
    /// locked columns, the diagonal block made exactly symmetric.
    fn store_coefficients(&mut self, coef: &Mat<f64>, blk: usize) {
        let (h, e) = (&mut self.h, self.e);
        for j in 0..blk {
            for i in 0..self.c {
                let x = if i < self.nl { 0.0 } else { coef[(i, j)] };
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
    }

    /// The new block `W` as the pending columns `[c, c + blk)`, coupled to
    /// the block `[e_prev, e_prev + blk)` it came from by `B`.
    fn append(&mut self, w: &Mat<f64>, bmat: &Mat<f64>, e_prev: usize, blk: usize) {
        let c = self.c;
        tall::copy(self.v.subcols_mut(c, blk), w.as_ref());
        for j in 0..blk {
            for i in 0..blk {
                self.h[(c + i, e_prev + j)] = bmat[(i, j)];
                self.h[(e_prev + j, c + i)] = bmat[(i, j)];
            }
        }
        self.c += blk;
    }

    /// Rayleigh-Ritz on the expanded part `..e` past the locked columns;
    /// those are Ritz pairs themselves (unit vectors, `theta = H_jj`). The
    /// residual estimate of a Ritz pair `(theta, V y)` is `||B E^T y||`
    /// (the module docs of [`super`]): 0 for a locked one, and for all
    /// once the basis spans the free space.
    fn rayleigh_ritz(&self, block: &Block) -> Result<Ritz, LinalgError> {
        let (h, nl, e) = (&self.h, self.nl, self.e);
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
        let last = u.subrows(block.e_prev, block.blk);
        let estimate: Vec<f64> = idx
            .iter()
            .map(|&i| {
                if e >= self.free || i < nl {
                    0.0
                } else {
                    (block.bmat.as_ref() * last.col(i)).norm_l2()
                }
            })
            .collect();
        Ok(Ritz {
            u,
            idx,
            theta,
            estimate,
        })
    }

    /// The run's answer: the converged Ritz pairs with `theta > 0` as
    /// eigenpairs of the pencil, and for a run that `stop`s early the
    /// unconverged wanted ones and the block after them ([`Stalled`]).
    fn run(
        &self,
        op: &Operator<'_>,
        ritz: &Ritz,
        conv: &[bool],
        nev: usize,
        b: usize,
        stop: bool,
    ) -> Run {
        let (e, theta) = (self.e, &ritz.theta);
        let vectors = |pick: &[usize]| {
            let y = Mat::from_fn(e, pick.len(), |r, j| ritz.u[(r, ritz.idx[pick[j]])]);
            self.v.subcols(0, e) * &y
        };
        let pick: Vec<usize> = (0..e).filter(|&i| conv[i] && theta[i] > 0.0).collect();
        let x = vectors(&pick);
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
                start: vectors(&open[..open.len().min(b)]),
            }
        });
        Run { converged, stalled }
    }

    /// Thick restart: the basis contracted to the best `restart_size` Ritz
    /// vectors, the converged wanted ones first and locked, plus the
    /// residual block `W` of the full basis; `H` becomes diagonal (the Ritz
    /// values) with the arrow `B E^T Y` to the residual block.
    fn restart(
        &mut self,
        ritz: &Ritz,
        conv: &[bool],
        nev: usize,
        restart_size: usize,
        block: &Block,
    ) {
        let (e, blk) = (self.e, block.blk);
        let kk = restart_size.min(e);
        let mut keep: Vec<usize> = (0..kk).filter(|&j| j < nev && conv[j]).collect();
        self.nl = keep.len();
        keep.extend((0..kk).filter(|&j| !(j < nev && conv[j])));
        let y = Mat::from_fn(e, kk, |r, j| ritz.u[(r, ritz.idx[keep[j]])]);
        rotate_in_place(&mut self.v, e, y.as_ref());
        tall::copy(self.v.subcols_mut(kk, blk), block.w.as_ref());
        self.h.fill(0.0);
        let coupling = block.bmat.as_ref() * y.subrows(block.e_prev, blk);
        for j in 0..kk {
            self.h[(j, j)] = ritz.theta[keep[j]];
            for i in 0..blk {
                let x = if j < self.nl { 0.0 } else { coupling[(i, j)] };
                self.h[(kk + i, j)] = x;
                self.h[(j, kk + i)] = x;
            }
        }
        self.e = kk;
        self.c = kk + blk;
    }
}

/// The Ritz pairs of one sweep in descending `theta`: `theta[k]` is the
/// value of column `idx[k]` of `u` (the eigenvectors of `H[..e, ..e]`),
/// `estimate[k]` its residual estimate.
struct Ritz {
    u: Mat<f64>,
    idx: Vec<usize>,
    theta: Vec<f64>,
    estimate: Vec<f64>,
}

impl Ritz {
    /// Which pairs have converged: an estimate within `tolerance |theta|`,
    /// or within the round-off of `H`, [`FLOOR`] `eps theta_max` (the
    /// rigid-body modes' theta when the shift is small), which no residual
    /// gets below. Above the wanted band, the unwanted eigenvalues just
    /// above the shift have the largest `|theta|` (negative).
    fn converged(&self, tolerance: f64) -> Vec<bool> {
        let theta = &self.theta;
        let theta_max = theta
            .first()
            .map_or(0.0, |t| t.abs())
            .max(theta.last().map_or(0.0, |t| t.abs()));
        let floor = FLOOR * f64::EPSILON * theta_max;
        (0..theta.len())
            .map(|i| self.estimate[i] <= (tolerance * theta[i].abs()).max(floor))
            .collect()
    }

    /// Whether every one of the `nev` wanted Ritz values (with `e >= nev`
    /// of them) is within about 1e-6 of its eigenvalue (the error is the
    /// squared estimate over the gap), so that a shift above them lands
    /// just above the wanted band.
    fn close(&self, nev: usize, e: usize) -> bool {
        e >= nev && (0..nev).all(|i| self.estimate[i] <= 1e-3 * self.theta[i].abs())
    }
}

/// The sweeps of a run, and the bookkeeping of the stall rule.
#[derive(Default)]
struct Sweeps {
    step: usize,
    /// The most wanted pairs converged at once so far.
    record: usize,
    /// Sweeps past the first restart since the record.
    since: usize,
    restarts: usize,
}

impl Sweeps {
    /// Counts a sweep with `wanted_conv` wanted pairs converged. Sweeps
    /// before the first restart, while the basis still grows, are no
    /// stall (see the module docs).
    fn count(&mut self, wanted_conv: usize) {
        if wanted_conv > self.record {
            (self.record, self.since) = (wanted_conv, 0);
        } else if self.restarts > 0 {
            self.since += 1;
        }
    }

    /// Whether the run stalls: past the first restart (the basis no longer
    /// grows), `stall_sweeps > 0` sweeps in a row without a new converged
    /// wanted pair.
    fn stalled(&self, stall_sweeps: usize) -> bool {
        stall_sweeps > 0 && self.restarts > 0 && self.since >= stall_sweeps
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
