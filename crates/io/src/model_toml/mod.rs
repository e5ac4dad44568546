//! The model part of a TOML model file (format documented in
//! `docs/model-file.md`): title, mesh deck, materials, sections, nodes,
//! beam lines, elements, node sets, boundary conditions, couplings,
//! constraints (equations, MPCs, ties) and damping, read into a
//! [`flexbody_fem::Model`].
//!
//! The file's other tables (interface, MBS, study, simulation, frequency
//! response) describe what is done with the model; they are read by the
//! scenario reader of the `flexbody` crate, which names their keys to
//! [`parse_model_toml`]. Here they are skipped; a top-level key neither
//! reader knows is refused with the nearest of both key sets.

mod build;
mod raw;

pub use raw::DofEntry;

use crate::deck::{DeckOptions, UnknownKeywords};
use crate::{InputError, TomlSource};
use flexbody_fem::Model;

/// The FE model a TOML file describes.
#[derive(Clone, Debug)]
pub struct ModelToml {
    pub title: Option<String>,
    pub model: Model,
    /// Unknown keywords the `mesh` deck skipped (only under
    /// [`DeckOptions::allow_unknown`]).
    pub unknown: UnknownKeywords,
    /// The `mesh` deck's warnings (parameters and fixed DOFs it ignored),
    /// each naming the deck.
    pub warnings: Vec<String>,
    /// The `mesh` deck's note on the routine keywords it skipped
    /// (`*STEP`, outputs), naming the deck.
    pub notes: Vec<String>,
    /// The `mesh` deck's element sets (upper-case names).
    pub element_sets: std::collections::BTreeMap<String, Vec<usize>>,
    /// The file's and its deck's materials and sections, for the user.
    pub catalogue: crate::deck::Catalogue,
}

/// The top-level keys of the FE model, in the order `docs/model-file.md`
/// gives them.
pub const MODEL_KEYS: &[&str] = &[
    "title",
    "mesh",
    "material",
    "section",
    "nodes",
    "beam_line",
    "element",
    "sets",
    "boundary",
    "coupling",
    "equation",
    "mpc",
    "tie",
    "damping",
];

/// Reads the model sections of a TOML text and builds the model; errors
/// name the file and line. `other_keys` are the top-level keys the caller
/// reads (none for a file that is only a model): they are skipped here,
/// and a key in neither [`MODEL_KEYS`] nor `other_keys` is refused. A
/// `mesh` deck is read with `options`.
pub fn parse_model_toml(
    src: TomlSource<'_>,
    options: &DeckOptions,
    other_keys: &[&str],
) -> Result<ModelToml, InputError> {
    let known: Vec<&str> = MODEL_KEYS.iter().chain(other_keys).copied().collect();
    src.refuse_unknown_top_level(&known)?;
    let raw: raw::RawModel = src.parse()?;
    let built = build::build(src, &raw, options)?;
    Ok(ModelToml {
        title: raw.title,
        model: built.model,
        unknown: built.unknown,
        warnings: built.warnings,
        notes: built.notes,
        element_sets: built.element_sets,
        catalogue: built.catalogue,
    })
}
