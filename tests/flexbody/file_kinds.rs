//! A command given another kind of file than it takes says what it got and
//! what it takes (exit code 2), instead of its parser's first complaint; a
//! file of the right kind keeps its parser's file:line message.

use super::support::{fails_with, flexbody, hex_beam_deck, reduce_args, stderr, variant};

#[test]
fn study_on_a_deck_says_it_takes_a_model_file() {
    let deck = hex_beam_deck();
    fails_with(
        &["study", deck.to_str().unwrap(), "--no-plots"],
        &[
            "hex_beam.inp is a CalculiX/Abaqus deck",
            "`study` takes a model file (.toml) with a [study] table",
            "docs/model-file.md",
        ],
    );
}

#[test]
fn a_deck_named_toml_is_recognised_by_its_content() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bar.toml");
    std::fs::copy(hex_beam_deck(), &path).unwrap();
    fails_with(
        &["study", path.to_str().unwrap(), "--no-plots"],
        &[
            "bar.toml is a CalculiX/Abaqus deck",
            "`study` takes a model file",
        ],
    );
}

#[test]
fn inspect_on_a_deck_says_it_reads_reduced_bodies() {
    let deck = hex_beam_deck();
    fails_with(
        &["inspect", deck.to_str().unwrap()],
        &[
            "hex_beam.inp is a CalculiX/Abaqus deck",
            "`inspect` takes a reduced body (JSON, SID or a Matrix Market folder)",
            "what `reduce` writes",
        ],
    );
}

#[test]
fn inspect_on_an_mbdyn_file_says_flexbody_writes_it_but_does_not_read_it() {
    // Its `**` comments would make it look like a deck.
    let dir = tempfile::tempdir().unwrap();
    let fem = dir.path().join("body.fem");
    let o = flexbody(&reduce_args(
        hex_beam_deck(),
        "free-residual",
        "2",
        &fem,
        &["--interface", "13", "--format", "mbdyn"],
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    fails_with(
        &["inspect", fem.to_str().unwrap()],
        &[
            "body.fem is MBDyn's modal FEM file, which flexbody writes for MBDyn but does not read",
            "`inspect` takes a reduced body",
        ],
    );
}

#[test]
fn inspect_on_a_model_file_says_it_reads_reduced_bodies() {
    let model = super::side_beam_path();
    fails_with(
        &["inspect", model.to_str().unwrap()],
        &[
            "side_beam.toml is a model file (TOML)",
            "`inspect` takes a reduced body",
        ],
    );
}

#[test]
fn reduce_on_a_reduced_body_says_it_takes_a_model() {
    let dir = tempfile::tempdir().unwrap();
    let body = dir.path().join("body.json");
    std::fs::write(
        &body,
        "{\n  \"format\": \"flexbody-reduced-body/1\",\n  \"r\": 1\n}\n",
    )
    .unwrap();
    let args = reduce_args(
        &body,
        "craig-bampton",
        "2",
        dir.path().join("out.json"),
        &[],
    );
    fails_with(
        &args,
        &[
            "body.json is a reduced body (JSON)",
            "`reduce` takes a model file (.toml), a deck (.inp)",
        ],
    );
}

#[test]
fn a_model_file_with_a_syntax_error_keeps_its_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let m = variant(
        dir.path(),
        "m.toml",
        "density = 6800.0",
        "density = = 6800.0",
    );
    let o = flexbody(&["study", &m, "--no-plots"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("m.toml:9:"), "{err}");
    assert!(!err.contains("takes"), "{err}");
}
