//! Sparse `LDL^T` factorisation with a symbolic/numeric split.
//!
//! The symbolic step (fill-reducing ordering, elimination tree) is computed
//! once and shared behind an [`Arc`]; the numeric step runs per matrix (per
//! shift `K - sigma M` in eigen solvers). Solves take many right-hand sides at
//! once (block solves: one sweep through `L` per block). The pivots `D` are kept
//! in the original row order so that a vanishing pivot names the DOF where a
//! matrix is singular, and their signs give the inertia (Sturm count).
//!
//! The phases have a file each: `symbolic` (the supernodal structure,
//! analysed on the node graph), `numeric` (the factorisation in parallel
//! over the elimination tree) and `solve` (block solves, in parallel over
//! the same tree).

mod factor;
pub(crate) mod numeric;
pub(crate) mod solve;
pub(crate) mod symbolic;

use crate::memory::Budget;
use crate::ordering::{nested_dissection, Dissection, Ordering};
use crate::progress::{Progress, Stage};
use crate::{LinalgError, SparseMat};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LdltRef, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::Par;
use faer::{Conj, MatMut, Side};
use numeric::{Input, Panels};
use std::sync::Arc;
use symbolic::{FactorRef, Supernodes};
use symbolic::{SolvePlan, UpdatePlan};

pub use factor::{Factor, Inertia};

/// Tuning of the numeric factorisation.
#[derive(Copy, Clone, Debug)]
pub struct LdltParams {
    /// A pivot `|d_i| <= singularity_tolerance * |a_ii|` is taken as zero: the
    /// factorisation fails with [`LinalgError::Singular`] naming row `i`.
    /// Round-off pivots of a singular stiffness matrix sit near 1e-15 relative;
    /// legitimate pivots of slender structures stay far above 1e-12.
    pub singularity_tolerance: f64,
}

impl Default for LdltParams {
    fn default() -> Self {
        Self {
            singularity_tolerance: 1e-11,
        }
    }
}

/// Symbolic analysis of a symmetric sparsity pattern (ordering, elimination
/// tree, supernodes, the plan of parallel solves), reusable for every
/// matrix with that pattern.
#[derive(Clone, Debug)]
pub struct SymbolicLdlt {
    inner: Arc<Analysis>,
    ordering: Ordering,
    /// faer's parallelism on this analysis
    /// ([`SymbolicLdlt::with_parallelism`]; all of rayon's threads unless
    /// set).
    par: Par,
    /// The memory its factors may take ([`SymbolicLdlt::with_budget`]).
    budget: Budget,
}

/// The structure a numeric factorisation fills.
#[derive(Debug)]
enum Analysis {
    /// Ours: supernodes factorised and solved in parallel over the tree.
    Supernodal(Supernodal),
    /// faer's, for small or very sparse matrices.
    Simplicial(SymbolicCholesky<usize>),
}

#[derive(Debug)]
struct Supernodal {
    supernodes: Supernodes,
    /// `forward[new] = old`, `inverse[old] = new`.
    forward: Vec<usize>,
    inverse: Vec<usize>,
    plan: SolvePlan,
    updates: UpdatePlan,
}

impl Supernodal {
    fn new(supernodes: Supernodes, forward: Vec<usize>, inverse: Vec<usize>) -> Self {
        let plan = SolvePlan::new(&supernodes, rayon::current_num_threads());
        let updates = UpdatePlan::new(&supernodes, &plan);
        Self {
            supernodes,
            forward,
            inverse,
            plan,
            updates,
        }
    }
}

impl SymbolicLdlt {
    /// Analyses the pattern of the symmetric matrix `a` with
    /// [`Ordering::Auto`].
    pub fn analyze(a: &SparseMat) -> Result<Self, LinalgError> {
        Self::analyze_pattern(a.symbolic(), Ordering::Auto)
    }

    /// Analyses a symmetric pattern of which the lower triangle is read
    /// (both triangles or only the lower one stored), with `ordering`.
    pub fn analyze_pattern(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        ordering: Ordering,
    ) -> Result<Self, LinalgError> {
        let ordering = ordering.resolve(pattern.nrows());
        let permutation = match ordering {
            Ordering::NestedDissection => Some(nested_dissection(pattern)?),
            _ => None,
        };
        Self::analyze_permuted(pattern, permutation)
    }

