//! Reading the cards in order: each keyword read, skipped with a warning,
//! refused (the lists are in `known.rs`) or, unknown, refused or collected
//! (`unknown.rs`); nodes, elements, sets and boundary conditions. Materials and sections are in `properties.rs`.
//! Nothing is checked across cards here beyond what must exist already
//! (sets named in set data and in `*BOUNDARY`); the model is built and
//! checked in `build.rs`.

use super::cards::{is_numeric, name, Card, DataLine, Files, Loc};
use super::known::{nearest_known, IGNORED, REFUSED};
use super::steps::StepAction;
use super::unknown::{DeckOptions, UnknownKeywords};
use crate::InputError;
use flexbody_fem::element::{element_types, ElementType, SectionKind};
use flexbody_fem::{Dof, DofKind, Node, NodeId, Rayleigh};
use std::collections::{BTreeMap, HashMap, HashSet};

/// Set entries held before their memory is first compared with the room
/// left (then at every doubling): 4 Mi entries, about 100 MB.
const SET_ENTRIES_UNCHECKED: usize = 1 << 22;

/// Keywords that belong to the current `*MATERIAL` block.
const MATERIAL_OPTIONS: &[&str] = &[
    "ELASTIC",
    "DENSITY",
    "EXPANSION",
    "CONDUCTIVITY",
    "SPECIFICHEAT",
    "PLASTIC",
    "CYCLICHARDENING",
    "CREEP",
    "DAMPING",
    "HYPERELASTIC",
    "HYPERFOAM",
    "DEFORMATIONPLASTICITY",
    "USERMATERIAL",
    "DEPVAR",
];

/// The keyword that gives elements of a section kind their properties.
pub(super) fn property_keyword(section: SectionKind) -> &'static str {
    match section {
        SectionKind::Solid => "*SOLID SECTION",
        SectionKind::Shell => "*SHELL SECTION",
        SectionKind::Beam => "*BEAM SECTION",
        SectionKind::Mass => "*MASS",
        SectionKind::Spring { .. } => "*SPRING",
        SectionKind::Dashpot { .. } => "*DASHPOT",
    }
}

/// Why an element type is refused, for the types users are likely to have.
fn unsupported_type_hint(t: &str) -> &'static str {
    match t {
        "S4R5" | "S8R5" | "S9R5" => {
            " (Abaqus' thin shells with five DOFs per node are not implemented; S3, S4, S6 and \
             S8 are)"
        }
        _ if t.starts_with('S') => " (flexbody's shells are S3, S4, S6 and S8 (S3R, S4R, S8R))",
        _ if t.starts_with('M') => " (membranes are not implemented)",
        _ if t.starts_with("CP") || t.starts_with("CAX") => {
            " (plane and axisymmetric elements are not implemented)"
        }
        _ => "",
    }
}

/// An element as read: its properties come from a section found later.
#[derive(Clone, Debug)]
pub(super) struct RawElement {
    pub id: usize,
    /// Its type in the element registry.
    pub kind: &'static ElementType,
    pub nodes: Vec<NodeId>,
    pub loc: Loc,
}

/// A `*COUPLING` with its `*KINEMATIC` or `*DISTRIBUTING` card.
pub(super) struct DeckCoupling {
    pub name: String,
    pub point: NodeId,
    pub surface: String,
    pub kind: Option<flexbody_fem::CouplingKind>,
    pub loc: Loc,
}

