//! The numeric `LDL^T` factor: one type, whether it factors a plain
//! symmetric matrix ([`Factor::of`]) or a pencil's `K - sigma M`
//! ([`crate::pencil::Pencil::factorize`]).

use super::{LdltParams, SymbolicLdlt};
use crate::{LinalgError, SparseMat};
use faer::{Mat, MatMut, MatRef};

/// Counts of negative, zero and positive pivots: by Sylvester's law of inertia
/// the counts of eigenvalues of `A` below, at and above zero. For
/// `A = K - sigma M` (M positive definite), the negative count is the number
/// of eigenvalues of `K phi = lambda M phi` below `sigma` (the Sturm count).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Inertia {
    pub negative: usize,
    pub zero: usize,
    pub positive: usize,
}

/// Numeric `LDL^T` of a symmetric (possibly indefinite) sparse matrix `A`:
/// of `K - sigma M` for a pencil (`sigma` its [`Factor::shift`]), of the
/// matrix itself (shift 0) otherwise.
#[derive(Clone, Debug)]
pub struct Factor {
    symbolic: SymbolicLdlt,
    values: Vec<f64>,
    shift: f64,
    inertia: Inertia,
    /// The first pivot (elimination order) that is round-off against its
    /// row's diagonal: an error for a matrix that must be regular,
    /// legitimate in a shifted, indefinite one.
    vanished: Option<Vanished>,
    /// A factor of `K` with fixed equations
    /// ([`crate::pencil::Pencil::factorize_static`]).
    fixed: bool,
}

/// A pivot that vanished: its row (original order), its value and the
/// row's diagonal entry.
#[derive(Copy, Clone, Debug)]
struct Vanished {
    row: usize,
    pivot: f64,
    diagonal: f64,
}

impl Factor {
    /// Analyses and factorises the symmetric `a` (its lower triangle is
    /// read) with default parameters; fails with [`LinalgError::Singular`]
    /// naming the row (original order) whose pivot vanishes. Unreported:
    /// the factorisations of large models, which a user waits for, are the
    /// pencil's.
    pub fn of(a: &SparseMat) -> Result<Self, LinalgError> {
        let symbolic = SymbolicLdlt::analyze(a)?;
        Self::of_analyzed(&symbolic, a, LdltParams::default())
    }

    /// [`Self::of`] on the analysis `symbolic` of `a`'s pattern.
    pub fn of_analyzed(
        symbolic: &SymbolicLdlt,
        a: &SparseMat,
        params: LdltParams,
    ) -> Result<Self, LinalgError> {
        let n = a.nrows();
        if a.ncols() != n || symbolic.dim() != n {
            return Err(LinalgError::Dimension(format!(
                "LDL^T of a {}x{} matrix with a symbolic analysis of size {}",
                n,
                a.ncols(),
                symbolic.dim()
            )));
        }
        let diagonal = crate::sparse::diagonal(a);
        let mut values = Vec::new();
        let factored = symbolic.factorize_into(a.as_ref(), &mut values);
        Self::scanned(symbolic, factored, values, 0.0, &diagonal, params)?.regular()
    }

    /// The factor of `symbolic` whose numeric factorisation gave `factored`
    /// and `values`, its pivots read against `diagonal` (of `A`, original
    /// order): the inertia, and the first pivot that vanished by
    /// `params.singularity_tolerance` times its diagonal (a zero diagonal,
    /// legitimate in an indefinite matrix, counts as the largest one). A
    /// pivot the factorisation itself found zero is the error naming its row.
    pub(crate) fn scanned(
        symbolic: &SymbolicLdlt,
        factored: Result<(), LinalgError>,
        values: Vec<f64>,
        shift: f64,
        diagonal: &[f64],
        params: LdltParams,
    ) -> Result<Self, LinalgError> {
        let forward = symbolic.forward();
        match factored {
            Err(LinalgError::Singular { index, .. }) => {
                let row = forward[index];
                return Err(LinalgError::Singular {
                    index: row,
                    pivot: 0.0,
                    diagonal: diagonal[row],
                });
            }
            other => other?,
        }
        let largest = diagonal.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let mut inertia = Inertia {
            negative: 0,
            zero: 0,
            positive: 0,
        };
        let mut vanished = None;
        for (i, d) in symbolic.permuted_pivots(&values).into_iter().enumerate() {
            let row = forward[i];
            let scale = match diagonal[row] {
                0.0 => largest,
                a => a.abs(),
            };
            // The first in elimination order: later ones are polluted by it.
            if vanished.is_none()
                && (!d.is_finite() || d.abs() <= params.singularity_tolerance * scale)
            {
                vanished = Some(Vanished {
                    row,
                    pivot: d,
                    diagonal: diagonal[row],
                });
            }
            if d < 0.0 {
                inertia.negative += 1;
            } else if d > 0.0 {
                inertia.positive += 1;
            } else {
                inertia.zero += 1;
            }
        }
        Ok(Self {
            symbolic: symbolic.clone(),
            values,
            shift,
            inertia,
            vanished,
            fixed: false,
        })
    }

