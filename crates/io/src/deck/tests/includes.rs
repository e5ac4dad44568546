//! `*INCLUDE`: files read in place, errors naming the included file.

use super::*;

#[test]
fn include_files_are_read_in_place() {
    let deck = read_deck(&path_in_decks("include_main.inp"), &DeckOptions::default()).unwrap();
    assert_eq!(deck.model.nodes().len(), 8);
    assert_eq!(deck.model.node_sets()["NALL"].len(), 8);
    assert_eq!(deck.model.dof_map().len(), 8 * 3 - 3);
    assert_eq!(deck.skipped, vec!["*HEADING (line 2)".to_string()]);
    assert!(deck.warnings.is_empty());
}

#[test]
fn an_error_in_an_included_file_names_that_file_and_line() {
    let e = read_deck(&path_in_decks("include_bad.inp"), &DeckOptions::default()).unwrap_err();
    match &e {
        InputError::Invalid { path, line, .. } => {
            assert!(path.ends_with("include_bad_material.inp"), "{e}");
            assert_eq!(*line, Some(4), "{e}");
        }
        other => panic!("{other}"),
    }
    assert!(e.to_string().contains("increase strictly"), "{e}");
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
    let deck = parse_deck(&dir.join("main.inp"), main, &DeckOptions::default());
    std::fs::remove_dir_all(&dir).ok();
    let deck = deck.unwrap();
    assert_eq!(deck.model.elements().len(), 1);
    assert_eq!(deck.model.dof_map().len(), 12);
}
