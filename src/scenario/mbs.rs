//! The MBS around the body: `[[rigid_body]]`, `[track]` and
//! `[[connection]]`.

use super::raw::RawFile;
use flexbody_fem::{Dof, DofKind, Model};
use flexbody_io::{InputError, TomlSource};
use flexbody_mbs::{Connection, Endpoint, RigidBody};
use std::collections::{HashMap, HashSet};

/// The moving rigid bodies, and every rigid body's index among them by
/// name (`None` for a held one, which is ground).
pub(super) struct RigidBodies {
    pub bodies: Vec<RigidBody>,
    pub index: HashMap<String, Option<usize>>,
}

pub(super) fn rigid_bodies(src: TomlSource<'_>, raw: &RawFile) -> Result<RigidBodies, InputError> {
    let mut bodies = Vec::new();
    let mut index: HashMap<String, Option<usize>> = HashMap::new();
    for rb in &raw.rigid_body {
        let b = rb.get_ref();
        if b.name == "ground" || b.name == "track" {
            return Err(src.at(rb, format!("rigid body name '{}' is reserved", b.name)));
        }
        flexbody_fem::require_positive(format!("mass of rigid body '{}'", b.name), b.mass)
            .map_err(|e| src.at(rb, e.to_string()))?;
        flexbody_fem::require_inertia(format!("inertia of rigid body '{}'", b.name), b.inertia)
            .map_err(|e| src.at(rb, e.to_string()))?;
        if let Some(c) = b.center.iter().find(|c| !c.is_finite()) {
            return Err(src.at(
                rb,
                format!("rigid body '{}': center {c} is not finite", b.name),
            ));
        }
        let idx = if b.fixed {
            None
        } else {
            bodies.push(RigidBody {
                name: b.name.clone(),
                mass: b.mass,
                inertia: b.inertia,
                center: b.center,
                active: b.dofs.clone().unwrap_or_else(|| DofKind::ALL.to_vec()),
            });
            Some(bodies.len() - 1)
        };
        if index.insert(b.name.clone(), idx).is_some() {
            return Err(src.at(rb, format!("rigid body '{}' is defined twice", b.name)));
        }
    }
    Ok(RigidBodies { bodies, index })
}

pub(super) fn check_track(src: TomlSource<'_>, raw: &RawFile) -> Result<(), InputError> {
    if let Some(t) = raw.track {
        if !(t.wavelength.is_finite() && t.wavelength > 0.0 && t.amplitude.is_finite()) {
            return Err(src.error(
                None,
                "track: wavelength must be positive and amplitude finite",
            ));
        }
    }
    Ok(())
}

/// "; did you mean 'x'?" for the end name (a rigid body's, `ground` or
/// `track`) nearest to `name`, if one is near.
fn did_you_mean(name: &str, rigid: &RigidBodies) -> String {
    let mut known: Vec<&str> = rigid.index.keys().map(String::as_str).collect();
    known.extend(["ground", "track"]);
    known.sort_unstable();
    flexbody_io::spelling::nearest(name, known)
        .map_or_else(String::new, |n| format!("; did you mean '{n}'?"))
}

/// The connections: end b on the flexible body or a rigid body, end a on
/// ground, the track or a rigid body, and the force law between them.
pub(super) fn connections(
    src: TomlSource<'_>,
    raw: &RawFile,
    model: &Model,
    rigid: &RigidBodies,
) -> Result<Vec<Connection>, InputError> {
    let mut connections = Vec::new();
    let mut names = HashSet::new();
    for c in &raw.connection {
        let r = c.get_ref();
        let offset = c.span().start;
        let what = format!("connection '{}'", r.name);
        if !names.insert(r.name.clone()) {
            return Err(src.at(c, format!("{what} is defined twice")));
        }
        let law = r.law().map_err(|e| src.at(c, format!("{what}: {e}")))?;
        if flexbody_reduce::method::unit(r.direction).is_none() {
            return Err(src.at(c, format!("{what}: direction must be a non-zero vector")));
        }
        let rigid_end = |name: &str, default_point: [f64; 3]| -> Result<Endpoint, InputError> {
            match rigid.index.get(name) {
                Some(None) => Ok(Endpoint::Ground),
                Some(Some(i)) => Ok(Endpoint::Rigid {
                    body: *i,
                    point: r.point.unwrap_or(default_point),
                }),
                None => Err(src.at(
                    c,
                    format!(
                        "{what}: '{name}' is not a rigid body{}",
                        did_you_mean(name, rigid)
                    ),
                )),
            }
        };
        // End b: a node of the flexible body, or a rigid body.
        let (b, b_pos) = match (r.node, &r.body) {
            (Some(node), None) => {
                if model.node(node).is_none() {
                    return Err(src.error(
                        Some(offset),
                        format!("{what} refers to node {node}, which does not exist"),
                    ));
                }
                for (k, kind) in [DofKind::Ux, DofKind::Uy, DofKind::Uz]
                    .into_iter()
                    .enumerate()
                {
                    if r.direction[k] != 0.0
                        && model.dof_map().index_of(Dof::new(node, kind)).is_none()
                    {
                        return Err(src.at(
                            c,
                            format!("{what}: node {node} has no free DOF {kind} along the spring direction"),
                        ));
                    }
                }
                (Endpoint::Flexible { body: 0, node }, model.coords(node))
            }
            (None, Some(body)) => {
                let center = raw
                    .rigid_body
                    .iter()
                    .find(|b| &b.get_ref().name == body)
                    .map_or([0.0; 3], |b| b.get_ref().center);
                (rigid_end(body, center)?, r.point.unwrap_or(center))
            }
            _ => {
                return Err(src.at(
                    c,
                    format!("{what}: give either `node` (flexible body) or `body` (rigid body)"),
                ))
            }
        };
        let a = match r.to.as_str() {
            "ground" => Endpoint::Ground,
            "track" => {
                if raw.track.is_none() {
                    return Err(src.at(
                        c,
                        format!("{what} goes to the track, but there is no [track] table"),
                    ));
                }
                Endpoint::Track {
                    x: r.track_x.unwrap_or(b_pos[0]),
                }
            }
            name if rigid.index.contains_key(name) => rigid_end(name, b_pos)?,
            name => {
                return Err(src.at(
                    c,
                    format!(
                    "{what} goes to '{name}', which is neither ground, track nor a rigid body{}",
                    did_you_mean(name, rigid)
                ),
                ))
            }
        };
        connections.push(Connection {
            name: r.name.clone(),
            a,
            b,
            direction: r.direction,
            law,
        });
    }
    Ok(connections)
}
