//! flexbody: reduce a linear FE model of one component to a small flexible
//! body for multibody simulation (MBS), couple it into MBS equations, recover
//! displacements and section forces from the Ritz coordinates, and measure
//! what the reduction costs in accuracy.
//!
//! The method is that of Dietz & Knothe, "Reduktion der Anzahl der
//! Freiheitsgrade in Finite-Element-Substrukturen" (ILR-Mitteilung 315, TU
//! Berlin 1997); equation numbers in the docs are the report's. Units are SI
//! throughout.
//!
//! Data flows one way, one crate per stage:
//! [`fem`] (model, K, M) -> [`reduce`] (modes, [`reduce::ReducedBody`]) ->
//! [`mbs`] (coupling, harmonic response) -> [`recover`] (section forces) ->
//! [`study`], [`report`], [`plot`] and [`report_html`] (accuracy report);
//! [`io`] reads FE models, [`scenario`] what a model file does with its
//! model (interface, MBS, study), [`output`] computes what the files of a reduced body hold
//! besides the body (the SID's floating-frame content, the VTU's mode
//! fields), and [`export`] formats them.
//!
//! ```no_run
//! use flexbody::{fem, reduce, scenario};
//! let file = scenario::read_model_file("examples/side_beam.toml".as_ref())?;
//! let sub = fem::Substructure::from_model(&file.model)?;
//! let spec = reduce::Reduction::new(reduce::Method::FreeResidual, 1, file.interface.clone());
//! let body = reduce::reduce(&sub, &spec)?;
//! assert_eq!(body.r(), 7); // 2 rigid + 4 residual inertia-relief + 1 eigenmode
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod file_kind;
pub mod huge_pages;
pub mod input;
pub mod model_summary;
pub mod output;
pub mod output_folder;
pub mod plot;
pub mod report;
pub mod report_html;
pub mod scenario;
pub mod simulate;
pub mod study;

pub use flexbody_export as export;
pub use flexbody_fem as fem;
pub use flexbody_io as io;
pub use flexbody_linalg as linalg;
pub use flexbody_mbs as mbs;
pub use flexbody_recover as recover;
pub use flexbody_reduce as reduce;
