//! One element and small patches: rigid-body modes, the patch tests of
//! membrane and bending, stresses on the three surfaces, bad input.

use super::super::mitc::cross;
use super::*;
use crate::element::mat_vec;
use faer::Mat;

/// A quadrilateral warped out of its plane (node 3 lifted), a skew
/// triangle, both off the origin.
fn warped_quad() -> Vec<[f64; 3]> {
    vec![
        [10.0, 5.0, 1.0],
        [10.9, 5.1, 1.05],
        [11.1, 5.8, 1.25],
        [10.1, 5.7, 0.95],
    ]
}

fn skew_triangle() -> Vec<[f64; 3]> {
    vec![[10.0, 5.0, 1.0], [10.9, 5.3, 1.2], [10.2, 5.9, 0.8]]
}

/// [`skew_triangle`] with mid-side nodes lifted off its edges (a curved S6).
fn curved_triangle6() -> Vec<[f64; 3]> {
    with_midsides(&skew_triangle(), &[0.02, -0.03, 0.01])
}

/// The corners and, per edge, its midpoint lifted by `lift` along z.
fn with_midsides(corners: &[[f64; 3]], lift: &[f64]) -> Vec<[f64; 3]> {
    let n = corners.len();
    let mut x = corners.to_vec();
    for (k, l) in lift.iter().enumerate() {
        let (a, b) = (corners[k], corners[(k + 1) % n]);
        x.push([
            0.5 * (a[0] + b[0]),
            0.5 * (a[1] + b[1]),
            0.5 * (a[2] + b[2]) + l,
        ]);
    }
    x
}

/// [`warped_quad`] with mid-side nodes lifted off its edges (a curved
/// S8).
fn curved_quad8() -> Vec<[f64; 3]> {
    with_midsides(&warped_quad(), &[0.02, -0.03, 0.01, 0.015])
}

/// Every kind on a distorted element: warped, skew, curved.
fn distorted() -> [(ShellKind, Vec<[f64; 3]>); 4] {
    [
        (ShellKind::S4, warped_quad()),
        (ShellKind::S3, skew_triangle()),
        (ShellKind::S6, curved_triangle6()),
        (ShellKind::S8, curved_quad8()),
    ]
}

fn shell(kind: ShellKind, thickness: f64, offset: f64) -> Shell {
    Shell {
        id: 7,
        kind,
        nodes: (1..=kind.node_count() as NodeId).collect(),
        material: nafems_steel(),
        thickness,
        offset,
    }
}

/// The six rigid motions at `coords`: `u = c + w x x`, `theta = w`.
fn rigid_motions(coords: &[[f64; 3]]) -> Vec<Vec<f64>> {
    (0..6)
        .map(|m| {
            let mut c = [0.0; 3];
            let mut w = [0.0; 3];
            if m < 3 {
                c[m] = 1.0;
            } else {
                w[m - 3] = 1.0;
            }
            coords
                .iter()
                .flat_map(|x| {
                    let r = cross(w, *x);
                    [c[0] + r[0], c[1] + r[1], c[2] + r[2], w[0], w[1], w[2]]
                })
                .collect()
        })
        .collect()
}

#[test]
fn rigid_motions_strain_nothing_on_warped_and_offset_elements() {
    for (kind, coords) in distorted() {
        for offset in [0.0, 0.5, -0.3] {
            let e = shell(kind, 0.05, offset);
            let k = e.matrices(&coords).unwrap().stiffness;
            for (m, u) in rigid_motions(&coords).iter().enumerate() {
                let f = mat_vec(&k, u);
                let norm_u = u.iter().map(|v| v * v).sum::<f64>().sqrt();
                let rel = f.iter().fold(0.0_f64, |a, v| a.max(v.abs())) / (k.norm_max() * norm_u);
                assert!(
                    rel < 1e-13,
                    "{kind:?}, offset {offset}, motion {m}: {rel:e}"
                );
            }
        }
    }
}

#[test]
fn one_element_has_six_zero_energy_modes_and_no_spurious_one() {
    for (kind, coords) in distorted() {
        let k = shell(kind, 0.05, 0.0).matrices(&coords).unwrap().stiffness;
        let values = k.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
        let largest = values.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let zero = values.iter().filter(|v| v.abs() < 1e-10 * largest).count();
        let smallest_other = values
            .iter()
            .filter(|v| v.abs() >= 1e-10 * largest)
            .fold(f64::INFINITY, |a, v| a.min(*v));
        eprintln!(
            "{kind:?}: {zero} zero eigenvalues, then {:.2e} of the largest",
            smallest_other / largest
        );
        assert_eq!(zero, 6, "{kind:?}");
        assert!(smallest_other > 0.0, "{kind:?}");
    }
}

