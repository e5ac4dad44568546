//! Tests of the deck reader: small decks inline, include decks in
//! `crates/io/tests/decks/`.

use super::*;
use flexbody_fem::element::{AxialSpring, PointMass, SolidKind, Spring};
use flexbody_fem::{BeamTheory, Dof, DofKind, Element, SectionShape};

fn parse(text: &str) -> Result<Deck, InputError> {
    parse_deck(Path::new("test.inp"), text)
}

/// 1-based line of the first line of `text` containing `needle`.
/// An exact line wins over a line that only contains `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.trim() == needle)
        .or_else(|| text.lines().position(|l| l.contains(needle)))
        .unwrap_or_else(|| panic!("'{needle}' not in the deck"))
        + 1
}

/// The line and message of the error the deck must give.
fn error_of(text: &str) -> (usize, String) {
    match parse(text) {
        Err(InputError::Invalid {
            line: Some(line),
            message,
            ..
        }) => (line, message),
        Err(other) => panic!("error without a line: {other}"),
        Ok(_) => panic!("the deck was accepted"),
    }
}

/// Asserts the deck fails on the line containing `needle`, with a message
/// containing each of `words`.
fn assert_error(text: &str, needle: &str, words: &[&str]) {
    let (line, message) = error_of(text);
    assert_eq!(line, line_of(text, needle), "{message}");
    for w in words {
        assert!(message.contains(w), "'{w}' not in: {message}");
    }
}

fn path_in_decks(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/decks")
        .join(name)
}

/// Two C3D8 bricks stacked along z: nodes 1-4 at z = 0, 5-8 at 1, 9-12 at 2.
const BRICKS: &str = "\
*HEADING
two bricks
** nodes
*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
9, 0, 0, 2
10, 1, 0, 2
11, 1, 1, 2
12, 0, 1, 2
*NSET, NSET=base, GENERATE
1, 4, 1
*NSET, NSET=Top
9, 10, 11, 12,
*NSET, NSET=ends
BASE, top
*ELEMENT, TYPE=C3D8, ELSET=lower
1, 1, 2, 3, 4, 5, 6, 7, 8
*Element, type=c3d8
2, 5, 6, 7, 8, 9, 10, 11, 12
*ELSET, ELSET=all
lower, 2
*MATERIAL, NAME=Steel
*ELASTIC
2.1e11, 0.3
*DENSITY
7850.
*SOLID SECTION, ELSET=ALL, MATERIAL=STEEL
*BOUNDARY
BASE, 1, 6
*STEP
*FREQUENCY
10
*NODE FILE
U
*END STEP
";

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
        deck.warnings,
        vec![
            "*HEADING (line 1)".to_string(),
            format!("*STEP (line {})", line_of(BRICKS, "*STEP")),
            format!("*FREQUENCY (line {})", line_of(BRICKS, "*FREQUENCY")),
            format!("*NODE FILE (line {})", line_of(BRICKS, "*NODE FILE")),
            format!("*END STEP (line {})", line_of(BRICKS, "*END STEP")),
            format!(
                "*BOUNDARY (line {}): 12 fixed DOF(s) ignored because no element gives the node \
                 that DOF (first: node 1 rx; solid elements have no rotations)",
                line_of(BRICKS, "BASE, 1, 6")
            ),
        ]
    );
}

