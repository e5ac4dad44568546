//! Loading a component from any input flexbody reads, by file type:
//! a model file (`.toml`), an Abaqus/CalculiX deck (`.inp`), CalculiX's
//! matrix output (`job.sti` with `job.mas` and `job.dof` beside it), or
//! Matrix Market stiffness (`.mtx`, with the mass and DOF files given).
//! Every input becomes a [`Substructure`]; meshes also keep their model for
//! recovery of element quantities, which matrices alone cannot give.

use crate::fem::{Dof, Model, Substructure, SystemMatrices};
use crate::io::deck::{Catalogue, DeckOptions, UnknownKeywords};
use crate::io::InputError;
use crate::reduce::{Method, Reduction};
use crate::scenario::{read_model_file_with, ModelFile};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A component ready to reduce.
#[derive(Debug)]
pub struct Component {
    pub path: PathBuf,
    pub sub: Substructure,
    /// The mesh, when the input had one (not for matrices).
    pub model: Option<Model>,
    /// The model file, when the input was one (interface, MBS, study).
    pub file: Option<ModelFile>,
    /// Element sets of a deck (upper-case name -> element ids).
    pub element_sets: BTreeMap<String, Vec<usize>>,
    /// Materials and sections of a deck.
    pub catalogue: Catalogue,
    /// Warnings for the user, each naming the deck it is about (the input
    /// deck or a model file's `mesh`): `part.inp: ignored parameter ...`.
    pub warnings: Vec<String>,
    /// Notes for the user: the routine keywords a deck skipped, one line
    /// per deck ([`crate::io::deck::Deck::skipped_note`]).
    pub notes: Vec<String>,
    /// Unknown keywords of a deck (also one a model file names) that were
    /// skipped under [`DeckOptions::allow_unknown`]; show their
    /// [`UnknownKeywords::summary`].
    pub unknown_keywords: UnknownKeywords,
    /// Seconds spent reading the files and assembling K and M.
    pub timing: (f64, f64),
}

/// Extra files for matrix input.
#[derive(Clone, Debug, Default)]
pub struct MatrixFiles {
    /// Matrix Market mass matrix (with a `.mtx` stiffness).
    pub mass: Option<PathBuf>,
    /// DOF map: one `node dof` line per equation (with a `.mtx` stiffness).
    pub dofs: Option<PathBuf>,
    /// Node coordinates, one `node x y z` line per node
    /// ([`read_node_coordinates`](crate::io::coordinates::read_node_coordinates)),
    /// for CalculiX or Matrix Market matrices.
    pub coords: Option<PathBuf>,
}

/// Errors naming the input that is wrong.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error(transparent)]
    Input(#[from] InputError),
    #[error("{}: {cause}", .path.display())]
    Assembly {
        path: PathBuf,
        cause: crate::fem::FemError,
    },
    #[error("{}: unknown input type; expected .toml (model file), .inp (deck), .sti (CalculiX matrices) or .mtx (Matrix Market)", .0.display())]
    UnknownType(PathBuf),
    #[error("{}: Matrix Market input needs --mass M.mtx and --dofs DOFS.txt", .0.display())]
    MissingMatrixFiles(PathBuf),
    #[error("{}: --coords gives node coordinates to matrix input (.sti, .mtx); this model has its own mesh", .0.display())]
    CoordsWithMesh(PathBuf),
    #[error("interface '{name}' is neither a node set nor a node number; {sets}")]
    UnknownInterface { name: String, sets: String },
    #[error("interface node {0} has no DOFs")]
    InterfaceNodeWithoutDofs(u64),
}

/// Reads the component at `path`; a deck with an unknown keyword is
/// refused.
pub fn load(path: &Path, matrices: &MatrixFiles) -> Result<Component, LoadError> {
    load_with(path, matrices, &DeckOptions::default())
}

