//! Local axes at nodes (`*TRANSFORM`) as a change of basis of the
//! equations, for a reduction whose interface names local DOFs.
//!
//! An [`Axes`] `R` holds the local axes in its columns, in global
//! components (as [`crate::Orientation::axes_at`] gives them): a nodal
//! vector with global components `u` has the local components `u' = R^T u`,
//! and `u = R u'`. Rotations turn like translations. Over all equations the
//! change of basis is `u = T u'`, where `T` is the identity except for the
//! 3x3 blocks `R` on the translations and on the rotations of each node with
//! local axes. `T` is orthogonal: `K' = T^T K T` and `M' = T^T M T` have
//! the eigenvalues of K and M, and a Ritz basis `Phi'` over local DOFs is
//! `Phi = T Phi'` over the global ones, with the same reduced matrices
//! (eq. 5-7).

use crate::dof::{Dof, DofKind, DofMap};
use crate::model::NodeId;
use crate::transform::family;
use crate::FemError;
use faer::Mat;
use flexbody_linalg::sparse::{from_triplets, Triplet};
use flexbody_linalg::SparseMat;
use std::collections::BTreeMap;

/// The local axes of a node: column `i` is local axis `i` in global
/// components.
pub type Axes = [[f64; 3]; 3];

/// How far `R^T R` may be from the identity, entry by entry.
const ORTHONORMAL: f64 = 1e-9;

/// Checks that the axes of `node` are finite and orthonormal.
pub fn check_axes(node: NodeId, r: &Axes) -> Result<(), FemError> {
    let column = |i: usize| [r[0][i], r[1][i], r[2][i]];
    for i in 0..3 {
        for j in 0..3 {
            let (a, b) = (column(i), column(j));
            let dot: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            let expected = if i == j { 1.0 } else { 0.0 };
            if !dot.is_finite() || (dot - expected).abs() > ORTHONORMAL {
                return Err(FemError::InvalidValue {
                    what: format!(
                        "local axes of node {node}: product of axes {} and {}",
                        i + 1,
                        j + 1
                    ),
                    rule: "that of orthonormal axes (1 for an axis with itself, 0 for two)",
                    value: dot,
                });
            }
        }
    }
    Ok(())
}

/// One 3x3 block of `T`: the equations of a node's x, y and z translations
/// (or rotations) and the node's axes.
#[derive(Clone, Debug)]
struct Block {
    equations: [usize; 3],
    axes: Axes,
}

/// The change of basis `u = T u'` over the equations of a DOF map, for the
/// nodes given local axes.
#[derive(Clone, Debug, Default)]
pub struct AxesChange {
    blocks: Vec<Block>,
}

impl AxesChange {
    /// The change of basis for the nodes of `axes` in `map`. A node whose
    /// translations (or rotations) are in the map only in part (one held
    /// by a boundary condition or eliminated by a constraint) has no local
    /// components of them, and is refused, naming the node and the DOF
    /// that is not free. Nodes without DOFs in `map` are left out.
    pub fn new(map: &DofMap, axes: &BTreeMap<NodeId, Axes>) -> Result<Self, FemError> {
        let mut blocks = Vec::new();
        for (&node, r) in axes {
            check_axes(node, r)?;
            for first in [DofKind::Ux, DofKind::Rx] {
                let kinds = family(first);
                let equations = kinds.map(|k| map.index_of(Dof::new(node, k)));
                if equations.iter().all(Option::is_none) {
                    continue;
                }
                if let Some(k) = kinds.iter().zip(&equations).find(|(_, e)| e.is_none()) {
                    let family = if first.is_rotation() {
                        "rotations"
                    } else {
                        "translations"
                    };
                    return Err(FemError::LocalAxes(format!(
                        "node {node} (*TRANSFORM): its {} is held or eliminated by a \
                         constraint, and DOFs along its local axes need all three {family} free",
                        k.0
                    )));
                }
                blocks.push(Block {
                    equations: equations.map(|e| e.unwrap_or_default()),
                    axes: *r,
                });
            }
        }
        Ok(Self { blocks })
    }

    /// True if no equation changes.
    pub fn is_identity(&self) -> bool {
        self.blocks.is_empty()
    }

    /// The nonzero entries `(a, T_ia)` of row `i` of `T`, for every row.
    fn rows(&self, n: usize) -> Vec<Vec<(usize, f64)>> {
        let mut rows: Vec<Vec<(usize, f64)>> = (0..n).map(|i| vec![(i, 1.0)]).collect();
        for b in &self.blocks {
            for (j, &row) in b.equations.iter().enumerate() {
                rows[row] = b
                    .equations
                    .iter()
                    .enumerate()
                    .map(|(k, &col)| (col, b.axes[j][k]))
                    .filter(|(_, v)| *v != 0.0)
                    .collect();
            }
        }
        rows
    }

