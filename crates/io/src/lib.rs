//! Input files of flexbody.
//!
//! [`deck`] reads Abaqus/CalculiX input decks (`.inp`); [`matrices`] reads
//! FE matrices written by other programs (CalculiX `.sti`/`.mas`/`.dof`,
//! Matrix Market). [`model_file`] reads the project's TOML model files: the FE model (nodes,
//! beam lines, elements, sets, boundary conditions, damping), the interface,
//! the MBS around the body (rigid bodies, connections, track) and the study
//! cases. Units are SI throughout (m, kg, s, N, Pa, rad, rad/s). Every error
//! names the file and, where it comes from a line of the file, the line.

pub mod deck;
pub mod matrices;
pub mod model_file;

pub use deck::{parse_deck, read_deck, Deck};
pub use model_file::{
    parse_model_file, read_model_file, read_profile, BodySource, CaseSpec, FrfSpec, ModelFile,
    SimulationSpec, StudySpec,
};

use std::path::PathBuf;

/// A problem with an input file: where, and what.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("{}: cannot read: {cause}", .path.display())]
    Read {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error("{}:{}: {message}", .path.display(), .line.map_or_else(String::new, |l| l.to_string()))]
    Invalid {
        path: PathBuf,
        line: Option<usize>,
        message: String,
    },
}
