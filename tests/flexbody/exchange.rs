//! Reduced-body exchange formats: the SID file's round trip and broken
//! files, the JSON file, the Matrix Market folder, the VTU file and format
//! detection.

use super::support::{hex_beam, reduce_with, side_beam_json};
use flexbody::export::sid::{parse_sid, read_sid, write_sid};
use flexbody::export::vtu::Encoding;
use flexbody::export::{read_any, read_json, summary, vtk, AnyBody, ExportError, Format};
use flexbody::fem::{Model, Substructure};
use flexbody::output;
use flexbody::reduce::{Method, ReducedBody};
use std::path::Path;

/// Writes `body` in `format` as `flexbody reduce` does (without accuracy
/// figures): its file content computed, then formatted.
fn write(
    body: &ReducedBody,
    sub: &Substructure,
    model: Option<&Model>,
    format: Format,
    path: &Path,
) -> Result<(), ExportError> {
    let files = output::body_output(sub, model, body, format, Default::default()).unwrap();
    flexbody::export::write(&files, format, path)
}

/// Writes the binary VTU file of `body` on `model`: its mode fields
/// computed, then formatted.
fn write_vtu(model: &Model, body: &ReducedBody, path: &Path) -> Result<(), ExportError> {
    write_vtu_as(model, body, Encoding::Binary, path)
}

/// [`write_vtu`] in `encoding`.
fn write_vtu_as(
    model: &Model,
    body: &ReducedBody,
    encoding: Encoding,
    path: &Path,
) -> Result<(), ExportError> {
    vtk::write_vtu(
        model,
        &output::mode_fields(model, body).unwrap(),
        encoding,
        path,
    )
}

/// The hex-element beam, its mesh, and its free-residual body of 2
/// eigenmodes with the tip node 13 as interface.
fn hex_beam_body() -> (Substructure, Model, ReducedBody) {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 2, &[13]);
    (sub, model, body)
}

#[test]
fn sid_round_trip_keeps_every_number() {
    let (sub, model, body) = hex_beam_body();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.sid");
    let sid = output::sid(&sub, Some(&model), &body).unwrap();
    write_sid(&sid, &path).unwrap();
    let back = read_sid(&path).unwrap();
    assert_eq!(back, output::sid(&sub, Some(&model), &body).unwrap());
    assert!(matches!(read_any(&path).unwrap(), AnyBody::Sid(..)));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    let text = std::fs::read_to_string(&path).unwrap();
    for block in [
        "part",
        "new modal",
        "refmod",
        "new frame",
        "new node",
        "end node",
        "end frame",
        "mdCM",
        "J",
        "Ct",
        "Cr",
        "Me",
        "Gr",
        "Ge",
        "Oe",
        "ksigma",
        "Ke",
        "De",
        "end modal",
        "end part",
    ] {
        assert!(text.lines().any(|l| l.trim() == block), "no line '{block}'");
    }
}

#[test]
fn broken_sid_files_name_the_block_and_line() {
    let (sub, _, body) = hex_beam_body();
    let text = output::sid(&sub, None, &body).unwrap().to_text();

    // Truncated inside Ke.
    let cut = text.find("\nKe\n").unwrap() + 40;
    let e = parse_sid(&text[..cut]).unwrap_err();
    assert_eq!(e.block, "Ke", "{e}");
    assert!(e.to_string().contains("ends inside block 'Ke'"), "{e}");
    assert_eq!(e.line, text[..cut].lines().count());

    // One entry of Ke missing: a wrong count.
    let missing: String = text
        .lines()
        .filter(|l| !(l.trim_start().starts_with("m0(2, 1) =") && ke_line(&text, l)))
        .map(|l| format!("{l}\n"))
        .collect();
    let e = parse_sid(&missing).unwrap_err();
    assert_eq!(e.block, "Ke", "{e}");
    assert!(e.message.contains("entries, expected"), "{e}");
    let end_ke = missing.lines().position(|l| l == "end Ke").unwrap() + 1;
    assert_eq!(e.line, end_ke);

    // nelastq that does not match the names.
    let nq = body.r() - 6;
    let wrong = text.replace(&format!("nelastq = {nq}"), &format!("nelastq = {}", nq + 1));
    let e = parse_sid(&wrong).unwrap_err();
    assert_eq!(e.block, "refmod", "{e}");

    // Through the file reader the path is named too.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.sid");
    std::fs::write(&path, &text[..cut]).unwrap();
    let e = read_sid(&path).unwrap_err().to_string();
    assert!(
        e.contains("cut.sid") && e.contains("block 'Ke'") && e.contains("line"),
        "{e}"
    );
}

