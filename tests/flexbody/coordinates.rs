//! Node coordinates for matrix input (`--coords`): matrices from any FE
//! program make a SID, with the same floating frame as the mesh they came
//! from.

use super::support::{fails_with, hex_beam_deck, reduce_args, run_ok};
use flexbody::export::read_sid;
use std::path::{Path, PathBuf};

/// The CalculiX matrices of the hex_beam deck (`*FREQUENCY,
/// SOLVER=MATRIXSTORAGE`), beside it.
fn hex_beam_matrices() -> PathBuf {
    hex_beam_deck().with_extension("sti")
}

/// The `*NODE` lines of the hex_beam deck as `node x y z` lines, written
/// to `path`, without the nodes `drop`.
fn write_coordinates(path: &Path, drop: &[&str]) {
    let deck = std::fs::read_to_string(hex_beam_deck()).unwrap();
    let text: String = deck
        .lines()
        .skip_while(|l| !l.starts_with("*NODE"))
        .skip(1)
        .take_while(|l| !l.starts_with('*'))
        .filter(|l| !drop.contains(&l.split(',').next().unwrap().trim()))
        .map(|l| l.replace(',', " ") + "\n")
        .collect();
    std::fs::write(path, text).unwrap();
}

#[test]
fn matrices_with_coordinates_make_the_sid_of_their_mesh() {
    // The same free-residual body (tip node 13), once from the deck and
    // once from CalculiX's matrices with the deck's coordinates: the same
    // mass, centre of mass and inertia tensor, and the same elastic
    // frequencies, to the 14 digits CalculiX writes.
    let dir = tempfile::tempdir().unwrap();
    let coords = dir.path().join("nodes.txt");
    write_coordinates(&coords, &[]);
    let extra = ["--interface", "13", "--format", "sid"];
    let from_deck = dir.path().join("deck.sid");
    run_ok(&reduce_args(
        hex_beam_deck(),
        "free-residual",
        "4",
        &from_deck,
        &extra,
    ));
    let from_matrices = dir.path().join("matrices.sid");
    let mut args = reduce_args(
        hex_beam_matrices(),
        "free-residual",
        "4",
        &from_matrices,
        &extra,
    );
    args.extend(["--coords".into(), coords.to_str().unwrap().into()]);
    run_ok(&args);
    let (a, b) = (
        read_sid(&from_deck).unwrap(),
        read_sid(&from_matrices).unwrap(),
    );
    let close = |what: &str, x: f64, y: f64, scale: f64| {
        assert!((x - y).abs() <= 1e-10 * scale, "{what}: {x} against {y}");
    };
    close("mass", a.refmod.mass, b.refmod.mass, a.refmod.mass);
    let (ca, cb) = (a.center_of_mass(), b.center_of_mass());
    let scale = a.j.m0.norm_max();
    for i in 0..3 {
        close("centre of mass", ca[i], cb[i], 1.0);
        for j in 0..3 {
            close("J", a.j.m0[(i, j)], b.j.m0[(i, j)], scale);
        }
    }
    let (fa, fb) = (a.frequencies_hz().unwrap(), b.frequencies_hz().unwrap());
    assert_eq!(fa.len(), fb.len());
    for (x, y) in fa.iter().zip(&fb) {
        close("frequency", *x, *y, *x);
    }
    assert_eq!(b.nodes[0].origin.m0[(0, 0)], 0.6);

    // A JSON body of the matrices lists their nodes with the coordinates
    // given; matrices have no elements to lump, so no masses.
    let json = dir.path().join("matrices.json");
    let mut args = reduce_args(
        hex_beam_matrices(),
        "free-residual",
        "4",
        &json,
        &["--interface", "13"],
    );
    args.extend(["--coords".into(), coords.to_str().unwrap().into()]);
    run_ok(&args);
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let nodes = doc["nodes"].as_array().unwrap();
    assert_eq!(
        nodes.len(),
        std::fs::read_to_string(&coords).unwrap().lines().count()
    );
    let tip = nodes.iter().find(|n| n["id"] == 13).unwrap();
    assert_eq!(tip["coords"][0], 0.6);
    assert!(nodes.iter().all(|n| n.get("mass").is_none()), "{tip}");
}

#[test]
fn coordinates_that_do_not_fit_the_matrices_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body.sid");
    let reduce = |coords: &Path| {
        let mut args = reduce_args(hex_beam_matrices(), "free", "4", &out, &["--format", "sid"]);
        args.extend(["--coords".into(), coords.to_str().unwrap().into()]);
        args
    };
    // A node of the matrices without coordinates.
    let missing = dir.path().join("missing.txt");
    write_coordinates(&missing, &["27"]);
    fails_with(
        &reduce(&missing),
        &[
            "missing.txt",
            "no coordinates for node 27, which has DOFs in the matrices",
        ],
    );
    // A line that is not `node x y z`, a value that is not a number, a
    // node listed twice: each at its line.
    for (name, text, message) in [
        (
            "short.txt",
            "1 0 0 0\n3 0.1 0\n",
            "short.txt:2: expected `node x y z`",
        ),
        (
            "nan.txt",
            "1 0 0 0\n3 0.1 nan 0\n",
            "nan.txt:2: node 3: 'nan' is not a finite number",
        ),
        (
            "twice.txt",
            "1 0 0 0\n\n1 0.1 0 0\n",
            "twice.txt:3: node 1 is listed twice (first on line 1)",
        ),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        fails_with(&reduce(&path), &[message]);
    }
    // A mesh has coordinates of its own.
    let coords = dir.path().join("nodes.txt");
    write_coordinates(&coords, &[]);
    let mut args = reduce_args(hex_beam_deck(), "free", "4", &out, &[]);
    args.extend(["--coords".into(), coords.to_str().unwrap().into()]);
    fails_with(&args, &["--coords gives node coordinates to matrix input"]);
    assert!(!out.exists());
}
