//! Exudyn reading the SID file (`scripts/exudyn_check.py`) agrees with
//! flexbody.

use super::support::{
    hex_beam, hex_beam_deck, python_imports, reduce_args, reduce_with, run_ok, run_script,
    skip_without_peer,
};
use flexbody::fem::{Dof, DofKind};
use flexbody::reduce::{Method, ReducedBody};
use std::path::PathBuf;

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
/// scipy, unless [`peers_required`](super::support::peers_required). With `FLEXBODY_EXUDYN_DIR` set, the
/// files are kept there (see [`write_exudyn_data`]).
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
    write_exudyn_data(&dir);
    run_script("exudyn_check.py", &[&dir]);
}

/// Writes what `scripts/exudyn_check.py` reads into `dir`: `body.sid`
/// (written by the `flexbody reduce --format sid` command), `nodes.txt`
/// (x y z per node, DOF order), `mass.mtx` and `stiffness.mtx` (full M and
/// K), `modes.mtx` (the SID's elastic mode shapes Phi, m x nq), and
/// `flexbody.json` (frequencies, load, settings, tip node, and the tip
/// displacement history of flexbody's trapezoidal-rule time response).
fn write_exudyn_data(dir: &std::path::Path) {
    use flexbody::mbs::time::{simulate, Excitation, History, TimeForce, TimeSettings};
    use flexbody::mbs::{Endpoint, FlexibleBody, System};
    use flexbody::reduce::ffrf::elastic_basis;
    use flexbody::reduce::ModeKind;
    std::fs::create_dir_all(dir).unwrap();
    let (sub, _) = hex_beam();
    let tip = 13;
    run_ok(&reduce_args(
        hex_beam_deck(),
        "free-residual",
        "4",
        dir.join("body.sid"),
        &["--interface", &tip.to_string(), "--format", "sid"],
    ));
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
