//! Arrays between flexbody and numpy: dense matrices become
//! Fortran-ordered numpy arrays over a buffer numpy owns (the one copy is
//! out of faer's padded columns); sparse matrices go out and come in as
//! the CSC arrays `indptr`, `indices`, `data` that `scipy.sparse.csc_array`
//! takes, checked on the way in (shape, order, finite, symmetric).

use crate::errors::invalid;
use faer::MatRef;
use flexbody::fem::{Dof, DofKind, DofMap};
use flexbody::linalg::sparse::Triplet;
use flexbody::linalg::SparseMat;
use numpy::npyffi::NPY_ORDER;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

/// `m` as a numpy array (Fortran order, so columns are contiguous as in
/// faer).
pub fn dense<'py>(py: Python<'py>, m: MatRef<'_, f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (rows, cols) = (m.nrows(), m.ncols());
    let mut data = Vec::with_capacity(rows * cols);
    for j in 0..cols {
        data.extend(m.col(j).iter().copied());
    }
    PyArray1::from_vec(py, data).reshape_with_order([rows, cols], NPY_ORDER::NPY_FORTRANORDER)
}

/// `rows` x `cols` values, row by row, as a C-ordered numpy array.
pub fn rows<'py, T: numpy::Element>(
    py: Python<'py>,
    data: Vec<T>,
    cols: usize,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let rows = data.len().checked_div(cols).unwrap_or(0);
    PyArray1::from_vec(py, data).reshape([rows, cols])
}

/// The DOFs as an `(n, 2)` int64 array: node id, then 1..6 for
/// ux, uy, uz, rx, ry, rz.
pub fn dof_rows<'py>(py: Python<'py>, dofs: &[Dof]) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let data: Vec<i64> = dofs
        .iter()
        .flat_map(|d| [d.node as i64, d.kind.index() as i64 + 1])
        .collect();
    rows(py, data, 2)
}

/// A sparse matrix as `(indptr, indices, data, n)`, CSC with int64
/// indices, for `scipy.sparse.csc_array((data, indices, indptr))`.
pub type CscParts<'py> = (
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<f64>>,
    usize,
);

/// `a` as [`CscParts`].
pub fn csc<'py>(py: Python<'py>, a: &SparseMat) -> CscParts<'py> {
    let n = a.ncols();
    let indptr: Vec<i64> = a.col_ptr().iter().map(|&p| p as i64).collect();
    let indices: Vec<i64> = a.row_idx().iter().map(|&i| i as i64).collect();
    let data: Vec<f64> = a.val().to_vec();
    (
        PyArray1::from_vec(py, indptr),
        PyArray1::from_vec(py, indices),
        PyArray1::from_vec(py, data),
        n,
    )
}

/// A square symmetric matrix `name` of `n` equations from CSC arrays
/// (duplicates summed): the shape, the index ranges and finite values are
/// checked, and the matrix must be symmetric to 1e-10 of its largest
/// entry (then the two triangles are averaged, as the Matrix Market reader
/// does); no diagonal entry may be negative (a stiffness, mass or damping
/// matrix is positive semi-definite).
pub fn symmetric_from_csc(
    name: &str,
    shape: (usize, usize),
    indptr: &[i64],
    indices: &[i64],
    data: &[f64],
) -> PyResult<SparseMat> {
    let (rows, cols) = shape;
    if rows != cols {
        return Err(invalid(format!(
            "{name} is {rows} x {cols}; it must be square"
        )));
    }
    let n = rows;
    if indptr.len() != n + 1 {
        return Err(invalid(format!(
            "{name}: indptr has {} entries for {n} columns; expected {}",
            indptr.len(),
            n + 1
        )));
    }
    if indices.len() != data.len() {
        return Err(invalid(format!(
            "{name}: {} row indices for {} values",
            indices.len(),
            data.len()
        )));
    }
    let nnz = data.len() as i64;
    if indptr[0] != 0 || indptr[n] != nnz || indptr.windows(2).any(|w| w[0] > w[1]) {
        return Err(invalid(format!(
            "{name}: indptr must rise from 0 to the number of entries ({nnz})"
        )));
    }
    let mut triplets = Vec::with_capacity(2 * data.len());
    let mut largest = 0.0_f64;
    for j in 0..n {
        for p in indptr[j] as usize..indptr[j + 1] as usize {
            let (i, v) = (indices[p], data[p]);
            if i < 0 || i as usize >= n {
                return Err(invalid(format!(
                    "{name}: row index {i} in column {j} is outside 0..{n}"
                )));
            }
            if !v.is_finite() {
                return Err(invalid(format!(
                    "{name}: entry ({i}, {j}) is {v}; every entry must be finite"
                )));
            }
            largest = largest.max(v.abs());
            triplets.push(Triplet::new(i as usize, j, v));
        }
    }
    let a = flexbody::linalg::sparse::from_triplets(n, n, &triplets)
        .map_err(|e| invalid(format!("{name}: {e}")))?;
    let at = a
        .as_ref()
        .transpose()
        .to_col_major()
        .map_err(|e| invalid(format!("{name}: {e:?}")))?;
    let (worst, at_entry) = largest_asymmetry(&a, &at);
    if worst > 1e-10 * largest {
        let (i, j) = at_entry;
        return Err(invalid(format!(
            "{name} is not symmetric: entries ({i}, {j}) and ({j}, {i}) differ by {worst:e} \
             (largest entry {largest:e}; at most 1e-10 of it is taken as round-off)"
        )));
    }
    for (i, d) in flexbody::linalg::sparse::diagonal(&a).iter().enumerate() {
        if *d < 0.0 {
            return Err(invalid(format!(
                "{name}: diagonal entry ({i}, {i}) is {d:e}; a stiffness, mass or damping \
                 matrix is positive semi-definite"
            )));
        }
    }
    let mut both = flexbody::linalg::sparse::triplets_of(&a, 0.5);
    both.extend(flexbody::linalg::sparse::triplets_of(&at, 0.5));
    flexbody::linalg::sparse::from_triplets(n, n, &both)
        .map_err(|e| invalid(format!("{name}: {e}")))
}

