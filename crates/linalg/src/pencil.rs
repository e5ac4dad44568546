//! The shifted matrices `A(sigma) = K - sigma M` of one pencil and their
//! `LDL^T` factorisations: the operator `(K - sigma M)^-1 M` of shift-invert
//! eigen solvers, and the Sturm count (inertia) at any shift.
//!
//! The pencil keeps its own compact copy of `K` and `M`: their lower
//! triangles on one union pattern (`LowerPattern`), 0.17 GB at 3e5 DOFs
//! where both in full storage take 0.52 GB, so a caller that needs them no
//! more can drop them. The values of `A(sigma)` are `k - sigma m` entry by
//! entry. The symbolic analysis ([`SymbolicLdlt`]: ordering, elimination
//! tree, supernodes, the plan of parallel solves) is computed once from the
//! pattern and shared by every shift. The numeric factorisation is a
//! supernodal `LDL^T` without pivoting in faer's layout, parallel over the
//! elimination tree ([`crate::ldlt`]): `A(sigma)` is positive definite
//! below the spectrum and, above it, stable enough for the inertia that a
//! Sturm check needs (the practice of Lanczos codes in FE programs).

use crate::eigen::EigenPairs;
use crate::lanczos::residuals_of;
use crate::ldlt::numeric::Input;
use crate::ldlt::{Factor, LdltParams, SymbolicLdlt};
use crate::lower::LowerPattern;
use crate::memory::Budget;
use crate::ordering::{nested_dissection, Ordering};
use crate::progress::{Progress, Stage};
use crate::{LinalgError, SparseMat};
use faer::{Mat, MatRef};

/// The pencil `(K, M)`: the lower triangle of `K` on the union pattern of
/// both, that of `M` on its own pattern of nonzeros (a third of the union
/// for solids: products with `M` read only that), and the analysis of the
/// union.
#[derive(Clone, Debug)]
pub struct Pencil {
    pattern: LowerPattern,
    k: Vec<f64>,
    mass_pattern: LowerPattern,
    m: Vec<f64>,
    symbolic: SymbolicLdlt,
    /// Storage touched while the ordering ran, for the first factor.
    spare: Spare,
}

/// Storage for a factor, taken once, and how many of its values are
/// resident (touched).
#[derive(Debug, Default)]
struct Spare(std::sync::Mutex<(Vec<f64>, usize)>);

