//! Model files that read a deck, frames of beam lines meeting at joints,
//! and point masses on coupling reference nodes.

use crate::decks::coupled_deck;
use crate::support::{fails_with, flexbody, run_ok, stderr, stdout_json};
use std::path::{Path, PathBuf};

/// `flexbody info` of `model`: its standard output and its notes and
/// warnings.
fn info(model: &Path) -> (String, Vec<String>) {
    let o = run_ok(&["info", model.to_str().unwrap()]);
    let warnings = stderr(&o)
        .lines()
        .filter(|l| l.starts_with("warning:") || l.starts_with("note:"))
        .map(str::to_owned)
        .collect();
    (String::from_utf8_lossy(&o.stdout).into_owned(), warnings)
}

/// The number after `key` on the line of `info` output that starts with it.
fn info_number(out: &str, key: &str) -> f64 {
    let line = out.lines().find(|l| l.starts_with(key)).expect(key);
    line[key.len()..]
        .trim_start_matches([':', ' '])
        .split([',', ' '])
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// The mass along x, y and z that `info` prints (`t^T M t`).
fn info_masses(out: &str) -> Vec<f64> {
    let key = "mass along x, y, z (kg), free DOFs: ";
    let line = out.lines().find(|l| l.starts_with(key)).expect(key);
    line[key.len()..]
        .split(", ")
        .map(|x| x.parse().unwrap())
        .collect()
}

/// The lowest `count` natural frequencies (Hz) of `model`.
fn frequencies(model: &Path, count: usize) -> Vec<f64> {
    let n = count.to_string();
    let o = run_ok(&["modes", model.to_str().unwrap(), "--count", &n, "--json"]);
    serde_json::from_value(stdout_json(&o)["frequencies_hz"].clone()).unwrap()
}

/// Equal to round-off, relative to the largest, for every entry.
fn assert_close(a: &[f64], b: &[f64], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    let scale = a.iter().chain(b).fold(0.0_f64, |m, x| m.max(x.abs()));
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= 1e-8 * scale, "{what}: {a:?} vs {b:?}");
    }
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A deck with a `*COUPLING` read through a model file: the same DOFs, the
/// same frequencies and the same warnings as the deck itself, and the
/// coupling's reference node carries a spring of the model file.
#[test]
fn a_model_file_keeps_the_couplings_and_warnings_of_its_deck() {
    let dir = tempfile::tempdir().unwrap();
    let deck = write(dir.path(), "coupled.inp", &coupled_deck("*KINEMATIC\n1, 6"));
    let file = write(dir.path(), "coupled.toml", "mesh = \"coupled.inp\"\n");
    let (deck_out, deck_warnings) = info(&deck);
    let (file_out, file_warnings) = info(&file);
    let dofs = info_number(&deck_out, "DOFs");
    assert_eq!(
        dofs,
        (84 - 12 + 6) as f64,
        "the coupling eliminates the face"
    );
    assert_eq!(info_number(&file_out, "DOFs"), dofs);
    assert!(!deck_warnings.is_empty(), "the deck's *STEPs are ignored");
    assert_eq!(file_warnings, deck_warnings);
    assert!(
        deck_warnings[0]
            .contains("coupled.inp: skipped, as they do not change the linear K, M or D: *STEP"),
        "{deck_warnings:?}"
    );
    assert_close(
        &frequencies(&file, 10),
        &frequencies(&deck, 10),
        "deck through a model file",
    );

    let spring = write(
        dir.path(),
        "spring.toml",
        "mesh = \"coupled.inp\"\n\n[[element]]\ntype = \"spring\"\nid = 9100\n\
         dof = { node = 9001, dof = \"uz\" }\nstiffness = 1.0e6\n",
    );
    let (spring_out, _) = info(&spring);
    assert_eq!(info_number(&spring_out, "DOFs"), dofs);
    // Held by the spring, the six rigid-body modes become five.
    let f = frequencies(&spring, 7);
    assert!(f[4].abs() < 1e-2 * f[5] && f[5] > 1.0, "{f:?}");
}

/// `*BOUNDARY` on a coupling's reference node holds those DOFs (the node
/// has six, though no element gives it any), in the deck and through a
/// model file.
#[test]
fn a_deck_fixes_dofs_of_a_coupling_reference_node() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        coupled_deck("*KINEMATIC\n1, 6").replacen("*STEP", "*BOUNDARY\n9001, 1, 3\n*STEP", 1);
    let deck = write(dir.path(), "held.inp", &text);
    let file = write(dir.path(), "held.toml", "mesh = \"held.inp\"\n");
    for path in [&deck, &file] {
        let (out, warnings) = info(path);
        assert_eq!(info_number(&out, "DOFs"), (84 - 12 + 6 - 3) as f64);
        assert!(
            !warnings.iter().any(|w| w.contains("BOUNDARY")),
            "{warnings:?}"
        );
    }
}

/// The header of a portal frame: steel, a 0.1 m square tube.
const FRAME: &str = r#"
[[material]]
name = "steel"
youngs_modulus = 2.1e11
density = 7850.0

[[section]]
name = "tube"
shape = "box"
width = 0.1
height = 0.1
wall = 0.005
"#;