#[test]
fn mass_is_the_shells_mass_with_its_rotary_inertia() {
    // A flat rectangle 0.8 x 0.5 m, 20 mm thick: total mass rho a A on each
    // translation, rho a^3 / 12 A about the in-plane axes, nothing about
    // the normal; as S4 and as S8 (whose condensed centre node moves
    // rigidly with a rigid motion of the others).
    let corners = vec![[0.0; 3], [0.8, 0.0, 0.0], [0.8, 0.5, 0.0], [0.0, 0.5, 0.0]];
    let (a, area, rho) = (0.02, 0.4, 8000.0);
    for (kind, coords) in [
        (ShellKind::S4, corners.clone()),
        (ShellKind::S8, with_midsides(&corners, &[0.0; 4])),
    ] {
        let n = coords.len();
        let m = shell(kind, a, 0.0).matrices(&coords).unwrap().mass;
        let total = |dof: usize| -> f64 {
            (0..n)
                .flat_map(|p| (0..n).map(move |q| (p, q)))
                .map(|(p, q)| m[(6 * p + dof, 6 * q + dof)])
                .sum()
        };
        for d in 0..3 {
            let want = rho * a * area;
            assert!((total(d) - want).abs() < 1e-12 * want, "{kind:?} {d}");
        }
        let rotary = rho * a.powi(3) / 12.0 * area;
        if kind == ShellKind::S4 {
            assert!((total(3) - rotary).abs() < 1e-12 * rotary);
            assert!((total(4) - rotary).abs() < 1e-12 * rotary);
            assert_eq!(total(5), 0.0);
        }
        // Rigid rotations about the centroid's axes: the plate's moments
        // of inertia plus the rotary inertia in the plane.
        let centre = [0.4, 0.25, 0.0];
        let mass = rho * a * area;
        let want = [
            mass * 0.5 * 0.5 / 12.0 + rotary,
            mass * 0.8 * 0.8 / 12.0 + rotary,
            mass * (0.8 * 0.8 + 0.5 * 0.5) / 12.0,
        ];
        for (axis, want) in want.iter().enumerate() {
            let mut w = [0.0; 3];
            w[axis] = 1.0;
            let u: Vec<f64> = coords
                .iter()
                .flat_map(|x| {
                    let r = [0, 1, 2].map(|i| x[i] - centre[i]);
                    let t = cross(w, r);
                    [t[0], t[1], t[2], w[0], w[1], w[2]]
                })
                .collect();
            let inertia: f64 = mat_vec(&m, &u).iter().zip(&u).map(|(x, y)| x * y).sum();
            assert!(
                (inertia - want).abs() < 1e-12 * want,
                "{kind:?} axis {axis}: {inertia} against {want}"
            );
        }
    }
}

/// The patch of MacNeal and Harder (1985): a 0.24 x 0.12 rectangle of five
/// quadrilaterals around an irregular interior one, or those five cut into
/// ten triangles; returns coordinates and element node lists (indices).
fn patch(kind: ShellKind) -> (Vec<[f64; 3]>, Vec<Vec<usize>>) {
    let coords = vec![
        [0.0, 0.0, 0.0],
        [0.24, 0.0, 0.0],
        [0.24, 0.12, 0.0],
        [0.0, 0.12, 0.0],
        [0.04, 0.02, 0.0],
        [0.18, 0.03, 0.0],
        [0.16, 0.08, 0.0],
        [0.08, 0.08, 0.0],
    ];
    let quads = [
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
        [4, 5, 6, 7],
    ];
    let linear: Vec<Vec<usize>> = match kind {
        ShellKind::S4 | ShellKind::S8 => quads.iter().map(|q| q.to_vec()).collect(),
        ShellKind::S3 | ShellKind::S6 => quads
            .iter()
            .flat_map(|q| [vec![q[0], q[1], q[2]], vec![q[0], q[2], q[3]]])
            .collect(),
    };
    if !kind.is_quadratic() {
        return (coords, linear);
    }
    // Mid-side nodes at the middle of each (straight) edge, shared.
    let mut coords = coords;
    let mut midsides: std::collections::HashMap<(usize, usize), usize> = Default::default();
    let cells = linear
        .iter()
        .map(|c| {
            let mut cell = c.clone();
            for k in 0..c.len() {
                let (a, b) = (c[k], c[(k + 1) % c.len()]);
                let m = *midsides.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    coords.push(std::array::from_fn(|i| 0.5 * (coords[a][i] + coords[b][i])));
                    coords.len() - 1
                });
                cell.push(m);
            }
            cell
        })
        .collect();
    (coords, cells)
}

