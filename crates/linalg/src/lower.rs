//! Symmetric sparse matrices stored by their lower triangle on one shared
//! pattern: the compact copy of `K` and `M` that the shift-invert solver
//! keeps. Half the entries of full storage, and one index array for both
//! matrices: at 3e5 DOFs (C3D8) 0.17 GB against 0.52 GB for `K` and `M` in
//! full, so the caller can drop the full matrices while the factor and the
//! Lanczos basis are alive.

use crate::SparseMat;
use faer::sparse::SymbolicSparseColMatRef;
use faer::{Mat, MatRef};
use rayon::prelude::*;

/// A lower-triangular pattern (rows sorted, the diagonal first in every
/// column, always present) for the values of one or more symmetric
/// matrices.
#[derive(Clone, Debug)]
pub struct LowerPattern {
    col_ptr: Vec<usize>,
    /// Row indices in 32 bits: half the index traffic of the products;
    /// [`Self::with_symbolic`] widens them for faer.
    row_idx: Vec<u32>,
}

/// Columns per parallel task when filling values.
const FILL_CHUNK: usize = 4096;

impl LowerPattern {
    /// The lower triangles of the symmetric `k` and `m` on their union
    /// pattern, with the values of each. When both have one pattern with
    /// sorted columns that hold their diagonal (as assembly gives them),
    /// that is a copy of the lower parts; otherwise the union is built and
    /// each matrix merged onto it.
    pub fn of_pair(k: &SparseMat, m: &SparseMat) -> (Self, Vec<f64>, Vec<f64>) {
        Self::of_pair_sharing(k, m, Self::share_pattern(k, m))
    }

    /// Whether `k` and `m` store one pattern (compressed columns, the same
    /// rows), as assembly gives them.
    pub(crate) fn share_pattern(k: &SparseMat, m: &SparseMat) -> bool {
        k.col_nnz().is_none()
            && m.col_nnz().is_none()
            && k.col_ptr() == m.col_ptr()
            && k.row_idx() == m.row_idx()
    }

    /// [`Self::of_pair`] with [`Self::share_pattern`] already known.
    pub(crate) fn of_pair_sharing(
        k: &SparseMat,
        m: &SparseMat,
        shared: bool,
    ) -> (Self, Vec<f64>, Vec<f64>) {
        if let Some(copy) = shared.then(|| Self::of_shared(k, m)).flatten() {
            return copy;
        }
        let pattern = Self::union(&[k, m]);
        let (kv, mv) = (pattern.values_of(k), pattern.values_of(m));
        (pattern, kv, mv)
    }

    /// [`Self::of_pair`] for one shared pattern (`k` and `m` must
    /// [share](Self::share_pattern) it) of sorted columns with their
    /// diagonals; `None` otherwise.
    fn of_shared(k: &SparseMat, m: &SparseMat) -> Option<(Self, Vec<f64>, Vec<f64>)> {
        let all: Vec<usize> = (0..k.ncols()).collect();
        Self::of_shared_within(k, m, &all)
    }

    /// [`Self::of_pair`] of the submatrices of `k` and `m` on the equations
    /// `keep` (ascending; renumbered `0..keep.len()`): the pencil of a body
    /// held at the other equations, without the submatrices in full
    /// storage (0.8 GB at 3e5 DOFs, written by one thread) as a step
    /// between.
    pub fn of_pair_within(
        k: &SparseMat,
        m: &SparseMat,
        keep: &[usize],
    ) -> (Self, Vec<f64>, Vec<f64>) {
        let ascending = keep.windows(2).all(|w| w[0] < w[1]);
        let fast = (ascending && Self::share_pattern(k, m))
            .then(|| Self::of_shared_within(k, m, keep))
            .flatten();
        fast.unwrap_or_else(|| {
            let sub = |a| crate::sparse::submatrix(a, keep, keep);
            Self::of_pair(&sub(k), &sub(m))
        })
    }

