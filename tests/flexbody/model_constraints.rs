//! Constraints in model files: a deck's `*EQUATION`, `*MPC` and `*TIE`
//! read through `mesh =`, and the file's own `[[equation]]`, `[[mpc]]`
//! and `[[tie]]`, each against the same constraint read by the deck
//! reader from CalculiX's keywords (the fixtures of
//! `scripts/calculix_fixtures.py`, whose frequencies
//! `calculix_constraints.rs` checks against ccx).
//!
//! Two models are the same when they have the same nodes (after ADJUST),
//! the same independent DOFs and the same lowest frequencies to 1e-10
//! (both eliminate the same DOFs by the same equations: measured 0, and
//! 9e-14 where a tie's master is the exterior of an element set).

use super::calculix::fixture_dir;
use super::support::fails_with;
use flexbody::fem::{assemble, Model};
use flexbody::input::{load, MatrixFiles};
use flexbody::reduce::modes::{eigenmodes, Wanted};
use std::path::{Path, PathBuf};

/// The deck of CalculiX fixture `name`.
fn fixture(name: &str) -> PathBuf {
    fixture_dir(name).join(format!("{name}.inp"))
}

/// The model of a deck or model file.
fn model(path: &Path) -> Model {
    load(path, &MatrixFiles::default())
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .model
        .expect("a mesh")
}

/// The lowest `n` frequencies (Hz) of a model.
fn frequencies(model: &Model, n: usize) -> Vec<f64> {
    let s = assemble(model).unwrap();
    eigenmodes(&s.stiffness, &s.mass, Wanted::Lowest(n))
        .unwrap()
        .frequencies_hz()
}

/// `a` and `b` are the same model: nodes (positions to 1e-12 m: a tie's
/// ADJUST moves a slave node by round-off, differently when it projects
/// onto another face at an edge), independent DOFs and the lowest ten
/// frequencies to 1e-10 relative.
fn assert_same_model(a: &Model, b: &Model, what: &str) {
    assert_eq!(a.nodes().len(), b.nodes().len(), "{what}: nodes");
    for (p, q) in a.nodes().iter().zip(b.nodes()) {
        let apart = (0..3)
            .map(|k| (p.coords[k] - q.coords[k]).abs())
            .fold(0.0, f64::max);
        assert!(p.id == q.id && apart <= 1e-12, "{what}: {p:?} vs {q:?}");
    }
    assert_eq!(a.dof_map().dofs(), b.dof_map().dofs(), "{what}: DOFs");
    let (fa, fb) = (frequencies(a, 10), frequencies(b, 10));
    let worst = fa
        .iter()
        .zip(&fb)
        .map(|(x, y)| (x - y).abs() / y)
        .fold(0.0, f64::max);
    eprintln!(
        "{what}: {} DOFs, frequencies agree to {worst:.1e}",
        a.dof_map().len()
    );
    assert!(worst <= 1e-10, "{what}: {fa:?} vs {fb:?}");
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// A TOML string of a path.
fn quoted(path: &Path) -> String {
    format!("{:?}", path.to_str().unwrap())
}

/// A deck's `*EQUATION`s, `*MPC`s and `*TIE` are part of its model: read
/// through a model file's `mesh =` it has the DOFs and frequencies of the
/// deck read alone (they were once dropped there, leaving the constraint
/// DOFs free).
#[test]
fn a_deck_keeps_its_equations_mpcs_and_ties_through_a_model_file() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["equation_bar", "mpc_bar", "tie_blocks"] {
        let deck = fixture(name);
        let file = write(
            dir.path(),
            &format!("{name}.toml"),
            &format!("mesh = {}\n", quoted(&deck)),
        );
        let (a, b) = (model(&deck), model(&file));
        assert!(!a.equations().is_empty(), "{name}");
        assert_eq!(a.equations(), b.equations(), "{name}");
        assert_same_model(&a, &b, name);
    }
}

/// The text of fixture `name` without the lines from `from` up to (not
/// including) the next line that starts with `to`.
fn without(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(fixture(name)).unwrap();
    let start = text.find(from).unwrap_or_else(|| panic!("{name}: {from}"));
    let end = start
        + text[start..]
            .find(to)
            .unwrap_or_else(|| panic!("{name}: {to}"));
    format!("{}{}", &text[..start], &text[end..])
}

