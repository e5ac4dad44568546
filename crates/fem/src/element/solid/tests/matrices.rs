//! Element matrices: rigid-body motions without strain energy, symmetry,
//! the spectrum of K and M, mass and volume.

use super::{distorted, dot, max_abs, solid, AFFINE, HEX_EDGES, RHO};
use crate::element::mat_vec;
use crate::element::solid::shape::{self};
use crate::element::solid::SolidKind;
use faer::Side;

/// The six rigid-body motions (translations, small rotations about the
/// origin) at the given points.
pub(super) fn rigid_modes(coords: &[[f64; 3]]) -> Vec<Vec<f64>> {
    let mut modes = Vec::new();
    for d in 0..3 {
        let mut t = [0.0; 3];
        t[d] = 1.0;
        modes.push(coords.iter().flat_map(|_| t).collect());
    }
    for d in 0..3 {
        let mut w = [0.0; 3];
        w[d] = 1.0;
        modes.push(
            coords
                .iter()
                .flat_map(|x| {
                    [
                        w[1] * x[2] - w[2] * x[1],
                        w[2] * x[0] - w[0] * x[2],
                        w[0] * x[1] - w[1] * x[0],
                    ]
                })
                .collect(),
        );
    }
    modes
}

#[test]
fn rigid_body_motions_have_no_strain_energy() {
    for kind in SolidKind::ALL {
        let x = distorted(kind, 23, 0.15);
        let em = solid(kind).matrices(&x).unwrap();
        let k_max = max_abs(&em.stiffness);
        for (r, u) in rigid_modes(&x).iter().enumerate() {
            let u_max = u.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let f = mat_vec(&em.stiffness, u);
            let f_max = f.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert!(
                f_max <= 1e-12 * k_max * u_max,
                "{kind:?} rigid mode {r}: |K u| = {f_max:e}"
            );
            let energy = dot(u, &f);
            assert!(
                energy.abs() <= 1e-12 * k_max * dot(u, u),
                "{kind:?} rigid mode {r}: u^T K u = {energy:e}"
            );
        }
    }
}

#[test]
fn matrices_are_exactly_symmetric() {
    for kind in SolidKind::ALL {
        let x = distorted(kind, 29, 0.15);
        let em = solid(kind).matrices(&x).unwrap();
        let nd = 3 * kind.node_count();
        assert_eq!(em.dofs.len(), nd);
        assert_eq!((em.stiffness.nrows(), em.stiffness.ncols()), (nd, nd));
        assert_eq!((em.mass.nrows(), em.mass.ncols()), (nd, nd));
        for i in 0..nd {
            for j in 0..nd {
                assert_eq!(em.stiffness[(i, j)], em.stiffness[(j, i)], "{kind:?} K");
                assert_eq!(em.mass[(i, j)], em.mass[(j, i)], "{kind:?} M");
            }
        }
    }
}

/// The eigenvalues (ascending) of the stiffness and of the mass matrix of
/// an element of `kind` on [`distorted`]`(kind, seed, 0.15)`, and the
/// largest of each.
fn spectra(kind: SolidKind, seed: u64) -> [(Vec<f64>, f64); 2] {
    let x = distorted(kind, seed, 0.15);
    let em = solid(kind).matrices(&x).unwrap();
    [&em.stiffness, &em.mass].map(|a| {
        let lam = a.self_adjoint_eigenvalues(Side::Lower).unwrap();
        let top = *lam.last().unwrap();
        (lam, top)
    })
}

#[test]
fn stiffness_is_positive_semidefinite_with_six_rigid_modes() {
    for kind in SolidKind::ALL {
        let [(lam, top), _] = spectra(kind, 31);
        let tol = 1e-10 * top;
        assert!(lam[0] > -tol, "{kind:?}: negative eigenvalue {:e}", lam[0]);
        let zeros = lam.iter().filter(|l| l.abs() <= tol).count();
        // C3D20R: 8 points x 6 strains bound the rank by 48 of 60, so a
        // single element has 6 hourglass modes besides the 6 rigid ones.
        // C3D6: both points lie on the line through the triangles'
        // centroids, where twisting the end triangles against each other
        // about that line strains nothing: one spurious mode (CalculiX's
        // C3D6 has it too; its K is the same, see calculix.rs).
        let expected = match kind {
            SolidKind::C3D20R => 12,
            SolidKind::C3D6 => 7,
            _ => 6,
        };
        assert_eq!(zeros, expected, "{kind:?}: eigenvalues {lam:?}");
    }
}

#[test]
fn mass_is_positive_semidefinite() {
    for kind in SolidKind::ALL {
        let [_, (lam, top)] = spectra(kind, 37);
        assert!(
            lam[0] > -1e-12 * top,
            "{kind:?}: negative eigenvalue {:e}",
            lam[0]
        );
    }
}

