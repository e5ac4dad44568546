//! Block solves `L D L^T X = B` with faer's supernodal factor, in parallel
//! over the supernodal elimination tree.
//!
//! # Subtrees in parallel
//! faer's own solve walks the supernodes one after another and parallelises
//! inside each dense kernel; most supernodes of a large mesh are small, and
//! a thread hand-off per kernel costs more than it gains. Nested dissection yields a tree whose large subtrees are independent:
//! the forward sweep of two disjoint subtrees only meets in the separators
//! above them. A [`SolvePlan`] splits the tree into such subtrees (tasks,
//! each a contiguous range of rows in the postordered factor) and the
//! supernodes above them (the top). The forward sweep runs the tasks in
//! parallel, each thread adding its tasks' updates of top rows into a
//! buffer of its own, then sums the buffers and finishes the top; the backward sweep finishes
//! the top first and then runs the tasks in parallel, each reading the top
//! rows from a shared copy.
//!
//! # Row-major groups of right-hand sides
//! A solve reads every entry of `L` once per sweep and does little with it,
//! so its speed is that of reading `L` from memory. The right-hand sides go
//! through in groups of 8, stored row-major: a row of the group
//! is one cache line, and each entry of `L` updates it with two 4-wide
//! fused multiply-adds. A supernode's update of its pattern rows is
//! streamed straight from its column-major block, four columns at a time,
//! into (forward) or out of (backward) those rows: no packed copy of the
//! block as a general matrix product would make, no temporary. The
//! diagonal blocks go the same way, four columns at a time. The large
//! supernodes of the top split their rows (forward) or columns (backward)
//! between the threads.
//!
//! Four columns of a small supernode are four short streams (about a
//! hundred rows each), which the hardware prefetcher follows poorly
//! (`bench/kernel_streams.c` measures a kernel of this shape against one
//! stream of the same entries). While a group of four columns
//! runs, each eighth row asks the cache for the same row of the next
//! group's columns, and the last group of a pass for the columns the next
//! pass starts with (the next group of a diagonal block, the first group's
//! top rows after the local ones).

use crate::ldlt::numeric::Shared;
use crate::ldlt::symbolic::{FactorRef, SolvePlan, Task};
use crate::lower::{Lane, LANE};
use faer::{MatMut, MatRef};
use rayon::prelude::*;
use std::ops::Range;

impl SolvePlan {
    /// Number of subtrees solved in parallel.
    #[cfg(test)]
    pub fn tasks(&self) -> usize {
        self.tasks.len()
    }

    /// Solves `A X = B` in place with `P A P^T = L D L^T` (`x` holds `B` on
    /// entry and `X` on exit, in the original order; `inverse[old]` is the
    /// factor's row of original row `old`). The columns go through the
    /// factor 8 at a time, each group stored row-major (one cache line
    /// per row): every entry of `L` read from memory updates the whole group
    /// with two vector operations, and gathering or scattering a pattern row
    /// moves one cache line.
    pub(crate) fn solve_in_place(
        &self,
        factor: FactorRef<'_>,
        inverse: &[usize],
        x: MatMut<'_, f64>,
    ) {
        self.solve_with(factor, inverse, x, has_fma());
    }

