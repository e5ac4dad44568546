//! S3/S4/S8 shells and their `*SHELL SECTION`s.

use super::*;
use flexbody_fem::element::{Shell, ShellKind};

/// Two S4 and one S3 in the x-y plane, 3 mm steel, the nodes on the top
/// face (OFFSET=SPOS) for the triangle's set.
const SHELLS: &str = "\
*NODE
1, 0., 0., 0.
2, 1., 0., 0.
3, 2., 0., 0.
4, 0., 1., 0.
5, 1., 1., 0.
6, 2., 1., 0.
7, 3., 0.5, 0.
*ELEMENT, TYPE=S4, ELSET=QUADS
1, 1, 2, 5, 4
2, 2, 3, 6, 5
*ELEMENT, TYPE=S3, ELSET=TRIS
3, 3, 7, 6
*MATERIAL, NAME=STEEL
*ELASTIC
2.1e11, 0.3
*DENSITY
7850.
*SHELL SECTION, ELSET=QUADS, MATERIAL=STEEL
0.003
*SHELL SECTION, ELSET=TRIS, MATERIAL=STEEL, OFFSET=SPOS
0.003, 5
";

#[test]
fn s4_and_s3_shells_with_their_sections() {
    let deck = parse(SHELLS).unwrap();
    let shells: Vec<&Shell> = deck
        .model
        .elements()
        .iter()
        .map(|e| match e {
            Element::Shell(s) => s,
            other => panic!("not a shell: {other:?}"),
        })
        .collect();
    assert_eq!(shells.len(), 3);
    assert_eq!(shells[0].kind, ShellKind::S4);
    assert_eq!(shells[2].kind, ShellKind::S3);
    assert!(shells.iter().all(|s| s.thickness == 0.003));
    assert_eq!([shells[0].offset, shells[2].offset], [0.0, 0.5]);
    assert_eq!(shells[0].material.youngs_modulus, 2.1e11);
    // Six DOFs on each of the seven nodes.
    assert_eq!(deck.model.dof_map().len(), 42);
    assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
}

#[test]
fn s8_shells_read_with_their_eight_nodes_and_s8r_as_s8() {
    // The two quadrilaterals as one S8 over both (mid-side nodes 8..11)
    // and one S8R (a curved cell beside it).
    let text = SHELLS
        .replace(
            "7, 3., 0.5, 0.\n",
            "7, 3., 0.5, 0.\n8, 1., 0., 0.\n9, 2., 0.5, 0.\n10, 1., 1., 0.\n11, 0., 0.5, 0.\n\
             12, 3., 0., 0.\n13, 4., 0., 0.\n14, 4., 1., 0.\n15, 3.5, 0., 0.01\n\
             16, 4., 0.5, 0.\n17, 3.5, 1., 0.\n19, 3., 1., 0.\n",
        )
        .replace(
            "*ELEMENT, TYPE=S4, ELSET=QUADS\n1, 1, 2, 5, 4\n2, 2, 3, 6, 5\n",
            "*ELEMENT, TYPE=S8, ELSET=QUADS\n1, 1, 3, 6, 4, 8, 9, 10, 11\n\
             *ELEMENT, TYPE=S8R, ELSET=QUADS\n2, 12, 13, 14, 19, 15, 16, 17, 7\n",
        )
        .replace("*ELEMENT, TYPE=S3, ELSET=TRIS\n3, 3, 7, 6\n", "")
        .replace(
            "*SHELL SECTION, ELSET=TRIS, MATERIAL=STEEL, OFFSET=SPOS\n0.003, 5\n",
            "",
        );
    let deck = parse(&text).unwrap();
    let kinds: Vec<(ShellKind, usize)> = deck
        .model
        .elements()
        .iter()
        .map(|e| match e {
            Element::Shell(s) => (s.kind, s.nodes.len()),
            other => panic!("not a shell: {other:?}"),
        })
        .collect();
    assert_eq!(kinds, [(ShellKind::S8, 8), (ShellKind::S8, 8)]);
    assert!(
        deck.warnings
            .iter()
            .any(|w| w.contains("S8R elements are read as S8")),
        "{:?}",
        deck.warnings
    );
}

#[test]
fn meshers_reduced_shell_names_read_as_the_mitc_shells() {
    let deck = parse(
        &SHELLS
            .replace("TYPE=S4,", "TYPE=S4R,")
            .replace("TYPE=S3,", "TYPE=S3R,"),
    )
    .unwrap();
    assert!(deck
        .model
        .elements()
        .iter()
        .all(|e| matches!(e, Element::Shell(_))));
    let notes = deck.warnings.join("\n");
    assert!(notes.contains("S4R") && notes.contains("S3R"), "{notes}");
}

#[test]
fn bad_shell_sections_name_the_line() {
    assert_error(
        &SHELLS.replace(
            "*SHELL SECTION, ELSET=QUADS, MATERIAL=STEEL\n0.003",
            "*SHELL SECTION, ELSET=QUADS, MATERIAL=STEEL\n0.",
        ),
        "0.",
        &["*SHELL SECTION", "thickness must be positive"],
    );
    assert_error(
        &SHELLS.replace(
            "*SHELL SECTION, ELSET=QUADS, MATERIAL=STEEL\n0.003",
            "*SHELL SECTION, ELSET=QUADS, MATERIAL=STEEL\n-0.003",
        ),
        "-0.003",
        &["thickness must be positive", "-0.003"],
    );
    assert_error(
        &SHELLS.replace(
            "ELSET=QUADS, MATERIAL=STEEL",
            "ELSET=QUADS, MATERIAL=STEEL, COMPOSITE",
        ),
        "COMPOSITE",
        &["composite"],
    );
    assert_error(
        &SHELLS.replace(
            "ELSET=QUADS, MATERIAL=STEEL",
            "ELSET=QUADS, MATERIAL=STEEL, NODAL THICKNESS",
        ),
        "NODAL THICKNESS",
        &["nodal thickness"],
    );
    assert_error(
        &SHELLS.replace(
            "ELSET=QUADS, MATERIAL=STEEL\n0.003\n",
            "ELSET=QUADS, MATERIAL=STEEL\n0.003\n0.002\n",
        ),
        "0.002",
        &["composite"],
    );
    assert_error(
        &SHELLS.replace("OFFSET=SPOS", "OFFSET=TOP"),
        "OFFSET=TOP",
        &["OFFSET=TOP"],
    );
    // A shell without a section, and a solid section on shells.
    assert_error(
        &SHELLS.replace(
            "*SHELL SECTION, ELSET=TRIS, MATERIAL=STEEL, OFFSET=SPOS\n0.003, 5\n",
            "",
        ),
        "3, 3, 7, 6",
        &["*SHELL SECTION"],
    );
}

#[test]
fn a_warped_or_inverted_shell_names_the_element() {
    // Node 5 lifted by 0.8 m: element 1 warps beyond the limit.
    let warped = SHELLS.replace("5, 1., 1., 0.", "5, 1., 1., 0.8");
    let err = parse(&warped).unwrap_err().to_string();
    assert!(err.contains("element 1") && err.contains("warped"), "{err}");
    // Node 5 pulled into element 1 past its diagonal: inverted at node 5.
    let inverted = SHELLS.replace("5, 1., 1., 0.", "5, 0.1, 0.1, 0.");
    let err = parse(&inverted).unwrap_err().to_string();
    assert!(err.contains("element 1") && err.contains("node 5"), "{err}");
}
