//! The shift-invert operator of the Lanczos runs, on one factor of
//! `K - sigma M` at a time: `OP = (K - sigma M)^-1 M` below the spectrum,
//! `-(K - s M)^-1 M` above the wanted eigenvalues (the Sturm check's
//! factor), or the free body's `T_perp K_held^-1 P M` ([`Held`]); and the
//! Sturm counts (Sylvester's law of inertia) on the same storage.

use super::run::basis_shape;
use super::{Held, LanczosParams, LanczosStats};
use crate::ldlt::Factor;
use crate::pencil::Pencil;
use crate::progress::{Progress, Stage};
use crate::tall;
use crate::LinalgError;
use faer::{Mat, MatRef};
use std::time::Instant;

/// [`Held`] with `M T`.
pub(super) struct HeldState<'a> {
    held: Held<'a>,
    m_rigid: Mat<f64>,
}

/// `OP = (K - sigma M)^-1 M` on the factor of `K - sigma M`, which it
/// factorises when first needed and again after a Sturm check has borrowed
/// its storage (one factor in memory at a time); counts the solves and times
/// the solves, the products with `M` and the factorisations. After
/// [`Operator::move_above`] the shift lies above the wanted eigenvalues and
/// the operator is `-(K - sigma M)^-1 M`: its positive `theta = 1 / (sigma -
/// lambda)` are the eigenvalues below the shift, the largest nearest it.
pub(super) struct Operator<'p> {
    pub(super) pencil: &'p Pencil,
    sigma: f64,
    /// 1 below the spectrum, -1 above the wanted eigenvalues:
    /// `theta = sign / (lambda - sigma)`.
    pub(super) sign: f64,
    /// The free body's support and rigid-body modes, until the shift
    /// moves above the band.
    held: Option<HeldState<'p>>,
    factor: Option<Factor>,
    /// Storage of a factor no longer held, reused by the next one.
    spare: Vec<f64>,
    progress: &'p dyn Progress,
    pub(super) solves: usize,
    pub(super) block_solves: usize,
    pub(super) solve_seconds: f64,
    pub(super) mass_seconds: f64,
    pub(super) mass_products: usize,
    pub(super) factorization_seconds: f64,
    pub(super) sturm_seconds: f64,
}

impl<'p> Operator<'p> {
    /// The operator at shift `sigma` (0 with `held`), on `factor` if given
    /// (a factor of `K - sigma M`, or the held one), else factorised when
    /// first needed in the storage `spare`.
    pub(super) fn new(
        pencil: &'p Pencil,
        sigma: f64,
        held: Option<Held<'p>>,
        factor: Option<Factor>,
        spare: Vec<f64>,
        progress: &'p dyn Progress,
    ) -> Self {
        let held = held.map(|h| HeldState {
            m_rigid: pencil.mul_mass(h.rigid),
            held: h,
        });
        Self {
            pencil,
            sigma,
            sign: 1.0,
            held,
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
        }
    }

    /// Copies the work counted and the times into `stats`.
    pub(super) fn record(&self, stats: &mut LanczosStats) {
        stats.solves = self.solves;
        stats.block_solves = self.block_solves;
        stats.solve_seconds = self.solve_seconds;
        stats.mass_seconds = self.mass_seconds;
        stats.mass_products = self.mass_products;
        stats.factorization_seconds = self.factorization_seconds;
        stats.sturm_seconds = self.sturm_seconds;
    }

    /// Factorises `K - sigma M` (if not held), checking that `sigma` lies
    /// below the spectrum.
    pub(super) fn factorize(&mut self) -> Result<&Factor, LinalgError> {
        if self.factor.is_none() {
            let t = Instant::now();
            let sigma = self.sigma;
            let f = match &self.held {
                // Reports its own stages.
                Some(h) => self
                    .pencil
                    .factorize_static(h.held.support, self.progress)?,
                None => {
                    self.progress.report(&Stage::Factorization { shift: sigma });
                    let f = self.pencil.refactorize(
                        sigma,
                        std::mem::take(&mut self.spare),
                        self.progress,
                    )?;
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
    pub(super) fn ensure_room(
        &self,
        nev: usize,
        params: &LanczosParams,
    ) -> Result<(), LinalgError> {
        let n = self.pencil.dim();
        let entries = self.pencil.factor_len();
        let resident = if self.factor.is_some() {
            entries
        } else {
            self.spare.len().min(entries)
        };
        let budget = self.pencil.budget();
        budget.ensure_factor(n, entries, resident)?;
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
        budget.ensure(
            (basis + factor) as u64,
            &format!(
                "a Lanczos run for {nev} modes ({vectors} vectors of {n} equations{with_factor})"
            ),
        )
    }

    /// Eigenvalues below `bound` by the inertia of `K - bound M`, in the
    /// storage of the operator's factor, which is given up.
    pub(super) fn sturm_count(&mut self, bound: f64) -> Result<usize, LinalgError> {
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
    pub(super) fn move_above(&mut self, bound: f64) -> Result<(f64, usize), LinalgError> {
        let (s, count, f) = self.factor_at(bound)?;
        self.factor = Some(f);
        self.sigma = s;
        self.sign = -1.0;
        self.held = None;
        Ok((s, count))
    }

    /// `lambda` of an eigenvalue `theta` of the operator.
    pub(super) fn lambda(&self, theta: f64) -> f64 {
        self.sigma + self.sign / theta
    }

    /// The `LDL^T` of `K - s M` for `s` from `bound` up (a shift on an
    /// eigenvalue, a zero pivot, is moved up by a relative 1e-8), in the
    /// storage of the operator's factor, with its count of eigenvalues
    /// below `s`; counted as the Sturm check's time.
    pub(super) fn factor_at(&mut self, bound: f64) -> Result<(f64, usize, Factor), LinalgError> {
        let t = Instant::now();
        let mut storage = match self.factor.take() {
            Some(f) => f.into_storage(),
            None => std::mem::take(&mut self.spare),
        };
        let mut s = bound;
        for _ in 0..3 {
            self.progress.report(&Stage::Factorization { shift: s });
            match self.pencil.refactorize(s, storage, self.progress) {
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
    pub(super) fn solve(&mut self, mut x: Mat<f64>) -> Result<Mat<f64>, LinalgError> {
        if let Some(h) = &self.held {
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
        if let Some(h) = &self.held {
            // T_perp: the held response has a rigid-body part; without it
            // the block need not lose half its norm to the basis
            // projection, which then takes a second pass and product.
            let c = tall::gram(h.m_rigid.as_ref(), x.as_ref());
            tall::add_product(x.as_mut(), h.held.rigid, c.as_ref(), -1.0);
        }
        Ok(x)
    }

    /// `M X`.
    pub(super) fn mass(&mut self, x: MatRef<'_, f64>) -> Mat<f64> {
        let t = Instant::now();
        let mx = self.pencil.mul_mass(x);
        self.mass_seconds += t.elapsed().as_secs_f64();
        self.mass_products += x.ncols();
        mx
    }
}