    /// [`Self::of_pair_within`] for one shared pattern of sorted columns
    /// with their diagonals and ascending `keep`; `None` otherwise. Counted
    /// first, then filled by chunks of columns in parallel, each into its
    /// own part of the three arrays.
    fn of_shared_within(
        k: &SparseMat,
        m: &SparseMat,
        keep: &[usize],
    ) -> Option<(Self, Vec<f64>, Vec<f64>)> {
        let (cp, ri) = (k.col_ptr(), k.row_idx());
        let mut new_of = vec![u32::MAX; k.ncols()];
        for (new, &old) in keep.iter().enumerate() {
            new_of[old] = u32::try_from(new).ok()?;
        }
        let new_of = &new_of;
        // Each kept column's lower part (from its diagonal) and the number
        // of kept rows in it.
        let lower: Vec<Option<(usize, usize)>> = keep
            .par_iter()
            .map(|&j| {
                let rows = &ri[cp[j]..cp[j + 1]];
                let sorted = rows.windows(2).all(|w| w[0] < w[1]);
                let d = rows.partition_point(|&i| i < j);
                let kept = rows[d..].iter().filter(|&&i| new_of[i] != u32::MAX).count();
                (sorted && rows.get(d) == Some(&j)).then_some((cp[j] + d, kept))
            })
            .collect();
        let lower: Vec<(usize, usize)> = lower.into_iter().collect::<Option<_>>()?;
        let mut col_ptr = Vec::with_capacity(keep.len() + 1);
        col_ptr.push(0);
        for (c, &(_, kept)) in lower.iter().enumerate() {
            col_ptr.push(col_ptr[c] + kept);
        }
        let len = col_ptr[keep.len()];
        let (mut row_idx, mut kv, mut mv) = (vec![0u32; len], vec![0.0; len], vec![0.0; len]);
        // Chunks of FILL_CHUNK columns, each writing its own range.
        let mut chunks = Vec::new();
        let (mut r, mut kr, mut mr) = (&mut row_idx[..], &mut kv[..], &mut mv[..]);
        for c0 in (0..keep.len()).step_by(FILL_CHUNK) {
            let c1 = (c0 + FILL_CHUNK).min(keep.len());
            let size = col_ptr[c1] - col_ptr[c0];
            let (a, rest_r) = std::mem::take(&mut r).split_at_mut(size);
            let (b, rest_k) = std::mem::take(&mut kr).split_at_mut(size);
            let (d, rest_m) = std::mem::take(&mut mr).split_at_mut(size);
            chunks.push((c0..c1, a, b, d));
            (r, kr, mr) = (rest_r, rest_k, rest_m);
        }
        chunks
            .into_par_iter()
            .for_each(|(cols, rows, kvals, mvals)| {
                let mut q = 0;
                for c in cols {
                    for p in lower[c].0..cp[keep[c] + 1] {
                        let i = new_of[ri[p]];
                        if i != u32::MAX {
                            rows[q] = i;
                            kvals[q] = k.val()[p];
                            mvals[q] = m.val()[p];
                            q += 1;
                        }
                    }
                }
            });
        Some((Self { col_ptr, row_idx }, kv, mv))
    }

    /// The union of the lower triangles of the square matrices `of` (all of
    /// one size), with every diagonal entry.
    pub fn union(of: &[&SparseMat]) -> Self {
        let n = of.first().map_or(0, |a| a.ncols());
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(of.first().map_or(0, |a| a.compute_nnz() / 2 + n));
        col_ptr.push(0);
        let mut rows = Vec::new();
        for j in 0..n {
            rows.clear();
            for a in of {
                rows.extend(a.row_idx_of_col(j).filter(|&i| i >= j));
            }
            rows.push(j);
            rows.sort_unstable();
            rows.dedup();
            row_idx.extend(rows.iter().map(|&i| i as u32));
            col_ptr.push(row_idx.len());
        }
        Self { col_ptr, row_idx }
    }

    /// Number of rows and columns.
    pub fn dim(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Stored entries (lower triangle with the diagonal).
    pub fn len(&self) -> usize {
        self.row_idx.len()
    }

    /// Calls `f` with the pattern for faer (row indices widened to
    /// `usize` in a temporary, for an analysis or a factorisation).
    pub fn with_symbolic<R>(&self, f: impl FnOnce(SymbolicSparseColMatRef<'_, usize>) -> R) -> R {
        let wide: Vec<usize> = self.row_idx.par_iter().map(|&i| i as usize).collect();
        f(SymbolicSparseColMatRef::new_checked(
            self.dim(),
            self.dim(),
            &self.col_ptr,
            None,
            &wide,
        ))
    }

    /// The rows of column `j`, ascending, its diagonal first.
    pub fn rows_of(&self, j: usize) -> &[u32] {
        &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]]
    }

