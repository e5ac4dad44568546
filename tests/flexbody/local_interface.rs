//! Interface DOFs along local axes (`*TRANSFORM`): a reduction whose
//! interface names DOFs of a transformed node takes them along the node's
//! local axes, as CalculiX and Abaqus read boundary conditions there.
//!
//! The independent reference is geometry: the same bar meshed turned by
//! `R^T`, so that the local axes of the tip node lie along the global ones,
//! reduced on the global DOFs of the tip. Both bodies must be the same
//! body: equal reduced frequencies, and bases that map onto each other by
//! `u = R u_ref` at every node.

use super::support::{fails_with, run_ok, stdout_json};
use faer::Mat;
use flexbody::export::{read_json, read_sid};
use flexbody::fem::{Dof, DofKind, Substructure};
use flexbody::input::file_reduction;
use flexbody::io::deck::{parse_deck, DeckOptions};
use flexbody::reduce::{reduce, Method, ReducedBody, Reduction};
use flexbody::scenario::read_model_file;
use std::path::Path;

/// Cells along x, y, z of the bar (0.5 m x 0.1 m x 0.06 m: no two bending
/// frequencies alike).
const CELLS: [usize; 3] = [6, 2, 2];
const SIZE: [f64; 3] = [0.5, 0.1, 0.06];

/// The points of `*TRANSFORM, TYPE=R`: `a` on the local x axis, `b` in the
/// local xy plane.
const A: [f64; 3] = [1.0, 1.0, 1.0];
const B: [f64; 3] = [-1.0, 1.0, 0.0];

fn node_id(i: usize, j: usize, k: usize) -> usize {
    1 + i + (CELLS[0] + 1) * (j + (CELLS[1] + 1) * k)
}

/// The tip node: the corner at x = L, y = 0, z = 0.
fn tip() -> u64 {
    node_id(CELLS[0], 0, 0) as u64
}

/// The local axes of the tip, from `A` and `B` by Gram-Schmidt (columns).
fn axes() -> [[f64; 3]; 3] {
    let norm = |v: [f64; 3]| {
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.map(|x| x / n)
    };
    let x = norm(A);
    let d: f64 = B.iter().zip(&x).map(|(b, x)| b * x).sum();
    let y = norm([B[0] - d * x[0], B[1] - d * x[1], B[2] - d * x[2]]);
    let z = [
        x[1] * y[2] - x[2] * y[1],
        x[2] * y[0] - x[0] * y[2],
        x[0] * y[1] - x[1] * y[0],
    ];
    std::array::from_fn(|i| [x[i], y[i], z[i]])
}

/// The C3D8 bar deck, its nodes placed by `place`; `clamped` holds the
/// face x = 0; `extra` is appended (a `*TRANSFORM`, a `*BOUNDARY`).
fn bar(place: impl Fn([f64; 3]) -> [f64; 3], clamped: bool, extra: &str) -> String {
    let mut s = String::from("*NODE\n");
    for k in 0..=CELLS[2] {
        for j in 0..=CELLS[1] {
            for i in 0..=CELLS[0] {
                let x = [
                    SIZE[0] * i as f64 / CELLS[0] as f64,
                    SIZE[1] * j as f64 / CELLS[1] as f64,
                    SIZE[2] * k as f64 / CELLS[2] as f64,
                ];
                let p = place(x);
                s += &format!(
                    "{}, {:.17e}, {:.17e}, {:.17e}\n",
                    node_id(i, j, k),
                    p[0],
                    p[1],
                    p[2]
                );
            }
        }
    }
    s += "*ELEMENT, TYPE=C3D8, ELSET=EALL\n";
    let mut e = 1;
    for k in 0..CELLS[2] {
        for j in 0..CELLS[1] {
            for i in 0..CELLS[0] {
                let n = |a: usize, b: usize, c: usize| node_id(i + a, j + b, k + c);
                s += &format!(
                    "{e}, {}, {}, {}, {}, {}, {}, {}, {}\n",
                    n(0, 0, 0),
                    n(1, 0, 0),
                    n(1, 1, 0),
                    n(0, 1, 0),
                    n(0, 0, 1),
                    n(1, 0, 1),
                    n(1, 1, 1),
                    n(0, 1, 1)
                );
                e += 1;
            }
        }
    }
    s += "*NSET, NSET=ROOT\n";
    for k in 0..=CELLS[2] {
        for j in 0..=CELLS[1] {
            s += &format!("{}\n", node_id(0, j, k));
        }
    }
    s += &format!("*NSET, NSET=TIP\n{}\n", tip());
    s += "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n";
    s += "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n";
    if clamped {
        s += "*BOUNDARY\nROOT, 1, 3\n";
    }
    s + extra
}

