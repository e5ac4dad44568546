//! The model's `K` and `M` as a reduction holds them, and the products
//! with them that the residualisation (eq. 23-24) and the projections
//! `T^T K T`, `T^T M T` (eq. 5-7) need once the modes are found.
//!
//! A caller that hands `K` and `M` over ([`Held::Given`]) lets a large
//! model's solver drop them as soon as it holds its compact copy
//! (the lower triangles in [`Pencil`]): the factorisations and the
//! Lanczos run then find the memory of the full matrices free, 2.4 GiB of
//! a 1e6-DOF solid. The products afterwards come from that copy
//! ([`Products::Pencil`]), or, for a body held at its interface, from the
//! copy of the interior plus the few columns that couple it to the
//! interface ([`Products::Bordered`]). A caller that needs `M` afterwards
//! (the SID's mass invariants) hands over `K` alone, 1.2 GiB of that solid.

use crate::modes::eigen::{eigenmodes, eigenmodes_on, Wanted};
use crate::ReduceError;
use faer::{Mat, MatRef};
use flexbody_linalg::memory::Budget;
use flexbody_linalg::ordering::Ordering;
use flexbody_linalg::pencil::Pencil;
use flexbody_linalg::progress::{NoProgress, Progress};
use flexbody_linalg::solver::{EigenRequest, Solver};
use flexbody_linalg::{sparse, LinalgError, SparseMat};

/// One of the model's matrices, in full storage, as a reduction holds it.
pub(crate) enum Held<'a> {
    /// Lent by the caller, who keeps it.
    Lent(&'a SparseMat),
    /// Handed over: dropped once a solver holds its compact copy.
    Given(SparseMat),
}

impl Held<'_> {
    fn get(&self) -> &SparseMat {
        match self {
            Held::Lent(a) => a,
            Held::Given(a) => a,
        }
    }
}

/// `K` and `M` of the model, each lent or handed over.
pub(crate) struct Matrices<'a> {
    k: Held<'a>,
    m: Held<'a>,
    /// The memory the solves on them may take.
    budget: Budget,
}

impl<'a> Matrices<'a> {
    /// Both lent: the caller keeps them.
    pub(crate) fn lent(k: &'a SparseMat, m: &'a SparseMat) -> Self {
        Self {
            k: Held::Lent(k),
            m: Held::Lent(m),
            budget: Budget::MACHINE,
        }
    }

    /// Both handed over.
    pub(crate) fn given(k: SparseMat, m: SparseMat) -> Self {
        Self {
            k: Held::Given(k),
            m: Held::Given(m),
            budget: Budget::MACHINE,
        }
    }

    /// `K` handed over, `M` lent (a caller that needs the mass afterwards,
    /// as the SID's invariants do).
    pub(crate) fn stiffness_given(k: SparseMat, m: &'a SparseMat) -> Self {
        Self {
            k: Held::Given(k),
            m: Held::Lent(m),
            budget: Budget::MACHINE,
        }
    }

    /// The matrices kept for the products where the dense eigen solver
    /// serves `wanted` of `n` equations: a model that small has no memory
    /// to save, and its products stay exactly [`sparse::project`]'s. `None`
    /// (dropped) otherwise, the pencil's compact copy serving instead.
    pub(crate) fn kept_if_small(self, n: usize, wanted: Wanted) -> Option<Self> {
        Solver::Auto.is_dense(n, wanted).then_some(self)
    }

    /// These matrices with their solves held to `budget`.
    pub(crate) fn under(self, budget: Budget) -> Self {
        Self { budget, ..self }
    }

    /// The memory the solves on these matrices may take.
    pub(crate) fn budget(&self) -> Budget {
        self.budget
    }

    /// The pencil of `K` (or `stiffness` in its place, such as `K` with
    /// springs) and `M`, on the equations `within` or all, under the
    /// matrices' budget.
    pub(crate) fn pencil(
        &self,
        stiffness: Option<&SparseMat>,
        within: Option<&[usize]>,
        progress: &dyn Progress,
    ) -> Result<Pencil, LinalgError> {
        let k = stiffness.unwrap_or(self.k());
        Ok(
            Pencil::analyze(k, self.m(), within, Ordering::Auto, progress)?
                .with_budget(self.budget),
        )
    }

    pub(crate) fn k(&self) -> &SparseMat {
        self.k.get()
    }

    pub(crate) fn m(&self) -> &SparseMat {
        self.m.get()
    }
}

/// Products with the model's `K` and `M`.
pub(crate) enum Products<'a> {
    /// The model's own matrices, where the dense eigen solver served (a
    /// small model: the products are those of [`sparse::project`]).
    Full(Matrices<'a>),
    /// The compact copy of the pencil the eigen solver analysed.
    Pencil(Pencil),
    /// A pencil of the interior equations only, bordered by the interface.
    Bordered(Box<Bordered>),
    /// The pencil of the body on its springs.
    Sprung(Box<Sprung>),
}

/// `K + C` and `M` of the body on its interface springs `C`: the products
/// of the free body take the springs' part off again (eq. 28).
pub(crate) struct Sprung {
    pub pencil: Pencil,
    pub springs: SparseMat,
}