    /// The factor if no pivot vanished, else the error naming the first.
    pub(crate) fn regular(mut self) -> Result<Self, LinalgError> {
        match self.vanished.take() {
            Some(v) => Err(LinalgError::Singular {
                index: v.row,
                pivot: v.pivot,
                diagonal: v.diagonal,
            }),
            None => Ok(self),
        }
    }

    /// Marks a factor of `K` with fixed equations.
    pub(crate) fn with_fixed(mut self) -> Self {
        self.fixed = true;
        self
    }

    /// Dimension of the factorised matrix.
    pub fn dim(&self) -> usize {
        self.symbolic.dim()
    }

    /// The shift `sigma` of this factorisation (0 for a plain matrix).
    pub fn shift(&self) -> f64 {
        self.shift
    }

    /// Signs of the pivots: for a pencil, `negative` eigenvalues lie below
    /// the shift.
    pub fn inertia(&self) -> Inertia {
        self.inertia
    }

    /// Solves `A X = B` for a block of right-hand sides.
    pub fn solve(&self, rhs: MatRef<'_, f64>) -> Mat<f64> {
        let mut x = rhs.to_owned();
        self.solve_in_place(x.as_mut());
        x
    }

    /// Solves `A X = B` in place, `x` holding `B` on entry (one sweep
    /// through `L` for the whole block, in parallel over the elimination
    /// tree).
    pub fn solve_in_place(&self, x: MatMut<'_, f64>) {
        assert_eq!(
            x.nrows(),
            self.dim(),
            "right-hand side has the wrong length"
        );
        self.symbolic.solve_in_place(&self.values, x);
    }

    /// Whether this factors `K` with fixed equations rather than
    /// `K - sigma M` ([`crate::pencil::Pencil::factorize_static`]).
    pub fn is_fixed(&self) -> bool {
        self.fixed
    }

    /// The factor's storage, for [`crate::pencil::Pencil::refactorize`].
    pub fn into_storage(self) -> Vec<f64> {
        self.values
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sparse::from_triplets;
    use faer::sparse::Triplet;

    /// Tridiagonal `[-1 2 -1]` chain of `n` springs, fixed at one end when
    /// `fixed` (else free: singular).
    fn chain(n: usize, fixed: bool, shift: f64) -> SparseMat {
        let mut t = Vec::new();
        for i in 0..n {
            let first_free = i == 0 && !fixed;
            let d = if first_free || i == n - 1 { 1.0 } else { 2.0 };
            t.push(Triplet::new(i, i, d - shift));
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -1.0));
                t.push(Triplet::new(i + 1, i, -1.0));
            }
        }
        from_triplets(n, n, &t).unwrap()
    }

    #[test]
    fn solves_a_block_of_right_hand_sides() {
        let a = chain(50, true, 0.0);
        let f = Factor::of(&a).unwrap();
        let b = Mat::from_fn(50, 3, |i, j| ((i * 7 + j * 3) % 11) as f64 - 5.0);
        let x = f.solve(b.as_ref());
        let r = &a * &x - &b;
        assert!(crate::sparse::max_abs(r.as_ref()) < 1e-10);
        assert_eq!(f.inertia().positive, 50);
    }

    #[test]
    fn free_chain_is_singular() {
        let a = chain(30, false, 0.0);
        match Factor::of(&a) {
            Err(LinalgError::Singular { index, .. }) => assert!(index < 30),
            other => panic!("expected a singular matrix, got {other:?}"),
        }
    }

    #[test]
    fn inertia_counts_eigenvalues_below_a_shift() {
        // Eigenvalues of the fixed-free chain: 2 - 2 cos((2k-1) pi / (2n+1)).
        let n = 40;
        let sigma = 1.05; // not an eigenvalue (1.0 is one, for k = 14)
        let below = (1..=n)
            .filter(|k| {
                2.0 - 2.0 * (((2 * k - 1) as f64) * std::f64::consts::PI / (2 * n + 1) as f64).cos()
                    < sigma
            })
            .count();
        let f = Factor::of(&chain(n, true, sigma)).unwrap();
        assert_eq!(f.inertia().negative, below);
    }
}