    /// `T^T a T` for a symmetric `a` with both triangles stored; the result
    /// is symmetric to the bit (its lower triangle mirrored).
    pub fn congruence(&self, a: &SparseMat) -> Result<SparseMat, FemError> {
        let n = a.nrows();
        if self.is_identity() {
            return Ok(a.clone());
        }
        let rows = self.rows(n);
        let r = a.as_ref();
        let mut lower = Vec::with_capacity(r.compute_nnz());
        for j in 0..n {
            for (i, v) in r.row_idx_of_col(j).zip(r.val_of_col(j)) {
                for &(p, ti) in &rows[i] {
                    for &(q, tj) in &rows[j] {
                        if p >= q {
                            lower.push(Triplet::new(p, q, (ti * tj) * v));
                        }
                    }
                }
            }
        }
        let lower = from_triplets(n, n, &lower)?;
        let l = lower.as_ref();
        let mut full = Vec::with_capacity(2 * l.compute_nnz());
        for j in 0..n {
            for (i, v) in l.row_idx_of_col(j).zip(l.val_of_col(j)) {
                full.push(Triplet::new(i, j, *v));
                if i != j {
                    full.push(Triplet::new(j, i, *v));
                }
            }
        }
        Ok(from_triplets(n, n, &full)?)
    }

    /// Rows of `x` (one per equation) from global to local components:
    /// `x <- T^T x`.
    pub fn rows_to_local(&self, x: &mut Mat<f64>) {
        self.turn_rows(x, true);
    }

    /// Rows of `x` (one per equation) from local to global components:
    /// `x <- T x`.
    pub fn rows_to_global(&self, x: &mut Mat<f64>) {
        self.turn_rows(x, false);
    }

    fn turn_rows(&self, x: &mut Mat<f64>, to_local: bool) {
        for b in &self.blocks {
            for c in 0..x.ncols() {
                let v = b.equations.map(|e| x[(e, c)]);
                for (i, &e) in b.equations.iter().enumerate() {
                    x[(e, c)] = (0..3)
                        .map(|j| {
                            let t = if to_local { b.axes[j][i] } else { b.axes[i][j] };
                            t * v[j]
                        })
                        .sum();
                }
            }
        }
    }
}

/// The local components `u' = R^T u` of the rows `global` (x, y, z of one
/// family, each a row over some columns): row `i` of the result is
/// `sum_j R_ji global_j`.
pub fn rows_along(r: &Axes, global: [&[f64]; 3]) -> [Vec<f64>; 3] {
    std::array::from_fn(|i| {
        (0..global[0].len())
            .map(|c| (0..3).map(|j| r[j][i] * global[j][c]).sum())
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Orientation;
    use flexbody_linalg::sparse::to_dense;

    fn map_of(nodes: &[NodeId], kinds: &[DofKind]) -> DofMap {
        DofMap::new(
            nodes
                .iter()
                .flat_map(|&n| kinds.iter().map(move |&k| Dof::new(n, k)))
                .collect(),
        )
    }

    #[test]
    fn the_congruence_equals_the_dense_product_and_turning_rows_back_restores_them() {
        let r = Orientation::cylindrical([0.0; 3], [0.2, 1.0, 0.3])
            .unwrap()
            .axes_at([0.7, -0.1, 0.4])
            .unwrap();
        let map = map_of(&[1, 2], &DofKind::ALL);
        let change = AxesChange::new(&map, &BTreeMap::from([(2, r)])).unwrap();
        let n = map.len();
        // A symmetric matrix with every entry set.
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let v = 1.0 / (1.0 + (i + j) as f64) + if i == j { 3.0 } else { 0.0 };
                t.push(Triplet::new(i, j, v));
            }
        }
        let a = from_triplets(n, n, &t).unwrap();
        let mut tm = Mat::<f64>::identity(n, n);
        change.rows_to_global(&mut tm);
        let expected = tm.transpose() * to_dense(&a) * &tm;
        let got = to_dense(&change.congruence(&a).unwrap());
        assert!((&got - &expected).norm_max() < 1e-14 * expected.norm_max());
        assert_eq!(got, got.transpose().to_owned(), "symmetric to the bit");
        // T is orthogonal: T^T T = I.
        let gram = tm.transpose() * &tm;
        assert!((&gram - Mat::<f64>::identity(n, n)).norm_max() < 1e-15);
        let x = Mat::from_fn(n, 2, |i, j| (i * 3 + j) as f64 - 4.0);
        let mut y = x.clone();
        change.rows_to_local(&mut y);
        assert!((&y - tm.transpose() * &x).norm_max() < 1e-13);
        change.rows_to_global(&mut y);
        assert!((&y - &x).norm_max() < 1e-13);
    }

    #[test]
    fn a_node_with_one_translation_held_has_no_local_axes() {
        let map = DofMap::new(vec![Dof::new(4, DofKind::Ux), Dof::new(4, DofKind::Uz)]);
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let err = AxesChange::new(&map, &BTreeMap::from([(4, id)])).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("node 4") && text.contains("uy"), "{text}");
        let skew = [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let err = AxesChange::new(&map_of(&[4], &DofKind::ALL), &BTreeMap::from([(4, skew)]));
        assert!(err.unwrap_err().to_string().contains("orthonormal"));
    }
}
