//! Exudyn reading the SID file (`scripts/exudyn_check.py`) agrees with
//! flexbody.

use super::support::{
    hex_beam_deck, python_imports, reduce_args, reduce_with, run_ok, run_script, skip_without_peer,
    welib_clamped_beam, write_beam_case, SKEW_TIMOSHENKO,
};
use flexbody::fem::{Dof, DofKind};
use flexbody::reduce::{Method, ReducedBody};
use std::path::PathBuf;

/// Exudyn, a real MBS client, against flexbody: `scripts/exudyn_check.py`
/// reads the SID file that `flexbody reduce --format sid` writes, builds an
/// `ObjectFFRFreducedOrder` from its invariants alone, and compares it with
/// the same body built apart from flexbody's invariants (for the C3D8 bar
/// `hex_beam`, by Exudyn's `FEMinterface` from the full M, K and mode
/// shapes; for a beam, from the mass integrals of
/// `scripts/beam_invariants.py` over the beam's shape functions and the
/// full K), and with flexbody's
/// own frequencies and trapezoidal-rule time response of the tip to a
/// harmonic force (frame held fixed: `Me q'' + Ke q = Phi_tip^T f(t)`); the
/// two Exudyn bodies then move at large: a free tumble (whose energy and
/// momentum must hold to the integrator's second order), and a pendulum
/// swinging under gravity from the tip node on a spherical joint, or, for
/// a clamped body, a hub turning under gravity. Six bodies ([`CASES`]):
/// free-residual and Craig-Bampton of the free bar and of a free skew
/// Timoshenko beam, and Craig-Bampton of the bar clamped at x = 0 and of a
/// beam clamped at the origin, whose full M holds the clamped nodes' mass
/// (the SID must too). The tolerances and the figures measured are in the
/// script.
///
/// Skipped, with a message, when `python3` cannot import exudyn, numpy and
/// scipy, unless [`peers_required`](super::support::peers_required). With `FLEXBODY_EXUDYN_DIR` set, the
/// files are kept there, one folder per case (see [`write_exudyn_data`]).
#[test]
fn exudyn_agrees_with_flexbody() {
    if let Err(why) = python_imports("exudyn, numpy, scipy") {
        skip_without_peer(
            "exudyn_agrees_with_flexbody",
            &format!("Exudyn (python3: {why})"),
        );
        return;
    }
    let temporary = tempfile::tempdir().unwrap();
    let dir = std::env::var_os("FLEXBODY_EXUDYN_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| temporary.path().to_path_buf());
    for case in &CASES {
        let folder = dir.join(case.name);
        write_exudyn_data(&folder, case);
        run_script("exudyn_check.py", &[&folder]);
    }
}

/// What a case reduces.
#[derive(Clone, Copy, PartialEq)]
enum Mesh {
    /// The C3D8 bar `hex_beam` (0.6 m along x), clamped at x = 0 if
    /// `clamped`; its tip is node 13 (x = 0.6 m).
    HexBar { clamped: bool },
    /// A free skew Timoshenko beam with rotary inertia, 6 elements, nodes
    /// 1 to 7 (`SKEW_TIMOSHENKO`).
    SkewBeam,
    /// An Euler-Bernoulli beam, 10 elements from the origin to x = 2 m,
    /// clamped at node 1 (the origin), tip node 11.
    ClampedBeam,
}

impl Mesh {
    fn clamped(self) -> bool {
        matches!(self, Mesh::HexBar { clamped: true } | Mesh::ClampedBeam)
    }

    fn is_beam(self) -> bool {
        matches!(self, Mesh::SkewBeam | Mesh::ClampedBeam)
    }

    /// The model file of the mesh, written into `dir` where needed.
    fn model(self, dir: &std::path::Path) -> PathBuf {
        match self {
            Mesh::HexBar { clamped } => case_deck(dir, clamped),
            Mesh::SkewBeam | Mesh::ClampedBeam => {
                let path = dir.join("beam.toml");
                let text = match self {
                    Mesh::SkewBeam => SKEW_TIMOSHENKO.to_string(),
                    _ => welib_clamped_beam(),
                };
                std::fs::write(&path, text).unwrap();
                path
            }
        }
    }
}

/// One body of the Exudyn check.
struct Case {
    name: &'static str,
    mesh: Mesh,
    /// `--method` of `flexbody reduce`.
    method: &'static str,
    modes: usize,
    interface: &'static [u64],
    /// The node where the force acts and the pendulum hangs.
    tip: u64,
}

const CASES: [Case; 6] = [
    Case {
        name: "free_residual",
        mesh: Mesh::HexBar { clamped: false },
        method: "free-residual",
        modes: 4,
        interface: &[13],
        tip: 13,
    },
    Case {
        name: "craig_bampton",
        mesh: Mesh::HexBar { clamped: false },
        method: "craig-bampton",
        modes: 3,
        interface: &[1, 27, 79, 13],
        tip: 13,
    },
    Case {
        name: "clamped_craig_bampton",
        mesh: Mesh::HexBar { clamped: true },
        method: "craig-bampton",
        modes: 4,
        interface: &[13],
        tip: 13,
    },
    Case {
        name: "beam_free_residual",
        mesh: Mesh::SkewBeam,
        method: "free-residual",
        modes: 4,
        interface: &[7],
        tip: 7,
    },
    Case {
        name: "beam_craig_bampton",
        mesh: Mesh::SkewBeam,
        method: "craig-bampton",
        modes: 3,
        interface: &[1, 7],
        tip: 7,
    },
    Case {
        name: "beam_clamped_craig_bampton",
        mesh: Mesh::ClampedBeam,
        method: "craig-bampton",
        modes: 4,
        interface: &[11],
        tip: 11,
    },
];

/// The hex_beam deck, clamped at x = 0 if `clamped`, written into `dir`.
fn case_deck(dir: &std::path::Path, clamped: bool) -> PathBuf {
    let text = std::fs::read_to_string(hex_beam_deck()).unwrap();
    if !clamped {
        return hex_beam_deck();
    }
    let root: Vec<&str> = text
        .lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split(',').map(str::trim).collect();
            (f.len() == 4 && f[1] == "0.0").then_some(f[0])
        })
        .collect();
    assert_eq!(root.len(), 4, "the bar's end face");
    let boundary: String = root.iter().map(|n| format!("{n}, 1, 3\n")).collect();
    let deck = dir.join("clamped.inp");
    let at = text.find("*STEP").unwrap();
    std::fs::write(
        &deck,
        format!("{}*BOUNDARY\n{boundary}{}", &text[..at], &text[at..]),
    )
    .unwrap();
    deck
}

