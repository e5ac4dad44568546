//! The `[simulation]` table, its `[[force]]` entries and track profiles.

use super::mbs::RigidBodies;
use super::raw::{RawFile, RawForce, RawSimulation};
use super::{BodySource, SimulationSpec};
use flexbody_fem::Model;
use flexbody_io::{InputError, TomlSource};
use flexbody_mbs::time::{Excitation, History, Profile, TimeForce, TimeSettings};
use flexbody_mbs::Endpoint;
use std::path::Path;
use toml::Spanned;

/// The run in time: where the body comes from, the integrator's settings,
/// the excitation and what is recorded.
pub(super) fn simulation(
    src: TomlSource<'_>,
    sim: &Spanned<RawSimulation>,
    raw: &RawFile,
    model: &Model,
    rigid: &RigidBodies,
) -> Result<SimulationSpec, InputError> {
    let r = sim.get_ref();
    let bad = |message: String| src.at(sim, format!("simulation: {message}"));
    let body = match (&r.body, r.method) {
        (Some(file), None) => BodySource::File(src.relative(file)),
        (None, Some(method)) => BodySource::Reduce {
            method,
            modes: r.modes,
        },
        _ => {
            return Err(bad(
                "give either `method` (and `modes`) or `body` (a reduced-body file)".into(),
            ))
        }
    };
    let settings = TimeSettings {
        step: r.step,
        duration: r.duration,
        alpha: r.alpha,
        adaptive: r.adaptive,
        max_steps: r.max_steps,
        ..TimeSettings::default()
    };
    settings.validate().map_err(bad)?;
    if !(r.speed.is_finite() && r.speed >= 0.0) {
        return Err(bad(format!("speed {} must be >= 0 (m/s)", r.speed)));
    }
    if !(r.ramp.is_finite() && r.ramp >= 0.0) {
        return Err(bad(format!("ramp {} must be >= 0 (s)", r.ramp)));
    }
    if let Some(z) = r
        .modal_damping
        .iter()
        .find(|z| !(z.is_finite() && **z >= 0.0))
    {
        return Err(bad(format!("modal damping ratio {z} must be >= 0")));
    }
    let profile = match &r.profile {
        None => None,
        Some(file) => Some(read_profile(&src.relative(file))?),
    };
    if profile.is_none()
        && raw.track.is_none()
        && raw.connection.iter().any(|c| c.get_ref().to == "track")
    {
        return Err(bad(
            "the track moves but there is neither a [track] table nor a `profile` file".into(),
        ));
    }
    check_records(r, model).map_err(bad)?;
    let forces = raw
        .force
        .iter()
        .map(|f| force(src, f, model, rigid))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(SimulationSpec {
        body,
        modal_damping: r.modal_damping.clone(),
        settings,
        excitation: Excitation {
            speed: r.speed,
            profile,
            ramp: r.ramp,
            forces,
        },
        record: r.record.clone(),
        record_nodes: r.record_nodes.clone(),
    })
}

/// Recorded elements have section forces (beams) and recorded nodes are
/// nodes of elements with stresses (solids, shells).
fn check_records(r: &RawSimulation, model: &Model) -> Result<(), String> {
    for e in &r.record {
        match model.elements().iter().find(|x| x.id() == *e) {
            Some(x) if x.has_section_forces() => {}
            Some(_) => {
                return Err(format!(
                    "record: element {e} is not a beam; section forces are recorded for beams"
                ))
            }
            None => return Err(format!("record: element {e} does not exist")),
        }
    }
    for n in &r.record_nodes {
        let on_solid = model
            .elements()
            .iter()
            .any(|e| e.has_stresses() && e.nodes().contains(n));
        if !on_solid {
            return Err(format!(
                "record_nodes: node {n} is not a node of a solid element"
            ));
        }
    }
    Ok(())
}

/// One `[[force]]`: a time history along a direction at a node of the
/// body or a point of a moving rigid body.
fn force(
    src: TomlSource<'_>,
    f: &Spanned<RawForce>,
    model: &Model,
    rigid: &RigidBodies,
) -> Result<TimeForce, InputError> {
    let x = f.get_ref();
    let what = format!("force '{}'", x.name);
    let at = match (x.node, &x.body) {
        (Some(node), None) => {
            if model.node(node).is_none() {
                return Err(src.at(
                    f,
                    format!("{what} refers to node {node}, which does not exist"),
                ));
            }
            Endpoint::Flexible { body: 0, node }
        }
        (None, Some(name)) => match rigid.index.get(name) {
            Some(Some(i)) => Endpoint::Rigid {
                body: *i,
                point: x.point.unwrap_or([0.0; 3]),
            },
            _ => return Err(src.at(f, format!("{what}: '{name}' is not a moving rigid body"))),
        },
        _ => return Err(src.at(f, format!("{what}: give either `node` or `body`"))),
    };
    let history = match (&x.harmonic, &x.table) {
        (Some(h), None) => History::Harmonic {
            amplitude: h.amplitude,
            frequency_hz: h.frequency_hz,
            phase: h.phase,
        },
        (None, Some(rows)) => {
            if rows
                .windows(2)
                .any(|w| w[1][0].partial_cmp(&w[0][0]) != Some(std::cmp::Ordering::Greater))
            {
                return Err(src.at(f, format!("{what}: table times must ascend")));
            }
            History::Table(rows.clone())
        }
        _ => return Err(src.at(f, format!("{what}: give either `harmonic` or `table`"))),
    };
    if flexbody_reduce::method::unit(x.direction).is_none() {
        return Err(src.at(f, format!("{what}: direction must be a non-zero vector")));
    }
    Ok(TimeForce {
        name: x.name.clone(),
        at,
        direction: x.direction,
        history,
    })
}
/// Reads a track profile: one `s, z` row per line (m), `#` comments and a
/// header line allowed, s strictly ascending.
pub fn read_profile(path: &Path) -> Result<Profile, InputError> {
    let text = flexbody_io::text::read_text(path)?;
    let bad = |line: usize, message: String| InputError::Invalid {
        path: path.to_path_buf(),
        line: Some(line),
        message,
    };
    let (mut s, mut z) = (Vec::new(), Vec::new());
    for (k, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split([',', ';', ' ', '\t'])
            .filter(|f| !f.is_empty())
            .collect();
        let parsed: Option<Vec<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        match parsed {
            None if s.is_empty()
                && z.is_empty()
                && fields.iter().all(|f| f.parse::<f64>().is_err()) =>
            {
                continue
            } // header
            Some(v) if v.len() == 2 && v.iter().all(|x| x.is_finite()) => {
                if let Some(last) = s.last() {
                    if v[0] <= *last {
                        return Err(bad(
                            k + 1,
                            format!("s = {} does not ascend (previous {last})", v[0]),
                        ));
                    }
                }
                s.push(v[0]);
                z.push(v[1]);
            }
            _ => {
                return Err(bad(
                    k + 1,
                    format!("expected two numbers `s, z` (m), got `{raw}`"),
                ))
            }
        }
    }
    if s.len() < 2 {
        return Err(InputError::Invalid {
            path: path.to_path_buf(),
            line: None,
            message: "a track profile needs at least two rows".into(),
        });
    }
    Ok(Profile::Table { s, z })
}
