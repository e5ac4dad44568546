//! Static mode types by dense linear algebra, written from the report's
//! equations and independent of the library's sparse factorisations: the
//! references the reduction methods' shared paths are held against.

use faer::linalg::solvers::Solve;
use faer::Mat;
use flexbody_linalg::{sparse, SparseMat};
use flexbody_reduce::modes::RigidModes;

/// `A^-1 B` by faer's dense LU with partial pivoting.
fn dense_solve(a: &SparseMat, b: &Mat<f64>) -> Mat<f64> {
    a.to_dense().partial_piv_lu().solve(b)
}

/// Equations of `0..n` not in `taken`.
fn others(taken: &[usize], n: usize) -> Vec<usize> {
    (0..n).filter(|i| !taken.contains(i)).collect()
}

/// Constraint modes `[I; -K_NN^-1 K_NH]` with the sorting undone (report
/// eq. 15-17).
pub fn constraint_modes(k: &SparseMat, boundary: &[usize]) -> Mat<f64> {
    let n = k.nrows();
    let interior = others(boundary, n);
    let k_nn = sparse::submatrix(k, &interior, &interior);
    let k_nh = sparse::submatrix(k, &interior, boundary).to_dense();
    let u_n = dense_solve(&k_nn, &(-k_nh));
    let mut t = Mat::zeros(n, boundary.len());
    for (j, &h) in boundary.iter().enumerate() {
        t[(h, j)] = 1.0;
        for (r, &i) in interior.iter().enumerate() {
            t[(i, j)] = u_n[(r, j)];
        }
    }
    t
}

/// Attachment modes `K^-1 P_1` of a supported body (eq. 18).
pub fn attachment_modes(k: &SparseMat, loads: &Mat<f64>) -> Mat<f64> {
    dense_solve(k, loads)
}

/// Inertia-relief attachment modes (eq. 18-20): the loads in equilibrium
/// with their rigid-body inertia, `P_g = (I - M T T^T) P_1`, solved on the
/// `support` held, and the rigid part removed, `G x = x - T T^T M x` (`T`
/// M-orthonormal).
pub fn inertia_relief_attachment_modes(
    k: &SparseMat,
    m: &SparseMat,
    rigid: &RigidModes,
    loads: &Mat<f64>,
    support: &[usize],
) -> Mat<f64> {
    let n = k.nrows();
    let t = &rigid.vectors;
    let m_dense = m.to_dense();
    let p_g = loads - &m_dense * t * (t.transpose() * loads);
    let free = others(support, n);
    let k_ff = sparse::submatrix(k, &free, &free);
    let p_f = Mat::from_fn(free.len(), loads.ncols(), |i, j| p_g[(free[i], j)]);
    let x_f = dense_solve(&k_ff, &p_f);
    let mut x = Mat::zeros(n, loads.ncols());
    for (r, &i) in free.iter().enumerate() {
        for j in 0..loads.ncols() {
            x[(i, j)] = x_f[(r, j)];
        }
    }
    &x - t * (t.transpose() * (&m_dense * &x))
}