/// The `*TRANSFORM` of node set `nset` (`TIP`, or `REF` of [`coupled`]).
fn transform(nset: &str) -> String {
    format!(
        "*TRANSFORM, NSET={nset}, TYPE=R\n{}, {}, {}, {}, {}, {}\n",
        A[0], A[1], A[2], B[0], B[1], B[2]
    )
}

/// The reference node of [`coupled`].
const REF: u64 = 9001;

/// A kinematic coupling of the face x = L to node 9001 off its centre
/// (placed by `place`), in node set `REF`.
fn coupled(place: impl Fn([f64; 3]) -> [f64; 3]) -> String {
    let p = place([SIZE[0], 0.04, 0.02]);
    let mut s = format!(
        "*NODE\n{REF}, {:.17e}, {:.17e}, {:.17e}\n*NSET, NSET=REF\n{REF}\n*NSET, NSET=FACE\n",
        p[0], p[1], p[2]
    );
    for k in 0..=CELLS[2] {
        for j in 0..=CELLS[1] {
            s += &format!("{}\n", node_id(CELLS[0], j, k));
        }
    }
    s + &format!(
        "*SURFACE, NAME=SFACE, TYPE=NODE\nFACE\n\
         *COUPLING, REF NODE={REF}, SURFACE=SFACE, CONSTRAINT NAME=END\n*KINEMATIC\n1, 3\n"
    )
}

/// `R^T x`: the mesh turned so that the tip's local axes are global.
fn turned(x: [f64; 3]) -> [f64; 3] {
    let r = axes();
    std::array::from_fn(|i| (0..3).map(|j| r[j][i] * x[j]).sum())
}

fn substructure(text: &str) -> (Substructure, flexbody::fem::Model) {
    let deck = parse_deck(Path::new("bar.inp"), text, &DeckOptions::default()).unwrap();
    (Substructure::from_model(&deck.model).unwrap(), deck.model)
}

/// Where the interface is: the tip node of the bar, or the reference node
/// of a coupling at its tip face.
#[derive(Clone, Copy, PartialEq)]
enum At {
    Tip,
    Coupling,
}

/// The body of the transformed bar (interface `kinds` at `at`, local) and
/// of the turned bar (the same kinds, global).
fn bodies(
    method: Method,
    modes: usize,
    clamped: bool,
    at: At,
    kinds: &[DofKind],
) -> [ReducedBody; 2] {
    let (node, extra, extra_turned) = match at {
        At::Tip => (tip(), transform("TIP"), String::new()),
        At::Coupling => (REF, coupled(|x| x) + &transform("REF"), coupled(turned)),
    };
    let interface: Vec<Dof> = kinds.iter().map(|&k| Dof::new(node, k)).collect();
    let (sub, model) = substructure(&bar(|x| x, clamped, &extra));
    let mut spec = Reduction::new(method, modes, interface.clone());
    spec.local_axes = model.local_axes().clone();
    let local = reduce(&sub, &spec).unwrap();
    let (sub_ref, model_ref) = substructure(&bar(turned, clamped, &extra_turned));
    assert!(model_ref.local_axes().is_empty());
    let reference = reduce(&sub_ref, &Reduction::new(method, modes, interface)).unwrap();
    [local, reference]
}

/// The largest entry of `a - b`.
fn axes_difference(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / y.abs().max(1.0))
        .fold(0.0, f64::max)
}

/// `R` times the three rows of each node of the reference basis, against
/// the local body's global rows, column by column up to the sign of the
/// column (eigenmodes have no sign); the largest difference relative to
/// the column's largest entry.
fn basis_difference(local: &ReducedBody, reference: &ReducedBody) -> f64 {
    let r = axes();
    let map = &local.dof_map;
    assert_eq!(map.dofs(), reference.dof_map.dofs());
    let mut worst = 0.0_f64;
    for c in 0..local.r() {
        let mut turned = Mat::<f64>::zeros(map.len(), 1);
        for (i, d) in map.dofs().iter().enumerate() {
            let row = |k: DofKind| {
                let j = reference.dof_map.index_of(Dof::new(d.node, k)).unwrap();
                reference.basis[(j, c)]
            };
            let kinds = flexbody::fem::transform::family(d.kind);
            let a = d.kind.index() % 3;
            turned[(i, 0)] = (0..3).map(|b| r[a][b] * row(kinds[b])).sum();
        }
        let col = local.basis.col(c);
        let dot: f64 = (0..map.len()).map(|i| col[i] * turned[(i, 0)]).sum();
        let sign = if dot < 0.0 { -1.0 } else { 1.0 };
        let scale = turned.norm_max();
        let diff = (0..map.len())
            .map(|i| (col[i] - sign * turned[(i, 0)]).abs())
            .fold(0.0, f64::max);
        worst = worst.max(diff / scale);
    }
    worst
}

