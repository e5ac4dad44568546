//! Bending of a two-node beam in one plane, DOFs `(v1, th1, v2, th2)` with
//! `th = dv/dx`: Timoshenko stiffness with the shear parameter
//! `phi = 12 E I / (G A_s L^2)` (phi = 0: Euler-Bernoulli), and the consistent
//! mass of translational and rotary inertia (Przemieniecki, Theory of Matrix
//! Structural Analysis, 1968, sec. 11.6). Exact for end-loaded beams.

/// Stiffness of the bending block.
pub(super) fn stiffness(ei: f64, phi: f64, l: f64) -> [[f64; 4]; 4] {
    let c = ei / ((1.0 + phi) * l.powi(3));
    let l2 = l * l;
    [
        [12.0 * c, 6.0 * l * c, -12.0 * c, 6.0 * l * c],
        [
            6.0 * l * c,
            (4.0 + phi) * l2 * c,
            -6.0 * l * c,
            (2.0 - phi) * l2 * c,
        ],
        [-12.0 * c, -6.0 * l * c, 12.0 * c, -6.0 * l * c],
        [
            6.0 * l * c,
            (2.0 - phi) * l2 * c,
            -6.0 * l * c,
            (4.0 + phi) * l2 * c,
        ],
    ]
}

/// Consistent mass of the bending block: translational inertia `rho_a`
/// (kg/m) plus rotary inertia `rho_i` (kg m), which may be zero.
pub(super) fn mass(rho_a: f64, rho_i: f64, phi: f64, l: f64) -> [[f64; 4]; 4] {
    let p = phi;
    let p2 = p * p;
    let d = (1.0 + p) * (1.0 + p);
    let ct = rho_a * l / d;
    let m11 = ct * (13.0 / 35.0 + 7.0 * p / 10.0 + p2 / 3.0);
    let m12 = ct * (11.0 / 210.0 + 11.0 * p / 120.0 + p2 / 24.0) * l;
    let m13 = ct * (9.0 / 70.0 + 3.0 * p / 10.0 + p2 / 6.0);
    let m14 = -ct * (13.0 / 420.0 + 3.0 * p / 40.0 + p2 / 24.0) * l;
    let m22 = ct * (1.0 / 105.0 + p / 60.0 + p2 / 120.0) * l * l;
    let m24 = -ct * (1.0 / 140.0 + p / 60.0 + p2 / 120.0) * l * l;
    let translational = [
        [m11, m12, m13, m14],
        [m12, m22, -m14, m24],
        [m13, -m14, m11, -m12],
        [m14, m24, -m12, m22],
    ];
    let cr = rho_i / (d * l);
    let r11 = cr * 6.0 / 5.0;
    let r12 = cr * (1.0 / 10.0 - p / 2.0) * l;
    let r22 = cr * (2.0 / 15.0 + p / 6.0 + p2 / 3.0) * l * l;
    let r24 = cr * (-1.0 / 30.0 - p / 6.0 + p2 / 6.0) * l * l;
    let rotary = [
        [r11, r12, -r11, r12],
        [r12, r22, -r12, r24],
        [-r11, -r12, r11, -r12],
        [r12, r24, -r12, r22],
    ];
    let mut m = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            m[i][j] = translational[i][j] + rotary[i][j];
        }
    }
    m
}

