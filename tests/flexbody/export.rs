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
    let e = write_json(&body, &[], &path).unwrap_err();
    assert!(e.to_string().contains("missing_dir/body.json"), "{e}");
    assert!(!path.exists());
}

/// A JSON body reduced from a mesh lists every node of the mesh, the
/// clamped one too, with its coordinates and HRZ lumped masses: their sum
/// along each axis is the mesh's whole mass (the 157 kg of the clamped
/// beam, 2 m of 0.01 m^2 steel, of which the free DOFs' mass matrix
/// holds 147.13 kg), as `info` reports it; the Matrix Market index lists
/// the same nodes, and `inspect` sums them.
#[test]
fn a_json_body_lists_the_mesh_nodes_with_lumped_masses_that_sum_to_the_full_mass() {
    use super::support::{reduce_args, run_ok};
    let model = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/sid/welib_clamped_beam.toml");
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("body.json");
    run_ok(&reduce_args(&model, "craig-bampton", "4", &json, &[]));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let nodes = doc["nodes"].as_array().unwrap();
    assert_eq!(nodes.len(), 11, "every node of the mesh, node 1 clamped");
    let whole = 2.0 * 0.01 * 7850.0;
    let mut sum = [0.0; 6];
    for (k, n) in nodes.iter().enumerate() {
        assert_eq!(n["id"], k as u64 + 1);
        let x = n["coords"][0].as_f64().unwrap();
        assert!(
            (x - 0.2 * k as f64).abs() < 1e-15,
            "node {}: x = {x}",
            k + 1
        );
        let m = n["mass"].as_array().unwrap();
        for (s, v) in sum.iter_mut().zip(m) {
            let v = v.as_f64().unwrap();
            assert!(v >= 0.0, "{n}");
            *s += v;
        }
    }
    for s in &sum[..3] {
        assert!((s - whole).abs() < 1e-12 * whole, "{sum:?}");
    }
    // The torsional inertia of the beam's sections, rho I_p L.
    let torsion = 7850.0 * 3.0e-5 * 2.0;
    assert!((sum[3] - torsion).abs() < 1e-12 * torsion, "{sum:?}");
    let info = run_ok(&["info", model.to_str().unwrap()]);
    let info = String::from_utf8_lossy(&info.stdout).into_owned();
    let line = info
        .lines()
        .find(|l| l.starts_with("full mass along x, y, z"))
        .unwrap();
    let full: f64 = line
        .rsplit(": ")
        .next()
        .unwrap()
        .split(", ")
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((full - sum[0]).abs() < 1e-12 * whole, "{line}");

    let folder = dir.path().join("body");
    run_ok(&reduce_args(
        &model,
        "craig-bampton",
        "4",
        &folder,
        &["--format", "mtx"],
    ));
    let index: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("index.json")).unwrap()).unwrap();
    assert_eq!(&index["nodes"], &doc["nodes"]);
    for body in [&json, &folder] {
        let o = run_ok(&["inspect", body.to_str().unwrap()]);
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(
            text.contains("mesh: 11 nodes, 11 with coordinates; lumped masses sum to 1.570000e2, 1.570000e2, 1.570000e2 kg"),
            "{text}"
        );
        let o = run_ok(&["inspect", "--json", body.to_str().unwrap()]);
        let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(summary["nodes"], 11);
        let lumped = summary["lumped_mass_kg"][2].as_f64().unwrap();
        assert!((lumped - whole).abs() < 1e-12 * whole, "{summary}");
    }
}

/// The nodes of a JSON body are checked as it is read: a negative lumped
/// mass, a coordinate that is not a number and a node listed twice are
/// refused, naming the node, the block and its line.
#[test]
fn broken_nodes_of_a_json_body_are_refused_at_their_block() {
    use super::support::{fails_with, reduce_args, run_ok};
    let model = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/sid/welib_clamped_beam.toml");
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("body.json");
    run_ok(&reduce_args(&model, "craig-bampton", "2", &json, &[]));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    // (case, the entry changed, its new value, the message)
    let cases = [
        (
            "negative",
            "/nodes/1/mass/0",
            serde_json::json!(-1.0),
            "node 2: lumped mass -1e0",
        ),
        (
            "text",
            "/nodes/1/coords/2",
            serde_json::json!("nan"),
            "invalid type: string \"nan\"",
        ),
        (
            "twice",
            "/nodes/2/id",
            serde_json::json!(2),
            "node 2 is listed twice",
        ),
    ];
    for (name, entry, value, needle) in cases {
        let mut d = doc.clone();
        *d.pointer_mut(entry).unwrap() = value;
        let text = serde_json::to_string_pretty(&d).unwrap();
        let bad = dir.path().join(format!("{name}.json"));
        std::fs::write(&bad, &text).unwrap();
        let line = if name == "text" {
            text.find("\"nan\"")
                .map(|at| text[..at].lines().count())
                .unwrap()
        } else {
            text.lines()
                .position(|l| l.starts_with("  \"nodes\""))
                .unwrap()
                + 1
        };
        fails_with(
            &["inspect", bad.to_str().unwrap()],
            &[&format!("line {line}, block 'nodes'"), needle],
        );
    }
}
