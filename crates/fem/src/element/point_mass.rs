//! Point mass with rotary inertia, on the DOFs its node has.

use super::VtkCell;
use super::{
    ElementBehaviour, ElementMatrices, ElementType, MassDistribution, MassPoint, SectionKind,
    SectionValues,
};
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

    /// The mass finite and not negative, the inertia tensor finite and
    /// positive semi-definite.
    fn validate(&self, _model: &Model) -> Result<(), FemError> {
        crate::require_non_negative(format!("mass of point mass {}", self.id), self.mass)?;
        crate::require_inertia(format!("inertia of point mass {}", self.id), self.inertia)
    }

    /// Mass on the node's six DOFs (translations: `mass`, rotations: the
    /// inertia tensor); the assembler drops those the model does not have.
    fn matrices(&self, _model: &Model) -> Result<ElementMatrices, FemError> {
        let [ixx, iyy, izz, ixy, iyz, ixz] = self.inertia;
        let tensor = [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]];
        let mass = Mat::from_fn(6, 6, |i, j| match (i < 3, j < 3) {
            (true, true) if i == j => self.mass,
            (false, false) => tensor[i - 3][j - 3],
            _ => 0.0,
        });
        Ok(ElementMatrices {
            dofs: self.dofs(),
            stiffness: Mat::zeros(6, 6),
            mass,
            damping: None,
        })
    }

    /// One rigid point at the node: its mass and inertia tensor.
    fn mass_distribution(&self, model: &Model) -> Result<MassDistribution, FemError> {
        let [ixx, iyy, izz, ixy, iyz, ixz] = self.inertia;
        Ok(MassDistribution::Points(vec![MassPoint {
            position: model.coords(self.node),
            mass: self.mass,
            inertia: [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]],
            translation: Mat::from_fn(3, 6, |i, j| f64::from(u8::from(j == i))),
            rotation: Mat::from_fn(3, 6, |i, j| f64::from(u8::from(j == i + 3))),
        }]))
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(VtkCell::VERTEX)
    }
}