    /// The rows of all columns, one after another.
    pub fn row_idx(&self) -> &[u32] {
        &self.row_idx
    }

    /// Start of each column's entries (`dim + 1` offsets).
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// The pattern of the entries of `values` that are not zero (and every
    /// diagonal entry), with those values: the mass matrix of solid elements
    /// couples no two directions, so on the pattern it shares with the
    /// stiffness two thirds of its entries are zeros that a product would
    /// read for nothing.
    pub fn without_zeros(&self, values: &[f64]) -> (Self, Vec<f64>) {
        let n = self.dim();
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let (mut row_idx, mut kept) = (Vec::new(), Vec::new());
        for j in 0..n {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            for (q, (&i, &v)) in self.row_idx[range.clone()]
                .iter()
                .zip(&values[range.clone()])
                .enumerate()
            {
                if q == 0 || v != 0.0 {
                    row_idx.push(i);
                    kept.push(v);
                }
            }
            col_ptr.push(row_idx.len());
        }
        (Self { col_ptr, row_idx }, kept)
    }

    /// `a += s B` for `a` on this pattern and `B` (`b` on `sub`, a pattern
    /// whose columns are subsets of this one's), columns in parallel. Only
    /// the tests add patterns: the factorisation forms `K - sigma M` entry
    /// by entry as it gathers a supernode.
    #[cfg(test)]
    pub fn add_scaled(&self, a: &mut [f64], s: f64, sub: &LowerPattern, b: &[f64]) {
        assert_eq!(
            sub.dim(),
            self.dim(),
            "LowerPattern::add_scaled: dimensions"
        );
        self.by_column_chunks(0..self.dim(), a, &|j, rows, a| {
            let mut p = 0;
            let sub_range = sub.col_ptr[j]..sub.col_ptr[j + 1];
            for (&i, &v) in sub.row_idx[sub_range.clone()].iter().zip(&b[sub_range]) {
                while rows[p] != i {
                    p += 1;
                }
                a[p] += s * v;
            }
        });
    }

    /// Calls `f(j, rows, values)` for every column `j` in `cols` with its
    /// rows and its part of `values` (an array over the pattern's entries
    /// from column `cols.start` on), chunks of columns in parallel.
    fn by_column_chunks(
        &self,
        cols: std::ops::Range<usize>,
        values: &mut [f64],
        f: &(impl Fn(usize, &[u32], &mut [f64]) + Sync),
    ) {
        if cols.len() > FILL_CHUNK {
            let mid = cols.start + cols.len() / 2;
            let (left, right) = values.split_at_mut(self.col_ptr[mid] - self.col_ptr[cols.start]);
            rayon::join(
                || self.by_column_chunks(cols.start..mid, left, f),
                || self.by_column_chunks(mid..cols.end, right, f),
            );
            return;
        }
        let base = self.col_ptr[cols.start];
        for j in cols {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            f(
                j,
                &self.row_idx[range.clone()],
                &mut values[range.start - base..range.end - base],
            );
        }
    }

    /// The values of the lower triangle of `a` (a matrix whose lower
    /// triangle lies in this pattern) on the pattern, columns in parallel.
    pub fn values_of(&self, a: &SparseMat) -> Vec<f64> {
        let mut out = vec![0.0; self.len()];
        self.by_column_chunks(0..self.dim(), &mut out, &|j, col, out| {
            // Sorted columns in the usual case: a merge walk, with a binary
            // search for an unsorted input.
            let mut p = 0;
            for (i, v) in a.row_idx_of_col(j).zip(a.val_of_col(j)) {
                if i < j {
                    continue;
                }
                while p < col.len() && (col[p] as usize) < i {
                    p += 1;
                }
                if p < col.len() && col[p] as usize == i {
                    out[p] += v;
                } else if let Ok(q) = col.binary_search(&(i as u32)) {
                    out[q] += v;
                    p = 0;
                }
            }
        });
        out
    }

