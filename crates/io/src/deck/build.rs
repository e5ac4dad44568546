//! From the cards read to a checked [`Model`]: sets resolved, properties
//! assigned to elements, fixed DOFs filtered, damping checked (see
//! [`check_damping`]), and every error of
//! building the [`Model`] and of [`Element::validate`] mapped to the deck line of the
//! element, node or boundary condition.

use super::cards::{Files, Loc};
use super::constraints;
use super::elasticity::{self, ElasticKind};
use super::keywords::{property_keyword, Reader};
use super::properties::{discrete_properties, DiscreteProperties, RawSection, SectionData};
use super::transform;
use crate::InputError;
use flexbody_fem::element::{ElementType, SectionKind, SectionValues};
use flexbody_fem::id_hash::{id_map, IdMap, IdSet};
use flexbody_fem::{
    Anisotropy, Dof, DofKind, Element, FemError, Material, Model, NodeId, Orientation,
};
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap, HashSet};

/// The checked model, the element sets and the warnings.
pub(super) struct Built {
    pub model: Model,
    pub element_sets: BTreeMap<String, Vec<usize>>,
    pub warnings: Vec<String>,
}

/// Builds and checks the model.
pub(super) fn build(reader: Reader<'_>) -> Result<Built, InputError> {
    let Reader {
        files,
        nodes,
        elements: raw,
        node_sets,
        node_set_order,
        element_sets,
        element_set_order,
        materials,
        sections,
        orientations,
        initial_temperature,
        fixed,
        mut warnings,
        surfaces,
        couplings,
        equations,
        mpcs,
        rigid_bodies,
        distributing,
        dcoup,
        element_surfaces,
        ties,
        transforms,
        contact,
        modal_rayleigh,
        ..
    } = reader;

    let node_ids: IdSet<NodeId> = nodes.iter().map(|n| n.id).collect();
    let element_index: IdMap<usize, usize> =
        raw.iter().enumerate().map(|(i, e)| (e.id, i)).collect();
    // In order of definition: a set that copies another comes after it, so
    // an undefined id is reported for the set that lists it.
    for set in &node_set_order {
        let entries = node_sets.get(set).map_or(&[][..], Vec::as_slice);
        if let Some((n, loc)) = entries.iter().find(|(n, _)| !node_ids.contains(n)) {
            return Err(files.error(
                *loc,
                format!("node set '{set}' refers to node {n}, which is not defined"),
            ));
        }
    }
    for set in &element_set_order {
        let entries = element_sets.get(set).map_or(&[][..], Vec::as_slice);
        if let Some((e, loc)) = entries
            .iter()
            .find(|(e, _)| !element_index.contains_key(e) && !dcoup.contains_key(e))
        {
            return Err(files.error(
                *loc,
                format!("element set '{set}' refers to element {e}, which is not defined"),
            ));
        }
    }

    // Which property keyword each element takes its properties from.
    let mut section_of: Vec<Option<usize>> = vec![None; raw.len()];
    for (si, s) in sections.iter().enumerate() {
        let entries = element_sets.get(&s.elset).ok_or_else(|| {
            files.error(
                s.loc,
                format!("{}: element set '{}' is not defined", s.keyword, s.elset),
            )
        })?;
        for (id, _) in entries {
            let Some(&ei) = element_index.get(id) else {
                continue; // checked above
            };
            let e = &raw[ei];
            if !s.data.accepts(e.kind) {
                return Err(files.error(
                    s.loc,
                    format!(
                        "{} on element set '{}': element {id} is of type {}, which takes its \
                         properties from {}",
                        s.keyword,
                        s.elset,
                        e.kind.name,
                        property_keyword(e.kind.section)
                    ),
                ));
            }
            match section_of[ei] {
                Some(prev) if prev != si => {
                    return Err(files.error(
                        s.loc,
                        format!(
                            "element {id} gets its properties twice: from {} on {} and from {}",
                            sections[prev].keyword,
                            files.describe(sections[prev].loc),
                            s.keyword
                        ),
                    ))
                }
                _ => section_of[ei] = Some(si),
            }
        }
    }

    let needed = materials.iter().find(|m| {
        m.elastic.as_ref().is_some_and(|e| e.1.is_table())
            || m.density.as_ref().is_some_and(|d| d.0.is_table())
    });
    let node_list: Vec<NodeId> = nodes.iter().map(|n| n.id).collect();
    let temperature = super::temperature::model_temperature(
        files,
        initial_temperature.as_ref(),
        &node_list,
        &node_sets,
        needed.map(|m| m.name.as_str()),
    )?;
    let mut props = Properties {
        files,
        materials: &materials,
        orientations: &orientations,
        temperature,
        built: HashMap::new(),
        discrete: HashMap::new(),
    };
    let mut elements = Vec::with_capacity(raw.len());
    let mut element_loc: IdMap<usize, Loc> = id_map(raw.len());
    for (ei, e) in raw.iter().enumerate() {
        let Some(si) = section_of[ei] else {
            return Err(files.error(
                e.loc,
                format!(
                    "element {} ({}) has no properties: no {} covers it",
                    e.id,
                    e.kind.name,
                    property_keyword(e.kind.section)
                ),
            ));
        };
        let values = props.section_values(si, &sections[si], e.kind)?;
        let element = (e.kind.build)(e.id, &e.nodes, &values)
            .map_err(|err| files.error(e.loc, err.to_string()))?;
        element_loc.insert(e.id, e.loc);
        elements.push(element);
    }

    // A rigid body's rotational node stands for its reference node's
    // rotations (CalculiX): its fixed translations fix those.
    let rotation_nodes: HashMap<NodeId, NodeId> = rigid_bodies
        .iter()
        .filter_map(|r| r.rotation.map(|n| (n, r.reference)))
        .collect();
    let coords: HashMap<NodeId, [f64; 3]> = nodes.iter().map(|n| (n.id, n.coords)).collect();
    let systems = transform::nodal_systems(files, &transforms, &node_sets, &coords)?;
    if let Some((node, (_, loc))) = systems.iter().find(|(n, _)| rotation_nodes.contains_key(n)) {
        return Err(files.error(
            *loc,
            format!(
                "*TRANSFORM: node {node} is the rotational node of a *RIGID BODY; its DOFs stand \
                 for the reference node's rotations and take no local system"
            ),
        ));
    }
    let fixed: Vec<(Dof, Loc)> = fixed
        .into_iter()
        .map(|(d, loc)| match rotation_nodes.get(&d.node) {
            Some(&reference) if d.kind.index() < 3 => {
                (Dof::new(reference, DofKind::ALL[d.kind.index() + 3]), loc)
            }
            _ => (d, loc),
        })
        .collect();
    let mut reference_points: Vec<NodeId> = couplings.iter().map(|c| c.point).collect();
    reference_points.extend(rigid_bodies.iter().map(|r| r.reference));
    reference_points.extend(dcoup.values().map(|(n, _)| *n));

    // Fixed DOFs: only those an element or a coupling's reference node
    // creates (CalculiX also ignores rotations fixed on nodes of solid
    // elements).
    let fixed_nodes: IdSet<NodeId> = fixed.iter().map(|(d, _)| d.node).collect();
    let mut active: IdSet<Dof> = elements
        .iter()
        .filter(|e| {
            !fixed_nodes.is_empty()
                && e.creates_dofs()
                && e.nodes().iter().any(|n| fixed_nodes.contains(n))
        })
        .flat_map(Element::dofs)
        .collect();
    for p in &reference_points {
        if fixed_nodes.contains(p) {
            active.extend(DofKind::ALL.map(|k| Dof::new(*p, k)));
        }
    }
    let mut kept = Vec::with_capacity(fixed.len());
    let mut dropped: Option<(Dof, Loc, usize)> = None;
    for (dof, loc) in &fixed {
        if !node_ids.contains(&dof.node) {
            return Err(files.error(
                *loc,
                format!(
                    "*BOUNDARY refers to node {}, which is not defined",
                    dof.node
                ),
            ));
        }
        let exists = if systems.contains_key(&dof.node) {
            transform::local_dof_exists(*dof, |d| active.contains(d)).ok_or_else(|| {
                files.error(
                    *loc,
                    format!(
                        "*BOUNDARY: node {} has a *TRANSFORM, and its local DOF {} mixes DOFs \
                         the node has with DOFs it has not",
                        dof.node,
                        dof.kind.index() + 1
                    ),
                )
            })?
        } else {
            active.contains(dof)
        };
        if exists {
            kept.push((*dof, *loc));
        } else {
            let d = dropped.get_or_insert((*dof, *loc, 0));
            d.2 += 1;
        }
    }
    if let Some((dof, loc, count)) = dropped {
        warnings.push(format!(
            "*BOUNDARY ({}): {count} fixed DOF(s) ignored because no element gives the node \
             that DOF (first: {dof}; solid elements have no rotations)",
            files.describe(loc)
        ));
    }

    let node_sets: BTreeMap<String, Vec<NodeId>> = node_sets
        .into_iter()
        .map(|(k, v)| (k, unique(v.into_iter().map(|(n, _)| n))))
        .collect();
    let element_sets: BTreeMap<String, Vec<usize>> = element_sets
        .into_iter()
        .map(|(k, v)| (k, unique(v.into_iter().map(|(e, _)| e))))
        .collect();

    // Interface points of *COUPLING cards, given to the model at
    // construction: a point mass may sit on a reference node.
    let mut coupled = Vec::new();
    let mut coupling_loc = HashMap::new();
    for c in couplings {
        let Some(kind) = c.kind else {
            return Err(files.error(c.loc, "*COUPLING without *KINEMATIC or *DISTRIBUTING"));
        };
        let nodes = surfaces.get(&c.surface.to_ascii_uppercase()).cloned().ok_or_else(|| {
            files.error(c.loc, format!("*COUPLING: surface '{}' is not defined as a node surface (*SURFACE, TYPE=NODE)", c.surface))
        })?;
        coupling_loc.insert(c.name.clone(), c.loc);
        coupled.push(flexbody_fem::Coupling {
            name: c.name,
            kind,
            point: c.point,
            nodes,
            weights: None,
        });
    }
    let mut constraint_loc = HashMap::new();
    constraints::rigid_bodies(
        files,
        &rigid_bodies,
        &node_sets,
        &element_sets,
        &elements,
        &mut coupled,
        &mut coupling_loc,
    )?;
    constraints::distributing(
        files,
        &distributing,
        &dcoup,
        &node_sets,
        &element_sets,
        &mut coupled,
        &mut coupling_loc,
    )?;
    let (kept, local_fixed) = transform::global_fixed(kept, &systems, &mut constraint_loc);
    let mut ties = ties;
    ties.extend(super::contact::tied_pairs(files, &contact)?);
    let tied = constraints::ties(
        files,
        &ties,
        constraints::Surfaces {
            nodes: &surfaces,
            elements: &element_surfaces,
        },
        &element_sets,
        &elements,
        &coords,
        &mut constraint_loc,
    )?;
    // ADJUST: slave nodes moved onto the master surface before assembly.
    let mut nodes = nodes;
    if !tied.moved.is_empty() {
        let at: HashMap<NodeId, [f64; 3]> = tied.moved.into_iter().collect();
        for n in &mut nodes {
            if let Some(x) = at.get(&n.id) {
                n.coords = *x;
            }
        }
    }
    let mut equations = constraints::equations(
        files,
        &equations,
        &mpcs,
        &coords,
        &rotation_nodes,
        &systems,
        &mut constraint_loc,
    )?;
    equations.extend(local_fixed);
    equations.extend(tied.equations);
    let used: HashSet<String> = props.built.keys().map(|(name, _)| name.clone()).collect();
    check_damping(files, &materials, &used, modal_rayleigh, &mut warnings)?;
    let mut parts = Model::of(nodes, elements)
        .node_sets(node_sets)
        .fixed(kept)
        .couplings(coupled)
        .equations(equations)
        .local_axes(systems.iter().map(|(n, (r, _))| (*n, *r)).collect());
    if let Some((rayleigh, _)) = modal_rayleigh {
        parts = parts.rayleigh(rayleigh);
    }
    let model = parts.build().map_err(|err| {
        let loc = match &err {
            FemError::UnknownNode { element, .. }
            | FemError::ZeroLength { element }
            | FemError::OrientationParallel { element, .. }
            | FemError::InvalidElement { element, .. } => element_loc.get(element).copied(),
            FemError::MassWithoutDof { node } => raw
                .iter()
                .find(|e| e.kind.section == SectionKind::Mass && e.nodes.first() == Some(node))
                .map(|e| e.loc),
            FemError::InvalidCoupling { name, .. } => coupling_loc.get(name).copied(),
            FemError::InvalidConstraint { name, .. } => constraint_loc
                .get(name)
                .or_else(|| coupling_loc.get(name))
                .copied(),
            _ => None,
        };
        files.error_near(loc, err.to_string())
    })?;
    // Every element's geometry in parallel; the first bad one (in the
    // model's order) is the error.
    let bad = model
        .elements()
        .par_iter()
        .filter_map(|e| e.validate(&model).err().map(|err| (e.id(), err)))
        .find_first(|_| true);
    if let Some((id, err)) = bad {
        return Err(files.error_near(element_loc.get(&id).copied(), err.to_string()));
    }
    check_dashpot_ends(files, &model, &fixed, &element_loc)?;
    Ok(Built {
        model,
        element_sets,
        warnings,
    })
}

