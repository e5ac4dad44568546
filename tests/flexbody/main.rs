//! flexbody's integration tests: one binary, one module per area. Each test
//! is also an example of the API.

mod cli;
mod export;
mod study;

use std::path::PathBuf;

/// The bundled example of the report's side beam.
pub fn side_beam_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam.toml")
}

pub fn side_beam_text() -> String {
    std::fs::read_to_string(side_beam_path()).expect("examples/side_beam.toml")
}
