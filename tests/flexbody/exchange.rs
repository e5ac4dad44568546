//! Reduced-body exchange formats: the SID file (FFRF invariants against the
//! full model, round trip, broken files), the Matrix Market folder, the VTU
//! file, format detection, and Exudyn reading the SID file
//! (`scripts/exudyn_check.py`).

use flexbody::export::sid::{parse_sid, read_sid, write_sid, Sid};
use flexbody::export::{
    read_any, read_json, summary, vtk, write, write_json, AnyBody, ExportError, Format,
};
use flexbody::fem::{Dof, DofKind, Model, Substructure};
use flexbody::input::{load, MatrixFiles};
use flexbody::reduce::{reduce, Method, ReducedBody, Reduction};
use std::path::PathBuf;

fn hex_beam() -> (Substructure, Model) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calculix/hex_beam/hex_beam.inp");
    let c = load(&path, &MatrixFiles::default()).unwrap();
    (c.sub, c.model.unwrap())
}

fn all_dofs(sub: &Substructure, nodes: &[u64]) -> Vec<Dof> {
    nodes
        .iter()
        .flat_map(|&n| DofKind::ALL.into_iter().map(move |k| Dof::new(n, k)))
        .filter(|d| sub.dof_map.index_of(*d).is_some())
        .collect()
}

fn reduce_with(sub: &Substructure, method: Method, modes: usize, nodes: &[u64]) -> ReducedBody {
    reduce(sub, &Reduction::new(method, modes, all_dofs(sub, nodes))).unwrap()
}

/// A free 3D beam (10 Euler-Bernoulli elements along x, offset from the
/// origin), with its analytical mass properties.
const BEAM_3D: &str = r#"
title = "free 3D beam"
[[material]]
name = "steel"
youngs_modulus = 2.1e11
density = 7850.0
[[section]]
name = "s"
shape = "general"
area = 0.01
iy = 2.0e-5
iz = 1.0e-5
torsion = 3.0e-5
[[beam_line]]
element = "beam"
rotary_inertia = false
from = [0.5, 0.2, -0.1]
to = [2.5, 0.2, -0.1]
elements = 10
first_node = 1
material = "steel"
section = "s"
orientation = [0.0, 0.0, 1.0]
"#;

fn beam_3d() -> (Substructure, Model) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("beam.toml");
    std::fs::write(&path, BEAM_3D).unwrap();
    let c = load(&path, &MatrixFiles::default()).unwrap();
    (c.sub, c.model.unwrap())
}

fn assert_close(what: &str, got: f64, want: f64, scale: f64) {
    assert!(
        (got - want).abs() <= 1e-11 * scale,
        "{what}: {got} against {want} (scale {scale})"
    );
}

/// Mass, centre of mass and inertia tensor (about the origin) of the SID
/// against the analytical values of the full model.
fn check_mass_properties(sid: &Sid, mass: f64, center: [f64; 3], inertia: [[f64; 3]; 3]) {
    assert_close("mass", sid.refmod.mass, mass, mass);
    let c = sid.center_of_mass();
    for i in 0..3 {
        assert_close("centre of mass", c[i], center[i], 1.0);
    }
    let scale = inertia[0][0]
        .abs()
        .max(inertia[1][1].abs())
        .max(inertia[2][2].abs());
    for (i, row) in inertia.iter().enumerate() {
        for (j, want) in row.iter().enumerate() {
            assert_close(&format!("J({i}, {j})"), sid.j.m0[(i, j)], *want, scale);
        }
    }
}

/// Mean-axis elastic modes: no rigid-body part (`Ct = Cr = 0`), unit modal
/// mass, and the non-zero frequencies of the reduced body.
fn check_elastic_modes(sid: &Sid, body: &ReducedBody, rigid: usize) {
    let nq = sid.nq();
    assert_eq!(nq + rigid, body.r());
    let scale = sid.refmod.mass.sqrt() * 10.0;
    assert!(sid.ct.m0.norm_max() < 1e-9 * scale, "Ct = {:?}", sid.ct.m0);
    assert!(sid.cr.m0.norm_max() < 1e-9 * scale, "Cr = {:?}", sid.cr.m0);
    for i in 0..nq {
        for j in 0..nq {
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((sid.me.m0[(i, j)] - want).abs() < 1e-9, "Me({i}, {j})");
        }
    }
    let ours = sid.frequencies_hz().unwrap();
    let full = body.frequencies_hz().unwrap();
    for (a, b) in ours.iter().zip(&full[rigid..]) {
        assert!((a - b).abs() < 1e-7 * b, "{a} Hz against {b} Hz");
    }
}

