//! Nodal coordinate systems (CalculiX/Abaqus `*TRANSFORM`): at a
//! transformed node, the DOFs that boundary conditions and equations name
//! are along the node's local axes. The model itself stays in global DOFs,
//! as CalculiX keeps it: a fixed local DOF becomes a homogeneous equation
//! among the node's global DOFs, and a local term of an equation becomes
//! global terms. The constraints are then eliminated like every other
//! [`Equation`].
//!
//! `R` is the matrix whose columns are the local axes in global components
//! (as [`crate::Orientation::axes_at`] gives it): the local component `i`
//! of a nodal vector `u` is `u_i' = sum_j R_ji u_j`. Rotations turn like
//! translations.

use crate::constraint::Equation;
use crate::dof::{Dof, DofKind};
use crate::model::NodeId;

/// Coefficients smaller than this (relative to the largest of a row, which
/// is 1 after scaling) are round-off of axes that lie along global ones.
const ROUND_OFF: f64 = 1e-12;

/// The global DOFs of the same family (translations or rotations) as
/// `kind`, in x, y, z order.
pub fn family(kind: DofKind) -> [DofKind; 3] {
    let first = if kind.is_rotation() { 3 } else { 0 };
    std::array::from_fn(|j| DofKind::ALL[first + j])
}

/// A local term `c u_i'` at `node` with axes `r` as global terms
/// `sum_j c R_ji u_j`, the largest first (so that it is the dependent DOF
/// when the term leads an equation); terms that are round-off are dropped.
pub fn local_term(node: NodeId, r: &[[f64; 3]; 3], kind: DofKind, c: f64) -> Vec<(Dof, f64)> {
    let i = kind.index() % 3;
    let mut terms: Vec<(Dof, f64)> = family(kind)
        .into_iter()
        .enumerate()
        .map(|(j, k)| (Dof::new(node, k), c * r[j][i]))
        .filter(|(_, v)| v.abs() > ROUND_OFF * c.abs())
        .collect();
    terms.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    terms
}

/// The local DOFs `kinds` of `node`, with axes `r`, held at zero: the
/// global DOFs this fixes outright (a local axis along a global one) and
/// the equations among the others (named `name`).
///
/// The rows `u_i' = 0` of each family are brought to reduced row echelon
/// form with the largest pivot first, so that every equation has its own
/// dependent global DOF, which appears in no other equation of the node.
pub fn fixed_local(
    node: NodeId,
    r: &[[f64; 3]; 3],
    kinds: &[DofKind],
    name: &str,
) -> (Vec<Dof>, Vec<Equation>) {
    let mut fixed = Vec::new();
    let mut equations = Vec::new();
    for rotations in [false, true] {
        let axes: std::collections::BTreeSet<usize> = kinds
            .iter()
            .filter(|k| k.is_rotation() == rotations)
            .map(|k| k.index() % 3)
            .collect();
        let mut rows: Vec<[f64; 3]> = axes.iter().map(|&i| [r[0][i], r[1][i], r[2][i]]).collect();
        let Some(&first) = kinds.iter().find(|k| k.is_rotation() == rotations) else {
            continue;
        };
        let dofs = family(first);
        let mut pivots: Vec<usize> = Vec::new();
        for k in 0..rows.len() {
            // The largest remaining entry of the remaining rows.
            let mut best = (k, 0, 0.0_f64);
            for (p, row) in rows.iter().enumerate().skip(k) {
                for (c, v) in row.iter().enumerate() {
                    if !pivots.contains(&c) && v.abs() > best.2 {
                        best = (p, c, v.abs());
                    }
                }
            }
            let (p, c, size) = best;
            if size <= ROUND_OFF {
                break;
            }
            rows.swap(k, p);
            let pivot = rows[k][c];
            rows[k] = rows[k].map(|v| v / pivot);
            for q in 0..rows.len() {
                if q != k {
                    let f = rows[q][c];
                    let row_k = rows[k];
                    for (v, vk) in rows[q].iter_mut().zip(row_k) {
                        *v -= f * vk;
                    }
                }
            }
            pivots.push(c);
        }
        for (row, &c) in rows.iter().zip(&pivots) {
            let others: Vec<(Dof, f64)> = (0..3)
                .filter(|&j| j != c && row[j].abs() > ROUND_OFF)
                .map(|j| (Dof::new(node, dofs[j]), row[j]))
                .collect();
            if others.is_empty() {
                fixed.push(Dof::new(node, dofs[c]));
            } else {
                let mut terms = vec![(Dof::new(node, dofs[c]), 1.0)];
                terms.extend(others);
                equations.push(Equation {
                    name: name.to_string(),
                    terms,
                });
            }
        }
    }
    (fixed, equations)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Orientation;

    /// The null space of the constraints: the global displacements they
    /// allow. Checked against the local axes left free.
    fn allowed(fixed: &[Dof], equations: &[Equation], u: [f64; 3]) -> bool {
        let at = |d: &Dof| u[d.kind.index() % 3];
        fixed.iter().all(|d| at(d).abs() < 1e-12)
            && equations
                .iter()
                .all(|e| e.terms.iter().map(|(d, c)| c * at(d)).sum::<f64>().abs() < 1e-12)
    }

    #[test]
    fn local_fixed_dofs_allow_exactly_the_free_local_axes() {
        // A cylindrical system at a point off the axis: no axis is global.
        let o = Orientation::cylindrical([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]).unwrap();
        let r = o.axes_at([0.3, -0.4, 1.1]).unwrap();
        let axis = |i: usize| [r[0][i], r[1][i], r[2][i]];
        let all = [DofKind::Ux, DofKind::Uy, DofKind::Uz];
        for held in [
            vec![0],
            vec![1],
            vec![2],
            vec![0, 2],
            vec![1, 2],
            vec![0, 1, 2],
        ] {
            let kinds: Vec<DofKind> = held.iter().map(|&i| all[i]).collect();
            let (fixed, eqs) = fixed_local(7, &r, &kinds, "t");
            // One constraint per held axis, each with its own dependent.
            assert_eq!(fixed.len() + eqs.len(), held.len());
            let mut dependents: Vec<Dof> = fixed.clone();
            dependents.extend(eqs.iter().map(|e| e.terms[0].0));
            dependents.sort();
            dependents.dedup();
            assert_eq!(dependents.len(), held.len());
            for e in &eqs {
                assert!(e.terms[1..].iter().all(|(d, _)| !dependents.contains(d)));
            }
            for i in 0..3 {
                let free = !held.contains(&i);
                assert_eq!(
                    allowed(&fixed, &eqs, axis(i)),
                    free,
                    "held {held:?}, axis {i}"
                );
            }
        }
    }

    #[test]
    fn an_axis_along_a_global_one_fixes_that_dof_and_rotations_turn_alike() {
        // Local 1 along global y, local 2 along -x, local 3 along z.
        let o = Orientation::rectangular([0.0, 2.0, 0.0], [-1.0, 0.0, 0.0]).unwrap();
        let r = o.axes_at([0.0; 3]).unwrap();
        let (fixed, eqs) = fixed_local(3, &r, &[DofKind::Ux, DofKind::Rz], "t");
        assert!(eqs.is_empty());
        assert_eq!(
            fixed,
            vec![Dof::new(3, DofKind::Uy), Dof::new(3, DofKind::Rz)]
        );
        // A local term becomes the global term of the same axis.
        assert_eq!(
            local_term(3, &r, DofKind::Ry, 2.0),
            vec![(Dof::new(3, DofKind::Rx), -2.0)]
        );
    }
}
