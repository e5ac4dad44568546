//! The generalized symmetric eigenproblem `K x = lambda M x` (report eq. 21,
//! undamped), dense path for small models.
//!
//! Shift-invert form, so that the low modes, the ones a reduction keeps, are
//! accurate to round-off relative to their own size: with a shift
//! `sigma < 0` (below every eigenvalue of a stable body), `K - sigma M = L L^T`
//! (Cholesky) and `L^-1 M L^-T y = theta y` with `theta = 1 / (lambda - sigma)`,
//! `x = L^-T y / sqrt(theta)`. The eigenvectors come out M-orthonormal and
//! sorted by ascending eigenvalue; `M` may be singular (massless DOFs have
//! infinite eigenvalues and are not returned). Cost O(m^3): the path for
//! models up to a few thousand DOFs.

use crate::memory::Budget;
use crate::LinalgError;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place_with_conj, solve_upper_triangular_in_place_with_conj,
};
use faer::{Conj, Mat, MatRef, Side};

/// Which eigenpairs of `K phi = lambda M phi` to compute.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Wanted {
    /// The lowest `n` eigenpairs.
    Lowest(usize),
    /// All eigenpairs with `lambda` below this bound (rad^2/s^2; a frequency
    /// `f` in Hz is the bound `(2 pi f)^2`, [`Wanted::below_hz`]).
    Below(f64),
    /// The lowest `count` eigenpairs, of those with `lambda` below `bound`
    /// ("the lowest 20 modes, but only those below 500 Hz",
    /// [`Wanted::lowest_below_hz`]): at most `count` pairs. The same pairs
    /// as `Below(bound)` cut to its lowest `count`, or as `Lowest(count)`
    /// without those at or above `bound`.
    LowestBelow { count: usize, bound: f64 },
}

impl Wanted {
    /// Every eigenpair below the frequency `f` (Hz): `lambda < (2 pi f)^2`.
    pub fn below_hz(f: f64) -> Self {
        Wanted::Below(lambda_of_hz(f))
    }

    /// The lowest `count` eigenpairs below the frequency `f` (Hz):
    /// [`Wanted::LowestBelow`] with `bound = (2 pi f)^2`.
    pub fn lowest_below_hz(count: usize, f: f64) -> Self {
        Wanted::LowestBelow {
            count,
            bound: lambda_of_hz(f),
        }
    }

    /// The most pairs wanted, where a count caps them.
    pub fn count(self) -> Option<usize> {
        match self {
            Wanted::Lowest(count) | Wanted::LowestBelow { count, .. } => Some(count),
            Wanted::Below(_) => None,
        }
    }

    /// The bound the pairs' `lambda` lie below, where there is one.
    pub fn bound(self) -> Option<f64> {
        match self {
            Wanted::Below(bound) | Wanted::LowestBelow { bound, .. } => Some(bound),
            Wanted::Lowest(_) => None,
        }
    }

    /// Whether the request is for no pair at all (a count of 0).
    pub fn is_none(self) -> bool {
        self.count() == Some(0)
    }

    /// The same request with its count (if it has one) changed by `f`.
    pub fn map_count(self, f: impl FnOnce(usize) -> usize) -> Self {
        match self {
            Wanted::Lowest(count) => Wanted::Lowest(f(count)),
            Wanted::LowestBelow { count, bound } => Wanted::LowestBelow {
                count: f(count),
                bound,
            },
            below => below,
        }
    }

    /// How many of the eigenvalues `ascending` (the lowest of a pencil,
    /// ascending) the request keeps: the first ones, up to its count and
    /// below its bound.
    pub fn kept(self, ascending: &[f64]) -> usize {
        let below = match self.bound() {
            Some(bound) => ascending.iter().filter(|&&l| l < bound).count(),
            None => ascending.len(),
        };
        self.count().map_or(below, |count| count.min(below))
    }
}

