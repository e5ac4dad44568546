//! The numeric supernodal `LDL^T` factorisation, in parallel over the
//! elimination tree, into faer's value layout.
//!
//! faer's numeric factorisation visits the supernodes one after another and
//! parallelises only inside each dense kernel, where most supernodes of a
//! large mesh are small. This one is the
//! same left-looking algorithm: a supernode gathers the updates
//! `L_ds D_d L_ds^T` of every descendant `d` whose pattern meets its
//! columns, then factorises its diagonal block densely and scales the block
//! below it. A supernode reads only its descendants and writes only its own
//! block, so the disjoint subtrees of a [`SolvePlan`] (contiguous ranges of
//! supernodes and of values) are factorised on separate threads; the
//! supernodes above them (the top: the large separators) follow
//! with faer's parallel dense kernels, siblings there in parallel too. The
//! result does not depend on the schedule (each supernode sums its updates
//! in the same order) and equals faer's to round-off. A descendant's update
//! on the supernode's own columns is needed only below the diagonal: that
//! square is computed as a lower triangle, half the products of a full one.
//!
//! Memory beyond `L`: the permuted lower triangle of `A` and, per thread,
//! the buffers of one update. The large separators of a solid's factor get
//! updates of thousands of rows and columns; they go by panels of columns
//! ([`Panels`]), so that a thread's buffer stays bounded whatever the
//! separator's size.

use crate::ldlt::symbolic::Supernodes;
use crate::ldlt::symbolic::{SolvePlan, UpdatePlan};
use crate::lower::LowerPattern;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::{cholesky_in_place, LdltError, LdltRegularization};
use faer::linalg::matmul::matmul;
use faer::sparse::SparseColMatRef;
use faer::{Accum, MatMut, MatRef, Par};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering as AtomicOrdering};

/// The lower triangle (original order) that a factorisation reads: faer's
/// matrix, or the shift-invert pencil's `K - sigma M` on its
/// [`LowerPattern`], read without a copy.
pub(crate) enum Input<'a> {
    Faer(SparseColMatRef<'a, usize, f64>),
    /// `K - sigma M` of a shift-invert pencil, formed entry by entry where
    /// it is read (no array of its values): `k` on `pattern`, `m` on `mass`
    /// (a pattern whose columns are subsets of `pattern`'s, both with sorted
    /// rows), the rows and columns of `fixed` equations decoupled (their
    /// diagonal kept, 1 where it is 0).
    Shifted {
        pattern: &'a LowerPattern,
        k: &'a [f64],
        mass: &'a LowerPattern,
        m: &'a [f64],
        sigma: f64,
        fixed: Option<&'a [bool]>,
    },
}