    /// [`Self::analyze_pattern`] with the nested-dissection order already
    /// computed (from this pattern, or one that contains it), or `None`
    /// for faer's AMD.
    ///
    /// Under nested dissection the supernodes come from the graph of the
    /// nodes (the symbolic phase); faer analyses the equations
    /// under AMD, and where the factor is simplicial.
    pub fn analyze_permuted(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        permutation: Option<Dissection>,
    ) -> Result<Self, LinalgError> {
        let n = pattern.nrows();
        let ordering = if permutation.is_some() {
            Ordering::NestedDissection
        } else {
            Ordering::Amd
        };
        let permutation = match permutation {
            Some(d) if d.forward.len() != n || d.inverse.len() != n => {
                return Err(LinalgError::Dimension(format!(
                    "a permutation of {} equations for a {n}-equation pattern",
                    d.forward.len()
                )));
            }
            Some(d) => match Supernodes::of_dissection(pattern, &d) {
                Some(supernodes) => {
                    let supernodal = Supernodal::new(supernodes, d.forward, d.inverse);
                    return Ok(Self {
                        inner: Arc::new(Analysis::Supernodal(supernodal)),
                        ordering,
                        par: Par::rayon(0),
                        budget: Budget::MACHINE,
                    });
                }
                None => Some(d),
            },
            None => None,
        };
        let order = permutation
            .as_ref()
            .map(|d| (d.forward.as_slice(), d.inverse.as_slice()));
        let inner = faer_analysis(pattern, order)?;
        let inner = match inner.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let (fwd, inv) = match inner.perm() {
                    Some(p) => (p.arrays().0.to_vec(), p.arrays().1.to_vec()),
                    None => ((0..n).collect(), (0..n).collect()),
                };
                Analysis::Supernodal(Supernodal::new(Supernodes::from_faer(s), fwd, inv))
            }
            SymbolicCholeskyRaw::Simplicial(_) => Analysis::Simplicial(inner),
        };
        Ok(Self {
            inner: Arc::new(inner),
            ordering,
            par: Par::rayon(0),
            budget: Budget::MACHINE,
        })
    }

    /// Number of rows of the analysed matrix.
    /// This analysis with faer's kernels under `par`: the dense work
    /// inside the largest supernodes, and faer's own factorisation and
    /// solve of a simplicial analysis. The independent subtrees of the
    /// elimination tree run on rayon's pool (bounded by running the caller
    /// in a pool of its own).
    pub fn with_parallelism(mut self, par: Par) -> Self {
        self.par = par;
        self
    }

    /// The parallelism of this analysis' factorisations and solves.
    pub fn parallelism(&self) -> Par {
        self.par
    }

    /// This analysis with its factors held to `budget`: a factor that
    /// would not fit is refused before its storage is taken
    /// ([`LinalgError::OutOfMemory`]).
    pub fn with_budget(mut self, budget: Budget) -> Self {
        self.budget = budget;
        self
    }

    /// The memory budget of this analysis' factors.
    pub fn budget(&self) -> Budget {
        self.budget
    }

    pub fn dim(&self) -> usize {
        match &*self.inner {
            Analysis::Supernodal(s) => s.supernodes.nrows(),
            Analysis::Simplicial(s) => s.nrows(),
        }
    }

    /// Number of stored entries of the factor `L`.
    pub fn factor_len(&self) -> usize {
        match &*self.inner {
            Analysis::Supernodal(s) => s.supernodes.len_val(),
            Analysis::Simplicial(s) => s.len_val(),
        }
    }

    /// Floating-point operations of one numeric factorisation (see
    /// `Supernodes::flops`).
    pub fn factor_flops(&self) -> f64 {
        match &*self.inner {
            Analysis::Supernodal(s) => s.supernodes.flops(),
            Analysis::Simplicial(s) => match s.raw() {
                SymbolicCholeskyRaw::Simplicial(s) => s
                    .col_ptr()
                    .windows(2)
                    .map(|w| ((w[1] - w[0]).saturating_sub(1) as f64).powi(2))
                    .sum(),
                SymbolicCholeskyRaw::Supernodal(s) => (0..s.n_supernodes())
                    .map(|k| {
                        let width = s.supernode_end()[k] - s.supernode_begin()[k];
                        crate::ldlt::symbolic::supernode_flops(
                            width,
                            s.supernode(k).pattern().len(),
                        )
                    })
                    .sum(),
            },
        }
    }

    /// The ordering used (with [`Ordering::Auto`] resolved).
    pub fn ordering(&self) -> Ordering {
        self.ordering
    }

    /// The analysis with the supernodes given.
    #[cfg(test)]
    pub(crate) fn with_supernodes(
        supernodes: Supernodes,
        forward: Vec<usize>,
        inverse: Vec<usize>,
    ) -> Self {
        Self {
            inner: Arc::new(Analysis::Supernodal(Supernodal::new(
                supernodes, forward, inverse,
            ))),
            ordering: Ordering::NestedDissection,
            par: Par::rayon(0),
            budget: Budget::MACHINE,
        }
    }

    /// faer's own analysis of `pattern` under this analysis' permutation:
    /// the reference that tests compare with.
    #[cfg(test)]
    pub(crate) fn faer_reference(
        &self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
    ) -> SymbolicCholesky<usize> {
        let forward = self.forward();
        let mut inverse = vec![0; forward.len()];
        for (new, &old) in forward.iter().enumerate() {
            inverse[old] = new;
        }
        faer_analysis(pattern, Some((&forward, &inverse))).unwrap()
    }

    /// The supernodes, where the factor is supernodal.
    #[cfg(test)]
    pub(crate) fn supernodes(&self) -> Option<&Supernodes> {
        match &*self.inner {
            Analysis::Supernodal(s) => Some(&s.supernodes),
            Analysis::Simplicial(_) => None,
        }
    }

    /// `forward[new] = old` of the fill-reducing permutation.
    pub(crate) fn forward(&self) -> Vec<usize> {
        match &*self.inner {
            Analysis::Supernodal(s) => s.forward.clone(),
            Analysis::Simplicial(s) => match s.perm() {
                Some(p) => p.arrays().0.to_vec(),
                None => (0..self.dim()).collect(),
            },
        }
    }

    /// The numeric `LDL^T` of `a` (pattern analysed here; its lower
    /// triangle is read) into `values`, reusing that buffer's allocation.
    /// `Err(i)`: the pivot in elimination position `i` vanished.
    pub(crate) fn factorize_into(
        &self,
        a: SparseColMatRef<'_, usize, f64>,
        values: &mut Vec<f64>,
    ) -> Result<(), LinalgError> {
        self.ensure_room(values.len())?;
        match &*self.inner {
            Analysis::Supernodal(s) => {
                self.factorize_supernodal(s, Input::Faer(a), values, Panels::DEFAULT, &|_| {})
            }
            Analysis::Simplicial(sym) => self.factorize_simplicial(sym, a, values),
        }
    }

    /// [`Self::factorize_into`] for a lower triangle given as an
    /// [`Input`] (such as a shift-invert pencil's `K - sigma M`, formed as
    /// it is read): the supernodal factorisation reads it as it is; only a
    /// small, simplicial one makes faer's matrix of it. `resident` values
    /// of `values` are in memory already (storage touched ahead).
    pub(crate) fn factorize_input_into(
        &self,
        input: Input<'_>,
        values: &mut Vec<f64>,
        resident: usize,
        progress: &dyn Progress,
    ) -> Result<(), LinalgError> {
        self.ensure_room(resident)?;
        match &*self.inner {
            Analysis::Supernodal(s) => {
                let report = reported_to(s, progress);
                self.factorize_supernodal(s, input, values, Panels::DEFAULT, &report)
            }
            Analysis::Simplicial(sym) => {
                let n = input.ncols();
                let col_ptr = input.col_ptr();
                let (rows, a) = input.lower_triangle();
                if rows.len() != col_ptr[n] {
                    return Err(LinalgError::Dimension(
                        "the factorisation's input is not a lower triangle".into(),
                    ));
                }
                let pattern = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, &rows);
                self.factorize_simplicial(sym, SparseColMatRef::new(pattern, &a), values)
            }
        }
    }

    /// What the factor lacks beyond `resident` values in storage must fit
    /// in memory (the storage it replaces is freed first): refused before
    /// factorising, with its size, rather than killed for memory meanwhile.
    fn ensure_room(&self, resident: usize) -> Result<(), LinalgError> {
        self.budget
            .ensure_factor(self.dim(), self.factor_len(), resident)
    }

    /// Our parallel numeric factorisation of a supernodal analysis, large
    /// updates split as `panels` says, its progress to `report` (the
    /// fraction done, at each percent).
    fn factorize_supernodal(
        &self,
        s: &Supernodal,
        a: Input<'_>,
        values: &mut Vec<f64>,
        panels: Panels,
        report: &(dyn Fn(f64) + Sync),
    ) -> Result<(), LinalgError> {
        // Every block is cleared where it is factorised: storage is taken
        // as it is, only fitted to the factor's length.
        crate::memory::fit(values, s.supernodes.len_val());
        crate::ldlt::numeric::factorize(
            &s.supernodes,
            &s.plan,
            &s.updates,
            a,
            &s.inverse,
            values,
            panels,
            self.par,
            report,
        )
        .map_err(|index| self.zero_pivot(index))
    }

    /// [`Self::factorize_into`] of a supernodal analysis with large updates
    /// split as `panels` says.
    #[cfg(test)]
    pub(crate) fn factorize_in_panels(
        &self,
        a: SparseColMatRef<'_, usize, f64>,
        values: &mut Vec<f64>,
        panels: Panels,
        report: &(dyn Fn(f64) + Sync),
    ) -> Result<(), LinalgError> {
        match &*self.inner {
            Analysis::Supernodal(s) => {
                self.factorize_supernodal(s, Input::Faer(a), values, panels, report)
            }
            Analysis::Simplicial(_) => Err(LinalgError::Dimension("a simplicial analysis".into())),
        }
    }

    /// faer's numeric factorisation of a simplicial analysis.
    fn factorize_simplicial(
        &self,
        sym: &SymbolicCholesky<usize>,
        a: SparseColMatRef<'_, usize, f64>,
        values: &mut Vec<f64>,
    ) -> Result<(), LinalgError> {
        values.clear();
        values.resize(sym.len_val(), 0.0);
        let par = self.par;
        let mut mem =
            MemBuffer::try_new(sym.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()))
                .map_err(|_| LinalgError::Faer("out of memory in LDL^T".into()))?;
        let result = sym.factorize_numeric_ldlt(
            values,
            a,
            Side::Lower,
            LdltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
        if let Err(faer::linalg::cholesky::ldlt::factor::LdltError::ZeroPivot { index }) = result {
            return Err(self.zero_pivot(index));
        }
        Ok(())
    }

    /// The error of a vanished pivot, `index` as faer reports it: 1-based,
    /// in elimination order.
    fn zero_pivot(&self, index: usize) -> LinalgError {
        LinalgError::Singular {
            index: index.saturating_sub(1).min(self.dim().saturating_sub(1)),
            pivot: 0.0,
            diagonal: 0.0,
        }
    }

    /// Solves `L D L^T X = B` in place with the factor `values`: in parallel
    /// over the elimination tree for a supernodal factor
    /// ([`crate::ldlt::solve`]), with faer's solve otherwise.
    pub(crate) fn solve_in_place(&self, values: &[f64], x: MatMut<'_, f64>) {
        match &*self.inner {
            Analysis::Supernodal(s) => {
                s.plan
                    .solve_in_place(FactorRef::new(&s.supernodes, values), &s.inverse, x);
            }
            Analysis::Simplicial(sym) => {
                let par = self.par;
                let mut mem = MemBuffer::new(sym.solve_in_place_scratch::<f64>(x.ncols(), par));
                LdltRef::new(sym, values).solve_in_place_with_conj(
                    Conj::No,
                    x,
                    par,
                    MemStack::new(&mut mem),
                );
            }
        }
    }

    /// The pivots `D` in elimination order.
    pub(crate) fn permuted_pivots(&self, values: &[f64]) -> Vec<f64> {
        let mut d = vec![0.0; self.dim()];
        match &*self.inner {
            Analysis::Simplicial(sym) => {
                let SymbolicCholeskyRaw::Simplicial(s) = sym.raw() else {
                    unreachable!("a simplicial analysis holds faer's simplicial factor")
                };
                let factor = s.factor();
                let col_ptr = factor.col_ptr();
                let row_idx = factor.row_idx();
                for (j, dj) in d.iter_mut().enumerate() {
                    if let Some(p) = (col_ptr[j]..col_ptr[j + 1]).find(|&p| row_idx[p] == j) {
                        *dj = values[p];
                    }
                }
            }
            Analysis::Supernodal(s) => {
                let factor = FactorRef::new(&s.supernodes, values);
                for sn in 0..s.supernodes.n_supernodes() {
                    let node = factor.supernode(sn);
                    let block = node.val();
                    for k in 0..block.ncols() {
                        d[node.start() + k] = block[(k, k)];
                    }
                }
            }
        }
        d
    }
}

/// faer's symbolic analysis of `pattern` (lower triangle) under the
/// permutation `(forward, inverse)`, or under faer's AMD.
pub(crate) fn faer_analysis(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    permutation: Option<(&[usize], &[usize])>,
) -> Result<SymbolicCholesky<usize>, LinalgError> {
    let n = pattern.nrows();
    let ordering = match permutation {
        Some((fwd, inv)) => SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n)),
        None => SymmetricOrdering::Amd,
    };
    factorize_symbolic_cholesky(pattern, Side::Lower, ordering, Default::default())
        .map_err(|e| LinalgError::Faer(format!("{e:?}")))
}

/// The `Factoring` reports of a supernodal factorisation, to `progress`.
fn reported_to<'a>(s: &Supernodal, progress: &'a dyn Progress) -> impl Fn(f64) + Sync + 'a {
    let flops = s.supernodes.flops();
    move |done| progress.report(&Stage::Factoring { done, flops })
}
