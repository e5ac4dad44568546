//! What `flexbody info` says about a model beyond its size: its node and
//! element sets, couplings, materials, sections, fixed DOFs and its full
//! mass (the fixed DOFs' share included), so that a user finds the names
//! to give `--interface` without opening the deck.

use crate::fem::{CouplingKind, DofKind, FemError, Model};
use crate::input::Component;
use std::collections::BTreeMap;

/// At most this many names per list; the rest are counted.
const SHOWN: usize = 12;

/// The lines of the listing, one per kind of definition; none for matrix
/// input (no mesh).
pub fn lines(c: &Component) -> Result<Vec<String>, FemError> {
    let Some(model) = &c.model else {
        return Ok(vec![]);
    };
    let mut out = vec![
        format!("node sets: {}", sized(model.node_sets(), "node")),
        format!("element sets: {}", sized(&c.element_sets, "element")),
    ];
    out.push(format!("couplings: {}", couplings(model)));
    let materials: Vec<String> = c
        .catalogue
        .materials
        .iter()
        .map(|m| {
            let value =
                |v: Option<f64>, unit: &str| v.map_or("-".into(), |v| format!("{v:e}{unit}"));
            format!(
                "{} (E {}, nu {}, density {})",
                m.name,
                value(m.youngs_modulus, " Pa"),
                value(m.poisson, ""),
                value(m.density, " kg/m^3")
            )
        })
        .collect();
    out.push(format!("materials: {}", listed(materials)));
    let sections: Vec<String> = c
        .catalogue
        .sections
        .iter()
        .map(|s| {
            // A model file's section is named; a deck's applies to a set.
            let mut t = if s.keyword.starts_with("[[") {
                format!("{} ({} elements)", s.elset, s.elements)
            } else {
                format!("{} on {} ({} elements)", s.keyword, s.elset, s.elements)
            };
            if let Some(m) = &s.material {
                t += &format!(", material {m}");
            }
            if let Some(m) = s.mass {
                t += &format!(", {m:e} kg each");
            }
            t
        })
        .collect();
    out.push(format!("sections: {}", listed(sections)));
    out.push(format!("fixed DOFs: {}", fixed(model)));
    let full = full_mass_along_axes(model)?.map(|m| format!("{m:.6e}"));
    out.push(format!(
        "full mass along x, y, z (kg), fixed DOFs included: {}",
        full.join(", ")
    ));
    Ok(out)
}

/// "A (4 nodes), B (2 nodes)" or "none".
fn sized<T>(sets: &BTreeMap<String, Vec<T>>, what: &str) -> String {
    listed(
        sets.iter()
            .map(|(name, members)| format!("{name} ({} {what}s)", members.len()))
            .collect(),
    )
}

/// The first [`SHOWN`] items, then how many more; "none" for none.
fn listed(items: Vec<String>) -> String {
    match items.len() {
        0 => "none".to_string(),
        n if n > SHOWN => format!("{} and {} more", items[..SHOWN].join(", "), n - SHOWN),
        _ => items.join(", "),
    }
}

fn couplings(model: &Model) -> String {
    listed(
        model
            .couplings()
            .iter()
            .map(|c| {
                let kind = match c.kind {
                    CouplingKind::Rigid => "kinematic",
                    CouplingKind::Distributing => "distributing",
                };
                format!(
                    "{} ({kind}, reference node {}, {} nodes)",
                    c.name,
                    c.point,
                    c.nodes.len()
                )
            })
            .collect(),
    )
}

/// "12 at 4 nodes: 1 (ux uy uz), ..." or "none".
fn fixed(model: &Model) -> String {
    let mut by_node: BTreeMap<u64, Vec<String>> = BTreeMap::new();
    let mut count = 0;
    for d in model.fixed_dofs() {
        by_node.entry(d.node).or_default().push(d.kind.to_string());
        count += 1;
    }
    if count == 0 {
        return "none (a free body)".to_string();
    }
    let nodes: Vec<String> = by_node
        .iter()
        .map(|(n, kinds)| format!("{n} ({})", kinds.join(" ")))
        .collect();
    format!("{count} at {} nodes: {}", by_node.len(), listed(nodes))
}

/// `t^T M t` for the unit translation `t` along x, y and z, summed over the
/// elements' own mass matrices: the whole body's mass, also where `M` of
/// the free DOFs lost the share of fixed ones.
pub fn full_mass_along_axes(model: &Model) -> Result<[f64; 3], FemError> {
    let mut mass = [0.0; 3];
    for e in model.elements() {
        let m = e.matrices(model)?;
        for (a, kind) in [DofKind::Ux, DofKind::Uy, DofKind::Uz]
            .into_iter()
            .enumerate()
        {
            let t: Vec<f64> = m
                .dofs
                .iter()
                .map(|d| f64::from(u8::from(d.kind == kind)))
                .collect();
            for (i, ti) in t.iter().enumerate().filter(|(_, t)| **t != 0.0) {
                for (j, tj) in t.iter().enumerate() {
                    mass[a] += ti * m.mass[(i, j)] * tj;
                }
            }
        }
    }
    Ok(mass)
}