impl Input<'_> {
    pub(crate) fn ncols(&self) -> usize {
        match self {
            Input::Faer(a) => a.ncols(),
            Input::Shifted { pattern, .. } => pattern.dim(),
        }
    }

    pub(crate) fn col_ptr(&self) -> &[usize] {
        match self {
            Input::Faer(a) => a.symbolic().col_ptr(),
            Input::Shifted { pattern, .. } => pattern.col_ptr(),
        }
    }

    /// Calls `f(row)` for the entries of column `j` on or below the
    /// diagonal (their values not formed).
    #[inline]
    fn lower_rows_of(&self, j: usize, mut f: impl FnMut(usize)) {
        let rows = match self {
            Input::Faer(a) => {
                a.row_idx_of_col_raw(j)
                    .iter()
                    .filter(|&&i| i >= j)
                    .for_each(|&i| f(i));
                return;
            }
            Input::Shifted { pattern, .. } => pattern.rows_of(j),
        };
        rows.iter()
            .map(|&i| i as usize)
            .filter(|&i| i >= j)
            .for_each(f);
    }

    /// Calls `f(row, value)` for the entries of column `j` on or below the
    /// diagonal.
    #[inline]
    pub(crate) fn lower_of(&self, j: usize, mut f: impl FnMut(usize, f64)) {
        match self {
            Input::Faer(a) => {
                for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                    if i >= j {
                        f(i, v);
                    }
                }
            }
            Input::Shifted {
                pattern,
                k,
                mass,
                m,
                sigma,
                fixed,
            } => {
                let range = pattern.col_ptr()[j]..pattern.col_ptr()[j + 1];
                let m_range = mass.col_ptr()[j]..mass.col_ptr()[j + 1];
                let (m_rows, m_values) = (&mass.row_idx()[m_range.clone()], &m[m_range]);
                let mut q = 0;
                for (&i, &kv) in pattern.row_idx()[range.clone()].iter().zip(&k[range]) {
                    let mut v = kv;
                    if m_rows.get(q) == Some(&i) {
                        v += -sigma * m_values[q];
                        q += 1;
                    }
                    let i = i as usize;
                    if let Some(fixed) = fixed {
                        if i == j {
                            if fixed[j] && v == 0.0 {
                                v = 1.0;
                            }
                        } else if fixed[i] || fixed[j] {
                            v = 0.0;
                        }
                    }
                    if i >= j {
                        f(i, v);
                    }
                }
            }
        }
    }

    /// The rows and values of the entries on or below the diagonal,
    /// column after column.
    pub(crate) fn lower_triangle(&self) -> (Vec<usize>, Vec<f64>) {
        let len = self.col_ptr()[self.ncols()];
        let (mut rows, mut values) = (Vec::with_capacity(len), Vec::with_capacity(len));
        for j in 0..self.ncols() {
            self.lower_of(j, |i, v| {
                rows.push(i);
                values.push(v);
            });
        }
        (rows, values)
    }
}

/// The lower triangle of `P A P^T` by columns (row indices of a column
/// unsorted): the entries each supernode takes in.
struct Permuted {
    col_ptr: Vec<usize>,
    row_idx: Vec<u32>,
    values: Vec<f64>,
}

impl Permuted {
    /// From the lower triangle of `a` (entries above the diagonal are
    /// skipped) and `inverse[old] = new`. The columns of `a` go in chunks
    /// of equal entry counts, one per thread: each counts its entries per
    /// permuted column, and then writes them after those of the chunks
    /// before it, so that every column holds its entries in the order of
    /// `a`'s columns, whatever the number of threads.
    fn new(a: &Input<'_>, inverse: &[usize]) -> Self {
        let n = a.ncols();
        let chunks = rayon::current_num_threads().clamp(1, 16);
        let cp = a.col_ptr();
        let total = cp[n];
        let mut bounds: Vec<usize> = (0..chunks)
            .map(|t| cp.partition_point(|&p| p < total * t / chunks).min(n))
            .collect();
        bounds.push(n);
        let target = |i: usize, j: usize| {
            let (r, c) = (inverse[i], inverse[j]);
            (r.max(c), r.min(c))
        };
        // Entries of each chunk per permuted column.
        let mut next: Vec<Vec<usize>> = (0..chunks)
            .into_par_iter()
            .map(|t| {
                let mut count = vec![0usize; n];
                for j in bounds[t]..bounds[t + 1] {
                    a.lower_rows_of(j, |i| count[target(i, j).1] += 1);
                }
                count
            })
            .collect();
        // Column pointers, and where each chunk starts in each column.
        let mut col_ptr = vec![0usize; n + 1];
        for c in 0..n {
            let mut at = col_ptr[c];
            for count in next.iter_mut() {
                let k = count[c];
                count[c] = at;
                at += k;
            }
            col_ptr[c + 1] = at;
        }
        let nnz = col_ptr[n];
        let mut row_idx = vec![0u32; nnz];
        let mut values = vec![0.0; nnz];
        let (rows_out, values_out) = (Shared(row_idx.as_mut_ptr()), Shared(values.as_mut_ptr()));
        next.par_iter_mut().enumerate().for_each(|(t, next)| {
            for j in bounds[t]..bounds[t + 1] {
                a.lower_of(j, |i, v| {
                    let (r, c) = target(i, j);
                    // SAFETY: the slots `next[c]` of this chunk lie between
                    // the counts of the chunks before it and after it in
                    // column `c`: no other thread writes them, and each is
                    // written once.
                    unsafe {
                        *rows_out.at(next[c]) = r as u32;
                        *values_out.at(next[c]) = v;
                    }
                    next[c] += 1;
                });
            }
        });
        Self {
            col_ptr,
            row_idx,
            values,
        }
    }
}