/// Patch test: the exact field `field(x)` (6 values per node) on the
/// boundary nodes, the interior solved from K; returns the interior
/// nodes' largest error relative to the field's largest value, and the
/// element stresses of the solution.
fn patch_test(kind: ShellKind, field: impl Fn([f64; 3]) -> [f64; 6]) -> (f64, Vec<Vec<[f64; 6]>>) {
    let (coords, cells) = patch(kind);
    let n = 6 * coords.len();
    let mut k = Mat::<f64>::zeros(n, n);
    let elements: Vec<(Shell, Vec<[f64; 3]>, Vec<usize>)> = cells
        .iter()
        .map(|c| {
            let e = shell(kind, 0.001, 0.0);
            (e, c.iter().map(|&a| coords[a]).collect(), c.clone())
        })
        .collect();
    for (e, x, c) in &elements {
        let ke = e.matrices(x).unwrap().stiffness;
        for (p, &a) in c.iter().enumerate() {
            for (q, &b) in c.iter().enumerate() {
                for i in 0..6 {
                    for j in 0..6 {
                        k[(6 * a + i, 6 * b + j)] += ke[(6 * p + i, 6 * q + j)];
                    }
                }
            }
        }
    }
    let exact: Vec<f64> = coords.iter().flat_map(|x| field(*x)).collect();
    // The nodes on the rectangle's boundary hold the field; the others are
    // free.
    let on_boundary = |x: &[f64; 3]| {
        x[0].abs() < 1e-12
            || (x[0] - 0.24).abs() < 1e-12
            || x[1].abs() < 1e-12
            || (x[1] - 0.12).abs() < 1e-12
    };
    let (mut free, mut fixed) = (Vec::new(), Vec::new());
    for (a, x) in coords.iter().enumerate() {
        let dofs = (6 * a..6 * a + 6).collect::<Vec<_>>();
        if on_boundary(x) {
            fixed.extend(dofs);
        } else {
            free.extend(dofs);
        }
    }
    let kff = Mat::from_fn(free.len(), free.len(), |r, c| k[(free[r], free[c])]);
    let rhs = Mat::from_fn(free.len(), 1, |r, _| {
        -fixed
            .iter()
            .map(|&c| k[(free[r], c)] * exact[c])
            .sum::<f64>()
    });
    let solved = kff.full_piv_lu().solve(&rhs);
    let mut u = exact.clone();
    for (r, &dof) in free.iter().enumerate() {
        u[dof] = solved[(r, 0)];
    }
    let scale = exact.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let error = free
        .iter()
        .map(|&d| (u[d] - exact[d]).abs())
        .fold(0.0, f64::max)
        / scale;
    let stresses = elements
        .iter()
        .map(|(e, x, c)| {
            let u_e: Vec<f64> = c
                .iter()
                .flat_map(|&a| u[6 * a..6 * a + 6].to_vec())
                .collect();
            e.surface_stresses(x, &u_e, 1).unwrap()
        })
        .collect();
    (error, stresses)
}

use faer::linalg::solvers::Solve;

#[test]
fn membrane_patch_test_gives_the_constant_stress() {
    // u = 1e-3 (x + y/2), v = 1e-3 (y + x/2): eps_xx = eps_yy = 1e-3,
    // gamma_xy = 1e-3, and the drilling rotation of the membrane, zero.
    let field = |x: [f64; 3]| {
        [
            1e-3 * (x[0] + 0.5 * x[1]),
            1e-3 * (x[1] + 0.5 * x[0]),
            0.0,
            0.0,
            0.0,
            0.0,
        ]
    };
    let (e, nu) = (200e9, 0.3);
    let want = [
        e / (1.0 - nu) * 1e-3,
        e / (1.0 - nu) * 1e-3,
        0.0,
        e / (2.0 * (1.0 + nu)) * 1e-3,
        0.0,
        0.0,
    ];
    for kind in ShellKind::ALL {
        let (error, stresses) = patch_test(kind, field);
        assert!(error < 1e-10, "{kind:?}: displacements off by {error:e}");
        for s in stresses.iter().flatten() {
            for (c, (got, w)) in s.iter().zip(want).enumerate() {
                assert!(
                    (got - w).abs() < 1e-6 * want[0],
                    "{kind:?} component {c}: {got} against {w}"
                );
            }
        }
    }
}

