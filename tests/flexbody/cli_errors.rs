//! The `flexbody` command on bad input: exit code 2, a message naming file
//! and line, never a panic.

use super::support::{
    fails_with, flexbody, hex_beam_deck, mid_span_interface, reduce_args, run_ok, stderr, variant,
};

/// `flexbody study` on the side beam with `from` replaced by `to` (written
/// as `name`) fails with all `needles`.
fn study_of_variant_fails_with(name: &str, from: &str, to: &str, needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let m = variant(dir.path(), name, from, to);
    fails_with(&["study", &m], needles);
}

#[test]
fn a_connection_to_a_missing_node_names_it_and_the_line() {
    study_of_variant_fails_with(
        "m.toml",
        "node = 21",
        "node = 99",
        &["m.toml:53:", "node 99", "does not exist"],
    );
}

#[test]
fn a_misspelt_section_key_is_refused_not_defaulted() {
    // A general section's shear area misspelt would have been skipped and
    // the default 5/6 of the area taken in its place.
    study_of_variant_fails_with(
        "m.toml",
        "shape = \"box\"             # box section b x h, wall t (appendix A)\nwidth = 0.24              # m, along y\nheight = 0.20             # m, along z\nwall = 0.012              # m",
        "shape = \"general\"\narea = 1e-2\niy = 1e-5\niz = 1e-5\ntorsion = 2e-5\nshear_area_z = 5e-3\nshear_aera_y = 5e-3",
        &[
            "m.toml:19:",
            "unknown key `shear_aera_y` in [[section]] 'box'",
            "did you mean `shear_area_y`?",
        ],
    );
    // The same with the key spelt right is read.
    let dir = tempfile::tempdir().unwrap();
    let good = variant(
        dir.path(),
        "g.toml",
        "shape = \"box\"             # box section b x h, wall t (appendix A)\nwidth = 0.24              # m, along y\nheight = 0.20             # m, along z\nwall = 0.012              # m",
        "shape = \"general\"\narea = 1e-2\niy = 1e-5\niz = 1e-5\ntorsion = 2e-5\nshear_area_z = 5e-3\nshear_area_y = 5e-3",
    );
    run_ok(&["info", &good]);
}

#[test]
fn a_negative_density_names_the_line() {
    study_of_variant_fails_with(
        "m.toml",
        "density = 6800.0",
        "density = -6800.0",
        &["m.toml:9:", "density"],
    );
}

#[test]
fn unknown_methods_are_refused() {
    let model = super::side_beam_path();
    fails_with(
        &[
            "reduce",
            model.to_str().unwrap(),
            "--method",
            "hurty",
            "--out",
            "x.json",
        ],
        &["unknown method 'hurty'", "free-residual"],
    );
    study_of_variant_fails_with(
        "m2.toml",
        "{ method = \"free\", modes = 7 }",
        "{ method = \"hurty\", modes = 7 }",
        &[
            "m2.toml:",
            "unknown value `hurty` for `method` in `cases[2]` of [study]",
        ],
    );
}

#[test]
fn an_interface_that_leaves_a_mechanism_names_the_free_dofs() {
    let dir = tempfile::tempdir().unwrap();
    let m = mid_span_interface(dir.path());
    let out = dir.path().join("b.json");
    fails_with(
        &reduce_args(&m, "craig-bampton", "1", &out, &[]),
        &["mechanism", "K_NN is singular", "node 1 uz", "node 21 uz"],
    );
    assert!(!out.exists());
}

#[test]
fn missing_files_and_unwritable_outputs_are_named() {
    fails_with(
        &["study", "no/such/model.toml"],
        &["no/such/model.toml", "cannot read"],
    );
    let model = super::side_beam_path();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("no_dir/body.json");
    fails_with(
        &[
            "reduce",
            model.to_str().unwrap(),
            "--method",
            "guyan",
            "--out",
            out.to_str().unwrap(),
        ],
        &["no_dir/body.json", "cannot write"],
    );
    assert!(!out.exists());
}

