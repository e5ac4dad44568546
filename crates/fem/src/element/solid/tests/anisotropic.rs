//! Anisotropic solids: an orientation rotates `C` exactly as a material
//! rotated by hand (the Bond matrix), isotropic `C` through the general
//! path gives the isotropic stiffness, stresses use the anisotropic `C`.

use super::{distorted, max_abs, solid, RHO};
use crate::anisotropy::tests::{bond_rotate, general, isotropic};
use crate::anisotropy::{Anisotropy, Orientation};
use crate::element::solid::SolidKind;
use crate::section::Material;
use faer::Mat;

fn with(kind: SolidKind, anisotropy: Anisotropy) -> super::Solid {
    let mut s = solid(kind);
    s.material = Material::anisotropic(anisotropy, RHO).unwrap();
    s
}

fn assert_close(a: &Mat<f64>, b: &Mat<f64>, tol: f64) {
    let scale = max_abs(a);
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            let d = (a[(i, j)] - b[(i, j)]).abs();
            assert!(
                d <= tol * scale,
                "({i}, {j}): {} vs {} ({d:e})",
                a[(i, j)],
                b[(i, j)]
            );
        }
    }
}

#[test]
fn orientation_equals_the_material_rotated_by_hand() {
    let c =
        Anisotropy::engineering([1.4e11, 9.0e9, 1.1e10], 0.28, 0.31, 0.4, 5e9, 4e9, 3e9).unwrap();
    let orientation = Orientation::rectangular([0.8, 0.5, -0.3], [-0.2, 0.9, 0.4]).unwrap();
    let r = orientation.axes_at([0.0; 3]).unwrap();
    for kind in SolidKind::ALL {
        let x = distorted(kind, 11, 0.1);
        let rotated = with(kind, Anisotropy::new(c, Some(orientation.clone())).unwrap());
        let by_hand = with(kind, Anisotropy::new(bond_rotate(&c, &r), None).unwrap());
        let (a, b) = (rotated.matrices(&x).unwrap(), by_hand.matrices(&x).unwrap());
        assert_close(&a.stiffness, &b.stiffness, 1e-12);
        assert_close(&a.mass, &b.mass, 0.0);
    }
}

#[test]
fn isotropic_elasticity_on_the_general_path_equals_the_fast_path() {
    let (e, nu) = (super::E, super::NU);
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let mu = e / (2.0 * (1.0 + nu));
    let orientation = Orientation::cylindrical([5.0, 0.0, 0.0], [5.0, 1.0, 3.0]).unwrap();
    // Not C3D8R: its hourglass stiffness scales with E for an isotropic
    // material and with C_xxxx (lambda + 2 mu here) for an anisotropic one,
    // as CalculiX's does (the `ortho_rotated_c3d8r` CalculiX fixture).
    for kind in SolidKind::ALL
        .into_iter()
        .filter(|k| *k != SolidKind::C3D8R)
    {
        let x = distorted(kind, 3, 0.1);
        let iso = solid(kind).matrices(&x).unwrap();
        let general = with(
            kind,
            Anisotropy::new(isotropic(lambda, mu), Some(orientation.clone())).unwrap(),
        )
        .matrices(&x)
        .unwrap();
        assert_close(&iso.stiffness, &general.stiffness, 1e-13);
    }
}

#[test]
fn stresses_use_the_anisotropic_elasticity() {
    // A homogeneous strain: every node and point carries sigma = C' eps.
    let c = general();
    let orientation = Orientation::rectangular([0.8, 0.5, -0.3], [-0.2, 0.9, 0.4]).unwrap();
    let global = bond_rotate(&c, &orientation.axes_at([0.0; 3]).unwrap());
    let h = [
        [1e-4, 2e-5, -3e-5],
        [4e-5, -2e-4, 1e-5],
        [-1e-5, 3e-5, 5e-5],
    ];
    let eps = [
        h[0][0],
        h[1][1],
        h[2][2],
        h[0][1] + h[1][0],
        h[1][2] + h[2][1],
        h[2][0] + h[0][2],
    ];
    let expected: Vec<f64> = (0..6)
        .map(|i| (0..6).map(|j| global[i][j] * eps[j]).sum())
        .collect();
    for kind in SolidKind::ALL {
        let x = distorted(kind, 5, 0.1);
        let u: Vec<f64> = x
            .iter()
            .flat_map(|p| [0, 1, 2].map(|i| (0..3).map(|j| h[i][j] * p[j]).sum::<f64>()))
            .collect();
        let s = with(kind, Anisotropy::new(c, Some(orientation.clone())).unwrap());
        for sn in s.nodal_stresses(&x, &u).unwrap() {
            for (a, b) in sn.iter().zip(&expected) {
                assert!(
                    (a - b).abs() < 1e-9 * 1e7,
                    "{kind:?}: {sn:?} vs {expected:?}"
                );
            }
        }
    }
}

#[test]
fn a_point_on_the_cylinder_axis_is_an_error() {
    // C3D4 integrates at its centroid: put the axis through it.
    let x = distorted(SolidKind::C3D4, 1, 0.0);
    let c: [f64; 3] = std::array::from_fn(|i| x.iter().map(|p| p[i]).sum::<f64>() / 4.0);
    let axis = Orientation::cylindrical(c, [c[0], c[1], c[2] + 1.0]).unwrap();
    let s = with(
        SolidKind::C3D4,
        Anisotropy::new(general(), Some(axis)).unwrap(),
    );
    let err = s.matrices(&x).unwrap_err().to_string();
    assert!(err.contains("on the axis"), "{err}");
}
