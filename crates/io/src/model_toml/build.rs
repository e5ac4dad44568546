//! From the raw model sections to a checked [`Model`], one section at a
//! time, in the order the sections depend on each other: materials and
//! sections, nodes, beam lines, the deck's model, elements, node sets,
//! boundary conditions, couplings, constraints (equations, MPCs, ties).
//! Every error names the line.
//!
//! A `mesh` deck contributes its whole model: nodes, elements, node sets,
//! fixed DOFs, couplings, equations and damping, and its warnings. The file's own
//! sections add to it; its `[damping]` replaces the deck's, nothing else
//! is replaced or dropped.

mod beam_lines;
mod constraints;

use super::raw::{RawElement, RawModel};
use crate::deck::{
    Catalogue, DeckOptions, MaterialEntry, SectionEntry, SurfaceFaces, UnknownKeywords,
};
use crate::{InputError, TomlSource};
use flexbody_fem::element::{Beam, PlanarBeam, PointMass, Shell, ShellKind, Spring};
use flexbody_fem::section::SectionConstants;
use flexbody_fem::{
    BeamProperties, BeamTheory, Coupling, Dof, Element, Equation, FemError, Material, Model, Node,
    Rayleigh,
};
use std::collections::{BTreeMap, HashMap, HashSet};
use toml::Spanned;

/// The checked model and what its deck left to tell the user.
pub(crate) struct Built {
    pub model: Model,
    /// Unknown keywords the deck skipped (`options.allow_unknown`).
    pub unknown: UnknownKeywords,
    /// The deck's warnings, each naming the deck:
    /// `part.inp: *BOUNDARY (line 36): ...`.
    pub warnings: Vec<String>,
    /// The deck's note on the routine keywords it skipped.
    pub notes: Vec<String>,
    /// The deck's element sets (upper-case names).
    pub element_sets: BTreeMap<String, Vec<usize>>,
    /// The file's and the deck's materials and sections.
    pub catalogue: Catalogue,
}

/// Checks the raw sections and assembles the model they describe.
pub(crate) fn build(
    src: TomlSource<'_>,
    raw: &RawModel,
    options: &DeckOptions,
) -> Result<Built, InputError> {
    let mut b = Builder::new(src, raw)?;
    for n in &raw.nodes {
        let (id, x, y, z) = *n.get_ref();
        b.add_node(id, [x, y, z], n.span().start)?;
    }
    b.beam_lines(raw, &options.memory)?;
    let (unknown, mut warnings, notes) = match &raw.mesh {
        Some(mesh) => b.deck_mesh(mesh, options)?,
        None => (UnknownKeywords::default(), Vec::new(), Vec::new()),
    };
    // `[damping]` replaces the deck's model-wide Rayleigh damping only; the
    // damping of the deck's elements stays, and the user is told.
    if raw.damping.is_some() && b.elements.iter().any(Element::has_damping) {
        warnings.push(format!(
            "{}: [damping] replaces the deck's *MODAL DAMPING only; the deck's dashpots and \
             material *DAMPING stay in D, added to it",
            b.src.path.display()
        ));
    }
    // The file's coupling points are nodes from the start: elements (a
    // point mass, a spring) may sit on them.
    let known: HashSet<u64> = b
        .nodes
        .iter()
        .map(|n| n.id)
        .chain(raw.coupling.iter().map(|c| c.get_ref().point))
        .collect();
    b.elements(raw, &known)?;
    b.node_sets(raw, &known)?;
    b.boundaries(raw, &known)?;
    let couplings = b.couplings(raw, &known)?;
    let constraints = b.constraints(raw, &known)?;
    let element_sets = std::mem::take(&mut b.deck_element_sets);
    let mut catalogue = file_catalogue(raw);
    let deck = std::mem::take(&mut b.deck_catalogue);
    catalogue.materials.extend(deck.materials);
    catalogue.sections.extend(deck.sections);
    Ok(Built {
        element_sets,
        catalogue,
        model: b.finish(raw, couplings, constraints)?,
        unknown,
        warnings,
        notes,
    })
}