impl Spare {
    fn take(&self) -> (Vec<f64>, usize) {
        std::mem::take(&mut *self.0.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

impl Clone for Spare {
    /// A clone holds none.
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl Pencil {
    /// Copies the lower triangles of the symmetric `k` and `m` onto their
    /// union pattern and analyses it with `ordering` (the time goes into the
    /// ordering for large models), reporting the ordering and the analysis
    /// to `progress`. With `within` (ascending equations, renumbered
    /// `0..within.len()`), the pencil is that of the submatrices on those
    /// equations, the body held at the others: its compact copy comes
    /// straight from `k` and `m`, without the submatrices in full storage.
    /// `k` and `m` are not borrowed afterwards.
    pub fn analyze(
        k: &SparseMat,
        m: &SparseMat,
        within: Option<&[usize]>,
        ordering: Ordering,
        progress: &dyn Progress,
    ) -> Result<Self, LinalgError> {
        let t = std::time::Instant::now();
        let equations = within.map_or(k.nrows(), <[usize]>::len);
        progress.report(&Stage::Ordering { equations });
        let pencil = Self::analyze_on(k, m, within, ordering)?;
        progress.report(&Stage::Analyzed {
            factor_len: pencil.factor_len(),
            flops: pencil.factor_flops(),
            seconds: t.elapsed().as_secs_f64(),
        });
        Ok(pencil)
    }

    /// The analysis of [`Self::analyze`], unreported.
    fn analyze_on(
        k: &SparseMat,
        m: &SparseMat,
        keep: Option<&[usize]>,
        ordering: Ordering,
    ) -> Result<Self, LinalgError> {
        let n = k.nrows();
        if k.ncols() != n || m.nrows() != n || m.ncols() != n {
            return Err(LinalgError::Dimension(format!(
                "pencil with K {}x{} and M {}x{}",
                k.nrows(),
                k.ncols(),
                m.nrows(),
                m.ncols()
            )));
        }
        if let Some(keep) = keep {
            if let Some(w) = keep.windows(2).find(|w| w[0] >= w[1]) {
                return Err(LinalgError::Dimension(format!(
                    "kept equations must ascend: {} before {}",
                    w[0], w[1]
                )));
            }
            if let Some(&bad) = keep.last().filter(|&&i| i >= n) {
                return Err(LinalgError::Dimension(format!(
                    "equation {bad} kept of a {n}-equation pencil"
                )));
            }
        }
        let size = keep.map_or(n, |keep| keep.len());
        if size > u32::MAX as usize {
            return Err(LinalgError::Dimension(format!(
                "{size} equations: the shift-invert solver takes at most {}",
                u32::MAX
            )));
        }
        // METIS (serial) runs on K's own pattern while the other thread
        // copies the lower triangles; when M has entries off K's pattern the
        // ordering waits for their union. On kept equations the order of
        // all, restricted, has no more fill than on the full matrix
        // (eliminating a subgraph in the induced order fills a subgraph).
        let nested = ordering.resolve(size) == Ordering::NestedDissection;
        let shared = LowerPattern::share_pattern(k, m);
        // Then it touches storage for the first factor until the ordering
        // is done: room for 16 entries of L per entry of K's lower triangle
        // (10 at 3e5 DOFs of the C3D8 beam), 4 of them touched at most (so
        // that the memory in use stays below the Lanczos run's): the first
        // factorisation then finds that much of its storage in memory.
        let ordered = std::sync::atomic::AtomicBool::new(false);
        let (permutation, ((pattern, kv, mass_pattern, mv), spare)) = rayon::join(
            || {
                let order = (nested && shared).then(|| {
                    let order = nested_dissection(k.symbolic())?;
                    Ok(match keep {
                        Some(keep) => order.restricted(keep),
                        None => order,
                    })
                });
                ordered.store(true, std::sync::atomic::Ordering::Release);
                order
            },
            || {
                let (pattern, kv, mv) = match keep {
                    Some(keep) => LowerPattern::of_pair_within(k, m, keep),
                    None => LowerPattern::of_pair_sharing(k, m, shared),
                };
                let (mass_pattern, mv) = pattern.without_zeros(&mv);
                let spare = crate::memory::touch_until(&ordered, 16 * kv.len(), 4 * kv.len());
                ((pattern, kv, mass_pattern, mv), spare)
            },
        );
        let permutation = match permutation {
            Some(p) => Some(p?),
            None if nested => Some(pattern.with_symbolic(nested_dissection)?),
            None => None,
        };
        let symbolic = pattern.with_symbolic(|p| SymbolicLdlt::analyze_permuted(p, permutation))?;
        Ok(Self {
            pattern,
            k: kv,
            mass_pattern,
            m: mv,
            symbolic,
            spare: Spare(std::sync::Mutex::new(spare)),
        })
    }

    /// `K X`.
    pub fn mul_stiffness(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        self.pattern.mul(&self.k, x)
    }

    /// `M X`.
    pub fn mul_mass(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        self.mass_pattern.mul(&self.m, x)
    }

    /// This pencil with its factorisations under `par`
    /// ([`SymbolicLdlt::with_parallelism`]); its factors keep it.
    pub fn with_parallelism(mut self, par: faer::Par) -> Self {
        self.symbolic = self.symbolic.with_parallelism(par);
        self
    }

    /// This pencil with its factorisations, Lanczos runs and dense eigen
    /// solves held to `budget` ([`SymbolicLdlt::with_budget`]); its factors
    /// keep it.
    pub fn with_budget(mut self, budget: Budget) -> Self {
        self.symbolic = self.symbolic.with_budget(budget);
        self
    }

    /// The memory budget of this pencil's solves.
    pub fn budget(&self) -> Budget {
        self.symbolic.budget()
    }

    /// `K` and `M` in dense storage, for the dense eigen solver.
    pub(crate) fn to_dense(&self) -> (Mat<f64>, Mat<f64>) {
        let eye = Mat::<f64>::identity(self.dim(), self.dim());
        (
            self.mul_stiffness(eye.as_ref()),
            self.mul_mass(eye.as_ref()),
        )
    }

    /// Each pair's residual `||K x - lambda M x|| / ||K x||`, as
    /// [`crate::lanczos::residuals`] defines it.
    pub(crate) fn residuals(&self, pairs: &EigenPairs) -> Vec<f64> {
        let (x, values) = (pairs.vectors.as_ref(), &pairs.values);
        let (kx, mx) = (self.mul_stiffness(x), self.mul_mass(x));
        residuals_of(&kx, &mx, values, x, &self.stiffness_diagonal())
    }

    /// The diagonal of `K`.
    pub fn stiffness_diagonal(&self) -> Vec<f64> {
        self.pattern.diagonal(&self.k)
    }

    /// The diagonal of `M`.
    pub fn mass_diagonal(&self) -> Vec<f64> {
        self.mass_pattern.diagonal(&self.m)
    }

    /// Number of equations.
    pub fn dim(&self) -> usize {
        self.pattern.dim()
    }

    /// The ordering that was used (with [`Ordering::Auto`] resolved).
    pub fn ordering(&self) -> Ordering {
        self.symbolic.ordering()
    }

    /// Stored entries of the factor `L`.
    pub fn factor_len(&self) -> usize {
        self.symbolic.factor_len()
    }

    /// Floating-point operations of one numeric factorisation.
    pub fn factor_flops(&self) -> f64 {
        self.symbolic.factor_flops()
    }

    /// The diagonal of `K - sigma M`, with 1 on a `fixed` equation where
    /// it is 0 (as [`Input::Shifted`] forms it).
    fn shifted_diagonal(&self, sigma: f64, fixed: Option<&[bool]>) -> Vec<f64> {
        let mut d = self.stiffness_diagonal();
        for (j, (d, m)) in d.iter_mut().zip(self.mass_diagonal()).enumerate() {
            *d += -sigma * m;
            if fixed.is_some_and(|f| f[j]) && *d == 0.0 {
                *d = 1.0;
            }
        }
        d
    }

    /// Factorises `K - sigma M`. An exactly zero pivot (a shift on an
    /// eigenvalue, or a singular `K` at `sigma = 0`) is an error naming the
    /// row in the original order. The factorisation's progress goes to
    /// `progress` (the caller reports its start and end).
    pub fn factorize(&self, sigma: f64, progress: &dyn Progress) -> Result<Factor, LinalgError> {
        self.refactorize(sigma, Vec::new(), progress)
    }

    /// [`Self::factorize`] into the storage of a factor that is no longer
    /// needed (the factor of a previous shift): the Sturm check of a large
    /// model then holds one factor in memory, not two.
    pub fn refactorize(
        &self,
        sigma: f64,
        values: Vec<f64>,
        progress: &dyn Progress,
    ) -> Result<Factor, LinalgError> {
        self.factorize_values(sigma, None, values, progress)
    }

    /// The `LDL^T` of `K` for static modes, with the equations `fixed` (may
    /// be none) held at zero: their rows and columns decoupled (diagonal
    /// kept), on the pencil's own analysis. Solving with zero right-hand
    /// sides there gives the static response of the body supported at
    /// `fixed` (the inertia-relief attachment modes' statically determinate
    /// support) without a sub-matrix or a second ordering. `K` must be
    /// regular there: a pivot that vanishes against its diagonal is
    /// [`LinalgError::Singular`] naming the row. Reported to `progress` as a
    /// factorisation at shift 0. With nothing fixed the factor can serve as
    /// the Lanczos operator at shift 0 ([`crate::lanczos::lanczos_on`]);
    /// otherwise its storage is reused there.
    pub fn factorize_static(
        &self,
        fixed: &[usize],
        progress: &dyn Progress,
    ) -> Result<Factor, LinalgError> {
        let t = std::time::Instant::now();
        progress.report(&Stage::Factorization { shift: 0.0 });
        let mask = (!fixed.is_empty()).then(|| {
            let mut mask = vec![false; self.dim()];
            for &i in fixed {
                mask[i] = true;
            }
            mask
        });
        let mut f = self
            .factorize_values(0.0, mask.as_deref(), Vec::new(), progress)?
            .regular()?;
        if mask.is_some() {
            f = f.with_fixed();
        }
        progress.report(&Stage::Factorized {
            shift: 0.0,
            seconds: t.elapsed().as_secs_f64(),
        });
        Ok(f)
    }

    fn factorize_values(
        &self,
        sigma: f64,
        fixed: Option<&[bool]>,
        values: Vec<f64>,
        progress: &dyn Progress,
    ) -> Result<Factor, LinalgError> {
        // No storage given: the one touched during the analysis, if unused.
        let (mut values, resident) = match values.capacity() {
            0 => self.spare.take(),
            _ => {
                let len = values.len();
                (values, len)
            }
        };
        let diagonal = self.shifted_diagonal(sigma, fixed);
        let input = Input::Shifted {
            pattern: &self.pattern,
            k: &self.k,
            mass: &self.mass_pattern,
            m: &self.m,
            sigma,
            fixed,
        };
        let factored = self
            .symbolic
            .factorize_input_into(input, &mut values, resident, progress);
        Factor::scanned(
            &self.symbolic,
            factored,
            values,
            sigma,
            &diagonal,
            LdltParams::default(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::NoProgress;
    use crate::sparse::from_triplets;
    use faer::sparse::Triplet;
    use faer::Mat;

    fn chain(n: usize) -> (SparseMat, SparseMat) {
        let mut t = Vec::new();
        let mut tm = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, if i == n - 1 { 1.0 } else { 2.0 }));
            tm.push(Triplet::new(i, i, 1.0));
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -1.0));
                t.push(Triplet::new(i + 1, i, -1.0));
            }
        }
        (
            from_triplets(n, n, &t).unwrap(),
            from_triplets(n, n, &tm).unwrap(),
        )
    }

    /// The memory budget is the pencil's own value: a pencil held to a
    /// budget smaller than its factor refuses the factorisation and the
    /// eigen solve before either starts, naming the cap, while a clone
    /// without the cap (the default) factorises.
    #[test]
    fn a_budget_is_held_by_the_pencil_it_is_given_to() {
        let (k, m) = chain(200_000);
        let free = Pencil::analyze(&k, &m, None, Ordering::Amd, &NoProgress).unwrap();
        assert!(free.factor_len() >= 1 << 18, "{}", free.factor_len());
        assert_eq!(free.budget(), Budget::MACHINE);
        let held = free.clone().with_budget(Budget::at_most(Some(1 << 10)));
        let refused = |e: LinalgError| match e {
            LinalgError::OutOfMemory { bound, .. } => {
                assert!(bound.contains("--max-memory"), "{bound}")
            }
            other => panic!("expected the budget to refuse, got {other:?}"),
        };
        refused(held.factorize(0.5, &NoProgress).unwrap_err());
        let request = crate::solver::EigenRequest::new(crate::eigen::Wanted::Lowest(3))
            .solver(crate::solver::Solver::Sparse);
        refused(held.eigen(None, &request, &NoProgress).unwrap_err());
        let f = free.factorize(0.5, &NoProgress).unwrap();
        assert_eq!(f.dim(), 200_000);
    }

    /// A body held at some equations: the pencil taken straight from the
    /// full matrices (nested dissection of the full pattern, restricted)
    /// solves and counts as the pencil of the submatrices does.
    #[test]
    fn the_pencil_within_kept_equations_solves_as_the_submatrices_do() {
        let n = 60;
        let (k, m) = chain(n);
        let keep: Vec<usize> = (0..n).filter(|&i| i != 0 && i != 30).collect();
        let reverse =
            crate::ordering::Dissection::from_order((0..n).rev().collect(), (0..n).rev().collect());
        let crate::ordering::Dissection {
            forward: fwd,
            inverse: inv,
            ..
        } = reverse.restricted(&keep);
        assert_eq!(fwd, (0..keep.len()).rev().collect::<Vec<_>>());
        assert!(inv.iter().enumerate().all(|(old, &new)| fwd[new] == old));
        let sub = |a: &SparseMat| crate::sparse::submatrix(a, &keep, &keep);
        let b = Mat::from_fn(keep.len(), 3, |i, j| (i * (j + 2) % 7) as f64 - 3.0);
        // A consistent mass on K's pattern (the ordering of the full
        // pattern, restricted) and a lumped one (the kept pattern's own).
        let consistent = SparseMat::new(
            k.symbolic().to_owned().unwrap(),
            k.val()
                .iter()
                .map(|v| if *v > 0.0 { 1.0 } else { 0.1 })
                .collect(),
        );
        for (m, ordering) in [
            (&m, Ordering::Amd),
            (&m, Ordering::NestedDissection),
            (&consistent, Ordering::NestedDissection),
        ] {
            let within = Pencil::analyze(&k, m, Some(&keep), ordering, &NoProgress).unwrap();
            let whole = Pencil::analyze(&sub(&k), &sub(m), None, ordering, &NoProgress).unwrap();
            let (f, g) = (
                within.factorize(1.05, &NoProgress).unwrap(),
                whole.factorize(1.05, &NoProgress).unwrap(),
            );
            assert_eq!(f.inertia(), g.inertia(), "{ordering:?}");
            let (mut x, mut y) = (b.clone(), b.clone());
            f.solve_in_place(x.as_mut());
            g.solve_in_place(y.as_mut());
            assert!(
                crate::sparse::max_abs((&x - &y).as_ref()) < 1e-10,
                "{ordering:?}"
            );
        }
        assert!(Pencil::analyze(&k, &m, Some(&[0, n][..]), Ordering::Amd, &NoProgress).is_err());
        assert!(Pencil::analyze(&k, &m, Some(&[3, 3, 5][..]), Ordering::Amd, &NoProgress).is_err());
        assert!(Pencil::analyze(&k, &m, Some(&[5, 3][..]), Ordering::Amd, &NoProgress).is_err());
    }

    /// On a supernodal factor, `K - sigma M` formed as the factorisation
    /// reads it solves as the assembled matrix does, and a held factor
    /// (equations fixed, as the free-residual support) solves the submatrix
    /// of the other equations.
    #[test]
    fn shifted_and_held_supernodal_factors_solve_their_matrices() {
        let k = crate::ldlt::solve::tests::grid(8);
        let n = k.nrows();
        // A mass on K's pattern with zeros off the 3 x 3 diagonal blocks'
        // diagonals (as the consistent mass of solids): its own pattern is
        // a third of the union.
        let m = {
            let sym = k.symbolic();
            let mut val = Vec::with_capacity(k.val().len());
            for j in 0..n {
                for &i in sym.row_idx_of_col_raw(j) {
                    val.push(match (i == j, i % 3 == j % 3) {
                        (true, _) => 2.0,
                        (false, true) => 0.25,
                        _ => 0.0,
                    });
                }
            }
            SparseMat::new(sym.to_owned().unwrap(), val)
        };
        let pencil =
            Pencil::analyze(&k, &m, None, Ordering::NestedDissection, &NoProgress).unwrap();
        assert!(pencil.symbolic.supernodes().is_some());
        let b = Mat::from_fn(n, 3, |i, j| ((i * 7 + j * 3) % 11) as f64 - 5.0);
        let sigma = 40.0;
        let f = pencil.factorize(sigma, &NoProgress).unwrap();
        let mut x = b.clone();
        f.solve_in_place(x.as_mut());
        let a = crate::sparse::add_scaled(&k, -sigma, &m).unwrap();
        let r = crate::sparse::symmetric_mul(&a, x.as_ref()) - &b;
        assert!(crate::sparse::max_abs(r.as_ref()) < 1e-10 * crate::sparse::max_abs(b.as_ref()));
        // On one thread of faer's kernels: the same solution.
        let serial = pencil.clone().with_parallelism(faer::Par::Seq);
        assert_eq!(serial.symbolic.parallelism(), faer::Par::Seq);
        let mut y = b.clone();
        let g = serial.factorize(sigma, &NoProgress).unwrap();
        g.solve_in_place(y.as_mut());
        assert!(
            crate::sparse::max_abs((&x - &y).as_ref()) < 1e-12 * crate::sparse::max_abs(x.as_ref())
        );

        let fixed = [0, 1, 2, 700, n - 1];
        let keep: Vec<usize> = (0..n).filter(|i| !fixed.contains(i)).collect();
        let held = pencil.factorize_static(&fixed, &NoProgress).unwrap();
        let mut bh = b.clone();
        for &i in &fixed {
            for j in 0..bh.ncols() {
                bh[(i, j)] = 0.0;
            }
        }
        let mut x = bh.clone();
        held.solve_in_place(x.as_mut());
        for &i in &fixed {
            assert!((0..x.ncols()).all(|j| x[(i, j)] == 0.0));
        }
        let sub = crate::sparse::submatrix(&k, &keep, &keep);
        let xs = Mat::from_fn(keep.len(), 3, |i, j| x[(keep[i], j)]);
        let bs = Mat::from_fn(keep.len(), 3, |i, j| b[(keep[i], j)]);
        let r = crate::sparse::symmetric_mul(&sub, xs.as_ref()) - &bs;
        assert!(crate::sparse::max_abs(r.as_ref()) < 1e-10 * crate::sparse::max_abs(b.as_ref()));
    }

    #[test]
    fn solves_and_counts_for_both_orderings() {
        let n = 60;
        let (k, m) = chain(n);
        for ordering in [Ordering::Amd, Ordering::NestedDissection] {
            let pencil = Pencil::analyze(&k, &m, None, ordering, &NoProgress).unwrap();
            let sigma = 1.05;
            let f = pencil.factorize(sigma, &NoProgress).unwrap();
            let below = (1..=n)
                .filter(|k| {
                    let th = ((2 * k - 1) as f64) * std::f64::consts::PI / (2 * n + 1) as f64;
                    2.0 - 2.0 * th.cos() < sigma
                })
                .count();
            assert_eq!(f.inertia().negative, below, "{ordering:?}");
            let b = Mat::from_fn(n, 2, |i, j| (i + j) as f64);
            let mut x = b.clone();
            f.solve_in_place(x.as_mut());
            let r = &k * &x - &m * &x * faer::Scale(sigma) - &b;
            assert!(crate::sparse::max_abs(r.as_ref()) < 1e-9);
        }
    }
}
