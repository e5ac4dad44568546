//! Builders the test modules share: running the `flexbody` command,
//! variants of the bundled examples, and a reduced CalculiX hex beam.

use flexbody::fem::{Dof, DofKind, Model, Substructure};
use flexbody::input::{load, MatrixFiles};
use flexbody::reduce::{reduce, Method, ReducedBody, Reduction};
use std::ffi::OsStr;
use std::fmt::Debug;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use tempfile::TempDir;

/// Whether the peer programs (CalculiX, Exudyn, meshio, Chromium) must be
/// present: `FLEXBODY_REQUIRE_PEERS=1` (as `.ci/run` sets it) makes a
/// missing peer a failure instead of a skipped check.
pub(crate) fn peers_required() -> bool {
    std::env::var_os("FLEXBODY_REQUIRE_PEERS").is_some_and(|v| v == "1")
}

/// `test` cannot run its peer check because `missing` is not there: a
/// failure under [`peers_required`], else a `SKIPPED` line on stderr.
pub(crate) fn skip_without_peer(test: &str, missing: &str) {
    assert!(
        !peers_required(),
        "FLEXBODY_REQUIRE_PEERS=1 but {missing} is missing; run scripts/install_peers.sh"
    );
    eprintln!("{test}: SKIPPED, {missing} is missing");
}

/// Whether `python3` imports `modules` (`"exudyn, numpy"`); if not, why.
pub(crate) fn python_imports(modules: &str) -> Result<(), String> {
    match Command::new("python3")
        .args(["-c", &format!("import {modules}")])
        .output()
    {
        Ok(o) if o.status.success() => Ok(()),
        Ok(o) => Err(String::from_utf8_lossy(&o.stderr)
            .lines()
            .last()
            .unwrap_or("")
            .to_string()),
        Err(e) => Err(format!("python3: {e}")),
    }
}

/// Runs `scripts/<script>` with `python3` and `args`, expecting success:
/// its standard output and error, which it also shows on stderr.
pub(crate) fn run_script<S: AsRef<OsStr>>(script: &str, args: &[S]) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("scripts")
        .join(script);
    let out = Command::new("python3")
        .arg(&path)
        .args(args)
        .output()
        .unwrap();
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    eprintln!("scripts/{script}:\n{log}");
    assert!(out.status.success(), "scripts/{script} failed:\n{log}");
    log
}

/// Runs the `flexbody` binary with `args`.
pub(crate) fn flexbody<S: AsRef<OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flexbody"))
        .args(args)
        .output()
        .expect("run flexbody")
}

/// Runs the `flexbody` binary with `args`, expecting success.
pub(crate) fn run_ok<S: AsRef<OsStr>>(args: &[S]) -> Output {
    let o = flexbody(args);
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

/// The standard output of `o` as a JSON document.
pub(crate) fn stdout_json(o: &Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout).unwrap()
}

/// The arguments `reduce MODEL --method METHOD --modes MODES --out OUT`,
/// followed by `extra`.
pub(crate) fn reduce_args(
    model: impl AsRef<Path>,
    method: &str,
    modes: &str,
    out: impl AsRef<Path>,
    extra: &[&str],
) -> Vec<String> {
    let path = |p: &Path| p.to_str().unwrap().to_owned();
    let mut args = vec![
        "reduce".to_owned(),
        path(model.as_ref()),
        "--method".to_owned(),
        method.to_owned(),
        "--modes".to_owned(),
        modes.to_owned(),
        "--out".to_owned(),
        path(out.as_ref()),
    ];
    args.extend(extra.iter().map(|a| a.to_string()));
    args
}

/// The standard error of `o` as text.
pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `args` expecting exit code 2 and a message containing all `needles`.
pub(crate) fn fails_with<S: AsRef<OsStr> + Debug>(args: &[S], needles: &[&str]) {
    let o = flexbody(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: expected '{n}' in: {err}");
    }
}

/// The solid side beam example (1668 DOFs, the sparse solver).
pub(crate) fn solid_side_beam() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam_solid.toml")
}

/// The deck of the CalculiX hex-element beam, `tests/fixtures/calculix/hex_beam`.
pub(crate) fn hex_beam_deck() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/calculix/hex_beam/hex_beam.inp")
}

/// The side beam with `from` replaced by `to`, written to `dir/name`.
pub(crate) fn variant(dir: &Path, name: &str, from: &str, to: &str) -> String {
    let text = super::side_beam_text();
    assert!(text.contains(from), "{from}");
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_string_lossy().into_owned()
}

