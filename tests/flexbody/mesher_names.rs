//! The element names meshers write (Abaqus/CAE, meshio): hybrid (H) and
//! modified (M) names read as flexbody's types with a warning that says
//! so, and element lines with more nodes than the type uses read as
//! CalculiX reads them (the first ones).

use super::calculix::fixture_dir;
use super::support::fails_with;
use flexbody::fem::element::{ElementType, ELEMENT_ALIASES};
use flexbody::fem::{assemble, SystemMatrices};
use flexbody::io::deck::{parse_deck, Deck, DeckOptions};
use std::path::Path;

fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(fixture_dir(name).join(format!("{name}.inp"))).unwrap()
}

fn read(text: &str) -> Deck {
    parse_deck(Path::new("mesh.inp"), text, &DeckOptions::default()).unwrap()
}

/// K and M of two decks are the same, entry by entry.
fn same_matrices(a: &SystemMatrices, b: &SystemMatrices) {
    assert_eq!(a.stiffness.to_dense(), b.stiffness.to_dense());
    assert_eq!(a.mass.to_dense(), b.mass.to_dense());
}

/// A cantilever of two B31 elements with a rectangular section.
const BEAM: &str = "*NODE
1, 0.0, 0.0, 0.0
2, 0.5, 0.0, 0.0
3, 1.0, 0.0, 0.0
*ELEMENT, TYPE=B31, ELSET=EB
1, 1, 2
2, 2, 3
*MATERIAL, NAME=STEEL
*ELASTIC
2.1e11, 0.3
*DENSITY
7850.
*BEAM SECTION, ELSET=EB, MATERIAL=STEEL, SECTION=RECT
0.1, 0.05
0.0, 1.0, 0.0
*BOUNDARY
1, 1, 6
";

/// [`BEAM`] as one three-node beam.
const B32_BEAM: &str = "*NODE
1, 0.0, 0.0, 0.0
2, 0.5, 0.0, 0.0
3, 1.0, 0.0, 0.0
*ELEMENT, TYPE=B32, ELSET=EB
1, 1, 2, 3
*MATERIAL, NAME=STEEL
*ELASTIC
2.1e11, 0.3
*DENSITY
7850.
*BEAM SECTION, ELSET=EB, MATERIAL=STEEL, SECTION=RECT
0.1, 0.05
0.0, 1.0, 0.0
*BOUNDARY
1, 1, 6
";

#[test]
fn every_alias_reads_as_a_registered_type() {
    for alias in ELEMENT_ALIASES {
        let (kind, found) = ElementType::resolve(alias.name).unwrap();
        assert_eq!(kind.name, alias.reads_as);
        assert_eq!(found, Some(alias));
        // An alias never hides a registered type.
        assert!(ElementType::find(alias.name).is_none(), "{}", alias.name);
    }
    assert!(
        ElementType::resolve("c3d10mh").is_some(),
        "case-insensitive"
    );
    assert!(ElementType::resolve("C3D10HS").is_none());
}

/// Two S4, one S3 and one S8 shell, 3 mm steel, one edge held.
const SHELLS: &str = "\
*NODE
1, 0., 0., 0.
2, 1., 0., 0.
3, 2., 0., 0.
4, 0., 1., 0.
5, 1., 1., 0.1
6, 2., 1., 0.
7, 3., 0.5, 0.
8, 3., 1., 0.
9, 3., 2., 0.
10, 2., 2., 0.
11, 2.5, 1., 0.
12, 3., 1.5, 0.02
13, 2.5, 2., 0.
14, 2., 1.5, 0.
*ELEMENT, TYPE=S4, ELSET=PLATE
1, 1, 2, 5, 4
2, 2, 3, 6, 5
*ELEMENT, TYPE=S3, ELSET=PLATE
3, 3, 7, 6
*ELEMENT, TYPE=S8, ELSET=PLATE
4, 6, 8, 9, 10, 11, 12, 13, 14
*MATERIAL, NAME=STEEL
*ELASTIC
2.1e11, 0.3
*DENSITY
7850.
*SHELL SECTION, ELSET=PLATE, MATERIAL=STEEL
0.003
*BOUNDARY
1, 1, 6
4, 1, 6
";

