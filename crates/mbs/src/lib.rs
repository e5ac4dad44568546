//! Linear multibody systems with flexible bodies (report section 4).
//!
//! Bodies contribute their coordinates: a reduced flexible body its Ritz
//! coordinates q (`u_j = T_j q`, eq. 8), the full FE model (the reference
//! solution) its nodal DOFs, a rigid body the six motions of its centre of
//! mass (`u_i = R_i u_st`, eq. 12). Springs between points of bodies, ground
//! or a base-excited track point add `c_n g_n g_n^T` with the kinematics row
//! `g_n = d_n^T [-R_i | T_j]` (eq. 9-11). [`harmonic`] solves the steady
//! state at an excitation frequency Omega.
//!
//! Units: SI (m, kg, s, N, rad/s).

pub mod body;
pub mod connection;
pub mod force_law;
pub mod harmonic;
mod linear_solve;
pub mod modal;
pub mod system;
#[cfg(test)]
mod test_systems;
pub mod time;

pub use body::{FlexibleBody, RigidBody};
pub use connection::{Connection, Endpoint, Track};
pub use force_law::ForceLaw;
pub use harmonic::{harmonic_response, HarmonicResponse};
pub use modal::{damped_modes, DampedMode};
pub use system::{Assembled, Layout, System};
pub use time::{
    simulate, Excitation, History, Profile, State, TimeForce, TimeResponse, TimeSettings,
};

/// Errors of MBS assembly and solution, naming the connection and body.
#[derive(Debug, thiserror::Error)]
pub enum MbsError {
    #[error("connection '{connection}': flexible body {body} does not exist")]
    UnknownFlexibleBody { connection: String, body: usize },
    #[error("connection '{connection}': rigid body {body} does not exist")]
    UnknownRigidBody { connection: String, body: usize },
    #[error("connection '{connection}': node {node} of the flexible body has no DOF {dof}, but the spring direction has a component along it")]
    MissingDof {
        connection: String,
        node: u64,
        dof: &'static str,
    },
    #[error("connection '{connection}': {what}")]
    Invalid { connection: String, what: String },
    #[error("connection '{0}' is base-excited but the system has no track")]
    NoTrack(String),
    #[error("the dynamic stiffness at Omega = {omega} rad/s is singular: Omega is an undamped eigenfrequency of the system, or a body is not supported")]
    Singular { omega: f64 },
    #[error("time integration: {0}")]
    Settings(String),
    #[error("Newton iterations did not converge at t = {time} s after {iterations} iterations; reduce the time step")]
    NoConvergence { time: f64, iterations: usize },
    #[error("the damped modes of a system of {coordinates} coordinates need the dense eigen solver, which stops at {limit}: reduce the body first")]
    TooLargeForDense { coordinates: usize, limit: usize },
    #[error("the dense eigen solver resolves {found} of the {coordinates} undamped modes of the system (the others are massless: directions whose mass is round-off); its damped modes need all of them")]
    UnresolvedModes { found: usize, coordinates: usize },
    #[error(transparent)]
    Linalg(#[from] flexbody_linalg::LinalgError),
}
