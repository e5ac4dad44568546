//! Solid elements: C3D8 bricks with sets and boundary conditions, C3D20
//! continuation lines, refused zero-volume and inverted solids.

use super::*;
use flexbody_fem::mesh::SolidBlock;

#[test]
fn c3d8_bricks_with_sets_and_boundary() {
    let deck = parse(BRICKS).unwrap();
    let model = &deck.model;
    assert_eq!(model.nodes().len(), 12);
    assert_eq!(model.elements().len(), 2);
    for e in model.elements() {
        let Element::Solid(s) = e else {
            panic!("not a solid: {e:?}")
        };
        assert_eq!(s.kind, SolidKind::C3D8);
        assert_eq!(s.material.youngs_modulus, 2.1e11);
        assert_eq!(s.material.density, 7850.0);
    }
    let sets = model.node_sets();
    assert_eq!(sets["BASE"], vec![1, 2, 3, 4]);
    assert_eq!(sets["TOP"], vec![9, 10, 11, 12]);
    assert_eq!(sets["ENDS"], vec![1, 2, 3, 4, 9, 10, 11, 12]);
    assert_eq!(deck.element_sets["LOWER"], vec![1]);
    assert_eq!(deck.element_sets["ALL"], vec![1, 2]);
    // Rotations 4-6 do not exist on solid nodes: dropped.
    let fixed: Vec<Dof> = model.fixed_dofs().copied().collect();
    let expected: Vec<Dof> = (1..=4)
        .flat_map(|n| [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|k| Dof::new(n, k)))
        .collect();
    assert_eq!(fixed, expected);
    assert_eq!(model.dof_map().len(), 12 * 3 - 12);
    assert_eq!(
        deck.skipped,
        vec![
            "*HEADING (line 1)".to_string(),
            format!("*STEP (line {})", line_of(BRICKS, "*STEP")),
            format!("*FREQUENCY (line {})", line_of(BRICKS, "*FREQUENCY")),
            format!("*NODE FILE (line {})", line_of(BRICKS, "*NODE FILE")),
            format!("*END STEP (line {})", line_of(BRICKS, "*END STEP")),
        ]
    );
    assert_eq!(
        deck.warnings,
        vec![format!(
            "*BOUNDARY (line {}): 12 fixed DOF(s) ignored because no element gives the node \
             that DOF (first: node 1 rx; solid elements have no rotations)",
            line_of(BRICKS, "BASE, 1, 6")
        )]
    );
}

/// Nodes of the 2 m cube as a C3D20 (a one-cell [`SolidBlock`], in
/// Abaqus order: corners, then the mid-side nodes of edges 1-2, 2-3, 3-4,
/// 4-1, 5-6, 6-7, 7-8, 8-5, 1-5, 2-6, 3-7, 4-8).
fn c3d20_nodes() -> String {
    let cube = SolidBlock {
        kind: SolidKind::C3D20,
        cells: [1, 1, 1],
        origin: [0.0; 3],
        size: [2.0; 3],
        corner_distortion: 0.0,
        edge_distortion: 0.0,
        seed: 1,
    }
    .mesh();
    let points: Vec<[f64; 3]> = cube.elements[0].iter().map(|&n| cube.coords[n]).collect();
    let mut s = String::from("*NODE\n");
    for (i, p) in points.iter().enumerate() {
        s += &format!("{}, {}, {}, {}\n", i + 1, p[0], p[1], p[2]);
    }
    s
}

#[test]
fn c3d20_element_lines_continue_after_a_trailing_comma() {
    let text = c3d20_nodes()
        + "*ELEMENT, TYPE=C3D20, ELSET=E\n\
           1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,\n\
           16, 17, 18, 19, 20\n\
           *ELEMENT, TYPE=C3D20R, ELSET=E\n\
           2, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10,\n\
           11, 12, 13, 14, 15,\n\
           16, 17, 18, 19, 20\n\
           *MATERIAL, NAME=AL\n*ELASTIC\n70e9, 0.33\n*DENSITY\n2700\n\
           *SOLID SECTION, ELSET=E, MATERIAL=AL\n1.\n";
    let deck = parse(&text).unwrap();
    let kinds: Vec<SolidKind> = deck
        .model
        .elements()
        .iter()
        .map(|e| match e {
            Element::Solid(s) => {
                assert_eq!(s.nodes, (1..=20).collect::<Vec<u64>>());
                s.kind
            }
            other => panic!("not a solid: {other:?}"),
        })
        .collect();
    assert_eq!(kinds, vec![SolidKind::C3D20, SolidKind::C3D20R]);
    assert_eq!(deck.model.dof_map().len(), 60);
}

#[test]
fn zero_volume_and_inverted_solids_are_refused_at_their_line() {
    // All eight nodes in the plane z = 0.
    let flat = BRICKS
        .replace("5, 0, 0, 1", "5, 0, 0, 0")
        .replace("6, 1, 0, 1", "6, 1, 0, 0")
        .replace("7, 1, 1, 1", "7, 1, 1, 0")
        .replace("8, 0, 1, 1", "8, 0, 1, 0");
    assert_error(&flat, "1, 1, 2, 3, 4, 5, 6, 7, 8", &["element 1", "volume"]);
    // Bottom and top faces swapped: negative volume.
    let inverted = BRICKS.replace("1, 1, 2, 3, 4, 5, 6, 7, 8", "1, 5, 6, 7, 8, 1, 2, 3, 4");
    assert_error(
        &inverted,
        "1, 5, 6, 7, 8, 1, 2, 3, 4",
        &["element 1", "inverted"],
    );
}