/// A beam line of 4 elements with `ends` (keys) and more keys.
fn line(ends: &str) -> String {
    format!(
        "\n[[beam_line]]\nelement = \"beam\"\nelements = 4\nmaterial = \"steel\"\n\
         section = \"tube\"\norientation = [0.0, 1.0, 0.0]\n{ends}\n"
    )
}

/// The feet of the frame held: node `left` and node `right`.
fn feet(left: u64, right: u64) -> String {
    [left, right]
        .map(|n| {
            format!("\n[[boundary]]\nnode = {n}\ndofs = [\"ux\", \"uy\", \"uz\", \"rx\", \"ry\", \"rz\"]\n")
        })
        .concat()
}

/// The portal frame (columns 3 m, beam 4 m, 4 elements each) with every
/// node and element written out: the reference.
fn explicit_frame() -> String {
    let points: Vec<[f64; 3]> = (0..=4)
        .map(|i| [0.0, 0.0, 0.75 * i as f64])
        .chain((1..=4).map(|i| [i as f64, 0.0, 3.0]))
        .chain((1..=4).map(|i| [4.0, 0.0, 3.0 - 0.75 * i as f64]))
        .collect();
    let nodes: Vec<String> = points
        .iter()
        .enumerate()
        .map(|(i, p)| format!("[{}, {:?}, {:?}, {:?}]", 101 + i, p[0], p[1], p[2]))
        .collect();
    let elements: String = (0..12)
        .map(|i| {
            format!(
                "\n[[element]]\ntype = \"beam\"\nid = {}\nnodes = [{}, {}]\nmaterial = \"steel\"\n\
                 section = \"tube\"\norientation = [0.0, 1.0, 0.0]\n",
                i + 1,
                101 + i,
                102 + i
            )
        })
        .collect();
    format!(
        "nodes = [{}]\n{FRAME}{elements}{}",
        nodes.join(", "),
        feet(101, 113)
    )
}

/// Three beam lines meeting at the frame's corners share the corner nodes,
/// by position or by naming them; the frame has the nodes and frequencies
/// of the same frame written node by node. Two positions for one id stay
/// an error naming both.
#[test]
fn beam_lines_meeting_at_joints_share_the_joint_nodes() {
    let dir = tempfile::tempdir().unwrap();
    let reference = write(dir.path(), "explicit.toml", &explicit_frame());
    let by_position = format!(
        "{FRAME}{}{}{}{}",
        line("from = [0.0, 0.0, 0.0]\nto = [0.0, 0.0, 3.0]\nfirst_node = 1"),
        line("from = [0.0, 0.0, 3.0]\nto = [4.0, 0.0, 3.0]\nfirst_node = 5"),
        line("from = [4.0, 0.0, 3.0]\nto = [4.0, 0.0, 0.0]\nfirst_node = 20"),
        feet(1, 24)
    );
    let by_name = format!(
        "{FRAME}{}{}{}{}",
        line("from = [0.0, 0.0, 0.0]\nto = [0.0, 0.0, 3.0]\nfirst_node = 1"),
        line("start_node = 5\nto = [4.0, 0.0, 3.0]\nfirst_node = 10"),
        line("start_node = 14\nto = [4.0, 0.0, 0.0]\nfirst_node = 20"),
        feet(1, 24)
    );
    let want = frequencies(&reference, 6);
    let (out, _) = info(&reference);
    assert_eq!(info_number(&out, "nodes"), 13.0);
    for (name, text) in [("position.toml", by_position), ("named.toml", by_name)] {
        let path = write(dir.path(), name, &text);
        let (out, _) = info(&path);
        assert_eq!(info_number(&out, "nodes"), 13.0, "{name}");
        assert_eq!(info_number(&out, "DOFs"), 11.0 * 6.0, "{name}");
        assert_close(&frequencies(&path, 6), &want, name);
    }

    // Node 4 is the left column's, at z = 2.25 m; the beam puts its own
    // node 4 at x = 1 m.
    let conflict = write(
        dir.path(),
        "conflict.toml",
        &format!(
            "{FRAME}{}{}",
            line("from = [0.0, 0.0, 0.0]\nto = [0.0, 0.0, 3.0]\nfirst_node = 1"),
            line("from = [0.0, 0.0, 3.0]\nto = [4.0, 0.0, 3.0]\nfirst_node = 3"),
        ),
    );
    fails_with(
        &["info", conflict.to_str().unwrap()],
        &[
            "conflict.toml",
            "node 4 is defined twice",
            "[1.0, 0.0, 3.0]",
            "[0.0, 0.0, 2.25]",
        ],
    );
    let missing = write(
        dir.path(),
        "missing.toml",
        &format!(
            "{FRAME}{}",
            line("start_node = 77\nto = [4.0, 0.0, 3.0]\nfirst_node = 10")
        ),
    );
    fails_with(
        &["info", missing.to_str().unwrap()],
        &["missing.toml", "start_node = 77 does not exist"],
    );
}