/// Reads the component at `path`, a deck (or a model file's deck) with
/// `options`.
pub fn load_with(
    path: &Path,
    matrices: &MatrixFiles,
    options: &DeckOptions,
) -> Result<Component, LoadError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let start = std::time::Instant::now();
    let read_time = std::cell::Cell::new(0.0);
    let assemble = |model: &Model| {
        read_time.set(start.elapsed().as_secs_f64());
        Substructure::from_model(model).map_err(|source| LoadError::Assembly {
            path: path.to_path_buf(),
            cause: source,
        })
    };
    let timing = || {
        let total = start.elapsed().as_secs_f64();
        (read_time.get(), total - read_time.get())
    };
    if files_with_mesh(&ext) && matrices.coords.is_some() {
        return Err(LoadError::CoordsWithMesh(path.to_path_buf()));
    }
    match ext.as_str() {
        "toml" => {
            let file = read_model_file_with(path, options)?;
            Ok(Component {
                path: path.to_path_buf(),
                sub: assemble(&file.model)?,
                model: Some(file.model.clone()),
                unknown_keywords: file.unknown_keywords.clone(),
                warnings: file.warnings.clone(),
                notes: file.notes.clone(),
                element_sets: file.element_sets.clone(),
                catalogue: file.catalogue.clone(),
                file: Some(file),
                timing: timing(),
            })
        }
        "inp" => {
            let deck = crate::io::deck::read_deck(path, options)?;
            let (warnings, notes) = (deck.warning_lines(), deck.skipped_note());
            Ok(Component {
                path: path.to_path_buf(),
                sub: assemble(&deck.model)?,
                model: Some(deck.model),
                file: None,
                warnings,
                notes: notes.into_iter().collect(),
                element_sets: deck.element_sets,
                catalogue: deck.catalogue,
                unknown_keywords: deck.unknown,
                timing: timing(),
            })
        }
        "sti" => {
            let m = crate::io::matrices::read_calculix_matrices(&path.with_extension(""))?;
            from_matrices(path, m, matrices, start)
        }
        "mtx" => {
            let (Some(mass), Some(dofs)) = (&matrices.mass, &matrices.dofs) else {
                return Err(LoadError::MissingMatrixFiles(path.to_path_buf()));
            };
            let m = crate::io::matrices::read_matrix_market(path, mass, dofs)?;
            from_matrices(path, m, matrices, start)
        }
        _ => Err(LoadError::UnknownType(path.to_path_buf())),
    }
}

/// Whether an input of extension `ext` is a mesh (a model file or a deck).
fn files_with_mesh(ext: &str) -> bool {
    matches!(ext, "toml" | "inp")
}

/// The component of matrices `m` read from `path`, with the node
/// coordinates of `files.coords` if given.
fn from_matrices(
    path: &Path,
    m: crate::io::matrices::MatrixModel,
    files: &MatrixFiles,
    start: std::time::Instant,
) -> Result<Component, LoadError> {
    let coordinates = match &files.coords {
        Some(coords) => crate::io::coordinates::read_node_coordinates(coords, &m.dof_map)?,
        None => Default::default(),
    };
    let seconds = start.elapsed().as_secs_f64();
    let matrices = SystemMatrices {
        stiffness: m.stiffness,
        mass: m.mass,
        damping: None,
    };
    let sub = Substructure::from_matrices(m.dof_map, matrices, coordinates);
    Ok(Component::of_matrices(path.to_path_buf(), sub, seconds))
}

impl Component {
    /// A component of matrices alone (no mesh, no model file), read from
    /// `path` in `seconds`.
    pub fn of_matrices(path: PathBuf, sub: Substructure, seconds: f64) -> Self {
        Component {
            path,
            sub,
            model: None,
            file: None,
            element_sets: BTreeMap::new(),
            catalogue: Catalogue::default(),
            warnings: vec![],
            notes: vec![],
            unknown_keywords: UnknownKeywords::default(),
            timing: (seconds, 0.0),
        }
    }

    /// `K` and `M` (and the damping), dropping the mesh and everything else.
    pub fn into_matrices(self) -> SystemMatrices {
        self.sub.matrices
    }