/// The ids in first-seen order, each once.
fn unique<T: Copy + Eq + std::hash::Hash>(ids: impl Iterator<Item = T>) -> Vec<T> {
    let mut seen = HashSet::new();
    ids.filter(|id| seen.insert(*id)).collect()
}

/// Material Rayleigh damping (`*DAMPING, ALPHA=, BETA=`) is applied per
/// material, as Abaqus does. Two things are checked against the used
/// materials:
/// - with `*MODAL DAMPING, RAYLEIGH` too, the deck is refused: CalculiX
///   2.20 keeps one global alpha and beta (the card read last wins), and
///   Abaqus applies the two to different procedures; adding them would be
///   neither;
/// - where the used materials' damping differs (one damped, another not, or
///   other values), a warning says so: CalculiX 2.20 applies the `*DAMPING`
///   read last to the whole model.
fn check_damping(
    files: &Files,
    materials: &[super::properties::RawMaterial],
    used: &HashSet<String>,
    modal: Option<(flexbody_fem::Rayleigh, Loc)>,
    warnings: &mut Vec<String>,
) -> Result<(), InputError> {
    let damped: Vec<(&str, flexbody_fem::Rayleigh, Loc)> = materials
        .iter()
        .filter(|m| used.contains(&m.name))
        .filter_map(|m| m.damping.map(|(r, loc)| (m.name.as_str(), r, loc)))
        .collect();
    let Some(&(name, first, loc)) = damped.first() else {
        return Ok(());
    };
    if let Some((_, modal_loc)) = modal {
        return Err(files.error(
            modal_loc,
            format!(
                "*MODAL DAMPING, RAYLEIGH and the material damping of '{name}' (*DAMPING on {}) \
                 are both given: CalculiX keeps only the one read last, Abaqus applies them \
                 to different procedures; give one of them",
                files.describe(loc)
            ),
        ));
    }
    let uniform = damped.len() == used.len() && damped.iter().all(|(_, r, _)| *r == first);
    if !uniform {
        warnings.push(format!(
            "*DAMPING ({}): the materials' Rayleigh damping differs ({} of {} used materials \
             damped); it is applied per material, as in Abaqus (CalculiX 2.20 applies the \
             *DAMPING read last to the whole model)",
            files.describe(loc),
            damped.len(),
            used.len()
        ));
    }
    Ok(())
}

