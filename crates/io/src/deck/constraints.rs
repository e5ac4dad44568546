//! The constraint keywords as read: `*EQUATION`, `*MPC`, `*RIGID BODY` and
//! `*DISTRIBUTING COUPLING` (with its DCOUP3D element). They become
//! [`flexbody_fem::Equation`]s and [`flexbody_fem::Coupling`]s in
//! `build.rs` by the functions at the end of this file, where the sets
//! and nodes they name are resolved.

use super::cards::{is_numeric, name, Card, Files, Loc};
use super::keywords::Reader;
use crate::InputError;
use flexbody_fem::tie::TieEquations;
use flexbody_fem::{
    Coupling, CouplingKind, Dof, DofKind, Element, Equation, Face, MpcKind, NodeId,
};
use std::collections::{BTreeMap, HashMap, HashSet};

/// One equation of an `*EQUATION` card: `(node, DOF, coefficient)` terms.
pub(super) struct RawEquation {
    pub terms: Vec<(NodeId, DofKind, f64)>,
    pub loc: Loc,
}

/// One `*MPC` card: its type and nodes.
pub(super) struct RawMpc {
    pub kind: MpcKind,
    pub nodes: Vec<NodeId>,
    pub loc: Loc,
}

/// A `*TIE`: slave and master surface names.
pub(super) struct RawTie {
    pub name: String,
    /// The card in messages: `*TIE T1`, `*CONTACT PAIR 2 (tied)`.
    pub label: String,
    pub slave: String,
    pub master: String,
    pub tolerance: Option<f64>,
    pub adjust: bool,
    pub loc: Loc,
}

/// Whose nodes a rigid body or distributing coupling holds.
pub(super) enum Members {
    NodeSet(String),
    ElementSet(String),
}

/// A `*RIGID BODY`: the reference node and its members move rigidly.
pub(super) struct RawRigidBody {
    pub reference: NodeId,
    /// CalculiX's rotational node: its translations are the reference
    /// node's rotations.
    pub rotation: Option<NodeId>,
    pub members: Members,
    pub loc: Loc,
}

/// A `*DISTRIBUTING COUPLING`: the DCOUP3D element set whose node is the
/// reference node, and the coupled nodes (numbers or node sets) with their
/// weights.
pub(super) struct RawDistributing {
    pub elset: String,
    pub entries: Vec<(String, f64, Loc)>,
    pub loc: Loc,
}