/// The deck read card by card, before sections are assigned.
pub(super) struct Reader<'a> {
    pub files: &'a Files,
    pub nodes: Vec<Node>,
    node_loc: HashMap<NodeId, Loc>,
    pub elements: Vec<RawElement>,
    element_loc: HashMap<usize, Loc>,
    /// Set entries with the line that listed them (copied with their
    /// line when a set names another), and the sets in order of definition.
    pub node_sets: BTreeMap<String, Vec<(NodeId, Loc)>>,
    pub node_set_order: Vec<String>,
    pub element_sets: BTreeMap<String, Vec<(usize, Loc)>>,
    pub element_set_order: Vec<String>,
    pub materials: Vec<super::properties::RawMaterial>,
    pub sections: Vec<super::properties::RawSection>,
    /// `*INITIAL CONDITIONS, TYPE=TEMPERATURE`: the model temperature.
    pub initial_temperature: Option<Card>,
    /// `*ORIENTATION`s: name, system, line.
    pub orientations: Vec<(String, flexbody_fem::Orientation, Loc)>,
    /// Fixed DOFs with their `*BOUNDARY` data line.
    pub fixed: Vec<(Dof, Loc)>,
    pub warnings: Vec<String>,
    /// Keywords skipped because they do not change K, M or D, each with
    /// the line of its first use: `"*STEP (line 40)"`.
    pub skipped: Vec<String>,
    /// Node-based surfaces (`*SURFACE, TYPE=NODE`): name -> nodes.
    pub surfaces: BTreeMap<String, Vec<NodeId>>,
    /// Element-based surfaces: name -> (element or element set, face
    /// number 1-6, line).
    pub element_surfaces: BTreeMap<String, Vec<(String, usize, Loc)>>,
    pub ties: Vec<super::constraints::RawTie>,
    /// `*CONTACT PAIR`s and their surface interactions.
    pub contact: super::contact::Contact,
    /// `*TRANSFORM`s in the order read.
    pub transforms: Vec<super::transform::RawTransform>,
    pub couplings: Vec<DeckCoupling>,
    pub equations: Vec<super::constraints::RawEquation>,
    pub mpcs: Vec<super::constraints::RawMpc>,
    pub rigid_bodies: Vec<super::constraints::RawRigidBody>,
    pub distributing: Vec<super::constraints::RawDistributing>,
    /// DCOUP3D elements: id -> (reference node, line).
    pub dcoup: BTreeMap<usize, (NodeId, Loc)>,
    /// The model's Rayleigh damping of `*MODAL DAMPING, RAYLEIGH`.
    pub modal_rayleigh: Option<(Rayleigh, Loc)>,
    /// Unknown keywords skipped under `allow_unknown`.
    pub unknown: UnknownKeywords,
    options: DeckOptions,
    warned: HashSet<String>,
    pub(super) current_material: Option<usize>,
    steps: super::steps::Steps,
    instances: usize,
    /// Data lines of the deck's `*NODE` and `*ELEMENT` cards: no more
    /// nodes and elements than these can be defined, so no `GENERATE`
    /// range of more numbers can name only defined ones.
    definable: Definable,
    /// Set entries added so far, and the count at which their memory is
    /// compared with the room left next.
    set_entries: std::cell::Cell<(usize, usize)>,
}

/// Upper bounds on the nodes and elements a deck defines: the data lines
/// of its `*NODE` and `*ELEMENT` cards.
#[derive(Copy, Clone, Debug, Default)]
struct Definable {
    nodes: usize,
    elements: usize,
}

impl<'a> Reader<'a> {
    pub fn new(files: &'a Files, options: DeckOptions) -> Self {
        Self {
            files,
            nodes: Vec::new(),
            node_loc: HashMap::new(),
            elements: Vec::new(),
            element_loc: HashMap::new(),
            node_sets: BTreeMap::new(),
            node_set_order: Vec::new(),
            element_sets: BTreeMap::new(),
            element_set_order: Vec::new(),
            materials: Vec::new(),
            sections: Vec::new(),
            orientations: Vec::new(),
            initial_temperature: None,
            fixed: Vec::new(),
            warnings: Vec::new(),
            skipped: Vec::new(),
            surfaces: BTreeMap::new(),
            element_surfaces: BTreeMap::new(),
            ties: Vec::new(),
            transforms: Vec::new(),
            contact: Default::default(),
            couplings: Vec::new(),
            equations: Vec::new(),
            mpcs: Vec::new(),
            rigid_bodies: Vec::new(),
            distributing: Vec::new(),
            dcoup: BTreeMap::new(),
            modal_rayleigh: None,
            unknown: UnknownKeywords {
                deck: files.paths[0].clone(),
                keywords: Vec::new(),
            },
            options,
            warned: HashSet::new(),
            current_material: None,
            steps: super::steps::Steps::default(),
            instances: 0,
            definable: Definable::default(),
            set_entries: std::cell::Cell::new((0, SET_ENTRIES_UNCHECKED)),
        }
    }

