//! The solve as a small state machine: one method per state, each
//! returning the next state.
//!
//! ```text
//! Count ──> Dense | Empty                          (answers)
//!   └──> FirstRun ──> Finish                       (no Sturm check)
//!          └──> PlaceCheck ──> Check ──> Finish
//!                                ├──> BackToTop ──> Run
//!                                └──> Run ──> Check
//!                                      └──> Slice ──> Check
//! ```
//!
//! [`State::Count`] sizes the solve (a band's Sturm count), the first run
//! converges what it can at the initial shift, [`State::PlaceCheck`] puts
//! the Sturm bound above it, and [`State::Check`] compares the count with
//! the eigenvalues found: done, an error, or one more run on the check's
//! factor, at the band's top or on a slice below it after a stall (the
//! module docs of [`super`]). [`State::Finish`] orders the converged pairs.

use super::dense::{dense_pairs, spans_the_space};
use super::operator::Operator;
use super::run::{krylov_schur, Locked, Rng, Run, Stalled};
use super::sturm::{Sturm, STALL_SWEEPS};
use super::{EigenSolution, Held, LanczosParams, LanczosStats, SturmReport};
use crate::eigen::{EigenPairs, Wanted};
use crate::ldlt::Factor;
use crate::pencil::Pencil;
use crate::progress::{Progress, Stage};
use crate::LinalgError;
use faer::Mat;
use std::time::Instant;

/// Where the solve stands; each state names the method that handles it.
pub(super) enum State {
    /// [`Solver::count`]: the number wanted (a band's Sturm count), and
    /// whether a Lanczos basis holds it.
    Count,
    /// [`Solver::dense`]: too many pairs for a basis.
    Dense,
    /// [`Solver::empty`]: nothing wanted.
    Empty,
    /// [`Solver::first_run`]: the run at the initial shift.
    FirstRun,
    /// [`Solver::place_check`]: the Sturm bound above the first run's pairs
    /// (what remains of a stalled run goes along).
    PlaceCheck(Option<Stalled>),
    /// [`Solver::check`]: the count at the bound against the pairs found.
    Check(Sturm),
    /// [`Solver::back_to_top`]: the operator's shift back to the bound.
    BackToTop(Sturm),
    /// [`Solver::run_again`]: one more run on the operator's slice.
    Run(Sturm),
    /// [`Solver::slice`]: a stalled run's rest, on a shift below the slice.
    Slice(Sturm, Stalled),
    /// [`Solver::finish`]: the converged pairs ordered and checked.
    Finish(Option<SturmReport>),
}

/// One solve of [`super::lanczos_on`]: the operator, the pairs converged
/// so far and the work counted.
pub(super) struct Solver<'a> {
    pub(super) pencil: &'a Pencil,
    pub(super) wanted: Wanted,
    held: Option<Held<'a>>,
    pub(super) params: &'a LanczosParams,
    pub(super) progress: &'a dyn Progress,
    pub(super) op: Operator<'a>,
    /// The initial shift `sigma` (the scale of the shifts placed later).
    pub(super) sigma: f64,
    pub(super) k_diag: Vec<f64>,
    pub(super) stats: LanczosStats,
    /// Eigenpairs wanted: the count, a band's Sturm count, or the smaller
    /// of the two.
    pub(super) nev: usize,
    /// A band's bound and its Sturm count, made before any run (for a count
    /// below a bound, only where the count does not cut the band).
    pub(super) band: Option<(f64, usize)>,
    /// The converged pairs of every run (the rigid-body modes of a held
    /// operator first).
    pub(super) locked: Locked,
    rng: Rng,
    /// Start of the solve, and of the Lanczos iterations.
    pub(super) started: Instant,
    pub(super) iterations: Instant,
    /// Factorisation and Sturm time before the iterations.
    pub(super) first_factorization: f64,
    pub(super) band_count_seconds: f64,
}

impl<'a> Solver<'a> {
    /// Checks the pencil and the request and sets up the operator at the
    /// initial shift: `params.shift`, else `-1e-6 trace(K) / trace(M)`
    /// (below every eigenvalue, scaled to the model), or 0 when `held`.
    pub(super) fn new(
        pencil: &'a Pencil,
        factor: Option<Factor>,
        wanted: Wanted,
        held: Option<Held<'a>>,
        params: &'a LanczosParams,
        progress: &'a dyn Progress,
    ) -> Result<Self, LinalgError> {
        let started = Instant::now();
        let n = pencil.dim();
        let stats = LanczosStats {
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
            Some(f) if held.is_none() && !f.is_fixed() && f.shift() == sigma => {
                (Some(f), Vec::new())
            }
            Some(f) => (None, f.into_storage()),
            None => (None, Vec::new()),
        };
        if let (Some(h), Wanted::Lowest(count)) = (&held, wanted) {
            elastic_beyond_rigid(count, h)?;
        }
        // The rigid-body modes of a held operator are known: lambda = 0.
        let locked = match &held {
            Some(h) => Locked {
                x: h.rigid.to_owned(),
                lambda: vec![0.0; h.rigid.ncols()],
            },
            None => Locked {
                x: Mat::zeros(n, 0),
                lambda: vec![],
            },
        };
        Ok(Self {
            pencil,
            wanted,
            held,
            params,
            progress,
            op: Operator::new(pencil, sigma, held, factor, spare, progress),
            sigma,
            k_diag,
            stats,
            nev: wanted.count().unwrap_or(0),
            band: None,
            locked,
            rng: Rng(0x9e37_79b9_7f4a_7c15),
            started,
            iterations: started,
            first_factorization: 0.0,
            band_count_seconds: 0.0,
        })
    }