#[test]
fn two_unconnected_cubes_are_a_mechanism_named_with_its_zero_modes() {
    // Two steel C3D8 cubes that share no node: 12 zero frequencies where
    // a free body has 6 rigid-body motions.
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("cubes.inp");
    let mut text = String::from("*NODE\n");
    for (first, x0) in [(1, 0.0), (11, 2.0)] {
        for (k, [x, y, z]) in [
            [0, 0, 0],
            [1, 0, 0],
            [1, 1, 0],
            [0, 1, 0],
            [0, 0, 1],
            [1, 0, 1],
            [1, 1, 1],
            [0, 1, 1],
        ]
        .iter()
        .enumerate()
        {
            text += &format!("{}, {}, {y}, {z}\n", first + k, x0 + *x as f64);
        }
    }
    text += "*ELEMENT, TYPE=C3D8, ELSET=E\n1, 1, 2, 3, 4, 5, 6, 7, 8\n\
             2, 11, 12, 13, 14, 15, 16, 17, 18\n\
             *MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n\
             *SOLID SECTION, ELSET=E, MATERIAL=STEEL\n";
    std::fs::write(&deck, &text).unwrap();
    let deck = deck.to_str().unwrap();
    let o = run_ok(&["modes", deck, "--count", "14"]);
    assert!(
        stderr(&o).contains("12 modes have zero frequency, more than the 6 rigid-body motions"),
        "{}",
        stderr(&o)
    );
    let o = flexbody(&["modes", deck, "--count", "8"]);
    assert!(stderr(&o).contains("all 8 modes computed have zero frequency"));
    let out = dir.path().join("b.json");
    for method in ["free", "free-residual"] {
        fails_with(
            &reduce_args(deck, method, "6", &out, &["--interface", "1"]),
            &["12 zero-frequency modes but only 6 rigid-body modes"],
        );
    }
    assert!(!out.exists());
    // Held at four nodes of the first cube, the second is free: its 6
    // rigid-body motions are zero frequencies of a held model. Held at
    // four nodes of each, the model has none, and `modes` says nothing.
    let held = dir.path().join("held.inp");
    let hold = |nodes: &[u32]| -> String { nodes.iter().map(|n| format!("{n}, 1, 3\n")).collect() };
    std::fs::write(&held, format!("{text}*BOUNDARY\n{}", hold(&[1, 2, 4, 5]))).unwrap();
    let o = run_ok(&["modes", held.to_str().unwrap(), "--count", "8"]);
    assert!(
        stderr(&o).contains("6 modes have zero frequency although the model is held"),
        "{}",
        stderr(&o)
    );
    std::fs::write(
        &held,
        format!("{text}*BOUNDARY\n{}", hold(&[1, 2, 4, 5, 11, 12, 14, 15])),
    )
    .unwrap();
    let o = run_ok(&["modes", held.to_str().unwrap(), "--count", "8"]);
    assert!(!stderr(&o).contains("zero frequency"), "{}", stderr(&o));
}

