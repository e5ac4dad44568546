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

    /// The type named `name` (case-insensitive), or the type an alias of
    /// [`ELEMENT_ALIASES`] reads as, with the alias.
    pub fn resolve(name: &str) -> Option<(&'static ElementType, Option<&'static ElementAlias>)> {
        if let Some(t) = Self::find(name) {
            return Some((t, None));
        }
        let alias = ELEMENT_ALIASES
            .iter()
            .find(|a| a.name.eq_ignore_ascii_case(name))?;
        Self::find(alias.reads_as).map(|t| (t, Some(alias)))
    }
}

/// A name that meshers (Abaqus/CAE, meshio) write for an element flexbody
/// reads as one of its own types: the mapping is explicit, listed in the
/// README and reported when a deck uses it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElementAlias {
    /// The name in the deck (`"C3D10MH"`).
    pub name: &'static str,
    /// The registered type it is read as (`"C3D10"`).
    pub reads_as: &'static str,
    /// What the mapping means, for the report.
    pub meaning: &'static str,
}

const HYBRID: &str = "hybrid (H): Abaqus adds an independent pressure, condensed per \
    element, to handle incompressibility; for a compressible material its K is close to the \
    displacement element's, and the same where the pressure spans the element's volumetric \
    strain. flexbody uses the displacement element's K and M (M is the same in both)";
const REDUCED_SHELL: &str = "reduced integration (R): Abaqus integrates the membrane and \
    bending of S4R at one point with hourglass control (S3R is S3 itself); flexbody uses its \
    MITC shell, integrated fully, which has no hourglass modes; frequencies differ at the \
    discretisation level";
const REDUCED_QUADRATIC_SHELL: &str = "reduced integration (R): Abaqus integrates S8R at 2 x 2 \
    points; flexbody's S8 is a MITC shell integrated at 3 x 3 points, free of locking and of \
    spurious modes; frequencies differ at the discretisation level";
const HYBRID_BEAM: &str = "hybrid beam (H): Abaqus adds the axial and shear forces as unknowns, \
    for beams whose axial and shear stiffness dwarf their bending stiffness; read as flexbody's \
    beam of the same nodes (a Timoshenko beam), as the base type itself is";
const REDUCED_BEAM: &str = "reduced integration (R): CalculiX expands beams into a layer of \
    bricks and integrates those with the reduced rule (B31R: C3D8R, B32R: C3D20R); flexbody's \
    beams are beam elements (B31 exact for end loads, B32 integrated at two points along its \
    axis), for which R changes nothing; frequencies differ from CalculiX's expanded beams at the \
    discretisation level";
const MODIFIED_TET: &str = "modified tetrahedron (M): Abaqus' own shape functions and \
    integration (made for contact), read as the standard quadratic tetrahedron; frequencies \
    differ at the discretisation level";

/// The names meshers write that flexbody reads as one of its types.
/// Hybrid names of types flexbody lacks are not here: they are refused
/// like their base types.
pub const ELEMENT_ALIASES: &[ElementAlias] = &[
    ElementAlias {
        name: "C3D4H",
        reads_as: "C3D4",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D6H",
        reads_as: "C3D6",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D8H",
        reads_as: "C3D8",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D8RH",
        reads_as: "C3D8R",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D8IH",
        reads_as: "C3D8I",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D10H",
        reads_as: "C3D10",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D15H",
        reads_as: "C3D15",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D20H",
        reads_as: "C3D20",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D20RH",
        reads_as: "C3D20R",
        meaning: HYBRID,
    },
    ElementAlias {
        name: "C3D10M",
        reads_as: "C3D10",
        meaning: MODIFIED_TET,
    },
    ElementAlias {
        name: "C3D10MH",
        reads_as: "C3D10",
        meaning: "modified hybrid tetrahedron (MH): Abaqus' own shape functions and \
            integration with a condensed pressure, read as the standard quadratic tetrahedron; \
            frequencies differ at the discretisation level",
    },
    ElementAlias {
        name: "S4R",
        reads_as: "S4",
        meaning: REDUCED_SHELL,
    },
    ElementAlias {
        name: "S8R",
        reads_as: "S8",
        meaning: REDUCED_QUADRATIC_SHELL,
    },
    ElementAlias {
        name: "S3R",
        reads_as: "S3",
        meaning: REDUCED_SHELL,
    },
    ElementAlias {
        name: "B31H",
        reads_as: "B31",
        meaning: HYBRID_BEAM,
    },
    ElementAlias {
        name: "B31R",
        reads_as: "B31",
        meaning: REDUCED_BEAM,
    },
    ElementAlias {
        name: "B32H",
        reads_as: "B32",
        meaning: HYBRID_BEAM,
    },
    ElementAlias {
        name: "B32R",
        reads_as: "B32",
        meaning: REDUCED_BEAM,
    },
];

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
    /// A material, a thickness and an offset (`*SHELL SECTION`).
    Shell,
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
    Shell {
        material: Material,
        /// Thickness (m).
        thickness: f64,
        /// Mid-surface offset from the nodes along the normal, in
        /// thicknesses.
        offset: f64,
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
            SectionValues::Shell { .. } => SectionKind::Shell,
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
