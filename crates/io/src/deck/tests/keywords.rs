//! Keywords ignored, unknown and refused; bad decks naming line and
//! culprit; the Abaqus/CAE layout; boundary types and Fortran numbers;
//! garbled decks.

use super::*;

#[test]
fn ignored_unknown_and_refused_keywords() {
    let text = BEAM.to_string()
        + "*ORIENTATION, NAME=OR1\n1., 0., 0., 0., 1., 0.\n\
           *STEP, PERTURBATION\n*STATIC\n*CLOAD\n3, 3, 1000.\n*EL PRINT, ELSET=BEAM\nS\n*END STEP\n\
           *STEP\n*FREQUENCY\n5\n*END STEP\n";
    let deck = parse(&text).unwrap();
    let step = line_of(&text, "*STEP, PERTURBATION");
    assert_eq!(
        deck.skipped,
        vec![
            format!("*STEP (line {step})"),
            format!("*STATIC (line {})", step + 1),
            format!("*CLOAD (line {})", step + 2),
            format!("*EL PRINT (line {})", step + 4),
            format!("*END STEP (line {})", step + 6),
            format!("*FREQUENCY (line {})", step + 8),
        ]
    );
    for (keyword, what) in [
        (
            "*MATRIX ASSEMBLE, STIFFNESS=K1, MASS=M1\n",
            "stiffness and mass",
        ),
        (
            "*MEMBRANE SECTION, ELSET=BEAM, MATERIAL=STEEL\n0.01\n",
            "stiffness",
        ),
    ] {
        let text = BEAM.to_string() + keyword;
        let first = keyword.lines().next().unwrap();
        assert_error(&text, first, &["is not supported", what]);
    }
}

#[test]
fn an_unknown_keyword_is_refused_naming_file_line_and_nearest_keyword() {
    // A misspelt *BOUNDARY would leave the beam free-free.
    let text = BEAM.to_string() + "*BOUNDRY\n1, 1, 6\n*STEP\n*FREQUENCY\n5\n*END STEP\n";
    let e = parse(&text).unwrap_err();
    let InputError::Invalid {
        path,
        line,
        message,
    } = &e
    else {
        panic!("not an input error: {e}");
    };
    assert_eq!(path, Path::new("test.inp"));
    assert_eq!(*line, Some(line_of(&text, "*BOUNDRY")));
    assert!(message.contains("unknown keyword *BOUNDRY"), "{message}");
    assert!(message.contains("did you mean *BOUNDARY?"), "{message}");
    assert!(message.contains("--allow-unknown"), "{message}");
    assert!(e
        .to_string()
        .starts_with(&format!("test.inp:{}:", line.unwrap())));
    // The suggestion keeps the spaces of a two-word keyword.
    let text = BEAM.to_string() + "*SOLID SECTON, ELSET=BEAM, MATERIAL=STEEL\n";
    let (_, message) = error_of(&text);
    assert!(
        message.contains("did you mean *SOLID SECTION?"),
        "{message}"
    );
    // Nothing close: no suggestion.
    let text = BEAM.to_string() + "*FOO BAR\n1, 2\n";
    let (line, message) = error_of(&text);
    assert_eq!(line, line_of(&text, "*FOO BAR"));
    assert!(message.contains("unknown keyword *FOO BAR"), "{message}");
    assert!(!message.contains("did you mean"), "{message}");
}

#[test]
fn allowed_unknown_keywords_are_skipped_and_listed_once_each() {
    let text = BEAM.to_string()
        + "*FOO BAR\n1, 2\n*BOUNDRY\n3, 1, 6\n*STEP\n*FREQUENCY\n5\n*END STEP\n*FOO BAR\n";
    let allow = DeckOptions {
        allow_unknown: true,
        ..DeckOptions::default()
    };
    let deck = parse_deck(Path::new("test.inp"), &text, &allow).unwrap();
    let strict = parse(BEAM).unwrap();
    // Read as if the unknown keywords were not there: node 3 stays free.
    assert_eq!(deck.model.nodes().len(), strict.model.nodes().len());
    assert_eq!(deck.model.fixed_dofs().count(), 6);
    assert_eq!(strict.model.fixed_dofs().count(), 6);
    let foo: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with("*FOO"))
        .map(|(i, _)| i + 1)
        .collect();
    let boundry = line_of(&text, "*BOUNDRY");
    assert_eq!(
        deck.unknown.keywords,
        vec![
            UnknownKeyword {
                keyword: "*FOO BAR".into(),
                lines: foo.iter().map(|l| format!("line {l}")).collect(),
            },
            UnknownKeyword {
                keyword: "*BOUNDRY".into(),
                lines: vec![format!("line {boundry}")],
            },
        ]
    );
    assert!(deck.warnings.iter().all(|w| !w.contains("FOO")));
    assert_eq!(
        deck.unknown.summary().unwrap(),
        format!(
            "test.inp: unknown keywords skipped (--allow-unknown; they may have changed K, M or D): \
             *FOO BAR (lines {}, {}), *BOUNDRY (line {boundry})",
            foo[0], foo[1]
        )
    );
    assert_eq!(strict.unknown.summary(), None);
}

