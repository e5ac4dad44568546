//! The `flexbody` command: its outputs, and bad input (exit code 2, a
//! message naming file and line, never a panic).

use std::path::Path;
use std::process::{Command, Output};

pub(crate) fn flexbody(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flexbody"))
        .args(args)
        .output()
        .expect("run flexbody")
}

pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `args` expecting exit code 2 and a message containing all `needles`.
pub(crate) fn fails_with(args: &[&str], needles: &[&str]) {
    let o = flexbody(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: expected '{n}' in: {err}");
    }
}

/// The solid side beam example (1668 DOFs, the sparse solver).
fn solid_side_beam() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam_solid.toml")
}

/// The side beam with `from` replaced by `to`, written to `dir/name`.
fn variant(dir: &Path, name: &str, from: &str, to: &str) -> String {
    let text = super::side_beam_text();
    assert!(text.contains(from), "{from}");
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn study_json_lists_every_case_and_plots_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plots");
    let model = super::side_beam_path();
    let o = flexbody(&[
        "study",
        model.to_str().unwrap(),
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let cases = doc["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 14);
    let fr = cases
        .iter()
        .find(|c| c["method"] == "free-residual" && c["omega"] == 122.0)
        .unwrap();
    assert_eq!(fr["r"], 7);
    // The README's table: free-residual 2 + 4 + 1 at 122 rad/s errs by
    // 7.98e-9 in w, 1.37e-5 in M and 6.67e-5 in Q (measured); bounds at
    // about three times those.
    for (key, bound) in [("err_w", 3e-8), ("err_m", 5e-5), ("err_q", 2e-4)] {
        let err = fr[key].as_f64().unwrap();
        assert!(err < bound, "{key} = {err:e}");
    }
    let svgs: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(
        svgs.len(),
        14 + 2,
        "a plot per case, a convergence plot per Omega"
    );
    assert!(out.join("convergence_omega122.svg").exists());
    let svg = std::fs::read_to_string(out.join("free-residual_r7_omega122.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("shear force Q(x)"));
}

#[test]
fn reduce_writes_the_body_and_compares_frequencies() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body.json");
    let model = super::side_beam_path();
    let o = flexbody(&[
        "reduce",
        model.to_str().unwrap(),
        "--method",
        "free-residual",
        "--modes",
        "1",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["r"], 7);
    let full: Vec<f64> = serde_json::from_value(doc["full_hz"].clone()).unwrap();
    let reduced: Vec<f64> = serde_json::from_value(doc["reduced_hz"].clone()).unwrap();
    assert_eq!((full.len(), reduced.len()), (7, 7));
    // Rigid-body modes at 0 Hz; the kept eigenmode exactly; the rest above
    // the full model's (Rayleigh-Ritz).
    assert!(full[1] < 1e-3 && reduced[1] < 1e-3);
    assert!((reduced[2] - full[2]).abs() < 1e-9 * full[2]);
    for (r, f) in reduced.iter().zip(&full).skip(3) {
        assert!(*r >= *f * (1.0 - 1e-12));
    }
    let body = flexbody::export::read_json(&out).unwrap();
    assert_eq!(body.r(), 7);
    // Without the check, the full model is not solved again, and K and M
    // are handed over to the reduction (`reduce_taking`): the same body.
    let o = flexbody(&[
        "reduce",
        model.to_str().unwrap(),
        "--method",
        "free-residual",
        "--modes",
        "1",
        "--out",
        out.to_str().unwrap(),
        "--json",
        "--check",
        "never",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(doc["full_hz"].is_null());
    let again: Vec<f64> = serde_json::from_value(doc["reduced_hz"].clone()).unwrap();
    assert_eq!(again, reduced);
    // The table says why there is no comparison: the option, not the size.
    let o = flexbody(&[
        "reduce",
        model.to_str().unwrap(),
        "--method",
        "free-residual",
        "--modes",
        "1",
        "--out",
        out.to_str().unwrap(),
        "--check",
        "never",
    ]);
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(
        table.contains("(no comparison with the full model: --check never)"),
        "{table}"
    );
}

#[test]
fn a_connection_to_a_missing_node_names_it_and_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let m = variant(dir.path(), "m.toml", "node = 21", "node = 99");
    fails_with(&["study", &m], &["m.toml:53:", "node 99", "does not exist"]);
}

#[test]
fn a_negative_density_names_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let m = variant(
        dir.path(),
        "m.toml",
        "density = 6800.0",
        "density = -6800.0",
    );
    fails_with(&["study", &m], &["m.toml:9:", "density"]);
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
    let dir = tempfile::tempdir().unwrap();
    let m = variant(
        dir.path(),
        "m2.toml",
        "{ method = \"free\", modes = 7 }",
        "{ method = \"hurty\", modes = 7 }",
    );
    fails_with(&["study", &m], &["m2.toml:", "unknown variant `hurty`"]);
}

#[test]
fn an_interface_that_leaves_a_mechanism_names_the_free_dofs() {
    let dir = tempfile::tempdir().unwrap();
    let m = variant(
        dir.path(),
        "m.toml",
        "[track]",
        "[interface]\ndofs = [{ node = 11, dof = \"uz\" }]\n\n[track]",
    );
    let out = dir.path().join("b.json");
    fails_with(
        &[
            "reduce",
            &m,
            "--method",
            "craig-bampton",
            "--modes",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
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
fn modes_json_gives_frequencies_and_residuals() {
    let model = super::side_beam_path();
    let o = flexbody(&["modes", model.to_str().unwrap(), "--count", "4", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["dofs"], 42);
    let f: Vec<f64> = serde_json::from_value(doc["frequencies_hz"].clone()).unwrap();
    let res: Vec<f64> = serde_json::from_value(doc["residuals"].clone()).unwrap();
    assert!(res.iter().all(|r| *r < 1e-10), "{res:?}");
    // Free-free Euler-Bernoulli beam: f1 = (4.7300)^2 / (2 pi L^2) sqrt(E I / (rho A)).
    let (b, h, t) = (0.24_f64, 0.20_f64, 0.012_f64);
    let area = b * h - (b - 2.0 * t) * (h - 2.0 * t);
    let i = (b * h.powi(3) - (b - 2.0 * t) * (h - 2.0 * t).powi(3)) / 12.0;
    let f1 = 4.730_040_745_f64.powi(2) / (2.0 * std::f64::consts::PI * 2.5 * 2.5)
        * (2.1e11 * i / (6800.0 * area)).sqrt();
    assert!(f[0] < 1e-3 && f[1] < 1e-3);
    assert!((f[2] - f1).abs() < 1e-4 * f1, "{} vs {f1}", f[2]);
}

#[test]
fn reduce_writes_sid_mtx_and_vtu_and_inspect_reads_them() {
    let dir = tempfile::tempdir().unwrap();
    let deck = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calculix/hex_beam/hex_beam.inp");
    let (sid, vtu, mtx) = (
        dir.path().join("b.sid"),
        dir.path().join("b.vtu"),
        dir.path().join("b_mtx"),
    );
    let o = flexbody(&[
        "reduce",
        deck.to_str().unwrap(),
        "--method",
        "free-residual",
        "--modes",
        "2",
        "--interface",
        "1,13",
        "--format",
        "sid",
        "--out",
        sid.to_str().unwrap(),
        "--vtu",
        vtu.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = flexbody(&["inspect", sid.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && text.contains("SID") && text.contains("4.710000e1 kg"),
        "{text}"
    );
    assert!(std::fs::read_to_string(&vtu)
        .unwrap()
        .contains("UnstructuredGrid"));
    let o = flexbody(&[
        "reduce",
        deck.to_str().unwrap(),
        "--method",
        "craig-bampton",
        "--modes",
        "2",
        "--interface",
        "1,13,79",
        "--format",
        "mtx",
        "--out",
        mtx.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = flexbody(&["inspect", mtx.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("craig-bampton"));
    fails_with(
        &[
            "reduce",
            deck.to_str().unwrap(),
            "--method",
            "guyan",
            "--interface",
            "1,13,79",
            "--format",
            "xml",
            "--out",
            "x",
        ],
        &["unknown format 'xml'"],
    );
    fails_with(
        &["inspect", dir.path().join("none.sid").to_str().unwrap()],
        &["none.sid", "cannot read"],
    );
}

#[test]
fn a_sid_from_the_handed_over_stiffness_equals_the_one_from_kept_matrices() {
    // The solid side beam (1668 DOFs, the sparse solver): without the
    // comparison, `reduce --format sid` hands K to the solver and keeps M
    // for the invariants; with `--check always` both are kept (the full
    // model's eigen solve needs them). The two files are the same bytes.
    let dir = tempfile::tempdir().unwrap();
    let model = solid_side_beam();
    let sid = |check: &str| {
        let out = dir.path().join(format!("{check}.sid"));
        let o = flexbody(&[
            "reduce",
            model.to_str().unwrap(),
            "--method",
            "free-residual",
            "--modes",
            "6",
            "--format",
            "sid",
            "--check",
            check,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        (std::fs::read(&out).unwrap(), o.stdout)
    };
    let (given, table) = sid("never");
    let (kept, compared) = sid("always");
    assert!(String::from_utf8_lossy(&table).contains("--check never"));
    assert!(String::from_utf8_lossy(&compared).contains("full (Hz)"));
    // The mass invariants need M: the SID's mass is the box section's,
    // 6800 kg/m^3 x (0.24 x 0.20 - 0.216 x 0.176) m^2 x 2.5 m.
    let text = String::from_utf8_lossy(&given);
    let mass: f64 = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("mass = "))
        .and_then(|v| v.parse().ok())
        .expect("a mass line");
    let want = 6800.0 * (0.24 * 0.20 - 0.216 * 0.176) * 2.5;
    assert!((mass - want).abs() < 1e-12 * want, "{mass} vs {want}");
    assert!(given == kept, "the SID files differ");
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
    let o = flexbody(&["modes", deck, "--count", "14"]);
    assert!(o.status.success(), "{}", stderr(&o));
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
            &[
                "reduce",
                deck,
                "--method",
                method,
                "--modes",
                "6",
                "--interface",
                "1",
                "--out",
                out.to_str().unwrap(),
            ],
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
    let o = flexbody(&["modes", held.to_str().unwrap(), "--count", "8"]);
    assert!(o.status.success(), "{}", stderr(&o));
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
    let o = flexbody(&["modes", held.to_str().unwrap(), "--count", "8"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("zero frequency"), "{}", stderr(&o));
}

#[test]
fn reduce_refuses_an_output_it_cannot_write_before_it_reduces() {
    // Each of these once failed only after the reduction, the last one
    // with the body already written: at 1e6 DOFs, ten minutes later.
    let dir = tempfile::tempdir().unwrap();
    let fixtures = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calculix/hex_beam");
    let deck = fixtures.join("hex_beam.inp");
    let sti = fixtures.join("hex_beam.sti");
    let (deck, sti) = (deck.to_str().unwrap(), sti.to_str().unwrap());
    let body = dir.path().join("b.json");
    let a_file = dir.path().join("a_file");
    std::fs::write(&a_file, "x").unwrap();
    let folder = dir.path().to_str().unwrap();
    let reduce = |model: &str, out: &str, extra: &[&str], needles: &[&str]| {
        let mut args = vec![
            "reduce",
            model,
            "--method",
            "craig-bampton",
            "--modes",
            "2",
            "--interface",
            "1,13",
            "--out",
            out,
        ];
        args.extend_from_slice(extra);
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

#[test]
fn a_closed_stdout_ends_the_program_quietly() {
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_flexbody"))
        .args([
            "study",
            super::side_beam_path().to_str().unwrap(),
            "--no-plots",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away, like `| head -0`
    let out = child.wait_with_output().unwrap();
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    assert_eq!(out.status.code(), Some(0));
}

#[test]
fn many_modes_of_the_solid_converge_to_the_dense_ones() {
    // 200 of the 1668 modes of the solid side beam take the sparse Lanczos
    // solver (12 % of the spectrum, stiffness over 4 decades of theta);
    // 1000 take the dense one. Before converged Ritz pairs were locked the
    // Lanczos run lost and found them again until its step limit; before
    // free-residual chose its solver by the mode count, 1500 modes took
    // minutes there. Before the eigen-decompositions of both solvers were
    // scaled to unit size (faer's divide and conquer is not
    // scale-invariant), the run stalled at a false round-off floor and the
    // two solvers agreed to 1e-8 with residuals up to 5e-7; now 64 sweeps
    // at the first shift give residuals of 2e-8 and agree to 3e-12.
    let model = solid_side_beam();
    let run = |count: &str| -> (Vec<f64>, Vec<f64>) {
        let o = flexbody(&["modes", model.to_str().unwrap(), "--json", "--count", count]);
        assert!(o.status.success(), "{}", stderr(&o));
        let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let get = |k: &str| serde_json::from_value(doc[k].clone()).unwrap();
        (get("frequencies_hz"), get("residuals"))
    };
    let (sparse, residuals) = run("200");
    let (dense, _) = run("1000");
    assert_eq!(sparse.len(), 200);
    for (a, b) in sparse.iter().zip(&dense).skip(6) {
        assert!((a - b).abs() <= 1e-10 * b, "{a} vs {b}");
    }
    assert!(residuals.iter().all(|r| *r < 1e-7), "{residuals:?}");
    // Free-residual keeps its 200 eigenmodes of the held operator, and 1500
    // take the dense solver.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body.json");
    for modes in ["1500", "200"] {
        let o = flexbody(&[
            "reduce",
            model.to_str().unwrap(),
            "--method",
            "free-residual",
            "--modes",
            modes,
            "--out",
            out.to_str().unwrap(),
            "--check",
            "never",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let body: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let reduced: Vec<f64> = serde_json::from_value(body["frequencies_hz"].clone()).unwrap();
    for (a, b) in reduced.iter().zip(&dense).take(206).skip(6) {
        assert!((a - b).abs() <= 1e-8 * b, "{a} vs {b}");
    }
}

/// `flexbody modes MODEL --json EXTRA..`: the frequencies (Hz) and residuals.
fn modes_json(model: &std::path::Path, extra: &[&str]) -> (Vec<f64>, Vec<f64>) {
    let mut args = vec!["modes", model.to_str().unwrap(), "--json"];
    args.extend_from_slice(extra);
    let o = flexbody(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let column = |key: &str| serde_json::from_value::<Vec<f64>>(doc[key].clone()).unwrap();
    (column("frequencies_hz"), column("residuals"))
}

#[test]
fn modes_below_a_frequency_are_the_lowest_ones_up_to_it() {
    // The solid side beam (1668 DOFs, the sparse solver): --fmax 700 Hz
    // gives exactly the modes of --count 12 that lie below 700 Hz.
    let model = solid_side_beam();
    let (lowest, _) = modes_json(&model, &["--count", "12"]);
    let (band, _) = modes_json(&model, &["--fmax", "700"]);
    let below: Vec<f64> = lowest.iter().copied().filter(|f| *f < 700.0).collect();
    assert!(below.len() > 6 && below.len() < 12, "{lowest:?}");
    assert_eq!(band.len(), below.len());
    for (a, b) in band.iter().zip(&below) {
        if *b < 1.0 {
            // Rigid-body modes: round-off frequencies.
            assert!(*a < 1e-2, "{a} vs {b}");
        } else {
            assert!((a - b).abs() <= 1e-9 * b, "{a} vs {b}");
        }
    }
    let o = flexbody(&["modes", model.to_str().unwrap(), "--fmax=-3"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--fmax must be a positive frequency"));
}

#[test]
fn a_band_above_every_mode_gives_all_of_them_accurately() {
    // The solid side beam's 1668 modes, all below 1e6 Hz: too many for a
    // Lanczos basis, so the dense solver gives them (they once came from a
    // Krylov space of the whole model with residuals of 0.1 and out of
    // order). They equal --count over the whole model.
    let model = solid_side_beam();
    let (band, residuals) = modes_json(&model, &["--fmax", "1e6"]);
    let (every, _) = modes_json(&model, &["--count", "100000"]);
    assert_eq!(band.len(), 1668);
    let worst = residuals.iter().copied().fold(0.0, f64::max);
    assert!(worst < 1e-7, "largest residual {worst:e}");
    assert!(band.windows(2).all(|w| w[0] <= w[1]));
    for (a, b) in band.iter().zip(&every).skip(6) {
        assert!((a - b).abs() <= 1e-10 * b, "{a} vs {b}");
    }
    fails_with(
        &["modes", model.to_str().unwrap(), "--count", "0"],
        &["--count must be at least 1"],
    );
}

#[test]
fn a_factor_beyond_max_memory_is_refused_before_factorising() {
    // The solid side beam (the sparse solver). Under a budget of 1 MiB the
    // process already holds more than that: the factor is refused with its
    // size before any storage is taken, and no body is written.
    let model = solid_side_beam();
    let model = model.to_str().unwrap();
    fails_with(
        &["--max-memory", "0.001", "modes", model, "--count", "10"],
        &[
            "the LDL^T factor of",
            "entries of L) needs",
            "are left (--max-memory 1.0 MiB with",
            "coarser mesh",
        ],
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body.json");
    let out = out.to_str().unwrap();
    fails_with(
        &[
            "reduce",
            model,
            "--method",
            "free-residual",
            "--modes",
            "6",
            "--out",
            out,
            "--max-memory",
            "0.001",
        ],
        &["entries of L) needs", "--max-memory 1.0 MiB"],
    );
    assert!(!Path::new(out).exists());
    // A budget with room changes nothing; a budget must be positive.
    let o = flexbody(&[
        "--max-memory",
        "64",
        "modes",
        model,
        "--count",
        "10",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    fails_with(
        &["--max-memory", "0", "modes", model],
        &["'0' is not a positive number of GiB"],
    );
}

#[test]
fn a_lanczos_basis_beyond_max_memory_is_refused_before_factorising() {
    // 400 modes of the 1668-DOF solid side beam take the sparse solver
    // with a basis of 1264 vectors (17 MB), its factor 1.5 MB. A budget
    // of 25.6 MiB leaves room for the factor, not for both: refused,
    // naming the modes and vectors.
    let model = solid_side_beam();
    let model = model.to_str().unwrap();
    fails_with(
        &["--max-memory", "0.025", "modes", model, "--count", "400"],
        &[
            "a Lanczos run for 400 modes (1264 vectors of 1668 equations, \
             with the LDL^T factor's 1.5 MiB) needs",
            "(--max-memory 25.6 MiB with",
        ],
    );
    // The figure it needs, from the sizes alone: 1264 f64 vectors of n
    // equations (n = 1668: three DOFs per node of the model's mesh) plus
    // the factor it names. The factor holds at least the lower triangle of
    // K's pattern (fill-in only adds) and at most the dense n (n + 1) / 2
    // entries, 8 bytes each.
    let (n, lower) = stiffness_pattern(&solid_side_beam());
    assert_eq!(n, 1668);
    let o = flexbody(&["--max-memory", "0.025", "modes", model, "--count", "400"]);
    let err = stderr(&o);
    let factor = mib_after(&err, "the LDL^T factor's ");
    assert!(
        factor >= (lower * 8) as f64 / MIB && factor <= (n * (n + 1) / 2 * 8) as f64 / MIB,
        "factor {factor} MiB, K's lower triangle {lower} entries: {err}"
    );
    let needs = mib_after(&err, ") needs ");
    let basis = (1264 * n * 8) as f64 / MIB;
    // Both figures are printed to 0.1 MiB.
    assert!(
        (needs - (basis + factor)).abs() <= 0.1,
        "needs {needs} MiB = basis {basis} MiB + factor {factor} MiB: {err}"
    );
    // Fewer modes fit the same budget.
    let o = flexbody(&["--max-memory", "0.025", "modes", model, "--count", "10"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

const MIB: f64 = (1u64 << 20) as f64;

/// The number in MiB printed right after `key` in `text`.
fn mib_after(text: &str, key: &str) -> f64 {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("'{key}' in {text}"))
        + key.len();
    let rest = &text[at..];
    let value = rest.split(" MiB").next().unwrap();
    value
        .parse()
        .unwrap_or_else(|_| panic!("a number of MiB after '{key}': {rest}"))
}

/// Equations of a model file and the entries of the lower triangle
/// (diagonal included) of its assembled stiffness matrix.
fn stiffness_pattern(path: &Path) -> (usize, usize) {
    let file = flexbody::io::read_model_file(path).unwrap();
    let sub = flexbody::fem::Substructure::from_model(&file.model).unwrap();
    let k = sub.matrices.stiffness.as_ref();
    let lower = (0..k.ncols())
        .map(|j| k.row_idx_of_col(j).filter(|&i| i >= j).count())
        .sum();
    (sub.len(), lower)
}

#[test]
fn a_dense_eigen_solve_beyond_max_memory_is_refused_before_it_starts() {
    // 1000 of the 1668 modes of the solid side beam take the dense solver:
    // 12 matrices of 1668 x 1668 (267 MB; the run peaks at 265 MB). A
    // budget of 102 MiB is refused, naming the solve; 0.5 GiB is enough.
    let model = solid_side_beam();
    let model = model.to_str().unwrap();
    fails_with(
        &["--max-memory", "0.1", "modes", model, "--count", "1000"],
        &[
            "the dense eigen solve of 1668 equations (12 matrices of 1668 x 1668) needs",
            "(--max-memory 102.4 MiB with",
        ],
    );
    // The figure it needs, from the sizes alone: 12 dense matrices of
    // n x n f64 entries (8 bytes each), n = 1668 equations of the mesh.
    let (n, _) = stiffness_pattern(&solid_side_beam());
    let o = flexbody(&["--max-memory", "0.1", "modes", model, "--count", "1000"]);
    let needs = mib_after(&stderr(&o), ") needs ");
    let dense = (12 * n * n * 8) as f64 / MIB;
    assert!(
        (needs - dense).abs() <= 0.05,
        "needs {needs} MiB, 12 n^2 8 bytes = {dense} MiB"
    );
    let o = flexbody(&["--max-memory", "0.5", "modes", model, "--count", "1000"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn verbose_reduce_logs_the_stages_and_where_the_body_is_written() {
    // The solid side beam: ordering, factorisations and Lanczos steps of the
    // sparse solver, then the reduced body's size before its output.
    let model = solid_side_beam();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body.json");
    let o = flexbody(&[
        "--verbose",
        "reduce",
        model.to_str().unwrap(),
        "--method",
        "free-residual",
        "--modes",
        "6",
        "--out",
        out.to_str().unwrap(),
    ]);
    let log = stderr(&o);
    assert!(o.status.success(), "{log}");
    let at = |needle: &str| {
        log.find(needle)
            .unwrap_or_else(|| panic!("'{needle}' not in: {log}"))
    };
    assert!(at("] ordering ") < at("] factorising K"));
    assert!(at("] Sturm check: ") < at("] reduced: r = "));
    assert!(at("] reduced: r = ") < at("] written: "));
    assert!(out.exists());
}

#[test]
fn info_factor_gives_the_factor_that_modes_analyses() {
    // `info --factor` orders and analyses K - sigma M as the solver does:
    // the same entries of L as the `--verbose` log of `modes` reports.
    let model = solid_side_beam();
    let model = model.to_str().unwrap();
    let o = flexbody(&["info", model, "--factor"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let line = text
        .lines()
        .find(|l| l.starts_with("factor of K - sigma M"))
        .unwrap_or_else(|| panic!("no factor line in: {text}"));
    let entries: usize = line
        .split(": ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(line.contains("Flop per factorisation"), "{line}");
    assert!(text.contains("memory left: "), "{text}");
    let o = flexbody(&["--verbose", "modes", model, "--count", "8"]);
    let log = stderr(&o);
    assert!(o.status.success(), "{log}");
    assert!(
        log.contains(&format!("analysed: {entries} entries in L")),
        "{entries} vs {log}"
    );
    // Without --factor, no analysis.
    let o = flexbody(&["info", model]);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("entries of L"));
}

#[test]
fn frf_full_on_a_model_beyond_the_dense_solver_skips_the_damped_modes_by_name() {
    // The vehicle with its side beam in 3100 elements (6204 coordinates): the
    // transfer functions of the full model are solved (sparse), but its
    // damped modes would need the dense eigen solver; the command says so
    // and still writes frf.csv.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/vehicle.toml"),
    )
    .unwrap();
    assert!(text.contains("elements = 20\n") && text.contains("points = 240\n"));
    let model = dir.path().join("fine.toml");
    std::fs::write(
        &model,
        text.replacen("elements = 20\n", "elements = 3100\n", 1)
            .replacen("points = 240\n", "points = 3\n", 1),
    )
    .unwrap();
    let out = dir.path().join("out");
    let o = flexbody(&[
        "frf",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--full",
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout.contains("not computed"), "{stdout}");
    assert!(stdout.contains("dense eigen solver, which stops at 6000"));
    assert!(out.join("frf.csv").exists());
}