    /// [`Self::solve_in_place`] with the fused multiply-add kernels or the
    /// baseline ones.
    fn solve_with(
        &self,
        factor: FactorRef<'_>,
        inverse: &[usize],
        mut x: MatMut<'_, f64>,
        fma: bool,
    ) {
        const ROWS: usize = 4096;
        let n = x.nrows();
        assert_eq!(inverse.len(), n, "solve: permutation of another size");
        // Filled below before it is read: no zeroing pass.
        let mut y: Vec<Lane> = Vec::with_capacity(n);
        for c0 in (0..x.ncols()).step_by(LANE) {
            let g = LANE.min(x.ncols() - c0);
            // In: the rows of `x` in order, each to its place in the
            // factor's order (one cache line per row).
            {
                let cells = Shared(y.as_mut_ptr());
                let x = x.as_ref();
                (0..n).into_par_iter().step_by(ROWS).for_each(|r0| {
                    let cells = &cells;
                    for i in r0..(r0 + ROWS).min(n) {
                        let mut lane = Lane::ZERO;
                        for q in 0..g {
                            lane.0[q] = x[(i, c0 + q)];
                        }
                        // SAFETY: `inverse` is a permutation of 0..n, so
                        // each row of `y` (capacity n) is written by one
                        // thread once.
                        unsafe { cells.at(inverse[i]).write(lane) };
                    }
                });
            }
            // SAFETY: the loop above initialised all n rows.
            unsafe { y.set_len(n) };
            self.solve_group(factor, &mut y, fma);
            let y = &y;
            x.as_mut()
                .subcols_mut(c0, g)
                .par_row_chunks_mut(ROWS)
                .enumerate()
                .for_each(|(chunk, mut rows)| {
                    for r in 0..rows.nrows() {
                        let lane = &y[inverse[chunk * ROWS + r]].0;
                        for q in 0..g {
                            rows[(r, q)] = lane[q];
                        }
                    }
                });
        }
    }

    /// One group of right-hand sides in the factor's order.
    fn solve_group(&self, factor: FactorRef<'_>, x: &mut [Lane], fma: bool) {
        let nt = self.top_rows.len();
        // Forward sweep of the tasks; the updates of top rows go to a
        // buffer per run of consecutive tasks (not per task: most tasks
        // touch few top rows). The runs are fixed by the number of tasks
        // and threads, not by the scheduling, so the buffers add up in the
        // same order in every solve.
        let views = self.lane_views(x);
        let runs = (4 * rayon::current_num_threads()).clamp(1, views.len().max(1));
        let buffers: Vec<Vec<Lane>> = views
            .into_par_iter()
            .chunks(self.tasks.len().div_ceil(runs).max(1))
            .map(|run| {
                let mut top = vec![Lane::ZERO; nt];
                for (task, view) in run {
                    let mut rows = LaneRows {
                        local: view,
                        first: task.rows.start,
                        top: Top::Write(&mut top),
                        top_index: &self.top_index,
                    };
                    sweep(
                        fma,
                        factor,
                        task.supernodes.clone(),
                        &mut rows,
                        Sweep::Forward,
                    );
                }
                top
            })
            .collect();
        for b in &buffers {
            for (p, &r) in self.top_rows.iter().enumerate() {
                for q in 0..LANE {
                    x[r].0[q] += b[p].0[q];
                }
            }
        }
        drop(buffers);
        let mut rows = LaneRows {
            local: x,
            first: 0,
            top: Top::Write(&mut []),
            top_index: &self.top_index,
        };
        for &s in &self.top {
            if large(factor, s) {
                top_forward(fma, factor, s, rows.local);
            } else {
                sweep(fma, factor, s..s + 1, &mut rows, Sweep::Forward);
            }
        }
        let x = rows.local;
        // Backward sweep: the top first, then the tasks reading a copy of it.
        let mut rows = LaneRows {
            local: x,
            first: 0,
            top: Top::Write(&mut []),
            top_index: &self.top_index,
        };
        for &s in self.top.iter().rev() {
            if large(factor, s) {
                top_backward(fma, factor, s, rows.local);
            } else {
                sweep(fma, factor, s..s + 1, &mut rows, Sweep::Backward);
            }
        }
        let x = rows.local;
        let top_copy: Vec<Lane> = self.top_rows.iter().map(|&r| x[r]).collect();
        self.lane_views(x).into_par_iter().for_each(|(task, view)| {
            let mut rows = LaneRows {
                local: view,
                first: task.rows.start,
                top: Top::Read(&top_copy),
                top_index: &self.top_index,
            };
            sweep(
                fma,
                factor,
                task.supernodes.clone(),
                &mut rows,
                Sweep::Backward,
            );
        });
    }

