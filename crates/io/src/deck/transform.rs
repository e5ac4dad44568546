//! `*TRANSFORM, NSET=, TYPE=R|C`: local DOF directions at nodes, as
//! CalculiX reads them. At a transformed node, `*BOUNDARY` and `*EQUATION`
//! name local DOFs (translations and rotations along the local axes); the
//! model stays global (see [`flexbody_fem::transform`]). The data line
//! holds points `a` and `b` as in `*ORIENTATION`: rectangular, local x
//! along `a` and local y in the plane of `a` and `b`; cylindrical, the axis
//! from `a` to `b` with local x radial, y tangential and z axial at the
//! node. When several `*TRANSFORM`s name a node, the last one holds.

use super::cards::{name, Card, Files, Loc};
use super::keywords::Reader;
use crate::InputError;
use flexbody_fem::transform::{family, fixed_local};
use flexbody_fem::{Dof, Equation, NodeId, Orientation};
use std::collections::{BTreeMap, HashMap};

/// A `*TRANSFORM` as read.
pub(super) struct RawTransform {
    pub nset: String,
    pub system: Orientation,
    pub loc: Loc,
}

/// The local axes of a transformed node (columns in global components)
/// and the `*TRANSFORM` line that gave them.
pub(super) type NodalSystems = HashMap<NodeId, ([[f64; 3]; 3], Loc)>;

impl Reader<'_> {
    /// `*TRANSFORM, NSET=[, TYPE=R|C]`: one line `a, b` (six coordinates).
    pub(super) fn transform(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["NSET", "TYPE"]);
        let nset = card.require_name(self.files, "NSET")?;
        let what = format!("*TRANSFORM, NSET={nset}");
        let [line] = card.data.as_slice() else {
            return Err(self.files.error(
                card.loc,
                format!("{what} takes one data line: the coordinates of points a and b"),
            ));
        };
        let mut p = [0.0; 6];
        for (i, v) in p.iter_mut().enumerate() {
            *v = line.float(
                self.files,
                i,
                &format!("{what}: coordinate {} of a, b", i + 1),
            )?;
        }
        let (a, b) = ([p[0], p[1], p[2]], [p[3], p[4], p[5]]);
        let system = match card.value("TYPE").map(name).as_deref() {
            None | Some("R") => Orientation::rectangular(a, b),
            Some("C") => Orientation::cylindrical(a, b),
            Some(other) => {
                return Err(self.files.error(
                    card.loc,
                    format!("{what}: TYPE={other}: expected R (rectangular) or C (cylindrical)"),
                ))
            }
        }
        .map_err(|e| self.files.error(line.loc, format!("{what}: {e}")))?;
        self.transforms.push(RawTransform {
            nset,
            system,
            loc: card.loc,
        });
        Ok(())
    }
}

/// The nodal systems of the `*TRANSFORM`s, evaluated at the nodes (a
/// cylindrical system turns with the node's position); an error names a
/// node set that is not defined and a node on a cylindrical system's axis.
pub(super) fn nodal_systems(
    files: &Files,
    transforms: &[RawTransform],
    node_sets: &BTreeMap<String, Vec<(NodeId, Loc)>>,
    coords: &HashMap<NodeId, [f64; 3]>,
) -> Result<NodalSystems, InputError> {
    let mut systems = NodalSystems::new();
    for t in transforms {
        let members = node_sets.get(&t.nset).ok_or_else(|| {
            files.error(
                t.loc,
                format!("*TRANSFORM: node set '{}' is not defined", t.nset),
            )
        })?;
        for &(node, _) in members {
            let Some(&x) = coords.get(&node) else {
                continue; // an undefined set member is reported with its set
            };
            let r = t.system.axes_at(x).map_err(|e| {
                files.error(
                    t.loc,
                    format!("*TRANSFORM, NSET={}: node {node}: {e}", t.nset),
                )
            })?;
            systems.insert(node, (r, t.loc));
        }
    }
    Ok(systems)
}

/// Whether the local DOF `dof` of a transformed node exists: `Some(true)`
/// if the node has all three global DOFs of its family, `Some(false)` if
/// none, `None` if only some (a local direction that mixes DOFs the node
/// has with DOFs it has not).
pub(super) fn local_dof_exists(dof: Dof, has: impl Fn(&Dof) -> bool) -> Option<bool> {
    let n = family(dof.kind)
        .into_iter()
        .filter(|k| has(&Dof::new(dof.node, *k)))
        .count();
    match n {
        0 => Some(false),
        3 => Some(true),
        _ => None,
    }
}

/// The fixed DOFs with those of transformed nodes turned global: fixed
/// global DOFs where a local axis lies along a global one, equations
/// (named `*BOUNDARY on node N (line L)`, their line in `locs`) for the
/// others.
pub(super) fn global_fixed(
    fixed: Vec<(Dof, Loc)>,
    systems: &NodalSystems,
    locs: &mut HashMap<String, Loc>,
) -> (Vec<Dof>, Vec<Equation>) {
    let mut global = Vec::with_capacity(fixed.len());
    let mut local: BTreeMap<NodeId, (Vec<flexbody_fem::DofKind>, Loc)> = BTreeMap::new();
    for (dof, loc) in fixed {
        if systems.contains_key(&dof.node) {
            local
                .entry(dof.node)
                .or_insert((Vec::new(), loc))
                .0
                .push(dof.kind);
        } else {
            global.push(dof);
        }
    }
    let mut equations = Vec::new();
    for (node, (kinds, loc)) in local {
        let (r, _) = &systems[&node];
        let name = format!("*BOUNDARY in the local system of node {node}");
        let (fixed, eqs) = fixed_local(node, r, &kinds, &name);
        if !eqs.is_empty() {
            locs.insert(name, loc);
        }
        global.extend(fixed);
        equations.extend(eqs);
    }
    (global, equations)
}
