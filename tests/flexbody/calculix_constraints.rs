//! Constraints against CalculiX 2.20: `*EQUATION`, `*MPC` (PLANE, STRAIGHT,
//! BEAM), `*RIGID BODY`, `*DISTRIBUTING COUPLING` (DCOUP3D), `*TIE` and
//! `*TRANSFORM` on a clamped C3D8 bar, from the fixtures of `scripts/calculix_fixtures.py` (decks,
//! ccx's K and M over its independent DOFs, and its frequencies).
//!
//! flexbody eliminates each constraint's dependent DOFs exactly and must
//! give CalculiX's frequencies to 1e-6 (ccx prints 7 digits; its ARPACK
//! carries ~4e-7), and the frequencies of CalculiX's own K and M to 1e-9.
//! Where both eliminate the same DOFs (`*EQUATION`: the first term of each
//! equation), K and M must agree entry by entry as in `calculix.rs`.

use super::calculix::{
    ccx_frequencies, ccx_matrices, ccx_to_ours, compare_matrix, fixture_dir, MATRIX_ATOL,
    MATRIX_RTOL,
};

use flexbody::fem::{assemble, Dof, DofKind, Model};
use flexbody::io::deck::read_deck;
use flexbody::reduce::modes::{eigenmodes, Wanted};

