//! Verification of the beam elements against beam theory.

use crate::dof::{Dof, DofKind};
use crate::element::{Element, PointMass};
use crate::mesh::{BeamLine, BeamLineKind};
use crate::model::Model;
use crate::section::{BeamProperties, BeamTheory, Material, SectionShape};
use crate::{assemble, SystemMatrices};
use faer::Mat;
use flexbody_linalg::eigen::generalized_symmetric;

const E: f64 = 2.1e11;
const RHO: f64 = 7850.0;

fn props(theory: BeamTheory) -> BeamProperties {
    let section = SectionShape::Rect {
        width: 0.04,
        height: 0.06,
    }
    .constants()
    .unwrap();
    BeamProperties::new(Material::new(E, 0.3, RHO).unwrap(), section, theory)
}

/// A straight line of `n` elements from `a` to `b`; 3D beams when `planar`
/// is false. Nodes 1..=n+1; `fixed_start` clamps node 1.
fn line(
    n: usize,
    a: [f64; 3],
    b: [f64; 3],
    planar: bool,
    theory: BeamTheory,
    fixed_start: bool,
) -> Model {
    let kind = if planar {
        BeamLineKind::Planar
    } else {
        BeamLineKind::Spatial {
            // Local y: global y for beams along x, else global z.
            orientation: if (b[1] - a[1]).abs() + (b[2] - a[2]).abs() == 0.0 {
                [0.0, 1.0, 0.0]
            } else {
                [0.0, 0.0, 1.0]
            },
        }
    };
    let kinds: &[DofKind] = if planar {
        &[DofKind::Uz, DofKind::Ry]
    } else {
        &DofKind::ALL
    };
    let fixed = if fixed_start {
        kinds.iter().map(|k| Dof::new(1, *k)).collect()
    } else {
        vec![]
    };
    BeamLine {
        cells: n,
        start: a,
        end: b,
        kind,
        properties: props(theory),
    }
    .model(fixed)
    .unwrap()
}

fn eigenvalues(s: &SystemMatrices) -> Vec<f64> {
    generalized_symmetric(s.stiffness.to_dense().as_ref(), s.mass.to_dense().as_ref())
        .unwrap()
        .values
}

/// beta_n L of the elastic modes, from omega = (beta L)^2 sqrt(E I / (rho A L^4)).
fn beta_l(lambda: f64, ei: f64, rho_a: f64, l: f64) -> f64 {
    (lambda.sqrt() * (rho_a * l.powi(4) / ei).sqrt()).sqrt()
}

/// Asserts that the eigenvalues `lambdas` give the `exact` values of beta L
/// (beam theory of the `case`) to 1e-4.
fn assert_beta_l(lambdas: &[f64], exact: [f64; 3], ei: f64, rho_a: f64, l: f64, case: &str) {
    for (lam, exact) in lambdas.iter().zip(exact) {
        let b = beta_l(*lam, ei, rho_a, l);
        assert!(
            (b - exact).abs() / exact < 1e-4,
            "{case} beta L {b} vs {exact}"
        );
    }
}

#[test]
fn planar_free_free_and_cantilever_frequencies_converge() {
    let l = 2.0;
    let p = props(BeamTheory::EulerBernoulli);
    let (ei, rho_a) = (E * p.section.iy, RHO * p.section.area);
    let free = eigenvalues(
        &assemble(&line(
            40,
            [0.0; 3],
            [l, 0.0, 0.0],
            true,
            BeamTheory::EulerBernoulli,
            false,
        ))
        .unwrap(),
    );
    // Two rigid-body modes (heave, pitch), then the elastic ones.
    assert!(free[0].abs() < 1e-6 * free[2] && free[1].abs() < 1e-6 * free[2]);
    assert_beta_l(
        &free[2..5],
        [4.730_040_745, 7.853_204_624, 10.995_607_838],
        ei,
        rho_a,
        l,
        "free-free",
    );
    let clamped =
        eigenvalues(&assemble(&cantilever(40, l, true, BeamTheory::EulerBernoulli)).unwrap());
    assert_beta_l(
        &clamped[..3],
        [1.875_104_069, 4.694_091_133, 7.854_757_438],
        ei,
        rho_a,
        l,
        "cantilever",
    );
}

