//! Scalar spring between two DOFs, or from one DOF to ground; and the
//! spring along the line between two nodes.

use super::discrete::{
    axial_matrix, line_direction, scalar_dofs, scalar_element_dofs, scalar_matrix, scalar_nodes,
};
use super::registry::wrong_section;
use super::{node_dofs, Element, ElementBehaviour, ElementMatrices, ElementType, SectionKind};
use super::{SectionValues, VtkCell, TRANSLATIONS};
use crate::dof::Dof;
use crate::model::{Model, NodeId};
use crate::FemError;
use faer::Mat;

/// The deck's springs: SPRINGA along the line between its nodes, SPRING1
/// from one DOF to ground, SPRING2 between two DOFs.
pub(super) const ELEMENT_TYPES: &[ElementType] = &[
    ElementType {
        name: "SPRINGA",
        nodes: 2,
        section: SectionKind::Spring { dofs: 0 },
        reference_nodes: &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
        build: |id, nodes, section| match (section, nodes) {
            (SectionValues::Spring { stiffness, .. }, &[a, b]) => Ok(AxialSpring {
                id,
                nodes: [a, b],
                stiffness: *stiffness,
            }
            .into()),
            _ => Err(wrong_section("SPRINGA", id, section)),
        },
    },
    ElementType {
        name: "SPRING1",
        nodes: 1,
        section: SectionKind::Spring { dofs: 1 },
        reference_nodes: &[[0.0, 0.0, 0.0]],
        build: |id, nodes, section| scalar_spring("SPRING1", id, nodes, section, false),
    },
    ElementType {
        name: "SPRING2",
        nodes: 2,
        section: SectionKind::Spring { dofs: 2 },
        reference_nodes: &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
        build: |id, nodes, section| scalar_spring("SPRING2", id, nodes, section, true),
    },
];

/// A SPRING1 (`between: false`) or SPRING2 on the DOFs of its section.
fn scalar_spring(
    name: &str,
    id: usize,
    nodes: &[NodeId],
    section: &SectionValues,
    between: bool,
) -> Result<Element, FemError> {
    let SectionValues::Spring { dofs, stiffness } = section else {
        return Err(wrong_section(name, id, section));
    };
    let (first, second) = scalar_dofs("spring", id, nodes, dofs, between)?;
    Ok(Spring {
        id,
        first,
        second,
        stiffness: *stiffness,
    }
    .into())
}

/// Spring of stiffness `stiffness` (N/m, or N m/rad on rotations).
#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    pub id: usize,
    pub first: Dof,
    /// `None`: grounded spring.
    pub second: Option<Dof>,
    pub stiffness: f64,
}

impl ElementBehaviour for Spring {
    fn id(&self) -> usize {
        self.id
    }

    fn nodes(&self) -> Vec<NodeId> {
        scalar_nodes(self.first, self.second)
    }

    fn dofs(&self) -> Vec<Dof> {
        scalar_element_dofs(self.first, self.second)
    }

    fn matrices(&self, _model: &Model) -> Result<ElementMatrices, FemError> {
        let dofs = self.dofs();
        let n = dofs.len();
        Ok(ElementMatrices {
            dofs,
            stiffness: scalar_matrix(self.stiffness, n),
            mass: Mat::zeros(n, n),
            damping: None,
        })
    }

    /// A line between two DOFs' nodes, a vertex at a grounded spring.
    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(match self.second {
            Some(_) => VtkCell::LINE,
            None => VtkCell::VERTEX,
        })
    }
}

/// Spring along the line between two nodes: `k d d^T` on their translations
/// (CalculiX SPRINGA, linear).
#[derive(Clone, Debug, PartialEq)]
pub struct AxialSpring {
    pub id: usize,
    pub nodes: [NodeId; 2],
    /// Stiffness (N/m).
    pub stiffness: f64,
}

impl ElementBehaviour for AxialSpring {
    fn id(&self) -> usize {
        self.id
    }

    fn nodes(&self) -> Vec<NodeId> {
        self.nodes.to_vec()
    }

    fn dofs(&self) -> Vec<Dof> {
        node_dofs(&self.nodes, &TRANSLATIONS)
    }

    fn validate(&self, model: &Model) -> Result<(), FemError> {
        line_direction(model, self.id, self.nodes).map(|_| ())
    }

    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        let d = line_direction(model, self.id, self.nodes)?;
        Ok(ElementMatrices {
            dofs: self.dofs(),
            stiffness: axial_matrix(self.stiffness, d),
            mass: Mat::zeros(6, 6),
            damping: None,
        })
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(VtkCell::LINE)
    }
}