/// A pointer into an array whose entries the threads access disjointly.
#[derive(Copy, Clone)]
pub(crate) struct Shared<T>(pub(crate) *mut T);

// SAFETY: used only for accesses to disjoint entries (see the users).
unsafe impl<T> Send for Shared<T> {}
unsafe impl<T> Sync for Shared<T> {}

impl<T> Shared<T> {
    /// The entry `i`.
    ///
    /// # Safety
    /// `i` lies in the array, and no other thread accesses that entry.
    pub(crate) unsafe fn at(&self, i: usize) -> *mut T {
        unsafe { self.0.add(i) }
    }
}

/// Factorises the lower triangle of `a` (original order; `inverse[old] =
/// new` the analysis' permutation) into `values`, faer's supernodal layout
/// of `symbolic`. `Err(i)`: a pivot vanished, `i` as faer's
/// factorisation reports it (elimination order).
///
/// `report` receives the fraction of the factorisation's work done, at
/// each percent.
#[allow(clippy::too_many_arguments)]
pub(crate) fn factorize(
    symbolic: &Supernodes,
    plan: &SolvePlan,
    updates: &UpdatePlan,
    a: Input<'_>,
    inverse: &[usize],
    values: &mut [f64],
    panels: Panels,
    par: Par,
    report: &(dyn Fn(f64) + Sync),
) -> Result<(), usize> {
    assert_eq!(values.len(), symbolic.len_val());
    let a = Permuted::new(&a, inverse);
    let work = Work {
        symbolic,
        updates,
        a: &a,
        values: Shared(values.as_mut_ptr()),
        par,
        panels,
        tally: Tally {
            done: AtomicU64::new(0),
            report,
        },
    };
    // The subtrees of the plan in parallel, then the top: each top
    // supernode after its children there, siblings in parallel.
    plan.tasks
        .par_iter()
        .map_init(
            || Buffers::new(symbolic.nrows()),
            |buffers, task| {
                task.supernodes
                    .clone()
                    .try_for_each(|s| work.supernode(s, buffers, Par::Seq))
            },
        )
        .collect::<Result<Vec<()>, usize>>()?;
    work.subtrees(&updates.top_roots, &updates.top_children)
}

/// What every supernode's step reads.
struct Work<'a> {
    symbolic: &'a Supernodes,
    updates: &'a UpdatePlan,
    a: &'a Permuted,
    /// The factor's values, shared by the threads: each writes only the
    /// block of the supernode it factorises and reads only blocks of its
    /// finished descendants (the tree order makes the accesses disjoint).
    values: Shared<f64>,
    par: Par,
    /// The split of large updates ([`Panels::DEFAULT`]; finer in tests).
    panels: Panels,
    tally: Tally<'a>,
}

/// The work of the finished supernodes ([`UpdatePlan`]'s `work`),
/// reported at each percent of the whole.
struct Tally<'a> {
    /// Multiply-adds done, rounded per supernode.
    done: AtomicU64,
    report: &'a (dyn Fn(f64) + Sync),
}