#[test]
fn the_deck_gives_the_tip_the_axes_of_its_transform() {
    let (_, model) = substructure(&bar(|x| x, true, &transform("TIP")));
    let got = model.local_axes()[&tip()];
    assert!(axes_difference(got, axes()) < 1e-15, "{got:?}");
    assert_eq!(model.local_axes().len(), 1);
}

#[test]
fn craig_bampton_on_a_local_dof_is_the_body_of_the_mesh_turned_to_the_local_axes() {
    let [local, reference] = bodies(Method::CraigBampton, 4, true, At::Tip, &[DofKind::Ux]);
    let (f, f_ref) = (
        local.frequencies_hz().unwrap(),
        reference.frequencies_hz().unwrap(),
    );
    let df = relative_difference(&f, &f_ref);
    assert!(df < 1e-10, "{f:?} against {f_ref:?}: {df:e}");
    // The constraint mode and the fixed-interface eigenmodes, node by node.
    let db = basis_difference(&local, &reference);
    assert!(db < 1e-10, "basis: {db:e}");
    // The interface row is the local component: that of the turned mesh's
    // global ux (the constraint mode's is exactly 1).
    let (rows, rows_ref) = (local.interface_rows(), reference.interface_rows());
    assert!((rows[(0, 0)] - 1.0).abs() < 1e-12, "{rows:?}");
    assert!((rows_ref[(0, 0)] - 1.0).abs() < 1e-12);
    assert_eq!(
        local.local_axes.keys().copied().collect::<Vec<_>>(),
        vec![tip()]
    );
    assert_eq!(
        local.modes[0],
        flexbody::reduce::ModeKind::Constraint {
            dof: Dof::new(tip(), DofKind::Ux)
        }
    );

    // Without the axes the interface is global ux, another body.
    let (sub, _) = substructure(&bar(|x| x, true, &transform("TIP")));
    let global = reduce(
        &sub,
        &Reduction::new(Method::CraigBampton, 4, vec![Dof::new(tip(), DofKind::Ux)]),
    )
    .unwrap();
    let dg = relative_difference(&global.frequencies_hz().unwrap(), &f_ref);
    assert!(dg > 1e-3, "global ux should differ: {dg:e}");
}

#[test]
fn a_coupling_point_with_local_axes_keeps_a_local_translation_and_rotation() {
    let kinds = [DofKind::Uy, DofKind::Rz];
    let [local, reference] = bodies(Method::CraigBampton, 3, true, At::Coupling, &kinds);
    let (f, f_ref) = (
        local.frequencies_hz().unwrap(),
        reference.frequencies_hz().unwrap(),
    );
    let df = relative_difference(&f, &f_ref);
    assert!(df < 1e-10, "{f:?} against {f_ref:?}: {df:e}");
    let db = basis_difference(&local, &reference);
    assert!(db < 1e-10, "basis: {db:e}");
    // The constraint modes move the point by one along their own local
    // DOF and not along the other.
    let rows = local.interface_rows();
    for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
        let expected = if i == j { 1.0 } else { 0.0 };
        assert!((rows[(i, j)] - expected).abs() < 1e-12, "{rows:?}");
    }
    assert_eq!(
        local.local_axes.keys().copied().collect::<Vec<_>>(),
        vec![REF]
    );
}

#[test]
fn free_residual_on_two_local_dofs_is_the_body_of_the_turned_mesh() {
    let [local, reference] = bodies(
        Method::FreeResidual,
        3,
        false,
        At::Tip,
        &[DofKind::Ux, DofKind::Uz],
    );
    let (f, f_ref) = (
        local.frequencies_hz().unwrap(),
        reference.frequencies_hz().unwrap(),
    );
    // Six rigid-body modes at round-off, then the elastic ones.
    assert_eq!(f.len(), 6 + 2 + 3);
    let df = relative_difference(&f[6..], &f_ref[6..]);
    assert!(df < 1e-9, "{f:?} against {f_ref:?}: {df:e}");
    assert!(f[..6].iter().all(|x| x.abs() < 1e-3 * f[6]), "{f:?}");
}

