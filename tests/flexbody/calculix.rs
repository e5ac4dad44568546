//! Cross-check against CalculiX 2.20, the peer program: stiffness K, mass M
//! and natural frequencies of small solid models, one per element type.
//!
//! Each fixture in `tests/fixtures/calculix/<name>/` holds a deck
//! (`<name>.inp`), CalculiX's K and M over its free DOFs (`.sti`, `.mas`,
//! `.dof`, from `*FREQUENCY, SOLVER=MATRIXSTORAGE`) and its lowest natural
//! frequencies in Hz (`frequencies.txt`, 8 significant digits from ccx's
//! `.dat`). `scripts/calculix_fixtures.sh` writes them and, in CI, checks
//! them against a fresh ccx run; these tests need no ccx.
//!
//! flexbody reads the same deck, assembles K and M, and must agree with
//! CalculiX entry by entry to 1e-9 of the largest entry, DOFs matched by
//! node and direction. Its lowest frequencies must agree to 1e-6: ccx's
//! ARPACK stops at a tolerance of 1e-2 and its frequencies carry ~4e-7 of
//! error against an exact solve of the same K and M.

use flexbody::fem::element::SolidKind;
use flexbody::fem::{assemble, Element};
use flexbody::fem::{Dof, DofKind, Substructure, SystemMatrices};
use flexbody::io::deck::read_deck;
use flexbody::io::matrices::{read_calculix_matrices, MatrixModel};
use flexbody::linalg::SparseMat;
use flexbody::reduce::method::free_body_rigid_modes;
use flexbody::reduce::modes::eigenmodes;
use flexbody::reduce::{reduce, Method, Reduction};
use std::path::PathBuf;

/// One deck of the fixture folder.
struct Fixture {
    name: &'static str,
    element: SolidKind,
    /// Zero-frequency modes: 6 for a free body, 0 for the clamped plate.
    rigid_modes: usize,
}

static FIXTURES: [Fixture; 6] = [
    Fixture {
        name: "hex_beam",
        element: SolidKind::C3D8,
        rigid_modes: 6,
    },
    Fixture {
        name: "hex20_beam",
        element: SolidKind::C3D20,
        rigid_modes: 6,
    },
    Fixture {
        name: "plate_c3d20r",
        element: SolidKind::C3D20R,
        rigid_modes: 0,
    },
    Fixture {
        name: "tet_beam",
        element: SolidKind::C3D10,
        rigid_modes: 6,
    },
    Fixture {
        name: "tet4_beam",
        element: SolidKind::C3D4,
        rigid_modes: 6,
    },
    Fixture {
        name: "wedge_block",
        element: SolidKind::C3D6,
        rigid_modes: 6,
    },
];

/// Largest difference of matrix entries, relative to the largest entry.
const MATRIX_TOLERANCE: f64 = 1e-9;
/// Largest relative difference of elastic frequencies.
const FREQUENCY_TOLERANCE: f64 = 1e-6;

fn fixture(name: &str) -> &'static Fixture {
    FIXTURES.iter().find(|f| f.name == name).unwrap()
}

fn fixture_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calculix")
        .join(name)
}

fn ccx_matrices(name: &str) -> MatrixModel {
    read_calculix_matrices(&fixture_dir(name).join(name))
        .unwrap_or_else(|e| panic!("{name}: CalculiX matrices: {e}"))
}

fn ccx_frequencies(name: &str) -> Vec<f64> {
    let path = fixture_dir(name).join("frequencies.txt");
    let text = std::fs::read_to_string(&path).unwrap();
    text.split_whitespace()
        .map(|f| f.parse().unwrap_or_else(|_| panic!("{path:?}: `{f}`")))
        .collect()
}

/// Number of frequencies below 1e-4 of the highest one (rigid-body modes).
fn near_zero(frequencies: &[f64]) -> usize {
    let highest = frequencies.iter().fold(0.0_f64, |m, f| m.max(*f));
    frequencies.iter().filter(|f| **f < 1e-4 * highest).count()
}

