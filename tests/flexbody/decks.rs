//! Decks and matrices from other programs through the command line and the
//! library: frequencies against CalculiX's, reductions from a deck and from
//! bare matrices, solid stresses, and bad decks.

use flexbody::fem::{DofKind, Element};
use flexbody::input::{load, MatrixFiles};
use flexbody::recover::{nodal_stresses, ModalStress};
use flexbody::reduce::{reduce, Method, ModeKind, Reduction};
use std::ffi::OsStr;
use std::path::PathBuf;

fn fixture(name: &str, ext: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(format!("tests/fixtures/calculix/{name}/{name}.{ext}"))
}

fn ccx_frequencies(name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join(format!("tests/fixtures/calculix/{name}/frequencies.txt")),
    )
    .unwrap();
    text.lines().filter_map(|l| l.trim().parse().ok()).collect()
}

fn flexbody<S: AsRef<OsStr>>(args: &[S]) -> (i32, String, String) {
    let o = super::support::flexbody(args);
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn modes_json(path: &str) -> Vec<f64> {
    let (code, out, err) = flexbody(&["modes", path, "--count", "10", "--json"]);
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(
        doc["residuals"]
            .as_array()
            .unwrap()
            .iter()
            .all(|r| r.as_f64().unwrap() < 1e-9),
        "{doc}"
    );
    serde_json::from_value(doc["frequencies_hz"].clone()).unwrap()
}

#[test]
fn modes_of_a_deck_and_of_its_calculix_matrices_agree_with_calculix() {
    let deck = modes_json(fixture("hex_beam", "inp").to_str().unwrap());
    let matrices = modes_json(fixture("hex_beam", "sti").to_str().unwrap());
    let ccx = ccx_frequencies("hex_beam");
    assert_eq!(deck.len(), 10);
    // Rigid-body modes at round-off: the matrices come through a text file
    // with 14 digits, so theirs sit higher, still 1e-6 below the first
    // elastic mode.
    for k in 0..6 {
        assert!(
            deck[k] < 1e-6 * deck[6] && matrices[k] < 1e-5 * deck[6],
            "rigid mode {k}: {} {}",
            deck[k],
            matrices[k]
        );
    }
    for k in 6..10 {
        assert!(
            (deck[k] - ccx[k]).abs() < 1e-6 * ccx[k],
            "{} vs ccx {}",
            deck[k],
            ccx[k]
        );
        assert!((deck[k] - matrices[k]).abs() < 1e-9 * deck[k]);
    }
}

#[test]
fn a_deck_and_its_bare_matrices_reduce_to_the_same_body() {
    // Matrices carry no geometry: the rigid-body modes come from K's null
    // space instead of eq. 12; the span, and so the frequencies, agree.
    let deck = load(&fixture("hex_beam", "inp"), &MatrixFiles::default()).unwrap();
    let bare = load(&fixture("hex_beam", "sti"), &MatrixFiles::default()).unwrap();
    assert!(bare.model.is_none());
    let ends = "1,13";
    let spec = |c: &flexbody::input::Component| {
        Reduction::new(Method::FreeResidual, 2, c.interface(Some(ends)).unwrap())
    };
    let a = reduce(&deck.sub, &spec(&deck)).unwrap();
    let b = reduce(&bare.sub, &spec(&bare)).unwrap();
    assert_eq!(a.r(), 6 + 6 + 2);
    let (fa, fb) = (a.frequencies_hz().unwrap(), b.frequencies_hz().unwrap());
    for (x, y) in fa.iter().zip(&fb).skip(6) {
        assert!((x - y).abs() < 1e-7 * x, "{x} vs {y}");
    }
    // The kept eigenmodes are exact, the others bounded from above.
    let ccx = ccx_frequencies("hex_beam");
    assert!((fa[6] - ccx[6]).abs() < 1e-6 * ccx[6] && (fa[7] - ccx[7]).abs() < 1e-6 * ccx[7]);
}

#[test]
fn reduce_and_info_work_on_decks_and_matrices_from_the_command_line() {
    let dir = std::env::temp_dir().join(format!("flexbody-decks-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("tet.json");
    let deck = fixture("tet_beam", "inp");
    let (code, stdout, err) = flexbody(&super::support::reduce_args(
        &deck,
        "free-residual",
        "2",
        &out,
        &["--interface", "1", "--json"],
    ));
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("skipped, as they do not change the linear K, M or D: *STEP (line"),
        "the deck's skipped keywords are shown, on one line: {err}"
    );
    let doc: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(doc["r"], 6 + 3 + 2);
    // What was written: the r x r matrices, whose pencil has the two kept
    // eigenmodes' frequencies exactly (CalculiX's, to its 7 digits) and
    // six rigid-body modes; and the mass of the block, 7850 kg/m^3 x 0.2 x
    // 0.1 x 0.1 m (the deck's *DENSITY and geometry), as the rigid
    // translation's generalised mass.
    let body = flexbody::export::read_json(&out).unwrap();
    assert_eq!(
        (body.r(), body.mass.nrows(), body.stiffness.ncols()),
        (11, 11, 11)
    );
    assert_eq!(body.basis.nrows(), body.dof_map.len());
    let pairs =
        flexbody::linalg::eigen::generalized_symmetric(body.stiffness.as_ref(), body.mass.as_ref())
            .unwrap();
    let hz: Vec<f64> = pairs
        .values
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    let ccx = ccx_frequencies("tet_beam");
    // Rigid-body modes at round-off: measured 5.4e-8 of the first elastic.
    assert!(hz[..6].iter().all(|f| *f < 5e-7 * ccx[6]), "{hz:?}");
    for k in [6, 7] {
        // measured 7.7e-8 and 3.4e-7 (CalculiX prints 7 digits)
        assert!(
            (hz[k] - ccx[k]).abs() < 1e-6 * ccx[k],
            "{} vs ccx {}",
            hz[k],
            ccx[k]
        );
    }
    let printed: Vec<f64> = serde_json::from_value(doc["reduced_hz"].clone()).unwrap();
    for (a, b) in printed.iter().zip(&hz).skip(6) {
        assert!(
            (a - b).abs() < 1e-9 * b,
            "--json prints {a}, the file holds {b}"
        );
    }
    let mass = 7850.0 * 0.2 * 0.1 * 0.1;
    let ux = body
        .modes
        .iter()
        .position(|m| matches!(m, ModeKind::Rigid { motion } if motion == "ux"))
        .expect("a rigid ux mode");
    // The column is the unit translation along x, mass-normalised: s on
    // every ux, 0 elsewhere; its generalised mass is s^2 m.
    let column = body.basis.col_as_slice(ux);
    let scale = column[0];
    assert!(body
        .dof_map
        .dofs()
        .iter()
        .zip(column)
        .all(|(d, v)| (*v - scale * (d.kind == DofKind::Ux) as u8 as f64).abs() < 1e-12 * scale));
    let m = body.mass[(ux, ux)] / (scale * scale);
    // measured 5.7e-16
    assert!((m - mass).abs() < 1e-14 * mass, "{m} vs {mass} kg");
    let (code, stdout, _) = flexbody(&["info", fixture("tet_beam", "sti").to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(
        stdout.contains("matrices only") && stdout.contains("need the mesh"),
        "{stdout}"
    );
    let (code, _, err) = flexbody(&[
        "reduce",
        deck.to_str().unwrap(),
        "--method",
        "guyan",
        "--interface",
        "NOPE",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("'NOPE' is neither a node set nor a node number"),
        "{err}"
    );
}

#[test]
fn a_bad_deck_names_its_line_and_exits_2() {
    let dir = std::env::temp_dir().join(format!("flexbody-baddeck-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(fixture("hex_beam", "inp")).unwrap();
    let bad = dir.join("bad.inp");
    // Element 1 refers to a node that is never defined.
    let line = text
        .lines()
        .position(|l| l.starts_with("*ELEMENT"))
        .unwrap()
        + 2;
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let fields: Vec<&str> = lines[line - 1].split(',').collect();
    lines[line - 1] = format!("{}, 99999,{}", fields[0], fields[2..].join(","));
    std::fs::write(&bad, lines.join("\n")).unwrap();
    let (code, _, err) = flexbody(&["modes", bad.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!("bad.inp:{line}:")) && err.contains("99999"),
        "{err}"
    );
    assert!(!err.contains("panicked"));
}

#[test]
fn solid_stresses_from_ritz_coordinates_equal_those_from_displacements() {
    let deck = load(&fixture("hex20_beam", "inp"), &MatrixFiles::default()).unwrap();
    let model = deck.model.as_ref().unwrap();
    // A uniaxial stress state u = (e x, -nu e y, -nu e z): sigma_xx = E e,
    // von Mises = E e, at every node.
    let Element::Solid(s) = &model.elements()[0] else {
        panic!("a solid")
    };
    let (e_mod, nu, strain) = (s.material.youngs_modulus, s.material.poisson_ratio, 1e-4);
    let u: Vec<f64> = deck
        .sub
        .dof_map
        .dofs()
        .iter()
        .map(|d| {
            let x = model.coords(d.node);
            match d.kind {
                DofKind::Ux => strain * x[0],
                DofKind::Uy => -nu * strain * x[1],
                _ => -nu * strain * x[2],
            }
        })
        .collect();
    let stresses = nodal_stresses(model, &u).unwrap();
    for (sigma, vm) in stresses.stress.iter().zip(stresses.von_mises()) {
        assert!(
            (sigma[0] - e_mod * strain).abs() < 1e-9 * e_mod * strain,
            "{sigma:?}"
        );
        assert!(sigma[1..].iter().all(|v| v.abs() < 1e-9 * e_mod * strain));
        assert!((vm - e_mod * strain).abs() < 1e-9 * e_mod * strain);
    }
    // Modal stress matrices: sigma = T_sigma q.
    let body = reduce(
        &deck.sub,
        &Reduction::new(Method::FreeResidual, 2, deck.interface(Some("1")).unwrap()),
    )
    .unwrap();
    let modal = ModalStress::new(model, &body).unwrap();
    let q: Vec<f64> = (0..body.r())
        .map(|k| (k as f64 * 0.37).sin() * 1e-5)
        .collect();
    let direct = nodal_stresses(model, &body.displacements(&q)).unwrap();
    let from_q = modal.stresses(&q);
    let scale = direct
        .stress
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    for (a, b) in direct.stress.iter().zip(&from_q.stress) {
        for c in 0..6 {
            assert!((a[c] - b[c]).abs() < 1e-9 * scale);
        }
    }
}

/// The modal stress matrices (all basis columns at once, the elements in
/// parallel) hold each basis column's nodal stresses bit for bit, also
/// where a kinematic coupling gives the face nodes' displacements.
#[test]
fn modal_stresses_are_the_nodal_stresses_of_each_basis_column() {
    let dir = tempfile::tempdir().unwrap();
    let coupled = dir.path().join("coupled.inp");
    std::fs::write(&coupled, coupled_deck("*KINEMATIC\n1, 6")).unwrap();
    for (path, point) in [(fixture("hex20_beam", "inp"), "1"), (coupled, "9001")] {
        let deck = load(&path, &MatrixFiles::default()).unwrap();
        let model = deck.model.as_ref().unwrap();
        let spec = Reduction::new(
            Method::FreeResidual,
            3,
            deck.interface(Some(point)).unwrap(),
        );
        let body = reduce(&deck.sub, &spec).unwrap();
        let modal = ModalStress::new(model, &body).unwrap();
        for j in 0..body.r() {
            let column: Vec<f64> = body.basis.col_as_slice(j).to_vec();
            let direct = nodal_stresses(model, &column).unwrap();
            assert_eq!(direct.nodes, modal.nodes);
            for (k, sigma) in direct.stress.iter().enumerate() {
                for (c, v) in sigma.iter().enumerate() {
                    assert_eq!(
                        v.to_bits(),
                        modal.matrices[k][(c, j)].to_bits(),
                        "{}: node {}, column {j}",
                        path.display(),
                        modal.nodes[k]
                    );
                }
            }
        }
    }
}

/// The hex beam deck with an interface point coupled to its x = 0 face.
pub(crate) fn coupled_deck(kind: &str) -> String {
    let text = std::fs::read_to_string(fixture("hex_beam", "inp")).unwrap();
    let step = text.find("*STEP").unwrap();
    format!(
        "{}*NODE\n9001, 0.0, 0.05, 0.05\n*NSET, NSET=FACE\n1, 27, 79, 105\n*SURFACE, NAME=SFACE, TYPE=NODE\nFACE\n*COUPLING, REF NODE=9001, SURFACE=SFACE, CONSTRAINT NAME=END\n{kind}\n{}",
        &text[..step],
        &text[step..]
    )
}

#[test]
fn deck_couplings_make_interface_points() {
    let dir = std::env::temp_dir().join(format!("flexbody-coupled-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (kind, dofs) in [
        ("*KINEMATIC\n1, 6", 84 - 12 + 6),
        ("*DISTRIBUTING\n1, 6", 84),
    ] {
        let path = dir.join("coupled.inp");
        std::fs::write(&path, coupled_deck(kind)).unwrap();
        let deck = load(&path, &MatrixFiles::default()).unwrap();
        assert_eq!(deck.sub.len(), dofs, "{kind}");
        // The point is a 6-DOF interface: a free-residual body on it alone.
        let body = reduce(
            &deck.sub,
            &Reduction::new(
                Method::FreeResidual,
                1,
                deck.interface(Some("9001")).unwrap(),
            ),
        )
        .unwrap();
        assert_eq!(body.r(), 6 + 6 + 1);
    }
    let path = dir.join("bad.inp");
    for (text, needle) in [
        (
            coupled_deck("*DISTRIBUTING")
                .replace("SURFACE=SFACE, CONSTRAINT", "SURFACE=NOPE, CONSTRAINT"),
            "surface 'NOPE'",
        ),
        (
            coupled_deck("").replace(
                "CONSTRAINT NAME=END\n",
                "CONSTRAINT NAME=END\n*MATERIAL, NAME=X\n",
            ),
            "without *KINEMATIC or *DISTRIBUTING",
        ),
        (
            coupled_deck("*KINEMATIC\n1, 2"),
            "only full rigid couplings",
        ),
    ] {
        std::fs::write(&path, text).unwrap();
        let e = load(&path, &MatrixFiles::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("bad.inp:") && e.contains(needle), "{e}");
    }
}
