//! Rotation, engineering constants and the stability check of
//! anisotropic elasticity.

use super::*;

/// Isotropic `C` from the Lame constants.
pub(crate) fn isotropic(lambda: f64, mu: f64) -> Voigt {
    let mut c = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = lambda + if i == j { 2.0 * mu } else { 0.0 };
        }
        c[i + 3][i + 3] = mu;
    }
    c
}

/// A general symmetric positive definite `C` (Pa): diagonal dominant with
/// every coupling present.
pub(crate) fn general() -> Voigt {
    let mut c = [[0.0; 6]; 6];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, cij) in row.iter_mut().enumerate() {
            *cij = if i == j {
                (200.0 + 15.0 * i as f64) * 1e9
            } else {
                (7.0 + 3.0 * ((i + 2 * j) % 5) as f64 + 3.0 * ((j + 2 * i) % 5) as f64) * 1e9
            };
        }
    }
    c
}

/// The stress transformation (Bond) matrix in Voigt order `[11, 22, 33,
/// 12, 23, 31]`: `sigma' = M sigma` for `sigma'_ij = R_ia R_jb sigma_ab`,
/// built from the stress rule alone; then `C' = M C M^T`.
pub(crate) fn bond(r: &[[f64; 3]; 3]) -> Voigt {
    const PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];
    std::array::from_fn(|m| {
        let (i, j) = PAIRS[m];
        std::array::from_fn(|n| {
            let (a, b) = PAIRS[n];
            if a == b {
                r[i][a] * r[j][a]
            } else {
                r[i][a] * r[j][b] + r[i][b] * r[j][a]
            }
        })
    })
}

pub(crate) fn bond_rotate(c: &Voigt, r: &[[f64; 3]; 3]) -> Voigt {
    let m = bond(r);
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            (0..6)
                .flat_map(|k| (0..6).map(move |l| (k, l)))
                .map(|(k, l)| m[i][k] * c[k][l] * m[j][l])
                .sum()
        })
    })
}

fn max_diff(a: &Voigt, b: &Voigt) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}

fn max_abs(a: &Voigt) -> f64 {
    a.iter().flatten().fold(0.0_f64, |m, x| m.max(x.abs()))
}

const A: [f64; 3] = [0.8, 0.5, -0.3];
const B: [f64; 3] = [-0.2, 0.9, 0.4];

#[test]
fn rotation_agrees_with_the_bond_matrix() {
    let c = general();
    let r = Orientation::rectangular(A, B)
        .unwrap()
        .axes_at([0.0; 3])
        .unwrap();
    let d = max_diff(&rotate(&c, &r), &bond_rotate(&c, &r));
    assert!(d <= 1e-13 * max_abs(&c), "difference {d:e}");
}

#[test]
fn isotropic_elasticity_is_unchanged_by_any_rotation() {
    let c = isotropic(1.2e11, 8.1e10);
    let r = Orientation::rectangular(A, B)
        .unwrap()
        .axes_at([0.0; 3])
        .unwrap();
    let d = max_diff(&rotate(&c, &r), &c);
    assert!(d <= 1e-13 * max_abs(&c), "difference {d:e}");
}

#[test]
fn rectangular_axes_are_orthonormal_and_right_handed() {
    let r = Orientation::rectangular(A, B)
        .unwrap()
        .axes_at([0.0; 3])
        .unwrap();
    for i in 0..3 {
        for j in 0..3 {
            let d: f64 = (0..3).map(|k| r[k][i] * r[k][j]).sum();
            assert!((d - if i == j { 1.0 } else { 0.0 }).abs() < 1e-15);
        }
    }
    let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
        - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
        + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    assert!((det - 1.0).abs() < 1e-15);
    // Local 1 along a.
    let n = (A[0] * A[0] + A[1] * A[1] + A[2] * A[2]).sqrt();
    for k in 0..3 {
        assert!((r[k][0] - A[k] / n).abs() < 1e-15);
    }
}

