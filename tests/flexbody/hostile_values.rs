//! Values that are numbers but not physics are refused where they are
//! read, naming the file and line: inertia tensors that are not positive
//! semi-definite or not finite (once accepted, or failing late as a
//! singular matrix at some node), and a band `--fmax` that is no frequency
//! (`cli_modes.rs`); and the messages that say so name each cause once
//! and no empty line number, and quote no more than a short excerpt of a
//! huge line.

use super::support::fails_with;
use std::path::PathBuf;

fn vehicle() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/vehicle.toml");
    std::fs::read_to_string(path).unwrap()
}

/// `text` with `from` replaced by `to`, written to `dir/name`.
fn write(dir: &std::path::Path, name: &str, text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from}");
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn a_rigid_body_inertia_must_be_positive_semi_definite_and_finite() {
    let dir = tempfile::tempdir().unwrap();
    let text = vehicle();
    let line = text
        .lines()
        .position(|l| l.starts_with("[[rigid_body]]"))
        .unwrap()
        + 1;
    let from = "inertia = [0.0, 4000.0, 0.0, 0.0, 0.0, 0.0]";
    for (to, rule) in [
        (
            "inertia = [0.0, -4000.0, 0.0, 0.0, 0.0, 0.0]",
            "moments not negative",
        ),
        (
            "inertia = [10.0, 4000.0, 10.0, 300.0, 0.0, 0.0]",
            "products of inertia",
        ),
        ("inertia = [0.0, nan, 0.0, 0.0, 0.0, 0.0]", "finite"),
    ] {
        let model = write(dir.path(), "v.toml", &text, from, to);
        fails_with(
            &[
                "simulate",
                &model,
                "--out",
                dir.path().join("out").to_str().unwrap(),
            ],
            &[
                &format!("v.toml:{line}"),
                "inertia of rigid body 'car_body'",
                rule,
            ],
        );
    }
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_point_mass_inertia_must_be_positive_semi_definite_and_finite() {
    let dir = tempfile::tempdir().unwrap();
    let text = vehicle();
    // A point mass on the side beam's first node, after the last table of
    // the file's FE model.
    let anchor = "[[rigid_body]]";
    for (inertia, rule) in [
        ("[1.0, 1.0, -1.0, 0.0, 0.0, 0.0]", "moments not negative"),
        ("[1.0, 1.0, 1.0, 0.0, 0.0, 5.0]", "products of inertia"),
        ("[1.0, inf, 1.0, 0.0, 0.0, 0.0]", "finite"),
    ] {
        let mass = format!(
            "[[element]]\ntype = \"point-mass\"\nid = 9001\nnode = 1\nmass = 2.0\n\
             inertia = {inertia}\n\n{anchor}"
        );
        let model = write(dir.path(), "m.toml", &text, anchor, &mass);
        fails_with(
            &["info", &model],
            &["m.toml:", "inertia of point mass 9001", rule],
        );
    }
}

#[test]
fn a_message_names_each_cause_once_and_no_empty_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.json"), "{\"format\": \"x\"}").unwrap();
    let text = vehicle().replace("modes = 1\n", "");
    let from = "method = \"free-residual\"";
    let model = write(dir.path(), "v.toml", &text, from, "body = \"bad.json\" #");
    let o = super::support::flexbody(&[
        "simulate",
        &model,
        "--out",
        dir.path().join("o").to_str().unwrap(),
    ]);
    let err = super::support::stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.matches("missing field").count(), 1, "{err}");
    assert!(err.contains("reading the reduced body: "), "{err}");
    // A model without DOFs has no line to name: `file: message`.
    let deck = dir.path().join("nodes.inp");
    std::fs::write(&deck, "*NODE\n1, 0, 0, 0\n").unwrap();
    fails_with(
        &["info", deck.to_str().unwrap()],
        &["nodes.inp: the model has no DOFs"],
    );
}

#[test]
fn a_huge_line_is_not_echoed_whole() {
    let dir = tempfile::tempdir().unwrap();
    // A 3 MB coordinate in a deck, as a corrupted or hostile file has it.
    let deck = dir.path().join("big.inp");
    let huge = "9".repeat(3_000_000);
    std::fs::write(&deck, format!("*NODE\n1, {huge}, 0, 0\n")).unwrap();
    let o = super::support::flexbody(&["info", deck.to_str().unwrap()]);
    let err = super::support::stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(err.len() < 500, "{} bytes", err.len());
    // Longer than a line may be (1 MiB): refused as it is read.
    assert!(
        err.starts_with("error: ")
            && err.contains("big.inp:2: the line is at least")
            && err.contains("bytes long, more than the 1048576 a line"),
        "{}",
        &err[..200]
    );
    // Shorter, it is quoted as an excerpt of its start.
    let huge = "9".repeat(900_000);
    std::fs::write(&deck, format!("*NODE\n1, {huge}, 0, 0\n")).unwrap();
    let o = super::support::flexbody(&["info", deck.to_str().unwrap()]);
    let err = super::support::stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(err.len() < 400, "{} bytes", err.len());
    assert!(
        err.contains("big.inp:2: node 1: coordinate 1: expected a finite number, got '999")
            && err.contains("999... (900000 bytes)'"),
        "{}",
        &err[..200]
    );
}
