//! Geometry and input checks: inverted, flat and wrongly connected
//! elements, bad material and coordinates, elements far from the origin.

use super::{distorted, solid};
use crate::element::solid::SolidKind;
use crate::FemError;

fn reason(e: FemError) -> String {
    match e {
        FemError::InvalidElement { element, reason } => {
            assert_eq!(element, 7);
            reason
        }
        other => panic!("unexpected error {other}"),
    }
}

/// A node order that turns the element inside out: swaps the two ends of
/// the element (hexahedra, wedge) or two corners (tetrahedra), with the
/// mid-edge nodes that go with them.
fn reversed(kind: SolidKind) -> Vec<usize> {
    match kind {
        SolidKind::C3D8 | SolidKind::C3D8I | SolidKind::C3D8R => vec![4, 5, 6, 7, 0, 1, 2, 3],
        SolidKind::C3D20 | SolidKind::C3D20R => vec![
            4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19,
        ],
        SolidKind::C3D4 => vec![0, 2, 1, 3],
        // Corners 2 <-> 3; edges 1-2 <-> 3-1, 2-4 <-> 3-4.
        SolidKind::C3D10 => vec![0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
        SolidKind::C3D6 => vec![3, 4, 5, 0, 1, 2],
        SolidKind::C3D15 => vec![3, 4, 5, 0, 1, 2, 9, 10, 11, 6, 7, 8, 12, 13, 14],
    }
}

#[test]
fn inverted_elements_are_rejected() {
    for kind in SolidKind::ALL {
        let x = distorted(kind, 47, 0.1);
        solid(kind).validate(&x).unwrap();
        let swapped: Vec<[f64; 3]> = reversed(kind).iter().map(|&i| x[i]).collect();
        let r = reason(solid(kind).validate(&swapped).unwrap_err());
        assert!(
            r.starts_with("inverted: negative Jacobian at integration point 1"),
            "{kind:?}: {r}"
        );
        let mirrored: Vec<[f64; 3]> = x.iter().map(|p| [-p[0], p[1], p[2]]).collect();
        let r = reason(solid(kind).matrices(&mirrored).unwrap_err());
        assert!(r.starts_with("inverted"), "{kind:?}: {r}");
    }
    // Two corner nodes of a hexahedron swapped: a twisted element, inverted
    // at some integration points only.
    let mut x = distorted(SolidKind::C3D8, 47, 0.0);
    x.swap(0, 1);
    let r = reason(solid(SolidKind::C3D8).validate(&x).unwrap_err());
    assert!(r.starts_with("inverted"), "{r}");
}

#[test]
fn flat_elements_are_rejected() {
    for kind in SolidKind::ALL {
        let x: Vec<[f64; 3]> = distorted(kind, 53, 0.1)
            .iter()
            .map(|p| [p[0], p[1], 0.25])
            .collect();
        let r = reason(solid(kind).validate(&x).unwrap_err());
        assert!(r.starts_with("zero volume"), "{kind:?}: {r}");
        assert!(solid(kind).volume(&x).is_err());
        assert!(solid(kind).matrices(&x).is_err());
    }
}

#[test]
fn wrong_node_count_is_rejected() {
    let x = distorted(SolidKind::C3D8, 1, 0.1);
    let r = reason(solid(SolidKind::C3D20).validate(&x).unwrap_err());
    assert_eq!(r, "C3D20 needs 20 nodes, got 8");
    let r = reason(solid(SolidKind::C3D8).validate(&x[..7]).unwrap_err());
    assert_eq!(r, "C3D8 needs 8 nodes, got 7");
}

#[test]
fn bad_material_and_coordinates_are_rejected() {
    let x = distorted(SolidKind::C3D4, 1, 0.1);
    let mut s = solid(SolidKind::C3D4);
    s.material.poisson_ratio = 0.5;
    assert!(reason(s.validate(&x).unwrap_err()).contains("Poisson"));
    let mut s = solid(SolidKind::C3D4);
    s.material.youngs_modulus = 0.0;
    assert!(reason(s.validate(&x).unwrap_err()).contains("Young"));
    let mut bad = x.clone();
    bad[2][1] = f64::NAN;
    assert!(reason(solid(SolidKind::C3D4).validate(&bad).unwrap_err()).contains("finite"));
}

#[test]
fn elements_far_from_the_origin_are_accepted() {
    // A 1 mm element 10 km away: the Jacobian is built from coordinates
    // relative to the first node.
    let x: Vec<[f64; 3]> = distorted(SolidKind::C3D10, 59, 0.1)
        .iter()
        .map(|p| [1e4 + 1e-3 * p[0], -1e4 + 1e-3 * p[1], 5e3 + 1e-3 * p[2]])
        .collect();
    let v = solid(SolidKind::C3D10).volume(&x).unwrap();
    let v0 = solid(SolidKind::C3D10)
        .volume(&distorted(SolidKind::C3D10, 59, 0.1))
        .unwrap();
    // Rounding the coordinates to f64 moves the nodes by 2e-12 m, 2e-9 of
    // the element size.
    assert!((v - 1e-9 * v0).abs() < 1e-7 * v, "{v} vs {}", 1e-9 * v0);
}