#[test]
fn a_body_file_keeps_the_local_axes_and_the_sid_turns_the_node_frame() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bar.inp"),
        bar(|x| x, true, &transform("TIP")),
    )
    .unwrap();
    let model = dir.path().join("bar.toml");
    std::fs::write(
        &model,
        format!(
            "mesh = \"bar.inp\"\n[interface]\ndofs = [{{ node = {}, dof = \"ux\" }}]\n",
            tip()
        ),
    )
    .unwrap();
    let [expected, _] = bodies(Method::CraigBampton, 4, true, At::Tip, &[DofKind::Ux]);
    let json = dir.path().join("bar.json");
    let m = model.to_str().unwrap();
    run_ok(&[
        "reduce",
        m,
        "--method",
        "craig-bampton",
        "--modes",
        "4",
        "--out",
        json.to_str().unwrap(),
    ]);
    let body = read_json(&json).unwrap();
    // Axes that are not orthonormal, or on a node without interface DOFs,
    // are refused at their block.
    let text = std::fs::read_to_string(&json).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    for (entry, needle) in [
        (
            serde_json::json!({"node": tip(), "axes": [[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]}),
            "orthonormal",
        ),
        (
            serde_json::json!({"node": 1, "axes": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]}),
            "no interface DOF",
        ),
    ] {
        let mut bad = doc.clone();
        bad["local_axes"] = serde_json::json!([entry]);
        let path = dir.path().join("bad.json");
        std::fs::write(&path, serde_json::to_string_pretty(&bad).unwrap()).unwrap();
        let err = read_json(&path).unwrap_err().to_string();
        assert!(err.contains("local_axes") && err.contains(needle), "{err}");
    }
    assert_eq!(body.local_axes, expected.local_axes);
    assert_eq!(body.interface, expected.interface);
    let (a, b) = (body.interface_rows(), expected.interface_rows());
    assert!((&a - &b).norm_max() <= 1e-12 * b.norm_max(), "{a:?} {b:?}");
    let inspect = run_ok(&["inspect", json.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&inspect.stdout);
    assert!(
        text.contains("along local axes (*TRANSFORM) at 1 node"),
        "{text}"
    );
    let summary = stdout_json(&run_ok(&["inspect", json.to_str().unwrap(), "--json"]));
    assert_eq!(summary["local_axes_nodes"], serde_json::json!([tip()]));

    // The SID's node frame is the local one: AP m0 = R.
    let sid = dir.path().join("bar.sid");
    run_ok(&[
        "reduce",
        m,
        "--method",
        "craig-bampton",
        "--modes",
        "4",
        "--format",
        "sid",
        "--out",
        sid.to_str().unwrap(),
    ]);
    let sid = read_sid(&sid).unwrap();
    let node = sid.nodes.iter().find(|n| n.id == tip()).unwrap();
    let ap = std::array::from_fn(|i| std::array::from_fn(|j| node.ap.m0[(i, j)]));
    assert!(
        axes_difference(ap, axes()) < 1e-12,
        "AP m0 {:?}",
        node.ap.m0
    );
}

#[test]
fn a_local_interface_dof_at_a_node_held_along_another_local_axis_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let held = format!("{}*BOUNDARY\nTIP, 2, 2\n", transform("TIP"));
    let deck = dir.path().join("bar.inp");
    std::fs::write(&deck, bar(|x| x, true, &held)).unwrap();
    let out = dir.path().join("bar.json");
    fails_with(
        &[
            "reduce",
            deck.to_str().unwrap(),
            "--method",
            "craig-bampton",
            "--modes",
            "2",
            "--interface",
            &tip().to_string(),
            "--out",
            out.to_str().unwrap(),
        ],
        &[
            &format!("node {}", tip()),
            "local axes",
            "translations free",
        ],
    );
    assert!(!out.exists());
}

