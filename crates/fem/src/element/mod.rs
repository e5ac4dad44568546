//! Elements: each computes its matrices in global DOFs and, for beams, the
//! end forces of report eq. 25 (`s_e = K_e u_e + M_e u_e''`).
//!
//! An element type is one file here that implements [`ElementBehaviour`],
//! registered once, in this file: its line in `element_kinds!` (which
//! declares [`Element`]) and, if decks name it, its table of
//! [`ElementType`]s in [`ELEMENT_TYPES`]. The assembler, the deck reader,
//! recovery and the VTK writer use elements only through these;
//! `docs/elements.md` walks through adding one.

pub mod beam;
mod behaviour;
mod bending;
pub mod dashpot;
mod discrete;
mod mass_distribution;
pub mod planar_beam;
pub mod point_mass;
pub mod quadratic_beam;
mod registry;
pub mod shell;
pub mod solid;
pub mod spring;

pub use beam::Beam;
pub use behaviour::{ElementBehaviour, StressLayer, VtkCell};
pub use dashpot::{AxialDashpot, Dashpot};
pub use mass_distribution::{MassDistribution, MassPoint};
pub use planar_beam::PlanarBeam;
pub use point_mass::PointMass;
pub use quadratic_beam::QuadraticBeam;
pub use registry::{
    element_types, ElementAlias, ElementType, SectionKind, SectionValues, ELEMENT_ALIASES,
};
pub use shell::{Shell, ShellKind};
pub use solid::{von_mises, Solid, SolidKind};
pub use spring::{AxialSpring, Spring};

use crate::dof::{Dof, DofKind};
use crate::model::{Model, NodeId};
use crate::FemError;
use faer::Mat;
use serde::{Deserialize, Serialize};