#[test]
fn skew_3d_beam_has_six_rigid_modes_and_both_bending_planes() {
    let l = 2.0;
    let dir = [2.0_f64, 1.0, -0.5];
    let nd = (dir.iter().map(|x| x * x).sum::<f64>()).sqrt();
    let a = [0.3, -0.2, 0.1];
    let b = [0, 1, 2].map(|k| a[k] + dir[k] / nd * l);
    let p = props(BeamTheory::EulerBernoulli);
    let lam =
        eigenvalues(&assemble(&line(40, a, b, false, BeamTheory::EulerBernoulli, false)).unwrap());
    let first_elastic = lam[6];
    assert!(
        lam[..6].iter().all(|x| x.abs() < 1e-9 * first_elastic),
        "{:?}",
        &lam[..7]
    );
    // First bending mode in each plane: Iz (weak, width 0.04 along y) and Iy.
    let want_weak = beta_l(lam[6], E * p.section.iz, RHO * p.section.area, l);
    assert!(
        (want_weak - 4.730_040_745).abs() / 4.73 < 1e-4,
        "{want_weak}"
    );
    let strong = lam
        .iter()
        .map(|x| beta_l(*x, E * p.section.iy, RHO * p.section.area, l))
        .find(|b| (b - 4.730_040_745).abs() < 1e-3)
        .expect("first bending mode about local y");
    assert!((strong - 4.730_040_745).abs() / 4.73 < 1e-4);
}

/// A cantilever of `n` elements along global x from the origin to `l`,
/// clamped at node 1; 3D beams when `planar` is false.
fn cantilever(n: usize, l: f64, planar: bool, theory: BeamTheory) -> Model {
    line(n, [0.0; 3], [l, 0.0, 0.0], planar, theory, true)
}

/// Static tip deflection of a cantilever under a tip force P, solved on the
/// full model.
fn tip_deflection(model: &Model, tip: Dof, load: f64) -> f64 {
    let s = assemble(model).unwrap();
    let n = model.dof_map().len();
    let i = model.dof_map().index_of(tip).unwrap();
    let mut f = Mat::<f64>::zeros(n, 1);
    f[(i, 0)] = load;
    let ldlt = flexbody_linalg::ldlt::Factor::of(&s.stiffness).unwrap();
    ldlt.solve(f.as_ref())[(i, 0)]
}

#[test]
fn cantilever_tip_load_is_exact_for_both_theories() {
    let (l, p_load) = (1.5, 1000.0);
    let p = props(BeamTheory::Timoshenko);
    let ei = E * p.section.iy;
    let eb = cantilever(3, l, false, BeamTheory::EulerBernoulli);
    let w = tip_deflection(&eb, Dof::new(4, DofKind::Uz), p_load);
    let exact = p_load * l.powi(3) / (3.0 * ei);
    assert!((w - exact).abs() / exact < 1e-12, "{w} vs {exact}");
    let ti = cantilever(3, l, false, BeamTheory::Timoshenko);
    let w = tip_deflection(&ti, Dof::new(4, DofKind::Uz), p_load);
    let shear = p_load * l / (p.material.shear_modulus * p.section.shear_area_z);
    assert!(
        (w - (exact + shear)).abs() / exact < 1e-12,
        "{w} vs {}",
        exact + shear
    );
    let planar = cantilever(3, l, true, BeamTheory::EulerBernoulli);
    let w = tip_deflection(&planar, Dof::new(4, DofKind::Uz), p_load);
    assert!((w - exact).abs() / exact < 1e-12);
}

