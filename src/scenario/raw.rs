//! The scenario tables of a TOML model file as written, with source spans.
//! The model tables are read by [`flexbody_io::model_toml`], which also
//! refuses a top-level key neither reader knows. Every table here refuses
//! a key it does not know (`deny_unknown_fields`), with its line and the
//! nearest valid key.

use flexbody_io::model_toml::DofEntry;
use flexbody_mbs::{ForceLaw, Track};
use flexbody_reduce::Method;
use serde::Deserialize;
use toml::Spanned;

use super::CaseSpec;

/// The top-level keys of the scenario, in the order `docs/model-file.md`
/// gives them; the model's are [`flexbody_io::model_toml::MODEL_KEYS`].
pub(super) const SCENARIO_KEYS: &[&str] = &[
    "interface",
    "track",
    "rigid_body",
    "connection",
    "study",
    "simulation",
    "force",
    "frf",
];

/// The scenario's top-level keys ([`SCENARIO_KEYS`]); the model's are
/// skipped here, and a key neither reader knows is refused by
/// [`flexbody_io::model_toml::parse_model_toml`].
#[derive(Deserialize)]
pub(super) struct RawFile {
    pub interface: Option<RawInterface>,
    pub track: Option<Track>,
    #[serde(default)]
    pub rigid_body: Vec<Spanned<RawRigidBody>>,
    #[serde(default)]
    pub connection: Vec<Spanned<RawConnection>>,
    pub study: Option<RawStudy>,
    pub simulation: Option<Spanned<RawSimulation>>,
    pub frf: Option<Spanned<RawFrf>>,
    #[serde(default)]
    pub force: Vec<Spanned<RawForce>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawInterface {
    #[serde(default)]
    pub dofs: Vec<Spanned<DofEntry>>,
    #[serde(default)]
    pub nodes: Vec<Spanned<u64>>,
    #[serde(default)]
    pub support: Option<Vec<Spanned<DofEntry>>>,
    #[serde(default)]
    pub force_groups: Vec<Spanned<RawForceGroup>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawForceGroup {
    pub name: String,
    pub loads: Vec<RawLoad>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLoad {
    pub node: u64,
    pub dof: flexbody_fem::DofKind,
    pub value: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRigidBody {
    pub name: String,
    pub mass: f64,
    #[serde(default)]
    pub inertia: [f64; 6],
    pub center: [f64; 3],
    #[serde(default)]
    pub dofs: Option<Vec<flexbody_fem::DofKind>>,
    #[serde(default)]
    pub fixed: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawConnection {
    pub name: String,
    /// End b on the flexible body.
    #[serde(default)]
    pub node: Option<u64>,
    /// End b on a rigid body (instead of `node`).
    #[serde(default)]
    pub body: Option<String>,
    /// End a: "ground", "track" or a rigid body's name.
    pub to: String,
    pub direction: [f64; 3],
    #[serde(default)]
    pub law: Option<String>,
    #[serde(default)]
    pub stiffness: Option<f64>,
    #[serde(default)]
    pub damping: Option<f64>,
    #[serde(default)]
    pub points: Option<Vec<[f64; 2]>>,
    #[serde(default)]
    pub clearance: Option<f64>,
    #[serde(default)]
    pub force: Option<f64>,
    #[serde(default)]
    pub velocity: Option<f64>,
    /// Attachment point on a rigid-body end (m).
    #[serde(default)]
    pub point: Option<[f64; 3]>,
    #[serde(default)]
    pub track_x: Option<f64>,
}

/// The force laws a connection's `law` names.
const LAWS: &[&str] = &["linear", "piecewise-linear", "bump-stop", "friction-damper"];

impl RawConnection {
    /// The force law the fields describe, or a message naming what is wrong.
    pub fn law(&self) -> Result<ForceLaw, String> {
        let name = self.law.as_deref().unwrap_or("linear");
        let given: Vec<(&str, bool)> = vec![
            ("stiffness", self.stiffness.is_some()),
            ("damping", self.damping.is_some()),
            ("points", self.points.is_some()),
            ("clearance", self.clearance.is_some()),
            ("force", self.force.is_some()),
            ("velocity", self.velocity.is_some()),
        ];
        let need =
            |field: &str, v: Option<f64>| v.ok_or_else(|| format!("law {name} needs `{field}`"));
        let (law, allowed): (ForceLaw, &[&str]) = match name {
            "linear" => (
                ForceLaw::linear(self.stiffness.unwrap_or(0.0), self.damping.unwrap_or(0.0)),
                &["stiffness", "damping"],
            ),
            "piecewise-linear" => (
                ForceLaw::PiecewiseLinear {
                    points: self
                        .points
                        .clone()
                        .ok_or("law piecewise-linear needs `points` = [[v, F], ...]")?,
                    damping: self.damping.unwrap_or(0.0),
                },
                &["points", "damping"],
            ),
            "bump-stop" => (
                ForceLaw::BumpStop {
                    clearance: need("clearance", self.clearance)?,
                    stiffness: need("stiffness", self.stiffness)?,
                },
                &["clearance", "stiffness"],
            ),
            "friction-damper" => (
                ForceLaw::FrictionDamper {
                    force: need("force", self.force)?,
                    velocity: need("velocity", self.velocity)?,
                },
                &["force", "velocity"],
            ),
            other => {
                let hint = flexbody_io::spelling::nearest(other, LAWS.iter().copied())
                    .map_or_else(String::new, |law| format!("; did you mean `{law}`?"));
                return Err(format!(
                    "unknown law '{other}'{hint} (valid laws: linear, piecewise-linear, bump-stop, friction-damper)"
                ));
            }
        };
        if let Some((field, _)) = given.iter().find(|(f, g)| *g && !allowed.contains(f)) {
            return Err(format!("`{field}` is not a parameter of law {name}"));
        }
        law.validate()?;
        Ok(law)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawStudy {
    pub omegas: Vec<Spanned<f64>>,
    pub cases: Vec<Spanned<CaseSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSimulation {
    #[serde(default)]
    pub method: Option<Method>,
    #[serde(default)]
    pub modes: usize,
    #[serde(default)]
    pub body: Option<String>,
    #[serde(default)]
    pub modal_damping: Vec<f64>,
    pub speed: f64,
    pub duration: f64,
    pub step: f64,
    #[serde(default = "default_alpha")]
    pub alpha: f64,
    #[serde(default)]
    pub adaptive: Option<f64>,
    #[serde(default = "default_max_steps")]
    pub max_steps: usize,
    #[serde(default)]
    pub ramp: f64,
    #[serde(default)]
    pub profile: Option<String>,
    #[serde(default)]
    pub record: Vec<usize>,
    #[serde(default)]
    pub record_nodes: Vec<u64>,
}

fn default_max_steps() -> usize {
    flexbody_mbs::time::DEFAULT_MAX_STEPS
}

fn default_alpha() -> f64 {
    flexbody_mbs::time::TimeSettings::default().alpha
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFrf {
    pub band_hz: [f64; 2],
    pub points: usize,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawForce {
    pub name: String,
    #[serde(default)]
    pub node: Option<u64>,
    #[serde(default)]
    pub body: Option<String>,
    #[serde(default)]
    pub point: Option<[f64; 3]>,
    pub direction: [f64; 3],
    #[serde(default)]
    pub harmonic: Option<RawHarmonic>,
    #[serde(default)]
    pub table: Option<Vec<[f64; 2]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawHarmonic {
    pub amplitude: f64,
    pub frequency_hz: f64,
    #[serde(default)]
    pub phase: f64,
}

#[cfg(test)]
mod tests {
    use super::{RawFile, SCENARIO_KEYS};
    use flexbody_io::model_toml::MODEL_KEYS;
    use flexbody_io::TomlSource;
    use std::path::Path;

    #[test]
    fn every_scenario_key_is_read_and_the_model_keys_are_not() {
        // A date is no valid value of any scenario key: each key is
        // refused with it, so each is read by `RawFile` (not skipped).
        for key in SCENARIO_KEYS {
            let text = format!("{key} = 1979-05-27\n");
            let src = TomlSource::new(Path::new("m.toml"), &text);
            assert!(src.parse::<RawFile>().is_err(), "`{key}` is skipped");
        }
        for key in MODEL_KEYS {
            assert!(!SCENARIO_KEYS.contains(key), "`{key}` is read twice");
            let text = format!("{key} = 1979-05-27\n");
            let src = TomlSource::new(Path::new("m.toml"), &text);
            assert!(src.parse::<RawFile>().is_ok(), "`{key}` is read here");
        }
    }
}