#[test]
fn hybrid_and_modified_names_give_their_base_type_s_matrices_and_say_so() {
    let decks = [
        ("tet4_beam", "C3D4"),
        ("wedge_block", "C3D6"),
        ("hex_beam", "C3D8"),
        ("tet_beam", "C3D10"),
        ("hex20_beam", "C3D20"),
        ("plate_c3d20r", "C3D20R"),
        ("wedge15_beam", "C3D15"),
        ("hex8r_beam", "C3D8R"),
    ];
    let mut covered = 0;
    for alias in ELEMENT_ALIASES {
        let text = match decks.iter().find(|(_, base)| *base == alias.reads_as) {
            Some((name, _)) => fixture_text(name),
            // The C3D8 beam's deck with its elements as C3D8I.
            None if alias.reads_as == "C3D8I" => {
                fixture_text("hex_beam").replace("TYPE=C3D8, ", "TYPE=C3D8I, ")
            }
            None if alias.reads_as.starts_with('S') => SHELLS.to_string(),
            None if alias.reads_as == "B32" => B32_BEAM.to_string(),
            None => BEAM.to_string(),
        };
        let base = format!("TYPE={}, ", alias.reads_as);
        assert!(text.contains(&base), "{} in its deck", alias.reads_as);
        let renamed = text.replace(&base, &format!("TYPE={}, ", alias.name));
        let (a, b) = (read(&text), read(&renamed));
        same_matrices(&assemble(&a.model).unwrap(), &assemble(&b.model).unwrap());
        let said = b.warnings.join("\n");
        let expected = format!("{} elements are read as {}", alias.name, alias.reads_as);
        assert!(said.contains(&expected), "{said}");
        assert!(!a.warnings.join("\n").contains("are read as"));
        covered += 1;
    }
    assert_eq!(covered, ELEMENT_ALIASES.len());
}

#[test]
fn element_lines_with_more_nodes_read_the_first_as_calculix_does() {
    let text = fixture_text("tet4_beam");
    // Each C3D4 line gets a fifth node number, as some meshers write.
    let mut in_elements = false;
    let longer: String = text
        .lines()
        .map(|l| {
            if l.starts_with('*') {
                in_elements = l.starts_with("*ELEMENT");
                format!("{l}\n")
            } else if in_elements {
                format!("{l}, 1\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    assert_ne!(longer, text);
    let (a, b) = (read(&text), read(&longer));
    same_matrices(&assemble(&a.model).unwrap(), &assemble(&b.model).unwrap());
    let warned: Vec<&String> = b
        .warnings
        .iter()
        .filter(|w| w.contains("lists 5 nodes"))
        .collect();
    assert_eq!(
        warned.len(),
        1,
        "one warning per *ELEMENT card: {:?}",
        b.warnings
    );
    assert!(
        warned[0].contains("element 1 lists 5 nodes and type C3D4 uses 4"),
        "{}",
        warned[0]
    );
    assert!(warned[0].contains("line 33"), "{}", warned[0]);
}

#[test]
fn hybrid_names_of_types_flexbody_lacks_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("brick.inp");
    // C3D10HS: Abaqus' hybrid tetrahedron with improved surface stresses.
    let text = fixture_text("tet_beam").replace("TYPE=C3D10, ", "TYPE=C3D10HS, ");
    std::fs::write(&deck, &text).unwrap();
    let line = text.lines().position(|l| l.contains("C3D10HS")).unwrap() + 1;
    fails_with(
        &["info", deck.to_str().unwrap()],
        &[
            &format!("brick.inp:{line}"),
            "element type C3D10HS is not supported",
        ],
    );
}