#[test]
fn a_connection_at_a_transformed_node_acts_along_global_directions() {
    // Without an [interface], the interface is the DOFs the connection
    // acts on: at a node with local axes, all three (local) translations,
    // which span the global ones. The body is the one of the untransformed
    // bar with the node's global translations.
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, deck: &str, interface: &str| {
        std::fs::write(dir.path().join(format!("{name}.inp")), deck).unwrap();
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(
            &path,
            format!(
                "mesh = \"{name}.inp\"\n{interface}\n[[connection]]\nname = \"spring\"\n\
                 node = {}\nto = \"ground\"\ndirection = [0.0, 0.0, 1.0]\nstiffness = 1.0e6\n",
                tip()
            ),
        )
        .unwrap();
        read_model_file(&path).unwrap()
    };
    let local = file("local", &bar(|x| x, true, &transform("TIP")), "");
    let kinds = [DofKind::Ux, DofKind::Uy, DofKind::Uz];
    let expected: Vec<Dof> = kinds.iter().map(|&k| Dof::new(tip(), k)).collect();
    assert_eq!(local.interface, expected);
    let global = file(
        "global",
        &bar(|x| x, true, ""),
        &format!("[interface]\nnodes = [{}]\n", tip()),
    );
    assert_eq!(global.interface, expected);
    let body = |f: &flexbody::scenario::ModelFile| {
        let sub = Substructure::from_model(&f.model).unwrap();
        let spec = file_reduction(f, Method::CraigBampton, 3, f.interface.clone());
        reduce(&sub, &spec).unwrap()
    };
    let (a, b) = (body(&local), body(&global));
    assert_eq!(a.local_axes.len(), 1);
    assert!(b.local_axes.is_empty());
    let (fa, fb) = (a.frequencies_hz().unwrap(), b.frequencies_hz().unwrap());
    let df = relative_difference(&fa, &fb);
    assert!(df < 1e-10, "{fa:?} against {fb:?}: {df:e}");
    // What the connection sees, a unit force along global z at the node:
    // the same static deflection there, u = T_z K_red^-1 T_z^T.
    let compliance = |body: &ReducedBody| {
        use faer::linalg::solvers::Solve;
        let row = body.row_of(Dof::new(tip(), DofKind::Uz)).unwrap();
        let t = Mat::from_fn(row.len(), 1, |i, _| row[i]);
        let q = body.stiffness.llt(faer::Side::Lower).unwrap().solve(&t);
        (t.transpose() * q)[(0, 0)]
    };
    let (ca, cb) = (compliance(&a), compliance(&b));
    assert!((ca - cb).abs() < 1e-10 * cb, "{ca:e} against {cb:e}");
}

#[test]
fn simulate_records_interface_displacements_along_the_local_axes() {
    // The same run on the transformed bar (its tip's interface DOFs local)
    // and on the plain bar (global): all three translations of the tip in
    // both, so the bodies span the same motions and the local columns are
    // R^T times the global ones at every step.
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &str| {
        std::fs::write(
            dir.path().join(format!("{name}.inp")),
            bar(|x| x, true, extra),
        )
        .unwrap();
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(
            &path,
            format!(
                "mesh = \"{name}.inp\"\n[interface]\nnodes = [{tip}]\n\
                 [[connection]]\nname = \"spring\"\nnode = {tip}\nto = \"ground\"\n\
                 direction = [0.0, 0.0, 1.0]\nstiffness = 1.0e6\n\
                 [[force]]\nname = \"push\"\nnode = {tip}\ndirection = [0.3, 0.5, 1.0]\n\
                 harmonic = {{ amplitude = 1000.0, frequency_hz = 800.0, phase = 0.0 }}\n\
                 [simulation]\nmethod = \"craig-bampton\"\nmodes = 2\nspeed = 0.0\nduration = 0.004\n\
                 step = 1.0e-5\nalpha = 0.0\n",
                tip = tip()
            ),
        )
        .unwrap();
        let out = dir.path().join(name);
        run_ok(&[
            "simulate",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let text = std::fs::read_to_string(out.join("histories.csv")).unwrap();
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .unwrap()
            .split(',')
            .map(|h| h.trim().trim_matches('"').to_string())
            .collect();
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|v| v.trim().parse().unwrap()).collect())
            .collect();
        (header, rows)
    };
    let (h_local, local) = run("local", &transform("TIP"));
    let (h_global, global) = run("global", "");
    let column = |header: &[String], name: String| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("{name} in {header:?}"))
    };
    let r = axes();
    let kinds = ["ux", "uy", "uz"];
    let n = tip();
    let at_local: Vec<usize> = kinds
        .iter()
        .map(|k| column(&h_local, format!("node {n} {k} local (m)")))
        .collect();
    let at_global: Vec<usize> = kinds
        .iter()
        .map(|k| column(&h_global, format!("node {n} {k} (m)")))
        .collect();
    assert_eq!(local.len(), global.len());
    let scale = global
        .iter()
        .flat_map(|row| at_global.iter().map(|&c| row[c].abs()))
        .fold(0.0, f64::max);
    assert!(scale > 0.0);
    let mut worst = 0.0_f64;
    for (a, b) in local.iter().zip(&global) {
        for (i, &c) in at_local.iter().enumerate() {
            let expected: f64 = (0..3).map(|j| r[j][i] * b[at_global[j]]).sum();
            worst = worst.max((a[c] - expected).abs());
        }
    }
    assert!(worst < 1e-8 * scale, "{worst:e} of {scale:e}");
}
