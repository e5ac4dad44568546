//! The SID file's FFRF invariants against the full model: mass properties
//! and elastic modes of solids and beams.

use super::support::{hex_beam, reduce_with};
use flexbody::export::sid::Sid;
use flexbody::fem::{Model, Substructure};
use flexbody::input::{load, MatrixFiles};
use flexbody::output;
use flexbody::reduce::{Method, ReducedBody};

/// A free 3D beam (10 Euler-Bernoulli elements along x, offset from the
/// origin), with its analytical mass properties.
const BEAM_3D: &str = r#"
title = "free 3D beam"
[[material]]
name = "steel"
youngs_modulus = 2.1e11
density = 7850.0
[[section]]
name = "s"
shape = "general"
area = 0.01
iy = 2.0e-5
iz = 1.0e-5
torsion = 3.0e-5
[[beam_line]]
element = "beam"
rotary_inertia = false
from = [0.5, 0.2, -0.1]
to = [2.5, 0.2, -0.1]
elements = 10
first_node = 1
material = "steel"
section = "s"
orientation = [0.0, 0.0, 1.0]
"#;

fn beam_3d() -> (Substructure, Model) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("beam.toml");
    std::fs::write(&path, BEAM_3D).unwrap();
    let c = load(&path, &MatrixFiles::default()).unwrap();
    (c.sub, c.model.unwrap())
}

fn assert_close(what: &str, got: f64, want: f64, scale: f64) {
    assert!(
        (got - want).abs() <= 1e-11 * scale,
        "{what}: {got} against {want} (scale {scale})"
    );
}

/// Mass, centre of mass and inertia tensor (about the origin) of the SID
/// against the analytical values of the full model.
fn check_mass_properties(sid: &Sid, mass: f64, center: [f64; 3], inertia: [[f64; 3]; 3]) {
    assert_close("mass", sid.refmod.mass, mass, mass);
    let c = sid.center_of_mass();
    for i in 0..3 {
        assert_close("centre of mass", c[i], center[i], 1.0);
    }
    let scale = inertia[0][0]
        .abs()
        .max(inertia[1][1].abs())
        .max(inertia[2][2].abs());
    for (i, row) in inertia.iter().enumerate() {
        for (j, want) in row.iter().enumerate() {
            assert_close(&format!("J({i}, {j})"), sid.j.m0[(i, j)], *want, scale);
        }
    }
}

/// Mean-axis elastic modes: no rigid-body part (`Ct = Cr = 0`), unit modal
/// mass, and the non-zero frequencies of the reduced body.
fn check_elastic_modes(sid: &Sid, body: &ReducedBody, rigid: usize) {
    let nq = sid.nq();
    assert_eq!(nq + rigid, body.r());
    let scale = sid.refmod.mass.sqrt() * 10.0;
    assert!(sid.ct.m0.norm_max() < 1e-9 * scale, "Ct = {:?}", sid.ct.m0);
    assert!(sid.cr.m0.norm_max() < 1e-9 * scale, "Cr = {:?}", sid.cr.m0);
    for i in 0..nq {
        for j in 0..nq {
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((sid.me.m0[(i, j)] - want).abs() < 1e-9, "Me({i}, {j})");
        }
    }
    let ours = sid.frequencies_hz().unwrap();
    let full = body.frequencies_hz().unwrap();
    for (a, b) in ours.iter().zip(&full[rigid..]) {
        assert!((a - b).abs() < 1e-7 * b, "{a} Hz against {b} Hz");
    }
}

fn box_inertia(m: f64, a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    // Box [0,a] x [0,b] x [0,c] about the origin.
    let (xx, yy, zz) = (m * a * a / 3.0, m * b * b / 3.0, m * c * c / 3.0);
    let (xy, yz, zx) = (m * a * b / 4.0, m * b * c / 4.0, m * c * a / 4.0);
    [
        [yy + zz, -xy, -zx],
        [-xy, xx + zz, -yz],
        [-zx, -yz, xx + yy],
    ]
}

/// The SID of `body`, a reduction of the hex-element beam `sub` with mesh
/// `model`, checked against the beam's mass properties (steel, 0.6 x 0.1 x
/// 0.1 m from the origin) and its elastic modes.
fn hex_beam_sid(sub: &Substructure, model: &Model, body: &ReducedBody) -> Sid {
    let sid = output::sid(sub, Some(model), body).unwrap();
    let mass = 7850.0 * 0.6 * 0.1 * 0.1;
    check_mass_properties(
        &sid,
        mass,
        [0.3, 0.05, 0.05],
        box_inertia(mass, 0.6, 0.1, 0.1),
    );
    check_elastic_modes(&sid, body, 6);
    sid
}

#[test]
fn sid_of_a_solid_has_the_mass_properties_of_the_full_model() {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::FreeResidual, 4, &[13]);
    let sid = hex_beam_sid(&sub, &model, &body);
    // First-order J: for a translation-free mode, int Phi dm = 0 (mdCM m1
    // equals Ct), and J(q) stays symmetric.
    for k in 0..sid.nq() {
        let j1 = &sid.j.m1[k];
        assert!((j1 - j1.transpose()).norm_max() < 1e-9 * j1.norm_max().max(1.0));
        for i in 0..3 {
            assert_eq!(sid.md_cm.m1[k][(i, 0)], sid.ct.m0[(k, i)]);
        }
    }
    // One interface node with 3 translations; 6 stress rows per node.
    assert_eq!(sid.nodes.len(), 1);
    assert_eq!(sid.nodes[0].origin.m0[(0, 0)], 0.6);
    assert_eq!(sid.ksigma.nrow, 6 * model.nodes().len());
}

#[test]
fn sid_of_a_craig_bampton_solid_removes_the_rigid_motion_of_its_constraint_modes() {
    let (sub, model) = hex_beam();
    let body = reduce_with(&sub, Method::CraigBampton, 3, &[1, 27, 79, 13]);
    hex_beam_sid(&sub, &model, &body);
}

#[test]
fn sid_of_a_beam_has_the_mass_properties_of_the_full_model() {
    let (sub, model) = beam_3d();
    let body = reduce_with(&sub, Method::FreeResidual, 3, &[1, 11]);
    let sid = output::sid(&sub, Some(&model), &body).unwrap();
    let (rho, area, l, ip) = (7850.0, 0.01, 2.0, 3.0e-5);
    let mass = rho * area * l;
    let c = [1.5, 0.2, -0.1];
    // Slender rod along x about its centre, torsional inertia rho Ip L,
    // then the parallel-axis theorem to the origin.
    let jc = [rho * ip * l, mass * l * l / 12.0, mass * l * l / 12.0];
    let c2 = c.iter().map(|x| x * x).sum::<f64>();
    let inertia: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| (if i == j { jc[i] + mass * c2 } else { 0.0 }) - mass * c[i] * c[j])
    });
    check_mass_properties(&sid, mass, c, inertia);
    check_elastic_modes(&sid, &body, 6);
    assert_eq!(sid.nodes.len(), 2);
    assert_eq!(sid.ksigma.nrow, 12 * 10);
}