    /// The diagonal of the matrix with `values` on this pattern.
    pub fn diagonal(&self, values: &[f64]) -> Vec<f64> {
        self.col_ptr[..self.dim()]
            .iter()
            .map(|&p| values[p])
            .collect()
    }

    /// `A B` for the symmetric `A` with `values` on this pattern and dense
    /// `B`. Each thread takes a contiguous range of columns of equal work
    /// and owns the same range of rows of the product: column `j` adds
    /// `a_jj b_j + sum a_ij b_i` to row `j` and mirrors `a_ij b_j` into
    /// the rows `i > j` below it. Mirrored entries beyond the thread's own
    /// rows (few in a banded matrix, such as an FE mesh numbered along its
    /// length) go to a private overflow buffer that is added at the end.
    /// The right-hand sides go in groups of eight, row-major, so that one
    /// row's values are adjacent.
    pub fn mul(&self, values: &[f64], b: MatRef<'_, f64>) -> Mat<f64> {
        let (n, k) = (self.dim(), b.ncols());
        assert_eq!(b.nrows(), n, "LowerPattern::mul: dimensions");
        if n == 0 || k == 0 {
            return Mat::zeros(n, k);
        }
        // Column (and row) ranges of equal entry counts.
        let tasks = rayon::current_num_threads().clamp(1, 64);
        let total = self.len();
        let mut bounds = vec![0usize];
        for t in 1..tasks {
            let j = self.col_ptr.partition_point(|&p| p < total * t / tasks);
            bounds.push(j.clamp(bounds[t - 1], n));
        }
        bounds.push(n);
        // The last row each range reaches: its overflow ends there.
        let reach: Vec<usize> = (0..tasks)
            .map(|t| {
                (bounds[t]..bounds[t + 1])
                    .map(|j| self.row_idx[self.col_ptr[j + 1] - 1] as usize)
                    .max()
                    .map_or(bounds[t + 1], |r| (r + 1).max(bounds[t + 1]))
            })
            .collect();
        let rows_per_chunk = 4096;
        // Every entry of `out` is written below, group by group.
        let mut out = Mat::<f64>::with_capacity(n, k);
        // SAFETY: f64 has no invalid values, and each (row, column) of the
        // n x k matrix is written by the last loop before `out` is read.
        unsafe { out.set_dims(n, k) };
        for c0 in (0..k).step_by(LANE) {
            let g = LANE.min(k - c0);
            let x = packed(b, c0);
            let x = &x;
            // Each task's rows and overflow, zeroed by the task itself.
            let parts: Vec<(Vec<Lane>, Vec<Lane>)> = (0..tasks)
                .into_par_iter()
                .map(|t| {
                    let mut own = vec![Lane::ZERO; bounds[t + 1] - bounds[t]];
                    let mut over = vec![Lane::ZERO; reach[t] - bounds[t + 1]];
                    let part = Part {
                        pattern: self,
                        values,
                        x,
                        first: bounds[t],
                        end: bounds[t + 1],
                    };
                    part.run(&mut own, &mut over);
                    (own, over)
                })
                .collect();
            let (parts, bounds) = (&parts, &bounds);
            out.as_mut()
                .par_row_chunks_mut(rows_per_chunk)
                .enumerate()
                .for_each(|(chunk, mut block)| {
                    let first = chunk * rows_per_chunk;
                    // The task that owns the chunk's first row.
                    let mut t = bounds.partition_point(|&b| b <= first).saturating_sub(1);
                    for r in 0..block.nrows() {
                        let i = first + r;
                        while i >= bounds[t + 1] {
                            t += 1;
                        }
                        let mut row = parts[t].0[i - bounds[t]].0;
                        for (u, (_, over)) in parts.iter().enumerate() {
                            let start = bounds[u + 1];
                            if i >= start && i - start < over.len() {
                                for (v, o) in row.iter_mut().zip(&over[i - start].0) {
                                    *v += o;
                                }
                            }
                        }
                        for q in 0..g {
                            block[(r, c0 + q)] = row[q];
                        }
                    }
                });
        }
        out
    }
}

