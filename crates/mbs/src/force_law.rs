//! Force laws of connection elements: the force F (N, tension positive) as a
//! function of the elongation v (m) and its rate v' (m/s). The linear law is
//! eq. 10 with viscous damping; the others replace it in the time domain,
//! which is what the free-residual method leaves room for (report 6.6).

use serde::{Deserialize, Serialize};

/// A connection's force law.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ForceLaw {
    /// `F = c v + b v'` (eq. 10 with a viscous damper).
    Linear {
        /// c (N/m).
        stiffness: f64,
        /// b (N s/m).
        #[serde(default)]
        damping: f64,
    },
    /// `F = f(v) + b v'` with `f` piecewise linear through `points`
    /// (`[v, F]` pairs, v ascending), extended with the end slopes.
    PiecewiseLinear {
        points: Vec<[f64; 2]>,
        #[serde(default)]
        damping: f64,
    },
    /// A bump stop: no force until the connection has shortened by
    /// `clearance` (m); beyond, `F = c (v + clearance)` (compression).
    BumpStop { clearance: f64, stiffness: f64 },
    /// Friction-like damper with a smooth law: `F = F_max tanh(v' / v_ref)`.
    FrictionDamper {
        /// F_max (N).
        force: f64,
        /// v_ref (m/s): the rate at which the force reaches 76 % of F_max.
        velocity: f64,
    },
}

impl ForceLaw {
    /// A linear spring-damper.
    pub fn linear(stiffness: f64, damping: f64) -> Self {
        ForceLaw::Linear { stiffness, damping }
    }

    /// Force at elongation `v` and rate `v_dot`.
    pub fn force(&self, v: f64, v_dot: f64) -> f64 {
        match self {
            ForceLaw::Linear { stiffness, damping } => stiffness * v + damping * v_dot,
            ForceLaw::PiecewiseLinear { points, damping } => {
                piecewise(points, v).0 + damping * v_dot
            }
            ForceLaw::BumpStop {
                clearance,
                stiffness,
            } => {
                if v < -clearance {
                    stiffness * (v + clearance)
                } else {
                    0.0
                }
            }
            ForceLaw::FrictionDamper { force, velocity } => force * (v_dot / velocity).tanh(),
        }
    }

    /// Tangent `(dF/dv, dF/dv')` at `(v, v_dot)`.
    pub fn tangent(&self, v: f64, v_dot: f64) -> (f64, f64) {
        match self {
            ForceLaw::Linear { stiffness, damping } => (*stiffness, *damping),
            ForceLaw::PiecewiseLinear { points, damping } => (piecewise(points, v).1, *damping),
            ForceLaw::BumpStop {
                clearance,
                stiffness,
            } => (if v < -clearance { *stiffness } else { 0.0 }, 0.0),
            ForceLaw::FrictionDamper { force, velocity } => {
                let c = (v_dot / velocity).cosh();
                (0.0, force / (velocity * c * c))
            }
        }
    }

    /// Stored energy at elongation `v` (J); zero for the damper.
    pub fn potential(&self, v: f64) -> f64 {
        match self {
            ForceLaw::Linear { stiffness, .. } => 0.5 * stiffness * v * v,
            ForceLaw::PiecewiseLinear { points, .. } => piecewise_integral(points, v),
            ForceLaw::BumpStop {
                clearance,
                stiffness,
            } => {
                if v < -clearance {
                    0.5 * stiffness * (v + clearance).powi(2)
                } else {
                    0.0
                }
            }
            ForceLaw::FrictionDamper { .. } => 0.0,
        }
    }

    /// True for the linear law.
    pub fn is_linear(&self) -> bool {
        matches!(self, ForceLaw::Linear { .. })
    }

    /// The tangent at rest `(c, b)`: what frequency-domain methods use.
    pub fn linearized(&self) -> (f64, f64) {
        self.tangent(0.0, 0.0)
    }

