//! The `[interface]` table: the DOFs a reduced body keeps, the support of
//! its inertia-relief modes and its force groups; without the table, the
//! DOFs the connections act on.

use super::raw::RawFile;
use flexbody_fem::{Dof, DofKind, Model};
use flexbody_io::model_toml::DofEntry;
use flexbody_io::{InputError, TomlSource};
use flexbody_reduce::ForceGroup;
use std::collections::HashSet;
use toml::Spanned;

/// The interface of the reduction, checked against the model.
pub(super) struct Interface {
    pub dofs: Vec<Dof>,
    pub support: Option<Vec<Dof>>,
    pub force_groups: Vec<ForceGroup>,
}

pub(super) fn interface(
    src: TomlSource<'_>,
    raw: &RawFile,
    model: &Model,
) -> Result<Interface, InputError> {
    let free_dof = |d: &Spanned<DofEntry>, what: &str| -> Result<Dof, InputError> {
        let dof = d.get_ref().dof();
        if model.node(dof.node).is_none() {
            return Err(src.error(
                Some(d.span().start),
                format!("{what} refers to node {}, which does not exist", dof.node),
            ));
        }
        if model.dof_map().index_of(dof).is_none() {
            return Err(src.at(d, format!("{what}: {dof} is not a free DOF of the model")));
        }
        Ok(dof)
    };
    let mut out = Interface {
        dofs: Vec::new(),
        support: None,
        force_groups: Vec::new(),
    };
    if let Some(i) = &raw.interface {
        for d in &i.dofs {
            out.dofs.push(free_dof(d, "interface")?);
        }
        for n in &i.nodes {
            let node = *n.get_ref();
            if model.node(node).is_none() {
                return Err(src.error(
                    Some(n.span().start),
                    format!("interface refers to node {node}, which does not exist"),
                ));
            }
            out.dofs.extend(
                model
                    .dof_map()
                    .node_dofs(node)
                    .into_iter()
                    .map(|(k, _)| Dof::new(node, k)),
            );
        }
        for g in &i.force_groups {
            out.force_groups.push(force_group(src, g, model)?);
        }
        if let Some(s) = &i.support {
            out.support = Some(
                s.iter()
                    .map(|d| free_dof(d, "interface support"))
                    .collect::<Result<Vec<_>, _>>()?,
            );
        }
    } else {
        for c in &raw.connection {
            let r = c.get_ref();
            let Some(node) = r.node else { continue };
            for (k, kind) in [DofKind::Ux, DofKind::Uy, DofKind::Uz]
                .into_iter()
                .enumerate()
            {
                let d = Dof::new(node, kind);
                // At a node with local axes the interface DOFs are local;
                // the connection's global direction needs all three.
                let along = r.direction[k] != 0.0 || model.local_axes().contains_key(&node);
                if along && !out.dofs.contains(&d) {
                    out.dofs.push(d);
                }
            }
        }
    }
    let mut seen = HashSet::new();
    for d in &out.dofs {
        if !seen.insert(*d) {
            return Err(src.error(None, format!("interface: {d} is listed twice")));
        }
    }
    Ok(out)
}

/// One `[[interface.force_groups]]` entry: finite loads on free DOFs.
fn force_group(
    src: TomlSource<'_>,
    g: &Spanned<super::raw::RawForceGroup>,
    model: &Model,
) -> Result<ForceGroup, InputError> {
    let r = g.get_ref();
    let mut loads = Vec::new();
    for l in &r.loads {
        let dof = Dof::new(l.node, l.dof);
        if model.dof_map().index_of(dof).is_none() {
            return Err(src.at(
                g,
                format!(
                    "force group '{}': {dof} is not a free DOF of the model",
                    r.name
                ),
            ));
        }
        if !l.value.is_finite() {
            return Err(src.at(
                g,
                format!("force group '{}': load {} is not finite", r.name, l.value),
            ));
        }
        loads.push((dof, l.value));
    }
    if loads.is_empty() {
        return Err(src.at(g, format!("force group '{}' has no loads", r.name)));
    }
    Ok(ForceGroup {
        name: r.name.clone(),
        loads,
    })
}