#[test]
fn short_timoshenko_cantilever_is_softer_than_euler_bernoulli() {
    let l = 0.3; // length / depth = 5
    let eb = eigenvalues(&assemble(&cantilever(30, l, false, BeamTheory::EulerBernoulli)).unwrap());
    let ti = eigenvalues(&assemble(&cantilever(30, l, false, BeamTheory::Timoshenko)).unwrap());
    // Torsion and axial modes are the same in both theories; bending modes
    // (the two first ones, weak and strong axis) are lower with shear.
    for i in 0..6 {
        assert!(
            ti[i] <= eb[i] * (1.0 + 1e-9),
            "mode {i}: Timoshenko {} vs Euler-Bernoulli {}",
            ti[i],
            eb[i]
        );
    }
    assert!(
        ti[0] < 0.99 * eb[0] && ti[1] < 0.98 * eb[1],
        "{:?} vs {:?}",
        &ti[..2],
        &eb[..2]
    );
}

#[test]
fn point_mass_adds_only_to_existing_dofs() {
    let mut m = line(
        2,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        true,
        BeamTheory::EulerBernoulli,
        false,
    );
    let base = assemble(&m).unwrap();
    let mut elements = m.elements().to_vec();
    elements.push(Element::PointMass(PointMass {
        id: 9,
        node: 2,
        mass: 5.0,
        inertia: [1.0, 2.0, 3.0, 0.0, 0.0, 0.0],
    }));
    m = Model::of(m.nodes().to_vec(), elements).build().unwrap();
    let with = assemble(&m).unwrap();
    assert_eq!(m.dof_map().len(), 6);
    let uz = m.dof_map().index_of(Dof::new(2, DofKind::Uz)).unwrap();
    let ry = m.dof_map().index_of(Dof::new(2, DofKind::Ry)).unwrap();
    let (a, b) = (with.mass.to_dense(), base.mass.to_dense());
    assert!((a[(uz, uz)] - b[(uz, uz)] - 5.0).abs() < 1e-12);
    assert!((a[(ry, ry)] - b[(ry, ry)] - 2.0).abs() < 1e-12);
}

/// `sum_g m_g U_g^T U_g + Theta_g^T J_g Theta_g` over the mass points of
/// every element of `model` against its own mass matrix.
fn assert_points_hold_the_mass_matrix(model: &Model, case: &str) {
    use crate::element::MassDistribution;
    for e in model.elements() {
        let m = e.matrices(model).unwrap().mass;
        let MassDistribution::Points(points) = e.mass_distribution(model).unwrap() else {
            panic!("{case}: element {} has no mass points", e.id());
        };
        let n = m.nrows();
        let mut sum = Mat::<f64>::zeros(n, n);
        for p in &points {
            let j = Mat::from_fn(3, 3, |a, b| p.inertia[a][b]);
            sum += p.translation.transpose() * &p.translation * faer::Scale(p.mass)
                + p.rotation.transpose() * &j * &p.rotation;
        }
        let error = (&sum - &m).norm_max() / m.norm_max();
        assert!(error < 1e-13, "{case}, element {}: {error:e}", e.id());
    }
}

#[test]
fn mass_points_hold_each_element_mass_matrix() {
    // 3D beams along a skew axis, both theories (Timoshenko with rotary
    // inertia, Euler-Bernoulli without), and planar beams along +x and -x.
    for theory in [BeamTheory::Timoshenko, BeamTheory::EulerBernoulli] {
        let skew = line(3, [0.1, -0.2, 0.3], [1.1, 0.7, -0.5], false, theory, true);
        assert_points_hold_the_mass_matrix(&skew, &format!("skew 3D {theory:?}"));
    }
    for (a, b) in [([0.0; 3], [1.0, 0.0, 0.0]), ([1.0, 0.0, 0.0], [0.0; 3])] {
        let planar = line(2, a, b, true, BeamTheory::EulerBernoulli, false);
        assert_points_hold_the_mass_matrix(&planar, &format!("planar from {a:?}"));
    }
    // A point mass with a full inertia tensor on a 3D beam's node.
    let beam = line(
        1,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        false,
        BeamTheory::Timoshenko,
        false,
    );
    let mut elements = beam.elements().to_vec();
    elements.push(Element::PointMass(PointMass {
        id: 9,
        node: 2,
        mass: 5.0,
        inertia: [1.0, 2.0, 3.0, 0.1, -0.2, 0.3],
    }));
    let with_mass = Model::of(beam.nodes().to_vec(), elements).build().unwrap();
    assert_points_hold_the_mass_matrix(&with_mass, "point mass");
}