/// The eigenvalue `(2 pi f)^2` of the frequency `f` (Hz).
fn lambda_of_hz(f: f64) -> f64 {
    (2.0 * std::f64::consts::PI * f).powi(2)
}

/// Eigenvalues (ascending) and M-orthonormal eigenvectors (as columns).
#[derive(Clone, Debug)]
pub struct EigenPairs {
    pub values: Vec<f64>,
    pub vectors: Mat<f64>,
}

impl EigenPairs {
    /// Natural frequencies in Hz (`sqrt(max(lambda, 0)) / 2 pi`).
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.values.iter().map(|l| frequency_hz(*l)).collect()
    }

    /// The pairs `from..to`.
    pub fn slice(&self, from: usize, to: usize) -> EigenPairs {
        EigenPairs {
            values: self.values[from..to].to_vec(),
            vectors: self.vectors.subcols(from, to - from).to_owned(),
        }
    }
}

/// How many of the lowest `values` (ascending eigenvalues of one pencil)
/// are round-off zeros. A zero comes out at round-off of eps lambda_max (or
/// of a text file's digits), with either sign: the lowest counts as
/// non-zero only above `1e-8 top` (`top` the largest eigenvalue known), any
/// later one only a factor `gap` above every value before it.
pub fn leading_zeros(values: &[f64], top: f64, gap: f64) -> usize {
    (0..values.len())
        .find(|&i| {
            let v = values[i];
            v > 0.0
                && if i == 0 {
                    v > 1e-8 * top.abs()
                } else {
                    v > gap * values[..i].iter().fold(0.0_f64, |a, b| a.max(b.abs()))
                }
        })
        .unwrap_or(values.len())
}

/// `sqrt(lambda) / (2 pi)`, with round-off negatives of rigid-body modes
/// shown as 0 Hz.
pub fn frequency_hz(lambda: f64) -> f64 {
    lambda.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)
}

/// The eigenvalues (ascending) and orthonormal eigenvectors (columns) of
/// the dense symmetric matrix `a` (its lower triangle is read).
///
/// faer's solver (0.24) is not scale-invariant: above 128 rows it takes
/// divide and conquer, whose secant iteration on the secular equation stops
/// once two values of that function differ by less than an *absolute*
/// epsilon. For a matrix far from unit size (a shift-invert operator of an
/// SI model has norm 1e-9) with a graded spectrum, the roots and vectors
/// then come out with residuals `||A u - s u||` up to 1e11 `eps ||A||`
/// (measured at 2000 rows, eigenvalues over ten decades). Scaled to a
/// largest entry in `[0.5, 1)` by a power of two (exact), the same matrix
/// gives 6 `eps ||A||`. Every symmetric eigen-decomposition with vectors in
/// flexbody goes through here (eigenvalues alone take faer's QR iteration,
/// which was accurate on the same matrices unscaled).
pub fn symmetric_eigen(a: MatRef<'_, f64>) -> Result<(Vec<f64>, Mat<f64>), LinalgError> {
    let n = a.nrows();
    let largest = (0..n)
        .flat_map(|j| (j..n).map(move |i| (i, j)))
        .fold(0.0_f64, |m, (i, j)| m.max(a[(i, j)].abs()));
    if !largest.is_finite() {
        return Err(LinalgError::NonFinite { n });
    }
    let scale = if largest > 0.0 {
        (-largest.log2().floor() - 1.0)
            .clamp(-1000.0, 1000.0)
            .exp2()
    } else {
        1.0
    };
    let scaled = Mat::from_fn(n, n, |i, j| a[(i, j)] * scale);
    let evd = scaled
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
    let values = (0..n).map(|i| evd.S()[i] / scale).collect();
    Ok((values, evd.U().to_owned()))
}

