//! Tests of the deck reader: small decks inline, include decks in
//! `crates/io/tests/decks/`; the helpers they share.

use super::*;
use flexbody_fem::element::{AxialSpring, PointMass, SolidKind, Spring};
use flexbody_fem::{BeamTheory, Dof, DofKind, Element, SectionShape};

mod beams;
mod damping;
mod includes;
mod keywords;
mod masses;
mod registry;
mod shells;
mod solids;

fn parse(text: &str) -> Result<Deck, InputError> {
    parse_deck(Path::new("test.inp"), text, &DeckOptions::default())
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
