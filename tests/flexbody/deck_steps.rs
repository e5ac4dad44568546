//! Deck semantics that used to give a wrong answer with exit code 0: steps
//! (the model is the one of the first frequency step), a preloaded
//! perturbation step, user matrices; and constraint errors that name the
//! line and the DOFs.

use super::calculix::fixture_dir;
use flexbody::fem::{assemble, DofKind};
use flexbody::io::deck::{parse_deck, Deck, DeckOptions};
use flexbody::reduce::modes::{eigenmodes, Wanted};
use std::path::Path;

/// The free C3D8 bar of the CalculiX fixtures (0.6 x 0.1 x 0.1 m), its
/// steps cut off, and the node set FIX of its face x = 0.
fn bar() -> String {
    let text = std::fs::read_to_string(fixture_dir("hex_beam").join("hex_beam.inp")).unwrap();
    let model = &text[..text.find("*STEP").unwrap()];
    let deck = parse_deck(Path::new("bar.inp"), model, &DeckOptions::default()).unwrap();
    let face: Vec<String> = deck
        .model
        .nodes()
        .iter()
        .filter(|n| n.coords[0] == 0.0)
        .map(|n| n.id.to_string())
        .collect();
    format!("{model}*NSET, NSET=FIX\n{}\n", face.join(", "))
}

/// The id of a node at the far end x = 0.6 of the bar.
fn tip_node(text: &str) -> u64 {
    node_at(text, 0.6)
}

/// The id of a node at `x` along the bar.
fn node_at(text: &str, x: f64) -> u64 {
    let deck = parse_deck(Path::new("bar.inp"), text, &DeckOptions::default()).unwrap();
    deck.model
        .nodes()
        .iter()
        .find(|n| (n.coords[0] - x).abs() < 1e-12)
        .unwrap()
        .id
}

fn read(text: &str) -> Result<Deck, String> {
    parse_deck(Path::new("bar.inp"), text, &DeckOptions::default()).map_err(|e| e.to_string())
}

/// The lowest `n` frequencies (Hz) of a deck.
fn frequencies(deck: &Deck, n: usize) -> Vec<f64> {
    let s = assemble(&deck.model).unwrap();
    eigenmodes(&s.stiffness, &s.mass, Wanted::Lowest(n))
        .unwrap()
        .frequencies_hz()
}

/// 1-based line of the first line of `text` that starts with `start`.
fn line_of(text: &str, start: &str) -> usize {
    text.lines().position(|l| l.starts_with(start)).unwrap() + 1
}

/// CalculiX adds a loaded step's stress stiffening to a following
/// `*STEP, PERTURBATION` frequency step (measured with ccx 2.20 on a
/// clamped bar in 2.5 MN tension: 217.96 Hz against 68.63 Hz unloaded). A
/// linear reduction of the unloaded body would miss it: refused. Without
/// PERTURBATION, CalculiX's frequency step is the unloaded body's, which
/// flexbody computes.
#[test]
fn a_preloaded_perturbation_step_is_refused_and_a_plain_one_is_the_unloaded_body() {
    let base = bar() + "*BOUNDARY\nFIX, 1, 3\n";
    let tip = tip_node(&base);
    let loaded = format!("{base}*STEP\n*STATIC\n*CLOAD\n{tip}, 1, 2.5e6\n*END STEP\n");
    let perturbation = format!("{loaded}*STEP, PERTURBATION\n*FREQUENCY\n4\n*END STEP\n");
    let err = read(&perturbation).unwrap_err();
    let frequency_line = line_of(&perturbation, "*FREQUENCY");
    let load_line = line_of(&perturbation, "*CLOAD");
    for needle in [
        format!("bar.inp:{frequency_line}:"),
        "PERTURBATION".to_string(),
        "preload".to_string(),
        format!("*CLOAD on line {load_line}"),
    ] {
        assert!(err.contains(&needle), "{needle:?} not in: {err}");
    }
    // Without PERTURBATION: the unloaded body, the same as with no static
    // step at all.
    let plain = format!("{loaded}*STEP\n*FREQUENCY\n4\n*END STEP\n");
    let unloaded = format!("{base}*STEP\n*FREQUENCY\n4\n*END STEP\n");
    assert_eq!(
        frequencies(&read(&plain).unwrap(), 4),
        frequencies(&read(&unloaded).unwrap(), 4)
    );
    // A perturbation step after an unloaded static step is read.
    let unloaded_static =
        format!("{base}*STEP\n*STATIC\n*END STEP\n*STEP, PERTURBATION\n*FREQUENCY\n4\n*END STEP\n");
    assert!(read(&unloaded_static).is_ok());
}