/// Writes what `scripts/exudyn_check.py` reads into `dir`: `body.sid`
/// (written by the `flexbody reduce --format sid` command), `nodes.txt`
/// (x y z per node, in the order of the mesh's nodes), `mass.mtx` and
/// `stiffness.mtx` (full M and K of the unconstrained mesh: the clamped
/// nodes too), `modes.mtx` (the SID's elastic mode shapes Phi on those
/// DOFs, zero where clamped, m x nq), for a beam `beam.json` (what
/// `scripts/beam_invariants.py` reads: the beam's elements and Phi at
/// every node), and `flexbody.json` (the case, frequencies, load,
/// settings, tip node, and the tip displacement history of flexbody's
/// trapezoidal-rule time response).
fn write_exudyn_data(dir: &std::path::Path, case: &Case) {
    use flexbody::fem::{Model, Substructure};
    use flexbody::input::{load, MatrixFiles};
    use flexbody::mbs::time::{simulate, Excitation, History, TimeForce, TimeSettings};
    use flexbody::mbs::{Endpoint, FlexibleBody, System};
    use flexbody::reduce::ffrf::elastic_basis;
    use flexbody::reduce::ModeKind;
    std::fs::create_dir_all(dir).unwrap();
    let deck = case.mesh.model(dir);
    let interface: Vec<String> = case.interface.iter().map(u64::to_string).collect();
    run_ok(&reduce_args(
        &deck,
        case.method,
        &case.modes.to_string(),
        dir.join("body.sid"),
        &["--interface", &interface.join(","), "--format", "sid"],
    ));
    let c = load(&deck, &MatrixFiles::default()).unwrap();
    let (sub, model) = (c.sub, c.model.unwrap());
    let method = match case.method {
        "free-residual" => Method::FreeResidual,
        _ => Method::CraigBampton,
    };
    let body = reduce_with(&sub, method, case.modes, case.interface);
    let tip = case.tip;
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
        local_axes: Default::default(),
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
    // Full matrices of the mesh without its boundary conditions, and the
    // mode shapes on their DOFs (zero where clamped).
    let free_model = Model::of(model.nodes().to_vec(), model.elements().to_vec())
        .build()
        .unwrap();
    let full = Substructure::from_model(&free_model).unwrap();
    let shapes = faer::Mat::from_fn(full.dof_map.len(), nq, |i, k| {
        sub.dof_map
            .index_of(full.dof_map.dof(i))
            .map_or(0.0, |j| basis.shapes[(j, k)])
    });
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
    std::fs::write(dir.join("mass.mtx"), coordinate(&full.matrices.mass)).unwrap();
    std::fs::write(
        dir.join("stiffness.mtx"),
        coordinate(&full.matrices.stiffness),
    )
    .unwrap();
    let mut modes = format!(
        "%%MatrixMarket matrix array real general\n{} {}\n",
        shapes.nrows(),
        nq
    );
    for k in 0..nq {
        for i in 0..shapes.nrows() {
            modes.push_str(&format!("{:e}\n", shapes[(i, k)]));
        }
    }
    std::fs::write(dir.join("modes.mtx"), modes).unwrap();
    // Node by node, each node's DOFs together: 3 translations of a solid,
    // 6 DOFs of a 3D beam.
    let per_node = if case.mesh.is_beam() { 6 } else { 3 };
    assert_eq!(full.dof_map.len(), per_node * model.nodes().len());
    let mut nodes = String::new();
    for (p, n) in model.nodes().iter().enumerate() {
        for (k, kind) in DofKind::ALL[..per_node].iter().enumerate() {
            assert_eq!(full.dof_map.dof(per_node * p + k), Dof::new(n.id, *kind));
        }
        nodes.push_str(&format!(
            "{:e} {:e} {:e}\n",
            n.coords[0], n.coords[1], n.coords[2]
        ));
    }
    let tip_index = model.nodes().iter().position(|n| n.id == tip);
    std::fs::write(dir.join("nodes.txt"), nodes).unwrap();
    if case.mesh.is_beam() {
        write_beam_case(&model, &sub, &body, &dir.join("beam.json"));
    }
    let doc = serde_json::json!({
        "case": case.name,
        "method": case.method,
        "clamped": case.mesh.clamped(),
        "beam": case.mesh.is_beam(),
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