/// Dense `n x n` matrices [`generalized_symmetric`] holds at its peak
/// besides `K` and `M`: `K - sigma M`, its factor, `L^-1 M`, `C`, the
/// scaled copy and eigenvectors of [`symmetric_eigen`] with faer's
/// workspace, the vectors. (Measured: 1000 modes of a 1668-DOF solid
/// through `flexbody modes` peak at 11 such matrices with `K` and `M`.)
const DENSE_WORK: u64 = 10;

/// Below this many entries per matrix (1 MiB) the room is not checked:
/// reading `/proc` would cost more than the solve.
const TRIVIAL_ENTRIES: u64 = 1 << 17;

/// Refuses, before any storage is taken, a dense eigen solve of `n`
/// equations that would not fit in the room `budget` leaves; `inputs`
/// counts the dense `n x n` copies of `K` and `M` the caller has yet to
/// make.
pub fn ensure_dense_room(n: usize, inputs: u64, budget: Budget) -> Result<(), LinalgError> {
    let entries = (n as u64).saturating_mul(n as u64);
    if entries < TRIVIAL_ENTRIES {
        return Ok(());
    }
    let matrices = DENSE_WORK + inputs;
    budget.ensure(
        matrices
            .saturating_mul(entries)
            .saturating_mul(std::mem::size_of::<f64>() as u64),
        &format!("the dense eigen solve of {n} equations ({matrices} matrices of {n} x {n})"),
    )
}

/// All finite eigenpairs of `K x = lambda M x` for dense symmetric `K`
/// (positive semi-definite) and `M` (positive semi-definite, `K + M`
/// positive definite).
///
/// One shift-invert pass resolves about 13 decades of eigenvalues above its
/// shift; stiffer modes (a reduced body whose residual modes carry masses
/// 1e-17 of the rest) come out of a pass on the complement of the found
/// ones, and only directions of round-off mass stay unreturned.
///
/// Refused before it starts where its matrices would not fit in the
/// machine's room ([`Budget::MACHINE`]); a caller under a user's budget
/// checks [`ensure_dense_room`] with it first. The dense kernels run under
/// faer's parallelism setting, as faer's own dense decompositions do.
pub fn generalized_symmetric(
    k: MatRef<'_, f64>,
    m: MatRef<'_, f64>,
) -> Result<EigenPairs, LinalgError> {
    let n = k.nrows();
    if k.ncols() != n || m.nrows() != n || m.ncols() != n {
        return Err(LinalgError::Dimension(format!(
            "eigenproblem with K {}x{} and M {}x{}",
            k.nrows(),
            k.ncols(),
            m.nrows(),
            m.ncols()
        )));
    }
    if n == 0 {
        return Ok(EigenPairs {
            values: Vec::new(),
            vectors: Mat::zeros(0, 0),
        });
    }
    ensure_dense_room(n, 0, Budget::MACHINE)?;
    let trace_k: f64 = (0..n).map(|i| k[(i, i)].abs()).sum();
    let trace_m: f64 = (0..n).map(|i| m[(i, i)].abs()).sum();
    if trace_m == 0.0 {
        return Err(LinalgError::NoMass);
    }
    let found = lowest(k, m, trace_k / trace_m)?;
    if found.values.len() == n {
        return Ok(found);
    }
    Ok(complement(k, m, found))
}