/// The model is the one that holds at the first frequency step: a
/// `*BOUNDARY` (even a prescribed displacement) and loads in later steps
/// change nothing, and are reported once.
#[test]
fn boundary_conditions_after_the_frequency_step_do_not_change_its_model() {
    let base = bar();
    let text = format!(
        "{base}*STEP\n*FREQUENCY\n10\n*END STEP\n*STEP\n*STATIC\n*BOUNDARY\nFIX, 1, 3\nFIX, 1, 1, 0.001\n\
         *CLOAD\nFIX, 2, 10.\n*END STEP\n"
    );
    let deck = read(&text).unwrap();
    assert_eq!(
        deck.model.fixed_dofs().count(),
        0,
        "the free bar stays free"
    );
    let f = frequencies(&deck, 7);
    assert!(
        f[..6].iter().all(|x| *x < 1e-3 * f[6]),
        "six rigid-body modes: {f:?}"
    );
    let warnings = deck.warning_lines().join("\n");
    let boundary_line = line_of(&text, "*BOUNDARY");
    assert!(
        warnings.contains(&format!("*BOUNDARY (line {boundary_line})"))
            && warnings.contains("after the first frequency step"),
        "{warnings}"
    );
    assert_eq!(warnings.lines().count(), 1, "reported once: {warnings}");
    // Before the frequency step, the same *BOUNDARY holds the bar.
    let before = format!("{base}*BOUNDARY\nFIX, 1, 3\n*STEP\n*FREQUENCY\n10\n*END STEP\n");
    assert_eq!(read(&before).unwrap().model.fixed_dofs().count(), 12);
}

/// User matrices would change K and M: refused with their line, also
/// when unknown keywords are allowed.
#[test]
fn user_matrices_are_refused_with_their_line() {
    let text = bar() + "*MATRIX ASSEMBLE, STIFFNESS=K1, MASS=M1\n";
    let line = line_of(&text, "*MATRIX");
    for allow_unknown in [false, true] {
        let options = DeckOptions {
            allow_unknown,
            ..DeckOptions::default()
        };
        let err = parse_deck(Path::new("bar.inp"), &text, &options)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(&format!("bar.inp:{line}:")) && err.contains("stiffness and mass"),
            "{err}"
        );
    }
}

/// Bad constraints name the deck line, the constraint and the DOFs.
#[test]
fn bad_equations_name_their_line_and_dofs() {
    let base = bar() + "*BOUNDARY\nFIX, 1, 3\n";
    let fixed: u64 = base
        .lines()
        .skip_while(|l| !l.starts_with("*NSET, NSET=FIX"))
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    let tip = tip_node(&base);
    let (a, b) = (node_at(&base, 0.3), node_at(&base, 0.4));
    let cases = [
        // The dependent DOF is fixed.
        (
            format!("*EQUATION\n2\n{fixed}, 1, 1., {tip}, 1, -1.\n"),
            vec!["fixed", "ux"],
            1,
        ),
        // A rotation of a solid node does not exist.
        (
            format!("*EQUATION\n2\n{tip}, 4, 1., {tip}, 1, -1.\n"),
            vec!["not a DOF", "rx"],
            1,
        ),
        // An undefined node.
        (
            format!("*EQUATION\n2\n{tip}, 1, 1., 99999, 1, -1.\n"),
            vec!["node 99999"],
            1,
        ),
        // The same dependent DOF twice: over-constrained.
        (
            format!("*EQUATION\n2\n{tip}, 2, 1., {a}, 2, -1.\n2\n{tip}, 2, 1., {b}, 2, -1.\n"),
            vec!["over-constrained", "uy"],
            3,
        ),
        // A cycle.
        (
            format!("*EQUATION\n2\n{tip}, 3, 1., {a}, 3, -1.\n2\n{a}, 3, 1., {tip}, 3, -1.\n"),
            vec!["cycle"],
            3,
        ),
        // Fewer terms than announced.
        (
            format!("*EQUATION\n3\n{tip}, 3, 1., {a}, 3, -1.\n"),
            vec!["3 terms announced"],
            1,
        ),
    ];
    // The line of the equation to blame, after the *EQUATION card.
    for (cards, needles, offset) in cases {
        let text = base.clone() + &cards;
        let err = read(&text).unwrap_err();
        let line = line_of(&text, "*EQUATION") + offset;
        assert!(
            err.contains(&format!("bar.inp:{line}:")),
            "line {line}: {err}"
        );
        for needle in needles {
            assert!(err.contains(needle), "{needle:?} not in: {err}");
        }
    }
    // A good one eliminates one DOF.
    let good =
        read(&(base.clone() + &format!("*EQUATION\n2\n{tip}, 3, 1., {a}, 3, -1.\n"))).unwrap();
    let plain = read(&base).unwrap();
    assert_eq!(good.model.dof_map().len(), plain.model.dof_map().len() - 1);
    assert!(good
        .model
        .dof_map()
        .index_of(flexbody::fem::Dof::new(tip, DofKind::Uz))
        .is_none());
}

