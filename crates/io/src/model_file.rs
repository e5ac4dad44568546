//! The TOML model file (format documented in `docs/model-file.md`). Raw
//! TOML is deserialised into `Raw*` structs that keep source spans, then
//! checked and turned into a [`flexbody_fem::Model`] and the MBS
//! description, with errors that name the line.

use crate::InputError;
use flexbody_fem::element::{Beam, PlanarBeam, PointMass, Spring};
use flexbody_fem::{
    BeamProperties, BeamTheory, Coupling, CouplingKind, Dof, DofKind, Element, Material, Model,
    Node, Rayleigh, SectionShape,
};
use flexbody_mbs::time::{Excitation, History, Profile, TimeForce, TimeSettings};
use flexbody_mbs::{Connection, Endpoint, ForceLaw, RigidBody, Track};
use flexbody_reduce::{ForceGroup, GroundSpring, Method};
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};
use toml::Spanned;

/// A study case: a method and its number of eigenmodes.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    pub method: Method,
    /// Eigenmodes e; for `free` the total r including rigid-body modes.
    #[serde(default)]
    pub modes: usize,
    /// Or: every eigenmode below this frequency (Hz).
    #[serde(default)]
    pub fmax: Option<f64>,
}

/// The `[study]` table: cases and excitation frequencies.
#[derive(Clone, Debug, PartialEq)]
pub struct StudySpec {
    /// Excitation frequencies Omega (rad/s).
    pub omegas: Vec<f64>,
    pub cases: Vec<CaseSpec>,
}

/// A model file, checked.
#[derive(Clone, Debug)]
pub struct ModelFile {
    pub path: PathBuf,
    pub title: Option<String>,
    pub model: Model,
    /// Interface DOFs: given, or those the connections act on.
    pub interface: Vec<Dof>,
    /// Statically determinate support for inertia-relief modes, if given.
    pub support: Option<Vec<Dof>>,
    /// Force groups replacing unit loads (report section 7), if given.
    pub force_groups: Vec<ForceGroup>,
    /// Rigid bodies that move (held ones are ground).
    pub rigid_bodies: Vec<RigidBody>,
    /// Connections; flexible endpoints refer to body 0, the model.
    pub connections: Vec<Connection>,
    pub track: Option<Track>,
    pub study: Option<StudySpec>,
    pub simulation: Option<SimulationSpec>,
    pub frf: Option<FrfSpec>,
}

/// Where the flexible body of a simulation comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum BodySource {
    /// Reduce the file's model with this method and number of eigenmodes.
    Reduce { method: Method, modes: usize },
    /// A reduced-body file (JSON), resolved relative to the model file.
    File(PathBuf),
}

/// The `[simulation]` table: the vehicle run in time (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationSpec {
    pub body: BodySource,
    /// Modal damping ratios of the reduced body (one for all, or per mode).
    pub modal_damping: Vec<f64>,
    pub settings: TimeSettings,
    /// Vehicle speed, track profile, fade-in and time forces.
    pub excitation: Excitation,
    /// Beam elements whose section forces are recorded (eq. 25 with q'').
    pub record: Vec<usize>,
    /// Solid nodes whose von Mises stress is recorded.
    pub record_nodes: Vec<u64>,
}

/// The `[frf]` table: transfer functions over a band.
#[derive(Clone, Debug, PartialEq)]
pub struct FrfSpec {
    /// Lowest and highest frequency (Hz).
    pub band_hz: [f64; 2],
    pub points: usize,
}

impl ModelFile {
    /// The connections as springs to ground at their flexible node: the
    /// elastic support of the `elastic-residual` method (report Bild 8:
    /// the other ends held; nonlinear laws with their stiffness at rest).
    pub fn ground_springs(&self) -> Vec<GroundSpring> {
        self.connections
            .iter()
            .filter_map(|c| {
                let node = match (&c.a, &c.b) {
                    (_, Endpoint::Flexible { node, .. }) | (Endpoint::Flexible { node, .. }, _) => {
                        *node
                    }
                    _ => return None,
                };
                let (stiffness, _) = c.law.linearized();
                (stiffness > 0.0).then_some(GroundSpring {
                    node,
                    direction: c.direction,
                    stiffness,
                })
            })
            .collect()
    }
}