fn box_inertia(m: f64, a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    // Box [0,a] x [0,b] x [0,c] about the origin.
    let (xx, yy, zz) = (m * a * a / 3.0, m * b * b / 3.0, m * c * c / 3.0);
    let (xy, yz, zx) = (m * a * b / 4.0, m * b * c / 4.0, m * c * a / 4.0);
    [
        [yy + zz, -xy, -zx],
        [-xy, xx + zz, -yz],
        [-zx, -yz, xx + yy],
    ]
}

#[test]
fn sid_of_a_solid_has_the_mass_properties_of_the_full_model() {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 4, &[13]);
    let sid = Sid::new(&sub, Some(&model), &body).unwrap();
    let mass = 7850.0 * 0.6 * 0.1 * 0.1;
    check_mass_properties(
        &sid,
        mass,
        [0.3, 0.05, 0.05],
        box_inertia(mass, 0.6, 0.1, 0.1),
    );
    check_elastic_modes(&sid, &body, 6);
    // First-order J: for a translation-free mode, int Phi dm = 0 (mdCM m1
    // equals Ct), and J(q) stays symmetric.
    for k in 0..sid.nq() {
        let j1 = &sid.j.m1[k];
        assert!((j1 - j1.transpose()).norm_max() < 1e-9 * j1.norm_max().max(1.0));
        for i in 0..3 {
            assert_eq!(sid.md_cm.m1[k][(i, 0)], sid.ct.m0[(k, i)]);
        }
    }
    // One interface node with 3 translations; 6 stress rows per node.
    assert_eq!(sid.nodes.len(), 1);
    assert_eq!(sid.nodes[0].origin.m0[(0, 0)], 0.6);
    assert_eq!(sid.ksigma.nrow, 6 * model.nodes().len());
}

#[test]
fn sid_of_a_craig_bampton_solid_removes_the_rigid_motion_of_its_constraint_modes() {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::CraigBampton, 3, &[1, 27, 79, 13]);
    let sid = Sid::new(&sub, Some(&model), &body).unwrap();
    let mass = 7850.0 * 0.6 * 0.1 * 0.1;
    check_mass_properties(
        &sid,
        mass,
        [0.3, 0.05, 0.05],
        box_inertia(mass, 0.6, 0.1, 0.1),
    );
    check_elastic_modes(&sid, &body, 6);
}

#[test]
fn sid_of_a_beam_has_the_mass_properties_of_the_full_model() {
    let (sub, model) = beam_3d();
    let body = reduce_with(&sub, Method::FreeResidual, 3, &[1, 11]);
    let sid = Sid::new(&sub, Some(&model), &body).unwrap();
    let (rho, area, l, ip) = (7850.0, 0.01, 2.0, 3.0e-5);
    let mass = rho * area * l;
    let c = [1.5, 0.2, -0.1];
    // Slender rod along x about its centre, torsional inertia rho Ip L,
    // then the parallel-axis theorem to the origin.
    let jc = [rho * ip * l, mass * l * l / 12.0, mass * l * l / 12.0];
    let c2 = c.iter().map(|x| x * x).sum::<f64>();
    let inertia: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| (if i == j { jc[i] + mass * c2 } else { 0.0 }) - mass * c[i] * c[j])
    });
    check_mass_properties(&sid, mass, c, inertia);
    check_elastic_modes(&sid, &body, 6);
    assert_eq!(sid.nodes.len(), 2);
    assert_eq!(sid.ksigma.nrow, 12 * 10);
}