/// The file's own materials, and its sections with the elements of the
/// beam lines and `[[element]]` beams that take them.
fn file_catalogue(raw: &RawModel) -> Catalogue {
    let materials = raw
        .material
        .iter()
        .map(|m| MaterialEntry {
            kind: Some("isotropic"),
            name: m.name.get_ref().clone(),
            youngs_modulus: Some(*m.youngs_modulus.get_ref()),
            poisson: Some(*m.poisson_ratio.get_ref()),
            density: Some(*m.density.get_ref()),
        })
        .collect();
    let sections = raw
        .section
        .iter()
        .map(|s| {
            let name = &s.get_ref().name;
            let mut material = None;
            let mut elements = 0;
            for line in &raw.beam_line {
                let l = line.get_ref();
                if l.section.get_ref() == name {
                    elements += l.elements;
                    material.get_or_insert_with(|| l.material.get_ref().clone());
                }
            }
            for e in &raw.element {
                if let RawElement::Beam {
                    section,
                    material: m,
                    ..
                }
                | RawElement::PlanarBeam {
                    section,
                    material: m,
                    ..
                } = e.get_ref()
                {
                    if section == name {
                        elements += 1;
                        material.get_or_insert_with(|| m.clone());
                    }
                }
            }
            SectionEntry {
                keyword: "[[section]]".to_string(),
                elset: name.clone(),
                material,
                elements,
                mass: None,
            }
        })
        .collect();
    Catalogue {
        materials,
        sections,
    }
}

/// The model as it grows, with the line each node and element came from.
struct Builder<'a> {
    src: TomlSource<'a>,
    materials: HashMap<String, Material>,
    sections: HashMap<String, SectionConstants>,
    nodes: Vec<Node>,
    node_index: HashMap<u64, usize>,
    node_line: HashMap<u64, usize>,
    elements: Vec<Element>,
    element_line: HashMap<usize, usize>,
    sets: BTreeMap<String, Vec<u64>>,
    fixed: Vec<Dof>,
    /// Fixed DOFs of the deck, applied after the file's own.
    deck_fixed: Vec<Dof>,
    /// Couplings of the deck, with the file's own.
    deck_couplings: Vec<Coupling>,
    /// Equations of the deck (`*EQUATION`, `*MPC`, `*TIE`), before the
    /// file's own.
    deck_equations: Vec<Equation>,
    /// The deck's nodal coordinate systems (`*TRANSFORM`).
    deck_local_axes: std::collections::BTreeMap<flexbody_fem::NodeId, flexbody_fem::Axes>,
    /// Damping of the deck, unless the file has `[damping]`.
    deck_damping: Option<Rayleigh>,
    /// Element sets, materials and sections of the deck, for the user
    /// (and the element sets for ties).
    deck_element_sets: BTreeMap<String, Vec<usize>>,
    /// Element surfaces of the deck, for ties.
    deck_surfaces: BTreeMap<String, Vec<SurfaceFaces>>,
    deck_catalogue: Catalogue,
}

impl<'a> Builder<'a> {
    /// A builder that knows the file's materials and sections.
    fn new(src: TomlSource<'a>, raw: &RawModel) -> Result<Self, InputError> {
        let mut materials = HashMap::new();
        for m in &raw.material {
            let mat = Material::new(
                *m.youngs_modulus.get_ref(),
                *m.poisson_ratio.get_ref(),
                *m.density.get_ref(),
            )
            .map_err(|e| {
                let which = if *m.density.get_ref() < 0.0 || !m.density.get_ref().is_finite() {
                    &m.density
                } else if *m.youngs_modulus.get_ref() <= 0.0 {
                    &m.youngs_modulus
                } else {
                    &m.poisson_ratio
                };
                src.at(which, format!("material '{}': {e}", m.name.get_ref()))
            })?;
            if materials.insert(m.name.get_ref().clone(), mat).is_some() {
                return Err(src.at(
                    &m.name,
                    format!("material '{}' is defined twice", m.name.get_ref()),
                ));
            }
        }
        let mut sections = HashMap::new();
        for s in &raw.section {
            let c = s
                .get_ref()
                .shape
                .constants()
                .map_err(|e| src.at(s, format!("section '{}': {e}", s.get_ref().name)))?;
            if sections.insert(s.get_ref().name.clone(), c).is_some() {
                return Err(src.at(
                    s,
                    format!("section '{}' is defined twice", s.get_ref().name),
                ));
            }
        }
        Ok(Self {
            src,
            materials,
            sections,
            nodes: Vec::new(),
            node_index: HashMap::new(),
            node_line: HashMap::new(),
            elements: Vec::new(),
            element_line: HashMap::new(),
            sets: BTreeMap::new(),
            fixed: Vec::new(),
            deck_fixed: Vec::new(),
            deck_couplings: Vec::new(),
            deck_equations: Vec::new(),
            deck_local_axes: Default::default(),
            deck_damping: None,
            deck_element_sets: BTreeMap::new(),
            deck_surfaces: BTreeMap::new(),
            deck_catalogue: Catalogue::default(),
        })
    }

