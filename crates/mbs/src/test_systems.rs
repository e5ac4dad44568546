//! Systems the unit tests of several modules build.

use crate::{Connection, Endpoint, RigidBody, System};
use flexbody_fem::DofKind;

/// A rigid body `body` of mass `m` at the origin, moving in `uz` only, on a
/// spring-damper `spring` to ground of stiffness `k` and damping `b`.
pub(crate) fn grounded_oscillator(
    body: &str,
    spring: &str,
    m: f64,
    k: f64,
    b: f64,
) -> System<'static> {
    System {
        rigid: vec![RigidBody {
            name: body.into(),
            mass: m,
            inertia: [0.0; 6],
            center: [0.0; 3],
            active: vec![DofKind::Uz],
        }],
        connections: vec![Connection::linear(
            spring,
            Endpoint::Ground,
            Endpoint::Rigid {
                body: 0,
                point: [0.0; 3],
            },
            [0.0, 0.0, 1.0],
            k,
            b,
        )],
        ..Default::default()
    }
}
