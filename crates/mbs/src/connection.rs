//! Connection elements (report eq. 8-10): springs, dampers and nonlinear
//! force laws along a direction `d_n` between two points.

use crate::force_law::ForceLaw;
use serde::{Deserialize, Serialize};

/// One end of a connection.
#[derive(Clone, Debug, PartialEq)]
pub enum Endpoint {
    /// Fixed in space (also: a body held at rest).
    Ground,
    /// A wheel contact point at position `x` (m) along the vehicle, moved
    /// vertically (global z) by the track profile (base excitation).
    Track { x: f64 },
    /// A point (global coordinates, m) of rigid body `body`.
    Rigid { body: usize, point: [f64; 3] },
    /// Node `node` of flexible body `body`.
    Flexible { body: usize, node: u64 },
}

/// A connection element: elongation `v = d^T (u_b - u_a)` (eq. 9), force
/// `F(v, v')` from its law (eq. 10 for a linear spring-damper), tension
/// positive, acting along `d` on b and against it on a.
#[derive(Clone, Debug, PartialEq)]
pub struct Connection {
    pub name: String,
    pub a: Endpoint,
    pub b: Endpoint,
    /// Direction (normalised on use).
    pub direction: [f64; 3],
    pub law: ForceLaw,
}

impl Connection {
    /// A linear spring-damper of stiffness `c` (N/m) and damping `b` (N s/m).
    pub fn linear(
        name: &str,
        a: Endpoint,
        b: Endpoint,
        direction: [f64; 3],
        c: f64,
        damping: f64,
    ) -> Self {
        Self {
            name: name.into(),
            a,
            b,
            direction,
            law: ForceLaw::linear(c, damping),
        }
    }
}

/// Harmonic track profile `z(s) = a cos(2 pi s / L_w)` (report 6.1). A
/// vehicle moving over it at speed V excites at `Omega = 2 pi V / L_w`; the
/// wheel at `x` sees the complex amplitude `a exp(i 2 pi x / L_w)`. A key
/// besides `amplitude` and `wavelength` is refused when read.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Track {
    /// Amplitude a (m).
    pub amplitude: f64,
    /// Wavelength L_w (m).
    pub wavelength: f64,
}

impl Track {
    /// Complex amplitude `(re, im)` of the profile under the wheel at `x`.
    pub fn amplitude_at(&self, x: f64) -> (f64, f64) {
        let phase = 2.0 * std::f64::consts::PI * x / self.wavelength;
        (self.amplitude * phase.cos(), self.amplitude * phase.sin())
    }
}