    /// Beam properties from a material and a section named in the file.
    fn properties(
        &self,
        mat: &Spanned<String>,
        sec: &Spanned<String>,
        theory: BeamTheory,
        rotary: Option<bool>,
    ) -> Result<BeamProperties, InputError> {
        let m = self.materials.get(mat.get_ref()).ok_or_else(|| {
            self.src
                .at(mat, format!("material '{}' is not defined", mat.get_ref()))
        })?;
        let s = self.sections.get(sec.get_ref()).ok_or_else(|| {
            self.src
                .at(sec, format!("section '{}' is not defined", sec.get_ref()))
        })?;
        let mut p = BeamProperties::new(m.clone(), s.clone(), theory);
        if let Some(r) = rotary {
            p.rotary_inertia = r;
        }
        Ok(p)
    }

    fn add_node(&mut self, id: u64, coords: [f64; 3], offset: usize) -> Result<(), InputError> {
        if let Some(first) = self.node_line.insert(id, self.src.line(offset)) {
            return Err(self.src.error(
                Some(offset),
                format!("node {id} is defined twice (first on line {first})"),
            ));
        }
        if coords.iter().any(|c| !c.is_finite()) {
            return Err(self.src.error(
                Some(offset),
                format!("node {id} has a non-finite coordinate"),
            ));
        }
        self.node_index.insert(id, self.nodes.len());
        self.nodes.push(Node { id, coords });
        Ok(())
    }

    /// The position of node `id`, if defined so far.
    fn position(&self, id: u64) -> Option<[f64; 3]> {
        self.node_index.get(&id).map(|&i| self.nodes[i].coords)
    }

    fn add_element(&mut self, e: Element, offset: usize) -> Result<(), InputError> {
        if let Some(first) = self.element_line.insert(e.id(), self.src.line(offset)) {
            return Err(self.src.error(
                Some(offset),
                format!(
                    "element {} is defined twice (first on line {first})",
                    e.id()
                ),
            ));
        }
        self.elements.push(e);
        Ok(())
    }

    /// `mesh = "deck.inp"`: the deck's model, every part of it (nodes as
    /// its ties' ADJUST left them, elements, node sets, fixed DOFs,
    /// couplings, equations, damping); the unknown
    /// keywords it skipped, its warnings and its note, each naming the deck.
    fn deck_mesh(
        &mut self,
        mesh: &Spanned<String>,
        options: &DeckOptions,
    ) -> Result<(UnknownKeywords, Vec<String>, Vec<String>), InputError> {
        let path = self.src.relative(mesh.get_ref());
        let deck = crate::deck::read_deck(&path, options)?;
        let offset = mesh.span().start;
        for n in deck.model.nodes() {
            self.add_node(n.id, n.coords, offset)?;
        }
        for e in deck.model.elements() {
            self.add_element(e.clone(), offset)?;
        }
        for (name, set) in deck.model.node_sets() {
            self.sets
                .entry(name.clone())
                .or_default()
                .extend(set.iter().copied());
        }
        self.deck_fixed = deck.model.fixed_dofs().copied().collect();
        self.deck_couplings = deck.model.couplings().to_vec();
        self.deck_equations = deck.model.equations().to_vec();
        self.deck_local_axes = deck.model.local_axes().clone();
        self.deck_damping = deck.model.rayleigh();
        self.deck_element_sets = deck.element_sets.clone();
        self.deck_surfaces = deck.element_surfaces.clone();
        self.deck_catalogue = deck.catalogue.clone();
        let notes = deck.skipped_note().into_iter().collect();
        let warnings = deck.warning_lines();
        Ok((deck.unknown, warnings, notes))
    }

    fn check_node(
        &self,
        known: &HashSet<u64>,
        node: u64,
        offset: usize,
        what: &str,
    ) -> Result<(), InputError> {
        if known.contains(&node) {
            Ok(())
        } else {
            Err(self.src.error(
                Some(offset),
                format!("{what} refers to node {node}, which does not exist"),
            ))
        }
    }

