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
//! CalculiX entry by entry, DOFs matched by node and direction:
//! `|a_ij - b_ij| <= MATRIX_RTOL |b_ij| + MATRIX_ATOL sqrt(b_ii b_jj)`, so
//! that small entries are checked on the scale of their own row and column,
//! not of the largest entry. Its lowest frequencies must agree to 1e-6:
//! ccx's ARPACK stops at a tolerance of 1e-2 and its frequencies carry ~4e-7
//! of error against an exact solve of the same K and M.

use flexbody::fem::element::SolidKind;
use flexbody::fem::{assemble, Element};
use flexbody::fem::{Dof, DofKind, Substructure, SystemMatrices};
use flexbody::io::deck::read_deck;
use flexbody::io::matrices::{read_calculix_matrices, MatrixModel};
use flexbody::linalg::SparseMat;
use flexbody::reduce::method::free_body_rigid_modes;
use flexbody::reduce::modes::{eigenmodes, Wanted};
use flexbody::reduce::{reduce, Method, Reduction};
use std::path::PathBuf;

/// One deck of the fixture folder.
struct Fixture {
    name: &'static str,
    element: SolidKind,
    /// Zero-frequency modes: 6 for a free body, 0 for the clamped plate.
    rigid_modes: usize,
}

static FIXTURES: [Fixture; 8] = [
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
    Fixture {
        name: "wedge15_beam",
        element: SolidKind::C3D15,
        rigid_modes: 6,
    },
    Fixture {
        name: "hex8r_beam",
        element: SolidKind::C3D8R,
        rigid_modes: 6,
    },
];

/// Entry-wise agreement of K and M with CalculiX's:
/// `|a_ij - b_ij| <= MATRIX_RTOL |b_ij| + MATRIX_ATOL sqrt(b_ii b_jj)`.
///
/// CalculiX writes 14 significant digits (`%.13e`, a rounding of up to
/// 5e-14 of the entry) of values with its own round-off. Measured over the
/// seven fixtures, K and M: `|a - b| / |b|` at most 4.5e-14 on the entries
/// above the floor (`MATRIX_RTOL |b| > MATRIX_ATOL sqrt(b_ii b_jj)`);
/// `|a - b| / sqrt(b_ii b_jj)` at most 5.9e-15 on those below it (small
/// entries from cancellation, zeros in one program and round-off in the
/// other). The largest ratio to the allowance is 0.30.
pub(crate) const MATRIX_RTOL: f64 = 2e-13;
/// See [`MATRIX_RTOL`]: the absolute floor, relative to the row and column
/// scale `sqrt(b_ii b_jj)`.
pub(crate) const MATRIX_ATOL: f64 = 2e-14;
/// Largest relative difference of elastic frequencies.
const FREQUENCY_TOLERANCE: f64 = 1e-6;

fn fixture(name: &str) -> &'static Fixture {
    FIXTURES.iter().find(|f| f.name == name).unwrap()
}

pub(crate) fn fixture_dir(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calculix")
        .join(name)
}

pub(crate) fn ccx_matrices(name: &str) -> MatrixModel {
    read_calculix_matrices(&fixture_dir(name).join(name))
        .unwrap_or_else(|e| panic!("{name}: CalculiX matrices: {e}"))
}

pub(crate) fn ccx_frequencies(name: &str) -> Vec<f64> {
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

/// flexbody's equation of each of CalculiX's equations, the DOF sets being
/// the same (both programs eliminated the same DOFs).
pub(crate) fn ccx_to_ours(model: &flexbody::fem::Model, ccx: &MatrixModel) -> Vec<usize> {
    assert_eq!(model.dof_map().len(), ccx.dof_map.len());
    ccx.dof_map
        .dofs()
        .iter()
        .map(|d| model.dof_map().index_of(*d).expect("a DOF of both"))
        .collect()
}

/// Compares `ours` (on flexbody's equations) with `ccx` (on CalculiX's;
/// `to_ours[i]` is flexbody's equation of CalculiX's equation `i`) entry by
/// entry against [`MATRIX_RTOL`] and [`MATRIX_ATOL`]. Returns the largest
/// `|a - b| / |b|` over entries above the absolute floor and the largest
/// `|a - b| / sqrt(b_ii b_jj)` over those below it, or lists the entries
/// that fail.
pub(crate) fn compare_matrix(
    what: &str,
    ours: &SparseMat,
    ccx: &SparseMat,
    to_ours: &[usize],
    ccx_model: &MatrixModel,
) -> Result<(f64, f64), String> {
    let ours = ours.to_dense();
    let ccx = ccx.to_dense();
    let n = to_ours.len();
    let (mut relative, mut scaled) = (0.0_f64, 0.0_f64);
    let mut differences = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let a = ours[(to_ours[i], to_ours[j])];
            let b = ccx[(i, j)];
            let scale = (ccx[(i, i)] * ccx[(j, j)]).abs().sqrt();
            let d = (a - b).abs();
            if MATRIX_RTOL * b.abs() > MATRIX_ATOL * scale {
                relative = relative.max(d / b.abs());
            } else {
                scaled = scaled.max(d / scale);
            }
            let ratio = d / (MATRIX_RTOL * b.abs() + MATRIX_ATOL * scale);
            if ratio.is_nan() || ratio > 1.0 {
                differences.push((ratio, i, j, a, b));
            }
        }
    }
    if differences.is_empty() {
        return Ok((relative, scaled));
    }
    differences.sort_by(|x, y| y.0.total_cmp(&x.0));
    let dof = |i: usize| ccx_model.dof_map.dof(i).to_string();
    let mut report = format!(
        "{what}: {} of {} entries differ from CalculiX by more than {MATRIX_RTOL:e} |b| + {MATRIX_ATOL:e} sqrt(b_ii b_jj); the largest differences:",
        differences.len(),
        n * n
    );
    for (ratio, i, j, a, b) in differences.iter().take(12) {
        report += &format!(
            "\n  ({}, {}): flexbody {a:e}, CalculiX {b:e} ({ratio:.2e} times the allowed)",
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
    let deck = read_deck(&deck_path, &Default::default()).unwrap_or_else(|e| panic!("{what}: {e}"));
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
        (Ok((k_relative, k_scaled)), Ok((m_relative, m_scaled))) => eprintln!(
            "{what} against CalculiX: largest |a - b| / |b| K {k_relative:.1e}, M {m_relative:.1e} \
             (allowed {MATRIX_RTOL:e}); below the floor, largest |a - b| / sqrt(b_ii b_jj) \
             K {k_scaled:.1e}, M {m_scaled:.1e} (allowed {MATRIX_ATOL:e})"
        ),
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
    let frequencies = eigenmodes(&ours.stiffness, &ours.mass, Wanted::Lowest(expected.len()))
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
        let frequencies = eigenmodes(&ccx.stiffness, &ccx.mass, Wanted::Lowest(expected.len()))
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

/// Uniform strain with hourglass control, one-point mass (singular: the
/// beam's M has rank 72 of its 189 DOFs).
#[test]
fn c3d8r_hex_beam_matches_calculix() {
    cross_check("hex8r_beam");
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

#[test]
fn c3d15_wedge15_beam_matches_calculix() {
    cross_check("wedge15_beam");
}