#[test]
fn bad_decks_name_the_line_and_the_culprit() {
    let first = format!(
        "first on line {}",
        line_of(BRICKS, "1, 1, 2, 3, 4, 5, 6, 7, 8")
    );
    // The deck, the text replaced in it and its replacement, the line the
    // error names and words of its message.
    let cases: [(&str, &str, &str, &str, &[&str]); 19] = [
        // A node referenced by an element but never defined.
        (
            BEAM,
            "2, 2, 3",
            "2, 2, 99",
            "2, 2, 99",
            &["element 2", "node 99"],
        ),
        // Wrong node count for the type.
        (
            BRICKS,
            "1, 1, 2, 3, 4, 5, 6, 7, 8",
            "1, 1, 2, 3, 4, 5, 6, 7",
            "1, 1, 2, 3, 4, 5, 6, 7",
            &["element 1", "7 nodes", "C3D8 needs 8"],
        ),
        (
            BEAM,
            "1, 1, 2\n",
            "1, 1, 2, 3\n",
            "1, 1, 2, 3",
            &["element 1", "3 nodes", "B31 needs 2", "orientation node"],
        ),
        // A section naming a material that does not exist.
        (
            BRICKS,
            "MATERIAL=STEEL",
            "MATERIAL=ALU",
            "*SOLID SECTION",
            &["material 'ALU'", "not defined"],
        ),
        // A solid element without a section.
        (
            BRICKS,
            "lower, 2",
            "lower",
            "2, 5, 6, 7, 8",
            &["element 2", "C3D8", "*SOLID SECTION"],
        ),
        // Duplicate ids.
        (
            BRICKS,
            "3, 1, 1, 0",
            "2, 1, 1, 0",
            "2, 1, 1, 0",
            &["node 2 is defined twice", "first on line 6"],
        ),
        (
            BRICKS,
            "2, 5, 6, 7, 8",
            "1, 5, 6, 7, 8",
            "1, 5, 6, 7, 8",
            &["element 1 is defined twice", &first],
        ),
        // Unknown and unsupported element types.
        (
            BRICKS,
            "*Element, type=c3d8",
            "*ELEMENT, TYPE=S8R5",
            "TYPE=S8R5",
            &["element type S8R5 is not supported", "five DOFs per node"],
        ),
        (
            BRICKS,
            "*Element, type=c3d8",
            "*ELEMENT, TYPE=M3D4",
            "TYPE=M3D4",
            &["element type M3D4 is not supported", "membranes"],
        ),
        // A missing include file.
        (
            BRICKS,
            "** nodes",
            "*INCLUDE, INPUT=no_such_file.inp",
            "*INCLUDE",
            &["no_such_file.inp", "cannot read"],
        ),
        // A material without density, used by a section.
        (
            BRICKS,
            "*DENSITY\n7850.\n",
            "",
            "*MATERIAL",
            &["material 'STEEL'", "*DENSITY"],
        ),
        // An elasticity type flexbody does not read.
        (
            BRICKS,
            "*ELASTIC\n",
            "*ELASTIC, TYPE=HYPO\n",
            "*ELASTIC",
            &["TYPE=HYPO", "not supported"],
        ),
        // A prescribed displacement.
        (
            BRICKS,
            "BASE, 1, 6",
            "BASE, 3, 3, 0.001",
            "BASE, 3, 3",
            &["prescribed displacement"],
        ),
        // A boundary condition or a set on an undefined node.
        (BRICKS, "BASE, 1, 6", "13, 1, 3", "13, 1, 3", &["node 13"]),
        (
            BRICKS,
            "9, 10, 11, 12,",
            "9, 10, 11, 12, 77",
            "9, 10, 11, 12, 77",
            &["node set 'TOP'", "node 77"],
        ),
        // A section on a set that does not exist; a set name never defined.
        (
            BRICKS,
            "ELSET=ALL, MATERIAL",
            "ELSET=NONE, MATERIAL",
            "*SOLID SECTION",
            &["element set 'NONE'"],
        ),
        (
            BRICKS,
            "BASE, top",
            "BASE, side",
            "BASE, side",
            &["node set 'SIDE' is not defined"],
        ),
        // Numbers that are not numbers.
        (
            BEAM,
            "2, 0.5, 0, 0",
            "2, 0.5, zero, 0",
            "2, 0.5, zero",
            &["node 2", "coordinate 2", "'zero'"],
        ),
        (
            BEAM,
            "2.1E11, 0.3",
            "2.1E11, 0.6",
            "2.1E11, 0.6",
            &["material 'STEEL'", "Poisson"],
        ),
    ];
    for (deck, from, to, line, words) in cases {
        assert_error(&deck.replace(from, to), line, words);
    }
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
    assert_eq!(
        deck.skipped.len() + deck.warnings.len(),
        8,
        "{:?} {:?}",
        deck.skipped,
        deck.warnings
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

#[test]
fn set_entries_beyond_the_memory_budget_are_refused_before_they_are_stored() {
    // Set B copies set A 2.1 million times: 4.2 million entries, where the
    // memory check starts.
    let mut text = BEAM.to_string() + "*NSET, NSET=A\n1, 2\n*NSET, NSET=B\n";
    let line = "A, A, A, A, A, A, A, A, A, A, A, A, A, A, A, A\n";
    for _ in 0..131_250 {
        text.push_str(line);
    }
    let none_left = DeckOptions {
        memory: flexbody_linalg::memory::Budget::at_most(Some(1)),
        ..DeckOptions::default()
    };
    let e = parse_deck(Path::new("sets.inp"), &text, &none_left)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("sets.inp:")
            && e.contains(
                "the deck's set entries (4194304 node and element numbers) needs 96.0 MiB"
            )
            && e.contains("--max-memory"),
        "{e}"
    );
    // Within the machine's memory the same deck reads.
    let deck = parse_deck(Path::new("sets.inp"), &text, &DeckOptions::default()).unwrap();
    assert_eq!(deck.model.node_sets()["B"], vec![1, 2]);
}
