//! What `flexbody info` says about a model beyond its size: its node and
//! element sets, couplings, materials, sections, fixed DOFs, damping and
//! its full mass (the fixed DOFs' share included), so that a user finds the
//! names to give `--interface` without opening the deck.

use crate::fem::{CouplingKind, DofKind, FemError, Model, Rayleigh};
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
            match m.kind {
                // Orthotropic and anisotropic: no single E and nu.
                Some(kind) if kind != "isotropic" => format!(
                    "{} ({kind}, density {})",
                    m.name,
                    value(m.density, " kg/m^3")
                ),
                _ => format!(
                    "{} (E {}, nu {}, density {})",
                    m.name,
                    value(m.youngs_modulus, " Pa"),
                    value(m.poisson, ""),
                    value(m.density, " kg/m^3")
                ),
            }
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
    out.push(format!("damping: {}", damping(model)));
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

/// The parts of D (report eq. 1): "Rayleigh alpha 0.5 1/s, beta 1e-4 s
/// (whole model); material Rayleigh alpha 2 1/s, beta 0 s on 120
/// elements; 3 dashpots (c 1.5e3 to 4e3 N s/m)" or "none (D = 0)".
pub(crate) fn damping(model: &Model) -> String {
    let rayleigh = |r: Rayleigh| format!("alpha {:e} 1/s, beta {:e} s", r.alpha, r.beta);
    let mut parts = Vec::new();
    if let Some(r) = model.rayleigh().filter(|r| r.alpha != 0.0 || r.beta != 0.0) {
        parts.push(format!("Rayleigh {} (whole model)", rayleigh(r)));
    }
    let mut by_material: Vec<(Rayleigh, usize)> = Vec::new();
    let mut dashpots: Vec<f64> = Vec::new();
    for e in model.elements() {
        let b = e.behaviour();
        if let Some(r) = b.material_damping() {
            match by_material.iter_mut().find(|(q, _)| *q == r) {
                Some((_, n)) => *n += 1,
                None => by_material.push((r, 1)),
            }
        }
        match e {
            crate::fem::Element::Dashpot(d) => dashpots.push(d.coefficient),
            crate::fem::Element::AxialDashpot(d) => dashpots.push(d.coefficient),
            _ => {}
        }
    }
    for (r, n) in by_material {
        parts.push(format!("material Rayleigh {} on {n} elements", rayleigh(r)));
    }
    if !dashpots.is_empty() {
        let (lo, hi) = dashpots
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(lo, hi), &c| {
                (lo.min(c), hi.max(c))
            });
        let range = if lo == hi {
            format!("{lo:e}")
        } else {
            format!("{lo:e} to {hi:e}")
        };
        parts.push(format!("{} dashpots (c {range} N s/m)", dashpots.len()));
    }
    if parts.is_empty() {
        "none (D = 0)".to_string()
    } else {
        parts.join("; ")
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
