//! Sparse helpers: assembly from triplets, sub-matrices by index lists,
//! sparse-times-dense products, and conversion to dense for small problems.

use crate::{LinalgError, SparseMat};
pub use faer::sparse::Triplet;
use faer::{Mat, MatRef};

/// Builds an `nrows x ncols` sparse matrix, summing duplicate entries.
pub fn from_triplets(
    nrows: usize,
    ncols: usize,
    triplets: &[Triplet<usize, usize, f64>],
) -> Result<SparseMat, LinalgError> {
    SparseMat::try_new_from_triplets(nrows, ncols, triplets)
        .map_err(|e| LinalgError::Faer(format!("{e:?}")))
}

/// The sub-matrix `a[rows, cols]` (rows and cols are lists of indices of `a`).
pub fn submatrix(a: &SparseMat, rows: &[usize], cols: &[usize]) -> SparseMat {
    let mut row_map = vec![usize::MAX; a.nrows()];
    for (new, &old) in rows.iter().enumerate() {
        row_map[old] = new;
    }
    let mut triplets = Vec::new();
    for (new_col, &old_col) in cols.iter().enumerate() {
        let col = a.as_ref();
        for (i, v) in col
            .row_idx_of_col(old_col)
            .zip(col.val_of_col(old_col).iter())
        {
            let r = row_map[i];
            if r != usize::MAX {
                triplets.push(Triplet::new(r, new_col, *v));
            }
        }
    }
    // Indices are in range by construction.
    SparseMat::try_new_from_triplets(rows.len(), cols.len(), &triplets)
        .expect("submatrix indices are in range")
}

/// `a * b` for sparse `a` and dense `b`.
pub fn mul(a: &SparseMat, b: MatRef<'_, f64>) -> Mat<f64> {
    a * b
}

/// `b^T a b` for sparse symmetric `a` and dense `b`, symmetrised exactly.
pub fn project(a: &SparseMat, b: MatRef<'_, f64>) -> Mat<f64> {
    let ab = a * b;
    let mut p = b.transpose() * &ab;
    symmetrize(&mut p);
    p
}

/// Replaces `p` by `(p + p^T) / 2` in place.
pub fn symmetrize(p: &mut Mat<f64>) {
    let n = p.nrows();
    for j in 0..n {
        for i in 0..j {
            let v = 0.5 * (p[(i, j)] + p[(j, i)]);
            p[(i, j)] = v;
            p[(j, i)] = v;
        }
    }
}

/// Dense copy of a sparse matrix (for small problems only).
pub fn to_dense(a: &SparseMat) -> Mat<f64> {
    a.to_dense()
}

/// Largest absolute diagonal entry.
pub fn max_abs_diagonal(a: &SparseMat) -> f64 {
    diagonal(a).iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// The diagonal of a square sparse matrix.
pub fn diagonal(a: &SparseMat) -> Vec<f64> {
    let r = a.as_ref();
    (0..a.ncols())
        .map(|j| {
            r.row_idx_of_col(j)
                .zip(r.val_of_col(j).iter())
                .filter(|(i, _)| *i == j)
                .map(|(_, v)| *v)
                .sum()
        })
        .collect()
}

/// `a + s * b` for sparse matrices of equal shape.
pub fn add_scaled(a: &SparseMat, s: f64, b: &SparseMat) -> Result<SparseMat, LinalgError> {
    if a.nrows() != b.nrows() || a.ncols() != b.ncols() {
        return Err(LinalgError::Dimension(format!(
            "{}x{} + {}x{}",
            a.nrows(),
            a.ncols(),
            b.nrows(),
            b.ncols()
        )));
    }
    let mut t = triplets_of(a, 1.0);
    t.extend(triplets_of(b, s));
    from_triplets(a.nrows(), a.ncols(), &t)
}

/// The entries of `a`, scaled by `s`, as triplets.
pub fn triplets_of(a: &SparseMat, s: f64) -> Vec<Triplet<usize, usize, f64>> {
    let r = a.as_ref();
    let mut t = Vec::with_capacity(r.compute_nnz());
    for j in 0..a.ncols() {
        for (i, v) in r.row_idx_of_col(j).zip(r.val_of_col(j).iter()) {
            t.push(Triplet::new(i, j, s * v));
        }
    }
    t
}

/// Largest absolute entry of a dense matrix (0 for an empty one).
pub fn max_abs(a: MatRef<'_, f64>) -> f64 {
    let mut m = 0.0_f64;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            m = m.max(a[(i, j)].abs());
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> SparseMat {
        from_triplets(
            3,
            3,
            &[
                Triplet::new(0, 0, 4.0),
                Triplet::new(1, 1, 5.0),
                Triplet::new(2, 2, 6.0),
                Triplet::new(0, 1, 1.0),
                Triplet::new(1, 0, 1.0),
                Triplet::new(0, 0, 1.0),
            ],
        )
        .unwrap()
    }

    #[test]
    fn duplicates_are_summed_and_submatrix_picks_entries() {
        let a = sample();
        assert_eq!(diagonal(&a), vec![5.0, 5.0, 6.0]);
        let s = submatrix(&a, &[1, 0], &[0]);
        let d = s.to_dense();
        assert_eq!((d[(0, 0)], d[(1, 0)]), (1.0, 5.0));
    }

    #[test]
    fn projection_is_symmetric() {
        let a = sample();
        let b = Mat::from_fn(3, 2, |i, j| (i + 2 * j) as f64 + 0.5);
        let p = project(&a, b.as_ref());
        assert_eq!(p[(0, 1)], p[(1, 0)]);
        let dense = b.transpose() * a.to_dense() * &b;
        assert!((p[(0, 1)] - dense[(0, 1)]).abs() < 1e-12);
    }
}
