//! Reads FE models: decks, matrices and the model part of TOML model files.
//!
//! [`deck`] reads Abaqus/CalculiX input decks (`.inp`); [`matrices`] reads
//! FE matrices written by other programs (CalculiX `.sti`/`.mas`/`.dof`,
//! Matrix Market); [`model_toml`] reads the FE model of the project's TOML
//! model files (nodes, beam lines, elements, sets, boundary conditions,
//! couplings, damping, or a deck it names). What is done with a model
//! (interface, MBS, study) is not read here. Units are SI throughout (m, kg,
//! s, N, Pa, rad, rad/s). Every error names the file and, where it comes from
//! a line of the file, the line.

pub mod coordinates;
pub mod deck;
pub mod matrices;
pub mod model_toml;
pub mod spelling;
pub mod text;
mod toml_keys;
mod toml_source;

pub use deck::{parse_deck, read_deck, Deck, DeckOptions};
pub use model_toml::{parse_model_toml, ModelToml};
pub use toml_keys::LARGEST_NUMBER;
pub use toml_source::TomlSource;

use std::path::PathBuf;

/// A problem with an input file: where, and what.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    #[error("{}: cannot read: {cause}", .path.display())]
    Read {
        path: PathBuf,
        cause: std::io::Error,
    },
    /// `path:line: message`, or `path: message` where no line applies;
    /// a long message is [`shortened`](text::shortened).
    #[error("{}{}: {}", .path.display(), .line.map_or_else(String::new, |l| format!(":{l}")), text::shortened(.message))]
    Invalid {
        path: PathBuf,
        line: Option<usize>,
        message: String,
    },
}
