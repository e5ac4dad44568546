//! The Sturm check and the shift moves after the first run (the module
//! docs of [`super`]): by Sylvester's law of inertia the negative pivots of
//! the `LDL^T` of `K - s M` count the eigenvalues below `s`. The check's
//! factor is also the operator of the runs that follow,
//! `-(K - s M)^-1 M`, on the band's top or, after a stall, on a slice
//! below it.

use super::run::{Locked, Stalled};
use super::solver::{Solver, State};
use super::SturmReport;
use crate::progress::Stage;
use crate::LinalgError;
use faer::Mat;

/// The Sturm check and the operator's shift after the first run.
pub(super) struct Sturm {
    /// The check's shift `s`: a band's bound, or a shift just above the
    /// first run's highest wanted pair.
    bound: f64,
    /// Eigenvalues below `bound` (the inertia of `K - bound M`).
    count: usize,
    /// Of those, found by the first run.
    found_first: usize,
    /// The operator's shift and its count: the band's top, or a slice
    /// below it after a stall there.
    slice: (f64, usize),
    /// Start vectors of the next run: the unconverged Ritz vectors of a
    /// stalled one.
    start: Option<Mat<f64>>,
    /// Runs after the first.
    attempts: usize,
    /// Moves of the shift below the band's top.
    moves: usize,
}

impl Solver<'_> {
    /// Places the Sturm check after the first run: a band's bound, counted
    /// before; otherwise a shift just above the `nev`-th eigenvalue found
    /// (or, after a stall, above the `nev`-th Ritz value, an upper bound of
    /// its eigenvalue, into the gap to the next one), where the operator
    /// moves with the check's factor.
    pub(super) fn place_check(&mut self, stalled: Option<Stalled>) -> Result<State, LinalgError> {
        // The first run's blocks are free now: their pages go back before
        // the Sturm factorisation takes its own.
        crate::memory::release_free_memory();
        let (bound, count) = match self.band {
            Some((bound, count)) => (bound, count),
            None => {
                let ritz = stalled.as_ref().map_or(&[][..], |s| &s.lambda[..]);
                let v = found_and_ritz(&self.locked, ritz);
                let top = v[self.nev.min(v.len()) - 1];
                let shift = if stalled.is_some() {
                    shift_above(&v, top, (top - self.sigma).abs())
                } else {
                    top + 1e-4 * (top - self.sigma).abs()
                };
                self.op.move_above(shift)?
            }
        };
        Ok(State::Check(Sturm {
            bound,
            count,
            found_first: self.locked.count_below(bound),
            slice: (bound, count),
            start: stalled.map(|s| s.start),
            attempts: 0,
            moves: 0,
        }))
    }

    /// Compares the count with the eigenvalues found below the bound: more
    /// is an error (pairs found twice, or spurious ones, never returned as
    /// modes), as many completes the solve, fewer asks for another run
    /// (within [`super::LanczosParams::sturm_runs`]), from the band's top
    /// when the operator is still below the spectrum or a slice below the
    /// top is complete.
    pub(super) fn check(&mut self, sturm: Sturm) -> Result<State, LinalgError> {
        let (bound, count) = (sturm.bound, sturm.count);
        let have = self.locked.count_below(bound);
        self.progress.report(&Stage::SturmCheck {
            bound,
            count,
            found: have,
        });
        // Eigenvalues within round-off of the bound (a band's bound on
        // a frequency) may fall on either side of the count.
        let tol = 1e-10 * bound.abs();
        let surely = self.locked.count_below(bound - tol);
        let maybe = self.locked.count_below(bound + tol);
        if surely > count {
            return Err(LinalgError::SturmSpurious {
                found: have,
                count,
                bound,
            });
        }
        if maybe >= count {
            return Ok(State::Finish(Some(SturmReport {
                bound,
                count,
                found_first: sturm.found_first,
                found: have,
            })));
        }
        if sturm.attempts == self.params.sturm_runs {
            return Err(LinalgError::SturmMissing {
                found: have,
                count,
                bound,
                runs: sturm.attempts,
            });
        }
        let (shift, below) = sturm.slice;
        let slice_done = shift != bound && self.locked.count_below(shift) >= below;
        Ok(if self.op.sign > 0.0 || slice_done {
            State::BackToTop(sturm)
        } else {
            State::Run(sturm)
        })
    }

    /// Moves the operator to the band's top: a band's count came first, or
    /// a slice below it is complete.
    pub(super) fn back_to_top(&mut self, mut sturm: Sturm) -> Result<State, LinalgError> {
        (sturm.bound, _) = self.op.move_above(sturm.bound)?;
        sturm.slice = (sturm.bound, sturm.count);
        Ok(State::Run(sturm))
    }

    /// One more run, for the eigenvalues of the slice still missing, from
    /// the stalled run's rest if there is one. It may stall too while the
    /// shift can still move down ([`MAX_MOVES`]), after twice
    /// [`STALL_SWEEPS`]: a move below the band's top costs a factorisation
    /// more.
    pub(super) fn run_again(&mut self, mut sturm: Sturm) -> Result<State, LinalgError> {
        sturm.attempts += 1;
        let (shift, below) = sturm.slice;
        let missing = below - self.locked.count_below(shift);
        let stall_sweeps = if sturm.moves < MAX_MOVES {
            2 * STALL_SWEEPS
        } else {
            0
        };
        let run = self.lanczos_run(missing, stall_sweeps, sturm.start.take())?;
        self.locked.append(run.converged);
        Ok(match run.stalled {
            Some(stalled) => State::Slice(sturm, stalled),
            None => State::Check(sturm),
        })
    }

    /// After a stalled run the rest lie farther below its shift: a slice
    /// below it, just above the highest of them, with a count of its own
    /// (unless that would not lie below the slice, which ends the moves);
    /// the next run starts from the stalled run's rest.
    pub(super) fn slice(
        &mut self,
        mut sturm: Sturm,
        stalled: Stalled,
    ) -> Result<State, LinalgError> {
        sturm.moves += 1;
        let hi = stalled.lambda.iter().copied().fold(f64::MIN, f64::max);
        let v = found_and_ritz(&self.locked, &stalled.lambda);
        let shift = shift_above(&v, hi, (hi - self.sigma).abs()).min(sturm.slice.0);
        if shift < sturm.slice.0 {
            sturm.slice = self.op.move_above(shift)?;
        } else {
            sturm.moves = MAX_MOVES;
        }
        sturm.start = Some(stalled.start);
        Ok(State::Check(sturm))
    }
}

/// Sweeps without a new converged wanted pair after which the first run
/// hands over to a shift above the wanted band (twice as many for a move
/// below the band's top, which costs a factorisation more).
pub(super) const STALL_SWEEPS: usize = 4;

/// Moves of the shift below the band's top after stalls.
const MAX_MOVES: usize = 4;

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
pub(super) fn shift_above(v: &[f64], top: f64, span: f64) -> f64 {
    let next = v
        .iter()
        .copied()
        .filter(|&x| x > top)
        .fold(f64::INFINITY, f64::min);
    let half = (0.5 * (next - top)).min(0.05 * span);
    top + half.max(1e-4 * span)
}