/// Compares the elastic frequencies of `ours` with CalculiX's, and the
/// number of rigid-body modes of both with the fixture's.
fn compare_frequencies(what: &str, fixture: &Fixture, ours: &[f64], ccx: &[f64]) {
    let rigid = fixture.rigid_modes;
    assert_eq!(
        near_zero(ccx),
        rigid,
        "{what}: CalculiX's frequencies {ccx:?} should have {rigid} near zero"
    );
    assert_eq!(
        near_zero(ours),
        rigid,
        "{what}: frequencies {ours:?} should have {rigid} near zero"
    );
    for (mode, (a, b)) in ours.iter().zip(ccx).enumerate().skip(rigid) {
        let relative = (a - b).abs() / b;
        assert!(
            relative <= FREQUENCY_TOLERANCE,
            "{what}: mode {} is {a} Hz, CalculiX has {b} Hz (relative difference {relative:.2e})",
            mode + 1
        );
    }
}

/// `max |ours - ccx| / max |ccx|` over all entries, with `ours` on
/// flexbody's equations and `ccx` on CalculiX's (`to_ours[i]` is flexbody's
/// equation of CalculiX's equation `i`). Lists the largest differences if
/// that is above [`MATRIX_TOLERANCE`].
fn compare_matrix(
    what: &str,
    ours: &SparseMat,
    ccx: &SparseMat,
    to_ours: &[usize],
    ccx_model: &MatrixModel,
) -> Result<f64, String> {
    let ours = ours.to_dense();
    let ccx = ccx.to_dense();
    let n = to_ours.len();
    let mut largest = 0.0_f64;
    for i in 0..n {
        for j in 0..n {
            largest = largest.max(ccx[(i, j)].abs());
        }
    }
    let mut worst = 0.0_f64;
    let mut differences = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let a = ours[(to_ours[i], to_ours[j])];
            let b = ccx[(i, j)];
            let relative = (a - b).abs() / largest;
            worst = worst.max(relative);
            if relative > MATRIX_TOLERANCE {
                differences.push((relative, i, j, a, b));
            }
        }
    }
    if differences.is_empty() {
        return Ok(worst);
    }
    differences.sort_by(|x, y| y.0.total_cmp(&x.0));
    let dof = |i: usize| ccx_model.dof_map.dof(i).to_string();
    let mut report = format!(
        "{what}: {} of {} entries differ from CalculiX by more than {MATRIX_TOLERANCE:e} of the largest entry ({largest:e}); the largest differences:",
        differences.len(),
        n * n
    );
    for (relative, i, j, a, b) in differences.iter().take(12) {
        report += &format!(
            "\n  ({}, {}): flexbody {a:e}, CalculiX {b:e} ({relative:.2e} of the largest)",
            dof(*i),
            dof(*j)
        );
    }
    Err(report)
}

/// Reads the deck of `name` with flexbody, assembles it, and compares K, M
/// and the lowest frequencies with CalculiX's.
fn cross_check(name: &str) {
    let fixture = fixture(name);
    let kind = fixture.element.name();
    let what = format!("{name} ({kind})");
    let deck_path = fixture_dir(name).join(format!("{name}.inp"));
    let deck = read_deck(&deck_path).unwrap_or_else(|e| panic!("{what}: {e}"));
    let model = &deck.model;
    assert!(
        model
            .elements()
            .iter()
            .all(|e| matches!(e, Element::Solid(s) if s.kind == fixture.element)),
        "{what}: the deck should hold {kind} elements only"
    );
    let ours = assemble(model).unwrap_or_else(|e| panic!("{what}: assembly: {e}"));
    let ccx = ccx_matrices(name);

    // CalculiX's equation i is flexbody's equation to_ours[i].
    assert_eq!(
        model.dof_map().len(),
        ccx.dof_map.len(),
        "{what}: flexbody has {} free DOFs, CalculiX {}",
        model.dof_map().len(),
        ccx.dof_map.len()
    );
    let to_ours: Vec<usize> = ccx
        .dof_map
        .dofs()
        .iter()
        .map(|d| {
            model.dof_map().index_of(*d).unwrap_or_else(|| {
                panic!("{what}: CalculiX's DOF {d} is not a free DOF of flexbody")
            })
        })
        .collect();

    let k = compare_matrix(
        &format!("{what} K"),
        &ours.stiffness,
        &ccx.stiffness,
        &to_ours,
        &ccx,
    );
    let m = compare_matrix(&format!("{what} M"), &ours.mass, &ccx.mass, &to_ours, &ccx);
    match (k, m) {
        (Ok(_), Ok(_)) => {}
        (k, m) => panic!(
            "{}",
            [k.err(), m.err()]
                .into_iter()
                .flatten()
                .collect::<Vec<_>>()
                .join("\n")
        ),
    }

    let expected = ccx_frequencies(name);
    let frequencies = eigenmodes(&ours.stiffness, &ours.mass, expected.len())
        .unwrap_or_else(|e| panic!("{what}: eigenmodes: {e}"))
        .frequencies_hz();
    compare_frequencies(&what, fixture, &frequencies, &expected);
}