#[test]
fn translation_carries_the_element_mass() {
    for kind in SolidKind::ALL {
        // C3D20R integrates the mass with 2x2x2 points, exact for straight
        // edges (trilinear geometry) but not for curved ones.
        let x = if kind == SolidKind::C3D20R {
            let mut x = distorted(SolidKind::C3D8, 41, 0.15);
            for (a, b) in HEX_EDGES {
                x.push([0, 1, 2].map(|c| 0.5 * (x[a][c] + x[b][c])));
            }
            x
        } else {
            distorted(kind, 41, 0.15)
        };
        let s = solid(kind);
        let em = s.matrices(&x).unwrap();
        let mass = RHO * s.volume(&x).unwrap();
        for t in &rigid_modes(&x)[..3] {
            let mt = dot(t, &mat_vec(&em.mass, t));
            assert!(
                (mt - mass).abs() <= 1e-12 * mass,
                "{kind:?}: {mt} vs {mass}"
            );
        }
    }
}

#[test]
fn volume_is_exact_for_boxes_tets_and_wedges() {
    let (a, b, c) = (0.3, 0.2, 0.7);
    let scale = |r: &[f64; 3]| [0.3 + a * r[0], -1.0 + b * r[1], 2.0 + c * r[2]];
    for kind in [SolidKind::C3D8, SolidKind::C3D20, SolidKind::C3D20R] {
        let x: Vec<[f64; 3]> = shape::node_coordinates(kind)
            .iter()
            .map(|r| scale(&r.map(|v| 0.5 * (v + 1.0))))
            .collect();
        let v = solid(kind).volume(&x).unwrap();
        assert!((v - a * b * c).abs() < 1e-15, "{kind:?}: {v}");
    }
    for kind in [SolidKind::C3D4, SolidKind::C3D10] {
        let x: Vec<[f64; 3]> = shape::node_coordinates(kind).iter().map(scale).collect();
        let v = solid(kind).volume(&x).unwrap();
        assert!((v - a * b * c / 6.0).abs() < 1e-15, "{kind:?}: {v}");
    }
    let x: Vec<[f64; 3]> = shape::node_coordinates(SolidKind::C3D6)
        .iter()
        .map(|r| scale(&[r[0], r[1], 0.5 * (r[2] + 1.0)]))
        .collect();
    let v = solid(SolidKind::C3D6).volume(&x).unwrap();
    assert!((v - a * b * c / 2.0).abs() < 1e-15, "C3D6: {v}");
}

#[test]
fn volume_of_a_distorted_element_agrees_across_kinds() {
    // Straight-edged 20-node element = the 8-node one; the volume of a
    // sheared parallelepiped is |det A|.
    let x8 = distorted(SolidKind::C3D8, 43, 0.2);
    let mut x20 = x8.clone();
    for (a, b) in HEX_EDGES {
        x20.push([0, 1, 2].map(|c| 0.5 * (x8[a][c] + x8[b][c])));
    }
    let v8 = solid(SolidKind::C3D8).volume(&x8).unwrap();
    let v20 = solid(SolidKind::C3D20).volume(&x20).unwrap();
    let v20r = solid(SolidKind::C3D20R).volume(&x20).unwrap();
    assert!(
        (v8 - v20).abs() < 1e-14 * v8 && (v8 - v20r).abs() < 1e-14 * v8,
        "{v8} {v20} {v20r}"
    );
    let det_a = AFFINE[0][0] * (AFFINE[1][1] * AFFINE[2][2] - AFFINE[1][2] * AFFINE[2][1])
        - AFFINE[0][1] * (AFFINE[1][0] * AFFINE[2][2] - AFFINE[1][2] * AFFINE[2][0])
        + AFFINE[0][2] * (AFFINE[1][0] * AFFINE[2][1] - AFFINE[1][1] * AFFINE[2][0]);
    let p = distorted(SolidKind::C3D20, 1, 0.0);
    let v = solid(SolidKind::C3D20).volume(&p).unwrap();
    assert!((v - 8.0 * det_a).abs() < 1e-14, "{v} vs {}", 8.0 * det_a);
}

#[test]
fn unit_cube_c3d8_matches_the_closed_form_mass_matrix() {
    // Consistent mass of a trilinear brick: rho V / 216 * (2^3, 2^2, 2, 1)
    // for nodes sharing 3, 2, 1, 0 coordinates.
    let x: Vec<[f64; 3]> = shape::node_coordinates(SolidKind::C3D8)
        .iter()
        .map(|r| r.map(|v| 0.5 * (v + 1.0)))
        .collect();
    let em = solid(SolidKind::C3D8).matrices(&x).unwrap();
    for a in 0..8 {
        for b in 0..8 {
            let shared = (0..3).filter(|&c| x[a][c] == x[b][c]).count() as i32;
            let exact = RHO / 216.0 * 2f64.powi(shared);
            assert!((em.mass[(3 * a, 3 * b)] - exact).abs() < 1e-12 * exact);
            assert_eq!(em.mass[(3 * a, 3 * b + 1)], 0.0);
        }
    }
}