    /// `[[element]]`: single beams, shells, point masses and springs.
    fn elements(&mut self, raw: &RawModel, known: &HashSet<u64>) -> Result<(), InputError> {
        for e in &raw.element {
            let offset = e.span().start;
            let named = |s: &String| Spanned::new(e.span(), s.clone());
            let element = match e.get_ref() {
                RawElement::PlanarBeam {
                    id,
                    nodes,
                    material,
                    section,
                    rotary_inertia,
                } => Element::PlanarBeam(PlanarBeam {
                    id: *id,
                    nodes: *nodes,
                    properties: self.properties(
                        &named(material),
                        &named(section),
                        BeamTheory::EulerBernoulli,
                        *rotary_inertia,
                    )?,
                }),
                RawElement::Beam {
                    id,
                    nodes,
                    material,
                    section,
                    theory,
                    rotary_inertia,
                    orientation,
                } => Element::Beam(Beam {
                    id: *id,
                    nodes: *nodes,
                    properties: self.properties(
                        &named(material),
                        &named(section),
                        *theory,
                        *rotary_inertia,
                    )?,
                    orientation: *orientation,
                }),
                RawElement::Shell {
                    id,
                    nodes,
                    material,
                    thickness,
                    offset: shell_offset,
                } => {
                    let kind = match nodes.len() {
                        3 => ShellKind::S3,
                        4 => ShellKind::S4,
                        6 => ShellKind::S6,
                        8 => ShellKind::S8,
                        n => {
                            return Err(self.src.error(
                                Some(offset),
                                format!(
                                    "shell {id} has {n} nodes; an S3 has 3, an S4 4, an S6 6, \
                                     an S8 8"
                                ),
                            ))
                        }
                    };
                    flexbody_fem::require_positive(format!("thickness of shell {id}"), *thickness)
                        .map_err(|x| self.src.error(Some(offset), x.to_string()))?;
                    let m = self.materials.get(material).ok_or_else(|| {
                        self.src.error(
                            Some(offset),
                            format!("shell {id}: material '{material}' is not defined"),
                        )
                    })?;
                    Element::Shell(Shell {
                        id: *id,
                        kind,
                        nodes: nodes.clone(),
                        material: m.clone(),
                        thickness: *thickness,
                        offset: *shell_offset,
                    })
                }
                RawElement::PointMass {
                    id,
                    node,
                    mass,
                    inertia,
                } => {
                    flexbody_fem::require_non_negative(format!("mass of point mass {id}"), *mass)
                        .map_err(|x| self.src.error(Some(offset), x.to_string()))?;
                    Element::PointMass(PointMass {
                        id: *id,
                        node: *node,
                        mass: *mass,
                        inertia: *inertia,
                    })
                }
                RawElement::Spring {
                    id,
                    dof,
                    to,
                    stiffness,
                } => {
                    flexbody_fem::require_positive(format!("stiffness of spring {id}"), *stiffness)
                        .map_err(|x| self.src.error(Some(offset), x.to_string()))?;
                    Element::Spring(Spring {
                        id: *id,
                        first: dof.dof(),
                        second: to.map(|t| t.dof()),
                        stiffness: *stiffness,
                    })
                }
            };
            for node in element.nodes() {
                self.check_node(known, node, offset, &format!("element {}", element.id()))?;
            }
            self.add_element(element, offset)?;
        }
        Ok(())
    }

    /// `[sets]`: named node sets, added to those of beam lines and the deck.
    fn node_sets(&mut self, raw: &RawModel, known: &HashSet<u64>) -> Result<(), InputError> {
        for (name, set) in &raw.sets {
            for node in set.get_ref() {
                self.check_node(
                    known,
                    *node,
                    set.span().start,
                    &format!("node set '{name}'"),
                )?;
            }
            self.sets
                .entry(name.clone())
                .or_default()
                .extend(set.get_ref().iter().copied());
        }
        Ok(())
    }

    /// `[[boundary]]`: fixed DOFs, then those of the deck.
    fn boundaries(&mut self, raw: &RawModel, known: &HashSet<u64>) -> Result<(), InputError> {
        for b in &raw.boundary {
            self.check_node(
                known,
                b.get_ref().node,
                b.span().start,
                "boundary condition",
            )?;
            let node = b.get_ref().node;
            self.fixed
                .extend(b.get_ref().dofs.iter().map(|k| Dof::new(node, *k)));
        }
        let deck_fixed = std::mem::take(&mut self.deck_fixed);
        self.fixed.extend(deck_fixed);
        Ok(())
    }