/// `K` and `M` of a body held at `boundary`: the pencil of the `interior`
/// equations (renumbered `0..interior.len()`) and the coupling blocks
/// `K_NB`, `M_NB` (sparse) and `K_BB`, `M_BB` (dense), all exact copies
/// of the model's entries.
pub(crate) struct Bordered {
    pub pencil: Pencil,
    pub interior: Vec<usize>,
    pub boundary: Vec<usize>,
    pub k_nb: SparseMat,
    pub m_nb: SparseMat,
    pub k_bb: Mat<f64>,
    pub m_bb: Mat<f64>,
}

impl Bordered {
    /// The coupling blocks of `k` and `m` around `pencil`, the pencil of
    /// their `interior` equations.
    pub(crate) fn new(
        pencil: Pencil,
        k: &SparseMat,
        m: &SparseMat,
        interior: Vec<usize>,
        boundary: Vec<usize>,
    ) -> Self {
        Self {
            k_nb: sparse::submatrix(k, &interior, &boundary),
            m_nb: sparse::submatrix(m, &interior, &boundary),
            k_bb: sparse::submatrix(k, &boundary, &boundary).to_dense(),
            m_bb: sparse::submatrix(m, &boundary, &boundary).to_dense(),
            pencil,
            interior,
            boundary,
        }
    }

    /// `[A_NN A_NB; A_BN A_BB] x` with `A_NN x_N` from `interior`.
    fn mul(
        &self,
        x: MatRef<'_, f64>,
        interior: impl FnOnce(MatRef<'_, f64>) -> Mat<f64>,
        a_nb: &SparseMat,
        a_bb: &Mat<f64>,
    ) -> Mat<f64> {
        let c = x.ncols();
        let x_n = Mat::from_fn(self.interior.len(), c, |i, j| x[(self.interior[i], j)]);
        let x_b = Mat::from_fn(self.boundary.len(), c, |i, j| x[(self.boundary[i], j)]);
        let mut y_n = interior(x_n.as_ref());
        let mut y_b = a_bb * &x_b;
        let a = a_nb.as_ref();
        for b in 0..self.boundary.len() {
            for (i, v) in a.row_idx_of_col(b).zip(a.val_of_col(b)) {
                for j in 0..c {
                    y_n[(i, j)] += v * x_b[(b, j)];
                    y_b[(b, j)] += v * x_n[(i, j)];
                }
            }
        }
        let mut y = Mat::zeros(x.nrows(), c);
        for j in 0..c {
            for (k, &i) in self.interior.iter().enumerate() {
                y[(i, j)] = y_n[(k, j)];
            }
            for (k, &i) in self.boundary.iter().enumerate() {
                y[(i, j)] = y_b[(k, j)];
            }
        }
        y
    }
}

impl<'a> Products<'a> {
    /// `full` where the model's own matrices were kept, else `compact`.
    pub(crate) fn full_or(full: Option<Matrices<'a>>, compact: Products<'a>) -> Self {
        match full {
            Some(matrices) => Products::Full(matrices),
            None => compact,
        }
    }

    /// The lowest `count` eigenvalues of the free model's `K` and `M`, to
    /// count a mechanism's zero modes ([`crate::modes::zero_modes`]); none
    /// from the pencil of a body held at its interface or on springs, which
    /// is not the free body's.
    pub(crate) fn lowest_eigenvalues(&self, count: usize) -> Result<Vec<f64>, ReduceError> {
        match self {
            Products::Full(matrices) => {
                Ok(eigenmodes(matrices.k(), matrices.m(), Wanted::Lowest(count))?.values)
            }
            Products::Pencil(pencil) => {
                let request = EigenRequest::new(Wanted::Lowest(count));
                Ok(eigenmodes_on(pencil, None, &request, &NoProgress)?.values)
            }
            Products::Bordered(_) | Products::Sprung(_) => Ok(Vec::new()),
        }
    }

    /// `K X`.
    pub(crate) fn mul_stiffness(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        match self {
            Products::Full(a) => sparse::symmetric_mul(a.k(), x),
            Products::Pencil(p) => p.mul_stiffness(x),
            Products::Bordered(b) => b.mul(x, |x| b.pencil.mul_stiffness(x), &b.k_nb, &b.k_bb),
            Products::Sprung(s) => s.pencil.mul_stiffness(x) - sparse::symmetric_mul(&s.springs, x),
        }
    }

    /// `M X`.
    pub(crate) fn mul_mass(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        match self {
            Products::Full(a) => sparse::symmetric_mul(a.m(), x),
            Products::Pencil(p) => p.mul_mass(x),
            Products::Bordered(b) => b.mul(x, |x| b.pencil.mul_mass(x), &b.m_nb, &b.m_bb),
            Products::Sprung(s) => s.pencil.mul_mass(x),
        }
    }

    /// `T^T K T`, symmetrised exactly (eq. 7).
    pub(crate) fn project_stiffness(&self, t: MatRef<'_, f64>) -> Mat<f64> {
        sparse::project_product(t, self.mul_stiffness(t))
    }

    /// `T^T M T`, symmetrised exactly (eq. 5).
    pub(crate) fn project_mass(&self, t: MatRef<'_, f64>) -> Mat<f64> {
        sparse::project_product(t, self.mul_mass(t))
    }

    /// `T_res = T_stat - Phi Phi^T M T_stat` for M-orthonormal `phi`
    /// (eq. 23-24, [`crate::modes::residual_modes`]).
    pub(crate) fn residual_modes(&self, static_modes: &Mat<f64>, phi: &Mat<f64>) -> Mat<f64> {
        crate::modes::residual::residual_modes_by(static_modes, phi, |t| self.mul_mass(t))
    }
}
