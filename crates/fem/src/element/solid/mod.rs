//! Isoparametric solid elements with consistent mass and linear isotropic
//! elasticity, in the node numbering and with the integration rules of
//! Abaqus/CalculiX, so that assembled matrices agree with CalculiX's:
//!
//! | kind | nodes | stiffness rule | mass rule |
//! | --- | --- | --- | --- |
//! | C3D8 | 8 | 2x2x2 Gauss | (as CalculiX) |
//! | C3D20 | 20 | 3x3x3 Gauss | (as CalculiX) |
//! | C3D20R | 20 | 2x2x2 Gauss | (as CalculiX) |
//! | C3D10 | 10 | 4-point | (as CalculiX) |
//! | C3D4 | 4 | 1-point | (as CalculiX) |
//! | C3D6 | 6 | 2-point | (as CalculiX) |
//!
//! DOFs: `ux, uy, uz` per node, in element node order. Stresses in Voigt
//! order `[sxx, syy, szz, sxy, syz, szx]` (Pa).

use super::ElementMatrices;
use crate::dof::{Dof, DofKind};
use crate::model::NodeId;
use crate::section::Material;
use crate::FemError;

/// Solid element types (Abaqus/CalculiX names).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum SolidKind {
    C3D8,
    C3D20,
    C3D20R,
    C3D10,
    C3D4,
    C3D6,
}

impl SolidKind {
    pub const ALL: [SolidKind; 6] = [
        SolidKind::C3D8,
        SolidKind::C3D20,
        SolidKind::C3D20R,
        SolidKind::C3D10,
        SolidKind::C3D4,
        SolidKind::C3D6,
    ];

    /// Number of nodes.
    pub fn node_count(self) -> usize {
        match self {
            SolidKind::C3D8 => 8,
            SolidKind::C3D20 | SolidKind::C3D20R => 20,
            SolidKind::C3D10 => 10,
            SolidKind::C3D4 => 4,
            SolidKind::C3D6 => 6,
        }
    }

    /// Abaqus/CalculiX name (`"C3D20R"`).
    pub fn name(self) -> &'static str {
        match self {
            SolidKind::C3D8 => "C3D8",
            SolidKind::C3D20 => "C3D20",
            SolidKind::C3D20R => "C3D20R",
            SolidKind::C3D10 => "C3D10",
            SolidKind::C3D4 => "C3D4",
            SolidKind::C3D6 => "C3D6",
        }
    }

    /// Parses a name, case-insensitive.
    pub fn parse(s: &str) -> Option<Self> {
        SolidKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s))
    }
}

/// A solid element.
#[derive(Clone, Debug, PartialEq)]
pub struct Solid {
    pub id: usize,
    pub kind: SolidKind,
    /// Node ids in Abaqus/CalculiX order (`kind.node_count()` of them).
    pub nodes: Vec<NodeId>,
    pub material: Material,
}

impl Solid {
    pub(crate) fn dofs(&self) -> Vec<Dof> {
        self.nodes
            .iter()
            .flat_map(|&n| [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|k| Dof::new(n, k)))
            .collect()
    }

    /// Checks node count and geometry (no zero-volume or inverted element).
    pub fn validate(&self, coords: &[[f64; 3]]) -> Result<(), FemError> {
        let _ = coords;
        Err(FemError::InvalidElement {
            element: self.id,
            reason: "solid elements are not implemented yet".into(),
        })
    }

    /// Element volume (m^3).
    pub fn volume(&self, coords: &[[f64; 3]]) -> Result<f64, FemError> {
        self.validate(coords).map(|_| 0.0)
    }

    /// Stiffness and consistent mass in the DOFs of [`Solid::dofs`].
    pub(crate) fn matrices(&self, coords: &[[f64; 3]]) -> Result<ElementMatrices, FemError> {
        self.validate(coords)?;
        unreachable!()
    }

    /// Stresses at the element's nodes (Pa, Voigt order) from the element
    /// displacements `u_e` (order of [`Solid::dofs`]).
    pub fn nodal_stresses(
        &self,
        coords: &[[f64; 3]],
        u_e: &[f64],
    ) -> Result<Vec<[f64; 6]>, FemError> {
        let _ = u_e;
        self.validate(coords).map(|_| vec![])
    }
}

/// Von Mises equivalent stress of a Voigt stress `[sxx, syy, szz, sxy, syz, szx]`.
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, xy, yz, zx] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (xy * xy + yz * yz + zx * zx))
        .sqrt()
}
