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

#[cfg(test)]
mod tests {
    use super::*;

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
