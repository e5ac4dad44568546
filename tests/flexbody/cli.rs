//! The `flexbody` command: its outputs, files and logs.

use super::support::{
    fails_with, flexbody, hex_beam_deck, reduce_args, run_ok, solid_side_beam, stderr, stdout_json,
};
use std::process::Command;

#[test]
fn study_json_lists_every_case_and_plots_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plots");
    let model = super::side_beam_path();
    let o = run_ok(&[
        "study",
        model.to_str().unwrap(),
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    let doc = stdout_json(&o);
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
    let reduce = |extra: &[&str]| flexbody(&reduce_args(&model, "free-residual", "1", &out, extra));
    let o = reduce(&["--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc = stdout_json(&o);
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
    // are handed over to the reduction (`Keep::Neither`): the same body.
    let o = reduce(&["--json", "--check", "never"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let doc = stdout_json(&o);
    assert!(doc["full_hz"].is_null());
    let again: Vec<f64> = serde_json::from_value(doc["reduced_hz"].clone()).unwrap();
    assert_eq!(again, reduced);
    // The table says why there is no comparison: the option, not the size.
    let o = reduce(&["--check", "never"]);
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(
        table.contains("(no comparison with the full model: --check never)"),
        "{table}"
    );
}

#[test]
fn modes_json_gives_frequencies_and_residuals() {
    let model = super::side_beam_path();
    let o = run_ok(&["modes", model.to_str().unwrap(), "--count", "4", "--json"]);
    let doc = stdout_json(&o);
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
    let deck = hex_beam_deck();
    let (sid, vtu, mtx) = (
        dir.path().join("b.sid"),
        dir.path().join("b.vtu"),
        dir.path().join("b_mtx"),
    );
    run_ok(&reduce_args(
        &deck,
        "free-residual",
        "2",
        &sid,
        &[
            "--interface",
            "1,13",
            "--format",
            "sid",
            "--vtu",
            vtu.to_str().unwrap(),
        ],
    ));
    let o = flexbody(&["inspect", sid.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && text.contains("SID") && text.contains("4.710000e1 kg"),
        "{text}"
    );
    assert!(String::from_utf8_lossy(&std::fs::read(&vtu).unwrap()).contains("UnstructuredGrid"));
    run_ok(&reduce_args(
        &deck,
        "craig-bampton",
        "2",
        &mtx,
        &["--interface", "1,13,79", "--format", "mtx"],
    ));
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
        let o = run_ok(&reduce_args(
            &model,
            "free-residual",
            "6",
            &out,
            &["--format", "sid", "--check", check],
        ));
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
    let o = run_ok(&[
        "frf",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--full",
    ]);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("not computed"), "{stdout}");
    assert!(stdout.contains("dense eigen solver, which stops at 6000"));
    assert!(out.join("frf.csv").exists());
}
