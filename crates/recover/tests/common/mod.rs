//! Shared by the verification tests: dense copies of the assembled
//! matrices and a Gaussian elimination, so that the full model is solved
//! without the library's own solvers.

#![allow(dead_code)]

use flexbody_fem::{assemble, Dof, Model};

/// The assembled stiffness and mass of `model` as dense row-major matrices
/// over its equations.
pub fn dense_matrices(model: &Model) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let s = assemble(model).unwrap();
    let dense = |a: &flexbody_fem::assembly::SystemMatrices, stiffness: bool| {
        let m = if stiffness { &a.stiffness } else { &a.mass };
        let n = m.nrows();
        let mut d = vec![vec![0.0; n]; n];
        let r = m.as_ref();
        let entries = (0..n).flat_map(|j| {
            r.row_idx_of_col(j)
                .zip(r.val_of_col(j))
                .map(move |(i, v)| (i, j, *v))
        });
        for (i, j, v) in entries {
            d[i][j] += v;
        }
        d
    };
    (dense(&s, true), dense(&s, false))
}

/// `A x`.
pub fn mat_vec(a: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
    a.iter()
        .map(|row| row.iter().zip(x).map(|(p, q)| p * q).sum())
        .collect()
}

/// Solves `A x = b` by Gaussian elimination with partial pivoting.
pub fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for k in 0..n {
        let p = (k..n)
            .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
            .unwrap();
        assert!(a[p][k] != 0.0, "singular matrix at column {k}");
        a.swap(k, p);
        b.swap(k, p);
        let bk = b[k];
        let (top, bottom) = a.split_at_mut(k + 1);
        let pivot = &top[k];
        for (row, bi) in bottom.iter_mut().zip(&mut b[k + 1..]) {
            let f = row[k] / pivot[k];
            if f != 0.0 {
                for (x, p) in row[k..].iter_mut().zip(&pivot[k..]) {
                    *x -= f * p;
                }
                *bi -= f * bk;
            }
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|j| a[k][j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k][k];
    }
    x
}

/// A load vector over the model's equations from `(DOF, value)` pairs
/// (several pairs on one DOF add up).
pub fn load_vector(model: &Model, loads: &[(Dof, f64)]) -> Vec<f64> {
    let mut f = vec![0.0; model.dof_map().len()];
    for (d, v) in loads {
        f[model.equation(*d, "test load").unwrap()] += v;
    }
    f
}

/// The static solution `K u = f` of the full model.
pub fn static_solution(model: &Model, loads: &[(Dof, f64)]) -> Vec<f64> {
    let (k, _) = dense_matrices(model);
    solve(k, load_vector(model, loads))
}

/// Largest absolute value.
pub fn max_abs(v: impl IntoIterator<Item = f64>) -> f64 {
    v.into_iter().fold(0.0, |m, x| m.max(x.abs()))
}