/// A model file in `dir`: `mesh = "deck"` (the deck written beside it)
/// and `tables`.
fn model_file(dir: &Path, deck_text: &str, tables: &str) -> PathBuf {
    write(dir, "bare.inp", deck_text);
    write(dir, "m.toml", &format!("mesh = \"bare.inp\"\n{tables}"))
}

/// `[[equation]]` is `*EQUATION`: the equation bar's four equations in a
/// model file give the model of the fixture's deck.
#[test]
fn equation_tables_are_the_deck_equations() {
    let dir = tempfile::tempdir().unwrap();
    // The deck's cards, for comparison:
    //   39, 3, 1.0, 13, 3, -1.0     91, 3, 1.0, 13, 3, -1.0
    //   117, 3, 1.0, 13, 3, -1.0    39, 1, 2.0, 91, 2, -1.0, 117, 1, 0.5
    let file = model_file(
        dir.path(),
        &without("equation_bar", "*EQUATION", "*STEP"),
        r#"
[[equation]]
name = "lid 39"
terms = [{ node = 39, dof = "uz", coefficient = 1.0 }, { node = 13, dof = "uz", coefficient = -1.0 }]

[[equation]]
terms = [{ node = 91, dof = "uz", coefficient = 1.0 }, { node = 13, dof = "uz", coefficient = -1.0 }]

[[equation]]
terms = [{ node = 117, dof = "uz", coefficient = 1.0 }, { node = 13, dof = "uz", coefficient = -1.0 }]

[[equation]]
name = "skew"
terms = [
  { node = 39, dof = "ux", coefficient = 2.0 },
  { node = 91, dof = "uy", coefficient = -1.0 },
  { node = 117, dof = "ux", coefficient = 0.5 },
]
"#,
    );
    let (deck, file) = (model(&fixture("equation_bar")), model(&file));
    assert_eq!(file.equations().len(), 4);
    assert_same_model(&deck, &file, "[[equation]]");
}

/// `[[mpc]]` is `*MPC`: the PLANE, STRAIGHT and BEAM of the MPC bar.
#[test]
fn mpc_tables_are_the_deck_mpcs() {
    let dir = tempfile::tempdir().unwrap();
    let mut bare = std::fs::read_to_string(fixture("mpc_bar")).unwrap();
    for card in [
        "*MPC\nPLANE, 13, 39, 91, 117\n",
        "*MPC\nSTRAIGHT, 3, 13, 7, 9\n",
        "*MPC\nBEAM, 89, 31\n",
    ] {
        assert!(bare.contains(card), "{card}");
        bare = bare.replacen(card, "", 1);
    }
    let file = model_file(
        dir.path(),
        &bare,
        r#"
[[mpc]]                    # nodes 13, 39, 91 span the plane, 117 stays in it
kind = "plane"
nodes = [13, 39, 91, 117]

[[mpc]]                    # nodes 3, 13 span the line, 7 and 9 stay on it
kind = "straight"
nodes = [3, 13, 7, 9]

[[mpc]]                    # nodes 89 and 31 keep their distance
name = "strut"
kind = "beam"
nodes = [89, 31]
"#,
    );
    let (deck, file) = (model(&fixture("mpc_bar")), model(&file));
    assert_eq!(deck.equations().len(), file.equations().len());
    assert_same_model(&deck, &file, "[[mpc]]");
}