#[test]
fn cylindrical_axes_are_radial_tangential_axial() {
    // Axis along global z through (1, 0, 0).
    let o = Orientation::cylindrical([1.0, 0.0, 0.0], [1.0, 0.0, 2.0]).unwrap();
    let r = o.axes_at([1.0, 3.0, 5.0]).unwrap();
    let expected = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(r
        .iter()
        .flatten()
        .zip(expected.iter().flatten())
        .all(|(a, b)| (a - b).abs() < 1e-15));
    assert!(o.axes_at([1.0, 0.0, 0.7]).is_err(), "a point on the axis");
}

#[test]
fn additional_rotation_turns_about_the_local_axis() {
    // 90 degrees about local 3 of the global system: local 1 becomes y.
    let o = Orientation::rectangular([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
    let r = o
        .rotated(2, std::f64::consts::FRAC_PI_2)
        .unwrap()
        .axes_at([0.0; 3])
        .unwrap();
    let expected = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(r
        .iter()
        .flatten()
        .zip(expected.iter().flatten())
        .all(|(a, b)| (a - b).abs() < 1e-15));
    let cyl = Orientation::cylindrical([0.0; 3], [0.0, 0.0, 1.0]).unwrap();
    assert!(cyl.rotated(0, 0.1).is_err());
}

#[test]
fn engineering_constants_of_an_isotropic_material_give_lame() {
    let (e, nu) = (2.1e11, 0.3);
    let g = e / (2.0 * (1.0 + nu));
    let c = Anisotropy::engineering([e; 3], nu, nu, nu, g, g, g).unwrap();
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let d = max_diff(&c, &isotropic(lambda, g));
    assert!(d <= 1e-14 * max_abs(&c), "difference {d:e}");
}

#[test]
fn engineering_constants_invert_the_compliance() {
    let (e, nu12, nu13, nu23) = ([1.4e11, 9.0e9, 1.1e10], 0.28, 0.31, 0.4);
    let c = Anisotropy::engineering(e, nu12, nu13, nu23, 5e9, 4e9, 3e9).unwrap();
    // Uniaxial stress along 1: strains 1/E1, -nu12/E1, -nu13/E1.
    let strain = [1.0 / e[0], -nu12 / e[0], -nu13 / e[0]];
    let stress: Vec<f64> = (0..3)
        .map(|i| (0..3).map(|j| c[i][j] * strain[j]).sum())
        .collect();
    assert!((stress[0] - 1.0).abs() < 1e-12);
    assert!(stress[1].abs() < 1e-12 && stress[2].abs() < 1e-12);
    assert_eq!(
        (c[3][3], c[4][4], c[5][5]),
        (5e9, 3e9, 4e9),
        "G12 on 12, G23 on 23, G13 on 31"
    );
}

#[test]
fn unstable_materials_are_refused() {
    let mut c = general();
    c[0][1] = 1e12;
    c[1][0] = 1e12;
    let err = Anisotropy::new(c, None).unwrap_err().to_string();
    assert!(err.contains("not positive definite"), "{err}");
    assert!(Anisotropy::engineering([1e9; 3], 0.9, 0.9, 0.9, 1e9, 1e9, 1e9).is_err());
    let mut asym = general();
    asym[0][5] += 1e9;
    assert!(Anisotropy::new(asym, None).is_err());
    assert!(Anisotropy::new(general(), None).is_ok());
}

#[test]
fn symmetry_class_tells_orthotropic_from_anisotropic() {
    let c = Anisotropy::engineering([1e11, 2e10, 3e10], 0.2, 0.2, 0.3, 5e9, 4e9, 3e9).unwrap();
    let ortho = Anisotropy::new(c, None).unwrap();
    assert_eq!(ortho.symmetry_class(), SymmetryClass::Orthotropic);
    let aniso = Anisotropy::new(general(), None).unwrap();
    assert_eq!(aniso.symmetry_class(), SymmetryClass::Anisotropic);
}
