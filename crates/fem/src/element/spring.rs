//! Scalar spring between two DOFs, or from one DOF to ground; and the
//! spring along the line between two nodes.

use super::registry::wrong_section;
use super::{
    axis, node_dofs, Element, ElementBehaviour, ElementMatrices, ElementType, SectionKind,
};
use super::{SectionValues, VtkCell, TRANSLATIONS};
use crate::dof::{Dof, DofKind};
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
    let dof =
        |node: Option<&NodeId>, kind: Option<DofKind>| node.zip(kind).map(|(n, k)| Dof::new(*n, k));
    let missing = |reason: &str| FemError::InvalidElement {
        element: id,
        reason: reason.into(),
    };
    let first = dof(nodes.first(), dofs[0]).ok_or_else(|| missing("spring without a DOF"))?;
    let second = if between {
        Some(dof(nodes.get(1), dofs[1]).ok_or_else(|| missing("spring without a second DOF"))?)
    } else {
        None
    };
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
        let mut n = vec![self.first.node];
        if let Some(s) = self.second {
            n.push(s.node);
        }
        n
    }

    fn dofs(&self) -> Vec<Dof> {
        let mut d = vec![self.first];
        d.extend(self.second);
        d
    }

    fn matrices(&self, _model: &Model) -> Result<ElementMatrices, FemError> {
        let c = self.stiffness;
        let dofs = self.dofs();
        let n = dofs.len();
        let stiffness = Mat::from_fn(n, n, |i, j| if i == j { c } else { -c });
        Ok(ElementMatrices {
            dofs,
            stiffness,
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

impl AxialSpring {
    /// Length and unit direction; an error for coincident nodes.
    fn axis(&self, model: &Model) -> Result<[f64; 3], FemError> {
        let (l, d) = axis(model.coords(self.nodes[0]), model.coords(self.nodes[1]));
        if l.is_nan() || l <= 0.0 {
            return Err(FemError::ZeroLength { element: self.id });
        }
        Ok(d)
    }
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
        self.axis(model).map(|_| ())
    }

    fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        let d = self.axis(model)?;
        let k = self.stiffness;
        let stiffness = Mat::from_fn(6, 6, |i, j| {
            let sign = if (i < 3) == (j < 3) { 1.0 } else { -1.0 };
            sign * k * d[i % 3] * d[j % 3]
        });
        Ok(ElementMatrices {
            dofs: self.dofs(),
            stiffness,
            mass: Mat::zeros(6, 6),
            damping: None,
        })
    }

    fn vtk_cell(&self) -> Option<VtkCell> {
        Some(VtkCell::LINE)
    }
}
