//! Finite-element substructures: nodes with 3D coordinates, a DOF map, node
//! sets, elements (planar and 3D beams, point masses, springs), and sparse
//! assembly of mass, stiffness and Rayleigh damping (report eq. 1).
//!
//! Units are SI throughout: m, kg, s, N, Pa, rad.

pub mod anisotropy;
pub mod assembly;
pub mod constraint;
pub mod coupling;
pub mod dof;
pub mod element;
pub mod id_hash;
pub mod local_axes;
pub mod lumped;
pub mod mesh;
pub mod model;
pub mod section;
pub mod substructure;
pub mod tie;
pub mod transform;

pub use anisotropy::{Anisotropy, Orientation};
pub use assembly::{assemble, SystemMatrices};
pub use constraint::{Equation, MpcKind};
pub use coupling::{Coupling, CouplingKind};
pub use dof::{Dof, DofKind, DofMap};
pub use element::{Element, ElementMatrices, SectionForces};
pub use local_axes::{Axes, AxesChange};
pub use model::{Model, ModelParts, Node, NodeId, Rayleigh, ValueTerms};
pub use section::{BeamProperties, BeamTheory, Material, SectionShape};
pub use substructure::{Substructure, Support};
pub use tie::{Face, Tie};

/// Errors in building or assembling a model. They name the element, node or
/// DOF that is wrong (user ids, not internal indices).
#[derive(Debug, thiserror::Error)]
pub enum FemError {
    #[error("node {0} is defined twice")]
    DuplicateNode(NodeId),
    #[error("element {element} refers to node {node}, which does not exist")]
    UnknownNode { element: usize, node: NodeId },
    #[error("{what} refers to node {node}, which does not exist")]
    UnknownNodeIn { what: String, node: NodeId },
    #[error("element {element} has zero length")]
    ZeroLength { element: usize },
    #[error(
        "planar beam element {element} must lie along the x axis (same y and z at both nodes)"
    )]
    PlanarBeamNotAlongX { element: usize },
    #[error("element {element}: orientation vector {orientation:?} is parallel to the beam axis")]
    OrientationParallel {
        element: usize,
        orientation: [f64; 3],
    },
    /// An elasticity or orientation that is not usable (the message says why).
    #[error("{0}")]
    InvalidMaterial(String),
    #[error("{what} must be {rule}, got {value}")]
    InvalidValue {
        what: String,
        rule: &'static str,
        value: f64,
    },
    #[error("point mass on node {node}: no element or coupling gives that node a DOF to carry it")]
    MassWithoutDof { node: NodeId },
    #[error("{what}: node {node} has no DOF {dof}")]
    UnknownDof {
        what: String,
        node: NodeId,
        dof: DofKind,
    },
    #[error("element {element}: {reason}")]
    InvalidElement { element: usize, reason: String },
    #[error("coupling '{name}': {reason}")]
    InvalidCoupling { name: String, reason: String },
    #[error("constraint {name}: {reason}")]
    InvalidConstraint { name: String, reason: String },
    #[error("the model has no DOFs")]
    Empty,
    /// Local axes that cannot be used where they are given.
    #[error("local axes: {0}")]
    LocalAxes(String),
    #[error(transparent)]
    Linalg(#[from] flexbody_linalg::LinalgError),
}

/// Checks that `value` is finite and positive; `what` names it in the error.
pub fn require_positive(what: impl Into<String>, value: f64) -> Result<f64, FemError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(FemError::InvalidValue {
            what: what.into(),
            rule: "positive and finite",
            value,
        })
    }
}

/// Checks an inertia tensor `[ixx, iyy, izz, ixy, iyz, ixz]` (kg m^2):
/// finite and positive semi-definite (every principal minor not negative,
/// to round-off of its size), as the inertia of matter is. `what` names it.
pub fn require_inertia(what: impl Into<String>, inertia: [f64; 6]) -> Result<(), FemError> {
    let [xx, yy, zz, xy, yz, xz] = inertia;
    let bad = |rule: &'static str, value: f64| {
        Err(FemError::InvalidValue {
            what: what.into(),
            rule,
            value,
        })
    };
    if let Some(v) = inertia.iter().find(|v| !v.is_finite()) {
        return bad("finite", *v);
    }
    let scale = inertia.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let tol = 1e-12 * scale;
    if let Some(v) = [xx, yy, zz].into_iter().find(|v| *v < -tol) {
        return bad("a positive semi-definite tensor (moments not negative)", v);
    }
    for minor in [xx * yy - xy * xy, yy * zz - yz * yz, xx * zz - xz * xz] {
        if minor < -tol * scale {
            return bad(
                "a positive semi-definite tensor (products of inertia too large for the moments)",
                minor,
            );
        }
    }
    let det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
    if det < -tol * scale * scale {
        return bad(
            "a positive semi-definite tensor (products of inertia too large for the moments)",
            det,
        );
    }
    Ok(())
}

/// Checks that `value` is finite and not negative.
pub fn require_non_negative(what: impl Into<String>, value: f64) -> Result<f64, FemError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(FemError::InvalidValue {
            what: what.into(),
            rule: "zero or positive and finite",
            value,
        })
    }
}
