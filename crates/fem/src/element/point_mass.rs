//! Point mass with rotary inertia, on the DOFs its node has.

use super::VtkCell;
use super::{ElementBehaviour, ElementMatrices, ElementType, SectionKind, SectionValues};
use crate::dof::{Dof, DofKind};
use crate::model::{Model, NodeId};
use crate::FemError;
use faer::Mat;

/// The deck's MASS: a point mass without rotary inertia.
pub(super) const ELEMENT_TYPES: &[ElementType] = &[ElementType {
    name: "MASS",
    nodes: 1,
    section: SectionKind::Mass,
    reference_nodes: &[[0.0, 0.0, 0.0]],
    build: |id, nodes, section| match (section, nodes) {
        (SectionValues::Mass { mass }, &[node]) => Ok(PointMass {
            id,
            node,
            mass: *mass,
            inertia: [0.0; 6],
        }
        .into()),
        _ => Err(super::registry::wrong_section("MASS", id, section)),
    },
}];

/// A lumped mass `mass` (kg) and inertia tensor (kg m^2, about the node, in
/// global axes: `[ixx, iyy, izz, ixy, iyz, ixz]`).
#[derive(Clone, Debug, PartialEq)]
pub struct PointMass {
    pub id: usize,
    pub node: NodeId,
    pub mass: f64,
    pub inertia: [f64; 6],
}

impl ElementBehaviour for PointMass {
    fn id(&self) -> usize {
        self.id
    }

    fn nodes(&self) -> Vec<NodeId> {
        vec![self.node]
    }

    fn dofs(&self) -> Vec<Dof> {
        DofKind::ALL
            .into_iter()
            .map(|k| Dof::new(self.node, k))
            .collect()
    }

    /// A point mass only loads the DOFs other elements give its node.
    fn creates_dofs(&self) -> bool {
        false
    }

    /// Mass on the node's existing DOFs (translations: `mass`, rotations:
    /// the inertia tensor restricted to the rotations present).
    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
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
        Ok(ElementMatrices {
            dofs: present
                .into_iter()
                .map(|k| Dof::new(self.node, k))
                .collect(),
            stiffness: Mat::zeros(n, n),
            mass,
        })
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(VtkCell::VERTEX)
    }
}
