//! Deck constraints beyond CalculiX's fixtures: tied `*CONTACT PAIR`s (a
//! tie by another name) and `*TRANSFORM` (local DOF directions), with the
//! errors that refuse what they cannot mean.
//!
//! CalculiX itself only activates contact in a nonlinear static step before
//! a perturbation frequency step, where its penalty springs (stiffness K of
//! `*SURFACE BEHAVIOR`) approach the exact tie flexbody builds; the tie
//! itself is checked against CalculiX in `calculix_constraints.rs`.

use super::calculix::fixture_dir;
use flexbody::fem::{assemble, Dof, DofKind};
use flexbody::io::deck::{parse_deck, Deck, DeckOptions};
use std::path::Path;

/// The tied blocks of the CalculiX fixtures (a coarse clamped bar and a
/// finer block on its far face), steps cut off, with the `*TIE` replaced
/// by `joint`.
fn blocks(joint: &str) -> String {
    let text = std::fs::read_to_string(fixture_dir("tie_blocks").join("tie_blocks.inp")).unwrap();
    let model = &text[..text.find("*STEP").unwrap()];
    let tie = "*TIE, NAME=JOINT\nSLAVE, MASTER\n";
    assert!(model.contains(tie));
    model.replace(tie, joint)
}

fn read(text: &str) -> Result<Deck, String> {
    parse_deck(Path::new("blocks.inp"), text, &DeckOptions::default()).map_err(|e| e.to_string())
}

/// 1-based line of the first line of `text` that starts with `start`.
fn line_of(text: &str, start: &str) -> usize {
    text.lines().position(|l| l.starts_with(start)).unwrap() + 1
}

const TIED_CONTACT: &str = "*CONTACT PAIR, INTERACTION=GLUE, TYPE=SURFACE TO SURFACE
SLAVE, MASTER
*SURFACE INTERACTION, NAME=GLUE
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=TIED
1.0e14
*FRICTION
0.3, 1.0e14
";

#[test]
fn a_tied_contact_pair_is_the_tie_of_its_surfaces() {
    let tie = read(&blocks("*TIE, NAME=JOINT\nSLAVE, MASTER\n")).unwrap();
    let contact = read(&blocks(TIED_CONTACT)).unwrap();
    // The same independent DOFs (the slave translations eliminated) ...
    assert_eq!(tie.model.dof_map().dofs(), contact.model.dof_map().dofs());
    assert!(contact.model.dof_map().len() < contact.model.nodes().len() * 3 - 12);
    // ... and the same K and M, entry by entry.
    let (a, b) = (
        assemble(&tie.model).unwrap(),
        assemble(&contact.model).unwrap(),
    );
    for (what, x, y) in [("K", &a.stiffness, &b.stiffness), ("M", &a.mass, &b.mass)] {
        let (x, y) = (x.to_dense(), y.to_dense());
        let scale = x.norm_max();
        let diff = (&x - &y).norm_max();
        assert!(diff <= 1e-15 * scale, "{what}: {diff:e} of {scale:e}");
    }
}

#[test]
fn contact_that_does_not_tie_is_refused_with_its_line() {
    for behavior in [
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n1.0e12, 0.0, 1.0e-3\n",
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD\n",
        "", // no behaviour: hard contact
    ] {
        let joint = format!(
            "*CONTACT PAIR, INTERACTION=SI1, TYPE=NODE TO SURFACE\nSLAVE, MASTER\n\
             *SURFACE INTERACTION, NAME=SI1\n{behavior}"
        );
        let text = blocks(&joint);
        let err = read(&text).unwrap_err();
        let line = line_of(&text, "SLAVE, MASTER");
        assert!(
            err.contains(&format!("blocks.inp:{line}")) && err.contains("nonlinear contact"),
            "{err}"
        );
    }
    let text = blocks("*CONTACT PAIR, INTERACTION=NONE\nSLAVE, MASTER\n");
    let err = read(&text).unwrap_err();
    assert!(
        err.contains("surface interaction 'NONE' is not defined"),
        "{err}"
    );
    // General contact stays refused.
    let err = read(&blocks("*CONTACT\n")).unwrap_err();
    assert!(err.contains("*CONTACT is not supported"), "{err}");
}