/// Declares [`Element`] from one line per element type (`Variant(Type)`,
/// the type implementing [`ElementBehaviour`]): the enum, its
/// [`Element::behaviour`] and a `From` of each type.
macro_rules! element_kinds {
    ($($(#[$doc:meta])* $variant:ident($ty:ty),)+) => {
        /// The element kinds flexbody assembles: one variant per type that
        /// implements [`ElementBehaviour`].
        #[derive(Clone, Debug, PartialEq)]
        pub enum Element {
            $($(#[$doc])* $variant($ty),)+
        }

        impl Element {
            /// The element as its type's [`ElementBehaviour`].
            pub fn behaviour(&self) -> &dyn ElementBehaviour {
                match self {
                    $(Element::$variant(e) => e,)+
                }
            }
        }

        $(impl From<$ty> for Element {
            fn from(e: $ty) -> Self {
                Element::$variant(e)
            }
        })+
    };
}

// The registration: one line per element type.
element_kinds! {
    /// Planar Euler-Bernoulli beam along x, bending in the x-z plane (uz, ry).
    PlanarBeam(PlanarBeam),
    /// 3D beam, 6 DOFs per node, Euler-Bernoulli or Timoshenko.
    Beam(Beam),
    /// Three-node quadratic 3D Timoshenko beam, straight or curved (B32).
    QuadraticBeam(QuadraticBeam),
    /// Point mass with rotary inertia.
    PointMass(PointMass),
    /// Scalar spring to ground or between two DOFs.
    Spring(Spring),
    /// Spring along the line between two nodes (CalculiX SPRINGA).
    AxialSpring(AxialSpring),
    /// Viscous dashpot on one DOF to ground or between two DOFs.
    Dashpot(Dashpot),
    /// Viscous dashpot along the line between two nodes (DASHPOTA).
    AxialDashpot(AxialDashpot),
    /// Solid element (C3D8, C3D8I, C3D8R, C3D20, C3D20R, C3D10, C3D4, C3D6,
    /// C3D15).
    Solid(Solid),
    /// Shell element, 6 DOFs per node (S3, S4, S6).
    Shell(Shell),
}

/// The element types decks name, the rows of every element file, in the
/// order the deck reader lists them: solids, shells, beams, masses,
/// springs, dashpots.
pub static ELEMENT_TYPES: &[&[ElementType]] = &[
    solid::ELEMENT_TYPES,
    shell::ELEMENT_TYPES,
    beam::ELEMENT_TYPES,
    quadratic_beam::ELEMENT_TYPES,
    point_mass::ELEMENT_TYPES,
    spring::ELEMENT_TYPES,
    dashpot::ELEMENT_TYPES,
];

/// Element matrices in the element's global DOFs: stiffness K_e, mass M_e
/// and viscous damping D_e (report eq. 1), all in the order of `dofs`.
#[derive(Clone, Debug)]
pub struct ElementMatrices {
    pub dofs: Vec<Dof>,
    pub stiffness: Mat<f64>,
    pub mass: Mat<f64>,
    /// `None`: the element adds nothing to D.
    pub damping: Option<Mat<f64>>,
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
        self.behaviour().id()
    }

    /// Nodes the element connects.
    pub fn nodes(&self) -> Vec<NodeId> {
        self.behaviour().nodes()
    }

    /// True if the element gives its nodes DOFs (stiffness); point masses
    /// only load the DOFs others create ([`ElementBehaviour::creates_dofs`]).
    pub fn creates_dofs(&self) -> bool {
        self.behaviour().creates_dofs()
    }

    /// The DOFs the element acts on (before any are fixed).
    pub fn dofs(&self) -> Vec<Dof> {
        self.behaviour().dofs()
    }

    /// Checks the element's geometry (length, orientation, volume) without
    /// building its matrices.
    pub fn validate(&self, model: &Model) -> Result<(), FemError> {
        self.behaviour().validate(model)
    }

    /// Stiffness, mass and damping in global DOFs. The damping matrix is
    /// the element's own (a dashpot's) plus `alpha M_e + beta K_e` of its
    /// material's Rayleigh damping ([`ElementBehaviour::material_damping`]).
    pub fn matrices(&self, model: &Model) -> Result<ElementMatrices, FemError> {
        let behaviour = self.behaviour();
        let mut em = behaviour.matrices(model)?;
        if let Some(r) = behaviour.material_damping() {
            let (m, k) = (&em.mass, &em.stiffness);
            let rayleigh = Mat::from_fn(m.nrows(), m.ncols(), |i, j| {
                r.alpha * m[(i, j)] + r.beta * k[(i, j)]
            });
            em.damping = Some(match em.damping {
                Some(own) => own + rayleigh,
                None => rayleigh,
            });
        }
        Ok(em)
    }

    /// True if [`Self::matrices`] gives a damping matrix: a dashpot, or an
    /// element whose material has Rayleigh damping.
    pub fn has_damping(&self) -> bool {
        let b = self.behaviour();
        b.has_damping() || b.material_damping().is_some()
    }

    /// Where the element's mass is in space, for the floating-frame
    /// invariants ([`ElementBehaviour::mass_distribution`]).
    pub fn mass_distribution(&self, model: &Model) -> Result<MassDistribution, FemError> {
        self.behaviour().mass_distribution(model)
    }

    /// True if the element has section forces (beams).
    pub fn has_section_forces(&self) -> bool {
        self.behaviour().has_section_forces()
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
        self.behaviour().section_forces(model, u_e, a_e)
    }

    /// True if the element has stresses (solids, shells).
    pub fn has_stresses(&self) -> bool {
        self.behaviour().has_stresses()
    }

    /// The layers of [`Self::stresses`] at each node
    /// ([`ElementBehaviour::stress_layers`]).
    pub fn stress_layers(&self) -> &'static [StressLayer] {
        self.behaviour().stress_layers()
    }

    /// Nodal stresses of `columns` displacement fields (solids and shells;
    /// `None` otherwise), as [`ElementBehaviour::stresses`].
    pub fn stresses(
        &self,
        model: &Model,
        u_e: &[f64],
        columns: usize,
    ) -> Result<Option<Vec<[f64; 6]>>, FemError> {
        self.behaviour().stresses(model, u_e, columns)
    }

    /// The VTK cell that draws the element, if any.
    pub fn vtk_cell(&self) -> Option<VtkCell> {
        self.behaviour().vtk_cell()
    }
}

/// The DOFs `kinds` of each node, node by node: the DOF order of an
/// element whose nodes all carry the same DOFs.
pub(crate) fn node_dofs(nodes: &[NodeId], kinds: &[DofKind]) -> Vec<Dof> {
    nodes
        .iter()
        .flat_map(|&n| kinds.iter().map(move |&k| Dof::new(n, k)))
        .collect()
}

/// The translations `ux, uy, uz`.
pub(crate) const TRANSLATIONS: [DofKind; 3] = [DofKind::Ux, DofKind::Uy, DofKind::Uz];

/// Coordinates of the given nodes (ids from a checked model).
pub(crate) fn element_coords(model: &Model, nodes: &[NodeId]) -> Vec<[f64; 3]> {
    nodes.iter().map(|&n| model.coords(n)).collect()
}

/// `y = A x` for a small dense matrix and a slice.
/// Static condensation of the DOFs after the first `nb` of a symmetric
/// element matrix `k`: the stiffness `K_bb - K_bc K_cc^-1 K_cb` over the
/// kept DOFs (symmetric to the last bit, as every element's matrices are)
/// and the map `X = -K_cc^-1 K_cb` that gives the condensed DOFs from the
/// kept ones; `None` if `K_cc` is not positive definite.
pub(crate) fn condense(k: &Mat<f64>, nb: usize) -> Option<(Mat<f64>, Mat<f64>)> {
    use faer::linalg::solvers::Solve;
    let nc = k.nrows() - nb;
    let kcc = k.as_ref().submatrix(nb, nb, nc, nc).to_owned();
    let kcb = k.as_ref().submatrix(nb, 0, nc, nb).to_owned();
    let x = -kcc.llt(faer::Side::Lower).ok()?.solve(&kcb);
    let mut out = k.as_ref().submatrix(0, 0, nb, nb).to_owned();
    out += kcb.transpose() * &x;
    for c in 0..nb {
        for r in 0..c {
            let v = 0.5 * (out[(r, c)] + out[(c, r)]);
            out[(r, c)] = v;
            out[(c, r)] = v;
        }
    }
    Some((out, x))
}

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