impl Reader<'_> {
    /// `*EQUATION`: a line with the number of terms, then `node, DOF,
    /// coefficient` triples, up to four a line, for each equation.
    pub(super) fn equation(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &[]);
        let mut lines = card.data.iter().peekable();
        while let Some(head) = lines.next() {
            let count = head.id(self.files, 0, "*EQUATION: number of terms")? as usize;
            if count == 0 || count > 10_000 {
                return Err(self.files.error(
                    head.loc,
                    format!("*EQUATION: {count} terms (1 to 10000 accepted)"),
                ));
            }
            let mut terms = Vec::with_capacity(count);
            while terms.len() < count {
                let Some(line) = lines.next() else {
                    return Err(self.files.error(
                        head.loc,
                        format!("*EQUATION: {count} terms announced, {} given", terms.len()),
                    ));
                };
                let fields: Vec<&str> = line
                    .fields
                    .iter()
                    .map(String::as_str)
                    .filter(|f| !f.is_empty())
                    .collect();
                if !fields.len().is_multiple_of(3) {
                    return Err(self.files.error(
                        line.loc,
                        "*EQUATION: each term is three fields: node, DOF, coefficient",
                    ));
                }
                for (k, t) in fields.chunks(3).enumerate() {
                    let node = self.equation_node(t[0], line.loc)?;
                    let dof = line.id(self.files, 3 * k + 1, "*EQUATION: DOF")?;
                    if !(1..=6).contains(&dof) {
                        return Err(self.files.error(
                            line.loc,
                            format!(
                                "*EQUATION: DOF {dof} of node {node}: only DOFs 1 to 6 (ux uy uz rx ry rz)"
                            ),
                        ));
                    }
                    let c = line.float(self.files, 3 * k + 2, "*EQUATION: coefficient")?;
                    terms.push((node, DofKind::ALL[dof as usize - 1], c));
                }
                if terms.len() > count {
                    return Err(self.files.error(
                        line.loc,
                        format!("*EQUATION: {count} terms announced, more given"),
                    ));
                }
            }
            self.equations.push(RawEquation {
                terms,
                loc: head.loc,
            });
        }
        Ok(())
    }

    /// A node of an equation term: a number, or a node set of one node.
    fn equation_node(&self, field: &str, loc: Loc) -> Result<NodeId, InputError> {
        if is_numeric(field) {
            return super::cards::parse_id(field).ok_or_else(|| {
                self.files.error(
                    loc,
                    format!(
                        "*EQUATION: node should be a positive number, got '{field}'",
                        field = crate::text::excerpt(field)
                    ),
                )
            });
        }
        match self.node_sets.get(&name(field)).map(Vec::as_slice) {
            Some([(node, _)]) => Ok(*node),
            Some(set) => Err(self.files.error(
                loc,
                format!(
                    "*EQUATION: node set '{}' has {} nodes; only node numbers or sets of one node are supported",
                    name(field),
                    set.len()
                ),
            )),
            None => Err(self.files.error(
                loc,
                format!("*EQUATION: node set '{}' is not defined", name(field)),
            )),
        }
    }

    /// `*MPC`: one MPC a card, `TYPE, node, node, ...` continued on the
    /// following lines; node sets stand for their nodes (CalculiX).
    pub(super) fn mpc(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &[]);
        let Some(first) = card.data.first() else {
            return Err(self.files.error(card.loc, "*MPC has no data line"));
        };
        let kind_name = name(first.get(0).unwrap_or(""));
        let kind = MpcKind::parse(&kind_name).ok_or_else(|| {
            self.files.error(
                first.loc,
                format!(
                    "*MPC type '{kind_name}' is not supported (supported: BEAM, PLANE, STRAIGHT)",
                    kind_name = crate::text::excerpt(&kind_name)
                ),
            )
        })?;
        let mut nodes = Vec::new();
        for (l, line) in card.data.iter().enumerate() {
            for (i, f) in line.fields.iter().enumerate().skip(usize::from(l == 0)) {
                if f.is_empty() {
                    continue;
                }
                if is_numeric(f) {
                    nodes.push(line.id(self.files, i, &format!("*MPC {kind_name}: node"))?);
                } else {
                    let set = self.node_sets.get(&name(f)).ok_or_else(|| {
                        self.files.error(
                            line.loc,
                            format!("*MPC {kind_name}: node set '{}' is not defined", name(f)),
                        )
                    })?;
                    nodes.extend(set.iter().map(|(n, _)| *n));
                }
            }
        }
        self.mpcs.push(RawMpc {
            kind,
            nodes,
            loc: card.loc,
        });
        Ok(())
    }

    /// `*RIGID BODY, REF NODE=, (NSET= | ELSET=)[, ROT NODE=]`.
    pub(super) fn rigid_body(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["NSET", "ELSET", "REFNODE", "ROTNODE"]);
        let node = |key: &str| -> Result<Option<NodeId>, InputError> {
            card.value(key)
                .map(|v| {
                    super::cards::parse_id(v).ok_or_else(|| {
                        self.files.error(
                            card.loc,
                            format!(
                                "*RIGID BODY: {key} should be a node number, got '{v}'",
                                v = crate::text::excerpt(v)
                            ),
                        )
                    })
                })
                .transpose()
        };
        let reference = node("REFNODE")?.ok_or_else(|| {
            self.files.error(
                card.loc,
                "*RIGID BODY needs REF NODE= (flexbody does not create a reference node)",
            )
        })?;
        let rotation = node("ROTNODE")?;
        let members = match (card.value("NSET"), card.value("ELSET")) {
            (Some(n), None) => Members::NodeSet(name(n)),
            (None, Some(e)) => Members::ElementSet(name(e)),
            _ => {
                return Err(self
                    .files
                    .error(card.loc, "*RIGID BODY needs one of NSET= or ELSET="))
            }
        };
        self.rigid_bodies.push(RawRigidBody {
            reference,
            rotation,
            members,
            loc: card.loc,
        });
        Ok(())
    }

    /// `*TIE, NAME=[, POSITION TOLERANCE=][, ADJUST=YES|NO]`: one line
    /// `slave surface, master surface`.
    pub(super) fn tie(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["NAME", "POSITIONTOLERANCE", "ADJUST"]);
        for p in [
            "CYCLICSYMMETRY",
            "MULTISTAGE",
            "FLUIDPRESSURE",
            "FLUIDCOUPLING",
        ] {
            if card.has(p) {
                return Err(self
                    .files
                    .error(card.loc, format!("*TIE, {p}: only mesh tying is supported")));
            }
        }
        let tie_name = card.require_name(self.files, "NAME")?;
        let tolerance = match card.value("POSITIONTOLERANCE") {
            None => None,
            Some(v) => Some(
                super::cards::parse_float(v)
                    .filter(|t| t.is_finite() && *t >= 0.0)
                    .ok_or_else(|| {
                        self.files.error(
                            card.loc,
                            format!(
                                "*TIE: POSITION TOLERANCE should be a length >= 0, got '{v}'",
                                v = crate::text::excerpt(v)
                            ),
                        )
                    })?,
            ),
        };
        let adjust = match card.value("ADJUST").map(name).as_deref() {
            None | Some("YES") => true,
            Some("NO") => false,
            Some(other) => {
                return Err(self.files.error(
                    card.loc,
                    format!("*TIE: ADJUST={other}: YES or NO (a node set is not supported)"),
                ))
            }
        };
        let [line] = card.data.as_slice() else {
            return Err(self.files.error(
                card.loc,
                "*TIE takes one data line: slave surface, master surface",
            ));
        };
        let (Some(slave), Some(master)) = (line.get(0), line.get(1)) else {
            return Err(self.files.error(
                line.loc,
                "*TIE: give the slave surface and the master surface",
            ));
        };
        self.ties.push(RawTie {
            label: format!("*TIE {tie_name}"),
            name: tie_name,
            slave: name(slave),
            master: name(master),
            tolerance,
            adjust,
            loc: line.loc,
        });
        Ok(())
    }

    /// `*DISTRIBUTING COUPLING, ELSET=`: `node or node set, weight` lines.
    pub(super) fn distributing_coupling(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["ELSET"]);
        let elset = card.require_name(self.files, "ELSET")?;
        let mut entries = Vec::new();
        for line in &card.data {
            let target = line.get(0).filter(|t| !t.is_empty()).ok_or_else(|| {
                self.files.error(
                    line.loc,
                    "*DISTRIBUTING COUPLING: node or node set is missing",
                )
            })?;
            let weight = line.float(self.files, 1, "*DISTRIBUTING COUPLING: weight")?;
            if !(weight.is_finite() && weight > 0.0) {
                return Err(self.files.error(
                    line.loc,
                    format!("*DISTRIBUTING COUPLING: weight {weight} must be positive"),
                ));
            }
            entries.push((target.to_string(), weight, line.loc));
        }
        if entries.is_empty() {
            return Err(self
                .files
                .error(card.loc, "*DISTRIBUTING COUPLING lists no nodes"));
        }
        self.distributing.push(RawDistributing {
            elset,
            entries,
            loc: card.loc,
        });
        Ok(())
    }
}