// ---------------------------------------------------------------- raw TOML

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    title: Option<String>,
    /// An Abaqus/CalculiX deck with the FE model (relative to this file).
    mesh: Option<Spanned<String>>,
    #[serde(default)]
    coupling: Vec<Spanned<RawCoupling>>,
    #[serde(default)]
    material: Vec<RawMaterial>,
    #[serde(default)]
    section: Vec<Spanned<RawSection>>,
    #[serde(default)]
    nodes: Vec<Spanned<(u64, f64, f64, f64)>>,
    #[serde(default)]
    beam_line: Vec<Spanned<RawBeamLine>>,
    #[serde(default)]
    element: Vec<Spanned<RawElement>>,
    #[serde(default)]
    sets: BTreeMap<String, Spanned<Vec<u64>>>,
    #[serde(default)]
    boundary: Vec<Spanned<RawBoundary>>,
    damping: Option<Rayleigh>,
    interface: Option<RawInterface>,
    track: Option<Track>,
    #[serde(default)]
    rigid_body: Vec<Spanned<RawRigidBody>>,
    #[serde(default)]
    connection: Vec<Spanned<RawConnection>>,
    study: Option<RawStudy>,
    simulation: Option<Spanned<RawSimulation>>,
    frf: Option<Spanned<FrfRaw>>,
    #[serde(default)]
    force: Vec<Spanned<RawForce>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSimulation {
    #[serde(default)]
    method: Option<Method>,
    #[serde(default)]
    modes: usize,
    #[serde(default)]
    body: Option<String>,
    #[serde(default)]
    modal_damping: Vec<f64>,
    speed: f64,
    duration: f64,
    step: f64,
    #[serde(default = "default_alpha")]
    alpha: f64,
    #[serde(default)]
    adaptive: Option<f64>,
    #[serde(default)]
    ramp: f64,
    #[serde(default)]
    profile: Option<String>,
    #[serde(default)]
    record: Vec<usize>,
    #[serde(default)]
    record_nodes: Vec<u64>,
}

