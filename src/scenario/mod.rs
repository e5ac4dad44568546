//! What is done with a model: the scenario tables of a TOML model file
//! (format documented in `docs/model-file.md`).
//!
//! A model file holds an FE model, read by [`flexbody_io::model_toml`], and
//! around it the reduction interface, the MBS (rigid bodies, connections,
//! track), the accuracy study, the run in time and the frequency response.
//! This module reads the latter into [`flexbody_reduce`] and [`flexbody_mbs`]
//! types. Raw TOML is deserialised into `Raw*` structs that keep source
//! spans, then checked table by table, with errors that name the line.

mod cases;
mod interface;
mod mbs;
mod raw;
mod simulation;

pub use simulation::read_profile;

use flexbody_fem::{Dof, Model};
use flexbody_io::deck::{DeckOptions, UnknownKeywords};
use flexbody_io::model_toml::{parse_model_toml, ModelToml};
use flexbody_io::{InputError, TomlSource};
use flexbody_mbs::time::{Excitation, TimeSettings};
use flexbody_mbs::{Connection, Endpoint, FlexibleBody, RigidBody, System, Track};
use flexbody_reduce::{ForceGroup, GroundSpring, Method};
use serde::Deserialize;
use std::path::{Path, PathBuf};

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

/// A model file, checked: the FE model and what is done with it.
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
    /// Unknown keywords the `mesh` deck skipped (only when read with
    /// [`DeckOptions::allow_unknown`]); show [`UnknownKeywords::summary`].
    pub unknown_keywords: UnknownKeywords,
    /// The `mesh` deck's warnings for the user, each naming the deck.
    pub warnings: Vec<String>,
    /// The `mesh` deck's note on the routine keywords it skipped.
    pub notes: Vec<String>,
    /// The `mesh` deck's element sets (upper-case names).
    pub element_sets: std::collections::BTreeMap<String, Vec<usize>>,
    /// The file's and its deck's materials and sections.
    pub catalogue: flexbody_io::deck::Catalogue,
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
    /// The MBS of this file around `body`, its one flexible body: the
    /// file's rigid bodies, connections and track.
    pub fn system<'a>(&self, body: FlexibleBody<'a>) -> System<'a> {
        System {
            flexible: vec![body],
            rigid: self.rigid_bodies.clone(),
            connections: self.connections.clone(),
            track: self.track,
        }
    }

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

/// Reads and checks a model file; a `mesh` deck with an unknown keyword
/// is refused.
pub fn read_model_file(path: &Path) -> Result<ModelFile, InputError> {
    read_model_file_with(path, &DeckOptions::default())
}

/// Reads and checks a model file, its `mesh` deck read with `options`.
pub fn read_model_file_with(path: &Path, options: &DeckOptions) -> Result<ModelFile, InputError> {
    let text = flexbody_io::text::read_text(path)?;
    parse_model_file_with(path, &text, options)
}

/// [`parse_model_file_with`] refusing unknown deck keywords.
pub fn parse_model_file(path: &Path, text: &str) -> Result<ModelFile, InputError> {
    parse_model_file_with(path, text, &DeckOptions::default())
}

/// Parses and checks the text of a model file (`path` names it in errors):
/// first every top-level key and the scenario tables' syntax, then the
/// model (a `mesh` deck read with `options`), then the tables that refer
/// to it.
pub fn parse_model_file_with(
    path: &Path,
    text: &str,
    options: &DeckOptions,
) -> Result<ModelFile, InputError> {
    let src = TomlSource::new(path, text);
    let raw: raw::RawFile = src.parse()?;
    let ModelToml {
        title,
        model,
        unknown,
        warnings,
        notes,
        element_sets,
        catalogue,
    } = parse_model_toml(src, options, raw::SCENARIO_KEYS)?;
    let rigid = mbs::rigid_bodies(src, &raw)?;
    mbs::check_track(src, &raw)?;
    let connections = mbs::connections(src, &raw, &model, &rigid)?;
    let interface = interface::interface(src, &raw, &model)?;
    let simulation = match &raw.simulation {
        None => None,
        Some(sim) => Some(simulation::simulation(src, sim, &raw, &model, &rigid)?),
    };
    let study = cases::study(src, &raw)?;
    let frf = cases::frf(src, &raw)?;
    Ok(ModelFile {
        path: path.to_path_buf(),
        title,
        model,
        interface: interface.dofs,
        support: interface.support,
        force_groups: interface.force_groups,
        rigid_bodies: rigid.bodies,
        connections,
        track: raw.track,
        study,
        simulation,
        frf,
        unknown_keywords: unknown,
        warnings,
        notes,
        element_sets,
        catalogue,
    })
}