/// flexbody's model of fixture `name`, read from its deck.
fn model(name: &str) -> Model {
    let path = fixture_dir(name).join(format!("{name}.inp"));
    read_deck(&path, &Default::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .model
}

/// The lowest `n` frequencies (Hz) of a model.
fn frequencies(model: &Model, n: usize) -> Vec<f64> {
    let s = assemble(model).unwrap();
    eigenmodes(&s.stiffness, &s.mass, Wanted::Lowest(n))
        .unwrap()
        .frequencies_hz()
}

/// flexbody's frequencies of `name` against ccx's printed ones (1e-6) and
/// against an exact solve of ccx's K and M (1e-9).
fn frequencies_match(name: &str) -> Model {
    let model = model(name);
    let printed = ccx_frequencies(name);
    let ours = frequencies(&model, printed.len());
    let ccx = ccx_matrices(name);
    let exact = eigenmodes(&ccx.stiffness, &ccx.mass, Wanted::Lowest(printed.len()))
        .unwrap()
        .frequencies_hz();
    for (mode, ((a, b), c)) in ours.iter().zip(&printed).zip(&exact).enumerate() {
        let printed_rel = (a - b).abs() / b;
        let exact_rel = (a - c).abs() / c;
        assert!(
            printed_rel <= 1e-6 && exact_rel <= 1e-9,
            "{name}: mode {} is {a} Hz; CalculiX prints {b} Hz ({printed_rel:.1e}), its K and M give \
             {c} Hz ({exact_rel:.1e})",
            mode + 1
        );
    }
    eprintln!(
        "{name}: {} frequencies agree with CalculiX's; ours {ours:?}",
        ours.len()
    );
    model
}

#[test]
fn equations_match_calculix_matrix_by_matrix() {
    let model = frequencies_match("equation_bar");
    // Both programs eliminate the first DOF of each equation: the same
    // independent DOFs, and the same K and M.
    let ours = assemble(&model).unwrap();
    let ccx = ccx_matrices("equation_bar");
    let to_ours = ccx_to_ours(&model, &ccx);
    for (what, a, b) in [
        ("K", &ours.stiffness, &ccx.stiffness),
        ("M", &ours.mass, &ccx.mass),
    ] {
        let (relative, scaled) = compare_matrix(what, a, b, &to_ours, &ccx)
            .unwrap_or_else(|report| panic!("equation_bar {report}"));
        eprintln!(
            "equation_bar {what}: largest |a - b| / |b| {relative:.1e} (allowed {MATRIX_RTOL:e}), \
             below the floor {scaled:.1e} (allowed {MATRIX_ATOL:e})"
        );
    }
    // The tip face's uz are one: the equations hold in every mode.
    let s = assemble(&model).unwrap();
    let modes = eigenmodes(&s.stiffness, &s.mass, Wanted::Lowest(4)).unwrap();
    let tip: Vec<u64> = model
        .nodes()
        .iter()
        .filter(|n| (n.coords[0] - 0.6).abs() < 1e-12)
        .map(|n| n.id)
        .collect();
    for k in 0..4 {
        let u: Vec<f64> = (0..model.dof_map().len())
            .map(|i| modes.vectors[(i, k)])
            .collect();
        let uz: Vec<f64> = tip
            .iter()
            .map(|n| model.value(Dof::new(*n, DofKind::Uz), &u))
            .collect();
        for w in &uz {
            assert!(
                (w - uz[0]).abs() <= 1e-12 * uz[0].abs().max(1e-300),
                "{uz:?}"
            );
        }
    }
}

#[test]
fn plane_straight_and_beam_mpcs_match_calculix() {
    frequencies_match("mpc_bar");
}

#[test]
fn a_rigid_body_with_a_point_mass_matches_calculix() {
    let model = frequencies_match("rigid_body_bar");
    // The reference node carries the face: six DOFs, the face's none.
    for k in DofKind::ALL {
        assert!(model.dof_map().index_of(Dof::new(9001, k)).is_some());
    }
}

#[test]
fn a_distributing_coupling_matches_calculix() {
    frequencies_match("distributing_bar");
}

/// A finer block tied to the bar's far face by `*TIE` (element surfaces,
/// non-matching nodes): the slave nodes follow the master faces' bilinear
/// interpolation, as in CalculiX. Both eliminate the slave translations:
/// K and M agree entry by entry to 1e-7 of their row and column scale
/// (measured 2e-9, 1e-8 of the entry: ccx's projection of the slave nodes
/// onto the master faces stops at about that, where flexbody's reaches
/// round-off; the frequencies agree to 1e-9 all the same).
#[test]
fn a_tied_non_matching_block_matches_calculix() {
    let model = frequencies_match("tie_blocks");
    let ours = assemble(&model).unwrap();
    let ccx = ccx_matrices("tie_blocks");
    let to_ours = ccx_to_ours(&model, &ccx);
    for (what, a, b) in [
        ("K", &ours.stiffness, &ccx.stiffness),
        ("M", &ours.mass, &ccx.mass),
    ] {
        let (a, b) = (a.to_dense(), b.to_dense());
        let n = to_ours.len();
        let mut worst = 0.0_f64;
        for i in 0..n {
            for j in 0..n {
                let scale = (b[(i, i)] * b[(j, j)]).abs().sqrt();
                let d = (a[(to_ours[i], to_ours[j])] - b[(i, j)]).abs() / scale;
                worst = worst.max(d);
            }
        }
        eprintln!("tie_blocks {what}: largest |a - b| / sqrt(b_ii b_jj) {worst:.1e}");
        assert!(worst < 1e-7, "tie_blocks {what}: {worst:e}");
    }
}

/// `*TRANSFORM`: the tip face held tangentially in a cylindrical system
/// about the bar's axis, a node held along an inclined axis, and an
/// `*EQUATION` with a term along a local axis (without that node's
/// `*TRANSFORM` the frequencies move by up to 16 %, so the term's
/// direction is tested). In every mode, the local components held are zero.
#[test]
fn local_systems_match_calculix() {
    let model = frequencies_match("transform_bar");
    let s = assemble(&model).unwrap();
    let modes = eigenmodes(&s.stiffness, &s.mass, Wanted::Lowest(4)).unwrap();
    let node = |n| {
        model
            .nodes()
            .iter()
            .find(|x| x.id == n)
            .map(|x| x.coords)
            .unwrap()
    };
    let set = |name: &str| model.node_sets()[name].clone();
    for m in 0..modes.values.len() {
        let u: Vec<f64> = modes.vectors.col(m).iter().copied().collect();
        let disp = |n: u64| -> [f64; 3] {
            [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|k| model.value(Dof::new(n, k), &u))
        };
        let size = (0..u.len()).map(|i| u[i].abs()).fold(0.0, f64::max);
        // Tip: tangential = axis x radial, the axis along x through the
        // middle of the cross-section.
        for n in set("TIPT") {
            let x = node(n);
            let radial = [0.0, x[1] - 0.05, x[2] - 0.05];
            let tangential = [0.0, -radial[2], radial[1]];
            let d = disp(n);
            let t: f64 = (0..3).map(|i| d[i] * tangential[i]).sum();
            assert!(
                t.abs() < 1e-12 * size,
                "mode {m}: node {n} moves tangentially by {t:e}"
            );
        }
        // Inclined: local x along (1, 1, 0).
        let n = set("INCLINED")[0];
        let d = disp(n);
        assert!(
            (d[0] + d[1]).abs() < 1e-12 * size,
            "mode {m}: node {n}: {d:?}"
        );
        // The equation: local x of LOCALTERM, along (0, 1, 1), equals uz of
        // the other node.
        let n = set("LOCALTERM")[0];
        let d = disp(n);
        let equation = &model.equations()[0];
        let other = equation.terms.last().unwrap().0.node;
        let lhs = (d[1] + d[2]) / 2f64.sqrt();
        assert!((lhs - disp(other)[2]).abs() < 1e-12 * size, "mode {m}");
    }
}