/// The columns `first..end` of one thread in [`LowerPattern::mul`].
struct Part<'a> {
    pattern: &'a LowerPattern,
    values: &'a [f64],
    x: &'a [Lane],
    first: usize,
    end: usize,
}

impl Part<'_> {
    /// Adds the columns' products to `own` (rows `first..end`) and `over`
    /// (rows from `end` on), with fused multiply-adds where the CPU has
    /// them (the kernel compiled twice, chosen at run time: the release
    /// build targets the x86-64 baseline).
    fn run(&self, own: &mut [Lane], over: &mut [Lane]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU has both features, checked above.
            unsafe { self.run_avx2(own, over) };
            return;
        }
        self.kernel::<false>(own, over);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn run_avx2(&self, own: &mut [Lane], over: &mut [Lane]) {
        self.kernel::<true>(own, over);
    }

    #[inline(always)]
    fn kernel<const FMA: bool>(&self, own: &mut [Lane], over: &mut [Lane]) {
        let madd = |a: f64, b: f64, c: f64| if FMA { a.mul_add(b, c) } else { a * b + c };
        let (col_ptr, row_idx) = (&self.pattern.col_ptr, &self.pattern.row_idx);
        let (first, end, x, values) = (self.first, self.end, self.x, self.values);
        for j in first..end {
            let range = col_ptr[j]..col_ptr[j + 1];
            let xj = x[j].0;
            let diag = values[range.start];
            let mut acc: [f64; LANE] = std::array::from_fn(|q| diag * xj[q]);
            let rows = &row_idx[range.start + 1..range.end];
            for (&i, &v) in rows.iter().zip(&values[range.start + 1..range.end]) {
                let i = i as usize;
                let xi = &x[i].0;
                let yi = if i < end {
                    &mut own[i - first].0
                } else {
                    &mut over[i - end].0
                };
                for q in 0..LANE {
                    acc[q] = madd(v, xi[q], acc[q]);
                    yi[q] = madd(v, xj[q], yi[q]);
                }
            }
            let yj = &mut own[j - first].0;
            for q in 0..LANE {
                yj[q] += acc[q];
            }
        }
    }
}

/// Right-hand sides per pass of the sparse products ([`LowerPattern::mul`],
/// [`crate::sparse::symmetric_mul`]).
pub(crate) const LANE: usize = 8;

/// One row of a group of right-hand sides: a cache line.
#[derive(Copy, Clone)]
#[repr(C, align(64))]
pub(crate) struct Lane(pub(crate) [f64; LANE]);

impl Lane {
    pub(crate) const ZERO: Lane = Lane([0.0; LANE]);
}

