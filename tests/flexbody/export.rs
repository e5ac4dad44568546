//! Reduced-body files: a JSON round trip, and clear errors for broken files.

use super::support::side_beam_json;
use flexbody::export::{read_json, write_json, ExportError};
use flexbody::reduce::Method;

#[test]
fn json_round_trip_keeps_every_number() {
    let (dir, path, body) = side_beam_json(Method::FreeResidual, 1);
    let back = read_json(&path).unwrap();
    assert_eq!(back.r(), 7);
    assert_eq!(back.basis, body.basis);
    assert_eq!(back.mass, body.mass);
    assert_eq!(back.stiffness, body.stiffness);
    assert_eq!(back.interface, body.interface);
    assert_eq!(back.modes, body.modes);
    assert_eq!(back.dof_map.dofs(), body.dof_map.dofs());
    // No temporary file is left beside it.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn broken_files_are_reported_with_what_is_wrong() {
    let (dir, path, _) = side_beam_json(Method::Guyan, 0);
    let text = std::fs::read_to_string(&path).unwrap();

    let truncated = dir.path().join("truncated.json");
    std::fs::write(&truncated, &text[..text.len() / 2]).unwrap();
    let e = read_json(&truncated).unwrap_err();
    assert!(
        matches!(e, ExportError::Format { .. }) && e.to_string().contains("line"),
        "{e}"
    );

    let wrong_r = dir.path().join("wrong_r.json");
    std::fs::write(&wrong_r, text.replace("\"r\": 4", "\"r\": 5")).unwrap();
    let e = read_json(&wrong_r).unwrap_err().to_string();
    assert!(e.contains("mass has 4 rows, r = 5"), "{e}");
}

#[test]
fn a_failed_write_leaves_no_file() {
    let (_, _, body) = super::side_beam_body(Method::Guyan, 0);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing_dir/body.json");
    let e = write_json(&body, &path).unwrap_err();
    assert!(e.to_string().contains("missing_dir/body.json"), "{e}");
    assert!(!path.exists());
}