/// A node of the bar's far end and the node set TIP of that face.
fn tip(text: &str) -> (u64, Vec<u64>) {
    let deck = read(text).unwrap();
    let mut face: Vec<u64> = deck
        .model
        .nodes()
        .iter()
        .filter(|n| (n.coords[0] - 0.3).abs() < 1e-12 && n.id < 10001)
        .map(|n| n.id)
        .collect();
    face.sort();
    (face[0], face)
}

#[test]
fn a_rotated_boundary_condition_holds_the_node_along_the_local_axis_only() {
    let base = blocks(TIED_CONTACT);
    let (node, _) = tip(&base);
    // Local x along (1, 1, 0): ux + uy = 0, one equation; uz stays free.
    let text = format!(
        "{base}*NSET, NSET=TURNED\n{node}\n*TRANSFORM, NSET=TURNED\n1.0, 1.0, 0.0, 0.0, 0.0, 1.0\n\
         *BOUNDARY\nTURNED, 1\n"
    );
    let plain = read(&base).unwrap();
    let turned = read(&text).unwrap();
    assert_eq!(
        turned.model.dof_map().len() + 1,
        plain.model.dof_map().len()
    );
    let u: Vec<f64> = (0..turned.model.dof_map().len())
        .map(|i| (i as f64 * 0.37).sin())
        .collect();
    let d =
        [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|k| turned.model.value(Dof::new(node, k), &u));
    assert!((d[0] + d[1]).abs() < 1e-15 && d[0].abs() > 1e-3, "{d:?}");
    // Local rotations of a solid node are ignored, as CalculiX does, with
    // the warning of the global ones.
    let text = format!(
        "{base}*NSET, NSET=TURNED\n{node}\n*TRANSFORM, NSET=TURNED\n1.0, 1.0, 0.0, 0.0, 0.0, 1.0\n\
         *BOUNDARY\nTURNED, 4, 6\n"
    );
    let deck = read(&text).unwrap();
    assert_eq!(deck.model.dof_map().len(), plain.model.dof_map().len());
    assert!(
        deck.warnings
            .iter()
            .any(|w| w.contains("no element gives the node that DOF")),
        "{:?}",
        deck.warnings
    );
}

#[test]
fn bad_local_systems_name_their_line_and_node() {
    let base = blocks(TIED_CONTACT);
    let (node, face) = tip(&base);
    let set = format!(
        "*NSET, NSET=TIP\n{}\n",
        face.iter()
            .map(u64::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    );
    // A cylindrical system whose axis runs through a node of the set: no
    // radial direction there.
    let x = read(&base).unwrap().model.coords(node);
    let text = format!(
        "{base}{set}*TRANSFORM, NSET=TIP, TYPE=C\n{}, {}, {}, {}, {}, {}\n*BOUNDARY\nTIP, 1\n",
        x[0] - 1.0,
        x[1],
        x[2],
        x[0] + 1.0,
        x[1],
        x[2]
    );
    let err = read(&text).unwrap_err();
    let line = line_of(&text, "*TRANSFORM");
    assert!(
        err.contains(&format!("blocks.inp:{line}"))
            && err.contains(&format!("node {node}"))
            && err.contains("lies on the axis"),
        "{err}"
    );
    for (card, expected) in [
        (
            "*TRANSFORM, NSET=NOSUCH\n1, 0, 0, 0, 1, 0\n",
            "node set 'NOSUCH' is not defined",
        ),
        ("*TRANSFORM, NSET=TIP, TYPE=S\n1, 0, 0, 0, 1, 0\n", "TYPE=S"),
        ("*TRANSFORM, NSET=TIP\n1, 0, 0, 2, 0, 0\n", "parallel"),
        ("*TRANSFORM, NSET=TIP\n1, 0, 0\n", "coordinate 4 of a, b"),
    ] {
        let text = format!("{base}{set}{card}");
        let err = read(&text).unwrap_err();
        let line = line_of(&text, "*TRANSFORM");
        assert!(
            err.contains(expected)
                && (err.contains(&format!("blocks.inp:{line}"))
                    || err.contains(&format!("blocks.inp:{}", line + 1))),
            "{card}: {err}"
        );
    }
}
