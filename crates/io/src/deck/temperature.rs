//! The model temperature at which temperature tables of `*ELASTIC` and
//! `*DENSITY` are read, as CalculiX 2.20 uses it in a frequency step (each
//! checked with ccx): the initial temperature of `*INITIAL CONDITIONS,
//! TYPE=TEMPERATURE`; a `*TEMPERATURE` in a step does not change the
//! matrices of a frequency step (and ccx refuses it without initial
//! temperatures); with no initial temperature ccx reads the first record of
//! each table. Only a uniform field is accepted: one value on every node of
//! the model; anything else is refused at the line that breaks it.

use super::cards::{Card, Files};
use crate::InputError;
use flexbody_fem::NodeId;
use std::collections::{BTreeMap, HashSet};

/// The uniform model temperature; `needed` names the material with a
/// table (a field is only checked when some table needs it).
pub(super) fn model_temperature(
    files: &Files,
    initial: Option<&Card>,
    nodes: &[NodeId],
    node_sets: &BTreeMap<String, Vec<(NodeId, super::cards::Loc)>>,
    needed: Option<&str>,
) -> Result<Option<f64>, InputError> {
    let (Some(needed), Some(card)) = (needed, initial) else {
        return Ok(None);
    };
    let mut value: Option<f64> = None;
    let mut covered: HashSet<NodeId> = HashSet::new();
    for line in &card.data {
        let t = line.float(files, 1, &format!("{}: temperature", card.display))?;
        if let Some(v) = value {
            if v != t {
                return Err(files.error(
                    line.loc,
                    format!(
                        "{}: temperature {t} differs from {v} of an earlier line; material \
                         '{needed}' has a temperature table and only a uniform temperature \
                         field is supported",
                        card.display
                    ),
                ));
            }
        }
        value = Some(t);
        let target = line.get(0).ok_or_else(|| {
            files.error(
                line.loc,
                format!("{}: node or node set missing", card.display),
            )
        })?;
        match super::cards::parse_id(target) {
            Some(id) => {
                covered.insert(id);
            }
            None => {
                let set = node_sets.get(&super::cards::name(target)).ok_or_else(|| {
                    files.error(
                        line.loc,
                        format!(
                            "{}: node set '{target}' is not defined",
                            card.display,
                            target = crate::text::excerpt(target)
                        ),
                    )
                })?;
                covered.extend(set.iter().map(|(n, _)| *n));
            }
        }
    }
    let Some(t) = value else {
        return Ok(None);
    };
    {
        if let Some(n) = nodes.iter().find(|n| !covered.contains(n)) {
            return Err(files.error(
                card.loc,
                format!(
                    "{}: node {n} gets no temperature (others are at {t}); \
                     material '{needed}' has a temperature table and only a uniform \
                     temperature field is supported",
                    card.display
                ),
            ));
        }
    }
    Ok(Some(t))
}
