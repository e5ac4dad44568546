//! Harmonic steady state of the MBS equations (report eq. 11):
//! `(K - Omega^2 M + i Omega D) q = f`, with the track's complex amplitudes
//! (a vehicle over `z(s) = a cos(2 pi s / L_w)`). Nonlinear connections enter
//! with their tangent at rest ([`crate::ForceLaw::linearized`]).

use crate::linear_solve::solve;
use crate::system::{Assembled, System};
use crate::MbsError;
use faer::sparse::Triplet;
use flexbody_linalg::sparse;

/// Steady-state response at one frequency; complex amplitudes as (re, im).
#[derive(Clone, Debug)]
pub struct HarmonicResponse {
    /// Excitation frequency Omega (rad/s).
    pub omega: f64,
    /// FE displacement amplitudes of each flexible body: (re, im).
    pub flexible: Vec<(Vec<f64>, Vec<f64>)>,
    /// Coordinates of each flexible body (q): (re, im).
    pub flexible_coords: Vec<(Vec<f64>, Vec<f64>)>,
    /// Coordinates of each rigid body: (re, im).
    pub rigid: Vec<(Vec<f64>, Vec<f64>)>,
    /// Force amplitude in each connection (N), tension positive: (re, im).
    pub forces: Vec<(f64, f64)>,
}