/// The shift-invert solve: a first shift far below the mean eigenvalue
/// `mean`, then one at the lowest elastic eigenvalue.
fn lowest(k: MatRef<'_, f64>, m: MatRef<'_, f64>, mean: f64) -> Result<EigenPairs, LinalgError> {
    // First pass with a shift far below the mean eigenvalue; then, if the
    // lowest elastic eigenvalue is far from it, a second pass shifted to its
    // size, which makes the low modes accurate relative to themselves.
    let mean = mean.max(f64::MIN_POSITIVE);
    let mut sigma = -1e-6 * mean;
    // K of only rigid-body modes (a reduced body without elastic modes) is
    // itself round-off, with negative eigenvalues that may lie below a
    // shift taken from its size: then the shift goes down until
    // K - sigma M is positive definite.
    let mut retries = 0;
    let first = loop {
        match shifted(k, m, sigma) {
            Err(LinalgError::Singular { .. }) if retries < SHIFT_RETRIES => {
                sigma *= 1e3;
                retries += 1;
            }
            result => break result?,
        }
    };
    // The lowest elastic eigenvalue sets the second shift; round-off zeros
    // of rigid-body modes (slightly negative or positive, larger when K
    // comes from a text file) must not. Here the gap is wide (1e6): taking
    // a zero for elastic would put the second shift on round-off.
    let v = &first.values;
    let top = v.last().map_or(0.0, |x| x.abs());
    let lowest_elastic = v.get(leading_zeros(v, top, 1e6)).copied();
    match lowest_elastic {
        Some(l) if !(1e-2..=1e2).contains(&(l / sigma.abs())) => shifted(k, m, -l),
        _ => Ok(first),
    }
}

/// The eigenpairs that one shift-invert pass left out, added to `found`:
/// the eigenvectors still missing are M-orthogonal to the found ones `X`,
/// so they lie in the null space of `X^T M`. In coordinates scaled by
/// `D = diag(M)^-1/2` (a mass of 1e-17 becomes 1 there, and so visible
/// above round-off) an orthonormal basis `Q` of that null space gives the
/// small pencil `(Q^T K' Q, Q^T M' Q)`. Its mass directions below
/// round-off are massless and dropped; on the others `M'` is made the
/// identity and `K'` diagonalised: a standard symmetric eigenproblem.
fn complement(k: MatRef<'_, f64>, m: MatRef<'_, f64>, found: EigenPairs) -> EigenPairs {
    let n = k.nrows();
    let kept = found.values.len();
    let positive: Vec<f64> = (0..n).map(|i| m[(i, i)]).filter(|&d| d > 0.0).collect();
    let mean = positive.iter().sum::<f64>() / positive.len().max(1) as f64;
    let d: Vec<f64> = (0..n)
        .map(|i| 1.0 / if m[(i, i)] > 0.0 { m[(i, i)] } else { mean }.sqrt())
        .collect();
    let ms = Mat::from_fn(n, n, |i, j| d[i] * m[(i, j)] * d[j]);
    let ks = Mat::from_fn(n, n, |i, j| d[i] * k[(i, j)] * d[j]);
    // D M X = M' X' with X' = D^-1 X: its range is orthogonal to the null
    // space sought; the last n - kept columns of a full QR span that.
    let mx = m * &found.vectors;
    let mx = Mat::from_fn(n, kept, |i, j| d[i] * mx[(i, j)]);
    let q = mx.qr().compute_Q();
    let q = q.subcols(kept, n - kept);
    let mut mq = q.transpose() * &ms * q;
    crate::sparse::symmetrize(&mut mq);
    let Ok((s, mass_u)) = symmetric_eigen(mq.as_ref()) else {
        return found;
    };
    let scale = (0..n).map(|i| ms[(i, i)]).fold(0.0_f64, f64::max);
    let massive: Vec<usize> = (0..n - kept)
        .filter(|&i| s[i] > 1e-13 * n as f64 * scale)
        .collect();
    if massive.is_empty() {
        return found;
    }
    // Z = Q V S^-1/2: Z^T M' Z = I.
    let qv = q * mass_u;
    let z = Mat::from_fn(n, massive.len(), |i, j| {
        qv[(i, massive[j])] / s[massive[j]].sqrt()
    });
    let mut a = z.transpose() * &ks * &z;
    crate::sparse::symmetrize(&mut a);
    let Ok((stiff_s, stiff_u)) = symmetric_eigen(a.as_ref()) else {
        return found;
    };
    let y = &z * stiff_u;
    let mut pairs: Vec<(f64, usize)> = (0..kept).map(|j| (found.values[j], j)).collect();
    pairs.extend((0..massive.len()).map(|j| (stiff_s[j], kept + j)));
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let column = |i: usize, c: usize| {
        if c < kept {
            found.vectors[(i, c)]
        } else {
            d[i] * y[(i, c - kept)]
        }
    };
    EigenPairs {
        values: pairs.iter().map(|p| p.0).collect(),
        vectors: Mat::from_fn(n, pairs.len(), |i, j| column(i, pairs[j].1)),
    }
}