impl Tally<'_> {
    /// Supernode `s` is finished.
    fn finished(&self, updates: &UpdatePlan, s: usize) {
        let total = updates.total_work.max(1.0);
        let work = updates.work[s] as u64;
        let before = self.done.fetch_add(work, AtomicOrdering::Relaxed);
        let after = before + work;
        let percent = |done: u64| (100 * done as u128) / total as u128;
        if percent(after) > percent(before) {
            (self.report)(after as f64 / total);
        }
    }
}

/// Reused buffers of one thread.
struct Buffers {
    /// `local[row]`: the row's place in the current block (`u32::MAX`
    /// outside its pattern).
    local: Vec<u32>,
    product: Vec<f64>,
    scaled: Vec<f64>,
    pivots: Vec<f64>,
    rows: Vec<u32>,
}

impl Buffers {
    fn new(n: usize) -> Self {
        Self {
            local: vec![u32::MAX; n],
            product: vec![],
            scaled: vec![],
            pivots: vec![],
            rows: vec![],
        }
    }
}

impl Work<'_> {
    /// The top supernodes `roots` and everything below them in `children`,
    /// siblings in parallel.
    fn subtrees(&self, roots: &[usize], children: &[Vec<usize>]) -> Result<(), usize> {
        roots
            .par_iter()
            .map_init(
                || Buffers::new(self.symbolic.nrows()),
                |buffers, &s| {
                    self.subtrees(&children[s], children)?;
                    self.supernode(s, buffers, self.par)
                },
            )
            .collect::<Result<Vec<()>, usize>>()
            .map(|_| ())
    }

    /// The values of supernode `s`'s block.
    ///
    /// # Safety
    /// No other thread may access the block meanwhile; a mutable block must
    /// not be aliased.
    #[allow(clippy::mut_from_ref)]
    unsafe fn block(&self, s: usize) -> &mut [f64] {
        let ptr = self.symbolic.col_ptr_for_val();
        std::slice::from_raw_parts_mut(self.values.at(ptr[s]), ptr[s + 1] - ptr[s])
    }

    /// Supernode `s`, its descendants factorised.
    fn supernode(&self, s: usize, buffers: &mut Buffers, par: Par) -> Result<(), usize> {
        let sym = self.symbolic;
        let (s_start, s_end) = (sym.supernode_begin()[s], sym.supernode_end()[s]);
        let s_pattern = sym.supernode(s).pattern();
        let s_ncols = s_end - s_start;
        let s_nrows = s_ncols + s_pattern.len();
        let local = &mut buffers.local;
        // Rows of the block: the diagonal block's, then the pattern's.
        for (i, &r) in s_pattern.iter().enumerate() {
            local[r] = (s_ncols + i) as u32;
        }
        // SAFETY: `s` is this thread's; no descendant of it is running.
        let ls = unsafe { self.block(s) };
        ls.fill(0.0);
        let mut ls = MatMut::from_column_major_slice_mut(ls, s_nrows, s_ncols);
        // A's columns.
        let a = self.a;
        for j in s_start..s_end {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let i = a.row_idx[p] as usize;
                let row = if i < s_end {
                    i - s_start
                } else {
                    local[i] as usize
                };
                ls[(row, j - s_start)] += a.values[p];
            }
        }
        // The descendants' updates: L_s -= L_d,mid..bot D_d L_d,mid^T.
        for &d in self.updates.of(s) {
            let d = d as usize;
            let (d_start, d_end) = (sym.supernode_begin()[d], sym.supernode_end()[d]);
            let d_pattern = sym.supernode(d).pattern();
            let d_ncols = d_end - d_start;
            // SAFETY: `d` is a finished descendant; nobody writes it now.
            let ld = MatRef::from_column_major_slice(
                unsafe { self.block(d) },
                d_ncols + d_pattern.len(),
                d_ncols,
            );
            let first = d_pattern.partition_point(|&r| r < s_start);
            let mid = d_pattern[first..].partition_point(|&r| r < s_end);
            let rows = &d_pattern[first..];
            let below = ld.subrows(d_ncols + first, rows.len());
            buffers.pivots.clear();
            buffers.pivots.extend((0..d_ncols).map(|k| ld[(k, k)]));
            buffers.rows.clear();
            buffers.rows.extend(rows.iter().map(|&r| {
                if r < s_end {
                    (r - s_start) as u32
                } else {
                    buffers.local[r]
                }
            }));
            // By panels of `s`'s columns, so that the buffers stay small
            // for the large separators' updates (one panel for most).
            let width = self.panels.width(rows.len(), mid);
            for c0 in (0..mid).step_by(width) {
                let w = width.min(mid - c0);
                self.update_panel(&mut ls, below, c0, w, buffers, par);
            }
        }
        for &r in s_pattern {
            buffers.local[r] = u32::MAX;
        }
        // The diagonal block, then the block below: L_bot = A_bot L_top^-T D^-1.
        let (mut top, mut bot) = ls.split_at_row_mut(s_ncols);
        let below = bot.nrows();
        let mut mem = MemBuffer::new(
            faer::linalg::cholesky::ldlt::factor::cholesky_in_place_scratch::<f64>(
                s_ncols,
                par,
                Default::default(),
            ),
        );
        match cholesky_in_place(
            top.as_mut(),
            LdltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        ) {
            Ok(_) => {}
            Err(LdltError::ZeroPivot { index }) => return Err(index + s_start),
        }
        for j in 0..s_ncols {
            for i in 0..j {
                top[(i, j)] = 0.0;
            }
        }
        faer::linalg::triangular_solve::solve_unit_lower_triangular_in_place(
            top.as_ref(),
            bot.as_mut().transpose_mut(),
            par_for(s_ncols * s_ncols * below, par),
        );
        for j in 0..s_ncols {
            let d = top[(j, j)].recip();
            for i in 0..below {
                bot[(i, j)] *= d;
            }
        }
        self.tally.finished(self.updates, s);
        Ok(())
    }

    /// Columns `c0..c0 + w` of a descendant's update `L_d,below D_d
    /// L_d,mid^T` subtracted from the block `ls` of `s`: `below` holds the
    /// descendant's rows from `s`'s first column on (those of `s`'s
    /// columns first), `buffers.rows` their rows in `ls` and
    /// `buffers.pivots` the descendant's `D`. Only rows from `c0` on are
    /// needed (the lower triangle).
    fn update_panel(
        &self,
        ls: &mut MatMut<'_, f64>,
        below: MatRef<'_, f64>,
        c0: usize,
        w: usize,
        buffers: &mut Buffers,
        par: Par,
    ) {
        let d_ncols = below.ncols();
        let below = below.subrows(c0, below.nrows() - c0);
        let nrows = below.nrows();
        // (D L_panel^T): d_ncols x w.
        grow(&mut buffers.scaled, d_ncols * w);
        let scaled = &mut buffers.scaled[..d_ncols * w];
        MatMut::from_column_major_slice_mut(scaled, d_ncols, w)
            .copy_from(below.subrows(0, w).transpose());
        for col in scaled.chunks_exact_mut(d_ncols) {
            for (x, &p) in col.iter_mut().zip(&buffers.pivots) {
                *x *= p;
            }
        }
        let scaled = MatRef::from_column_major_slice(scaled, d_ncols, w);
        // Overwritten by the product: only grown, never cleared.
        grow(&mut buffers.product, nrows * w);
        let mut product =
            MatMut::from_column_major_slice_mut(&mut buffers.product[..nrows * w], nrows, w);
        let par_here = par_for(nrows * w * d_ncols, par);
        if w >= TRIANGLE_FROM {
            // The first `w` rows (those of the panel's own columns) are
            // needed on and below the diagonal only: their square as a
            // lower triangle, half its flops.
            let (upper, lower) = product.as_mut().split_at_row_mut(w);
            let (b_upper, b_lower) = below.split_at_row(w);
            faer::linalg::matmul::triangular::matmul(
                upper,
                faer::linalg::matmul::triangular::BlockStructure::TriangularLower,
                Accum::Replace,
                b_upper,
                faer::linalg::matmul::triangular::BlockStructure::Rectangular,
                scaled,
                faer::linalg::matmul::triangular::BlockStructure::Rectangular,
                1.0,
                par_here,
            );
            matmul(lower, Accum::Replace, b_lower, scaled, 1.0, par_here);
        } else {
            matmul(
                product.as_mut(),
                Accum::Replace,
                below,
                scaled,
                1.0,
                par_here,
            );
        }
        let rows = &buffers.rows[c0..];
        for c in 0..w {
            let col = rows[c] as usize;
            // Only the lower triangle: rows from c on.
            for (i, &row) in rows.iter().enumerate().skip(c) {
                ls[(row as usize, col)] -= product[(i, c)];
            }
        }
    }
}