/// The nodes of `members`: a node set's, or those of an element set's
/// elements (each once, in order).
fn member_nodes(
    files: &Files,
    what: &str,
    members: &Members,
    loc: Loc,
    node_sets: &BTreeMap<String, Vec<NodeId>>,
    element_sets: &BTreeMap<String, Vec<usize>>,
    elements: &[Element],
) -> Result<Vec<NodeId>, InputError> {
    match members {
        Members::NodeSet(set) => node_sets
            .get(set)
            .cloned()
            .ok_or_else(|| files.error(loc, format!("{what}: node set '{set}' is not defined"))),
        Members::ElementSet(set) => {
            let ids = element_sets.get(set).ok_or_else(|| {
                files.error(loc, format!("{what}: element set '{set}' is not defined"))
            })?;
            let wanted: HashSet<usize> = ids.iter().copied().collect();
            let mut seen = HashSet::new();
            Ok(elements
                .iter()
                .filter(|e| wanted.contains(&e.id()))
                .flat_map(Element::nodes)
                .filter(|n| seen.insert(*n))
                .collect())
        }
    }
}

/// `*RIGID BODY`s as rigid couplings of their reference node, named
/// `RIGID BODY-k` (their line in `locs`).
pub(super) fn rigid_bodies(
    files: &Files,
    bodies: &[RawRigidBody],
    node_sets: &BTreeMap<String, Vec<NodeId>>,
    element_sets: &BTreeMap<String, Vec<usize>>,
    elements: &[Element],
    couplings: &mut Vec<Coupling>,
    locs: &mut HashMap<String, Loc>,
) -> Result<(), InputError> {
    for (k, body) in bodies.iter().enumerate() {
        let name = format!("RIGID BODY-{}", k + 1);
        let mut nodes = member_nodes(
            files,
            "*RIGID BODY",
            &body.members,
            body.loc,
            node_sets,
            element_sets,
            elements,
        )?;
        // The reference node may be listed among the members (CalculiX
        // allows it); it is the point, not a member.
        nodes.retain(|n| *n != body.reference && Some(*n) != body.rotation);
        if let Some(rot) = body.rotation {
            if let Some(e) = elements.iter().find(|e| e.nodes().contains(&rot)) {
                return Err(files.error(
                    body.loc,
                    format!(
                        "*RIGID BODY: ROT NODE {rot} belongs to element {}; the rotational node \
                         stands for the reference node's rotations and must be a free node",
                        e.id()
                    ),
                ));
            }
        }
        locs.insert(name.clone(), body.loc);
        couplings.push(Coupling {
            name,
            kind: CouplingKind::Rigid,
            point: body.reference,
            nodes,
            weights: None,
        });
    }
    Ok(())
}