/// The tie fixture's deck without its `*TIE`, the slave block moved by
/// `gap` along x (away from the master block), and the nodes of the slave
/// block's face at x = 0.3 + gap: the slave nodes.
fn tie_blocks_untied(gap: f64) -> (String, Vec<u64>) {
    let text = without("tie_blocks", "*TIE", "*STEP");
    let mut slaves = Vec::new();
    let mut out = String::new();
    for line in text.lines() {
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let node = match fields.as_slice() {
            [id, x, y, z] if !line.starts_with('*') => id
                .parse::<u64>()
                .ok()
                .zip(x.parse::<f64>().ok())
                .map(|(id, x)| (id, x, y, z)),
            _ => None,
        };
        match node {
            // The slave block's nodes are numbered from 10001.
            Some((id, x, y, z)) if id > 10_000 => {
                if x == 0.3 {
                    slaves.push(id);
                }
                out.push_str(&format!("{id}, {}, {y}, {z}\n", x + gap));
            }
            _ => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    assert_eq!(slaves.len(), 16, "the slave face: 3 x 3 elements");
    (out, slaves)
}

/// `[[tie]]` is `*TIE`: the slave block's face tied to the master block's
/// face `MASTER` (an element surface of the deck), or to the exterior
/// faces of the master block's last column of elements.
#[test]
fn tie_tables_are_the_deck_tie() {
    let dir = tempfile::tempdir().unwrap();
    let (bare, slaves) = tie_blocks_untied(0.0);
    let deck = model(&fixture("tie_blocks"));
    for master in [
        r#"master = "MASTER""#,
        r#"master_elements = "MASTERELEMENTS""#,
    ] {
        let file = model_file(
            dir.path(),
            &bare,
            &format!(
                "\n[sets]\ninterface = {slaves:?}\n\n[[tie]]\nname = \"joint\"\nset = \"interface\"\n{master}\n"
            ),
        );
        assert_same_model(&deck, &model(&file), master);
    }
}

/// A tie moves its slave nodes onto the master surface (ADJUST, the
/// default, as in CalculiX) across a gap within the tolerance: the deck's
/// `*TIE` read through `mesh =` keeps the moved nodes, and `[[tie]]`
/// moves them the same way; `adjust = false` leaves them where they are.
#[test]
fn a_tie_moves_its_slave_nodes_across_a_gap_as_the_deck_does() {
    let dir = tempfile::tempdir().unwrap();
    let gap = 4e-4; // within the default tolerance: 2.5 % of the face size
    let (bare, slaves) = tie_blocks_untied(gap);
    let tie = "*TIE, NAME=JOINT\nSLAVE, MASTER\n*STEP";
    let with_tie = write(dir.path(), "tied.inp", &bare.replacen("*STEP", tie, 1));
    let deck = model(&with_tie);
    for s in &slaves {
        let x = deck.coords(*s)[0];
        assert!(
            (x - 0.3).abs() <= 1e-12,
            "node {s} at x = {x}, not on the master face"
        );
    }
    let through = write(dir.path(), "tied.toml", "mesh = \"tied.inp\"\n");
    assert_same_model(&deck, &model(&through), "*TIE through mesh =");

    let tables = format!("\n[[tie]]\nname = \"joint\"\nnodes = {slaves:?}\nmaster = \"master\"\n");
    let file = model_file(dir.path(), &bare, &tables);
    assert_same_model(&deck, &model(&file), "[[tie]] across a gap");

    let kept = model_file(dir.path(), &bare, &format!("{tables}adjust = false\n"));
    let kept = model(&kept);
    for s in &slaves {
        assert_eq!(kept.coords(*s)[0], 0.3 + gap, "node {s} stays");
    }
}

/// The line of the first `marker` in `text`.
fn line_of(text: &str, marker: &str) -> usize {
    let at = text.find(marker).unwrap_or_else(|| panic!("{marker}"));
    text[..at].matches('\n').count() + 1
}

/// `info` of a model file of `deck_text` and `tables` exits with code 2,
/// naming `m.toml` at the line of `marker` and each of `needles`.
fn refused(deck_text: &str, tables: &str, marker: &str, needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let file = model_file(dir.path(), deck_text, tables);
    let text = std::fs::read_to_string(&file).unwrap();
    let at = format!("m.toml:{}:", line_of(&text, marker));
    let mut all = vec![at.as_str()];
    all.extend(needles);
    fails_with(&["info", file.to_str().unwrap()], &all);
}

/// Bad constraints are errors with exit code 2 naming the file, the line,
/// the entry and the node or DOF.
#[test]
fn bad_equations_and_mpcs_are_named_with_their_line() {
    let bar = without("equation_bar", "*EQUATION", "*STEP");
    let term = |node: u64, dof: &str, c: f64| {
        format!("{{ node = {node}, dof = \"{dof}\", coefficient = {c} }}")
    };
    // A node the model does not have.
    refused(
        &bar,
        &format!(
            "[[equation]]\nname = \"e\"\nterms = [\n  {},\n  {},\n]\n",
            term(39, "uz", 1.0),
            term(999, "uz", -1.0)
        ),
        "{ node = 999",
        &["[[equation]] 'e' refers to node 999, which does not exist"],
    );
    // A rotation of a solid node: no element gives it.
    refused(
        &bar,
        &format!(
            "\n[[equation]]\nterms = [{}, {}]\n",
            term(39, "rx", 1.0),
            term(13, "uz", -1.0)
        ),
        "[[equation]]",
        &[
            "[[equation]] number 1",
            "node 39 rx",
            "not a DOF of the model",
        ],
    );
    // The same dependent DOF twice: over-constrained, at the second.
    let one = format!(
        "terms = [{}, {}]\n",
        term(39, "uz", 1.0),
        term(13, "uz", -1.0)
    );
    let two = format!(
        "terms = [{}, {}]\n",
        term(39, "uz", 1.0),
        term(91, "uz", -1.0)
    );
    refused(
        &bar,
        &format!("\n[[equation]]\n{one}\n[[equation]]\nname = \"again\"\n{two}"),
        "[[equation]]\nname = \"again\"",
        &["[[equation]] 'again'", "node 39 uz", "over-constrained"],
    );
    // A misspelt key and a misspelt kind, with the nearest spelling.
    refused(
        &bar,
        "\n[[equation]]\nterms = [{ node = 39, dof = \"uz\", coeficient = 1.0 }]\n",
        "coeficient",
        &["unknown key `coeficient`", "did you mean `coefficient`?"],
    );
    refused(
        &bar,
        "\n[[mpc]]\nkind = \"plain\"\nnodes = [13, 39, 91, 117]\n",
        "\"plain\"",
        &[
            "unknown value `plain` for `kind` in [[mpc]]",
            "did you mean `plane`?",
        ],
    );
    // An MPC on a node the model does not have, and one that is degenerate.
    refused(
        &bar,
        "\n[[mpc]]\nkind = \"beam\"\nnodes = [89, 8900]\n",
        "[[mpc]]",
        &["[[mpc]] number 1 refers to node 8900, which does not exist"],
    );
    refused(
        &bar,
        "\n[[mpc]]\nkind = \"plane\"\nnodes = [1, 3, 5, 13]\n",
        "[[mpc]]",
        &["[[mpc]] number 1", "collinear"],
    );
}

/// Bad ties: a slave node off the master surface, an unknown node set,
/// master surface or element set (with the nearest name), a misspelt key.
#[test]
fn bad_ties_are_named_with_their_line() {
    let (bare, slaves) = tie_blocks_untied(0.0);
    let tie = |lines: &str| {
        format!("\n[sets]\ninterface = {slaves:?}\n\n[[tie]]\nname = \"joint\"\n{lines}")
    };
    // Node 1 is 0.3 m from the master face.
    refused(
        &bare,
        &tie("nodes = [1]\nmaster = \"MASTER\"\n"),
        "[[tie]]",
        &[
            "tie 'joint'",
            "no master face within the position tolerance",
            "node(s) 1",
        ],
    );
    refused(
        &bare,
        &tie("set = \"interfce\"\nmaster = \"MASTER\"\n"),
        "[[tie]]",
        &["node set 'interfce' does not exist; did you mean 'interface'?"],
    );
    refused(
        &bare,
        &tie("set = \"interface\"\nmaster = \"MASTR\"\n"),
        "[[tie]]",
        &[
            "master surface 'MASTR' is not an element surface of the deck",
            "did you mean 'MASTER'?",
        ],
    );
    refused(
        &bare,
        &tie("set = \"interface\"\nmaster_elements = \"MASTERELEMENT\"\n"),
        "[[tie]]",
        &[
            "element set 'MASTERELEMENT' is not an element set of the deck",
            "did you mean 'MASTERELEMENTS'?",
        ],
    );
    refused(
        &bare,
        &tie("set = \"interface\"\nmaster = \"MASTER\"\ntolerence = 1e-3\n"),
        "tolerence",
        &[
            "unknown key `tolerence` in [[tie]] 'joint'",
            "did you mean `tolerance`?",
        ],
    );
}