/// How a descendant's update is split into panels of the supernode's
/// columns.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Panels {
    /// Entries of the largest update product a thread computes at once.
    pub(crate) entries: usize,
    /// The narrowest panel of a split update (gemm's efficiency).
    pub(crate) min_width: usize,
}

impl Panels {
    /// Products of at most 32 MiB (`2^22` entries), where the top
    /// separators' updates of a large solid would take gigabytes in one
    /// piece.
    pub(crate) const DEFAULT: Panels = Panels {
        entries: 1 << 22,
        min_width: 64,
    };

    /// Columns per panel of an update of `rows x mid`: all of them up to
    /// `entries` entries in the product, else panels of that many (at
    /// least `min_width` columns).
    fn width(self, rows: usize, mid: usize) -> usize {
        if rows * mid <= self.entries {
            mid.max(1)
        } else {
            (self.entries / rows.max(1)).max(self.min_width).max(1)
        }
    }
}

/// Columns of a descendant's update from which its square on the
/// supernode's own columns is computed as a lower triangle only.
const TRIANGLE_FROM: usize = 32;

/// Makes `v` at least `len` long (a work buffer whose contents are
/// overwritten before they are read: no clearing pass).
fn grow(v: &mut Vec<f64>, len: usize) {
    if v.len() < len {
        v.resize(len, 0.0);
    }
}