/// `*DISTRIBUTING COUPLING`s as distributing couplings of their DCOUP3D
/// element's node, named `DISTRIBUTING COUPLING-k`.
pub(super) fn distributing(
    files: &Files,
    cards: &[RawDistributing],
    dcoup: &BTreeMap<usize, (NodeId, Loc)>,
    node_sets: &BTreeMap<String, Vec<NodeId>>,
    element_sets: &BTreeMap<String, Vec<usize>>,
    couplings: &mut Vec<Coupling>,
    locs: &mut HashMap<String, Loc>,
) -> Result<(), InputError> {
    for (k, card) in cards.iter().enumerate() {
        let ids = element_sets.get(&card.elset).ok_or_else(|| {
            files.error(
                card.loc,
                format!(
                    "*DISTRIBUTING COUPLING: element set '{}' is not defined",
                    card.elset
                ),
            )
        })?;
        let point = match ids.as_slice() {
            [id] => dcoup.get(id).map(|(n, _)| *n).ok_or_else(|| {
                files.error(
                    card.loc,
                    format!(
                        "*DISTRIBUTING COUPLING: element {id} of set '{}' is not a DCOUP3D element",
                        card.elset
                    ),
                )
            })?,
            _ => {
                return Err(files.error(
                    card.loc,
                    format!(
                        "*DISTRIBUTING COUPLING: element set '{}' must hold one DCOUP3D element, it holds {}",
                        card.elset,
                        ids.len()
                    ),
                ))
            }
        };
        let mut nodes = Vec::new();
        let mut weights = Vec::new();
        for (target, weight, loc) in &card.entries {
            let members: Vec<NodeId> = if is_numeric(target) {
                vec![super::cards::parse_id(target).ok_or_else(|| {
                    files.error(
                        *loc,
                        format!("*DISTRIBUTING COUPLING: node should be a positive number, got '{target}'", target = crate::text::excerpt(target)),
                    )
                })?]
            } else {
                node_sets.get(&name(target)).cloned().ok_or_else(|| {
                    files.error(
                        *loc,
                        format!(
                            "*DISTRIBUTING COUPLING: node set '{}' is not defined",
                            name(target)
                        ),
                    )
                })?
            };
            for n in members {
                nodes.push(n);
                weights.push(*weight);
            }
        }
        let name = format!("DISTRIBUTING COUPLING-{}", k + 1);
        locs.insert(name.clone(), card.loc);
        couplings.push(Coupling {
            name,
            kind: CouplingKind::Distributing,
            point,
            nodes,
            weights: Some(weights),
        });
    }
    Ok(())
}