/// The command line exits 2 on a bad constraint and writes nothing.
#[test]
fn a_bad_constraint_exits_2_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("bad.inp");
    let base = bar();
    let tip = tip_node(&base);
    let a = node_at(&base, 0.3);
    std::fs::write(
        &deck,
        base + &format!("*MPC\nPLANE, {tip}, {tip}, {a}, {a}\n"),
    )
    .unwrap();
    let out = dir.path().join("body.json");
    let run = super::support::flexbody(&[
        "reduce".as_ref(),
        deck.as_os_str(),
        "--method".as_ref(),
        "craig-bampton".as_ref(),
        "--interface".as_ref(),
        "1".as_ref(),
        "--modes".as_ref(),
        "4".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("bad.inp:") && stderr.contains("*MPC"),
        "{stderr}"
    );
    assert!(!out.exists());
}

/// A tie whose slave nodes lie beyond the position tolerance names them
/// and the tie's line (CalculiX only warns and leaves them loose: a
/// mechanism); within it, ADJUST (the default) moves them onto the master
/// surface, as CalculiX does.
#[test]
fn a_tie_names_the_slave_nodes_it_cannot_place() {
    let text = std::fs::read_to_string(fixture_dir("tie_blocks").join("tie_blocks.inp")).unwrap();
    let shifted = |gap: f64, tie_card: &str| -> String {
        text.lines()
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                match f[0].trim().parse::<u64>() {
                    Ok(id) if id > 10000 && f.len() == 4 => {
                        let x: f64 = f[1].trim().parse().unwrap();
                        format!("{id}, {}, {}, {}", x + gap, f[2], f[3])
                    }
                    _ => l.replace("*TIE, NAME=JOINT", tie_card),
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let far = shifted(2e-3, "*TIE, NAME=JOINT, POSITION TOLERANCE=1e-3");
    let err = read(&far).unwrap_err();
    let line = line_of(&far, "SLAVE, MASTER");
    for needle in [
        format!("bar.inp:{line}:"),
        "tie 'JOINT'".to_string(),
        "16 slave node(s)".to_string(),
        "10001".to_string(),
    ] {
        assert!(err.contains(&needle), "{needle:?} not in: {err}");
    }
    // A gap of 0.2 mm within the tolerance: adjusted (the default) the
    // block is the tied one moved by the gap; not adjusted it is not.
    let tied = |card: &str| frequencies(&read(&shifted(2e-4, card)).unwrap(), 3);
    let adjusted = tied("*TIE, NAME=JOINT");
    assert_eq!(adjusted, tied("*TIE, NAME=JOINT, ADJUST=YES"));
    let loose = tied("*TIE, NAME=JOINT, ADJUST=NO");
    // ccx 2.20 on the same decks: 274.5606 Hz adjusted, 274.7370 Hz not.
    assert!(
        (adjusted[0] - 274.5606).abs() < 1e-4 * 274.5606,
        "{adjusted:?}"
    );
    assert!((loose[0] - 274.7370).abs() < 1e-4 * 274.7370, "{loose:?}");
}