/// Threads only for kernels large enough to gain from them.
fn par_for(flops: usize, par: Par) -> Par {
    if flops >= 1 << 18 {
        par
    } else {
        Par::Seq
    }
}

#[cfg(test)]
mod tests {
    use crate::ldlt::solve::tests::grid;
    use crate::ldlt::SymbolicLdlt;
    use crate::ordering::Ordering;
    use crate::sparse::{add_scaled, max_abs, symmetric_mul};
    use crate::SparseMat;
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
    use faer::Mat;
    use faer::Side;

    /// faer's own numeric factorisation of `a` on faer's analysis under
    /// the same permutation (the same supernodes: `crate::ldlt::symbolic`).
    fn faer_values(symbolic: &SymbolicLdlt, a: &SparseMat) -> Vec<f64> {
        let sym = &symbolic.faer_reference(a.symbolic());
        let mut values = vec![0.0; sym.len_val()];
        let par = faer::Par::Seq;
        let mut mem =
            MemBuffer::new(sym.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()));
        sym.factorize_numeric_ldlt(
            &mut values,
            a.as_ref(),
            Side::Lower,
            LdltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .unwrap();
        values
    }

    /// The subtrees and the top in parallel give faer's factor of a
    /// definite matrix to round-off; of an indefinite one (the pencil of a
    /// Sturm count) the same inertia and a solve as accurate.
    #[test]
    fn the_parallel_factor_is_faers_factor() {
        let a = grid(12);
        let n = a.nrows();
        let symbolic =
            SymbolicLdlt::analyze_pattern(a.symbolic(), Ordering::NestedDissection).unwrap();
        let identity = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(
            n,
            n,
            &(0..n)
                .map(|i| faer::sparse::Triplet::new(i, i, 1.0))
                .collect::<Vec<_>>(),
        )
        .unwrap();
        // Shifted past the lowest eigenvalues: negative pivots.
        let shifted = add_scaled(&a, -101.5, &identity).unwrap();
        let b = Mat::from_fn(n, 3, |i, j| ((i * 7 + j * 5) % 13) as f64 - 6.0);
        for (m, definite) in [(&a, true), (&shifted, false)] {
            let mut ours = Vec::new();
            symbolic.factorize_into(m.as_ref(), &mut ours).unwrap();
            let theirs = faer_values(&symbolic, m);
            let scale = theirs.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            let diff = ours
                .iter()
                .zip(&theirs)
                .fold(0.0_f64, |s, (x, y)| s.max((x - y).abs()));
            let negative = |v: &[f64]| {
                symbolic
                    .permuted_pivots(v)
                    .iter()
                    .filter(|&&d| d < 0.0)
                    .count()
            };
            assert_eq!(negative(&ours), negative(&theirs));
            if definite {
                assert!(diff <= 1e-14 * scale, "{diff:e} of {scale:e}");
                assert_eq!(negative(&ours), 0);
            } else {
                assert!(negative(&ours) > 0);
                let mut x = b.clone();
                symbolic.solve_in_place(&ours, x.as_mut());
                let r = symmetric_mul(m, x.as_ref()) - &b;
                assert!(max_abs(r.as_ref()) < 1e-9 * max_abs(b.as_ref()));
            }
            // Updates split into panels of a few columns (the large
            // separators' updates of big models) give the same factor to
            // round-off.
            for entries in [1, 40, 300, 12_000] {
                let mut panels = Vec::new();
                let split = crate::ldlt::numeric::Panels {
                    entries,
                    min_width: 1,
                };
                symbolic
                    .factorize_in_panels(m.as_ref(), &mut panels, split, &|_| {})
                    .unwrap();
                let diff = panels
                    .iter()
                    .zip(&ours)
                    .fold(0.0_f64, |s, (x, y)| s.max((x - y).abs()));
                assert!(diff <= 1e-13 * scale, "{entries}: {diff:e} of {scale:e}");
                assert_eq!(negative(&panels), negative(&ours));
            }
            // The permuted input is split between the threads; the factor
            // does not depend on how many there are.
            for threads in [1, 3] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let mut again = Vec::new();
                pool.install(|| symbolic.factorize_into(m.as_ref(), &mut again))
                    .unwrap();
                assert_eq!(again, ours, "{threads} threads");
            }
        }
    }

    /// The progress of a factorisation: at most one report per percent of
    /// its work, from whichever thread finishes a supernode, the last at
    /// exactly 1.
    #[test]
    fn a_factorisation_reports_each_percent_of_its_work_once() {
        let a = grid(24);
        let symbolic =
            SymbolicLdlt::analyze_pattern(a.symbolic(), Ordering::NestedDissection).unwrap();
        let reports = std::sync::Mutex::new(Vec::new());
        let mut values = Vec::new();
        symbolic
            .factorize_in_panels(
                a.as_ref(),
                &mut values,
                crate::ldlt::numeric::Panels::DEFAULT,
                &|done| reports.lock().unwrap().push(done),
            )
            .unwrap();
        let mut done = reports.into_inner().unwrap();
        done.sort_by(f64::total_cmp);
        assert_eq!(done.last(), Some(&1.0), "{done:?}");
        assert!(done.len() >= 10, "{done:?}");
        let percents: Vec<u64> = done.iter().map(|d| (d * 100.0).floor() as u64).collect();
        assert!(percents.windows(2).all(|w| w[0] < w[1]), "{percents:?}");
        assert!(done[0] > 0.0);
    }
}