/// The `*EQUATION`s and `*MPC`s as equations, named `*EQUATION k` and
/// `*MPC k (TYPE)` (their line in `locs`). A term on a rigid body's
/// rotational node is the reference node's rotation; a term on a
/// transformed node is along its local axis.
pub(super) fn equations(
    files: &Files,
    equations: &[RawEquation],
    mpcs: &[RawMpc],
    coords: &HashMap<NodeId, [f64; 3]>,
    rotation_nodes: &HashMap<NodeId, NodeId>,
    systems: &super::transform::NodalSystems,
    locs: &mut HashMap<String, Loc>,
) -> Result<Vec<Equation>, InputError> {
    let mut out = Vec::with_capacity(equations.len() + mpcs.len());
    for (k, e) in equations.iter().enumerate() {
        let name = format!("*EQUATION {}", k + 1);
        let terms = e
            .terms
            .iter()
            .flat_map(|&(node, kind, c)| match rotation_nodes.get(&node) {
                Some(&reference) if kind.index() < 3 => {
                    vec![(Dof::new(reference, DofKind::ALL[kind.index() + 3]), c)]
                }
                _ => match systems.get(&node) {
                    Some((r, _)) => flexbody_fem::transform::local_term(node, r, kind, c),
                    None => vec![(Dof::new(node, kind), c)],
                },
            })
            .collect();
        locs.insert(name.clone(), e.loc);
        out.push(Equation { name, terms });
    }
    for (k, m) in mpcs.iter().enumerate() {
        let name = format!("*MPC {} ({:?})", k + 1, m.kind).to_uppercase();
        let mut x = Vec::with_capacity(m.nodes.len());
        for n in &m.nodes {
            x.push(
                *coords
                    .get(n)
                    .ok_or_else(|| files.error(m.loc, format!("*MPC: node {n} is not defined")))?,
            );
        }
        let eqs = m
            .kind
            .equations(&name, &m.nodes, &x)
            .map_err(|err| files.error(m.loc, err.to_string()))?;
        locs.insert(name, m.loc);
        out.extend(eqs);
    }
    Ok(out)
}