/// A dashpot creates no DOFs: each of its nodes must have some of the DOFs
/// it acts on from other elements or couplings, or be held by a
/// `*BOUNDARY` (a grounded end, whose fixed DOFs were dropped because no
/// element gives them). Else the dashpot's line is the error: the node
/// would be held without the deck saying so.
fn check_dashpot_ends(
    files: &Files,
    model: &Model,
    fixed: &[(Dof, Loc)],
    element_loc: &IdMap<usize, Loc>,
) -> Result<(), InputError> {
    let held: IdSet<NodeId> = fixed.iter().map(|(d, _)| d.node).collect();
    let fixed_in_model: HashSet<Dof> = model.fixed_dofs().copied().collect();
    for e in model.elements().iter().filter(|e| !e.creates_dofs()) {
        if matches!(e, Element::PointMass(_)) {
            continue;
        }
        let dofs = e.dofs();
        for node in e.nodes() {
            let has = dofs
                .iter()
                .filter(|d| d.node == node)
                .any(|d| fixed_in_model.contains(d) || !model.terms(*d).is_empty());
            if !has && !held.contains(&node) {
                return Err(files.error_near(
                    element_loc.get(&e.id()).copied(),
                    format!(
                        "element {}: node {node} has none of the DOFs the dashpot acts on (a \
                         dashpot creates no DOFs: no other element or coupling gives them) and \
                         no *BOUNDARY holds it; connect the node, or fix it to ground the dashpot",
                        e.id()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Materials and spring and dashpot data, checked once per use.
struct Properties<'a> {
    files: &'a Files,
    materials: &'a [super::properties::RawMaterial],
    orientations: &'a [(String, Orientation, Loc)],
    /// The model temperature at which tables are read; `None`: their first
    /// records.
    temperature: Option<f64>,
    /// Built materials by name and orientation.
    built: HashMap<(String, Option<String>), Material>,
    discrete: HashMap<(usize, &'static str), DiscreteProperties>,
}

impl Properties<'_> {
    /// The material a section names: defined, with `*ELASTIC` and
    /// `*DENSITY` read at the model temperature; anisotropic ones turned by
    /// the section's orientation.
    fn material(&mut self, s: &RawSection) -> Result<Material, InputError> {
        let files = self.files;
        let Some(name) = &s.material else {
            return Err(files.error(s.loc, format!("{} needs MATERIAL=...", s.keyword)));
        };
        let key = (name.clone(), s.orientation.clone());
        if let Some(m) = self.built.get(&key) {
            return Ok(m.clone());
        }
        let m = self
            .materials
            .iter()
            .find(|m| &m.name == name)
            .ok_or_else(|| {
                files.error(
                    s.loc,
                    format!("{}: material '{name}' is not defined", s.keyword),
                )
            })?;
        let used = format!("used by {} on {}", s.keyword, files.describe(s.loc));
        let (kind, elastic, _) = m.elastic.as_ref().ok_or_else(|| {
            files.error(m.loc, format!("material '{name}' has no *ELASTIC ({used})"))
        })?;
        let (density, _) = m.density.as_ref().ok_or_else(|| {
            files.error(
                m.loc,
                format!("material '{name}' has no *DENSITY; the mass matrix needs it ({used})"),
            )
        })?;
        let (rho, density_loc) = density.at(self.temperature);
        let rho = rho[0];
        flexbody_fem::require_non_negative("density", rho)
            .map_err(|err| files.error(density_loc, format!("material '{name}': {err}")))?;
        let (constants, elastic_loc) = elastic.at(self.temperature);
        let orientation = match &s.orientation {
            None => None,
            Some(o) => Some(
                self.orientations
                    .iter()
                    .find(|(n, _, _)| n == o)
                    .map(|(_, o, _)| o.clone())
                    .ok_or_else(|| {
                        files.error(
                            s.loc,
                            format!("{}: orientation '{o}' is not defined", s.keyword),
                        )
                    })?,
            ),
        };
        let bad = |err: String| files.error(elastic_loc, format!("material '{name}': {err}"));
        let mut material = match kind {
            ElasticKind::Isotropic => {
                Material::new(constants[0], constants[1], rho).map_err(|e| bad(e.to_string()))?
            }
            _ => {
                let c = elasticity::voigt(*kind, &constants).map_err(bad)?;
                let a = Anisotropy::new(c, orientation).map_err(|e| bad(e.to_string()))?;
                Material::anisotropic(a, rho).map_err(|e| bad(e.to_string()))?
            }
        };
        if let Some((rayleigh, loc)) = m.damping {
            material = material
                .with_damping(rayleigh)
                .map_err(|err| files.error(loc, format!("material '{name}': {err}")))?;
        }
        self.built.insert(key, material.clone());
        Ok(material)
    }

    /// The values section `s` (number `si`) gives an element of type
    /// `kind`, which it accepts.
    fn section_values(
        &mut self,
        si: usize,
        s: &RawSection,
        kind: &'static ElementType,
    ) -> Result<SectionValues, InputError> {
        Ok(match &s.data {
            SectionData::Solid => SectionValues::Solid {
                material: self.material(s)?,
            },
            SectionData::Shell { thickness, offset } => SectionValues::Shell {
                material: self.isotropic_material(s, "shells")?,
                thickness: *thickness,
                offset: *offset,
            },
            SectionData::Beam { constants, n1 } => SectionValues::Beam {
                material: self.beam_material(s)?,
                constants: constants.clone(),
                orientation: *n1,
            },
            SectionData::Mass(mass) => SectionValues::Mass { mass: *mass },
            SectionData::Spring(_) => {
                let p = self.discrete(si, s, kind)?;
                SectionValues::Spring {
                    dofs: [p.first, p.second],
                    stiffness: p.value,
                }
            }
            SectionData::Dashpot(_) => {
                let p = self.discrete(si, s, kind)?;
                SectionValues::Dashpot {
                    dofs: [p.first, p.second],
                    coefficient: p.value,
                }
            }
        })
    }

    /// The material of a beam section: isotropic only.
    fn beam_material(&mut self, s: &RawSection) -> Result<Material, InputError> {
        self.isotropic_material(s, "beams")
    }

    /// The material of section `s`, which must be isotropic for `what`
    /// (beams: their section constants need one E and G; shells: their
    /// plane-stress law).
    fn isotropic_material(&mut self, s: &RawSection, what: &str) -> Result<Material, InputError> {
        let material = self.material(s)?;
        if material.anisotropy.is_some() {
            let name = s.material.as_deref().unwrap_or_default();
            return Err(self.files.error(
                s.loc,
                format!(
                    "{}: material '{name}' is anisotropic; {what} take isotropic materials \
                     only (one E and nu)",
                    s.keyword
                ),
            ));
        }
        Ok(material)
    }

    /// The DOFs and stiffness or coefficient of springs or dashpots of type
    /// `kind` under section `si`.
    fn discrete(
        &mut self,
        si: usize,
        s: &RawSection,
        kind: &'static ElementType,
    ) -> Result<DiscreteProperties, InputError> {
        if let Some(p) = self.discrete.get(&(si, kind.name)) {
            return Ok(*p);
        }
        let (SectionData::Spring(lines) | SectionData::Dashpot(lines)) = &s.data else {
            return Err(self
                .files
                .error(s.loc, format!("{} data expected", s.keyword)));
        };
        let p = discrete_properties(self.files, s.loc, lines, kind)?;
        self.discrete.insert((si, kind.name), p);
        Ok(p)
    }
}