/// Harmonic steady state at `omega` (rad/s).
pub fn harmonic_response(system: &System, omega: f64) -> Result<HarmonicResponse, MbsError> {
    let layout = system.layout();
    let n = layout.len;
    let kins = system.all_kinematics(&layout)?;
    let Assembled {
        mass,
        damping,
        stiffness,
    } = system.assemble(&kins, true)?;
    // Prescribed elongations (complex) and their loads: the spring's energy
    // gives -c g v_p, the damper -b g (i Omega v_p).
    let prescribed: Vec<(f64, f64)> = kins
        .iter()
        .map(|kin| {
            kin.tracks.iter().fold((0.0, 0.0), |acc, &(x, coef)| {
                let z = system.track.map_or((0.0, 0.0), |t| t.amplitude_at(x));
                (acc.0 + coef * z.0, acc.1 + coef * z.1)
            })
        })
        .collect();
    let (mut load_re, mut load_im) = (vec![0.0; n], vec![0.0; n]);
    for ((c, kin), vp) in system.connections.iter().zip(&kins).zip(&prescribed) {
        let (k, b) = c.law.linearized();
        for &(i, gi) in &kin.row {
            load_re[i] -= gi * (k * vp.0 - omega * b * vp.1);
            load_im[i] -= gi * (k * vp.1 + omega * b * vp.0);
        }
    }
    let a = sparse::add_scaled(&stiffness, -omega * omega, &mass)?;
    let damped = damping.compute_nnz() > 0 && omega != 0.0;
    let (q_re, q_im) = if damped {
        // (A + i B)(x + i y) = f, B = Omega D, as the real symmetric
        // [A  -B; -B  -A] [x; y] = [f_re; -f_im].
        let mut t = Vec::new();
        for e in sparse::triplets_of(&a, 1.0) {
            t.push(Triplet::new(e.row, e.col, e.val));
            t.push(Triplet::new(e.row + n, e.col + n, -e.val));
        }
        for e in sparse::triplets_of(&damping, omega) {
            t.push(Triplet::new(e.row, e.col + n, -e.val));
            t.push(Triplet::new(e.row + n, e.col, -e.val));
        }
        let big = sparse::from_triplets(2 * n, 2 * n, &t)?;
        let rhs: Vec<f64> = load_re
            .iter()
            .copied()
            .chain(load_im.iter().map(|v| -v))
            .collect();
        let x = solve(&big, &[rhs], omega)?.remove(0);
        (x[..n].to_vec(), x[n..].to_vec())
    } else if load_im.iter().any(|v| *v != 0.0) {
        let mut x = solve(&a, &[load_re, load_im], omega)?;
        let im = x.remove(1);
        (x.remove(0), im)
    } else {
        (solve(&a, &[load_re], omega)?.remove(0), vec![0.0; n])
    };
    let part = |at: usize, len: usize| (q_re[at..at + len].to_vec(), q_im[at..at + len].to_vec());
    let flexible_coords: Vec<(Vec<f64>, Vec<f64>)> = system
        .flexible
        .iter()
        .zip(&layout.flexible)
        .map(|(b, &at)| part(at, b.len()))
        .collect();
    let flexible = system
        .flexible
        .iter()
        .zip(&flexible_coords)
        .map(|(b, (re, im))| (b.displacements(re), b.displacements(im)))
        .collect();
    let rigid = system
        .rigid
        .iter()
        .zip(&layout.rigid)
        .map(|(b, &at)| part(at, b.len()))
        .collect();
    let forces = system
        .connections
        .iter()
        .zip(&kins)
        .zip(&prescribed)
        .map(|((c, kin), vp)| {
            let v_re = kin.apply(&q_re) + vp.0;
            let v_im = kin.apply(&q_im) + vp.1;
            // F = (c + i Omega b) v.
            let (stiffness, damping) = c.law.linearized();
            (
                stiffness * v_re - omega * damping * v_im,
                stiffness * v_im + omega * damping * v_re,
            )
        })
        .collect();
    Ok(HarmonicResponse {
        omega,
        flexible,
        flexible_coords,
        rigid,
        forces,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linear_solve::solve_lu;
    use crate::test_systems::grounded_oscillator;
    use crate::{Connection, Endpoint, ForceLaw, RigidBody, Track};
    use faer::Mat;
    use flexbody_fem::DofKind;
    use flexbody_linalg::ldlt::Factor;
    use flexbody_linalg::SparseMat;

    /// `K - Omega^2 M` of a fixed-free chain of 60 unit springs and masses,
    /// with `Omega^2` between its 5th and 6th eigenvalue (indefinite), and
    /// a damper at every third mass.
    fn chain() -> (SparseMat, SparseMat) {
        let n = 60;
        let omega2 = {
            // lambda_k = 4 sin^2((2k - 1) pi / (2 (2n + 1))) for k = 5, 6.
            let l = |k: f64| {
                4.0 * ((2.0 * k - 1.0) * std::f64::consts::PI / (2.0 * (2 * n + 1) as f64))
                    .sin()
                    .powi(2)
            };
            0.5 * (l(5.0) + l(6.0))
        };
        let mut a = Vec::new();
        let mut b = Vec::new();
        for i in 0..n {
            let diag = if i + 1 == n { 1.0 } else { 2.0 };
            a.push(Triplet::new(i, i, diag - omega2));
            if i + 1 < n {
                a.push(Triplet::new(i, i + 1, -1.0));
                a.push(Triplet::new(i + 1, i, -1.0));
            }
            if i % 3 == 0 {
                b.push(Triplet::new(i, i, 0.05));
            }
        }
        (
            sparse::from_triplets(n, n, &a).unwrap(),
            sparse::from_triplets(n, n, &b).unwrap(),
        )
    }

    #[test]
    fn the_symmetric_solve_equals_the_lu_solve_on_an_indefinite_matrix() {
        let (a, b) = chain();
        let n = a.nrows();
        // The LDL^T exists without pivoting here: its 5 negative pivots are
        // the eigenvalues below Omega^2 (Sylvester).
        let f = Factor::of(&a).unwrap();
        assert_eq!(f.inertia().negative, 5);
        let f_re: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let f_im: Vec<f64> = (0..n).map(|i| (i as f64 * 0.11).cos()).collect();
        let x = solve(&a, &[f_re.clone(), f_im.clone()], 1.0).unwrap();
        let rhs = Mat::from_fn(n, 2, |i, j| [&f_re, &f_im][j][i]);
        let want = solve_lu(&a, &rhs, 1.0).unwrap();
        for j in 0..2 {
            for i in 0..n {
                assert!((x[j][i] - want[(i, j)]).abs() < 1e-10 * want.norm_max());
            }
        }
        // Damped: the real symmetric form [A -B; -B -A] against the LU of
        // the plain real form [A -B; B A].
        let mut sym = Vec::new();
        let mut plain = Vec::new();
        for e in sparse::triplets_of(&a, 1.0) {
            sym.push(Triplet::new(e.row, e.col, e.val));
            sym.push(Triplet::new(e.row + n, e.col + n, -e.val));
            plain.push(Triplet::new(e.row, e.col, e.val));
            plain.push(Triplet::new(e.row + n, e.col + n, e.val));
        }
        for e in sparse::triplets_of(&b, 1.0) {
            sym.push(Triplet::new(e.row, e.col + n, -e.val));
            sym.push(Triplet::new(e.row + n, e.col, -e.val));
            plain.push(Triplet::new(e.row, e.col + n, -e.val));
            plain.push(Triplet::new(e.row + n, e.col, e.val));
        }
        let sym = sparse::from_triplets(2 * n, 2 * n, &sym).unwrap();
        let plain = sparse::from_triplets(2 * n, 2 * n, &plain).unwrap();
        assert!(Factor::of(&sym).is_ok());
        let rhs: Vec<f64> = f_re
            .iter()
            .copied()
            .chain(f_im.iter().map(|v| -v))
            .collect();
        let x = solve(&sym, &[rhs], 1.0).unwrap();
        let rhs = Mat::from_fn(2 * n, 1, |i, _| if i < n { f_re[i] } else { f_im[i - n] });
        let want = solve_lu(&plain, &rhs, 1.0).unwrap();
        for i in 0..2 * n {
            assert!((x[0][i] - want[(i, 0)]).abs() < 1e-10 * want.norm_max());
        }
    }

    #[test]
    fn a_vanishing_pivot_falls_back_to_the_lu() {
        // [0 1; 1 0]: no LDL^T without pivoting, the LU swaps the rows.
        let a = sparse::from_triplets(2, 2, &[Triplet::new(0, 1, 1.0), Triplet::new(1, 0, 1.0)])
            .unwrap();
        assert!(Factor::of(&a).is_err());
        let x = solve(&a, &[vec![3.0, 5.0]], 1.0).unwrap();
        assert_eq!(x, vec![vec![5.0, 3.0]]);
        // Singular: an error naming the frequency, not a wrong answer.
        let zero = sparse::from_triplets(2, 2, &[Triplet::new(0, 0, 1.0)]).unwrap();
        assert!(matches!(
            solve(&zero, &[vec![1.0, 1.0]], 7.0),
            Err(MbsError::Singular { omega }) if omega == 7.0
        ));
    }

    /// A rigid mass on a spring-damper over the track: the closed form
    /// `x = (k + i Omega b) z / (k - m Omega^2 + i Omega b)`.
    #[test]
    fn rigid_mass_on_a_damped_track_spring_matches_the_closed_form() {
        let (m, k, b, a, wavelength, x) = (500.0, 2.0e5, 3.0e3, 0.01, 4.0, 0.7);
        let system = System {
            flexible: vec![],
            rigid: vec![RigidBody {
                name: "mass".into(),
                mass: m,
                inertia: [1.0; 6],
                center: [x, 0.0, 0.5],
                active: vec![DofKind::Uz],
            }],
            connections: vec![Connection {
                name: "spring".into(),
                a: Endpoint::Track { x },
                b: Endpoint::Rigid {
                    body: 0,
                    point: [x, 0.0, 0.5],
                },
                direction: [0.0, 0.0, 1.0],
                law: ForceLaw::linear(k, b),
            }],
            track: Some(Track {
                amplitude: a,
                wavelength,
            }),
        };
        for omega in [0.0, 5.0, 20.0, 80.0] {
            let r = harmonic_response(&system, omega).unwrap();
            let phase = 2.0 * std::f64::consts::PI * x / wavelength;
            let z = (a * phase.cos(), a * phase.sin());
            // (k + i w b) z / (k - m w^2 + i w b), complex arithmetic by hand.
            let num = (k * z.0 - omega * b * z.1, k * z.1 + omega * b * z.0);
            let den = (k - m * omega * omega, omega * b);
            let d2 = den.0 * den.0 + den.1 * den.1;
            let want = (
                (num.0 * den.0 + num.1 * den.1) / d2,
                (num.1 * den.0 - num.0 * den.1) / d2,
            );
            let got = (r.rigid[0].0[0], r.rigid[0].1[0]);
            assert!(
                (got.0 - want.0).abs() + (got.1 - want.1).abs() < 1e-12 * a,
                "{omega}: {got:?} vs {want:?}"
            );
            // Tension F pulls the mass back: m x'' = -F, so F = m Omega^2 x.
            let f = r.forces[0];
            assert!(
                (f.0 - m * omega * omega * got.0).abs() < 1e-9 * k * a,
                "{f:?}"
            );
            assert!(
                (f.1 - m * omega * omega * got.1).abs() < 1e-9 * k * a,
                "{f:?}"
            );
        }
    }

    #[test]
    fn undamped_resonance_is_reported() {
        let (m, k) = (2.0, 8.0);
        let system = grounded_oscillator("mass", "spring", m, k, 0.0);
        assert!(matches!(
            harmonic_response(&system, 2.0),
            Err(MbsError::Singular { .. })
        ));
    }
}
