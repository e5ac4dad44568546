//! The element types input decks name (Abaqus/CalculiX `*ELEMENT, TYPE=`):
//! one table row per type, kept in the element's own file and listed once
//! in [`ELEMENT_TYPES`](super::ELEMENT_TYPES). The deck reader takes the
//! type names, node counts, section kinds and construction from here.

use super::{Element, ELEMENT_TYPES};
use crate::dof::DofKind;
use crate::model::NodeId;
use crate::section::{Material, SectionConstants};
use crate::FemError;

/// One element type of the input decks.
#[derive(Clone, Copy, Debug)]
pub struct ElementType {
    /// Abaqus/CalculiX name, upper case (`"C3D20R"`).
    pub name: &'static str,
    /// Number of nodes an element of this type lists.
    pub nodes: usize,
    /// The kind of section that gives it its properties.
    pub section: SectionKind,
    /// Node positions of an undistorted element of this type, in its node
    /// order: a valid element for tests and meshes built in code.
    pub reference_nodes: &'static [[f64; 3]],
    /// Builds element `id` on `nodes` (`self.nodes` of them, checked by
    /// the caller) from the values of its section, which must be of kind
    /// `section`.
    pub build:
        fn(id: usize, nodes: &[NodeId], section: &SectionValues) -> Result<Element, FemError>,
}

impl ElementType {
    /// The type named `name` (case-insensitive).
    pub fn find(name: &str) -> Option<&'static ElementType> {
        element_types().find(|t| t.name.eq_ignore_ascii_case(name))
    }
}

/// The error of a `build` given section values its type does not take.
pub(crate) fn wrong_section(type_name: &str, id: usize, section: &SectionValues) -> FemError {
    FemError::InvalidElement {
        element: id,
        reason: format!(
            "type {type_name} does not take its properties from a {:?} section",
            section.kind()
        ),
    }
}

/// Every registered element type, in the order of
/// [`ELEMENT_TYPES`](super::ELEMENT_TYPES).
pub fn element_types() -> impl Iterator<Item = &'static ElementType> {
    ELEMENT_TYPES.iter().flat_map(|types| types.iter())
}

/// The kind of section (property definition) an element type takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionKind {
    /// A material (`*SOLID SECTION`).
    Solid,
    /// A material, cross-section constants and an orientation
    /// (`*BEAM SECTION`).
    Beam,
    /// A mass (`*MASS`).
    Mass,
    /// A stiffness and `dofs` DOF numbers (`*SPRING`; 0 for a spring along
    /// the line between its nodes).
    Spring { dofs: usize },
    /// A damping coefficient and `dofs` DOF numbers (`*DASHPOT`; 0 for a
    /// dashpot along the line between its nodes).
    Dashpot { dofs: usize },
}

/// The values a section gives an element.
#[derive(Clone, Debug, PartialEq)]
pub enum SectionValues {
    Solid {
        material: Material,
    },
    Beam {
        material: Material,
        constants: SectionConstants,
        /// Approximate direction of the local y axis (global components).
        orientation: [f64; 3],
    },
    Mass {
        /// Mass (kg).
        mass: f64,
    },
    Spring {
        /// The DOF at the first and the second node (springs between DOFs).
        dofs: [Option<DofKind>; 2],
        /// Stiffness (N/m, or N m/rad on rotations).
        stiffness: f64,
    },
    Dashpot {
        /// The DOF at the first and the second node (dashpots between DOFs).
        dofs: [Option<DofKind>; 2],
        /// Viscous damping coefficient (N s/m, or N m s/rad on rotations).
        coefficient: f64,
    },
}

impl SectionValues {
    /// The kind of these values (`dofs` of a spring: those given).
    pub fn kind(&self) -> SectionKind {
        match self {
            SectionValues::Solid { .. } => SectionKind::Solid,
            SectionValues::Beam { .. } => SectionKind::Beam,
            SectionValues::Mass { .. } => SectionKind::Mass,
            SectionValues::Spring { dofs, .. } => SectionKind::Spring {
                dofs: dofs.iter().flatten().count(),
            },
            SectionValues::Dashpot { dofs, .. } => SectionKind::Dashpot {
                dofs: dofs.iter().flatten().count(),
            },
        }
    }
}