fn default_alpha() -> f64 {
    TimeSettings::default().alpha
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FrfRaw {
    band_hz: [f64; 2],
    points: usize,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawForce {
    name: String,
    #[serde(default)]
    node: Option<u64>,
    #[serde(default)]
    body: Option<String>,
    #[serde(default)]
    point: Option<[f64; 3]>,
    direction: [f64; 3],
    #[serde(default)]
    harmonic: Option<RawHarmonic>,
    #[serde(default)]
    table: Option<Vec<[f64; 2]>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawHarmonic {
    amplitude: f64,
    frequency_hz: f64,
    #[serde(default)]
    phase: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    name: Spanned<String>,
    youngs_modulus: Spanned<f64>,
    #[serde(default = "default_poisson")]
    poisson_ratio: Spanned<f64>,
    density: Spanned<f64>,
}

fn default_poisson() -> Spanned<f64> {
    Spanned::new(0..0, 0.3)
}

#[derive(Deserialize)]
struct RawSection {
    name: String,
    #[serde(flatten)]
    shape: SectionShape,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
enum BeamKind {
    PlanarBeam,
    Beam,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBeamLine {
    element: BeamKind,
    #[serde(default)]
    theory: BeamTheory,
    #[serde(default)]
    rotary_inertia: Option<bool>,
    from: [f64; 3],
    to: [f64; 3],
    elements: usize,
    first_node: u64,
    #[serde(default)]
    first_element: Option<usize>,
    material: Spanned<String>,
    section: Spanned<String>,
    #[serde(default)]
    orientation: Option<[f64; 3]>,
    #[serde(default)]
    set: Option<String>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
struct RawDof {
    node: u64,
    dof: DofKind,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
enum RawElement {
    PlanarBeam {
        id: usize,
        nodes: [u64; 2],
        material: String,
        section: String,
        #[serde(default)]
        rotary_inertia: Option<bool>,
    },
    Beam {
        id: usize,
        nodes: [u64; 2],
        material: String,
        section: String,
        #[serde(default)]
        theory: BeamTheory,
        #[serde(default)]
        rotary_inertia: Option<bool>,
        orientation: [f64; 3],
    },
    PointMass {
        id: usize,
        node: u64,
        mass: f64,
        #[serde(default)]
        inertia: [f64; 6],
    },
    Spring {
        id: usize,
        dof: RawDof,
        #[serde(default)]
        to: Option<RawDof>,
        stiffness: f64,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBoundary {
    node: u64,
    dofs: Vec<DofKind>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInterface {
    #[serde(default)]
    dofs: Vec<Spanned<RawDof>>,
    #[serde(default)]
    nodes: Vec<Spanned<u64>>,
    #[serde(default)]
    support: Option<Vec<Spanned<RawDof>>>,
    #[serde(default)]
    force_groups: Vec<Spanned<RawForceGroup>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCoupling {
    name: String,
    kind: CouplingKind,
    /// The interface point: a new node with 6 DOFs.
    point: u64,
    /// Its position (m); default: the centroid of the set.
    #[serde(default)]
    position: Option<[f64; 3]>,
    #[serde(default)]
    set: Option<String>,
    #[serde(default)]
    nodes: Option<Vec<u64>>,
    #[serde(default)]
    weights: Option<Vec<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawForceGroup {
    name: String,
    loads: Vec<RawLoad>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLoad {
    node: u64,
    dof: DofKind,
    value: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRigidBody {
    name: String,
    mass: f64,
    #[serde(default)]
    inertia: [f64; 6],
    center: [f64; 3],
    #[serde(default)]
    dofs: Option<Vec<DofKind>>,
    #[serde(default)]
    fixed: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConnection {
    name: String,
    /// End b on the flexible body.
    #[serde(default)]
    node: Option<u64>,
    /// End b on a rigid body (instead of `node`).
    #[serde(default)]
    body: Option<String>,
    /// End a: "ground", "track" or a rigid body's name.
    to: String,
    direction: [f64; 3],
    #[serde(default)]
    law: Option<String>,
    #[serde(default)]
    stiffness: Option<f64>,
    #[serde(default)]
    damping: Option<f64>,
    #[serde(default)]
    points: Option<Vec<[f64; 2]>>,
    #[serde(default)]
    clearance: Option<f64>,
    #[serde(default)]
    force: Option<f64>,
    #[serde(default)]
    velocity: Option<f64>,
    /// Attachment point on a rigid-body end (m).
    #[serde(default)]
    point: Option<[f64; 3]>,
    #[serde(default)]
    track_x: Option<f64>,
}

impl RawConnection {
    /// The force law the fields describe, or a message naming what is wrong.
    fn law(&self) -> Result<ForceLaw, String> {
        let name = self.law.as_deref().unwrap_or("linear");
        let given: Vec<(&str, bool)> = vec![
            ("stiffness", self.stiffness.is_some()),
            ("damping", self.damping.is_some()),
            ("points", self.points.is_some()),
            ("clearance", self.clearance.is_some()),
            ("force", self.force.is_some()),
            ("velocity", self.velocity.is_some()),
        ];
        let need =
            |field: &str, v: Option<f64>| v.ok_or_else(|| format!("law {name} needs `{field}`"));
        let (law, allowed): (ForceLaw, &[&str]) = match name {
            "linear" => (
                ForceLaw::linear(self.stiffness.unwrap_or(0.0), self.damping.unwrap_or(0.0)),
                &["stiffness", "damping"],
            ),
            "piecewise-linear" => (
                ForceLaw::PiecewiseLinear {
                    points: self.points.clone().ok_or("law piecewise-linear needs `points` = [[v, F], ...]")?,
                    damping: self.damping.unwrap_or(0.0),
                },
                &["points", "damping"],
            ),
            "bump-stop" => (
                ForceLaw::BumpStop {
                    clearance: need("clearance", self.clearance)?,
                    stiffness: need("stiffness", self.stiffness)?,
                },
                &["clearance", "stiffness"],
            ),
            "friction-damper" => (
                ForceLaw::FrictionDamper {
                    force: need("force", self.force)?,
                    velocity: need("velocity", self.velocity)?,
                },
                &["force", "velocity"],
            ),
            other => {
                return Err(format!(
                    "unknown law '{other}'; expected linear, piecewise-linear, bump-stop or friction-damper"
                ))
            }
        };
        if let Some((field, _)) = given.iter().find(|(f, g)| *g && !allowed.contains(f)) {
            return Err(format!("`{field}` is not a parameter of law {name}"));
        }
        law.validate()?;
        Ok(law)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStudy {
    omegas: Vec<f64>,
    cases: Vec<Spanned<CaseSpec>>,
}

// ------------------------------------------------------------------ reader

/// Reads and checks a model file.
pub fn read_model_file(path: &Path) -> Result<ModelFile, InputError> {
    let text = std::fs::read_to_string(path).map_err(|source| InputError::Read {
        path: path.to_path_buf(),
        cause: source,
    })?;
    parse_model_file(path, &text)
}

/// Parses and checks the text of a model file (`path` names it in errors).
pub fn parse_model_file(path: &Path, text: &str) -> Result<ModelFile, InputError> {
    let ctx = Context { path, text };
    let raw: RawFile = toml::from_str(text)
        .map_err(|e| ctx.error(e.span().map(|s| s.start), e.message().to_string()))?;
    ctx.build(raw)
}

struct Context<'a> {
    path: &'a Path,
    text: &'a str,
}

impl Context<'_> {
    fn line(&self, offset: usize) -> usize {
        self.text[..offset.min(self.text.len())]
            .matches('\n')
            .count()
            + 1
    }

    fn error(&self, offset: Option<usize>, message: impl Into<String>) -> InputError {
        InputError::Invalid {
            path: self.path.to_path_buf(),
            line: offset.map(|o| self.line(o)),
            message: message.into(),
        }
    }

    fn at<T>(&self, s: &Spanned<T>, message: impl Into<String>) -> InputError {
        let span = s.span();
        self.error((span.end > 0).then_some(span.start), message)
    }

    fn build(&self, raw: RawFile) -> Result<ModelFile, InputError> {
        // Materials and sections.
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
                self.at(which, format!("material '{}': {e}", m.name.get_ref()))
            })?;
            if materials.insert(m.name.get_ref().clone(), mat).is_some() {
                return Err(self.at(
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
                .map_err(|e| self.at(s, format!("section '{}': {e}", s.get_ref().name)))?;
            if sections.insert(s.get_ref().name.clone(), c).is_some() {
                return Err(self.at(
                    s,
                    format!("section '{}' is defined twice", s.get_ref().name),
                ));
            }
        }
        let props = |mat: &Spanned<String>,
                     sec: &Spanned<String>,
                     theory: BeamTheory,
                     rotary: Option<bool>|
         -> Result<BeamProperties, InputError> {
            let m = materials.get(mat.get_ref()).ok_or_else(|| {
                self.at(mat, format!("material '{}' is not defined", mat.get_ref()))
            })?;
            let s = sections.get(sec.get_ref()).ok_or_else(|| {
                self.at(sec, format!("section '{}' is not defined", sec.get_ref()))
            })?;
            let mut p = BeamProperties::new(m.clone(), s.clone(), theory);
            if let Some(r) = rotary {
                p.rotary_inertia = r;
            }
            Ok(p)
        };

        // Nodes: explicit, then generated by beam lines.
        let mut nodes: Vec<Node> = Vec::new();
        let mut node_line: HashMap<u64, usize> = HashMap::new();
        let mut add_node = |id: u64,
                            coords: [f64; 3],
                            offset: usize,
                            nodes: &mut Vec<Node>|
         -> Result<(), InputError> {
            if let Some(first) = node_line.insert(id, self.line(offset)) {
                return Err(self.error(
                    Some(offset),
                    format!("node {id} is defined twice (first on line {first})"),
                ));
            }
            if coords.iter().any(|c| !c.is_finite()) {
                return Err(self.error(
                    Some(offset),
                    format!("node {id} has a non-finite coordinate"),
                ));
            }
            nodes.push(Node { id, coords });
            Ok(())
        };
        for n in &raw.nodes {
            let (id, x, y, z) = *n.get_ref();
            add_node(id, [x, y, z], n.span().start, &mut nodes)?;
        }
        let mut elements: Vec<Element> = Vec::new();
        let mut element_line: HashMap<usize, usize> = HashMap::new();
        let mut sets: BTreeMap<String, Vec<u64>> = BTreeMap::new();
        let mut next_element = 1;
        for line in &raw.beam_line {
            let b = line.get_ref();
            let offset = line.span().start;
            if b.elements == 0 {
                return Err(self.at(line, "beam_line needs at least one element"));
            }
            let p = props(&b.material, &b.section, b.theory, b.rotary_inertia)?;
            if b.element == BeamKind::PlanarBeam && b.theory != BeamTheory::EulerBernoulli {
                return Err(self.at(line, "planar-beam elements are Euler-Bernoulli; use element = \"beam\" for Timoshenko"));
            }
            let ids: Vec<u64> = (0..=b.elements as u64).map(|i| b.first_node + i).collect();
            for (i, id) in ids.iter().enumerate() {
                let t = i as f64 / b.elements as f64;
                let c = [0, 1, 2].map(|k| b.from[k] + t * (b.to[k] - b.from[k]));
                add_node(*id, c, offset, &mut nodes)?;
            }
            let first = b.first_element.unwrap_or(next_element);
            for i in 0..b.elements {
                let id = first + i;
                let en = [ids[i], ids[i + 1]];
                let e = match b.element {
                    BeamKind::PlanarBeam => Element::PlanarBeam(PlanarBeam {
                        id,
                        nodes: en,
                        properties: p.clone(),
                    }),
                    BeamKind::Beam => Element::Beam(Beam {
                        id,
                        nodes: en,
                        properties: p.clone(),
                        orientation: b.orientation.ok_or_else(|| {
                            self.at(
                                line,
                                "beam_line of 3D beams needs an orientation (local y direction)",
                            )
                        })?,
                    }),
                };
                self.add_element(e, offset, &mut elements, &mut element_line)?;
            }
            next_element = first + b.elements;
            if let Some(set) = &b.set {
                sets.entry(set.clone()).or_default().extend(ids);
            }
        }
        // The mesh of a deck, if given.
        let mut deck_fixed: Vec<Dof> = Vec::new();
        if let Some(mesh) = &raw.mesh {
            let deck_path = self
                .path
                .parent()
                .unwrap_or(Path::new("."))
                .join(mesh.get_ref());
            let deck = crate::deck::read_deck(&deck_path)?;
            let offset = mesh.span().start;
            for n in deck.model.nodes() {
                add_node(n.id, n.coords, offset, &mut nodes)?;
            }
            for e in deck.model.elements() {
                self.add_element(e.clone(), offset, &mut elements, &mut element_line)?;
            }
            for (name, set) in deck.model.node_sets() {
                sets.entry(name.clone())
                    .or_default()
                    .extend(set.iter().copied());
            }
            deck_fixed = deck.model.fixed_dofs().copied().collect();
        }
        let known: HashSet<u64> = nodes.iter().map(|n| n.id).collect();
        let check_node = |node: u64, offset: usize, what: &str| -> Result<(), InputError> {
            if known.contains(&node) {
                Ok(())
            } else {
                Err(self.error(
                    Some(offset),
                    format!("{what} refers to node {node}, which does not exist"),
                ))
            }
        };
        for e in &raw.element {
            let offset = e.span().start;
            let element = match e.get_ref() {
                RawElement::PlanarBeam {
                    id,
                    nodes: en,
                    material,
                    section,
                    rotary_inertia,
                } => {
                    let sp = |s: &String| Spanned::new(e.span(), s.clone());
                    Element::PlanarBeam(PlanarBeam {
                        id: *id,
                        nodes: *en,
                        properties: props(
                            &sp(material),
                            &sp(section),
                            BeamTheory::EulerBernoulli,
                            *rotary_inertia,
                        )?,
                    })
                }
                RawElement::Beam {
                    id,
                    nodes: en,
                    material,
                    section,
                    theory,
                    rotary_inertia,
                    orientation,
                } => {
                    let sp = |s: &String| Spanned::new(e.span(), s.clone());
                    Element::Beam(Beam {
                        id: *id,
                        nodes: *en,
                        properties: props(&sp(material), &sp(section), *theory, *rotary_inertia)?,
                        orientation: *orientation,
                    })
                }
                RawElement::PointMass {
                    id,
                    node,
                    mass,
                    inertia,
                } => {
                    flexbody_fem::require_non_negative(format!("mass of point mass {id}"), *mass)
                        .map_err(|x| self.error(Some(offset), x.to_string()))?;
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
                        .map_err(|x| self.error(Some(offset), x.to_string()))?;
                    Element::Spring(Spring {
                        id: *id,
                        first: Dof::new(dof.node, dof.dof),
                        second: to.map(|t| Dof::new(t.node, t.dof)),
                        stiffness: *stiffness,
                    })
                }
            };
            for node in element.nodes() {
                check_node(node, offset, &format!("element {}", element.id()))?;
            }
            self.add_element(element, offset, &mut elements, &mut element_line)?;
        }
        for (name, set) in &raw.sets {
            for node in set.get_ref() {
                check_node(*node, set.span().start, &format!("node set '{name}'"))?;
            }
            sets.entry(name.clone())
                .or_default()
                .extend(set.get_ref().iter().copied());
        }
        let mut fixed = Vec::new();
        for b in &raw.boundary {
            check_node(b.get_ref().node, b.span().start, "boundary condition")?;
            fixed.extend(
                b.get_ref()
                    .dofs
                    .iter()
                    .map(|k| Dof::new(b.get_ref().node, *k)),
            );
        }
        fixed.extend(deck_fixed);
        // Interface points: new nodes coupled to node sets (RBE2/RBE3).
        let mut couplings = Vec::new();
        for c in &raw.coupling {
            let r = c.get_ref();
            let what = format!("coupling '{}'", r.name);
            let members: Vec<u64> = match (&r.set, &r.nodes) {
                (Some(set), None) => {
                    let key = sets.keys().find(|k| k.eq_ignore_ascii_case(set)).cloned();
                    match key {
                        Some(k) => sets[&k].clone(),
                        None => {
                            return Err(
                                self.at(c, format!("{what}: node set '{set}' does not exist"))
                            )
                        }
                    }
                }
                (None, Some(list)) => list.clone(),
                _ => return Err(self.at(c, format!("{what}: give either `set` or `nodes`"))),
            };
            if members.is_empty() {
                return Err(self.at(c, format!("{what}: its node set is empty")));
            }
            for n in &members {
                check_node(*n, c.span().start, &what)?;
            }
            let position = match r.position {
                Some(p) => p,
                None => {
                    let mut p = [0.0; 3];
                    for n in &members {
                        let x = nodes
                            .iter()
                            .find(|x| x.id == *n)
                            .map_or([0.0; 3], |x| x.coords);
                        for k in 0..3 {
                            p[k] += x[k] / members.len() as f64;
                        }
                    }
                    p
                }
            };
            add_node(r.point, position, c.span().start, &mut nodes)?;
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
        let coupling_lines: Vec<(String, usize)> = couplings
            .iter()
            .map(|(o, c)| (c.name.clone(), self.line(*o)))
            .collect();
        let model = Model::new(nodes, elements, sets, fixed.clone(), raw.damping)
            .and_then(|m| m.with_couplings(couplings.into_iter().map(|(_, c)| c).collect()))
            .map_err(|e| {
                // Point at the element or boundary line where we can.
                let line = match &e {
                    flexbody_fem::FemError::ZeroLength { element }
                    | flexbody_fem::FemError::PlanarBeamNotAlongX { element }
                    | flexbody_fem::FemError::OrientationParallel { element, .. } => {
                        element_line.get(element).copied()
                    }
                    flexbody_fem::FemError::UnknownDof { node, .. } => raw
                        .boundary
                        .iter()
                        .find(|b| b.get_ref().node == *node)
                        .map(|b| self.line(b.span().start)),
                    flexbody_fem::FemError::InvalidCoupling { name, .. } => coupling_lines
                        .iter()
                        .find(|(n, _)| n == name)
                        .map(|(_, l)| *l),
                    _ => None,
                };
                InputError::Invalid {
                    path: self.path.to_path_buf(),
                    line,
                    message: e.to_string(),
                }
            })?;
        // Element geometry errors (zero length, orientation) with their line,
        // before any computation starts.
        for e in model.elements() {
            e.validate(&model).map_err(|x| InputError::Invalid {
                path: self.path.to_path_buf(),
                line: element_line.get(&e.id()).copied(),
                message: x.to_string(),
            })?;
        }

        // MBS: rigid bodies, track, connections.
        let mut rigid_bodies = Vec::new();
        let mut rigid_index: HashMap<String, Option<usize>> = HashMap::new();
        for rb in &raw.rigid_body {
            let b = rb.get_ref();
            if b.name == "ground" || b.name == "track" {
                return Err(self.at(rb, format!("rigid body name '{}' is reserved", b.name)));
            }
            flexbody_fem::require_positive(format!("mass of rigid body '{}'", b.name), b.mass)
                .map_err(|e| self.at(rb, e.to_string()))?;
            let idx = if b.fixed {
                None
            } else {
                rigid_bodies.push(RigidBody {
                    name: b.name.clone(),
                    mass: b.mass,
                    inertia: b.inertia,
                    center: b.center,
                    active: b.dofs.clone().unwrap_or_else(|| DofKind::ALL.to_vec()),
                });
                Some(rigid_bodies.len() - 1)
            };
            if rigid_index.insert(b.name.clone(), idx).is_some() {
                return Err(self.at(rb, format!("rigid body '{}' is defined twice", b.name)));
            }
        }
        if let Some(t) = raw.track {
            if !(t.wavelength.is_finite() && t.wavelength > 0.0 && t.amplitude.is_finite()) {
                return Err(self.error(
                    None,
                    "track: wavelength must be positive and amplitude finite",
                ));
            }
        }
        let mut connections = Vec::new();
        let mut names = HashSet::new();
        for c in &raw.connection {
            let r = c.get_ref();
            let offset = c.span().start;
            let what = format!("connection '{}'", r.name);
            if !names.insert(r.name.clone()) {
                return Err(self.at(c, format!("{what} is defined twice")));
            }
            let law = r.law().map_err(|e| self.at(c, format!("{what}: {e}")))?;
            if flexbody_reduce::method::unit(r.direction).is_none() {
                return Err(self.at(c, format!("{what}: direction must be a non-zero vector")));
            }
            let rigid_end = |name: &str, default_point: [f64; 3]| -> Result<Endpoint, InputError> {
                match rigid_index.get(name) {
                    Some(None) => Ok(Endpoint::Ground),
                    Some(Some(i)) => Ok(Endpoint::Rigid {
                        body: *i,
                        point: r.point.unwrap_or(default_point),
                    }),
                    None => Err(self.at(c, format!("{what}: '{name}' is not a rigid body"))),
                }
            };
            // End b: a node of the flexible body, or a rigid body.
            let (b, b_pos) = match (r.node, &r.body) {
                (Some(node), None) => {
                    if model.node(node).is_none() {
                        return Err(self.error(
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
                            return Err(self.at(
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
                    return Err(self.at(
                        c,
                        format!(
                            "{what}: give either `node` (flexible body) or `body` (rigid body)"
                        ),
                    ))
                }
            };
            let a = match r.to.as_str() {
                "ground" => Endpoint::Ground,
                "track" => {
                    if raw.track.is_none() {
                        return Err(self.at(
                            c,
                            format!("{what} goes to the track, but there is no [track] table"),
                        ));
                    }
                    Endpoint::Track {
                        x: r.track_x.unwrap_or(b_pos[0]),
                    }
                }
                name if rigid_index.contains_key(name) => rigid_end(name, b_pos)?,
                name => {
                    return Err(self.at(
                        c,
                        format!(
                        "{what} goes to '{name}', which is neither ground, track nor a rigid body"
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

        // Interface: given, or what the connections act on.
        let check_dof = |d: &Spanned<RawDof>, what: &str| -> Result<Dof, InputError> {
            let dof = Dof::new(d.get_ref().node, d.get_ref().dof);
            if model.node(dof.node).is_none() {
                return Err(self.error(
                    Some(d.span().start),
                    format!("{what} refers to node {}, which does not exist", dof.node),
                ));
            }
            if model.dof_map().index_of(dof).is_none() {
                return Err(self.at(d, format!("{what}: {dof} is not a free DOF of the model")));
            }
            Ok(dof)
        };
        let mut interface: Vec<Dof> = Vec::new();
        let mut support = None;
        let mut force_groups = Vec::new();
        if let Some(i) = &raw.interface {
            for d in &i.dofs {
                interface.push(check_dof(d, "interface")?);
            }
            for n in &i.nodes {
                if model.node(*n.get_ref()).is_none() {
                    return Err(self.error(
                        Some(n.span().start),
                        format!(
                            "interface refers to node {}, which does not exist",
                            n.get_ref()
                        ),
                    ));
                }
                interface.extend(
                    model
                        .dof_map()
                        .node_dofs(*n.get_ref())
                        .into_iter()
                        .map(|(k, _)| Dof::new(*n.get_ref(), k)),
                );
            }
            for g in &i.force_groups {
                let r = g.get_ref();
                let mut loads = Vec::new();
                for l in &r.loads {
                    let dof = Dof::new(l.node, l.dof);
                    if model.dof_map().index_of(dof).is_none() {
                        return Err(self.at(
                            g,
                            format!(
                                "force group '{}': {dof} is not a free DOF of the model",
                                r.name
                            ),
                        ));
                    }
                    if !l.value.is_finite() {
                        return Err(self.at(
                            g,
                            format!("force group '{}': load {} is not finite", r.name, l.value),
                        ));
                    }
                    loads.push((dof, l.value));
                }
                if loads.is_empty() {
                    return Err(self.at(g, format!("force group '{}' has no loads", r.name)));
                }
                force_groups.push(ForceGroup {
                    name: r.name.clone(),
                    loads,
                });
            }
            if let Some(s) = &i.support {
                support = Some(
                    s.iter()
                        .map(|d| check_dof(d, "interface support"))
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
                    if r.direction[k] != 0.0 && !interface.contains(&d) {
                        interface.push(d);
                    }
                }
            }
        }
        let mut seen = HashSet::new();
        for d in &interface {
            if !seen.insert(*d) {
                return Err(self.error(None, format!("interface: {d} is listed twice")));
            }
        }

        let simulation = match &raw.simulation {
            None => None,
            Some(sim) => Some(self.simulation(sim, &raw, &model, &rigid_index)?),
        };
        let study = match raw.study {
            None => None,
            Some(s) => {
                for o in &s.omegas {
                    if !(o.is_finite() && *o >= 0.0) {
                        return Err(self.error(
                            None,
                            format!("study: omega {o} must be a finite frequency >= 0 (rad/s)"),
                        ));
                    }
                }
                for c in &s.cases {
                    if let Some(f) = c.get_ref().fmax {
                        if !(f.is_finite() && f > 0.0) || c.get_ref().modes > 0 {
                            return Err(self.at(c, "study: fmax must be a positive frequency (Hz), given instead of modes"));
                        }
                    }
                    if c.get_ref().method == Method::Guyan && c.get_ref().modes > 0 {
                        return Err(
                            self.at(c, "study: the guyan method takes no eigenmodes (modes = 0)")
                        );
                    }
                }
                Some(StudySpec {
                    omegas: s.omegas,
                    cases: s.cases.into_iter().map(|c| c.into_inner()).collect(),
                })
            }
        };
        let frf = match &raw.frf {
            None => None,
            Some(f) => {
                let r = f.get_ref();
                let [lo, hi] = r.band_hz;
                if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi > lo && r.points >= 2) {
                    return Err(self.at(
                        f,
                        "frf: band_hz = [low, high] with 0 <= low < high (Hz) and points >= 2",
                    ));
                }
                Some(FrfSpec {
                    band_hz: r.band_hz,
                    points: r.points,
                })
            }
        };
        Ok(ModelFile {
            path: self.path.to_path_buf(),
            title: raw.title,
            model,
            interface,
            support,
            force_groups,
            rigid_bodies,
            connections,
            track: raw.track,
            study,
            simulation,
            frf,
        })
    }

    /// The `[simulation]` table and the `[[force]]` entries.
    fn simulation(
        &self,
        sim: &Spanned<RawSimulation>,
        raw: &RawFile,
        model: &Model,
        rigid_index: &HashMap<String, Option<usize>>,
    ) -> Result<SimulationSpec, InputError> {
        let r = sim.get_ref();
        let bad = |message: String| self.at(sim, format!("simulation: {message}"));
        let body = match (&r.body, r.method) {
            (Some(file), None) => {
                BodySource::File(self.path.parent().unwrap_or(Path::new(".")).join(file))
            }
            (None, Some(method)) => BodySource::Reduce {
                method,
                modes: r.modes,
            },
            _ => {
                return Err(bad(
                    "give either `method` (and `modes`) or `body` (a reduced-body file)".into(),
                ))
            }
        };
        let settings = TimeSettings {
            step: r.step,
            duration: r.duration,
            alpha: r.alpha,
            adaptive: r.adaptive,
            ..TimeSettings::default()
        };
        settings.validate().map_err(bad)?;
        if !(r.speed.is_finite() && r.speed >= 0.0) {
            return Err(bad(format!("speed {} must be >= 0 (m/s)", r.speed)));
        }
        if !(r.ramp.is_finite() && r.ramp >= 0.0) {
            return Err(bad(format!("ramp {} must be >= 0 (s)", r.ramp)));
        }
        if let Some(z) = r
            .modal_damping
            .iter()
            .find(|z| !(z.is_finite() && **z >= 0.0))
        {
            return Err(bad(format!("modal damping ratio {z} must be >= 0")));
        }
        let profile = match &r.profile {
            None => None,
            Some(file) => Some(read_profile(
                &self.path.parent().unwrap_or(Path::new(".")).join(file),
            )?),
        };
        if profile.is_none()
            && raw.track.is_none()
            && raw.connection.iter().any(|c| c.get_ref().to == "track")
        {
            return Err(bad(
                "the track moves but there is neither a [track] table nor a `profile` file".into(),
            ));
        }
        for e in &r.record {
            match model.elements().iter().find(|x| x.id() == *e) {
                Some(Element::PlanarBeam(_)) | Some(Element::Beam(_)) => {}
                Some(_) => {
                    return Err(bad(format!(
                        "record: element {e} is not a beam; section forces are recorded for beams"
                    )))
                }
                None => return Err(bad(format!("record: element {e} does not exist"))),
            }
        }
        for n in &r.record_nodes {
            let on_solid = model
                .elements()
                .iter()
                .any(|e| matches!(e, Element::Solid(s) if s.nodes.contains(n)));
            if !on_solid {
                return Err(bad(format!(
                    "record_nodes: node {n} is not a node of a solid element"
                )));
            }
        }
        let mut forces = Vec::new();
        for f in &raw.force {
            let x = f.get_ref();
            let what = format!("force '{}'", x.name);
            let at = match (x.node, &x.body) {
                (Some(node), None) => {
                    if model.node(node).is_none() {
                        return Err(self.at(
                            f,
                            format!("{what} refers to node {node}, which does not exist"),
                        ));
                    }
                    Endpoint::Flexible { body: 0, node }
                }
                (None, Some(name)) => match rigid_index.get(name) {
                    Some(Some(i)) => Endpoint::Rigid {
                        body: *i,
                        point: x.point.unwrap_or([0.0; 3]),
                    },
                    _ => {
                        return Err(
                            self.at(f, format!("{what}: '{name}' is not a moving rigid body"))
                        )
                    }
                },
                _ => return Err(self.at(f, format!("{what}: give either `node` or `body`"))),
            };
            let history = match (&x.harmonic, &x.table) {
                (Some(h), None) => History::Harmonic {
                    amplitude: h.amplitude,
                    frequency_hz: h.frequency_hz,
                    phase: h.phase,
                },
                (None, Some(rows)) => {
                    if rows
                        .windows(2)
                        .any(|w| w[1][0].partial_cmp(&w[0][0]) != Some(std::cmp::Ordering::Greater))
                    {
                        return Err(self.at(f, format!("{what}: table times must ascend")));
                    }
                    History::Table(rows.clone())
                }
                _ => return Err(self.at(f, format!("{what}: give either `harmonic` or `table`"))),
            };
            if flexbody_reduce::method::unit(x.direction).is_none() {
                return Err(self.at(f, format!("{what}: direction must be a non-zero vector")));
            }
            forces.push(TimeForce {
                name: x.name.clone(),
                at,
                direction: x.direction,
                history,
            });
        }
        Ok(SimulationSpec {
            body,
            modal_damping: r.modal_damping.clone(),
            settings,
            excitation: Excitation {
                speed: r.speed,
                profile,
                ramp: r.ramp,
                forces,
            },
            record: r.record.clone(),
            record_nodes: r.record_nodes.clone(),
        })
    }

    fn add_element(
        &self,
        e: Element,
        offset: usize,
        elements: &mut Vec<Element>,
        lines: &mut HashMap<usize, usize>,
    ) -> Result<(), InputError> {
        if let Some(first) = lines.insert(e.id(), self.line(offset)) {
            return Err(self.error(
                Some(offset),
                format!(
                    "element {} is defined twice (first on line {first})",
                    e.id()
                ),
            ));
        }
        elements.push(e);
        Ok(())
    }
}

/// Reads a track profile: one `s, z` row per line (m), `#` comments and a
/// header line allowed, s strictly ascending.
pub fn read_profile(path: &Path) -> Result<Profile, InputError> {
    let text = std::fs::read_to_string(path).map_err(|source| InputError::Read {
        path: path.to_path_buf(),
        cause: source,
    })?;
    let bad = |line: usize, message: String| InputError::Invalid {
        path: path.to_path_buf(),
        line: Some(line),
        message,
    };
    let (mut s, mut z) = (Vec::new(), Vec::new());
    for (k, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let fields: Vec<&str> = line
            .split([',', ';', ' ', '\t'])
            .filter(|f| !f.is_empty())
            .collect();
        let parsed: Option<Vec<f64>> = fields.iter().map(|f| f.parse::<f64>().ok()).collect();
        match parsed {
            None if s.is_empty()
                && z.is_empty()
                && fields.iter().all(|f| f.parse::<f64>().is_err()) =>
            {
                continue
            } // header
            Some(v) if v.len() == 2 && v.iter().all(|x| x.is_finite()) => {
                if let Some(last) = s.last() {
                    if v[0] <= *last {
                        return Err(bad(
                            k + 1,
                            format!("s = {} does not ascend (previous {last})", v[0]),
                        ));
                    }
                }
                s.push(v[0]);
                z.push(v[1]);
            }
            _ => {
                return Err(bad(
                    k + 1,
                    format!("expected two numbers `s, z` (m), got `{raw}`"),
                ))
            }
        }
    }
    if s.len() < 2 {
        return Err(InputError::Invalid {
            path: path.to_path_buf(),
            line: None,
            message: "a track profile needs at least two rows".into(),
        });
    }
    Ok(Profile::Table { s, z })
}