#[test]
fn sid_round_trip_keeps_every_number() {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 2, &[13]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.sid");
    write_sid(&sub, Some(&model), &body, &path).unwrap();
    let back = read_sid(&path).unwrap();
    assert_eq!(back, Sid::new(&sub, Some(&model), &body).unwrap());
    assert!(matches!(read_any(&path).unwrap(), AnyBody::Sid(_)));
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
    let (sub, _) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 2, &[13]);
    let text = Sid::new(&sub, None, &body).unwrap().to_text();

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
    let (_, _, body) = super::side_beam_body(Method::FreeResidual, 1);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.json");
    write_json(&body, &path).unwrap();
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
    let AnyBody::Reduced(back) = read_any(&folder).unwrap() else {
        panic!("not a reduced body")
    };
    assert_eq!(back.basis, body.basis);
    assert_eq!(back.mass, body.mass);
    assert_eq!(back.stiffness, body.stiffness);
    assert_eq!(back.damping, body.damping);
    assert_eq!(back.modes, body.modes);
    assert_eq!(back.interface, body.interface);
    let index: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("index.json")).unwrap()).unwrap();
    assert_eq!(index["method"], "free-residual");
    assert_eq!(index["nodes"][20]["coords"][0], 2.5);
    // Through index.json as well.
    assert!(matches!(
        read_any(&folder.join("index.json")).unwrap(),
        AnyBody::Reduced(_)
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
    for format in Format::ALL {
        let path = dir.path().join(format!("missing/body.{format}"));
        let e = write(&body, &sub, Some(&file.model), format, &path);
        // The SID of a planar beam is written; all fail on the missing
        // folder except MTX, which creates its folder.
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
    let e = vtk::write_vtu(&file.model, &body, &path).unwrap_err();
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
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 2, &[13]);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("body.vtu");
    vtk::write_vtu(&model, &body, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
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
    // Cells: 6 hexahedra (VTK type 12).
    assert_eq!(vtk::cell_types(&model), vec![12; 6]);

    // A beam model: lines.
    let (file, _, body) = super::side_beam_body(Method::Free, 4);
    let path = dir.path().join("beam.vtu");
    vtk::write_vtu(&file.model, &body, &path).unwrap();
    assert_eq!(vtk::cell_types(&file.model), vec![3; 20]);
}

/// Whether the peer programs (CalculiX, Exudyn) must be present: set
/// `FLEXBODY_REQUIRE_PEERS=1` (as `.ci/run` does) to make a missing peer a
/// failure instead of a skipped check.
fn peers_required() -> bool {
    std::env::var_os("FLEXBODY_REQUIRE_PEERS").is_some_and(|v| v == "1")
}

/// Exudyn, a real MBS client, against flexbody: `scripts/exudyn_check.py`
/// reads the SID file that `flexbody reduce --format sid` writes for the
/// free C3D8 bar `hex_beam` (free-residual, tip node 13, 4 eigenmodes; 7
/// elastic coordinates, mean axes), builds an `ObjectFFRFreducedOrder` from
/// its invariants alone, and compares it with the same body built by
/// Exudyn's `FEMinterface` from the full M, K and mode shapes, and with
/// flexbody's own frequencies and trapezoidal-rule time response of the tip
/// to a harmonic force (frame held fixed: `Me q'' + Ke q = Phi_tip^T f(t)`),
/// and the two Exudyn bodies in a short free tumble. The tolerances and
/// the figures measured are in the script.
///
/// Skipped, with a message, when `python3` cannot import exudyn, numpy and
/// scipy, unless [`peers_required`]. With `FLEXBODY_EXUDYN_DIR` set, the
/// files are kept there (see [`write_exudyn_data`]).
#[test]
fn exudyn_agrees_with_flexbody() {
    use std::process::Command;
    let probe = Command::new("python3")
        .args(["-c", "import exudyn, numpy, scipy"])
        .output();
    if !probe.as_ref().is_ok_and(|o| o.status.success()) {
        let why = match &probe {
            Ok(o) => String::from_utf8_lossy(&o.stderr)
                .lines()
                .last()
                .unwrap_or("")
                .to_string(),
            Err(e) => format!("python3: {e}"),
        };
        assert!(
            !peers_required(),
            "FLEXBODY_REQUIRE_PEERS=1 but Exudyn is missing ({why}); run scripts/install_peers.sh"
        );
        eprintln!("exudyn_agrees_with_flexbody: SKIPPED, Exudyn is not available ({why})");
        return;
    }
    let temporary = tempfile::tempdir().unwrap();
    let dir = std::env::var_os("FLEXBODY_EXUDYN_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| temporary.path().to_path_buf());
    write_exudyn_data(&dir);
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scripts/exudyn_check.py");
    let out = Command::new("python3")
        .arg(&script)
        .arg(&dir)
        .output()
        .unwrap();
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    eprintln!("exudyn_agrees_with_flexbody:\n{log}");
    assert!(
        out.status.success(),
        "scripts/exudyn_check.py failed:\n{log}"
    );
}

/// Writes what `scripts/exudyn_check.py` reads into `dir`: `body.sid`
/// (written by the `flexbody reduce --format sid` command), `nodes.txt`
/// (x y z per node, DOF order), `mass.mtx` and `stiffness.mtx` (full M and
/// K), `modes.mtx` (the SID's elastic mode shapes Phi, m x nq), and
/// `flexbody.json` (frequencies, load, settings, tip node, and the tip
/// displacement history of flexbody's trapezoidal-rule time response).
fn write_exudyn_data(dir: &std::path::Path) {
    use flexbody::export::ffrf::elastic_basis;
    use flexbody::mbs::time::{simulate, Excitation, History, TimeForce, TimeSettings};
    use flexbody::mbs::{Endpoint, FlexibleBody, System};
    use flexbody::reduce::ModeKind;
    std::fs::create_dir_all(dir).unwrap();
    let (sub, _) = hex_beam();
    let tip = 13;
    let deck = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calculix/hex_beam/hex_beam.inp");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_flexbody"))
        .arg("reduce")
        .arg(&deck)
        .args(["--interface", &tip.to_string()])
        .args([
            "--method",
            "free-residual",
            "--modes",
            "4",
            "--format",
            "sid",
        ])
        .arg("--out")
        .arg(dir.join("body.sid"))
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "flexbody reduce: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let body = reduce_with(&sub, Method::FreeResidual, 4, &[tip]);
    let basis = elastic_basis(&sub, &body).unwrap();
    let nq = basis.shapes.ncols();
    let elastic = ReducedBody {
        method: body.method,
        dof_map: body.dof_map.clone(),
        basis: basis.shapes.clone(),
        mass: basis.mass.clone(),
        stiffness: basis.stiffness.clone(),
        damping: None,
        modes: basis
            .frequencies_hz
            .iter()
            .map(|f| ModeKind::Orthonormal { frequency_hz: *f })
            .collect(),
        interface: body.interface.clone(),
    };
    let f1 = basis.frequencies_hz[0];
    let (amplitude, frequency_hz) = (1000.0, 0.37 * f1);
    let settings = TimeSettings {
        step: 1.0 / (f1 * 200.0),
        duration: 6.0 / f1,
        alpha: 0.0,
        ..TimeSettings::default()
    };
    let system = System {
        flexible: vec![FlexibleBody::Reduced(&elastic)],
        ..System::default()
    };
    let excitation = Excitation {
        forces: vec![TimeForce {
            name: "tip".into(),
            at: Endpoint::Flexible { body: 0, node: tip },
            direction: [0.0, 0.0, 1.0],
            history: History::Harmonic {
                amplitude,
                frequency_hz,
                phase: 0.0,
            },
        }],
        ..Excitation::default()
    };
    let response = simulate(&system, &excitation, &settings, None).unwrap();
    let uz = sub.dof_map.index_of(Dof::new(tip, DofKind::Uz)).unwrap();
    let tip_uz: Vec<f64> = response
        .states
        .iter()
        .map(|s| (0..nq).map(|k| basis.shapes[(uz, k)] * s.x[k]).sum())
        .collect();
    // Full matrices and the mode shapes.
    let coordinate = |m: &flexbody::linalg::SparseMat| {
        let t = flexbody::linalg::sparse::triplets_of(m, 1.0);
        let mut s = format!(
            "%%MatrixMarket matrix coordinate real general\n{} {} {}\n",
            m.nrows(),
            m.ncols(),
            t.len()
        );
        for e in t {
            s.push_str(&format!("{} {} {:e}\n", e.row + 1, e.col + 1, e.val));
        }
        s
    };
    std::fs::write(dir.join("mass.mtx"), coordinate(&sub.matrices.mass)).unwrap();
    std::fs::write(
        dir.join("stiffness.mtx"),
        coordinate(&sub.matrices.stiffness),
    )
    .unwrap();
    let mut modes = format!(
        "%%MatrixMarket matrix array real general\n{} {}\n",
        basis.shapes.nrows(),
        nq
    );
    for k in 0..nq {
        for i in 0..basis.shapes.nrows() {
            modes.push_str(&format!("{:e}\n", basis.shapes[(i, k)]));
        }
    }
    std::fs::write(dir.join("modes.mtx"), modes).unwrap();
    let mut nodes = String::new();
    let mut tip_index = None;
    for (p, i) in (0..sub.dof_map.len()).step_by(3).enumerate() {
        let d = sub.dof_map.dof(i);
        assert_eq!(d.kind, DofKind::Ux, "3 translations per node");
        if d.node == tip {
            tip_index = Some(p);
        }
        let x = sub.node_coordinates(d.node).unwrap();
        nodes.push_str(&format!("{:e} {:e} {:e}\n", x[0], x[1], x[2]));
    }
    std::fs::write(dir.join("nodes.txt"), nodes).unwrap();
    let doc = serde_json::json!({
        "frequencies_hz": basis.frequencies_hz,
        "tip_node_index": tip_index.unwrap(),
        "tip_node_id": tip,
        "force": {"direction": [0.0, 0.0, 1.0], "amplitude": amplitude, "frequency_hz": frequency_hz},
        "step": settings.step,
        "duration": settings.duration,
        "times": response.times,
        "tip_uz": tip_uz,
    });
    std::fs::write(dir.join("flexbody.json"), doc.to_string()).unwrap();
}