/// The stored frequencies are those of the stored matrices: ccx's ARPACK
/// finds spurious modes of free bodies when asked for too many
/// (`scripts/calculix_fixtures.py` keeps the count low); an exact solve of
/// CalculiX's own K and M, read by `read_calculix_matrices`, catches that.
#[test]
fn calculix_frequencies_are_those_of_its_matrices() {
    for fixture in &FIXTURES {
        let ccx = ccx_matrices(fixture.name);
        let expected = ccx_frequencies(fixture.name);
        let frequencies = eigenmodes(&ccx.stiffness, &ccx.mass, expected.len())
            .unwrap()
            .frequencies_hz();
        compare_frequencies(
            &format!("{} (CalculiX's K and M)", fixture.name),
            fixture,
            &frequencies,
            &expected,
        );
    }
}

/// K and M alone (no mesh, no support known): the rigid-body modes are the
/// zero-frequency eigenmodes, found with either sign of their round-off
/// (all six come out positive from the C3D4 beam's text file, 5e-5 to 1.4e-3
/// against 2.5e8), and free-residual reduces the free bodies.
#[test]
fn rigid_body_modes_of_calculix_matrices_are_their_zero_modes() {
    for fixture in &FIXTURES {
        let ccx = ccx_matrices(fixture.name);
        let matrices = SystemMatrices {
            stiffness: ccx.stiffness,
            mass: ccx.mass,
            damping: None,
        };
        let sub = Substructure::from_matrices(ccx.dof_map, matrices, Default::default());
        let rigid = free_body_rigid_modes(&sub).unwrap();
        assert_eq!(rigid.count(), fixture.rigid_modes, "{}", fixture.name);
        if fixture.rigid_modes == 0 {
            continue;
        }
        let interface = vec![Dof::new(1, DofKind::Ux), Dof::new(1, DofKind::Uy)];
        let body = reduce(&sub, &Reduction::new(Method::FreeResidual, 4, interface))
            .unwrap_or_else(|e| panic!("{}: {e}", fixture.name));
        let reduced = body.frequencies_hz().unwrap();
        let expected = ccx_frequencies(fixture.name);
        compare_frequencies(
            &format!("{} (free-residual of CalculiX's K and M)", fixture.name),
            fixture,
            &reduced[..10],
            &expected[..10],
        );
    }
}

#[test]
fn c3d8_hex_beam_matches_calculix() {
    cross_check("hex_beam");
}

#[test]
fn c3d20_hex20_beam_matches_calculix() {
    cross_check("hex20_beam");
}

#[test]
fn c3d20r_clamped_plate_matches_calculix() {
    cross_check("plate_c3d20r");
}

#[test]
fn c3d10_tet_beam_matches_calculix() {
    cross_check("tet_beam");
}

#[test]
fn c3d4_tet4_beam_matches_calculix() {
    cross_check("tet4_beam");
}

#[test]
fn c3d6_wedge_block_matches_calculix() {
    cross_check("wedge_block");
}
