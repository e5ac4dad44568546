//! flexbody's integration tests: one binary, one module per area. Each test
//! is also an example of the API.

mod beams;
mod bounded_work;
mod calculix;
mod calculix_constraints;
mod calculix_materials;
mod cli;
mod cli_errors;
mod cli_lowest_below;
mod cli_modes;
mod coordinates;
mod damping;
mod deck_constraints;
mod deck_steps;
mod decks;
mod errors;
mod exchange;
mod export;
mod exudyn;
mod file_kinds;
mod guidance;
mod hostile_values;
mod interfaces;
mod local_interface;
mod mbdyn;
mod memory;
mod mesher_names;
mod model_constraints;
mod model_files;
mod plots;
mod report_html;
mod section_forces;
mod shells;
mod sid;
mod sid_dialects;
mod strict_toml;
mod study;
mod support;
mod tie_convergence;
mod vehicle;
mod vtu;
mod whole_outputs;

use flexbody::fem::Substructure;
use flexbody::linalg::memory::Budget;
use flexbody::linalg::progress::NoProgress;
use flexbody::reduce::{Method, ReducedBody};
use flexbody::scenario::{read_model_file, CaseSpec, ModelFile};
use flexbody::study::reduce_case;
use std::path::PathBuf;

/// The bundled example of the report's side beam.
pub fn side_beam_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam.toml")
}

pub fn side_beam_text() -> String {
    std::fs::read_to_string(side_beam_path()).expect("examples/side_beam.toml")
}

/// A study case of `method` with `modes` eigenmodes, no frequency band.
pub fn case(method: Method, modes: usize) -> CaseSpec {
    CaseSpec {
        method,
        modes,
        fmax: None,
    }
}

/// The side beam, its matrices, and its reduction by `method` with `modes`.
pub fn side_beam_body(method: Method, modes: usize) -> (ModelFile, Substructure, ReducedBody) {
    let file = read_model_file(&side_beam_path()).unwrap();
    let sub = Substructure::from_model(&file.model).unwrap();
    let body = reduce_case(
        &file,
        &sub,
        &CaseSpec {
            method,
            modes,
            fmax: None,
        },
        Budget::MACHINE,
        &NoProgress,
    )
    .unwrap();
    (file, sub, body)
}