#[test]
fn bending_patch_test_gives_the_constant_curvature() {
    // Kirchhoff bending w = 1e-3 (x^2 + x y + y^2) / 2 with theta_x =
    // dw/dy, theta_y = -dw/dx (so that u = z theta_y = -z dw/dx): constant
    // curvatures, no transverse shear; on the top face (z = a/2)
    // eps = -z (w_xx, w_yy, 2 w_xy).
    let field = |x: [f64; 3]| {
        let (px, py) = (1e-3 * (x[0] + 0.5 * x[1]), 1e-3 * (x[1] + 0.5 * x[0]));
        [
            0.0,
            0.0,
            0.5e-3 * (x[0] * x[0] + x[0] * x[1] + x[1] * x[1]),
            py,
            -px,
            0.0,
        ]
    };
    let (e, nu, a): (f64, f64, f64) = (200e9, 0.3, 0.001);
    let z = a / 2.0;
    let (kx, ky, kxy) = (1e-3, 1e-3, 1e-3);
    let c = e / (1.0 - nu * nu);
    let top = [
        -z * c * (kx + nu * ky),
        -z * c * (ky + nu * kx),
        0.0,
        -z * e / (2.0 * (1.0 + nu)) * kxy,
        0.0,
        0.0,
    ];
    for kind in ShellKind::ALL {
        let (error, stresses) = patch_test(kind, field);
        eprintln!("{kind:?}: bending patch off by {error:e}");
        assert!(error < 1e-8, "{kind:?}: displacements off by {error:e}");
        for s in &stresses {
            let n = kind.node_count();
            for a in 0..n {
                let (bottom, mid, up) = (s[a], s[n + a], s[2 * n + a]);
                for comp in 0..6 {
                    let scale = top[0].abs();
                    assert!(
                        (up[comp] - top[comp]).abs() < 1e-5 * scale,
                        "{kind:?} top {comp}: {} against {}",
                        up[comp],
                        top[comp]
                    );
                    assert!(
                        (bottom[comp] + top[comp]).abs() < 1e-5 * scale,
                        "{kind:?} bottom {comp}"
                    );
                    assert!(
                        mid[comp].abs() < 1e-5 * scale,
                        "{kind:?} middle {comp}: {}",
                        mid[comp]
                    );
                }
            }
        }
    }
}

fn error_of(e: &Shell, coords: &[[f64; 3]]) -> String {
    e.matrices(coords).unwrap_err().to_string()
}

#[test]
fn bad_shells_are_refused_naming_the_element() {
    let flat = vec![[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    for thickness in [0.0, -0.01, f64::NAN] {
        let err = error_of(&shell(ShellKind::S4, thickness, 0.0), &flat);
        assert!(
            err.contains("element 7") && err.contains("thickness"),
            "{err}"
        );
    }
    // Warped beyond the limit: one corner lifted by half the side.
    let mut warped = flat.clone();
    warped[2][2] = 0.5;
    let err = error_of(&shell(ShellKind::S4, 0.01, 0.0), &warped);
    assert!(err.contains("element 7") && err.contains("warped"), "{err}");
    // Inverted at a node: a concave (arrowhead) quadrilateral.
    let concave = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.2, 0.2, 0.0], [0.0, 1.0, 0.0]];
    let err = error_of(&shell(ShellKind::S4, 0.01, 0.0), &concave);
    assert!(err.contains("element 7") && err.contains("node 3"), "{err}");
    // A collapsed quadrilateral and a triangle on a line.
    let collapsed = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let err = error_of(&shell(ShellKind::S4, 0.01, 0.0), &collapsed);
    assert!(err.contains("element 7") && err.contains("S3"), "{err}");
    let line = vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    let err = error_of(&shell(ShellKind::S3, 0.01, 0.0), &line);
    assert!(
        err.contains("element 7") && err.contains("zero area"),
        "{err}"
    );
    // An S8 whose mid-side node sits beyond a quarter of its edge: the
    // Jacobian changes sign inside the element.
    let mut folded = with_midsides(&flat, &[0.0; 4]);
    folded[4][0] = 0.9;
    let err = error_of(&shell(ShellKind::S8, 0.01, 0.0), &folded);
    assert!(
        err.contains("element 7") && err.contains("Jacobian"),
        "{err}"
    );
    // Clockwise numbering is no error: the normal turns round.
    let reversed: Vec<[f64; 3]> = flat.iter().rev().copied().collect();
    assert!(shell(ShellKind::S4, 0.01, 0.0).matrices(&reversed).is_ok());
}
