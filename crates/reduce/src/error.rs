//! Errors of mode computation and reduction, naming DOFs by node and kind.

use flexbody_fem::{Dof, FemError};
use flexbody_linalg::LinalgError;

fn list(dofs: &[Dof]) -> String {
    let shown: Vec<String> = dofs.iter().take(8).map(|d| d.to_string()).collect();
    let more = if dofs.len() > 8 {
        format!(" and {} more", dofs.len() - 8)
    } else {
        String::new()
    };
    format!("{}{}", shown.join(", "), more)
}

/// What holds the body at its interface, and what can still move it, for
/// [`ReduceError::BodyMechanism`].
fn held(interface: &[Dof], rigid: usize) -> String {
    match rigid {
        0 => format!(
            "the model is supported and the interface DOFs ({}) are held: the body has a \
             mechanism of its own (supports that do not hold it, a part not connected to the \
             rest, a hinge, or a DOF no element stiffens)",
            list(interface)
        ),
        _ => format!(
            "the interface DOFs ({}) hold all {rigid} rigid-body motions: the body has a \
             mechanism of its own (a part not connected to the rest, a hinge, or a DOF no \
             element stiffens)",
            list(interface)
        ),
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ReduceError {
    /// K_NN of static condensation is singular (eq. 15): the boundary DOFs
    /// do not support the body statically.
    #[error(
        "the interface DOFs ({}) leave a mechanism: K_NN is singular (report eq. 15); \
         these DOFs can move without strain: {}. Add interface DOFs that support the body \
         statically, or use the free-residual method",
        list(.interface),
        list(.free)
    )]
    Mechanism { interface: Vec<Dof>, free: Vec<Dof> },
    /// K_NN of static condensation is singular although the interface
    /// holds the body's `rigid` rigid-body motions (none for a supported
    /// body): the body has a mechanism of its own, which no choice of
    /// interface DOFs among these or of method reduces.
    #[error(
        "K_NN is singular at {dof} although {}, which no reduction method removes; check \
         the mesh near {dof}",
        held(.interface, *.rigid)
    )]
    BodyMechanism {
        interface: Vec<Dof>,
        dof: Dof,
        rigid: usize,
    },
    /// A stiffness matrix is singular at a DOF (an internal mechanism).
    #[error("{what} is singular at {dof}: that DOF can move without strain (a mechanism, or a DOF no element stiffens)")]
    Singular { what: &'static str, dof: Dof },
    /// The body is free but its geometric rigid-body modes carry strain energy.
    #[error("rigid-body modes carry strain energy (relative {0:e}): the stiffness matrix is not that of a free body")]
    RigidModesStrained(f64),
    #[error(
        "the support for inertia-relief modes has {given} DOFs ({}); a statically determinate support needs exactly {needed} that fix all rigid-body modes",
        list(.dofs)
    )]
    SupportCount {
        given: usize,
        needed: usize,
        dofs: Vec<Dof>,
    },
    #[error(
        "the support ({}) does not fix every rigid-body motion and would constrain the body elsewhere (report Bild 4b); choose DOFs that fix translation and rotation, e.g. all DOFs of one node",
        list(.0)
    )]
    SupportNotDeterminate(Vec<Dof>),
    #[error("{requested} eigenmodes requested but the model has only {available}")]
    NotEnoughModes { requested: usize, available: usize },
    #[error(
        "method {method} with {modes} eigenmodes has {} Ritz vectors ({others} besides the eigenmodes), more than the model's {dofs} DOFs: they cannot be independent; ask for at most {} eigenmodes, or a lower fmax",
        .modes + .others,
        .dofs.saturating_sub(*.others)
    )]
    BasisBeyondModel {
        method: &'static str,
        modes: usize,
        others: usize,
        dofs: usize,
    },
    #[error("the free body has {zero} zero-frequency modes but only {rigid} rigid-body modes: it contains a mechanism")]
    FreeMechanism { zero: usize, rigid: usize },
    #[error("method {0} needs interface DOFs; none are given")]
    NoInterface(&'static str),
    #[error("interface DOF {0} is not a free DOF of the model")]
    UnknownInterfaceDof(Dof),
    #[error("interface DOF {0} is listed twice")]
    DuplicateInterfaceDof(Dof),
    #[error("the guyan method uses no eigenmodes; got modes = {0}")]
    GuyanWithModes(usize),
    #[error("method free needs at least one mode")]
    NoModes,
    #[error("force groups replace unit loads of attachment and inertia-relief modes; method {0} uses constraint modes (unit displacements), where groups do not apply")]
    ForceGroupsNotApplicable(&'static str),
    #[error("force group '{name}': {reason}")]
    ForceGroup { name: String, reason: String },
    #[error("both a number of modes ({0}) and a frequency band are given; give one")]
    ModesAndBand(usize),
    #[error(transparent)]
    Fem(#[from] FemError),
    #[error(transparent)]
    Linalg(#[from] LinalgError),
}