    /// Interface DOFs from a comma-separated list of node sets and node
    /// numbers (all free DOFs of each node), or the default interface
    /// ([`Component::default_interface`]) when `spec` is `None`.
    pub fn interface(&self, spec: Option<&str>) -> Result<Vec<Dof>, LoadError> {
        let Some(spec) = spec else {
            return Ok(self.default_interface().map(|d| d.dofs).unwrap_or_default());
        };
        let sets: BTreeMap<String, Vec<u64>> = self
            .model
            .as_ref()
            .map(|m| {
                m.node_sets()
                    .iter()
                    .map(|(k, v)| (k.to_ascii_uppercase(), v.clone()))
                    .collect()
            })
            .unwrap_or_default();
        let mut dofs = Vec::new();
        for token in spec.split(',').map(str::trim).filter(|t| !t.is_empty()) {
            let nodes = match sets.get(&token.to_ascii_uppercase()) {
                Some(n) => n.clone(),
                None => vec![token
                    .parse::<u64>()
                    .map_err(|_| LoadError::UnknownInterface {
                        name: token.to_string(),
                        sets: self.node_set_list(),
                    })?],
            };
            for node in nodes {
                let kinds = self.sub.dof_map.node_dofs(node);
                if kinds.is_empty() {
                    return Err(LoadError::InterfaceNodeWithoutDofs(node));
                }
                for (kind, _) in kinds {
                    let d = Dof::new(node, kind);
                    if !dofs.contains(&d) {
                        dofs.push(d);
                    }
                }
            }
        }
        Ok(dofs)
    }
}

/// The interface a command takes when none is given, and where it comes
/// from, for the command to say.
#[derive(Clone, Debug, PartialEq)]
pub struct DefaultInterface {
    pub dofs: Vec<Dof>,
    /// E.g. "the model file's `[interface]` table" or "the reference nodes
    /// of the deck's couplings (9001, 9002), all their DOFs".
    pub source: String,
}

impl Component {
    /// The interface without `--interface`: the model file's own (its
    /// `[interface]` table, or the DOFs its connections act on); else the
    /// reference nodes of the model's couplings, every free DOF of each;
    /// `None` where there is neither.
    pub fn default_interface(&self) -> Option<DefaultInterface> {
        if let Some(file) = self.file.as_ref().filter(|f| !f.interface.is_empty()) {
            return Some(DefaultInterface {
                dofs: file.interface.clone(),
                source:
                    "the model file's interface ([interface], or the DOFs its connections act on)"
                        .to_string(),
            });
        }
        let couplings = self.model.as_ref()?.couplings();
        let mut nodes: Vec<u64> = Vec::new();
        for c in couplings {
            if !nodes.contains(&c.point) {
                nodes.push(c.point);
            }
        }
        let dofs: Vec<Dof> = nodes
            .iter()
            .flat_map(|&n| {
                self.sub
                    .dof_map
                    .node_dofs(n)
                    .into_iter()
                    .map(move |(k, _)| Dof::new(n, k))
            })
            .collect();
        if dofs.is_empty() {
            return None;
        }
        let list: Vec<String> = nodes.iter().map(u64::to_string).collect();
        Some(DefaultInterface {
            dofs,
            source: format!(
                "the reference nodes of the couplings (node {}), all their DOFs",
                list.join(", ")
            ),
        })
    }

    /// "node sets here: A (4 nodes), B (2 nodes)", or that there are none.
    pub fn node_set_list(&self) -> String {
        let sets = self.model.as_ref().map(|m| m.node_sets());
        match sets.filter(|s| !s.is_empty()) {
            None => "the model has no node sets".to_string(),
            Some(sets) => {
                let names: Vec<String> = sets
                    .iter()
                    .map(|(name, nodes)| format!("{name} ({} nodes)", nodes.len()))
                    .collect();
                format!("node sets here: {}", names.join(", "))
            }
        }
    }
}

/// The reduction of `method` with `modes` eigenmodes on `interface` that
/// the model file `file` sets up: its support for inertia-relief modes, its
/// elastic supports, and its force groups where the method takes them
/// ([`Method::takes_force_groups`]; the others reduce on the interface
/// DOFs).
pub fn file_reduction(
    file: &ModelFile,
    method: Method,
    modes: usize,
    interface: Vec<Dof>,
) -> Reduction {
    let mut spec = Reduction::new(method, modes, interface);
    spec.local_axes = file.model.local_axes().clone();
    spec.support = file.support.clone();
    spec.springs = file.ground_springs();
    if method.takes_force_groups() {
        spec.force_groups = file.force_groups.clone();
    }
    spec
}
