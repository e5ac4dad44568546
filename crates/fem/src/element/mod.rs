//! Elements: each computes its matrices in global DOFs and, for beams, the
//! end forces of report eq. 25 (`s_e = K_e u_e + M_e u_e''`).

pub mod beam;
mod bending;
pub mod planar_beam;
pub mod point_mass;
pub mod solid;
pub mod spring;

pub use beam::Beam;
pub use planar_beam::PlanarBeam;
pub use point_mass::PointMass;
pub use solid::{von_mises, Solid, SolidKind};
pub use spring::{AxialSpring, Spring};

use crate::dof::Dof;
use crate::model::{Model, NodeId};
use crate::FemError;
use faer::Mat;
use serde::{Deserialize, Serialize};

/// The element kinds flexbody assembles.
#[derive(Clone, Debug, PartialEq)]
pub enum Element {
    /// Planar Euler-Bernoulli beam along x, bending in the x-z plane (uz, ry).
    PlanarBeam(PlanarBeam),
    /// 3D beam, 6 DOFs per node, Euler-Bernoulli or Timoshenko.
    Beam(Beam),
    /// Point mass with rotary inertia.
    PointMass(PointMass),
    /// Scalar spring to ground or between two DOFs.
    Spring(Spring),
    /// Spring along the line between two nodes (CalculiX SPRINGA).
    AxialSpring(AxialSpring),
    /// Solid element (C3D8, C3D20, C3D20R, C3D10, C3D4, C3D6).
    Solid(Solid),
}

/// Element matrices in the element's global DOFs.
#[derive(Clone, Debug)]
pub struct ElementMatrices {
    pub dofs: Vec<Dof>,
    pub stiffness: Mat<f64>,
    pub mass: Mat<f64>,
}

/// Section forces at both ends of a beam element, in its local frame, as the
/// internal force on the positive cut face: `[N, Qy, Qz, T, My, Mz]` (N, N m).
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SectionForces {
    pub start: [f64; 6],
    pub end: [f64; 6],
}

impl SectionForces {
    /// Component names in order.
    pub const NAMES: [&'static str; 6] = ["N", "Qy", "Qz", "T", "My", "Mz"];
}

impl Element {
    /// Element number (user id).
    pub fn id(&self) -> usize {
        match self {
            Element::PlanarBeam(e) => e.id,
            Element::Beam(e) => e.id,
            Element::PointMass(e) => e.id,
            Element::Spring(e) => e.id,
            Element::AxialSpring(e) => e.id,
            Element::Solid(e) => e.id,
        }
    }

    /// Nodes the element connects.
    pub fn nodes(&self) -> Vec<NodeId> {
        match self {
            Element::PlanarBeam(e) => e.nodes.to_vec(),
            Element::Beam(e) => e.nodes.to_vec(),
            Element::PointMass(e) => vec![e.node],
            Element::Spring(e) => {
                let mut n = vec![e.first.node];
                if let Some(s) = e.second {
                    n.push(s.node);
                }
                n
            }
            Element::AxialSpring(e) => e.nodes.to_vec(),
            Element::Solid(e) => e.nodes.clone(),
        }
    }

    /// True if the element gives its nodes DOFs (stiffness); point masses
    /// only load the DOFs others create.
    pub fn creates_dofs(&self) -> bool {
        !matches!(self, Element::PointMass(_))
    }

    /// The DOFs the element acts on (before any are fixed).
    pub fn dofs(&self) -> Vec<Dof> {
        match self {
            Element::PlanarBeam(e) => e.dofs(),
            Element::Beam(e) => e.dofs(),
            Element::PointMass(e) => e.dofs(),
            Element::Spring(e) => e.dofs(),
            Element::AxialSpring(e) => e.dofs(),
            Element::Solid(e) => e.dofs(),
        }
    }

    /// Checks the element's geometry (length, orientation) without building
    /// its matrices.
    pub fn validate(&self, model: &Model) -> Result<(), FemError> {
        match self {
            Element::PlanarBeam(e) => {
                e.validate(model.coords(e.nodes[0]), model.coords(e.nodes[1]))
            }
            Element::Beam(e) => e.validate(model.coords(e.nodes[0]), model.coords(e.nodes[1])),
            Element::AxialSpring(e) => {
                e.validate(model.coords(e.nodes[0]), model.coords(e.nodes[1]))
            }
            Element::Solid(e) => e.validate(&element_coords(model, &e.nodes)),
            Element::PointMass(_) | Element::Spring(_) => Ok(()),
        }
    }

    /// Stiffness and mass in global DOFs. Point masses return only the DOFs
    /// the model has at their node.
    pub fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        match self {
            Element::PlanarBeam(e) => {
                e.matrices(model.coords(e.nodes[0]), model.coords(e.nodes[1]))
            }
            Element::Beam(e) => e.matrices(model.coords(e.nodes[0]), model.coords(e.nodes[1])),
            Element::PointMass(e) => Ok(e.matrices(model)),
            Element::Spring(e) => Ok(e.matrices()),
            Element::AxialSpring(e) => {
                e.matrices(model.coords(e.nodes[0]), model.coords(e.nodes[1]))
            }
            Element::Solid(e) => e.matrices(&element_coords(model, &e.nodes)),
        }
    }

    /// Report eq. 25 for one element: end forces `K_e u_e + M_e a_e` turned
    /// into section forces at both ends (beams only; `None` otherwise).
    /// `u_e` and `a_e` are displacements and accelerations in the order of
    /// [`Element::dofs`].
    pub fn section_forces(
        &self,
        model: &Model,
        u_e: &[f64],
        a_e: &[f64],
    ) -> Result<Option<SectionForces>, FemError> {
        match self {
            Element::PlanarBeam(e) => e
                .section_forces(model.coords(e.nodes[0]), model.coords(e.nodes[1]), u_e, a_e)
                .map(Some),
            Element::Beam(e) => e
                .section_forces(model.coords(e.nodes[0]), model.coords(e.nodes[1]), u_e, a_e)
                .map(Some),
            _ => Ok(None),
        }
    }
}

/// Coordinates of the given nodes (ids from a checked model).
pub(crate) fn element_coords(model: &Model, nodes: &[NodeId]) -> Vec<[f64; 3]> {
    nodes.iter().map(|&n| model.coords(n)).collect()
}

/// `y = A x` for a small dense matrix and a slice.
pub(crate) fn mat_vec(a: &Mat<f64>, x: &[f64]) -> Vec<f64> {
    (0..a.nrows())
        .map(|i| (0..a.ncols()).map(|j| a[(i, j)] * x[j]).sum())
        .collect()
}

/// `T^T A T` for small dense matrices.
pub(crate) fn congruence(a: &Mat<f64>, t: &Mat<f64>) -> Mat<f64> {
    let mut out = t.transpose() * a * t;
    flexbody_linalg::sparse::symmetrize(&mut out);
    out
}

/// Length and unit direction from `a` to `b`.
pub(crate) fn axis(a: [f64; 3], b: [f64; 3]) -> (f64, [f64; 3]) {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    (l, [d[0] / l, d[1] / l, d[2] / l])
}

#[cfg(test)]
mod tests;
