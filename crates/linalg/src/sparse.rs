//! Sparse helpers: assembly from triplets, sub-matrices by index lists,
//! sparse-times-dense products, and conversion to dense for small problems.

use crate::lower::{packed, LANE};
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

/// The sub-matrix `a[rows, cols]` (rows and cols are lists of indices of
/// `a`), built column by column without a triplet list; the rows of each
/// column stay sorted when `rows` is ascending (a complement of DOFs).
pub fn submatrix(a: &SparseMat, rows: &[usize], cols: &[usize]) -> SparseMat {
    let mut row_map = vec![usize::MAX; a.nrows()];
    for (new, &old) in rows.iter().enumerate() {
        row_map[old] = new;
    }
    let r = a.as_ref();
    let mut col_ptr = Vec::with_capacity(cols.len() + 1);
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    col_ptr.push(0);
    let mut entries: Vec<(usize, f64)> = Vec::new();
    for &old_col in cols {
        entries.clear();
        entries.extend(
            r.row_idx_of_col(old_col)
                .zip(r.val_of_col(old_col))
                .filter(|(i, _)| row_map[*i] != usize::MAX)
                .map(|(i, v)| (row_map[i], *v)),
        );
        if !entries.windows(2).all(|w| w[0].0 < w[1].0) {
            entries.sort_by_key(|e| e.0);
            entries.dedup_by(|later, first| {
                let same = later.0 == first.0;
                if same {
                    first.1 += later.1;
                }
                same
            });
        }
        row_idx.extend(entries.iter().map(|e| e.0));
        values.extend(entries.iter().map(|e| e.1));
        col_ptr.push(row_idx.len());
    }
    let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(
        rows.len(),
        cols.len(),
        col_ptr,
        None,
        row_idx,
    );
    SparseMat::new(symbolic, values)
}

/// `a * b` for sparse `a` and dense `b`.
pub fn mul(a: &SparseMat, b: MatRef<'_, f64>) -> Mat<f64> {
    a * b
}

/// `a * b` for sparse *symmetric* `a` (both triangles stored) and dense `b`,
/// in parallel over the rows of the product: row `j` of `a b` is column `j`
/// of `a` dotted with `b`, so every thread reads `a` column by column and
/// writes its own rows. faer's generic product runs on one thread; this one
/// is what the reductions' `K Psi` and the residuals use (the eigen solver
/// multiplies with its compact copy, `LowerPattern::mul`).
pub fn symmetric_mul(a: &SparseMat, b: MatRef<'_, f64>) -> Mat<f64> {
    use rayon::prelude::*;
    assert_eq!(a.ncols(), b.nrows(), "symmetric_mul: dimensions");
    let (n, k) = (a.nrows(), b.ncols());
    if n == 0 || k == 0 {
        return Mat::zeros(n, k);
    }
    let mut out = Mat::<f64>::with_capacity(n, k);
    // SAFETY: f64 has no invalid values, and every entry of the n x k
    // matrix is written below (each group of columns, every row).
    unsafe { out.set_dims(n, k) };
    let (col_ptr, row_idx, values) = (a.col_ptr(), a.row_idx(), a.val());
    // Right-hand sides in groups of LANE, each copied row-major so that the
    // LANE values of one row are adjacent: one pass over a column of `a`
    // per group, with the sums in registers.
    let rows_per_task = (n / (8 * rayon::current_num_threads())).clamp(256, 16384);
    for c0 in (0..k).step_by(LANE) {
        let g = LANE.min(k - c0);
        let packed = &packed(b, c0);
        out.as_mut()
            .par_row_chunks_mut(rows_per_task)
            .enumerate()
            .for_each(|(chunk, mut block)| {
                let first = chunk * rows_per_task;
                for r in 0..block.nrows() {
                    let range = col_ptr[first + r]..col_ptr[first + r + 1];
                    let mut acc = [0.0_f64; LANE];
                    for (&i, &v) in row_idx[range.clone()].iter().zip(&values[range]) {
                        let row = &packed[i].0;
                        for (a, x) in acc.iter_mut().zip(row) {
                            *a += v * x;
                        }
                    }
                    for (q, a) in acc.iter().take(g).enumerate() {
                        block[(r, c0 + q)] = *a;
                    }
                }
            });
    }
    out
}

/// `b^T a b` for sparse symmetric `a` and dense `b`, symmetrised exactly.
pub fn project(a: &SparseMat, b: MatRef<'_, f64>) -> Mat<f64> {
    project_product(b, symmetric_mul(a, b))
}

/// `b^T (a b)` from the product `ab = a b` of a symmetric `a`,
/// symmetrised exactly.
pub fn project_product(b: MatRef<'_, f64>, ab: Mat<f64>) -> Mat<f64> {
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
    fn symmetric_product_equals_the_general_one() {
        // A 300 x 300 symmetric band with 11 right-hand sides (a full group
        // of 8 and a partial one), and a strided right-hand side.
        let n = 300;
        let mut t = Vec::new();
        for i in 0..n {
            for d in 0..4 {
                if i + d < n {
                    let v = 1.0 / (1 + i + 3 * d) as f64;
                    t.push(Triplet::new(i + d, i, v));
                    if d > 0 {
                        t.push(Triplet::new(i, i + d, v));
                    }
                }
            }
        }
        let a = from_triplets(n, n, &t).unwrap();
        let b = Mat::from_fn(n, 11, |i, j| ((i * 7 + j * 13) % 17) as f64 - 8.0);
        let want = &a * &b;
        let got = symmetric_mul(&a, b.as_ref());
        assert!(max_abs((&got - &want).as_ref()) <= 1e-14 * max_abs(want.as_ref()));
        let strided = b.transpose().to_owned();
        let got = symmetric_mul(&a, strided.transpose());
        assert!(max_abs((&got - &want).as_ref()) <= 1e-14 * max_abs(want.as_ref()));
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