/// A rigid spider with all nodes of a beam on a point at its middle, a
/// point mass `m` and a spring `k` (uz to ground) on the point: the
/// translational rigid-body mass is the beam's plus `m`, and the one
/// elastic mode has `omega = sqrt(k / (m_beam + m))`.
#[test]
fn a_point_mass_on_a_coupling_reference_node_adds_to_the_rigid_body() {
    let dir = tempfile::tempdir().unwrap();
    let (m, k) = (43.0, 2.0e5);
    let text = format!(
        "{FRAME}{}\n[[coupling]]\nname = \"spider\"\nkind = \"rigid\"\npoint = 100\n\
         set = \"beam\"\nposition = [0.0, 0.0, 1.5]\n\n\
         [[element]]\ntype = \"point-mass\"\nid = 100\nnode = 100\nmass = {m:?}\n\n\
         [[element]]\ntype = \"spring\"\nid = 101\ndof = {{ node = 100, dof = \"uz\" }}\n\
         stiffness = {k:?}\n",
        line("from = [0.0, 0.0, 0.0]\nto = [0.0, 0.0, 3.0]\nfirst_node = 1\nset = \"beam\"")
    );
    let path = write(dir.path(), "spider.toml", &text);
    let (out, _) = info(&path);
    assert_eq!(info_number(&out, "DOFs"), 6.0, "the point's DOFs only");
    // Box 0.1 m, wall 5 mm: A = 0.1^2 - 0.09^2; 3 m of steel.
    let beam = 7850.0 * (0.1 * 0.1 - 0.09 * 0.09) * 3.0;
    for mass in info_masses(&out) {
        assert!(
            (mass - (beam + m)).abs() < 1e-6 * mass,
            "{mass} vs {}",
            beam + m
        );
    }
    let f = frequencies(&path, 6);
    let want = (k / (beam + m)).sqrt() / (2.0 * std::f64::consts::PI);
    assert!((f[5] - want).abs() < 1e-8 * want, "{f:?}: {want}");
    assert!(f[..5].iter().all(|x| x.abs() < 1e-4 * want), "{f:?}");
}

/// A deck's MASS element on a `*COUPLING` reference node adds its mass to
/// the rigid-body mass, in the deck and through a model file.
#[test]
fn a_deck_mass_on_a_coupling_reference_node_is_carried() {
    let dir = tempfile::tempdir().unwrap();
    let plain = write(dir.path(), "plain.inp", &coupled_deck("*KINEMATIC\n1, 6"));
    let massed = coupled_deck("*KINEMATIC\n1, 6").replacen(
        "*STEP",
        "*ELEMENT, TYPE=MASS, ELSET=LUMP\n9100, 9001\n*MASS, ELSET=LUMP\n12.5\n*STEP",
        1,
    );
    let deck = write(dir.path(), "massed.inp", &massed);
    let file = write(dir.path(), "massed.toml", "mesh = \"massed.inp\"\n");
    let (out, _) = info(&plain);
    let structure = info_masses(&out);
    // The hex beam: 0.6 x 0.1 x 0.1 m of steel.
    let beam = 7850.0 * 0.6 * 0.1 * 0.1;
    assert!((structure[2] - beam).abs() < 1e-9 * beam, "{structure:?}");
    for path in [&deck, &file] {
        let o = flexbody(&["info", path.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        let (out, _) = info(path);
        for mass in info_masses(&out) {
            assert!((mass - (beam + 12.5)).abs() < 1e-9 * mass, "{mass}");
        }
    }
}

/// Every part of a deck's model survives a model file that reads it: the
/// nodes, elements, node sets, fixed DOFs, couplings and the DOF map.
#[test]
fn a_deck_read_by_a_model_file_is_the_deck_model() {
    use flexbody::input::{load, MatrixFiles};
    let dir = tempfile::tempdir().unwrap();
    let text = coupled_deck("*DISTRIBUTING\n1, 6").replacen(
        "*STEP",
        "*NSET, NSET=TIP\n13, 39\n*BOUNDARY\nTIP, 1, 3\n\
         *ELEMENT, TYPE=MASS, ELSET=LUMP\n9100, 9001\n*MASS, ELSET=LUMP\n2.0\n*STEP",
        1,
    );
    let deck = write(dir.path(), "part.inp", &text);
    let file = write(dir.path(), "part.toml", "mesh = \"part.inp\"\n");
    let a = load(&deck, &MatrixFiles::default()).unwrap();
    let b = load(&file, &MatrixFiles::default()).unwrap();
    let (a, b) = (a.model.unwrap(), b.model.unwrap());
    assert_eq!(a.nodes(), b.nodes());
    assert_eq!(a.elements(), b.elements());
    assert_eq!(a.node_sets(), b.node_sets());
    assert!(a.node_sets().contains_key("TIP"));
    assert_eq!(
        a.fixed_dofs().collect::<Vec<_>>(),
        b.fixed_dofs().collect::<Vec<_>>()
    );
    assert_eq!(a.fixed_dofs().count(), 6);
    assert_eq!(a.couplings(), b.couplings());
    assert_eq!(a.couplings().len(), 1);
    assert_eq!(a.rayleigh(), b.rayleigh());
    assert_eq!(a.dof_map().dofs(), b.dof_map().dofs());
}
