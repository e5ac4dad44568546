//! Point mass with rotary inertia, on the DOFs its node has.

use super::ElementMatrices;
use crate::dof::{Dof, DofKind};
use crate::model::{Model, NodeId};
use faer::Mat;

/// A lumped mass `mass` (kg) and inertia tensor (kg m^2, about the node, in
/// global axes: `[ixx, iyy, izz, ixy, iyz, ixz]`).
#[derive(Clone, Debug, PartialEq)]
pub struct PointMass {
    pub id: usize,
    pub node: NodeId,
    pub mass: f64,
    pub inertia: [f64; 6],
}

impl PointMass {
    pub(crate) fn dofs(&self) -> Vec<Dof> {
        DofKind::ALL
            .into_iter()
            .map(|k| Dof::new(self.node, k))
            .collect()
    }

    /// Mass on the node's existing DOFs (translations: `mass`, rotations:
    /// the inertia tensor restricted to the rotations present).
    pub(crate) fn matrices(&self, model: &Model) -> ElementMatrices {
        let present: Vec<DofKind> = model
            .dof_map()
            .node_dofs(self.node)
            .into_iter()
            .map(|(k, _)| k)
            .collect();
        let [ixx, iyy, izz, ixy, iyz, ixz] = self.inertia;
        let tensor = [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]];
        let n = present.len();
        let mass = Mat::from_fn(n, n, |i, j| {
            let (a, b) = (present[i], present[j]);
            match (a.is_rotation(), b.is_rotation()) {
                (false, false) if a == b => self.mass,
                (true, true) => tensor[a.index() - 3][b.index() - 3],
                _ => 0.0,
            }
        });
        ElementMatrices {
            dofs: present
                .into_iter()
                .map(|k| Dof::new(self.node, k))
                .collect(),
            stiffness: Mat::zeros(n, n),
            mass,
        }
    }
}