    /// Checks the parameters; the message says what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        match self {
            ForceLaw::Linear { stiffness, damping } => {
                if !(ok(*stiffness) && ok(*damping)) {
                    return Err(format!("stiffness {stiffness} and damping {damping} must be finite and not negative"));
                }
            }
            ForceLaw::PiecewiseLinear { points, damping } => {
                if points.len() < 2 {
                    return Err("a piecewise-linear law needs at least two points".into());
                }
                if let Some(w) = points
                    .windows(2)
                    .find(|w| w[1][0].partial_cmp(&w[0][0]) != Some(std::cmp::Ordering::Greater))
                {
                    return Err(format!(
                        "points must have ascending elongations; {} does not follow {}",
                        w[1][0], w[0][0]
                    ));
                }
                if points.iter().flatten().any(|x| !x.is_finite()) || !ok(*damping) {
                    return Err("points and damping must be finite (damping not negative)".into());
                }
            }
            ForceLaw::BumpStop {
                clearance,
                stiffness,
            } => {
                if !(ok(*clearance) && ok(*stiffness)) {
                    return Err(format!("clearance {clearance} and stiffness {stiffness} must be finite and not negative"));
                }
            }
            ForceLaw::FrictionDamper { force, velocity } => {
                if !(ok(*force) && velocity.is_finite() && *velocity > 0.0) {
                    return Err(format!(
                        "force {force} must be >= 0 and velocity {velocity} > 0"
                    ));
                }
            }
        }
        Ok(())
    }
}

/// `(f(v), f'(v))` of the piecewise-linear curve.
fn piecewise(points: &[[f64; 2]], v: f64) -> (f64, f64) {
    let k = segment(points, v);
    let ([v0, f0], [v1, f1]) = (points[k], points[k + 1]);
    let slope = (f1 - f0) / (v1 - v0);
    (f0 + slope * (v - v0), slope)
}

/// The segment used at `v` (end segments extend outwards).
fn segment(points: &[[f64; 2]], v: f64) -> usize {
    let n = points.len();
    (0..n - 1).find(|&k| v < points[k + 1][0]).unwrap_or(n - 2)
}

/// `integral_0^v f(s) ds` of the piecewise-linear curve.
fn piecewise_integral(points: &[[f64; 2]], v: f64) -> f64 {
    // Trapezoids between 0 and v, split at the breakpoints in between.
    let (lo, hi, sign) = if v >= 0.0 {
        (0.0, v, 1.0)
    } else {
        (v, 0.0, -1.0)
    };
    let mut cuts = vec![lo];
    cuts.extend(points.iter().map(|p| p[0]).filter(|x| *x > lo && *x < hi));
    cuts.push(hi);
    let area: f64 = cuts
        .windows(2)
        .map(|w| 0.5 * (w[1] - w[0]) * (piecewise(points, w[0]).0 + piecewise(points, w[1]).0))
        .sum();
    sign * area
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central differences of force and potential agree with the tangent and
    /// the force.
    #[test]
    fn tangents_and_potentials_are_consistent() {
        let laws = [
            ForceLaw::linear(1e5, 3e2),
            ForceLaw::PiecewiseLinear {
                points: vec![[-0.01, -2e3], [0.0, 0.0], [0.02, 1e3]],
                damping: 10.0,
            },
            ForceLaw::BumpStop {
                clearance: 0.01,
                stiffness: 1e6,
            },
            ForceLaw::FrictionDamper {
                force: 500.0,
                velocity: 0.05,
            },
        ];
        for law in &laws {
            law.validate().unwrap();
            for (v, vd) in [(-0.03, -0.1), (-0.005, 0.02), (0.011, 0.3), (0.05, -0.04)] {
                let h = 1e-7;
                let (kv, kd) = law.tangent(v, vd);
                let dfdv = (law.force(v + h, vd) - law.force(v - h, vd)) / (2.0 * h);
                let dfdd = (law.force(v, vd + h) - law.force(v, vd - h)) / (2.0 * h);
                assert!((dfdv - kv).abs() <= 1e-6 * kv.abs().max(1.0), "{law:?} {v}");
                assert!(
                    (dfdd - kd).abs() <= 1e-6 * kd.abs().max(1.0),
                    "{law:?} {vd}"
                );
                let dpdv = (law.potential(v + h) - law.potential(v - h)) / (2.0 * h);
                let elastic = law.force(v, 0.0);
                assert!(
                    (dpdv - elastic).abs() <= 1e-5 * elastic.abs().max(1.0),
                    "{law:?} {v}: {dpdv} vs {elastic}"
                );
            }
        }
    }

    #[test]
    fn bump_stop_pushes_only_beyond_its_clearance() {
        let b = ForceLaw::BumpStop {
            clearance: 0.02,
            stiffness: 1e6,
        };
        assert_eq!(b.force(-0.019, 0.0), 0.0);
        assert_eq!(b.force(0.5, 0.0), 0.0);
        assert!((b.force(-0.03, 0.0) + 1e4).abs() < 1e-9);
        assert_eq!(b.linearized(), (0.0, 0.0));
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = ForceLaw::PiecewiseLinear {
            points: vec![[0.0, 0.0], [0.0, 1.0]],
            damping: 0.0,
        }
        .validate();
        assert!(e.unwrap_err().contains("ascending"));
    }
}