/// Nodes of the 2 m cube as a C3D20 (Abaqus order: corners, then the
/// mid-side nodes of edges 1-2, 2-3, 3-4, 4-1, 5-6, 6-7, 7-8, 8-5, 1-5,
/// 2-6, 3-7, 4-8).
fn c3d20_nodes() -> String {
    let corners = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
        [0.0, 2.0, 0.0],
        [0.0, 0.0, 2.0],
        [2.0, 0.0, 2.0],
        [2.0, 2.0, 2.0],
        [0.0, 2.0, 2.0],
    ];
    let edges = [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ];
    let mut points: Vec<[f64; 3]> = corners.to_vec();
    for (a, b) in edges {
        points.push([0, 1, 2].map(|k| 0.5 * (corners[a][k] + corners[b][k])));
    }
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
fn include_files_are_read_in_place() {
    let deck = read_deck(&path_in_decks("include_main.inp")).unwrap();
    assert_eq!(deck.model.nodes().len(), 8);
    assert_eq!(deck.model.node_sets()["NALL"].len(), 8);
    assert_eq!(deck.model.dof_map().len(), 8 * 3 - 3);
    assert_eq!(deck.warnings, vec!["*HEADING (line 2)".to_string()]);
}

#[test]
fn an_error_in_an_included_file_names_that_file_and_line() {
    let e = read_deck(&path_in_decks("include_bad.inp")).unwrap_err();
    match &e {
        InputError::Invalid { path, line, .. } => {
            assert!(path.ends_with("include_bad_material.inp"), "{e}");
            assert_eq!(*line, Some(4), "{e}");
        }
        other => panic!("{other}"),
    }
    assert!(e.to_string().contains("temperature-dependent"), "{e}");
}

