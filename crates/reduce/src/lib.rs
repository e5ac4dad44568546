//! Mode sets and reduction methods (report sections 5 and 6).
//!
//! A reduction is a pure function from an FE model and its matrices to a
//! [`ReducedBody`]: the Ritz basis `T` (u = T q, eq. 3), the reduced matrices
//! `M_red = T^T M T`, `D_red = T^T D T`, `K_red = T^T K T` (eq. 5-7), and the
//! rows of `T` that coupling (interface rows `T_j`, eq. 8) and recovery
//! (element rows `T_e`, eq. 25) need.
//!
//! Mode types live in [`modes`], one file each; the methods that combine them
//! in [`method`]; the body in the floating frame of reference (elastic
//! coordinates and mass invariants, what a SID file carries) in [`ffrf`].

pub mod body;
mod consistency;
pub mod error;
pub mod ffrf;
pub mod method;
pub mod modes;
mod products;

pub use body::{natural_frequencies_hz, ModeKind, ReducedBody};
pub use consistency::BodyDefect;
pub use error::ReduceError;
pub use method::{
    reduce, reduce_keeping, reduce_reporting, ForceGroup, GroundSpring, Keep, Method, Reduction,
};

#[cfg(test)]
mod tests;