/// The faces of an element surface: their nodes in [`flexbody_fem::tie::solid_face`]
/// order. Only solid elements have faces here.
fn surface_faces(
    files: &Files,
    surface: &str,
    entries: &[(String, usize, Loc)],
    element_sets: &BTreeMap<String, Vec<usize>>,
    elements: &HashMap<usize, &Element>,
) -> Result<Vec<Face>, InputError> {
    let mut faces = Vec::new();
    for (target, face, loc) in entries {
        let ids: Vec<usize> = if is_numeric(target) {
            vec![super::cards::parse_id(target).ok_or_else(|| {
                files.error(
                    *loc,
                    format!(
                        "*SURFACE {surface}: bad element number '{target}'",
                        target = crate::text::excerpt(target)
                    ),
                )
            })? as usize]
        } else {
            element_sets.get(&name(target)).cloned().ok_or_else(|| {
                files.error(
                    *loc,
                    format!(
                        "*SURFACE {surface}: element set '{}' is not defined",
                        name(target)
                    ),
                )
            })?
        };
        for id in ids {
            let Some(Element::Solid(solid)) = elements.get(&id).copied() else {
                return Err(files.error(
                    *loc,
                    format!("*SURFACE {surface}: element {id} is not a solid element (ties join solid faces)"),
                ));
            };
            let local = flexbody_fem::tie::solid_face(solid.kind, *face).ok_or_else(|| {
                files.error(
                    *loc,
                    format!(
                        "*SURFACE {surface}: a {} element has no face S{face}",
                        solid.kind.name()
                    ),
                )
            })?;
            faces.push(Face {
                nodes: local.iter().map(|&i| solid.nodes[i]).collect(),
            });
        }
    }
    Ok(faces)
}

/// The surfaces of a deck: node surfaces (name -> nodes) and element
/// surfaces (name -> element or element set, face, line).
pub(super) struct Surfaces<'a> {
    pub nodes: &'a BTreeMap<String, Vec<NodeId>>,
    pub elements: &'a BTreeMap<String, Vec<(String, usize, Loc)>>,
}

/// The `*TIE`s as equations (named `tie 'NAME'`, their line in `locs`),
/// with the positions of the slave nodes they move (ADJUST).
pub(super) fn ties(
    files: &Files,
    ties: &[RawTie],
    surfaces: Surfaces<'_>,
    element_sets: &BTreeMap<String, Vec<usize>>,
    elements: &[Element],
    coords: &HashMap<NodeId, [f64; 3]>,
    locs: &mut HashMap<String, Loc>,
) -> Result<TieEquations, InputError> {
    let (node_surfaces, element_surfaces) = (surfaces.nodes, surfaces.elements);
    let by_id: HashMap<usize, &Element> = elements.iter().map(|e| (e.id(), e)).collect();
    let mut out = TieEquations::default();
    for t in ties {
        let slaves: Vec<NodeId> =
            match (node_surfaces.get(&t.slave), element_surfaces.get(&t.slave)) {
                (Some(nodes), _) => nodes.clone(),
                (None, Some(entries)) => {
                    let mut seen = HashSet::new();
                    surface_faces(files, &t.slave, entries, element_sets, &by_id)?
                        .into_iter()
                        .flat_map(|f| f.nodes)
                        .filter(|n| seen.insert(*n))
                        .collect()
                }
                (None, None) => {
                    return Err(files.error(
                        t.loc,
                        format!("{}: slave surface '{}' is not defined", t.label, t.slave),
                    ))
                }
            };
        let entries = element_surfaces.get(&t.master).ok_or_else(|| {
            files.error(
                t.loc,
                format!(
                    "{}: master surface '{}' is not defined as an element surface (*SURFACE, TYPE=ELEMENT)",
                    t.label, t.master
                ),
            )
        })?;
        let master = surface_faces(files, &t.master, entries, element_sets, &by_id)?;
        let tie = flexbody_fem::Tie {
            name: t.name.clone(),
            slaves,
            master,
            tolerance: t.tolerance,
            adjust: t.adjust,
        };
        let made = tie
            .equations(&|n| coords.get(&n).copied())
            .map_err(|e| files.error(t.loc, e.to_string()))?;
        locs.insert(format!("tie '{}'", t.name), t.loc);
        out.equations.extend(made.equations);
        out.moved.extend(made.moved);
    }
    Ok(out)
}
