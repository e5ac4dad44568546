//! M-orthonormalisation of a set of vectors, with rank detection.
//!
//! Modified Gram-Schmidt in the `M` inner product, applied twice ("twice is
//! enough") so that `X^T M X = I` holds to round-off. Columns that are
//! (numerically) combinations of earlier ones are dropped and reported, which
//! is how the geometric rigid-body modes of a planar model shrink from 6 to
//! the ones the DOFs can carry.

use crate::SparseMat;
use faer::{Mat, MatRef};

/// Result of [`m_orthonormalize`].
#[derive(Clone, Debug)]
pub struct Orthonormalized {
    /// The M-orthonormal columns.
    pub vectors: Mat<f64>,
    /// For each kept column, the index of the input column it came from.
    pub kept: Vec<usize>,
}

/// M-orthonormalises the columns of `x`; a column whose M-norm falls below
/// `drop_tolerance` times its original M-norm after removing the earlier
/// columns is dropped (as is a column of zero M-norm).
pub fn m_orthonormalize(x: MatRef<'_, f64>, m: &SparseMat, drop_tolerance: f64) -> Orthonormalized {
    let n = x.nrows();
    // One (parallel) product with M for all columns; Gram-Schmidt then
    // updates each column and its M-image together.
    let mx = crate::sparse::symmetric_mul(m, x);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
    let mut kept_cols: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    let mut kept = Vec::new();
    for j in 0..x.ncols() {
        let mut v: Vec<f64> = (0..n).map(|i| x[(i, j)]).collect();
        let mut mv: Vec<f64> = (0..n).map(|i| mx[(i, j)]).collect();
        let original = dot(&v, &mv).max(0.0).sqrt();
        if original == 0.0 || !original.is_finite() {
            continue;
        }
        for _pass in 0..2 {
            for (q, mq) in &kept_cols {
                let c = dot(q, &mv);
                for i in 0..n {
                    v[i] -= c * q[i];
                    mv[i] -= c * mq[i];
                }
            }
        }
        let norm = dot(&v, &mv).max(0.0).sqrt();
        if norm <= drop_tolerance * original {
            continue;
        }
        v.iter_mut().for_each(|a| *a /= norm);
        mv.iter_mut().for_each(|a| *a /= norm);
        kept_cols.push((v, mv));
        kept.push(j);
    }
    let vectors = Mat::from_fn(n, kept_cols.len(), |i, j| kept_cols[j].0[i]);
    Orthonormalized { vectors, kept }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sparse::from_triplets;
    use faer::sparse::Triplet;

    #[test]
    fn dependent_and_zero_columns_are_dropped() {
        let m = from_triplets(
            3,
            3,
            &[
                Triplet::new(0, 0, 2.0),
                Triplet::new(1, 1, 3.0),
                Triplet::new(2, 2, 4.0),
            ],
        )
        .unwrap();
        let x = Mat::from_fn(3, 4, |i, j| match j {
            0 => 1.0,
            1 => 2.0, // dependent on column 0
            2 => 0.0, // zero
            _ => (i as f64) - 1.0,
        });
        let o = m_orthonormalize(x.as_ref(), &m, 1e-10);
        assert_eq!(o.kept, vec![0, 3]);
        let g = o.vectors.transpose() * (&m * &o.vectors);
        assert!((g[(0, 0)] - 1.0).abs() < 1e-14 && g[(0, 1)].abs() < 1e-14);
    }
}