    /// Reads all cards in order.
    pub fn read(&mut self, cards: &[Card]) -> Result<(), InputError> {
        for card in cards {
            match card.keyword.as_str() {
                "NODE" => self.definable.nodes += card.data.len(),
                "ELEMENT" => self.definable.elements += card.data.len(),
                _ => {}
            }
        }
        for card in cards {
            let k = card.keyword.as_str();
            if let StepAction::AfterFrequency = self.steps.see(self.files, card)? {
                self.after_frequency(card);
                continue;
            }
            if !MATERIAL_OPTIONS.contains(&k) {
                self.current_material = None;
            }
            if !matches!(k, "SURFACEBEHAVIOR" | "FRICTION" | "GAPCONDUCTANCE") {
                self.contact.end_interaction();
            }
            match k {
                "NODE" => self.node(card)?,
                "ELEMENT" => self.element(card)?,
                "NSET" => self.nset(card)?,
                "ELSET" => self.elset(card)?,
                "BOUNDARY" => self.boundary(card)?,
                "MATERIAL" => self.material(card)?,
                "ELASTIC" => self.elastic(card)?,
                "DENSITY" => self.density(card)?,
                "ORIENTATION" => self.orientation(card)?,
                "INITIALCONDITIONS"
                    if card
                        .value("TYPE")
                        .is_some_and(|t| t.eq_ignore_ascii_case("TEMPERATURE")) =>
                {
                    self.initial_temperature = Some(card.clone())
                }
                "SOLIDSECTION" => self.solid_section(card)?,
                "SHELLSECTION" => self.shell_section(card)?,
                "BEAMSECTION" => self.beam_section(card)?,
                "MASS" => self.mass(card)?,
                "SPRING" => self.spring(card)?,
                "DASHPOT" => self.dashpot(card)?,
                "DAMPING" => self.damping(card)?,
                "MODALDAMPING" => self.modal_damping(card)?,
                "INSTANCE" => self.instance(card)?,
                "SURFACE" => self.surface(card)?,
                "COUPLING" => self.coupling(card)?,
                "KINEMATIC" | "DISTRIBUTING" => self.coupling_kind(card)?,
                "EQUATION" => self.equation(card)?,
                "MPC" => self.mpc(card)?,
                "RIGIDBODY" => self.rigid_body(card)?,
                "DISTRIBUTINGCOUPLING" => self.distributing_coupling(card)?,
                "TIE" => self.tie(card)?,
                "TRANSFORM" => self.transform(card)?,
                "CONTACTPAIR" => self.contact_pair(card)?,
                "SURFACEINTERACTION" => self.surface_interaction(card)?,
                "SURFACEBEHAVIOR" => self.surface_behavior(card)?,
                _ => {
                    if let Some((_, what)) = REFUSED.iter().find(|(r, _)| *r == k) {
                        return Err(self.files.error(
                            card.loc,
                            format!(
                                "{} is not supported: ignoring it would change the {what}",
                                card.display
                            ),
                        ));
                    }
                    if IGNORED.contains(&k) {
                        self.warn_once(card, "");
                    } else {
                        self.unknown_keyword(card)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// A boundary condition, load or step after the first frequency step:
    /// skipped, and the first of them reported.
    fn after_frequency(&mut self, card: &Card) {
        if !matches!(card.keyword.as_str(), "STEP" | "ENDSTEP")
            && self.warned.insert("after the frequency step".into())
        {
            let at = self
                .steps
                .done
                .map_or_else(String::new, |l| self.files.describe(l));
            self.warnings.push(format!(
                "ignored {} ({}) and the boundary conditions, loads and steps after the first \
                 frequency step (*FREQUENCY on {at}): they do not change the model of that step",
                card.display,
                self.files.describe(card.loc)
            ));
        }
    }

    /// An unknown keyword: refused, naming the nearest known keyword when
    /// one is close, or recorded when unknown keywords are allowed.
    fn unknown_keyword(&mut self, card: &Card) -> Result<(), InputError> {
        if self.options.allow_unknown {
            self.unknown
                .add(&card.display, self.files.describe(card.loc));
            return Ok(());
        }
        let hint = nearest_known(&card.keyword)
            .map_or_else(String::new, |k| format!("; did you mean *{k}?"));
        Err(self.error(
            card.loc,
            format!(
                "unknown keyword {}{hint} (a keyword flexbody does not know may change K, M or D; \
                 --allow-unknown skips unknown keywords with a warning)",
                card.display
            ),
        ))
    }

    /// Records `*KEY (line n)` the first time a keyword is skipped: among
    /// the routine skips without a `note`, else among the warnings.
    pub(super) fn warn_once(&mut self, card: &Card, note: &str) {
        if self.warned.insert(card.keyword.clone()) {
            let line = format!("{} ({}){note}", card.display, self.files.describe(card.loc));
            if note.is_empty() {
                self.skipped.push(line);
            } else {
                self.warnings.push(format!("ignored {line}"));
            }
        }
    }

    /// Warns about parameters the reader does not use.
    pub(super) fn check_params(&mut self, card: &Card, known: &[&str]) {
        for p in card.unknown_params(known) {
            self.warnings.push(format!(
                "{} ({}): parameter {p} ignored",
                card.display,
                self.files.describe(card.loc)
            ));
        }
    }

    fn error(&self, loc: Loc, message: impl Into<String>) -> InputError {
        self.files.error(loc, message)
    }

    fn node(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["NSET", "SYSTEM", "INPUT"]);
        if let Some(s) = card.value("SYSTEM") {
            if !s.eq_ignore_ascii_case("R") {
                return Err(self.error(
                    card.loc,
                    format!(
                        "*NODE, SYSTEM={s}: only rectangular coordinates (SYSTEM=R) are supported"
                    ),
                ));
            }
        }
        if card.has("INPUT") {
            return Err(self.error(
                card.loc,
                "*NODE, INPUT=...: not supported; use *INCLUDE, INPUT=... under *NODE",
            ));
        }
        let set = card.value("NSET").map(name);
        for line in &card.data {
            let id = line.id(self.files, 0, "node number")?;
            if line.fields.len() > 7 {
                return Err(self.error(
                    line.loc,
                    format!(
                        "node {id}: a *NODE line holds the number and at most 3 coordinates \
                         (and 3 normal components); found {} fields",
                        line.fields.len()
                    ),
                ));
            }
            let mut coords = [0.0; 3];
            for (k, c) in coords.iter_mut().enumerate() {
                *c = line.float_or(
                    self.files,
                    k + 1,
                    &format!("node {id}: coordinate {}", k + 1),
                    0.0,
                )?;
            }
            if let Some(first) = self.node_loc.insert(id, line.loc) {
                return Err(self.error(
                    line.loc,
                    format!(
                        "node {id} is defined twice (first on {})",
                        self.files.describe(first)
                    ),
                ));
            }
            self.nodes.push(Node { id, coords });
            if let Some(set) = &set {
                self.add_node_set_entries(set.clone(), [(id, line.loc)]);
            }
        }
        Ok(())
    }

    fn element(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["TYPE", "ELSET", "INPUT"]);
        if card.has("INPUT") {
            return Err(self.error(
                card.loc,
                "*ELEMENT, INPUT=...: not supported; use *INCLUDE, INPUT=... under *ELEMENT",
            ));
        }
        let type_name = card.require_name(self.files, "TYPE")?;
        if type_name == "DCOUP3D" {
            return self.dcoup3d(card);
        }
        let (kind, alias) = ElementType::resolve(&type_name).ok_or_else(|| {
            let supported: Vec<&str> = element_types().map(|t| t.name).collect();
            self.error(
                card.loc,
                format!(
                    "element type {type_name} is not supported{} (supported: {})",
                    unsupported_type_hint(&type_name),
                    supported.join(", ")
                ),
            )
        })?;
        if let Some(alias) = alias {
            if self.warned.insert(format!("element alias {}", alias.name)) {
                self.warnings.push(format!(
                    "{} ({}): {} elements are read as {}: {}",
                    card.display,
                    self.files.describe(card.loc),
                    alias.name,
                    alias.reads_as,
                    alias.meaning
                ));
            }
        }
        let set = card.value("ELSET").map(name);
        let needed = kind.nodes;
        let mut lines = card.data.iter();
        let mut extra_nodes_reported = false;
        while let Some(first) = lines.next() {
            let mut fields: Vec<&str> = first.fields.iter().map(String::as_str).collect();
            let mut continued = first.continued;
            // A line ending with a comma continues while nodes are missing.
            while continued && fields.len() < needed + 1 {
                let Some(next) = lines.next() else { break };
                fields.extend(next.fields.iter().map(String::as_str));
                continued = next.continued;
            }
            let id = first.id(self.files, 0, "element number")? as usize;
            let mut nodes = Vec::with_capacity(fields.len().saturating_sub(1));
            for (k, f) in fields.iter().enumerate().skip(1) {
                let node = super::cards::parse_id(f).ok_or_else(|| {
                    self.error(
                        first.loc,
                        format!(
                            "element {id}: node {k} should be a positive node number, got '{f}'",
                            f = crate::text::excerpt(f)
                        ),
                    )
                })?;
                nodes.push(node);
            }
            if nodes.len() > needed && kind.section == SectionKind::Solid {
                // CalculiX reads the nodes a solid has and ignores the
                // rest. (A beam's extra node is Abaqus' orientation node,
                // which must not be dropped silently.)
                if !extra_nodes_reported {
                    extra_nodes_reported = true;
                    self.warnings.push(format!(
                        "{} ({}): element {id} lists {} nodes and type {} uses {needed}; the \
                         first {needed} are read and the rest ignored, as CalculiX does (check \
                         the element type if that is not meant)",
                        card.display,
                        self.files.describe(first.loc),
                        nodes.len(),
                        kind.name
                    ));
                }
                nodes.truncate(needed);
            }
            if nodes.len() != needed {
                return Err(self.error(
                    first.loc,
                    format!(
                        "element {id} has {} nodes, but type {} needs {needed}{}",
                        nodes.len(),
                        kind.name,
                        if kind.section == SectionKind::Beam && nodes.len() > needed {
                            " (an orientation node, as Abaqus allows, is not read: give the \
                             direction on the *BEAM SECTION's second line)"
                        } else {
                            ""
                        }
                    ),
                ));
            }
            if let Some(previous) = self.element_loc.insert(id, first.loc) {
                return Err(self.error(
                    first.loc,
                    format!(
                        "element {id} is defined twice (first on {})",
                        self.files.describe(previous)
                    ),
                ));
            }
            self.elements.push(RawElement {
                id,
                kind,
                nodes,
                loc: first.loc,
            });
            if let Some(set) = &set {
                self.add_element_set_entries(set.clone(), [(id, first.loc)]);
            }
        }
        Ok(())
    }

    /// DCOUP3D elements: `id, reference node` (of a `*DISTRIBUTING
    /// COUPLING`).
    fn dcoup3d(&mut self, card: &Card) -> Result<(), InputError> {
        let set = card.value("ELSET").map(name);
        for line in &card.data {
            let id = line.id(self.files, 0, "element number")? as usize;
            let node = line.id(self.files, 1, &format!("element {id} (DCOUP3D): node"))?;
            if line.fields.iter().skip(2).any(|f| !f.is_empty()) {
                return Err(self.error(
                    line.loc,
                    format!("element {id}: a DCOUP3D element has one node"),
                ));
            }
            if let Some(previous) = self.element_loc.insert(id, line.loc) {
                return Err(self.error(
                    line.loc,
                    format!(
                        "element {id} is defined twice (first on {})",
                        self.files.describe(previous)
                    ),
                ));
            }
            self.dcoup.insert(id, (node, line.loc));
            if let Some(set) = &set {
                self.add_element_set_entries(set.clone(), [(id, line.loc)]);
            }
        }
        Ok(())
    }

    /// Adds entries to a node set, recording the order sets are defined in.
    fn add_node_set_entries(
        &mut self,
        set: String,
        entries: impl IntoIterator<Item = (NodeId, Loc)>,
    ) {
        add_set_entries(&mut self.node_sets, &mut self.node_set_order, set, entries);
    }

    /// Adds entries to an element set, recording the order sets are defined
    /// in.
    fn add_element_set_entries(
        &mut self,
        set: String,
        entries: impl IntoIterator<Item = (usize, Loc)>,
    ) {
        add_set_entries(
            &mut self.element_sets,
            &mut self.element_set_order,
            set,
            entries,
        );
    }

    /// `first, last[, step]` of a `GENERATE` line of a set of `what`
    /// (`node` or `element`). A range of more numbers than the deck can
    /// define nodes (or elements) is refused before it is expanded: some of
    /// its numbers would name none.
    fn generate(&self, line: &DataLine, what: &str) -> Result<Vec<u64>, InputError> {
        let first = line.id(self.files, 0, "GENERATE: first number")?;
        let last = line.id(self.files, 1, "GENERATE: last number")?;
        let step = match line.get(2) {
            None => 1,
            Some(_) => line.id(self.files, 2, "GENERATE: increment")?,
        };
        if last < first {
            return Err(self.error(
                line.loc,
                format!("GENERATE: last number {last} is smaller than first number {first}"),
            ));
        }
        let count = (last - first) / step + 1;
        let (definable, keyword) = match what {
            "node" => (self.definable.nodes, "*NODE"),
            _ => (self.definable.elements, "*ELEMENT"),
        };
        if count > definable as u64 {
            return Err(self.error(
                line.loc,
                format!(
                    "GENERATE: {first} to {last} in steps of {step} is {count} {what} numbers, \
                     but the deck's {keyword} cards have {definable} data lines, so it defines \
                     at most {definable} {what}s: a set lists only {what}s of the model"
                ),
            ));
        }
        self.room_for_set_entries(count as usize, line.loc)?;
        Ok((0..count).map(|i| first + i * step).collect())
    }

    /// `more` set entries, or an error when all set entries together
    /// would not fit in the memory left ([`DeckOptions::memory`]); looked
    /// at from [`SET_ENTRIES_UNCHECKED`] entries on, at every doubling.
    fn room_for_set_entries(&self, more: usize, loc: Loc) -> Result<(), InputError> {
        let (held, next_check) = self.set_entries.get();
        let total = held.saturating_add(more);
        let mut next = next_check;
        if total >= next_check {
            let bytes = total.saturating_mul(std::mem::size_of::<(u64, Loc)>());
            self.options
                .memory
                .ensure(
                    bytes as u64,
                    &format!("the deck's set entries ({total} node and element numbers)"),
                )
                .map_err(|e| self.error(loc, e.to_string()))?;
            next = total.saturating_mul(2);
        }
        self.set_entries.set((total, next));
        Ok(())
    }

    /// Ids and set names of a `*NSET` or `*ELSET` card.
    fn set_entries(
        &self,
        card: &Card,
        what: &str,
        lookup: impl Fn(&str) -> Option<Vec<(u64, Loc)>>,
    ) -> Result<Vec<(u64, Loc)>, InputError> {
        let mut entries = Vec::new();
        let generate = card.has("GENERATE");
        for line in &card.data {
            if generate {
                entries.extend(
                    self.generate(line, what)?
                        .into_iter()
                        .map(|id| (id, line.loc)),
                );
                continue;
            }
            for f in line.fields.iter().filter(|f| !f.is_empty()) {
                if is_numeric(f) {
                    let id =
                        super::cards::parse_id(f).ok_or_else(|| {
                            self.error(
                                line.loc,
                                format!(
                                "{} should list positive {what} numbers or set names, got '{f}'",
                                card.display, f = crate::text::excerpt(f)),
                            )
                        })?;
                    entries.push((id, line.loc));
                } else {
                    let other = lookup(&name(f)).ok_or_else(|| {
                        self.error(
                            line.loc,
                            format!(
                                "{what} set '{}' is not defined (define it before it is used)",
                                name(f)
                            ),
                        )
                    })?;
                    self.room_for_set_entries(other.len(), line.loc)?;
                    entries.extend(other);
                }
            }
        }
        Ok(entries)
    }

    fn nset(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(
            card,
            &["NSET", "GENERATE", "UNSORTED", "INTERNAL", "INSTANCE"],
        );
        if card.has("ELSET") {
            return Err(self.error(
                card.loc,
                "*NSET, ELSET=...: not supported; list the nodes or node sets",
            ));
        }
        let set = card.require_name(self.files, "NSET")?;
        let entries = self.set_entries(card, "node", |n| self.node_sets.get(n).cloned())?;
        self.add_node_set_entries(set, entries);
        Ok(())
    }

    fn elset(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(
            card,
            &["ELSET", "GENERATE", "UNSORTED", "INTERNAL", "INSTANCE"],
        );
        let set = card.require_name(self.files, "ELSET")?;
        let entries = self.set_entries(card, "element", |n| {
            self.element_sets
                .get(n)
                .map(|v| v.iter().map(|(id, l)| (*id as u64, *l)).collect())
        })?;
        self.add_element_set_entries(set, entries.into_iter().map(|(id, l)| (id as usize, l)));
        Ok(())
    }

    /// `node or NSET, first_dof[, last_dof[, value]]`, or `node, ENCASTRE`
    /// and the other Abaqus type names.
    fn boundary(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["OP", "AMPLITUDE", "TYPE", "FIXED", "LOADCASE"]);
        for p in ["SUBMODEL", "USER", "MASSFLOW"] {
            if card.has(p) {
                return Err(self.error(card.loc, format!("*BOUNDARY, {p}: not supported")));
            }
        }
        if let Some(t) = card.value("TYPE") {
            if !t.eq_ignore_ascii_case("DISPLACEMENT") {
                return Err(self.error(
                    card.loc,
                    format!(
                        "*BOUNDARY, TYPE={t}: only displacement boundary conditions are supported"
                    ),
                ));
            }
        }
        if self.steps.in_step
            && card
                .value("OP")
                .is_some_and(|v| v.eq_ignore_ascii_case("NEW"))
        {
            return Err(self.error(
                card.loc,
                "*BOUNDARY, OP=NEW in a step is not supported (it removes earlier boundary conditions)",
            ));
        }
        for line in &card.data {
            let target = line
                .get(0)
                .ok_or_else(|| self.error(line.loc, "*BOUNDARY: node or node set is missing"))?;
            let nodes: Vec<NodeId> = if is_numeric(target) {
                vec![line.id(self.files, 0, "*BOUNDARY: node number")?]
            } else {
                self.node_sets
                    .get(&name(target))
                    .ok_or_else(|| {
                        self.error(
                            line.loc,
                            format!("*BOUNDARY: node set '{}' is not defined", name(target)),
                        )
                    })?
                    .iter()
                    .map(|(n, _)| *n)
                    .collect()
            };
            let kinds = self.boundary_dofs(line)?;
            for n in nodes {
                self.fixed
                    .extend(kinds.iter().map(|k| (Dof::new(n, *k), line.loc)));
            }
        }
        Ok(())
    }

    /// The DOFs of one `*BOUNDARY` data line (after the node).
    fn boundary_dofs(&self, line: &DataLine) -> Result<Vec<DofKind>, InputError> {
        let first = line
            .get(1)
            .ok_or_else(|| self.error(line.loc, "*BOUNDARY: first DOF is missing"))?;
        if !is_numeric(first) {
            let dofs: &[usize] = match name(first).as_str() {
                "ENCASTRE" => &[1, 2, 3, 4, 5, 6],
                "PINNED" => &[1, 2, 3],
                "XSYMM" => &[1, 5, 6],
                "YSYMM" => &[2, 4, 6],
                "ZSYMM" => &[3, 4, 5],
                "XASYMM" => &[2, 3, 4],
                "YASYMM" => &[1, 3, 5],
                "ZASYMM" => &[1, 2, 6],
                other => {
                    return Err(self.error(
                        line.loc,
                        format!(
                            "*BOUNDARY: unknown boundary type '{other}'",
                            other = crate::text::excerpt(other)
                        ),
                    ))
                }
            };
            return Ok(dofs.iter().map(|d| DofKind::ALL[d - 1]).collect());
        }
        let a = line.id(self.files, 1, "*BOUNDARY: first DOF")?;
        let b = match line.get(2) {
            None => a,
            Some(_) => line.id(self.files, 2, "*BOUNDARY: last DOF")?,
        };
        let value = line.float_or(self.files, 3, "*BOUNDARY: value", 0.0)?;
        if value != 0.0 {
            return Err(self.error(
                line.loc,
                format!("*BOUNDARY: prescribed displacement {value} is not supported (only fixed DOFs, value 0)"),
            ));
        }
        if !(1..=6).contains(&a) || !(1..=6).contains(&b) || b < a {
            return Err(self.error(
                line.loc,
                format!("*BOUNDARY: DOFs {a} to {b}: only DOFs 1 to 6 (ux uy uz rx ry rz), first <= last"),
            ));
        }
        Ok((a..=b).map(|d| DofKind::ALL[d as usize - 1]).collect())
    }

    /// Abaqus assemblies: one instance of one part without a transformation
    /// is the part itself.
    /// `*SURFACE, NAME=, TYPE=NODE`: node sets or node numbers (for
    /// couplings and ties); `TYPE=ELEMENT` (the default): `element or
    /// element set, S1..S6` lines (element faces, for ties).
    fn surface(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["NAME", "TYPE", "INTERNAL"]);
        let name = card.require_name(self.files, "NAME")?;
        let kind = card.value("TYPE").map(super::cards::name);
        match kind.as_deref() {
            Some("NODE") => {
                let mut nodes = Vec::new();
                for line in &card.data {
                    let first = line.get(0).unwrap_or("");
                    match self.node_sets.get(&first.to_ascii_uppercase()) {
                        Some(set) => nodes.extend(set.iter().map(|(n, _)| *n)),
                        None => nodes.push(line.id(self.files, 0, "surface node or node set")?),
                    }
                }
                self.surfaces.insert(name, nodes);
            }
            None | Some("ELEMENT") => {
                let mut faces = Vec::new();
                for line in &card.data {
                    let target = line.get(0).filter(|t| !t.is_empty()).ok_or_else(|| {
                        self.error(line.loc, "*SURFACE: element or element set is missing")
                    })?;
                    let face = line.get(1).map(super::cards::name).unwrap_or_default();
                    let number = face
                        .strip_prefix('S')
                        .and_then(|n| n.parse::<usize>().ok())
                        .filter(|n| (1..=6).contains(n))
                        .ok_or_else(|| {
                            self.error(
                                line.loc,
                                format!(
                                    "*SURFACE {name}: face '{face}' should be S1 to S6",
                                    face = crate::text::excerpt(&face)
                                ),
                            )
                        })?;
                    faces.push((target.to_string(), number, line.loc));
                }
                self.element_surfaces.insert(name, faces);
            }
            Some(other) => {
                return Err(self.error(
                    card.loc,
                    format!(
                        "*SURFACE, TYPE={other}: only TYPE=NODE and TYPE=ELEMENT are supported"
                    ),
                ))
            }
        }
        Ok(())
    }

    /// `*COUPLING, REF NODE=, SURFACE=, CONSTRAINT NAME=`: an interface
    /// point coupled to a node surface by the `*KINEMATIC` or
    /// `*DISTRIBUTING` card that follows.
    fn coupling(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(
            card,
            &["REFNODE", "SURFACE", "CONSTRAINTNAME", "ORIENTATION"],
        );
        let point = card
            .require(self.files, "REFNODE")?
            .parse::<u64>()
            .map_err(|_| self.error(card.loc, "*COUPLING: REF NODE must be a node number"))?;
        let surface = card.require_name(self.files, "SURFACE")?;
        let name = card.value("CONSTRAINTNAME").map_or_else(
            || format!("COUPLING-{}", self.couplings.len() + 1),
            str::to_string,
        );
        self.couplings.push(DeckCoupling {
            name,
            point,
            surface,
            kind: None,
            loc: card.loc,
        });
        Ok(())
    }

    fn coupling_kind(&mut self, card: &Card) -> Result<(), InputError> {
        let Some(c) = self.couplings.last_mut().filter(|c| c.kind.is_none()) else {
            return Err(self.error(
                card.loc,
                format!("*{} must follow a *COUPLING card", card.display),
            ));
        };
        if card.keyword == "KINEMATIC" {
            // DOF ranges: all translations (1..3) or all DOFs (1..6).
            let mut dofs = std::collections::BTreeSet::new();
            for line in &card.data {
                let first = line.id(self.files, 0, "first DOF")?;
                let last = match line.get(1) {
                    Some(v) if !v.is_empty() => line.id(self.files, 1, "last DOF")?,
                    _ => first,
                };
                dofs.extend(first..=last);
            }
            let all3: std::collections::BTreeSet<u64> = (1..=3).collect();
            let all6: std::collections::BTreeSet<u64> = (1..=6).collect();
            if !(dofs.is_empty() || dofs == all3 || dofs == all6) {
                let loc = c.loc;
                return Err(self.error(loc, format!("*KINEMATIC on DOFs {dofs:?}: only full rigid couplings (DOFs 1-3 or 1-6) are supported")));
            }
            c.kind = Some(flexbody_fem::CouplingKind::Rigid);
        } else {
            c.kind = Some(flexbody_fem::CouplingKind::Distributing);
        }
        Ok(())
    }

    fn instance(&mut self, card: &Card) -> Result<(), InputError> {
        self.instances += 1;
        if self.instances > 1 || !card.data.is_empty() {
            return Err(self.error(
                card.loc,
                "*INSTANCE: only a single instance without translation or rotation is supported",
            ));
        }
        self.warn_once(card, "");
        Ok(())
    }
}

/// Adds entries to the set `set` of `sets`, appending its name to `order`
/// when it is new.
fn add_set_entries<T>(
    sets: &mut BTreeMap<String, Vec<(T, Loc)>>,
    order: &mut Vec<String>,
    set: String,
    entries: impl IntoIterator<Item = (T, Loc)>,
) {
    if !sets.contains_key(&set) {
        order.push(set.clone());
    }
    sets.entry(set).or_default().extend(entries);
}
