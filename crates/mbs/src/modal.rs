//! The damped quadratic eigenproblem of the coupled system (report eq. 21):
//! `(lambda^2 M + lambda D + K) t = 0`. Each complex pair
//! `lambda = -zeta omega ± i omega sqrt(1 - zeta^2)` gives a natural
//! frequency omega and a damping ratio zeta. Nonlinear connections enter with
//! their tangent at rest.
//!
//! Numerics: the first-order form `[0 I; -M^-1 K  -M^-1 D]` is far from
//! normal when the spectrum spans many decades (residual static modes are
//! stiff), and a general eigensolver then loses the low modes. Instead the
//! undamped problem `K phi = omega^2 M phi` is solved first (symmetric,
//! accurate), and in the scaled modal state `[Omega y; y']` the system
//! matrix is `[0 Omega; -Omega  -Phi^T D Phi]`: nearly normal, so its
//! eigenvalues carry an absolute error of round-off times omega_max only.
//! Dense: for reduced systems.

use crate::system::{Assembled, System};
use crate::MbsError;
use faer::Mat;
use flexbody_linalg::eigen::{ensure_dense_room, generalized_symmetric};
use flexbody_linalg::memory::Budget;
use flexbody_linalg::LinalgError;
use flexbody_reduce::modes::DENSE_LIMIT;

/// One damped mode (of a complex-conjugate pair, or a real overdamped root).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct DampedMode {
    /// lambda = (re, im) (1/s).
    pub eigenvalue: (f64, f64),
    /// Undamped natural frequency |lambda| / 2 pi (Hz).
    pub natural_hz: f64,
    /// Damped frequency |Im lambda| / 2 pi (Hz).
    pub damped_hz: f64,
    /// zeta = -Re lambda / |lambda| (1 for a real root; 0 for |lambda| = 0).
    pub damping_ratio: f64,
}

/// Damped modes of `system`, ascending natural frequency; each conjugate
/// pair once. Dense: a system of more than [`DENSE_LIMIT`] coordinates (a
/// full FE model) is an error.
pub fn damped_modes(system: &System) -> Result<Vec<DampedMode>, MbsError> {
    let layout = system.layout();
    let kins = system.all_kinematics(&layout)?;
    let Assembled {
        mass,
        damping,
        stiffness,
    } = system.assemble(&kins, true)?;
    let n = layout.len;
    if n > DENSE_LIMIT {
        return Err(MbsError::TooLargeForDense {
            coordinates: n,
            limit: DENSE_LIMIT,
        });
    }
    ensure_dense_room(n, 2, Budget::MACHINE)?;
    let undamped = generalized_symmetric(stiffness.to_dense().as_ref(), mass.to_dense().as_ref())?;
    if undamped.values.len() != n {
        // Massless coordinates (infinite eigenvalues) or a spectrum wider
        // than the dense solver resolves: the modal damping matrix below
        // would miss coordinates.
        return Err(MbsError::UnresolvedModes {
            found: undamped.values.len(),
            coordinates: n,
        });
    }
    let phi = &undamped.vectors;
    let omega: Vec<f64> = undamped.values.iter().map(|l| l.max(0.0).sqrt()).collect();
    let d_modal = phi.transpose() * damping.to_dense() * phi;
    let a = Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => 0.0,
        (true, false) => {
            if i == j - n {
                omega[i]
            } else {
                0.0
            }
        }
        (false, true) => {
            if i - n == j {
                -omega[j]
            } else {
                0.0
            }
        }
        (false, false) => -d_modal[(i - n, j - n)],
    });
    let values = a
        .eigenvalues()
        .map_err(|e| MbsError::Linalg(LinalgError::Faer(format!("{e:?}"))))?;
    let scale = values.iter().fold(0.0_f64, |s, v| s.max(v.re.hypot(v.im)));
    let mut modes: Vec<DampedMode> = values
        .iter()
        .filter(|v| v.im >= -1e-12 * scale)
        .map(|v| {
            let abs = v.re.hypot(v.im);
            DampedMode {
                eigenvalue: (v.re, v.im.max(0.0)),
                natural_hz: abs / (2.0 * std::f64::consts::PI),
                damped_hz: v.im.abs() / (2.0 * std::f64::consts::PI),
                damping_ratio: if abs > 1e-12 * scale {
                    -v.re / abs
                } else {
                    0.0
                },
            }
        })
        .collect();
    modes.sort_by(|a, b| a.natural_hz.total_cmp(&b.natural_hz));
    Ok(modes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_systems::grounded_oscillator;
    use crate::{Connection, Endpoint, RigidBody};
    use flexbody_fem::DofKind;

    #[test]
    fn one_damped_oscillator_has_its_frequency_and_ratio() {
        let (m, k, zeta): (f64, f64, f64) = (3.0, 1200.0, 0.05);
        let omega = (k / m).sqrt();
        let s = grounded_oscillator("m", "kc", m, k, 2.0 * zeta * omega * m);
        let modes = damped_modes(&s).unwrap();
        assert_eq!(modes.len(), 1);
        let md = modes[0];
        assert!((md.natural_hz * 2.0 * std::f64::consts::PI - omega).abs() < 1e-12 * omega);
        assert!((md.damping_ratio - zeta).abs() < 1e-12);
        assert!((md.damped_hz / md.natural_hz - (1.0 - zeta * zeta).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_system_beyond_the_dense_solver_is_refused_by_name() {
        // A full FE model's coordinates would ask the dense solver for
        // n^2 numbers (720 GB at 3e5): an error before any is allocated.
        let n = DENSE_LIMIT + 1;
        let s = System {
            rigid: (0..n)
                .map(|i| RigidBody {
                    name: format!("m{i}"),
                    mass: 1.0,
                    inertia: [0.0; 6],
                    center: [i as f64, 0.0, 0.0],
                    active: vec![DofKind::Uz],
                })
                .collect(),
            ..Default::default()
        };
        let err = damped_modes(&s).unwrap_err();
        assert!(matches!(
            err,
            MbsError::TooLargeForDense { coordinates, limit } if coordinates == n && limit == DENSE_LIMIT
        ));
        assert!(err.to_string().contains("reduce the body first"));
    }

    #[test]
    fn a_massless_coordinate_is_named_not_a_failed_factorisation() {
        // A body without rotary inertia pitching on two springs: the pitch
        // has stiffness but no mass, an infinite eigenvalue.
        let spring = |name: &str, x: f64| {
            Connection::linear(
                name,
                Endpoint::Ground,
                Endpoint::Rigid {
                    body: 0,
                    point: [x, 0.0, 0.0],
                },
                [0.0, 0.0, 1.0],
                1e5,
                10.0,
            )
        };
        let s = System {
            rigid: vec![RigidBody {
                name: "m".into(),
                mass: 2.0,
                inertia: [0.0; 6],
                center: [0.0; 3],
                active: vec![DofKind::Uz, DofKind::Ry],
            }],
            connections: vec![spring("front", 1.0), spring("rear", -1.0)],
            ..Default::default()
        };
        let err = damped_modes(&s).unwrap_err();
        assert!(
            matches!(
                err,
                MbsError::UnresolvedModes {
                    found: 1,
                    coordinates: 2
                }
            ),
            "{err}"
        );
        assert!(err.to_string().contains("massless"), "{err}");
    }
}
