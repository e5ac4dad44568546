//! The sparse eigen path of `eigenmodes` on solid models built in code:
//! it equals the dense solver, finds repeated frequencies with their full
//! multiplicity, and a mechanism is reported through `reduce`.
//!
//! The solid models are built in `models`; `eigen` tests the eigen
//! solvers, `methods` the reduction methods on one factorisation.

mod eigen;
mod methods;
mod models;
mod reference;