#[test]
fn include_relative_to_the_deck_in_a_temporary_folder() {
    let dir = std::env::temp_dir().join(format!("flexbody-deck-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(
        dir.join("sub/beam.inp"),
        "*ELEMENT, TYPE=B31, ELSET=B\n1, 1, 2\n",
    )
    .unwrap();
    let main = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*INCLUDE, INPUT=sub/beam.inp\n\
                *MATERIAL, NAME=S\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n\
                *BEAM SECTION, ELSET=B, MATERIAL=S, SECTION=CIRC\n0.01\n";
    let deck = parse_deck(&dir.join("main.inp"), main);
    std::fs::remove_dir_all(&dir).ok();
    let deck = deck.unwrap();
    assert_eq!(deck.model.elements().len(), 1);
    assert_eq!(deck.model.dof_map().len(), 12);
}

/// Three nodes along x, two B31 elements with a RECT section.
const BEAM: &str = "\
*NODE, NSET=ALL
1, 0, 0, 0
2, 0.5, 0, 0
3, 1.0, 0, 0
*ELEMENT, TYPE=B31, ELSET=BEAM
1, 1, 2
2, 2, 3
*MATERIAL, NAME=STEEL
*ELASTIC
2.1E11, 0.3
*DENSITY
7850
*BEAM SECTION, ELSET=BEAM, MATERIAL=STEEL, SECTION=RECT
0.04, 0.06
0., 1., 0.
*BOUNDARY
1, 1, 6
";

#[test]
fn b31_beam_with_a_rect_section() {
    let deck = parse(BEAM).unwrap();
    let expected = SectionShape::Rect {
        width: 0.04,
        height: 0.06,
    }
    .constants()
    .unwrap();
    for e in deck.model.elements() {
        let Element::Beam(b) = e else {
            panic!("not a beam: {e:?}")
        };
        assert_eq!(b.properties.section, expected);
        assert_eq!(b.properties.theory, BeamTheory::Timoshenko);
        assert!(b.properties.rotary_inertia);
        assert_eq!(b.orientation, [0.0, 1.0, 0.0]);
        assert_eq!(b.properties.material.youngs_modulus, 2.1e11);
    }
    // a = 0.04 along local y (n1), b = 0.06 along local z.
    assert!((expected.area - 0.0024).abs() < 1e-15);
    assert!((expected.iy - 0.04 * 0.06f64.powi(3) / 12.0).abs() < 1e-18);
    assert!((expected.iz - 0.06 * 0.04f64.powi(3) / 12.0).abs() < 1e-18);
    assert_eq!(deck.model.fixed_dofs().count(), 6);
    assert_eq!(deck.model.dof_map().len(), 12);
    assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
}

fn beam_with_section(section: &str, dims: &str) -> String {
    BEAM.replace(
        "SECTION=RECT\n0.04, 0.06\n0., 1., 0.\n",
        &format!("SECTION={section}\n{dims}\n"),
    )
}

#[test]
fn beam_sections_circ_pipe_box_and_the_default_n1() {
    let cases = [
        ("CIRC", "0.02", SectionShape::Circ { radius: 0.02 }),
        (
            "PIPE",
            "0.05, 0.004",
            SectionShape::Pipe {
                radius: 0.05,
                wall: 0.004,
            },
        ),
        (
            "BOX",
            "0.24, 0.20, 0.012, 0.012, 0.012, 0.012",
            SectionShape::Box {
                width: 0.24,
                height: 0.20,
                wall: 0.012,
            },
        ),
    ];
    for (name, dims, shape) in cases {
        let deck = parse(&beam_with_section(name, dims)).unwrap();
        let Element::Beam(b) = &deck.model.elements()[0] else {
            panic!("not a beam")
        };
        assert_eq!(b.properties.section, shape.constants().unwrap(), "{name}");
        assert_eq!(b.orientation, [0.0, 0.0, -1.0], "{name}");
    }
}

#[test]
fn beam_section_errors() {
    let text = beam_with_section("BOX", "0.24, 0.20, 0.012, 0.01, 0.012, 0.012");
    assert_error(&text, "0.24, 0.20", &["BOX", "equal walls"]);
    let text = beam_with_section("CIRC", "0.02, 0.03");
    assert_error(&text, "0.02, 0.03", &["elliptical"]);
    let text = beam_with_section("HEX", "0.02, 0.03");
    assert_error(&text, "*BEAM SECTION", &["SECTION=HEX", "not supported"]);
    let text = beam_with_section("RECT", "0.04, -0.06");
    assert_error(&text, "0.04, -0.06", &["rect height"]);
    // The default n1 (0, 0, -1) is parallel to a beam along z.
    let text = beam_with_section("CIRC", "0.02")
        .replace("2, 0.5, 0, 0", "2, 0, 0, 0.5")
        .replace("3, 1.0, 0, 0", "3, 0, 0, 1.0");
    assert_error(&text, "1, 1, 2", &["element 1", "parallel"]);
}

#[test]
fn mass_and_spring_elements() {
    let text = BEAM.to_string()
        + "*ELEMENT, TYPE=MASS, ELSET=TIP\n10, 3\n*MASS, ELSET=TIP\n12.5\n\
           *ELEMENT, TYPE=SPRING1, ELSET=S1\n11, 3\n*SPRING, ELSET=S1\n3\n1.0e6\n\
           *ELEMENT, TYPE=SPRING2, ELSET=S2\n12, 2, 3\n*SPRING, ELSET=S2\n2, 6\n2.0e6\n\
           *ELEMENT, TYPE=SPRINGA, ELSET=SA\n13, 1, 3\n*SPRING, ELSET=SA\n\n3.0e6\n";
    let deck = parse(&text).unwrap();
    let find = |id: usize| {
        deck.model
            .elements()
            .iter()
            .find(|e| e.id() == id)
            .unwrap()
            .clone()
    };
    assert_eq!(
        find(10),
        Element::PointMass(PointMass {
            id: 10,
            node: 3,
            mass: 12.5,
            inertia: [0.0; 6]
        })
    );
    assert_eq!(
        find(11),
        Element::Spring(Spring {
            id: 11,
            first: Dof::new(3, DofKind::Uz),
            second: None,
            stiffness: 1.0e6
        })
    );
    assert_eq!(
        find(12),
        Element::Spring(Spring {
            id: 12,
            first: Dof::new(2, DofKind::Uy),
            second: Some(Dof::new(3, DofKind::Rz)),
            stiffness: 2.0e6
        })
    );
    assert_eq!(
        find(13),
        Element::AxialSpring(AxialSpring {
            id: 13,
            nodes: [1, 3],
            stiffness: 3.0e6
        })
    );
}

#[test]
fn spring_and_mass_errors() {
    let base = BEAM.to_string() + "*ELEMENT, TYPE=SPRING1, ELSET=S1\n11, 3\n";
    assert_error(
        &(base.clone() + "*SPRING, ELSET=S1\n1.0e6\n"),
        "*SPRING",
        &["SPRING1", "DOF"],
    );
    assert_error(
        &(base.clone() + "*SPRING, ELSET=S1\n7\n1.0e6\n"),
        "7",
        &["DOF 7"],
    );
    assert_error(
        &(base.clone() + "*SPRING, ELSET=S1\n3\n-1.0e6\n"),
        "-1.0e6",
        &["stiffness"],
    );
    assert_error(
        &(base.clone() + "*SPRING, ELSET=S1, NONLINEAR\n3\n1., 0.1\n"),
        "*SPRING",
        &["NONLINEAR"],
    );
    assert_error(&base, "11, 3", &["element 11", "*SPRING"]);
    // *MASS on a spring element.
    assert_error(
        &(base + "*MASS, ELSET=S1\n2.0\n"),
        "*MASS",
        &["element 11", "SPRING1", "*SPRING"],
    );
}

#[test]
fn ignored_unknown_and_refused_keywords() {
    let text = BEAM.to_string()
        + "*ORIENTATION, NAME=OR1\n1., 0., 0., 0., 1., 0.\n*FOO BAR\n1, 2\n\
           *STEP, PERTURBATION\n*STATIC\n*CLOAD\n3, 3, 1000.\n*EL PRINT, ELSET=BEAM\nS\n*END STEP\n\
           *STEP\n*FREQUENCY\n5\n*END STEP\n";
    let deck = parse(&text).unwrap();
    let step = line_of(&text, "*STEP, PERTURBATION");
    assert_eq!(
        deck.warnings,
        vec![
            format!("*ORIENTATION (line {})", line_of(&text, "*ORIENTATION")),
            format!(
                "*FOO BAR (line {}): unknown keyword, skipped",
                line_of(&text, "*FOO")
            ),
            format!("*STEP (line {step})"),
            format!("*STATIC (line {})", step + 1),
            format!("*CLOAD (line {})", step + 2),
            format!("*EL PRINT (line {})", step + 4),
            format!("*END STEP (line {})", step + 6),
            format!("*FREQUENCY (line {})", step + 8),
        ]
    );
    for (keyword, what) in [
        ("*EQUATION\n2\n3, 3, 1., 2, 3, -1.\n", "stiffness"),
        ("*RIGID BODY, NSET=ALL, REF NODE=1\n", "stiffness"),
        ("*DISTRIBUTING COUPLING, ELSET=E\n", "stiffness"),
        ("*TIE, NAME=T\nA, B\n", "stiffness"),
        (
            "*SHELL SECTION, ELSET=BEAM, MATERIAL=STEEL\n0.01\n",
            "stiffness",
        ),
        ("*MPC\nBEAM, 1, 2\n", "stiffness"),
    ] {
        let text = BEAM.to_string() + keyword;
        let first = keyword.lines().next().unwrap();
        assert_error(&text, first, &["is not supported", what]);
    }
}

#[test]
fn bad_decks_name_the_line_and_the_culprit() {
    // A node referenced by an element but never defined.
    let text = BEAM.replace("2, 2, 3", "2, 2, 99");
    assert_error(&text, "2, 2, 99", &["element 2", "node 99"]);
    // Wrong node count for the type.
    let text = BRICKS.replace("1, 1, 2, 3, 4, 5, 6, 7, 8", "1, 1, 2, 3, 4, 5, 6, 7");
    assert_error(
        &text,
        "1, 1, 2, 3, 4, 5, 6, 7",
        &["element 1", "7 nodes", "C3D8 needs 8"],
    );
    let text = BEAM.replace("1, 1, 2\n", "1, 1, 2, 3\n");
    assert_error(
        &text,
        "1, 1, 2, 3",
        &["element 1", "3 nodes", "B31 needs 2"],
    );
    // A section naming a material that does not exist.
    let text = BRICKS.replace("MATERIAL=STEEL", "MATERIAL=ALU");
    assert_error(&text, "*SOLID SECTION", &["material 'ALU'", "not defined"]);
    // A solid element without a section.
    let text = BRICKS.replace("lower, 2", "lower");
    assert_error(
        &text,
        "2, 5, 6, 7, 8",
        &["element 2", "C3D8", "*SOLID SECTION"],
    );
    // Duplicate ids.
    let text = BRICKS.replace("3, 1, 1, 0", "2, 1, 1, 0");
    assert_error(
        &text,
        "2, 1, 1, 0",
        &["node 2 is defined twice", "first on line 6"],
    );
    let text = BRICKS.replace("2, 5, 6, 7, 8", "1, 5, 6, 7, 8");
    let first = format!(
        "first on line {}",
        line_of(BRICKS, "1, 1, 2, 3, 4, 5, 6, 7, 8")
    );
    assert_error(
        &text,
        "1, 5, 6, 7, 8",
        &["element 1 is defined twice", &first],
    );
    // Unknown and unsupported element types.
    let text = BRICKS.replace("*Element, type=c3d8", "*ELEMENT, TYPE=S4");
    assert_error(&text, "TYPE=S4", &["element type S4 is not supported"]);
    let text = BRICKS.replace("*Element, type=c3d8", "*ELEMENT, TYPE=C3D8I");
    assert_error(&text, "TYPE=C3D8I", &["C3D8I", "incompatible modes"]);
    // A missing include file.
    let text = BRICKS.replace("** nodes", "*INCLUDE, INPUT=no_such_file.inp");
    assert_error(&text, "*INCLUDE", &["no_such_file.inp", "cannot read"]);
    // A material without density, used by a section.
    let text = BRICKS.replace("*DENSITY\n7850.\n", "");
    assert_error(&text, "*MATERIAL", &["material 'STEEL'", "*DENSITY"]);
    // Anisotropic elasticity.
    let text = BRICKS.replace("*ELASTIC\n", "*ELASTIC, TYPE=ORTHO\n");
    assert_error(&text, "*ELASTIC", &["TYPE=ORTHO", "isotropic"]);
    // A prescribed displacement.
    let text = BRICKS.replace("BASE, 1, 6", "BASE, 3, 3, 0.001");
    assert_error(&text, "BASE, 3, 3", &["prescribed displacement"]);
    // A boundary condition or a set on an undefined node.
    let text = BRICKS.replace("BASE, 1, 6", "13, 1, 3");
    assert_error(&text, "13, 1, 3", &["node 13"]);
    let text = BRICKS.replace("9, 10, 11, 12,", "9, 10, 11, 12, 77");
    assert_error(&text, "9, 10, 11, 12, 77", &["node set 'TOP'", "node 77"]);
    // A section on a set that does not exist; a set name never defined.
    let text = BRICKS.replace("ELSET=ALL, MATERIAL", "ELSET=NONE, MATERIAL");
    assert_error(&text, "*SOLID SECTION", &["element set 'NONE'"]);
    let text = BRICKS.replace("BASE, top", "BASE, side");
    assert_error(&text, "BASE, side", &["node set 'SIDE' is not defined"]);
    // Numbers that are not numbers.
    let text = BEAM.replace("2, 0.5, 0, 0", "2, 0.5, zero, 0");
    assert_error(&text, "2, 0.5, zero", &["node 2", "coordinate 2", "'zero'"]);
    let text = BEAM.replace("2.1E11, 0.3", "2.1E11, 0.6");
    assert_error(&text, "2.1E11, 0.6", &["material 'STEEL'", "Poisson"]);
    // A point mass on a node no element gives a DOF.
    let text = BEAM.replace("3, 1.0, 0, 0", "3, 1.0, 0, 0\n4, 2.0, 0, 0")
        + "*ELEMENT, TYPE=MASS, ELSET=M\n20, 4\n*MASS, ELSET=M\n1.0\n";
    assert_error(&text, "20, 4", &["point mass on node 4"]);
    // No element at all.
    let e = parse("*NODE\n1, 0, 0, 0\n").unwrap_err();
    assert!(e.to_string().contains("no DOFs"), "{e}");
}

/// The layout Abaqus/CAE writes: one part, one instance, mixed case,
/// continued keyword lines, a `,` data line under *Solid Section.
#[test]
fn abaqus_cae_layout() {
    let nodes: String = BRICKS
        .lines()
        .skip(4)
        .take(12)
        .map(|l| format!("      {l}\n"))
        .collect();
    let text = format!(
        "*Heading\n*Part, name=Part-1\n*Node\n{nodes}\
         *Element, type=C3D8\n1, 1, 2, 3, 4, 5, 6, 7, 8\n2, 5, 6, 7, 8, 9, 10, 11, 12\n\
         *Elset, elset=Set-1, generate\n 1, 2, 1\n\
         *Solid Section, elset=Set-1,\n material=Material-1\n,\n*End Part\n\
         *Assembly, name=Assembly\n*Instance, name=Part-1-1, part=Part-1\n*End Instance\n\
         *Nset, nset=Set-2, instance=Part-1-1\n 1, 2, 3, 4\n*End Assembly\n\
         *Material, name=Material-1\n*Density\n 7850.,\n*Elastic\n 2.1e+11, 0.3\n\
         *Boundary\nSet-2, ENCASTRE\n"
    );
    let deck = parse(&text).unwrap();
    assert_eq!(deck.model.elements().len(), 2);
    assert_eq!(deck.model.dof_map().len(), 24);
    assert_eq!(deck.element_sets["SET-1"], vec![1, 2]);
    assert_eq!(deck.warnings.len(), 8, "{:?}", deck.warnings);
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

#[test]
fn boundary_types_and_fortran_numbers() {
    let text = BEAM
        .replace("1, 1, 6", "1, ENCASTRE\n3, ZSYMM")
        .replace("2.1E11, 0.3", "2.1D11, .3");
    let deck = parse(&text).unwrap();
    let fixed: Vec<Dof> = deck.model.fixed_dofs().copied().collect();
    let mut expected: Vec<Dof> = DofKind::ALL.iter().map(|k| Dof::new(1, *k)).collect();
    expected.extend([DofKind::Uz, DofKind::Rx, DofKind::Ry].map(|k| Dof::new(3, k)));
    assert_eq!(fixed, expected);
    let Element::Beam(b) = &deck.model.elements()[0] else {
        panic!("not a beam")
    };
    assert_eq!(b.properties.material.youngs_modulus, 2.1e11);
}

/// Truncated and garbled decks give errors, never panics.
#[test]
fn no_panic_on_garbled_decks() {
    let springs = BEAM.to_string()
        + "*ELEMENT, TYPE=MASS, ELSET=TIP\n10, 3\n*MASS, ELSET=TIP\n12.5\n\
           *ELEMENT, TYPE=SPRING2, ELSET=S2\n12, 2, 3\n*SPRING, ELSET=S2\n2, 6\n2.0e6\n\
           *NSET, NSET=G, GENERATE\n1, 3\n";
    for text in [BRICKS, springs.as_str()] {
        let chars: Vec<char> = text.chars().collect();
        for i in 0..chars.len() {
            let truncated: String = chars[..i].iter().collect();
            let _ = parse(&truncated);
            for c in [',', '*', '\n', 'x', '-', '0', '9', '='] {
                let mut garbled = chars.clone();
                garbled[i] = c;
                let _ = parse(&garbled.iter().collect::<String>());
            }
        }
    }
}
