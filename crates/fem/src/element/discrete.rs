//! What springs and dashpots share: the DOFs of a scalar element (one DOF
//! to ground or two DOFs), the direction of an axial one, and their
//! matrices, `c [1 -1; -1 1]` (or `[c]`) and `c [e e^T, -e e^T; -e e^T,
//! e e^T]`, which become a stiffness or a damping.

use super::axis;
use crate::dof::{Dof, DofKind};
use crate::model::{Model, NodeId};
use crate::FemError;
use faer::Mat;

/// The DOFs of a scalar `what` (spring, dashpot) of element `id` on
/// `nodes`: the first node's `dofs[0]`, and with `between` the second
/// node's `dofs[1]`.
pub(super) fn scalar_dofs(
    what: &str,
    id: usize,
    nodes: &[NodeId],
    dofs: &[Option<DofKind>; 2],
    between: bool,
) -> Result<(Dof, Option<Dof>), FemError> {
    let dof =
        |node: Option<&NodeId>, kind: Option<DofKind>| node.zip(kind).map(|(n, k)| Dof::new(*n, k));
    let missing = |reason: String| FemError::InvalidElement {
        element: id,
        reason,
    };
    let first =
        dof(nodes.first(), dofs[0]).ok_or_else(|| missing(format!("{what} without a DOF")))?;
    let second = if between {
        Some(
            dof(nodes.get(1), dofs[1])
                .ok_or_else(|| missing(format!("{what} without a second DOF")))?,
        )
    } else {
        None
    };
    Ok((first, second))
}

/// The nodes of a scalar element's DOFs.
pub(super) fn scalar_nodes(first: Dof, second: Option<Dof>) -> Vec<NodeId> {
    std::iter::once(first.node)
        .chain(second.map(|d| d.node))
        .collect()
}

/// The DOFs of a scalar element, first then second.
pub(super) fn scalar_element_dofs(first: Dof, second: Option<Dof>) -> Vec<Dof> {
    std::iter::once(first).chain(second).collect()
}

/// `c [1 -1; -1 1]` on two DOFs, `[c]` on one.
pub(super) fn scalar_matrix(c: f64, n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| if i == j { c } else { -c })
}

/// The unit direction from the first of `nodes` to the second; an error
/// for coincident nodes.
pub(super) fn line_direction(
    model: &Model,
    id: usize,
    nodes: [NodeId; 2],
) -> Result<[f64; 3], FemError> {
    let (l, e) = axis(model.coords(nodes[0]), model.coords(nodes[1]));
    if l.is_nan() || l <= 0.0 {
        return Err(FemError::ZeroLength { element: id });
    }
    Ok(e)
}

/// `c [e e^T, -e e^T; -e e^T, e e^T]` on the two nodes' translations.
pub(super) fn axial_matrix(c: f64, e: [f64; 3]) -> Mat<f64> {
    Mat::from_fn(6, 6, |i, j| {
        let sign = if (i < 3) == (j < 3) { 1.0 } else { -1.0 };
        sign * c * e[i % 3] * e[j % 3]
    })
}