/// The side beam reduced by `method` with `modes`, written as `body.json`
/// into a new temporary folder: the folder, the file and the body.
pub(crate) fn side_beam_json(method: Method, modes: usize) -> (TempDir, PathBuf, ReducedBody) {
    let (_, _, body) = super::side_beam_body(method, modes);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.json");
    flexbody::export::write_json(&body, &[], &path).unwrap();
    (dir, path, body)
}

/// The largest difference between the entries of `a` and `b`.
pub(crate) fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// 1 at every DOF of `sub` of `kind`, 0 at the others: a unit rigid
/// translation when `kind` is a translation.
pub(crate) fn unit_translation(sub: &Substructure, kind: DofKind) -> Vec<f64> {
    sub.dof_map
        .dofs()
        .iter()
        .map(|d| (d.kind == kind) as u8 as f64)
        .collect()
}

/// The side beam held at one interface DOF, node 11 uz, written to
/// `dir/m.toml`: heave is held, pitch about node 11 is not.
pub(crate) fn mid_span_interface(dir: &Path) -> String {
    variant(
        dir,
        "m.toml",
        "[track]",
        "[interface]\ndofs = [{ node = 11, dof = \"uz\" }]\n\n[track]",
    )
}

/// The CalculiX hex-element beam of `tests/fixtures/calculix/hex_beam`: its
/// matrices and its mesh.
pub(crate) fn hex_beam() -> (Substructure, Model) {
    let c = load(&hex_beam_deck(), &MatrixFiles::default()).unwrap();
    (c.sub, c.model.unwrap())
}

/// Every DOF of `nodes` that `sub` has.
fn all_dofs(sub: &Substructure, nodes: &[u64]) -> Vec<Dof> {
    nodes
        .iter()
        .flat_map(|&n| DofKind::ALL.into_iter().map(move |k| Dof::new(n, k)))
        .filter(|d| sub.dof_map.index_of(*d).is_some())
        .collect()
}

/// `sub` reduced by `method` with `modes`, its interface every DOF of `nodes`.
pub(crate) fn reduce_with(
    sub: &Substructure,
    method: Method,
    modes: usize,
    nodes: &[u64],
) -> ReducedBody {
    reduce(sub, &Reduction::new(method, modes, all_dofs(sub, nodes))).unwrap()
}

/// A free skew 3D Timoshenko beam with rotary inertia: unequal bending
/// stiffnesses, the local y axis from an orientation vector that is not
/// normal to the axis, and the whole beam away from the origin.
pub(crate) const SKEW_TIMOSHENKO: &str = r#"
title = "free skew Timoshenko beam"
[[material]]
name = "steel"
youngs_modulus = 2.1e11
poisson_ratio = 0.3
density = 7850.0
[[section]]
name = "s"
shape = "general"
area = 0.012
iy = 4.0e-5
iz = 1.5e-5
torsion = 3.0e-5
shear_area_y = 0.010
shear_area_z = 0.009
[[beam_line]]
element = "beam"
theory = "timoshenko"
from = [0.3, -0.2, 0.4]
to = [1.1, 0.5, -0.1]
elements = 6
first_node = 1
material = "steel"
section = "s"
orientation = [0.2, 0.1, 1.0]
"#;

