//! Patch tests: patches of 2x2x2 hexahedral cells (cut into tetrahedra or
//! wedges for those kinds) with a linear displacement field.

use super::{affine, assert_exact_stress, exact_stress, linear_field, max_abs, steel};
use super::{GRADIENT, OFFSET};
use crate::element::mat_vec;
use crate::element::solid::{Solid, SolidKind};
use crate::mesh::{SolidBlock, SolidMesh};

/// A mesh for patch tests: `cells^3` hexahedral cells over the unit cube,
/// each cut into the elements of `kind` (a [`SolidBlock`]), through the
/// global [`affine`] map; interior grid points moved at random if
/// `move_corners` and interior mid-edge nodes moved off their edges'
/// midpoints (curved edges) if `curve_edges`.
fn patch(kind: SolidKind, cells: usize, move_corners: bool, curve_edges: bool) -> SolidMesh {
    let mut mesh = SolidBlock {
        kind,
        cells: [cells; 3],
        origin: [0.0; 3],
        size: [1.0; 3],
        corner_distortion: if move_corners { 0.2 } else { 0.0 },
        edge_distortion: if curve_edges { 0.05 } else { 0.0 },
        seed: 5,
    }
    .mesh();
    mesh.coords = mesh.coords.iter().map(|&x| affine(x)).collect();
    mesh
}

/// Patch test with `u = a + B x` on every node: asserts that every element
/// reproduces the exact stress at its nodes and returns the largest
/// assembled internal force at an interior node relative to `|K| |u|`
/// (round-off if the patch test is passed).
fn patch_residual(kind: SolidKind, move_corners: bool, curve_edges: bool) -> f64 {
    let p = patch(kind, 2, move_corners, curve_edges);
    let n = 3 * p.coords.len();
    let u = linear_field(OFFSET, GRADIENT, &p.coords);
    let mut f = vec![0.0; n];
    let mut k_max = 0.0_f64;
    let sigma = exact_stress(GRADIENT);
    for (id, nodes) in p.elements.iter().enumerate() {
        let element = Solid {
            id,
            kind,
            nodes: nodes.iter().map(|&i| i as u64).collect(),
            material: steel(),
        };
        let x: Vec<[f64; 3]> = nodes.iter().map(|&i| p.coords[i]).collect();
        let em = element.matrices(&x).unwrap();
        k_max = k_max.max(max_abs(&em.stiffness));
        let ue: Vec<f64> = nodes
            .iter()
            .flat_map(|&i| [u[3 * i], u[3 * i + 1], u[3 * i + 2]])
            .collect();
        let fe = mat_vec(&em.stiffness, &ue);
        for (a, &i) in nodes.iter().enumerate() {
            for c in 0..3 {
                f[3 * i + c] += fe[3 * a + c];
            }
        }
        for (a, s) in element.nodal_stresses(&x, &ue).unwrap().iter().enumerate() {
            assert_exact_stress(s, &sigma, format_args!("{kind:?} element {id} node {a}"));
        }
    }
    let u_max = u.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let interior: Vec<usize> = (0..p.coords.len()).filter(|&i| !p.on_boundary(i)).collect();
    assert!(!interior.is_empty(), "{kind:?} patch without interior node");
    let f_max = interior
        .iter()
        .flat_map(|&i| f[3 * i..3 * i + 3].to_vec())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    f_max / (k_max * u_max)
}

#[test]
fn patch_test_of_affine_patches() {
    for kind in SolidKind::ALL {
        let r = patch_residual(kind, false, false);
        assert!(r <= 1e-12, "{kind:?}: interior forces {r:e} of |K| |u|");
    }
}

#[test]
fn patch_test_of_distorted_patches() {
    // Interior corners moved; curved interior edges for the quadratic
    // elements.
    let triangle_rule_of_degree_2 = [SolidKind::C3D10, SolidKind::C3D15];
    for kind in SolidKind::ALL {
        let curved = !triangle_rule_of_degree_2.contains(&kind);
        let r = patch_residual(kind, true, curved);
        assert!(r <= 1e-12, "{kind:?}: interior forces {r:e} of |K| |u|");
    }
    // C3D10 and C3D15 with curved edges do not pass: their rules (4 points;
    // 3 points in the triangle) integrate the stiffness exactly only where
    // for straight-edged elements. CalculiX's C3D10 and C3D15
    // are the same elements (calculix.rs compares curved ones).
    for kind in triangle_rule_of_degree_2 {
        let r = patch_residual(kind, true, true);
        assert!(
            r > 1e-8,
            "curved {kind:?} patch: interior forces {r:e} of |K| |u|"
        );
    }
}