/// The columns `c0..c0 + LANE` of `b` (zeros past its last column)
/// row-major, one [`Lane`] per row, built in parallel.
pub(crate) fn packed(b: MatRef<'_, f64>, c0: usize) -> Vec<Lane> {
    let g = LANE.min(b.ncols() - c0);
    (0..b.nrows())
        .into_par_iter()
        .with_min_len(4096)
        .map(|i| {
            Lane(std::array::from_fn(|q| {
                if q < g {
                    b[(i, c0 + q)]
                } else {
                    0.0
                }
            }))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sparse::{from_triplets, symmetric_mul, Triplet};

    /// A symmetric matrix with a pattern unlike its partner's.
    fn sample(n: usize, seed: usize) -> SparseMat {
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 4.0 + (i % 3) as f64));
            for d in [1, 7 + seed, 31] {
                if i + d < n && !(i * (seed + 3)).is_multiple_of(5) {
                    let v = -(((i + d + seed) % 11) as f64) / 10.0 - 0.05;
                    t.push(Triplet::new(i, i + d, v));
                    t.push(Triplet::new(i + d, i, v));
                }
            }
        }
        from_triplets(n, n, &t).unwrap()
    }

    /// One pattern for both (as assembly gives them) takes the copy of the
    /// lower parts; the result equals the general union and merge.
    #[test]
    fn a_shared_pattern_gives_the_union_and_its_values() {
        let k = sample(5000, 1);
        let values: Vec<f64> = k.val().iter().map(|v| v.abs() + 0.5).collect();
        let m = SparseMat::new(k.symbolic().to_owned().unwrap(), values);
        let (pattern, kv, mv) = LowerPattern::of_pair(&k, &m);
        let union = LowerPattern::union(&[&k, &m]);
        assert_eq!(pattern.col_ptr, union.col_ptr);
        assert_eq!(pattern.row_idx, union.row_idx);
        assert_eq!(kv, union.values_of(&k));
        assert_eq!(mv, union.values_of(&m));
        assert!(LowerPattern::share_pattern(&k, &m));
        assert!(LowerPattern::of_shared(&k, &m).is_some());
        assert!(!LowerPattern::share_pattern(&k, &sample(5000, 2)));
    }

    /// The pencil of a held body comes straight from the full matrices and
    /// equals the one of the submatrices, for a shared pattern (parallel
    /// chunks) and for two patterns (the fallback through the submatrices).
    #[test]
    fn the_pencil_within_kept_equations_equals_the_submatrices_pencil() {
        let n = 5000;
        let k = sample(n, 1);
        let shared = SparseMat::new(
            k.symbolic().to_owned().unwrap(),
            k.val().iter().map(|v| v.abs() + 0.5).collect(),
        );
        let held: Vec<usize> = vec![0, 17, 18, 19, 2500, 4999];
        let keep: Vec<usize> = (0..n).filter(|i| !held.contains(i)).collect();
        for m in [shared, sample(n, 2)] {
            let sub = |a: &SparseMat| crate::sparse::submatrix(a, &keep, &keep);
            let (want, want_k, want_m) = LowerPattern::of_pair(&sub(&k), &sub(&m));
            let (got, got_k, got_m) = LowerPattern::of_pair_within(&k, &m, &keep);
            assert_eq!(got.col_ptr, want.col_ptr);
            assert_eq!(got.row_idx, want.row_idx);
            assert_eq!((got_k, got_m), (want_k, want_m));
        }
        assert!(LowerPattern::of_shared_within(&k, &k, &keep).is_some());
    }

    /// Dropping the zeros keeps every diagonal entry, and a matrix added
    /// back from its own pattern gives the values on the union.
    #[test]
    fn a_pattern_without_zeros_keeps_products_and_adds_back_onto_the_union() {
        let n = 3000;
        let (k, m) = (sample(n, 0), sample(n, 2));
        let pattern = LowerPattern::union(&[&k, &m]);
        let (kv, mv) = (pattern.values_of(&k), pattern.values_of(&m));
        let (compact, cv) = pattern.without_zeros(&mv);
        assert!(compact.len() < pattern.len());
        assert_eq!(compact.len(), (m.compute_nnz() + n) / 2);
        assert_eq!(compact.diagonal(&cv), pattern.diagonal(&mv));
        let b = Mat::from_fn(n, 9, |i, j| ((i * 5 + j * 3) % 13) as f64 - 6.0);
        let got = compact.mul(&cv, b.as_ref());
        assert!(crate::sparse::max_abs((got - pattern.mul(&mv, b.as_ref())).as_ref()) < 1e-12);
        let mut shifted = kv.clone();
        pattern.add_scaled(&mut shifted, -2.5, &compact, &cv);
        let want: Vec<f64> = kv.iter().zip(&mv).map(|(k, m)| k - 2.5 * m).collect();
        assert_eq!(shifted, want);
    }

    #[test]
    fn products_on_the_union_pattern_equal_the_full_ones() {
        let n = 20000;
        let (k, m) = (sample(n, 0), sample(n, 2));
        let pattern = LowerPattern::union(&[&k, &m]);
        assert!(pattern.len() < k.compute_nnz() + m.compute_nnz());
        let b = Mat::from_fn(n, 11, |i, j| ((i * 7 + j * 13) % 17) as f64 - 8.0);
        for a in [&k, &m] {
            let values = pattern.values_of(a);
            let got = pattern.mul(&values, b.as_ref());
            let want = symmetric_mul(a, b.as_ref());
            assert!(crate::sparse::max_abs((got - &want).as_ref()) < 1e-12);
            assert_eq!(pattern.diagonal(&values), crate::sparse::diagonal(a));
        }
    }
}