/// How often the first shift moves down by 1e3 before a failed Cholesky
/// factorisation is reported (1e3^8 = 1e24 below the first).
const SHIFT_RETRIES: usize = 8;

fn shifted(k: MatRef<'_, f64>, m: MatRef<'_, f64>, sigma: f64) -> Result<EigenPairs, LinalgError> {
    let n = k.nrows();
    let a = Mat::from_fn(n, n, |i, j| k[(i, j)] - sigma * m[(i, j)]);
    let llt = a.llt(Side::Lower).map_err(|e| match e {
        faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
            LinalgError::Singular {
                index,
                pivot: 0.0,
                diagonal: a[(index.min(n - 1), index.min(n - 1))],
            }
        }
    })?;
    let l = llt.L();
    let par = faer::get_global_parallelism();
    // C = L^-1 M L^-T.
    let mut y = m.to_owned();
    solve_lower_triangular_in_place_with_conj(l, Conj::No, y.as_mut(), par);
    let mut c = y.transpose().to_owned();
    solve_lower_triangular_in_place_with_conj(l, Conj::No, c.as_mut(), par);
    crate::sparse::symmetrize(&mut c);
    let (theta, mut vectors) = symmetric_eigen(c.as_ref())?;
    solve_upper_triangular_in_place_with_conj(l.transpose(), Conj::No, vectors.as_mut(), par);
    let theta_max = theta.iter().fold(0.0_f64, |a, b| a.max(*b));
    // theta = 0 belongs to lambda = infinity (massless DOFs).
    let cutoff = theta_max * 1e-13 * n as f64;
    let mut order: Vec<usize> = (0..n).filter(|&i| theta[i] > cutoff).collect();
    order.sort_by(|&a, &b| theta[b].total_cmp(&theta[a]));
    let values = order.iter().map(|&i| sigma + 1.0 / theta[i]).collect();
    let vectors = Mat::from_fn(n, order.len(), |i, j| {
        vectors[(i, order[j])] / theta[order[j]].sqrt()
    });
    Ok(EigenPairs { values, vectors })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(n: usize, fixed: bool) -> Mat<f64> {
        Mat::from_fn(n, n, |i, j| {
            if i == j {
                if i == n - 1 || (i == 0 && !fixed) {
                    1.0
                } else {
                    2.0
                }
            } else if i.abs_diff(j) == 1 {
                -1.0
            } else {
                0.0
            }
        })
    }

    #[test]
    fn spring_mass_chain_matches_closed_form() {
        // Fixed-free chain of unit springs and masses 2: lambda_k = (2 - 2 cos th_k) / 2.
        let n = 12;
        let k = chain(n, true);
        let m = Mat::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.0 });
        let pairs = generalized_symmetric(k.as_ref(), m.as_ref()).unwrap();
        for (idx, lam) in pairs.values.iter().enumerate() {
            let th = (2 * idx + 1) as f64 * std::f64::consts::PI / (2 * n + 1) as f64;
            let exact = (2.0 - 2.0 * th.cos()) / 2.0;
            assert!((lam - exact).abs() < 1e-13 * exact.max(1.0));
        }
        let xtmx = pairs.vectors.transpose() * &m * &pairs.vectors;
        for i in 0..n {
            for j in 0..n {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((xtmx[(i, j)] - want).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn free_chain_has_an_exact_zero_and_massless_dofs_are_dropped() {
        // Free chain: one rigid mode at 0; the last DOF is massless.
        let n = 10;
        let k = chain(n, false);
        let m = Mat::from_fn(n, n, |i, j| if i == j && i < n - 1 { 1.0 } else { 0.0 });
        let pairs = generalized_symmetric(k.as_ref(), m.as_ref()).unwrap();
        assert_eq!(pairs.values.len(), n - 1);
        assert!(pairs.values[0].abs() < 1e-14, "{}", pairs.values[0]);
        let r =
            &k * pairs.vectors.col(1) - &m * pairs.vectors.col(1) * faer::Scale(pairs.values[1]);
        assert!(r.norm_max() < 1e-13);
    }

    #[test]
    fn rounded_zero_modes_do_not_set_the_shift() {
        // A free chain with a spectrum over 15 decades whose zero mode came
        // out slightly positive (as from K read from a text file): the shift
        // must come from the first elastic eigenvalue, or the stiff modes
        // look massless and are lost.
        let n = 14;
        let stiff: Vec<f64> = (0..n - 1).map(|i| 1e6 * 10f64.powi(i as i32 % 4)).collect();
        let mut k = Mat::<f64>::zeros(n, n);
        for (i, s) in stiff.iter().enumerate() {
            k[(i, i)] += s;
            k[(i + 1, i + 1)] += s;
            k[(i, i + 1)] -= s;
            k[(i + 1, i)] -= s;
        }
        let m = Mat::<f64>::identity(n, n);
        let exact = generalized_symmetric(k.as_ref(), m.as_ref()).unwrap();
        let rounded = Mat::from_fn(n, n, |i, j| k[(i, j)] + if i == j { 1e-3 } else { 0.0 });
        let pairs = generalized_symmetric(rounded.as_ref(), m.as_ref()).unwrap();
        assert_eq!(pairs.values.len(), n);
        for (a, b) in pairs.values.iter().zip(&exact.values).skip(1) {
            assert!((a - b - 1e-3).abs() < 1e-9 * b, "{a} vs {b}");
        }
    }

    #[test]
    fn a_stiffness_of_round_off_moves_the_shift_down() {
        // K of a body reduced to its rigid-body modes: R^T K R is round-off
        // with a negative eigenvalue (-1e-12) far below the first shift
        // (-1e-6 of trace K / trace M = -1e-18). Both eigenvalues come out.
        let k = faer::mat![[1e-12, 2e-12], [2e-12, 1e-12]];
        let m = Mat::<f64>::identity(2, 2);
        let pairs = generalized_symmetric(k.as_ref(), m.as_ref()).unwrap();
        assert_eq!(pairs.values.len(), 2);
        assert!(
            (pairs.values[0] + 1e-12).abs() < 1e-20,
            "{:?}",
            pairs.values
        );
        assert!(
            (pairs.values[1] - 3e-12).abs() < 1e-20,
            "{:?}",
            pairs.values
        );
        assert_eq!(pairs.frequencies_hz()[0], 0.0);
    }

    #[test]
    fn modes_stiffer_than_one_pass_resolves_come_from_the_complement() {
        // Two ordinary modes (1 and 4) and a block as of a reduced body's
        // residual modes: masses 1e-17, nearly equal, stiffness 1e-9. Its
        // eigenvalues are 1e-9 / (2e-17) = 5e7 and 1e-9 / 1e-25 = 1e16, the
        // latter 16 decades above the lowest, beyond one shift-invert pass.
        // The data fix the small mass difference to eps / e = 2e-8.
        let e = 1e-8;
        let m = faer::mat![
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1e-17, 1e-17 * (1.0 - e)],
            [0.0, 0.0, 1e-17 * (1.0 - e), 1e-17],
        ];
        let k = faer::mat![
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 4.0, 0.0, 0.0],
            [0.0, 0.0, 1e-9, 0.0],
            [0.0, 0.0, 0.0, 1e-9],
        ];
        let pairs = generalized_symmetric(k.as_ref(), m.as_ref()).unwrap();
        let exact = [1.0, 4.0, 1e-9 / (1e-17 * (2.0 - e)), 1e-9 / (1e-17 * e)];
        assert_eq!(pairs.values.len(), 4, "{:?}", pairs.values);
        for (l, x) in pairs.values.iter().zip(exact) {
            assert!((l - x).abs() < 1e-7 * x, "{l} vs {x}");
        }
        for j in 0..4 {
            let x = pairs.vectors.col(j);
            let r = &k * x - &m * x * faer::Scale(pairs.values[j]);
            assert!(r.norm_l2() < 1e-7 * (&k * x).norm_l2(), "mode {j}");
        }
        let xtmx = pairs.vectors.transpose() * &m * &pairs.vectors;
        let unit = Mat::<f64>::identity(4, 4);
        assert!((xtmx - unit).norm_max() < 1e-7);
    }

    #[test]
    fn a_graded_matrix_far_from_unit_size_has_accurate_eigenpairs() {
        // Q diag(d) Q^T with d over ten decades and norm 1e-9 (the size of
        // a shift-invert operator of an SI model), 300 rows: above faer's
        // divide-and-conquer threshold. Unscaled, faer's residuals reach
        // 1.5e9 eps ||A|| here; scaled, a few eps ||A||.
        let n = 300;
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed as f64 / u64::MAX as f64 - 0.5
        };
        let q = Mat::from_fn(n, n, |_, _| next()).qr().compute_Q();
        let d: Vec<f64> = (0..n)
            .map(|i| 1e-9 * 1e-10_f64.powf(i as f64 / (n - 1) as f64))
            .collect();
        let mut a = Mat::from_fn(n, n, |i, j| q[(i, j)] * d[j]) * q.transpose();
        crate::sparse::symmetrize(&mut a);
        let (values, u) = symmetric_eigen(a.as_ref()).unwrap();
        assert!(values.windows(2).all(|w| w[0] <= w[1]));
        let unit = f64::EPSILON * 1e-9;
        for (j, value) in values.iter().enumerate() {
            let r = &a * u.col(j) - u.col(j) * faer::Scale(*value);
            assert!(
                r.norm_l2() < 50.0 * unit,
                "pair {j}: {:e}",
                r.norm_l2() / unit
            );
        }
        let dev = (u.transpose() * &u - Mat::<f64>::identity(n, n)).norm_max();
        assert!(dev < 1e3 * f64::EPSILON, "{dev:e}");
        // The eigenvalues are the d's, to round-off of the largest.
        let mut exact = d.clone();
        exact.sort_by(f64::total_cmp);
        for (v, x) in values.iter().zip(&exact) {
            assert!((v - x).abs() < 50.0 * unit, "{v:e} vs {x:e}");
        }
    }

    #[test]
    fn leading_zeros_are_round_off_below_a_gap() {
        // Rigid-body zeros read from a text file, all positive (a CalculiX
        // tet mesh): six zeros below the first elastic 2.5e8.
        let text = [5.1e-5, 1.8e-4, 1.9e-4, 2.2e-4, 2.2e-4, 1.4e-3, 2.5e8];
        assert_eq!(leading_zeros(&text, 2.5e8, 1e6), 6);
        // A supported body: no zero.
        assert_eq!(leading_zeros(&[3.0, 5.0, 9.0], 9.0, 1e6), 0);
        // A stiff planar beam (stiffness over 13 decades): zeros at 27 and
        // 73, the first elastic eigenvalue only 3.4e4 above them.
        let stiff = [27.6, 73.2, 2.45e6, 1.86e7, 7.16e7, 1.96e8];
        assert_eq!(leading_zeros(&stiff, 1e19, 1e3), 2);
        // The wide gap takes them all for zeros.
        assert_eq!(leading_zeros(&stiff, 1e19, 1e6), stiff.len());
        // Signs of round-off do not matter; all zeros.
        assert_eq!(leading_zeros(&[-1e-9, 2e-9, -3e-9], 1.0, 1e3), 3);
    }
}
