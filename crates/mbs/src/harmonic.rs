//! Harmonic steady state of the MBS equations (report eq. 11):
//! `(K - Omega^2 M + i Omega D) q = f`, with the track's complex amplitudes
//! (a vehicle over `z(s) = a cos(2 pi s / L_w)`). Nonlinear connections enter
//! with their tangent at rest ([`crate::ForceLaw::linearized`]).

use crate::system::{Assembled, System};
use crate::MbsError;
use faer::linalg::solvers::Solve;
use faer::sparse::Triplet;
use faer::Mat;
use flexbody_linalg::{sparse, SparseMat};

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
    let (q_re, q_im) = if damped || load_im.iter().any(|v| *v != 0.0) {
        // [A  -B; B  A] [x; y] = [f_re; f_im], B = Omega D.
        let mut t = Vec::new();
        for e in sparse::triplets_of(&a, 1.0) {
            t.push(Triplet::new(e.row, e.col, e.val));
            t.push(Triplet::new(e.row + n, e.col + n, e.val));
        }
        for e in sparse::triplets_of(&damping, omega) {
            t.push(Triplet::new(e.row, e.col + n, -e.val));
            t.push(Triplet::new(e.row + n, e.col, e.val));
        }
        let big = sparse::from_triplets(2 * n, 2 * n, &t)?;
        let rhs: Vec<f64> = load_re.iter().chain(load_im.iter()).copied().collect();
        let x = solve(&big, &rhs, omega)?;
        (x[..n].to_vec(), x[n..].to_vec())
    } else {
        (solve(&a, &load_re, omega)?, vec![0.0; n])
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

/// Sparse LU solve with a residual check (a singular dynamic stiffness
/// shows up as a non-finite or inaccurate solution).
fn solve(a: &SparseMat, b: &[f64], omega: f64) -> Result<Vec<f64>, MbsError> {
    let n = b.len();
    let lu = a.sp_lu().map_err(|_| MbsError::Singular { omega })?;
    let rhs = Mat::from_fn(n, 1, |i, _| b[i]);
    let x = lu.solve(rhs.as_ref());
    let r = a * &x - &rhs;
    let finite = (0..n).all(|i| x[(i, 0)].is_finite());
    let a_max = a.as_ref().val().iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let scale = a_max * x.norm_max() + rhs.norm_max();
    let accurate = r.norm_max() <= 1e-8 * scale; // false for NaN too
    if !finite || !accurate {
        return Err(MbsError::Singular { omega });
    }
    Ok((0..n).map(|i| x[(i, 0)]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Connection, Endpoint, ForceLaw, RigidBody, Track};
    use flexbody_fem::DofKind;

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
        let system = System {
            rigid: vec![RigidBody {
                name: "mass".into(),
                mass: m,
                inertia: [0.0; 6],
                center: [0.0; 3],
                active: vec![DofKind::Uz],
            }],
            connections: vec![Connection {
                name: "spring".into(),
                a: Endpoint::Ground,
                b: Endpoint::Rigid {
                    body: 0,
                    point: [0.0; 3],
                },
                direction: [0.0, 0.0, 1.0],
                law: ForceLaw::linear(k, 0.0),
            }],
            ..Default::default()
        };
        assert!(matches!(
            harmonic_response(&system, 2.0),
            Err(MbsError::Singular { .. })
        ));
    }
}