    /// Runs the states from [`State::Count`] to an answer.
    pub(super) fn solve(mut self) -> Result<EigenSolution, LinalgError> {
        let mut state = State::Count;
        loop {
            state = match state {
                State::Count => self.count()?,
                State::Dense => return self.dense(),
                State::Empty => return Ok(self.empty()),
                State::FirstRun => self.first_run()?,
                State::PlaceCheck(stalled) => self.place_check(stalled)?,
                State::Check(sturm) => self.check(sturm)?,
                State::BackToTop(sturm) => self.back_to_top(sturm)?,
                State::Run(sturm) => self.run_again(sturm)?,
                State::Slice(sturm, stalled) => self.slice(sturm, stalled)?,
                State::Finish(report) => return self.finish(report),
            };
        }
    }

    /// The number of pairs wanted: for a band, the Sturm count at its upper
    /// bound; for a count below a bound, the smaller of the two (the band's
    /// check proves the pairs below the bound when they are no more than
    /// the count, else the count's check proves the lowest `count`, and no
    /// run looks for the band's pairs above them). A count whose basis
    /// would span the space goes to the dense solver; otherwise the memory
    /// for the run is checked and the operator factorised (which also
    /// checks that the shift lies below the spectrum).
    fn count(&mut self) -> Result<State, LinalgError> {
        match self.wanted {
            Wanted::Below(bound) => {
                let count = self.op.sturm_count(bound)?;
                self.band = Some((bound, count));
                self.nev = count;
            }
            Wanted::LowestBelow { count, bound } => {
                let below = self.op.sturm_count(bound)?;
                if below <= count {
                    self.band = Some((bound, below));
                    self.nev = below;
                } else if let Some(h) = &self.held {
                    elastic_beyond_rigid(count, h)?;
                }
            }
            Wanted::Lowest(_) => {}
        }
        let known = self.held.map_or(0, |h| h.rigid.ncols());
        let n = self.pencil.dim();
        let left = self.nev.saturating_sub(known);
        if spans_the_space(left, n - known.min(n), self.params) {
            return Ok(State::Dense);
        }
        self.op.ensure_room(left, self.params)?;
        self.op.factorize()?;
        if self.nev == 0 {
            return Ok(State::Empty);
        }
        self.first_factorization = self.op.factorization_seconds;
        self.band_count_seconds = self.op.sturm_seconds;
        self.iterations = Instant::now();
        Ok(State::FirstRun)
    }

    /// The wanted pairs by the dense solver, once the operator's factor is
    /// given up; a band's count goes into the report.
    fn dense(self) -> Result<EigenSolution, LinalgError> {
        let Self {
            pencil,
            wanted,
            progress,
            op,
            sigma,
            mut stats,
            nev,
            band,
            started,
            ..
        } = self;
        op.record(&mut stats);
        drop(op);
        let (pairs, residuals) = dense_pairs(pencil, wanted, nev, progress)?;
        stats.dense = true;
        progress.report(&Stage::Done {
            seconds: started.elapsed().as_secs_f64(),
        });
        let keep = pairs.values.len();
        Ok(EigenSolution {
            pairs,
            residuals,
            shift: sigma,
            sturm: band.map(|(bound, count)| SturmReport {
                bound,
                count,
                found_first: keep,
                found: keep,
            }),
            stats,
        })
    }

    /// No pairs: a count of 0, or a band without eigenvalues.
    fn empty(mut self) -> EigenSolution {
        self.op.record(&mut self.stats);
        EigenSolution {
            pairs: EigenPairs {
                values: vec![],
                vectors: Mat::zeros(self.pencil.dim(), 0),
            },
            residuals: vec![],
            shift: self.sigma,
            sturm: self.band.map(|(bound, count)| SturmReport {
                bound,
                count,
                found_first: 0,
                found: 0,
            }),
            stats: self.stats,
        }
    }

    /// The first run, at the initial shift, for the pairs not known yet.
    /// With a Sturm check to follow it may stop early (a stall, see
    /// [`STALL_SWEEPS`]); its unconverged rest then goes to the check's
    /// shift.
    fn first_run(&mut self) -> Result<State, LinalgError> {
        let checked = self.params.sturm_check || self.band.is_some();
        let left = self.nev.saturating_sub(self.locked.lambda.len());
        let mut stalled = None;
        if left > 0 {
            let stall_sweeps = if checked { STALL_SWEEPS } else { 0 };
            let run = self.lanczos_run(left, stall_sweeps, None)?;
            self.locked.append(run.converged);
            stalled = run.stalled;
        }
        Ok(if checked {
            State::PlaceCheck(stalled)
        } else {
            State::Finish(None)
        })
    }

    /// One [`krylov_schur`] run on the operator for `nev` pairs beyond the
    /// locked ones.
    pub(super) fn lanczos_run(
        &mut self,
        nev: usize,
        stall_sweeps: usize,
        start: Option<Mat<f64>>,
    ) -> Result<Run, LinalgError> {
        krylov_schur(
            &mut self.op,
            &self.locked,
            nev,
            self.params,
            self.progress,
            &mut self.rng,
            &mut self.stats,
            stall_sweeps,
            start.as_ref().map(|x| x.as_ref()),
        )
    }
}

/// A count of a free body's modes on the held operator must go beyond its
/// rigid-body modes: the Sturm check's bound lies just above the highest
/// mode found, and with the rigid-body modes alone it would sit on them.
fn elastic_beyond_rigid(count: usize, held: &Held<'_>) -> Result<(), LinalgError> {
    if count <= held.rigid.ncols() {
        return Err(LinalgError::Unservable(format!(
            "{count} modes of a free body with {} rigid-body modes: the held \
             operator needs at least one elastic mode",
            held.rigid.ncols()
        )));
    }
    Ok(())
}
