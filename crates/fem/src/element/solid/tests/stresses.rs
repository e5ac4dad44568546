//! Nodal stresses: exact for a linear field on distorted elements,
//! extrapolated in a C3D8, and a wrong displacement length refused.

use super::{assert_exact_stress, distorted, exact_stress, linear_field, solid};
use super::{E, GRADIENT, NU, OFFSET};
use crate::element::solid::shape::{self};
use crate::element::solid::SolidKind;

#[test]
fn nodal_stresses_of_a_linear_field_are_exact_on_distorted_elements() {
    let sigma = exact_stress(GRADIENT);
    for kind in SolidKind::ALL {
        let x = distorted(kind, 17, 0.15);
        let u = linear_field(OFFSET, GRADIENT, &x);
        let stresses = solid(kind).nodal_stresses(&x, &u).unwrap();
        assert_eq!(stresses.len(), kind.node_count());
        for (a, s) in stresses.iter().enumerate() {
            assert_exact_stress(s, &sigma, format_args!("{kind:?} node {a}"));
        }
    }
}

#[test]
fn nodal_stresses_extrapolate_a_linear_stress_field_in_a_c3d8() {
    // u = (c x y, 0, 0) on the reference cube: sxx = (lambda + 2 mu) c y and
    // sxy = mu c x, linear, which the trilinear extrapolation from the Gauss
    // points reproduces at the nodes.
    let c = 1e-3;
    let x: Vec<[f64; 3]> = shape::node_coordinates(SolidKind::C3D8).to_vec();
    let u: Vec<f64> = x.iter().flat_map(|p| [c * p[0] * p[1], 0.0, 0.0]).collect();
    let s = solid(SolidKind::C3D8).nodal_stresses(&x, &u).unwrap();
    let lambda = E * NU / ((1.0 + NU) * (1.0 - 2.0 * NU));
    let mu = E / (2.0 * (1.0 + NU));
    for (p, sp) in x.iter().zip(&s) {
        let sxx = (lambda + 2.0 * mu) * c * p[1];
        let sxy = mu * c * p[0];
        for (component, want) in [(0, sxx), (3, sxy)] {
            assert!(
                (sp[component] - want).abs() < 1e-9 * want.abs(),
                "{p:?} component {component}: {} vs {want}",
                sp[component]
            );
        }
    }
}

#[test]
fn nodal_stresses_reject_a_wrong_displacement_length() {
    let x = distorted(SolidKind::C3D8, 1, 0.1);
    let e = solid(SolidKind::C3D8)
        .nodal_stresses(&x, &[0.0; 23])
        .unwrap_err();
    assert!(e.to_string().contains("24 displacement values"), "{e}");
}