/// The shape functions behind [`mass`] (Przemieniecki's, interdependent
/// for `phi > 0`): at `xi = x / l` in `[0, 1]`, the deflection
/// `v = n_v . (v1, th1, v2, th2)` and the rotation of the section
/// `th = n_th . (v1, th1, v2, th2)` (`th = dv/dx` when `phi = 0`).
/// `int rho_a n_v n_v^T + rho_i n_th n_th^T dx` is [`mass`].
pub(super) fn shapes(phi: f64, l: f64, xi: f64) -> ([f64; 4], [f64; 4]) {
    let (x, x2, x3) = (xi, xi * xi, xi * xi * xi);
    let c = 1.0 / (1.0 + phi);
    let n_v = [
        c * (1.0 - 3.0 * x2 + 2.0 * x3 + phi * (1.0 - x)),
        c * l * (x - 2.0 * x2 + x3 + 0.5 * phi * (x - x2)),
        c * (3.0 * x2 - 2.0 * x3 + phi * x),
        c * l * (-x2 + x3 + 0.5 * phi * (x2 - x)),
    ];
    let n_th = [
        c * 6.0 * (x2 - x) / l,
        c * (1.0 - 4.0 * x + 3.0 * x2 + phi * (1.0 - x)),
        -c * 6.0 * (x2 - x) / l,
        c * (-2.0 * x + 3.0 * x2 + phi * x),
    ];
    (n_v, n_th)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shape_functions_integrate_to_the_mass_matrix() {
        // Six Gauss points: exact for the degree-6 products.
        let x = [
            0.033_765_242_898_424_03,
            0.169_395_306_766_867_76,
            0.380_690_406_958_401_56,
            0.619_309_593_041_598_5,
            0.830_604_693_233_132_2,
            0.966_234_757_101_575_9,
        ];
        let w = [
            0.085_662_246_189_585_14,
            0.180_380_786_524_069_36,
            0.233_956_967_286_345_52,
            0.233_956_967_286_345_52,
            0.180_380_786_524_069_36,
            0.085_662_246_189_585_14,
        ];
        for phi in [0.0, 0.3, 2.0] {
            let (l, rho_a, rho_i) = (0.7, 3.0, 0.02);
            let m = mass(rho_a, rho_i, phi, l);
            let mut q = [[0.0; 4]; 4];
            for (xi, wi) in x.iter().zip(w) {
                let (n_v, n_th) = shapes(phi, l, *xi);
                for i in 0..4 {
                    for j in 0..4 {
                        q[i][j] += wi * l * (rho_a * n_v[i] * n_v[j] + rho_i * n_th[i] * n_th[j]);
                    }
                }
            }
            for i in 0..4 {
                for j in 0..4 {
                    assert!(
                        (q[i][j] - m[i][j]).abs() < 1e-14 * m[0][0],
                        "phi {phi} ({i}, {j}): {} against {}",
                        q[i][j],
                        m[i][j]
                    );
                }
            }
            // At the ends the shape functions are the nodal values.
            let (v0, t0) = shapes(phi, l, 0.0);
            let (v1, t1) = shapes(phi, l, 1.0);
            assert_eq!(v0.map(|v| (v * 1e12).round()), [1e12, 0.0, 0.0, 0.0]);
            assert_eq!(t0.map(|v| (v * 1e12).round()), [0.0, 1e12, 0.0, 0.0]);
            assert_eq!(v1.map(|v| (v * 1e12).round()), [0.0, 0.0, 1e12, 0.0]);
            assert_eq!(t1.map(|v| (v * 1e12).round()), [0.0, 0.0, 0.0, 1e12]);
        }
    }

    #[test]
    fn rigid_motions_carry_no_strain_and_the_full_mass() {
        let (l, phi) = (0.7, 0.3);
        let k = stiffness(2.0, phi, l);
        // Translation (1, 0, 1, 0) and rotation (-l/2, 1, l/2, 1).
        for v in [[1.0, 0.0, 1.0, 0.0], [-l / 2.0, 1.0, l / 2.0, 1.0]] {
            for row in &k {
                let f: f64 = row.iter().zip(v).map(|(a, b)| a * b).sum();
                assert!(f.abs() < 1e-12, "{f}");
            }
        }
        let m = mass(3.0, 0.0, phi, l);
        let t = [1.0, 0.0, 1.0, 0.0];
        let total: f64 = (0..4)
            .map(|i| (0..4).map(|j| t[i] * m[i][j] * t[j]).sum::<f64>())
            .sum();
        assert!((total - 3.0 * l).abs() < 1e-14);
    }
}
