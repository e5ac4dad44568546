//! Anisotropic solids against CalculiX 2.20: `*ELASTIC, TYPE=ENGINEERING
//! CONSTANTS` in a rotated `*ORIENTATION` (with the additional rotation
//! line), `TYPE=ANISO` in a rectangular orientation, `TYPE=ORTHO` in a
//! cylindrical orientation on a ring segment (the axes turn from one
//! integration point to the next), and an isotropic `*ELASTIC` and
//! `*DENSITY` interpolated in their temperature tables at the initial
//! temperature; fixtures of `scripts/calculix_fixtures.py`.
//!
//! K and M must agree entry by entry as in `calculix.rs`, and the
//! frequencies to 1e-6 of ccx's printed ones and 1e-9 of an exact solve of
//! ccx's K and M.

use super::calculix::{
    ccx_frequencies, ccx_matrices, ccx_to_ours, compare_matrix, fixture_dir, MATRIX_ATOL,
    MATRIX_RTOL,
};
use flexbody::fem::assemble;
use flexbody::io::deck::read_deck;
use flexbody::reduce::modes::{eigenmodes, Wanted};

fn matches_calculix(name: &str) {
    let path = fixture_dir(name).join(format!("{name}.inp"));
    let model = read_deck(&path, &Default::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model;
    let ours = assemble(&model).unwrap();
    let ccx = ccx_matrices(name);
    let to_ours = ccx_to_ours(&model, &ccx);
    for (what, a, b) in [
        ("K", &ours.stiffness, &ccx.stiffness),
        ("M", &ours.mass, &ccx.mass),
    ] {
        let (relative, scaled) = compare_matrix(what, a, b, &to_ours, &ccx)
            .unwrap_or_else(|report| panic!("{name} {report}"));
        eprintln!(
            "{name} {what}: largest |a - b| / |b| {relative:.1e} (allowed {MATRIX_RTOL:e}), \
             below the floor {scaled:.1e} (allowed {MATRIX_ATOL:e})"
        );
    }
    let printed = ccx_frequencies(name);
    let n = printed.len();
    let mine = eigenmodes(&ours.stiffness, &ours.mass, Wanted::Lowest(n))
        .unwrap()
        .frequencies_hz();
    let exact = eigenmodes(&ccx.stiffness, &ccx.mass, Wanted::Lowest(n))
        .unwrap()
        .frequencies_hz();
    for (mode, ((a, b), c)) in mine.iter().zip(&printed).zip(&exact).enumerate() {
        let (printed_rel, exact_rel) = ((a - b).abs() / b, (a - c).abs() / c);
        assert!(
            printed_rel <= 1e-6 && exact_rel <= 1e-9,
            "{name}: mode {} is {a} Hz; CalculiX prints {b} Hz ({printed_rel:.1e}), its K and M \
             give {c} Hz ({exact_rel:.1e})",
            mode + 1
        );
    }
}

#[test]
fn engineering_constants_in_a_turned_rectangular_orientation_match_calculix() {
    matches_calculix("ortho_rotated_block");
}

/// C3D8R's hourglass stiffness scales with the elasticity's `C_xxxx` in
/// global axes for an anisotropic material, as CalculiX's does.
#[test]
fn engineering_constants_on_c3d8r_match_calculix() {
    matches_calculix("ortho_rotated_c3d8r");
}

#[test]
fn an_anisotropic_material_matches_calculix() {
    matches_calculix("aniso_block");
}

#[test]
fn a_cylindrical_orientation_on_a_ring_segment_matches_calculix() {
    matches_calculix("cylindrical_ring");
}

#[test]
fn elastic_and_density_tables_at_the_initial_temperature_match_calculix() {
    matches_calculix("temperature_bar");
}

/// `flexbody modes` on fixture `name`'s deck with `from` replaced by `to`
/// exits 2 with all `needles` in its message.
fn variant_fails_with(name: &str, from: &str, to: &str, needles: &[&str]) {
    let text = std::fs::read_to_string(fixture_dir(name).join(format!("{name}.inp"))).unwrap();
    assert!(text.contains(from), "{from}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.inp");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    super::support::fails_with(&["modes", path.to_str().unwrap()], needles);
}

#[test]
fn a_missing_anisotropic_constant_names_the_line() {
    variant_fails_with(
        "aniso_block",
        "-4.e9, 9.e9, -3.e9, 5.e9, 60.e9, 0.",
        "-4.e9, 9.e9, -3.e9, 5.e9",
        &["d.inp:47:", "COMPOSITE", "constant 21 of 21 is missing"],
    );
    // A record short of a line: 2 lines for 3 a record.
    variant_fails_with(
        "aniso_block",
        "-4.e9, 9.e9, -3.e9, 5.e9, 60.e9, 0.\n",
        "",
        &["d.inp:46:", "multiple of 3"],
    );
}

#[test]
fn an_unstable_material_names_the_material_and_line() {
    variant_fails_with(
        "aniso_block",
        "210.e9, 60.e9, 180.e9",
        "210.e9, 600.e9, 180.e9",
        &["d.inp:45:", "material 'COMPOSITE'", "not positive definite"],
    );
}

#[test]
fn an_unknown_orientation_names_the_section_line() {
    variant_fails_with(
        "aniso_block",
        "ORIENTATION=SKEW",
        "ORIENTATION=SKEWED",
        &["d.inp:50:", "orientation 'SKEWED' is not defined"],
    );
}

#[test]
fn temperatures_out_of_order_name_the_line() {
    variant_fails_with(
        "temperature_bar",
        "1.5e11, 0.33, 500.",
        "1.5e11, 0.33, 150.",
        &["d.inp:45:", "must increase strictly"],
    );
}

#[test]
fn a_non_uniform_initial_temperature_is_refused() {
    variant_fails_with(
        "temperature_bar",
        "NALL, 310.",
        "NALL, 310.\n1, 20.",
        &["differs from 310", "uniform"],
    );
}

/// `info` names the kind of an anisotropic material instead of an `E` and
/// `nu` it does not have.
#[test]
fn info_names_the_kind_of_anisotropic_materials() {
    for (name, kind) in [
        ("aniso_block", "anisotropic"),
        ("ortho_rotated_block", "orthotropic"),
        ("cylindrical_ring", "orthotropic"),
    ] {
        let deck = fixture_dir(name).join(format!("{name}.inp"));
        let o = super::support::run_ok(&["info".as_ref(), deck.as_os_str()]);
        let text = String::from_utf8_lossy(&o.stdout);
        let line = text.lines().find(|l| l.starts_with("materials: ")).unwrap();
        assert!(
            line.contains(&format!("({kind}, density ")) && !line.contains(" E "),
            "{name}: {line}"
        );
    }
}
