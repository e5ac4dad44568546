//! The end of a solve: the wanted converged pairs in ascending order,
//! M-orthonormal again after runs on several shifts, their Rayleigh
//! quotients and residuals.

use super::block_qr::dot;
use super::run::Locked;
use super::solver::Solver;
use super::{EigenSolution, SturmReport};
use crate::eigen::{EigenPairs, Wanted};
use crate::pencil::Pencil;
use crate::progress::Stage;
use crate::tall;
use crate::LinalgError;
use faer::{Mat, MatRef, Side};

impl Solver<'_> {
    /// Reports and records the work of the iterations, gives up the
    /// operator's factor, and returns the wanted pairs: ascending, `M`-
    /// orthonormal, each `lambda` the Rayleigh quotient of its vector, with
    /// its residual (the module docs of [`super`]).
    pub(super) fn finish(self, sturm: Option<SturmReport>) -> Result<EigenSolution, LinalgError> {
        let Self {
            pencil,
            wanted,
            progress,
            op,
            sigma,
            k_diag,
            mut stats,
            locked,
            started,
            iterations,
            first_factorization,
            band_count_seconds,
            ..
        } = self;
        progress.report(&Stage::LanczosDone {
            solves: op.solves,
            block_solves: op.block_solves,
            solve_seconds: op.solve_seconds,
            products: op.mass_products,
            mass_seconds: op.mass_seconds,
            seconds: iterations.elapsed().as_secs_f64() - (op.sturm_seconds - band_count_seconds),
        });
        op.record(&mut stats);
        stats.iteration_seconds = iterations.elapsed().as_secs_f64()
            - (stats.sturm_seconds - band_count_seconds)
            - (stats.factorization_seconds - first_factorization);
        drop(op);
        let (mut vectors, mut mx) = wanted_vectors(pencil, locked, wanted);
        if stats.runs > 1 {
            restore_orthogonality(&mut vectors, &mut mx)?;
        }
        let (values, kx) = rayleigh_ascending(pencil, &mut vectors, &mut mx);
        let residuals = residuals_of(&kx, &mx, &values, vectors.as_ref(), &k_diag);
        progress.report(&Stage::Done {
            seconds: started.elapsed().as_secs_f64(),
        });
        Ok(EigenSolution {
            pairs: EigenPairs { values, vectors },
            residuals,
            shift: sigma,
            sturm,
            stats,
        })
    }
}

/// The wanted converged vectors in ascending `lambda` (the lowest `count`,
/// those below a band's bound, or the lowest `count` of those), and `M`
/// times them.
fn wanted_vectors(pencil: &Pencil, locked: Locked, wanted: Wanted) -> (Mat<f64>, Mat<f64>) {
    let n = locked.x.nrows();
    let mut order: Vec<usize> = (0..locked.lambda.len()).collect();
    order.sort_by(|&a, &b| locked.lambda[a].total_cmp(&locked.lambda[b]));
    let ascending: Vec<f64> = order.iter().map(|&i| locked.lambda[i]).collect();
    let keep = wanted.kept(&ascending);
    order.truncate(keep);
    let vectors = Mat::from_fn(n, order.len(), |i, j| locked.x[(i, order[j])]);
    drop(locked);
    let mx = pencil.mul_mass(vectors.as_ref());
    (vectors, mx)
}

/// Runs after the first, on shifts above the band where the operator's
/// `|theta|` is large, leave their vectors M-orthogonal to some 1e-10
/// only. Cholesky QR in ascending `lambda` restores it and changes each
/// vector by the ones below it only: a low mode takes in no part of a high
/// one (which would cost its residual that part times `lambda_high /
/// lambda_low`). `mx = M x` follows.
fn restore_orthogonality(vectors: &mut Mat<f64>, mx: &mut Mat<f64>) -> Result<(), LinalgError> {
    let mut g = tall::gram(vectors.as_ref(), mx.as_ref());
    crate::sparse::symmetrize(&mut g);
    let l = g
        .llt(Side::Lower)
        .map_err(|err| LinalgError::Faer(format!("{err:?}")))?
        .L()
        .to_owned();
    for x in [vectors.as_mut(), mx.as_mut()] {
        tall::div_upper(x, l.transpose());
    }
    Ok(())
}

/// The Rayleigh quotients `x^T K x / x^T M x` of the columns, ascending,
/// and `K x`: they may swap neighbours the Ritz values ordered (repeated
/// eigenvalues, rigid-body modes at round-off), so the columns of
/// `vectors`, `mx` and `K x` are sorted with them.
fn rayleigh_ascending(
    pencil: &Pencil,
    vectors: &mut Mat<f64>,
    mx: &mut Mat<f64>,
) -> (Vec<f64>, Mat<f64>) {
    let mut kx = pencil.mul_stiffness(vectors.as_ref());
    let mut values: Vec<f64> = (0..vectors.ncols())
        .map(|j| dot(vectors.col(j), kx.col(j)) / dot(vectors.col(j), mx.col(j)))
        .collect();
    for j in 1..values.len() {
        let mut i = j;
        while i > 0 && values[i - 1] > values[i] {
            values.swap(i - 1, i);
            for x in [&mut *vectors, &mut *mx, &mut kx] {
                swap_columns(x, i - 1, i);
            }
            i -= 1;
        }
    }
    (values, kx)
}

/// Swaps columns `a < b` of `x`.
fn swap_columns(x: &mut Mat<f64>, a: usize, b: usize) {
    let (left, right) = x.as_mut().split_at_col_mut(b);
    let (mut p, mut q) = (left.col_mut(a), right.col_mut(0));
    for i in 0..p.nrows() {
        std::mem::swap(&mut p[i], &mut q[i]);
    }
}

/// [`super::residuals`] from the products `K x` and `M x`.
pub(crate) fn residuals_of(
    kx: &Mat<f64>,
    mx: &Mat<f64>,
    values: &[f64],
    vectors: MatRef<'_, f64>,
    k_diag: &[f64],
) -> Vec<f64> {
    let k_norm = k_diag.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    (0..values.len())
        .map(|j| {
            let r = kx.col(j) - mx.col(j) * faer::Scale(values[j]);
            let floor = k_norm * vectors.col(j).norm_l2();
            let scale = kx
                .col(j)
                .norm_l2()
                .max(mx.col(j).norm_l2() * values[j].abs());
            let scale = if scale < 1e-8 * floor { floor } else { scale };
            if scale > 0.0 {
                r.norm_l2() / scale
            } else {
                0.0
            }
        })
        .collect()
}