    /// The rows of `x` owned by each task, as disjoint slices.
    fn lane_views<'a>(&'a self, x: &'a mut [Lane]) -> Vec<(&'a Task, &'a mut [Lane])> {
        let mut views = Vec::with_capacity(self.tasks.len());
        let mut rest = x;
        let mut offset = 0;
        for task in &self.tasks {
            let (_, tail) = rest.split_at_mut(task.rows.start - offset);
            let (mine, tail) = tail.split_at_mut(task.rows.len());
            views.push((task, mine));
            rest = tail;
            offset = task.rows.end;
        }
        views
    }
}

fn has_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Row-major right-hand sides as one task sees them: its own rows (from
/// row `first` on) and a buffer for the rows of the top.
struct LaneRows<'a, 'b> {
    local: &'a mut [Lane],
    first: usize,
    top: Top<'b>,
    top_index: &'b [usize],
}

/// The top rows of a task: updated in the forward sweep, read in the
/// backward one.
enum Top<'b> {
    Write(&'b mut [Lane]),
    Read(&'b [Lane]),
}

#[derive(Copy, Clone, PartialEq)]
enum Sweep {
    Forward,
    Backward,
}

/// The forward or backward steps of the supernodes `range` (backward in
/// reverse order), compiled with fused multiply-adds where the CPU has them.
fn sweep(
    fma: bool,
    factor: FactorRef<'_>,
    range: Range<usize>,
    rows: &mut LaneRows<'_, '_>,
    dir: Sweep,
) {
    #[cfg(target_arch = "x86_64")]
    if fma {
        // SAFETY: the CPU has AVX2 and FMA (`has_fma`).
        unsafe { sweep_avx2(factor, range, rows, dir) };
        return;
    }
    let _ = fma;
    sweep_with::<false>(factor, range, rows, dir);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn sweep_avx2(
    factor: FactorRef<'_>,
    range: Range<usize>,
    rows: &mut LaneRows<'_, '_>,
    dir: Sweep,
) {
    sweep_with::<true>(factor, range, rows, dir);
}

#[inline(always)]
fn sweep_with<const FMA: bool>(
    factor: FactorRef<'_>,
    range: Range<usize>,
    rows: &mut LaneRows<'_, '_>,
    dir: Sweep,
) {
    match dir {
        Sweep::Forward => {
            for s in range {
                lane_step::<FMA>(factor, s, rows, dir);
            }
        }
        Sweep::Backward => {
            for s in range.rev() {
                lane_step::<FMA>(factor, s, rows, dir);
            }
        }
    }
}

/// Whether supernode `s` of the top is worth splitting between threads.
fn large(factor: FactorRef<'_>, s: usize) -> bool {
    let block = factor.supernode(s).val();
    block.nrows() * block.ncols() >= 1 << 16
}

/// The forward step of a large supernode of the top (`x` all rows): its
/// pattern rows split between threads.
fn top_forward(fma: bool, factor: FactorRef<'_>, s: usize, x: &mut [Lane]) {
    let node = factor.supernode(s);
    let block = node.val();
    let size = block.ncols();
    let (head, tail) = x.split_at_mut(node.start() + size);
    let xs = &mut head[node.start()..];
    triangular(fma, block, xs, Sweep::Forward);
    par_scatter(
        fma,
        block,
        size,
        xs,
        tail,
        node.pattern(),
        node.start() + size,
    );
    scale_by_pivots(block, xs);
}

/// `X_s = D_s^-1 X_s`, the pivots on the diagonal of the block.
#[inline(always)]
fn scale_by_pivots(block: MatRef<'_, f64>, xs: &mut [Lane]) {
    for (i, x) in xs.iter_mut().enumerate() {
        let d = block[(i, i)].recip();
        for v in x.0.iter_mut() {
            *v *= d;
        }
    }
}

/// `out[rows[p] - off] -= block[from + p, ..] X_s`, halves of the rows in
/// parallel (the rows ascend, so each half owns a range of `out`).
fn par_scatter(
    fma: bool,
    block: MatRef<'_, f64>,
    from: usize,
    xs: &[Lane],
    out: &mut [Lane],
    rows: &[usize],
    off: usize,
) {
    if rows.len() * xs.len() < 1 << 15 || rows.len() < 64 {
        dispatch_scatter(fma, block, from, xs, out, rows, off);
        return;
    }
    let mid = rows.len() / 2;
    let cut = rows[mid] - off;
    let (lo, hi) = out.split_at_mut(cut);
    rayon::join(
        || par_scatter(fma, block, from, xs, lo, &rows[..mid], off),
        || par_scatter(fma, block, from + mid, xs, hi, &rows[mid..], off + cut),
    );
}

/// The backward step of a large supernode of the top: its columns split
/// between threads, each gathering from all pattern rows.
fn top_backward(fma: bool, factor: FactorRef<'_>, s: usize, x: &mut [Lane]) {
    const COLUMNS: usize = 64;
    let node = factor.supernode(s);
    let block = node.val();
    let size = block.ncols();
    let (head, tail) = x.split_at_mut(node.start() + size);
    let xs = &mut head[node.start()..];
    let (rows, off) = (node.pattern(), node.start() + size);
    let src: &[Lane] = tail;
    xs.par_chunks_mut(COLUMNS)
        .enumerate()
        .for_each(|(k, chunk)| {
            dispatch_gather(fma, block, k * COLUMNS, size, src, rows, off, chunk)
        });
    triangular(fma, block, xs, Sweep::Backward);
}

/// [`scatter`] from the rows `rows[p] - off`, compiled for the CPU.
fn dispatch_scatter(
    fma: bool,
    block: MatRef<'_, f64>,
    from: usize,
    xs: &[Lane],
    out: &mut [Lane],
    rows: &[usize],
    off: usize,
) {
    #[cfg(target_arch = "x86_64")]
    if fma {
        #[target_feature(enable = "avx2,fma")]
        unsafe fn avx2(
            block: MatRef<'_, f64>,
            from: usize,
            xs: &[Lane],
            out: &mut [Lane],
            rows: &[usize],
            off: usize,
        ) {
            scatter::<true>(block, 0, from, xs, out, |p| rows[p] - off, rows.len(), None);
        }
        // SAFETY: the CPU has AVX2 and FMA (`has_fma`).
        unsafe { avx2(block, from, xs, out, rows, off) };
        return;
    }
    scatter::<false>(block, 0, from, xs, out, |p| rows[p] - off, rows.len(), None);
}

/// [`gather`] into the columns `j0..` from the rows `rows[p] - off`,
/// compiled for the CPU.
#[allow(clippy::too_many_arguments)]
fn dispatch_gather(
    fma: bool,
    block: MatRef<'_, f64>,
    j0: usize,
    from: usize,
    src: &[Lane],
    rows: &[usize],
    off: usize,
    xs: &mut [Lane],
) {
    #[cfg(target_arch = "x86_64")]
    if fma {
        #[allow(clippy::too_many_arguments)]
        #[target_feature(enable = "avx2,fma")]
        unsafe fn avx2(
            block: MatRef<'_, f64>,
            j0: usize,
            from: usize,
            src: &[Lane],
            rows: &[usize],
            off: usize,
            xs: &mut [Lane],
        ) {
            gather::<true>(
                block,
                j0,
                from,
                src,
                |p| rows[p] - off,
                rows.len(),
                xs,
                None,
            );
        }
        // SAFETY: the CPU has AVX2 and FMA (`has_fma`).
        unsafe { avx2(block, j0, from, src, rows, off, xs) };
        return;
    }
    gather::<false>(
        block,
        j0,
        from,
        src,
        |p| rows[p] - off,
        rows.len(),
        xs,
        None,
    );
}

/// The diagonal block's solve of a step, compiled for the CPU.
fn triangular(fma: bool, block: MatRef<'_, f64>, xs: &mut [Lane], dir: Sweep) {
    #[cfg(target_arch = "x86_64")]
    if fma {
        #[target_feature(enable = "avx2,fma")]
        unsafe fn avx2(block: MatRef<'_, f64>, xs: &mut [Lane], dir: Sweep) {
            match dir {
                Sweep::Forward => lower_solve::<true>(block, xs),
                Sweep::Backward => upper_solve::<true>(block, xs),
            }
        }
        // SAFETY: the CPU has AVX2 and FMA (`has_fma`).
        unsafe { avx2(block, xs, dir) };
        return;
    }
    match dir {
        Sweep::Forward => lower_solve::<false>(block, xs),
        Sweep::Backward => upper_solve::<false>(block, xs),
    }
}

/// Column `j` of a column-major block, rows `from..to`.
#[inline(always)]
fn column(block: MatRef<'_, f64>, j: usize, from: usize, to: usize) -> &[f64] {
    let col = block
        .col(j)
        .try_as_col_major()
        .expect("supernodal blocks are column-major");
    &col.as_slice()[from..to]
}

/// Columns `j..j + 4` of a column-major block, rows `from..to`.
#[inline(always)]
fn four_columns(block: MatRef<'_, f64>, j: usize, from: usize, to: usize) -> [&[f64]; 4] {
    [
        column(block, j, from, to),
        column(block, j + 1, from, to),
        column(block, j + 2, from, to),
        column(block, j + 3, from, to),
    ]
}

/// Hints the cache to load row `p` of four columns: the next group's,
/// while the current one runs (see [`scatter`]).
#[inline(always)]
fn prefetch_row(next: &[&[f64]; 4], p: usize) {
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (next, p);
    #[cfg(target_arch = "x86_64")]
    for c in next {
        if let Some(v) = c.get(p) {
            // SAFETY: a hint only, to an address inside the slice.
            unsafe {
                std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
                    (v as *const f64).cast::<i8>(),
                )
            };
        }
    }
}

#[inline(always)]
fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// One supernode's step. Forward: `X_s = L_ss^-1 X_s`, then the pattern
/// rows lose `L_ps X_s`. Backward: `X_s -= L_ps^T X_p`, then
/// `X_s = L_ss^-T X_s`. The pattern's rows inside the view come first
/// (ascending), those of the top after them.
#[inline(always)]
fn lane_step<const FMA: bool>(
    factor: FactorRef<'_>,
    s: usize,
    rows: &mut LaneRows<'_, '_>,
    dir: Sweep,
) {
    let node = factor.supernode(s);
    let block = node.val();
    let size = block.ncols();
    let pattern = node.pattern();
    let start = node.start() - rows.first;
    let inside = pattern.partition_point(|&r| r < rows.first + rows.local.len());
    let (head, tail) = rows.local.split_at_mut(start + size);
    let xs = &mut head[start..];
    // Pattern rows inside the view lie below the diagonal block.
    let off = rows.first + start + size;
    let (local, top_index) = (&pattern[..inside], rows.top_index);
    let top = &pattern[inside..];
    let m = size + pattern.len();
    match dir {
        Sweep::Forward => {
            lower_solve::<FMA>(block, xs);
            // The last group of the local rows prefetches the first one's
            // top rows, which come next.
            let then = (size >= 4).then(|| four_columns(block, 0, size + inside, m));
            scatter::<FMA>(block, 0, size, xs, tail, |p| local[p] - off, inside, then);
            let Top::Write(top_lanes) = &mut rows.top else {
                unreachable!("a forward sweep writes its top rows")
            };
            scatter::<FMA>(
                block,
                0,
                size + inside,
                xs,
                top_lanes,
                |p| top_index[top[p]],
                m - size - inside,
                None,
            );
            // X_s is final: D^-1 now, while it is in cache.
            scale_by_pivots(block, xs);
        }
        Sweep::Backward => {
            let then = (size >= 4).then(|| four_columns(block, 0, size + inside, m));
            gather::<FMA>(block, 0, size, tail, |p| local[p] - off, inside, xs, then);
            let top_lanes: &[Lane] = match &rows.top {
                Top::Write(t) => t,
                Top::Read(t) => t,
            };
            gather::<FMA>(
                block,
                0,
                size + inside,
                top_lanes,
                |p| top_index[top[p]],
                m - size - inside,
                xs,
                None,
            );
            upper_solve::<FMA>(block, xs);
        }
    }
}

/// `X_s = L_ss^-1 X_s` with the unit lower-triangular top of `block`: by
/// blocks of `width` columns, the triangle of a block then the rows below
/// it within the diagonal block (as a [`scatter`]).
#[inline(always)]
fn lower_solve<const FMA: bool>(block: MatRef<'_, f64>, xs: &mut [Lane]) {
    let n = xs.len();
    let mut j = 0;
    while j < n {
        let w = 4.min(n - j);
        lower_triangle::<FMA>(block, j, w, xs);
        let (left, right) = xs.split_at_mut(j + w);
        // The next group's columns over the same rows: most of its own.
        let then = (j + 8 <= n).then(|| four_columns(block, j + 4, j + w, n));
        scatter::<FMA>(block, j, j + w, &left[j..], right, |p| p, n - j - w, then);
        j += w;
    }
}

/// The triangle of the columns `j..j + w` of [`lower_solve`].
#[inline(always)]
fn lower_triangle<const FMA: bool>(block: MatRef<'_, f64>, j: usize, w: usize, xs: &mut [Lane]) {
    for jj in j..j + w {
        let xj = xs[jj].0;
        let col = column(block, jj, 0, j + w);
        for i in jj + 1..j + w {
            let l = -col[i];
            let xi = &mut xs[i].0;
            for q in 0..LANE {
                xi[q] = madd::<FMA>(l, xj[q], xi[q]);
            }
        }
    }
}

/// `X_s = L_ss^-T X_s`: by blocks of 4 columns from the last, the rows
/// below a block (as a [`gather`]) then its triangle.
#[inline(always)]
fn upper_solve<const FMA: bool>(block: MatRef<'_, f64>, xs: &mut [Lane]) {
    let n = xs.len();
    let mut end = n;
    while end > 0 {
        let w = 4.min(end);
        let j = end - w;
        let (left, right) = xs.split_at_mut(end);
        let then = (j >= 4).then(|| four_columns(block, j - 4, end, n));
        gather::<FMA>(block, j, end, right, |p| p, n - end, &mut left[j..], then);
        upper_triangle::<FMA>(block, j, w, xs);
        end = j;
    }
}

/// The triangle of the columns `j..j + w` of [`upper_solve`].
#[inline(always)]
fn upper_triangle<const FMA: bool>(block: MatRef<'_, f64>, j: usize, w: usize, xs: &mut [Lane]) {
    for jj in (j..j + w).rev() {
        let col = column(block, jj, 0, j + w);
        let mut acc = xs[jj].0;
        for i in jj + 1..j + w {
            let l = -col[i];
            let xi = &xs[i].0;
            for q in 0..LANE {
                acc[q] = madd::<FMA>(l, xi[q], acc[q]);
            }
        }
        xs[jj].0 = acc;
    }
}

/// `out[row(p)] -= sum_j block[from + p, j] X_s[j]` for `p < count`, four
/// columns of the block at a time. Each group prefetches the next group's
/// rows as it goes, and the last group the columns `then` (those the
/// caller reads next), row for row.
// Index loops over the lanes: the form the vectoriser takes best.
#[allow(clippy::needless_range_loop)]
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn scatter<const FMA: bool>(
    block: MatRef<'_, f64>,
    j0: usize,
    from: usize,
    xs: &[Lane],
    out: &mut [Lane],
    row: impl Fn(usize) -> usize,
    count: usize,
    then: Option<[&[f64]; 4]>,
) {
    if count == 0 {
        return;
    }
    let size = xs.len();
    let to = from + count;
    let mut j = 0;
    while j + 4 <= size {
        let c = four_columns(block, j0 + j, from, to);
        let next = match j + 8 <= size {
            true => Some(four_columns(block, j0 + j + 4, from, to)),
            false => then,
        };
        let x = [xs[j].0, xs[j + 1].0, xs[j + 2].0, xs[j + 3].0];
        for p in 0..count {
            if let (Some(next), 0) = (&next, p % 8) {
                prefetch_row(next, p);
            }
            let l = [-c[0][p], -c[1][p], -c[2][p], -c[3][p]];
            let y = &mut out[row(p)].0;
            for q in 0..LANE {
                let mut v = y[q];
                v = madd::<FMA>(l[0], x[0][q], v);
                v = madd::<FMA>(l[1], x[1][q], v);
                v = madd::<FMA>(l[2], x[2][q], v);
                v = madd::<FMA>(l[3], x[3][q], v);
                y[q] = v;
            }
        }
        j += 4;
    }
    for j in j..size {
        let c = column(block, j0 + j, from, to);
        let x = xs[j].0;
        for p in 0..count {
            let l = -c[p];
            let y = &mut out[row(p)].0;
            for q in 0..LANE {
                y[q] = madd::<FMA>(l, x[q], y[q]);
            }
        }
    }
}

/// `X_s[j] -= sum_p block[from + p, j] src[row(p)]` for `p < count`, four
/// columns of the block at a time, prefetching as [`scatter`] does.
// Index loops over the lanes: the form the vectoriser takes best.
#[allow(clippy::needless_range_loop)]
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn gather<const FMA: bool>(
    block: MatRef<'_, f64>,
    j0: usize,
    from: usize,
    src: &[Lane],
    row: impl Fn(usize) -> usize,
    count: usize,
    xs: &mut [Lane],
    then: Option<[&[f64]; 4]>,
) {
    if count == 0 {
        return;
    }
    let size = xs.len();
    let to = from + count;
    let mut j = 0;
    while j + 4 <= size {
        let c = four_columns(block, j0 + j, from, to);
        let next = match j + 8 <= size {
            true => Some(four_columns(block, j0 + j + 4, from, to)),
            false => then,
        };
        let mut acc = [[0.0; LANE]; 4];
        for p in 0..count {
            if let (Some(next), 0) = (&next, p % 8) {
                prefetch_row(next, p);
            }
            let y = &src[row(p)].0;
            for (a, col) in acc.iter_mut().zip(&c) {
                let l = col[p];
                for q in 0..LANE {
                    a[q] = madd::<FMA>(l, y[q], a[q]);
                }
            }
        }
        for (k, a) in acc.iter().enumerate() {
            for q in 0..LANE {
                xs[j + k].0[q] -= a[q];
            }
        }
        j += 4;
    }
    for j in j..size {
        let c = column(block, j0 + j, from, to);
        let mut acc = [0.0; LANE];
        for p in 0..count {
            let l = c[p];
            let y = &src[row(p)].0;
            for q in 0..LANE {
                acc[q] = madd::<FMA>(l, y[q], acc[q]);
            }
        }
        for q in 0..LANE {
            xs[j].0[q] -= acc[q];
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::ldlt::SymbolicLdlt;
    use crate::ordering::Ordering;
    use crate::sparse::{from_triplets, max_abs, symmetric_mul, Triplet};
    use faer::Mat;

    /// A 3D grid of `n^3` nodes with 3 DOFs each, every node coupled to its
    /// 26 neighbours: the pattern of a hexahedral solid mesh, positive
    /// definite by diagonal dominance.
    pub(crate) fn grid(n: usize) -> crate::SparseMat {
        let node = |i: usize, j: usize, k: usize| i + n * (j + n * k);
        let mut t = Vec::new();
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let a = node(i, j, k);
                    for (dk, dj, di) in (0..27).map(|q| (q / 9, (q / 3) % 3, q % 3)) {
                        let (ii, jj, kk) = (i + di, j + dj, k + dk);
                        if ii < 1 || jj < 1 || kk < 1 || ii > n || jj > n || kk > n {
                            continue;
                        }
                        let b = node(ii - 1, jj - 1, kk - 1);
                        for p in 0..3 {
                            for q in 0..3 {
                                let v = if a == b {
                                    if p == q {
                                        100.0
                                    } else {
                                        0.5
                                    }
                                } else {
                                    -0.3 - 0.01 * (p + q) as f64
                                };
                                t.push(Triplet::new(3 * a + p, 3 * b + q, v));
                            }
                        }
                    }
                }
            }
        }
        from_triplets(3 * n * n * n, 3 * n * n * n, &t).unwrap()
    }

    #[test]
    fn parallel_subtrees_solve_what_one_thread_solves() {
        let a = grid(12);
        let n = a.nrows();
        let symbolic =
            SymbolicLdlt::analyze_pattern(a.symbolic(), Ordering::NestedDissection).unwrap();
        let mut values = Vec::new();
        symbolic.factorize_into(a.as_ref(), &mut values).unwrap();
        let Some(s) = symbolic.supernodes() else {
            panic!("a 3D mesh of 5184 DOFs gets a supernodal factor");
        };
        let faer_symbolic = symbolic.faer_reference(a.symbolic());
        // 11 columns: a full group of 8 and one of 3.
        let b = Mat::from_fn(n, 11, |i, j| ((i * 31 + j * 17) % 23) as f64 - 11.0);
        let forward = symbolic.forward();
        let mut inverse = vec![0; n];
        for (i, &f) in forward.iter().enumerate() {
            inverse[f] = i;
        }
        // faer's own solve is the reference.
        let mut reference = b.clone();
        let mut mem = faer::dyn_stack::MemBuffer::new(
            faer_symbolic.solve_in_place_scratch::<f64>(b.ncols(), faer::Par::Seq),
        );
        faer::sparse::linalg::cholesky::LdltRef::new(&faer_symbolic, &values)
            .solve_in_place_with_conj(
                faer::Conj::No,
                reference.as_mut(),
                faer::Par::Seq,
                faer::dyn_stack::MemStack::new(&mut mem),
            );
        let r = symmetric_mul(&a, reference.as_ref()) - &b;
        assert!(max_abs(r.as_ref()) < 1e-12 * max_abs(b.as_ref()));
        let scale = max_abs(reference.as_ref());
        let mut answers = Vec::new();
        for threads in [1, 2, 4] {
            let plan = SolvePlan::new(s, threads);
            // The postordered nested-dissection tree splits into subtrees.
            if threads > 1 {
                assert!(plan.tasks() >= 4 * threads, "{} tasks", plan.tasks());
            }
            for fma in [false, has_fma()] {
                let mut x = b.clone();
                plan.solve_with(FactorRef::new(s, &values), &inverse, x.as_mut(), fma);
                assert!(max_abs((&x - &reference).as_ref()) < 1e-13 * scale);
                answers.push(x);
            }
        }
        // The split changes the order of the sums only.
        for x in &answers[1..] {
            assert!(max_abs((x - &answers[0]).as_ref()) < 1e-13 * max_abs(answers[0].as_ref()));
        }
        // And that order is fixed: the same solve gives the same bits every
        // time, however the threads steal work.
        let plan = SolvePlan::new(s, 4);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let solve = || {
            let mut x = b.clone();
            let factor = FactorRef::new(s, &values);
            pool.install(|| plan.solve_with(factor, &inverse, x.as_mut(), has_fma()));
            x
        };
        let first = solve();
        for _ in 0..8 {
            let x = solve();
            let same = (0..n)
                .all(|i| (0..b.ncols()).all(|j| x[(i, j)].to_bits() == first[(i, j)].to_bits()));
            assert!(same, "a repeated solve changed the last bits");
        }
    }
}
