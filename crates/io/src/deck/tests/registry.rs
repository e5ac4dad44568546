//! A deck with one element of every registered type reads into the same
//! elements the registry builds directly.

use super::*;
use crate::deck::keywords::property_keyword;
use flexbody_fem::element::SectionKind;
use flexbody_fem::mesh::EveryElementType;
use std::fmt::Write as _;

/// The data lines of the section keyword of `kind` that give the values
/// of `sample_section` (the material is the deck's STEEL).
fn section_lines(kind: SectionKind) -> &'static str {
    match kind {
        SectionKind::Solid => "",
        SectionKind::Shell => "0.01\n",
        SectionKind::Beam => "0.05, 0.08\n0.0, 1.0, 0.0\n",
        SectionKind::Mass => "12.5\n",
        SectionKind::Spring { dofs: 0 } => "1.0e6\n",
        SectionKind::Spring { dofs: 1 } => "2\n1.0e6\n",
        SectionKind::Spring { .. } => "2, 2\n1.0e6\n",
        SectionKind::Dashpot { dofs: 0 } => "\n2.0e3\n",
        SectionKind::Dashpot { dofs: 1 } => "2\n2.0e3\n",
        SectionKind::Dashpot { .. } => "2, 2\n2.0e3, 0.0\n",
    }
}

#[test]
fn a_deck_with_every_registered_type_gives_the_elements_the_registry_builds() {
    let every = EveryElementType::sample().unwrap();
    let mut text = String::from("*NODE\n");
    for n in &every.nodes {
        let [x, y, z] = n.coords;
        let _ = writeln!(text, "{}, {x}, {y}, {z}", n.id);
    }
    for (t, e) in &every.elements {
        let nodes: Vec<String> = e.nodes().iter().map(u64::to_string).collect();
        let _ = writeln!(
            text,
            "*ELEMENT, TYPE={}, ELSET=E{}\n{}, {}",
            t.name,
            e.id(),
            e.id(),
            nodes.join(", ")
        );
    }
    text.push_str("*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850\n");
    for (t, e) in &every.elements {
        let keyword = property_keyword(t.section);
        let params = match t.section {
            SectionKind::Solid | SectionKind::Shell => ", MATERIAL=STEEL",
            SectionKind::Beam => ", MATERIAL=STEEL, SECTION=RECT",
            SectionKind::Mass | SectionKind::Spring { .. } | SectionKind::Dashpot { .. } => "",
        };
        let _ = write!(
            text,
            "{keyword}, ELSET=E{}{params}\n{}",
            e.id(),
            section_lines(t.section)
        );
    }
    let deck = parse(&text).unwrap_or_else(|err| panic!("{err}\n{text}"));
    let expected: Vec<Element> = every.elements.iter().map(|(_, e)| e.clone()).collect();
    assert_eq!(deck.model.elements(), expected.as_slice());
    assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
}