/// Whether `line` (by content) is inside the `Ke` block of `text`: only the
/// Ke block has the line `m0(2, 1) = v` right after Ke's entries start.
fn ke_line(text: &str, line: &str) -> bool {
    let start = text.find("\nKe\n").unwrap();
    let end = text.find("\nend Ke\n").unwrap();
    text[start..end].lines().any(|l| l == line)
}

#[test]
fn broken_json_files_name_the_block_and_line() {
    let (dir, path, _) = side_beam_json(Method::FreeResidual, 1);
    let text = std::fs::read_to_string(&path).unwrap();

    let cut = text.find("\"basis\"").unwrap() + 200;
    let truncated = dir.path().join("truncated.json");
    std::fs::write(&truncated, &text[..cut]).unwrap();
    let e = read_json(&truncated).unwrap_err().to_string();
    assert!(e.contains("block 'basis'") && e.contains("line"), "{e}");

    let wrong = dir.path().join("wrong.json");
    std::fs::write(&wrong, text.replace("\"r\": 7", "\"r\": 6")).unwrap();
    let e = read_json(&wrong).unwrap_err().to_string();
    let mass_line = text
        .lines()
        .position(|l| l.starts_with("  \"mass\""))
        .unwrap()
        + 1;
    assert!(
        e.contains(&format!(
            "line {mass_line}, block 'mass': mass has 7 rows, r = 6"
        )),
        "{e}"
    );
}

#[test]
fn mtx_folder_round_trip_and_format_detection() {
    let (file, sub, body) = super::side_beam_body(Method::FreeResidual, 1);
    let body = body.with_modal_damping(&[0.02]).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("body");
    write(&body, &sub, Some(&file.model), Format::Mtx, &folder).unwrap();
    for f in [
        "mass.mtx",
        "stiffness.mtx",
        "damping.mtx",
        "basis.mtx",
        "index.json",
    ] {
        assert!(folder.join(f).is_file(), "{f}");
    }
    let AnyBody::Reduced(back, nodes) = read_any(&folder).unwrap() else {
        panic!("not a reduced body")
    };
    assert_eq!(back.basis, body.basis);
    assert_eq!(back.mass, body.mass);
    assert_eq!(back.stiffness, body.stiffness);
    assert_eq!(back.damping, body.damping);
    assert_eq!(back.modes, body.modes);
    assert_eq!(back.interface, body.interface);
    // Every node of the mesh, with its coordinates and lumped masses.
    assert_eq!(nodes.len(), file.model.nodes().len());
    assert!(nodes.iter().all(|n| n.coords.is_some() && n.mass.is_some()));
    let index: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("index.json")).unwrap()).unwrap();
    assert_eq!(index["method"], "free-residual");
    assert_eq!(index["nodes"][20]["coords"][0], 2.5);
    // Through index.json as well.
    assert!(matches!(
        read_any(&folder.join("index.json")).unwrap(),
        AnyBody::Reduced(..)
    ));

    // A truncated basis names the file and line.
    let basis = std::fs::read_to_string(folder.join("basis.mtx")).unwrap();
    std::fs::write(folder.join("basis.mtx"), &basis[..basis.len() / 2]).unwrap();
    let e = read_any(&folder).unwrap_err().to_string();
    assert!(
        e.contains("basis.mtx") && e.contains("line") && e.contains("expected 294"),
        "{e}"
    );
}

