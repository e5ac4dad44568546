//! Products of tall blocks of vectors (`n` rows, a few dozen columns at
//! most), as the Lanczos basis and its blocks are: by chunks of rows in
//! parallel, each chunk one sequential product.
//!
//! With `n = 3e5` and 8 columns, faer's parallel products split the few
//! columns or the long inner dimension between the threads and synchronise
//! inside every call; these shapes are bound by reading the tall operand
//! from memory, which chunks of rows do at full bandwidth with no
//! synchronisation but one join. The chunks are fixed by `n` alone and
//! partial sums add up in chunk order, so results do not depend on the
//! number of threads.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;

/// Rows per chunk: a chunk of 8 columns is 0.25 MB, of a basis of 80
/// columns 2.6 MB, within a core's cache either way.
const ROWS: usize = 4096;

/// `A^T B` for tall `A` and `B` with the same rows.
pub fn gram(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    assert_eq!(a.nrows(), b.nrows(), "gram: operands of different heights");
    let n = a.nrows();
    if n <= ROWS || a.ncols() == 0 || b.ncols() == 0 {
        return a.transpose() * b;
    }
    let parts: Vec<Mat<f64>> = (0..n.div_ceil(ROWS))
        .into_par_iter()
        .map(|k| {
            let (r0, r1) = (k * ROWS, ((k + 1) * ROWS).min(n));
            let mut c = Mat::zeros(a.ncols(), b.ncols());
            matmul(
                c.as_mut(),
                Accum::Replace,
                a.subrows(r0, r1 - r0).transpose(),
                b.subrows(r0, r1 - r0),
                1.0,
                Par::Seq,
            );
            c
        })
        .collect();
    let mut sum = Mat::zeros(a.ncols(), b.ncols());
    for p in &parts {
        sum += p;
    }
    sum
}

/// `W += alpha V C` for tall `W` and `V` and a small `C`.
pub fn add_product(w: MatMut<'_, f64>, v: MatRef<'_, f64>, c: MatRef<'_, f64>, alpha: f64) {
    assert_eq!(
        w.nrows(),
        v.nrows(),
        "add_product: operands of different heights"
    );
    w.par_row_chunks_mut(ROWS)
        .enumerate()
        .for_each(|(k, rows)| {
            let r0 = k * ROWS;
            let h = rows.nrows();
            matmul(rows, Accum::Add, v.subrows(r0, h), c, alpha, Par::Seq);
        });
}

/// `dst <- src` for tall blocks of one shape.
pub fn copy(dst: MatMut<'_, f64>, src: MatRef<'_, f64>) {
    assert_eq!(
        (dst.nrows(), dst.ncols()),
        (src.nrows(), src.ncols()),
        "copy: shapes differ"
    );
    dst.par_row_chunks_mut(ROWS)
        .enumerate()
        .for_each(|(k, mut rows)| {
            let h = rows.nrows();
            rows.copy_from(src.subrows(k * ROWS, h));
        });
}

/// `W <- W R^-1` for tall `W` and a small upper-triangular `R` (the `Q` of
/// `W = Q R`), by chunks of rows: each row is a row-vector times `R^-1`.
pub fn div_upper(w: MatMut<'_, f64>, r: MatRef<'_, f64>) {
    let b = r.ncols();
    assert_eq!(w.ncols(), b, "div_upper: R does not fit W");
    w.par_row_chunks_mut(ROWS).for_each(|mut rows| {
        // x R = y for the row x: x_j = (y_j - sum_{i<j} x_i r_ij) / r_jj,
        // column by column over the chunk's rows.
        for j in 0..b {
            let d = r[(j, j)].recip();
            for i in 0..j {
                let rij = r[(i, j)];
                if rij != 0.0 {
                    let (src, dst) = rows.as_mut().split_at_col_mut(j);
                    let src = src.col(i);
                    for (y, &x) in dst.col_mut(0).iter_mut().zip(src.iter()) {
                        *y -= x * rij;
                    }
                }
            }
            for y in rows.as_mut().col_mut(j).iter_mut() {
                *y *= d;
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tall(n: usize, m: usize, seed: usize) -> Mat<f64> {
        Mat::from_fn(n, m, |i, j| {
            (((i * 31 + j * 17 + seed) % 97) as f64 - 48.0) / 7.0
        })
    }

    fn max_abs(a: MatRef<'_, f64>) -> f64 {
        let mut m = 0.0_f64;
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                m = m.max(a[(i, j)].abs());
            }
        }
        m
    }

    #[test]
    fn chunked_products_equal_plain_ones_whatever_the_threads() {
        let n = 3 * ROWS + 123;
        let (v, w) = (tall(n, 12, 1), tall(n, 5, 2));
        let c = tall(12, 5, 3);
        let plain_gram = v.transpose() * &w;
        let mut plain_add = w.clone();
        plain_add -= &v * &c;
        let mut results = vec![];
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let (g, a) = pool.install(|| {
                let g = gram(v.as_ref(), w.as_ref());
                let mut a = w.clone();
                add_product(a.as_mut(), v.as_ref(), c.as_ref(), -1.0);
                (g, a)
            });
            let scale = max_abs(plain_gram.as_ref());
            assert!(max_abs((&g - &plain_gram).as_ref()) <= 1e-13 * scale);
            assert!(max_abs((&a - &plain_add).as_ref()) <= 1e-13 * max_abs(plain_add.as_ref()));
            results.push((g, a));
        }
        // The same bits with any number of threads.
        for (g, a) in &results[1..] {
            assert_eq!(g, &results[0].0);
            assert_eq!(a, &results[0].1);
        }
    }

    #[test]
    fn dividing_by_the_triangle_undoes_multiplying_by_it() {
        let n = 2 * ROWS + 7;
        let q = tall(n, 6, 4);
        let r = Mat::from_fn(6, 6, |i, j| {
            if i > j {
                0.0
            } else if i == j {
                2.0 + i as f64
            } else {
                0.3 * (i + 2 * j) as f64 - 1.0
            }
        });
        let mut w = &q * &r;
        div_upper(w.as_mut(), r.as_ref());
        assert!(max_abs((&w - &q).as_ref()) <= 1e-12 * max_abs(q.as_ref()));
    }
}