/// The largest `|a_ij - at_ij|` and where it is, both matrices CSC with
/// sorted rows.
fn largest_asymmetry(a: &SparseMat, at: &SparseMat) -> (f64, (usize, usize)) {
    let mut worst = (0.0, (0, 0));
    for j in 0..a.ncols() {
        let (ra, va) = (a.row_idx_of_col_raw(j), a.val_of_col(j));
        let (rb, vb) = (at.row_idx_of_col_raw(j), at.val_of_col(j));
        let (mut p, mut q) = (0, 0);
        while p < ra.len() || q < rb.len() {
            let (i, d) = match (ra.get(p), rb.get(q)) {
                (Some(&x), Some(&y)) if x == y => {
                    p += 1;
                    q += 1;
                    (x, va[p - 1] - vb[q - 1])
                }
                (Some(&x), Some(&y)) if x < y => {
                    p += 1;
                    (x, va[p - 1])
                }
                (Some(&x), None) => {
                    p += 1;
                    (x, va[p - 1])
                }
                (_, Some(&y)) => {
                    q += 1;
                    (y, -vb[q - 1])
                }
                (None, None) => break,
            };
            if d.abs() > worst.0 {
                worst = (d.abs(), (i, j));
            }
        }
    }
    worst
}

/// A DOF map from an `(n, 2)` array of node ids and DOF numbers 1..6;
/// a DOF listed twice, a negative node or a number outside 1..6 is named.
pub fn dof_map(flat: &[i64]) -> PyResult<DofMap> {
    if !flat.len().is_multiple_of(2) {
        return Err(invalid("dofs must be an (n, 2) array: node id, DOF 1..6"));
    }
    let mut dofs = Vec::with_capacity(flat.len() / 2);
    let mut seen = std::collections::HashSet::new();
    for (row, pair) in flat.chunks_exact(2).enumerate() {
        let (node, number) = (pair[0], pair[1]);
        if node < 0 {
            return Err(invalid(format!("dofs row {row}: node {node} is negative")));
        }
        let kind = usize::try_from(number - 1)
            .ok()
            .and_then(|k| DofKind::ALL.get(k).copied())
            .ok_or_else(|| {
                invalid(format!(
                    "dofs row {row}: DOF {number} of node {node} is not one of 1..6 (ux, uy, uz, rx, ry, rz)"
                ))
            })?;
        let dof = Dof::new(node as u64, kind);
        if !seen.insert(dof) {
            return Err(invalid(format!("dofs row {row}: {dof} is listed twice")));
        }
        dofs.push(dof);
    }
    Ok(DofMap::new(dofs))
}

/// Node ids and coordinates as the arrays `(ids (k,), xyz (k, 3))`,
/// ascending by id.
pub type NodeArrays<'py> = (Bound<'py, PyArray1<i64>>, Bound<'py, PyArray2<f64>>);

/// `nodes` as [`NodeArrays`], sorted by id.
pub fn node_arrays(py: Python<'_>, mut nodes: Vec<(u64, [f64; 3])>) -> PyResult<NodeArrays<'_>> {
    nodes.sort_by_key(|n| n.0);
    let ids = nodes.iter().map(|n| n.0 as i64).collect();
    let xyz = nodes.iter().flat_map(|n| n.1).collect();
    Ok((PyArray1::from_vec(py, ids), rows(py, xyz, 3)?))
}

/// The nodes of a component with their coordinates: every node of its
/// mesh, or the nodes matrices were given coordinates for.
pub fn component_nodes(c: &flexbody::input::Component) -> Vec<(u64, [f64; 3])> {
    match &c.model {
        Some(m) => m.nodes().iter().map(|n| (n.id, n.coords)).collect(),
        None => c.sub.coordinates.iter().map(|(&id, &x)| (id, x)).collect(),
    }
}