#[test]
fn every_writer_leaves_no_partial_file_and_names_the_path() {
    let (file, sub, body) = super::side_beam_body(Method::FreeResidual, 1);
    let dir = tempfile::tempdir().unwrap();
    // MTX last: it creates its folder, which the others would then find.
    let formats = Format::ALL.into_iter().filter(|f| *f != Format::Mtx);
    for format in formats.chain([Format::Mtx]) {
        let path = dir.path().join(format!("missing/body.{format}"));
        let e = write(&body, &sub, Some(&file.model), format, &path);
        // The SID and MBDyn files of a planar beam are written; all fail on
        // the missing folder except MTX, which creates its folder.
        if format == Format::Mtx {
            e.unwrap();
            continue;
        }
        let e = e.unwrap_err();
        assert!(matches!(e, ExportError::Write { .. }), "{format}: {e}");
        assert!(
            e.to_string().contains(&format!("missing/body.{format}")),
            "{e}"
        );
        assert!(!path.exists());
    }
    // MTX into a path below a regular file.
    let blocker = dir.path().join("blocker");
    std::fs::write(&blocker, "x").unwrap();
    let path = blocker.join("body");
    let e = write(&body, &sub, None, Format::Mtx, &path).unwrap_err();
    assert!(e.to_string().contains("blocker/body"), "{e}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    assert!(dir.path().join("missing").read_dir().unwrap().count() == 1);
    // A VTU into a missing folder.
    let path = dir.path().join("nowhere/body.vtu");
    let e = write_vtu(&file.model, &body, &path).unwrap_err();
    assert!(e.to_string().contains("nowhere/body.vtu"), "{e}");
}

#[test]
fn summary_names_r_mass_interface_and_frequencies() {
    let (file, sub, body) = super::side_beam_body(Method::FreeResidual, 1);
    let text = summary(&body);
    let mass = 6800.0 * (0.24 * 0.20 - 0.216 * 0.176) * 2.5;
    assert!(text.contains("r: 7"), "{text}");
    assert!(text.contains(&format!("mass: {mass:.6e} kg")), "{text}");
    assert!(text.contains("at 4 nodes: 1 7 15 21"), "{text}");
    assert!(text.contains("frequencies (Hz): 0.0000 "), "{text}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.sid");
    write(&body, &sub, Some(&file.model), Format::Sid, &path).unwrap();
    let text = read_any(&path).unwrap().summary();
    assert!(text.contains("r: 5 elastic coordinates"), "{text}");
    assert!(text.contains(&format!("mass: {mass:.6e} kg")), "{text}");
}

#[test]
fn vtu_holds_the_mesh_the_modes_and_the_stresses() {
    let (_, model, body) = hex_beam_body();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.vtu");
    for encoding in [Encoding::Binary, Encoding::Ascii] {
        write_vtu_as(&model, &body, encoding, &path).unwrap();
        // The XML before the binary section is text.
        let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
        assert!(text.contains("<VTKFile type=\"UnstructuredGrid\""));
        assert!(text.contains(&format!(
            "NumberOfPoints=\"{}\" NumberOfCells=\"6\"",
            model.nodes().len()
        )));
        for k in 1..=body.r() {
            assert!(text.contains(&format!("Name=\"mode {k:02}\"")), "mode {k}");
            assert!(
                text.contains(&format!("Name=\"mode {k:02} von Mises\"")),
                "mode {k}"
            );
            assert!(
                text.contains(&format!("Name=\"mode {k:02} stress\"")),
                "mode {k}"
            );
        }
        let appended = text.contains("<AppendedData encoding=\"raw\">");
        assert_eq!(appended, encoding == Encoding::Binary, "{encoding:?}");
    }
    // Cells: 6 hexahedra (VTK type 12).
    assert_eq!(vtk::cell_types(&model), vec![12; 6]);

    // A beam model: lines.
    let (file, _, body) = super::side_beam_body(Method::Free, 4);
    let path = dir.path().join("beam.vtu");
    write_vtu(&file.model, &body, &path).unwrap();
    assert_eq!(vtk::cell_types(&file.model), vec![3; 20]);
}
