//! M-orthonormalisation of the Lanczos blocks: projection on the basis,
//! Cholesky QR twice in the `M` inner product, and Gram-Schmidt with
//! breakdown handling where a block is too ill-conditioned for it.

use super::run::Rng;
use crate::pencil::Pencil;
use crate::tall;
use faer::{ColRef, Mat, MatMut, MatRef, Side};

/// `a^T b`.
pub(super) fn dot(a: ColRef<'_, f64>, b: ColRef<'_, f64>) -> f64 {
    a.transpose() * b
}

/// `W -= X (X^T MW)` for `MW = M W` (stale afterwards); returns `X^T MW`.
/// With `X` the M-orthonormal union of blocks that are M-orthogonal to
/// each other, the blocks may be projected one after the other with the
/// same `MW`.
pub(super) fn project_out(w: MatMut<'_, f64>, mw: MatRef<'_, f64>, x: MatRef<'_, f64>) -> Mat<f64> {
    let c = tall::gram(x, mw);
    if x.ncols() > 0 {
        tall::add_product(w, x, c.as_ref(), -1.0);
    }
    c
}

/// M-orthonormalises the columns of `w` (with `mw = M w`) in place by
/// Cholesky QR twice, or by Gram-Schmidt twice when the block is too
/// ill-conditioned for that; returns the upper-triangular `B` with
/// `W_in = Q B`. A column that vanishes against the earlier ones (to 1e-10
/// of `before`, its M-norm before the projection on the basis) is replaced
/// by a random vector orthogonal to `locked`, the basis and the earlier
/// columns, which enters `B` with a zero diagonal entry.
pub(super) fn orthonormalize_block(
    w: &mut Mat<f64>,
    mw: &mut Mat<f64>,
    before: &[f64],
    others: &[MatRef<'_, f64>],
    pencil: &Pencil,
    rng: &mut Rng,
) -> Mat<f64> {
    cholesky_qr2(w, mw, others, pencil, rng)
        .unwrap_or_else(|| gram_schmidt_block(w, mw, before, others, pencil, rng))
}

/// Cholesky QR twice in the `M` inner product: `G = W^T M W = R^T R`,
/// `W <- W R^-1`, once more for orthogonality to round-off; returns `B`
/// with `W_in = Q B`. Two small Gram matrices and BLAS-3 updates of the
/// `n x b` block in place, where Gram-Schmidt column by column costs `b^2`
/// passes over `n`. `None` (nothing changed) when `W` is too
/// ill-conditioned for it (the ratio of the extreme diagonal entries of
/// `R` below 1e-6, the point where `G` has lost half the digits); should
/// the second pass fail, Gram-Schmidt finishes what the first began.
fn cholesky_qr2(
    w: &mut Mat<f64>,
    mw: &mut Mat<f64>,
    others: &[MatRef<'_, f64>],
    pencil: &Pencil,
    rng: &mut Rng,
) -> Option<Mat<f64>> {
    let b = w.ncols();
    let mut total = Mat::<f64>::identity(b, b);
    for pass in 0..2 {
        let mut g = tall::gram(w.as_ref(), mw.as_ref());
        crate::sparse::symmetrize(&mut g);
        let factor = g.llt(Side::Lower).ok().map(|f| f.L().to_owned());
        let conditioned = factor.as_ref().is_some_and(|l| {
            let (lo, hi) = (0..b).fold((f64::INFINITY, 0.0_f64), |(lo, hi), i| {
                (lo.min(l[(i, i)]), hi.max(l[(i, i)]))
            });
            lo > 1e-6 * hi && hi.is_finite()
        });
        let l = match factor {
            Some(l) if conditioned => l,
            _ if pass == 0 => return None,
            _ => {
                // The columns have unit M-norm after the first pass.
                let unit = vec![1.0; b];
                let r = gram_schmidt_block(w, mw, &unit, others, pencil, rng);
                return Some(r * &total);
            }
        };
        // W R^-1 with R = L^T, in place.
        for x in [w.as_mut(), mw.as_mut()] {
            tall::div_upper(x, l.transpose());
        }
        total = l.transpose() * &total;
    }
    Some(total)
}

/// Gram-Schmidt column by column, twice, with breakdown handling (the
/// fallback of [`cholesky_qr2`]).
fn gram_schmidt_block(
    w: &mut Mat<f64>,
    mw: &mut Mat<f64>,
    before: &[f64],
    others: &[MatRef<'_, f64>],
    pencil: &Pencil,
    rng: &mut Rng,
) -> Mat<f64> {
    let (n, b) = (w.nrows(), w.ncols());
    let mut r = Mat::<f64>::zeros(b, b);
    for i in 0..b {
        for _pass in 0..2 {
            for j in 0..i {
                let c = dot(w.col(j), mw.col(i));
                r[(j, i)] += c;
                for p in 0..n {
                    w[(p, i)] -= c * w[(p, j)];
                    mw[(p, i)] -= c * mw[(p, j)];
                }
            }
        }
        let norm = dot(w.col(i), mw.col(i)).max(0.0).sqrt();
        if norm > 1e-10 * before[i] && norm.is_finite() {
            r[(i, i)] = norm;
            for p in 0..n {
                w[(p, i)] /= norm;
                mw[(p, i)] /= norm;
            }
            continue;
        }
        // Breakdown: an invariant subspace; continue with a fresh direction.
        let mut z = Mat::from_fn(n, 1, |_, _| rng.next());
        let mut mz = pencil.mul_mass(z.as_ref());
        for _pass in 0..2 {
            for x in others {
                project_out(z.as_mut(), mz.as_ref(), *x);
            }
            mz = pencil.mul_mass(z.as_ref());
            for j in 0..i {
                let c = dot(w.col(j), mz.col(0));
                for p in 0..n {
                    z[(p, 0)] -= c * w[(p, j)];
                    mz[(p, 0)] -= c * mw[(p, j)];
                }
            }
        }
        let norm = dot(z.col(0), mz.col(0)).max(0.0).sqrt();
        for p in 0..n {
            w[(p, i)] = z[(p, 0)] / norm;
            mw[(p, i)] = mz[(p, 0)] / norm;
        }
        // Column i of W was a combination of the earlier columns (their
        // coefficients stay in B); the new direction enters with 0.
    }
    r
}