    /// `[[coupling]]`: interface points, new nodes coupled to node sets
    /// (RBE2/RBE3), each with the offset of its entry.
    fn couplings(
        &mut self,
        raw: &RawModel,
        known: &HashSet<u64>,
    ) -> Result<Vec<(usize, Coupling)>, InputError> {
        let mut couplings = Vec::new();
        for c in &raw.coupling {
            let r = c.get_ref();
            let what = format!("coupling '{}'", r.name);
            let members: Vec<u64> = match (&r.set, &r.nodes) {
                (Some(set), None) => {
                    let key = self.sets.keys().find(|k| k.eq_ignore_ascii_case(set));
                    match key {
                        Some(k) => self.sets[k].clone(),
                        None => {
                            return Err(self
                                .src
                                .at(c, format!("{what}: node set '{set}' does not exist")))
                        }
                    }
                }
                (None, Some(list)) => list.clone(),
                _ => {
                    return Err(self
                        .src
                        .at(c, format!("{what}: give either `set` or `nodes`")))
                }
            };
            if members.is_empty() {
                return Err(self.src.at(c, format!("{what}: its node set is empty")));
            }
            for n in &members {
                self.check_node(known, *n, c.span().start, &what)?;
            }
            let position = r.position.unwrap_or_else(|| self.centroid(&members));
            self.add_node(r.point, position, c.span().start)?;
            couplings.push((
                c.span().start,
                Coupling {
                    name: r.name.clone(),
                    kind: r.kind,
                    point: r.point,
                    nodes: members,
                    weights: r.weights.clone(),
                },
            ));
        }
        Ok(couplings)
    }

    /// The mean position of existing nodes.
    fn centroid(&self, members: &[u64]) -> [f64; 3] {
        let mut p = [0.0; 3];
        for n in members {
            let x = self
                .nodes
                .iter()
                .find(|x| x.id == *n)
                .map_or([0.0; 3], |x| x.coords);
            for k in 0..3 {
                p[k] += x[k] / members.len() as f64;
            }
        }
        p
    }

    /// The model, its couplings and equations eliminated; errors of the
    /// model and of element geometry point at the line of the element,
    /// boundary condition, coupling or constraint where they can (a deck's
    /// constraint at the `mesh` line).
    fn finish(
        self,
        raw: &RawModel,
        couplings: Vec<(usize, Coupling)>,
        constraints: constraints::FileConstraints,
    ) -> Result<Model, InputError> {
        let src = self.src;
        let coupling_lines: Vec<(String, usize)> = couplings
            .iter()
            .map(|(o, c)| (c.name.clone(), src.line(*o)))
            .collect();
        let element_line = self.element_line;
        let mesh_line = raw.mesh.as_ref().map(|m| src.line(m.span().start));
        let deck_constraints: HashSet<String> =
            self.deck_equations.iter().map(|e| e.name.clone()).collect();
        let constraint_line = |name: &str| match constraints.entries.get(name) {
            Some(offset) => Some(src.line(*offset)),
            None => mesh_line.filter(|_| deck_constraints.contains(name)),
        };
        let mut parts = Model::of(self.nodes, self.elements)
            .node_sets(self.sets)
            .fixed(self.fixed)
            .couplings(
                self.deck_couplings
                    .into_iter()
                    .chain(couplings.into_iter().map(|(_, c)| c))
                    .collect(),
            )
            .equations(
                self.deck_equations
                    .into_iter()
                    .chain(constraints.equations)
                    .collect(),
            )
            .local_axes(self.deck_local_axes);
        if let Some(damping) = raw.damping.or(self.deck_damping) {
            parts = parts.rayleigh(damping);
        }
        let model = parts.build().map_err(|e| {
            let line = match &e {
                FemError::ZeroLength { element }
                | FemError::PlanarBeamNotAlongX { element }
                | FemError::OrientationParallel { element, .. } => {
                    element_line.get(element).copied()
                }
                FemError::UnknownDof { node, .. } => raw
                    .boundary
                    .iter()
                    .find(|b| b.get_ref().node == *node)
                    .map(|b| src.line(b.span().start)),
                FemError::InvalidCoupling { name, .. } => coupling_lines
                    .iter()
                    .find(|(n, _)| n == name)
                    .map(|(_, l)| *l),
                FemError::InvalidConstraint { name, .. } => constraint_line(name),
                _ => None,
            };
            InputError::Invalid {
                path: src.path.to_path_buf(),
                line,
                message: e.to_string(),
            }
        })?;
        // Element geometry errors (zero length, orientation) with their
        // line, before any computation starts.
        for e in model.elements() {
            e.validate(&model).map_err(|x| InputError::Invalid {
                path: src.path.to_path_buf(),
                line: element_line.get(&e.id()).copied(),
                message: x.to_string(),
            })?;
        }
        Ok(model)
    }
}