#[test]
fn reduce_refuses_an_output_it_cannot_write_before_it_reduces() {
    // Each of these once failed only after the reduction, the last one
    // with the body already written: at 1e6 DOFs, ten minutes later.
    let dir = tempfile::tempdir().unwrap();
    let deck = hex_beam_deck();
    let sti = deck.with_extension("sti");
    let (deck, sti) = (deck.to_str().unwrap(), sti.to_str().unwrap());
    let body = dir.path().join("b.json");
    let a_file = dir.path().join("a_file");
    std::fs::write(&a_file, "x").unwrap();
    let folder = dir.path().to_str().unwrap();
    let reduce = |model: &str, out: &str, extra: &[&str], needles: &[&str]| {
        let mut args = reduce_args(model, "craig-bampton", "2", out, &["--interface", "1,13"]);
        args.extend(extra.iter().map(|a| a.to_string()));
        fails_with(&args, needles);
    };
    let missing = dir.path().join("none/b.json");
    reduce(
        deck,
        missing.to_str().unwrap(),
        &[],
        &["none/b.json", "cannot write"],
    );
    reduce(deck, folder, &[], &["cannot write: it is a folder"]);
    let vtu = dir.path().join("none/b.vtu");
    let b = body.to_str().unwrap();
    reduce(deck, b, &["--vtu", vtu.to_str().unwrap()], &["none/b.vtu"]);
    let at = a_file.to_str().unwrap();
    reduce(
        deck,
        at,
        &["--format", "mtx"],
        &["a_file", "a file is in the folder's place"],
    );
    let other = dir.path().join("m.vtu");
    reduce(
        sti,
        b,
        &["--vtu", other.to_str().unwrap()],
        &["--vtu needs a mesh"],
    );
    assert!(!body.exists() && !other.exists());
    // Nothing of the checks is left behind.
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(left.len(), 1, "{left:?}");
    // The commands that write a folder make it first.
    let vehicle =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/vehicle.toml");
    let under_a_file = a_file.join("plots");
    let (vehicle, under) = (vehicle.to_str().unwrap(), under_a_file.to_str().unwrap());
    for command in ["study", "simulate", "frf"] {
        fails_with(
            &[command, vehicle, "--out", under],
            &["a_file/plots", "cannot create directory"],
        );
    }
    // A command that fails after making its folder takes it away again:
    // the vehicle has no [study] table.
    let new = dir.path().join("new");
    let deeper = new.join("deeper");
    fails_with(
        &["study", vehicle, "--out", deeper.to_str().unwrap()],
        &["no [study] table"],
    );
    assert!(!new.exists());
}

/// A cantilever of two B31 beams whose `*BOUNDARY` is misspelt `*BOUNDRY`
/// (line 15): read as written it would run free-free.
const MISSPELT_BOUNDARY: &str = "\
*HEADING
cantilever with a misspelt *BOUNDARY
*NODE
1, 0, 0, 0
2, 0.5, 0, 0
3, 1.0, 0, 0
*ELEMENT, TYPE=B31, ELSET=BEAM
1, 1, 2
2, 2, 3
*MATERIAL, NAME=STEEL
*ELASTIC
2.1E11, 0.3
*DENSITY
7850
*BOUNDRY
1, 1, 6
*BEAM SECTION, ELSET=BEAM, MATERIAL=STEEL, SECTION=RECT
0.04, 0.06
0., 1., 0.
*STEP
*FREQUENCY
3
*END STEP
";

#[test]
fn a_misspelt_deck_keyword_is_refused_unless_allowed() {
    // Before, *BOUNDRY was skipped with a warning lost among the ignored
    // *HEADING and *STEP, and the cantilever ran free-free with exit 0.
    assert_eq!(
        MISSPELT_BOUNDARY.lines().nth(14),
        Some("*BOUNDRY"),
        "line 15"
    );
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("beam.inp");
    std::fs::write(&deck, MISSPELT_BOUNDARY).unwrap();
    // A model file naming the deck obeys the same flag.
    let model = dir.path().join("beam.toml");
    std::fs::write(&model, "mesh = \"beam.inp\"\n").unwrap();
    for input in [&deck, &model] {
        let input = input.to_str().unwrap();
        fails_with(
            &["modes", input, "--count", "3"],
            &["beam.inp:15:", "*BOUNDRY", "did you mean *BOUNDARY?"],
        );
        let o = run_ok(&["modes", input, "--count", "3", "--allow-unknown"]);
        let err = stderr(&o);
        let unknown: Vec<&str> = err
            .lines()
            .filter(|l| l.contains("unknown keyword"))
            .collect();
        assert_eq!(
            unknown,
            [format!(
                "warning: {}: unknown keywords skipped (--allow-unknown; they may have \
                 changed K, M or D): *BOUNDRY (line 15)",
                deck.display()
            )],
            "{err}"
        );
        // Skipped, the beam is free: six rigid-body modes near 0 Hz.
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(out.contains("18 DOFs"), "{out}");
    }
    // The flag is global: accepted before the subcommand too.
    run_ok(&[
        "--allow-unknown",
        "modes",
        deck.to_str().unwrap(),
        "--count",
        "3",
    ]);
}