/// The welib comparison's clamped Euler-Bernoulli beam (no rotary
/// inertia), from `tests/fixtures/sid/`.
pub(crate) fn welib_clamped_beam() -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/sid/welib_clamped_beam.toml");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Writes what `scripts/beam_invariants.py` reads: the beam mesh of
/// `model` (nodes, elements with their section and material), the SID's
/// elastic mode shapes at every DOF of every node (zero where fixed), and
/// flexbody's invariants of `body`.
pub(crate) fn write_beam_case(
    model: &Model,
    sub: &Substructure,
    body: &ReducedBody,
    path: &std::path::Path,
) {
    use flexbody::fem::{BeamTheory, Dof, DofKind, Element};
    use flexbody::reduce::ffrf::FloatingFrame;
    use serde_json::json;
    let frame = FloatingFrame::new(sub, Some(model), body).unwrap();
    let phi = &frame.elastic.shapes;
    let nq = phi.ncols();
    let nodes: Vec<_> = model
        .nodes()
        .iter()
        .map(|n| {
            let modes: Vec<Vec<f64>> = DofKind::ALL
                .iter()
                .map(|&k| {
                    let terms = model.value_terms(Dof::new(n.id, k));
                    (0..nq)
                        .map(|q| {
                            let column: Vec<f64> = (0..phi.nrows()).map(|i| phi[(i, q)]).collect();
                            terms.of(&column)
                        })
                        .collect()
                })
                .collect();
            json!({"id": n.id, "x": n.coords, "phi": modes})
        })
        .collect();
    let elements: Vec<_> = model
        .elements()
        .iter()
        .map(|e| match e {
            Element::Beam(b) => {
                let p = &b.properties;
                let s = &p.section;
                json!({
                    "nodes": b.nodes, "orientation": b.orientation,
                    "E": p.material.youngs_modulus, "G": p.material.shear_modulus,
                    "rho": p.material.density, "A": s.area, "Iy": s.iy, "Iz": s.iz,
                    "Asy": s.shear_area_y, "Asz": s.shear_area_z,
                    "timoshenko": p.theory == BeamTheory::Timoshenko,
                    "rotary_inertia": p.rotary_inertia,
                })
            }
            other => panic!("a beam model holds beams only, not {other:?}"),
        })
        .collect();
    let inv = &frame.invariants;
    let mat = |m: &faer::Mat<f64>| -> Vec<Vec<f64>> {
        (0..m.nrows())
            .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
            .collect()
    };
    let doc = json!({
        "nodes": nodes, "elements": elements,
        "invariants": {
            "mass": inv.mass, "mdCM": inv.md_cm, "mdCM1": inv.md_cm1, "J": inv.j, "J1": inv.j1,
            "Ct": mat(&inv.ct), "Cr": mat(&inv.cr),
            "Cr1": inv.cr1.iter().map(mat).collect::<Vec<_>>(),
            "Me": mat(&inv.me), "Gr": mat(&inv.gr), "Ge": mat(&inv.ge), "Oe": mat(&inv.oe),
            "Oe1": inv.oe1.iter().map(mat).collect::<Vec<_>>(),
        },
    });
    std::fs::write(path, serde_json::to_string(&doc).unwrap()).unwrap();
}

/// The `[simulation]` of `file` run twice: with the body it reduces to,
/// and with the full model (the reference); the histories of each.
pub(crate) fn reduced_and_full_histories(
    file: &flexbody::scenario::ModelFile,
) -> (flexbody::simulate::Histories, flexbody::simulate::Histories) {
    use flexbody::linalg::{memory::Budget, progress::NoProgress};
    use flexbody::mbs::FlexibleBody;
    use flexbody::simulate::{run_simulation, simulation_body};
    let sub = Substructure::from_model(&file.model).unwrap();
    let spec = file.simulation.as_ref().unwrap();
    let body = simulation_body(file, &sub, spec, Budget::MACHINE, &NoProgress).unwrap();
    let red = run_simulation(file, FlexibleBody::Reduced(&body)).unwrap();
    let full = run_simulation(
        file,
        FlexibleBody::Full {
            dof_map: &sub.dof_map,
            matrices: &sub.matrices,
        },
    )
    .unwrap();
    (red, full)
}

/// CalculiX's frequencies (Hz) of `deck`, written to `dir/name.inp` and
/// run there (`ccx -i name`, one thread), or `None` without ccx.
pub(crate) fn calculix_frequencies(
    dir: &std::path::Path,
    name: &str,
    deck: &str,
) -> Option<Vec<f64>> {
    std::fs::write(dir.join(format!("{name}.inp")), deck).unwrap();
    let out = std::process::Command::new("ccx")
        .args(["-i", name])
        .current_dir(dir)
        .env("OMP_NUM_THREADS", "1")
        .output()
        .ok()?;
    let dat = std::fs::read_to_string(dir.join(format!("{name}.dat"))).unwrap_or_else(|e| {
        panic!(
            "no {name}.dat ({e}); ccx said:\n{}",
            String::from_utf8_lossy(&out.stdout)
        )
    });
    let table = dat
        .split("E I G E N V A L U E   O U T P U T")
        .nth(1)
        .unwrap();
    Some(
        table
            .lines()
            .filter_map(|l| {
                let f: Vec<&str> = l.split_whitespace().collect();
                (f.len() == 5 && f[0].parse::<usize>().is_ok()).then(|| f[3].parse().unwrap())
            })
            .collect(),
    )
}

/// flexbody's lowest `count` frequencies (Hz) of the deck `name` in `dir`
/// (`flexbody modes`).
pub(crate) fn our_frequencies(dir: &std::path::Path, count: usize, name: &str) -> Vec<f64> {
    let deck = dir.join(format!("{name}.inp"));
    let count = count.to_string();
    let o = run_ok(&["modes", deck.to_str().unwrap(), "--count", &count, "--json"]);
    stdout_json(&o)["frequencies_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}
