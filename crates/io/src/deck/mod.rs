//! Abaqus/CalculiX input decks (`.inp`) read into a [`flexbody_fem::Model`].
//!
//! Syntax: keyword lines start with `*` (case-insensitive; spaces in the
//! keyword ignored, so `*SOLID SECTION` = `*SOLIDSECTION`), parameters are
//! `KEY=VALUE` separated by commas; `**` lines are comments; blank lines are
//! skipped; data lines are comma-separated and may end with a comma. An
//! element line ending with a comma continues on the next line while nodes
//! are missing (C3D20). A keyword line ending with a comma continues on the
//! next line if that starts with `KEY=`. `*INCLUDE, INPUT=file` is read in
//! place, relative to the folder of the file that includes it. Set and
//! material names are compared in upper case. Units: SI assumed (nothing is
//! converted).
//!
//! What each keyword does:
//!
//! | keyword | reading |
//! | --- | --- |
//! | `*NODE` (`NSET=`) | `id, x, y, z`; missing coordinates are 0 |
//! | `*ELEMENT, TYPE=, ELSET=` | the types of [`ELEMENT_TYPES`](flexbody_fem::element::ELEMENT_TYPES): C3D8, C3D8I, C3D20, C3D20R, C3D10, C3D4, C3D6, C3D15 (solids), S3, S4, S6 (shells), B31 (Timoshenko beam), MASS, SPRINGA, SPRING1, SPRING2, DASHPOTA, DASHPOT1, DASHPOT2; any other type is an error |
//! | `*NSET`, `*ELSET` | ids, names of sets defined before, or `GENERATE` (`first, last[, step]`) |
//! | `*MATERIAL, NAME=` + `*ELASTIC` + `*DENSITY` | `*ELASTIC, TYPE=` ISO (`E, nu`), ORTHO, ENGINEERING CONSTANTS, ANISO (solids only; see `elasticity.rs`); several records make a temperature table, read at the uniform `*INITIAL CONDITIONS, TYPE=TEMPERATURE` (linear, constant beyond the ends; without one the first record, as CalculiX); a material used without `*DENSITY` is an error (the mass matrix needs it); a `C` that is not positive definite is an error at its line |
//! | `*DAMPING, ALPHA=, BETA=` (in a `*MATERIAL`) | Rayleigh damping of the material, as Abaqus reads it: each of its elements adds `alpha M_e + beta K_e` to D; materials damped differently get a warning (CalculiX 2.20 applies the `*DAMPING` read last to the whole model); `STRUCTURAL=` (hysteretic, a complex stiffness), `COMPOSITE=`, negative values and a data line are errors |
//! | `*ORIENTATION, NAME=, SYSTEM=R or C` | points a, b; optional `axis, angle` line (rectangular only); turns anisotropic materials of a `*SOLID SECTION, ORIENTATION=` (cylindrical: at each integration point) |
//! | `*SOLID SECTION, ELSET=, MATERIAL=[, ORIENTATION=]` | the data line is ignored; every solid needs one; beams refuse anisotropic materials |
//! | `*SHELL SECTION, ELSET=, MATERIAL=[, OFFSET=][, ORIENTATION=]` | the thickness (m) on the data line (a second value, section points, does not apply); OFFSET= a number of thicknesses, SPOS or SNEG; COMPOSITE, NODAL THICKNESS, a second data line and anisotropic materials are refused |
//! | `*BEAM SECTION, ELSET=, MATERIAL=, SECTION=` | RECT `a, b`; CIRC `r`; PIPE `r, t` (outer radius, wall); BOX `a, b, t1..t4` (equal walls only); second line n1 = local y, default `(0, 0, -1)`; a along local 1 (y), b along local 2 (z) |
//! | `*MASS, ELSET=` | mass (kg) of MASS elements |
//! | `*SPRING, ELSET=` | SPRINGA: stiffness; SPRING1: DOF, then stiffness; SPRING2: two DOFs, then stiffness |
//! | `*DASHPOT, ELSET=` | DASHPOTA: (a blank line, then) `c, frequency` with c in N s/m along the line between the nodes; DASHPOT1: DOF, then `c`; DASHPOT2: two DOFs, then `c`; into D only. A dashpot creates no DOFs: each end needs DOFs from other elements or couplings, or a `*BOUNDARY` (a grounded end). Negative `c`, a non-zero frequency (frequency-dependent), several lines (temperature tables), `NONLINEAR` and `ORIENTATION` are errors |
//! | `*MODAL DAMPING, RAYLEIGH` (in a step) | the model's Rayleigh damping `D = alpha M + beta K` from the CalculiX data line `first mode, last mode, alpha, beta` (the modes are not used; a line without the third and fourth field is an error, as CalculiX would read alpha = beta = 0); with material `*DAMPING` too, or a second one with other values, an error; damping ratios per mode range (no `RAYLEIGH`) are an error: they are no matrix of the FE model |
//! | `*SURFACE, NAME=, TYPE=NODE` + `*COUPLING, REF NODE=, SURFACE=` + `*KINEMATIC` (DOFs 1-3 or 1-6) or `*DISTRIBUTING` | an interface point (RBE2 or RBE3) coupled to the surface's nodes; element-based surfaces (`TYPE=ELEMENT`, the default: `element or ELSET, S1..S6`) serve `*TIE`; a MASS element or `*BOUNDARY` may sit on the reference node |
//! | `*TIE, NAME=[, POSITION TOLERANCE=][, ADJUST=YES/NO]` | `slave surface, master surface`: each slave node (node or element surface) follows the master solid faces' interpolation at its projection ([`flexbody_fem::Tie`]); ADJUST (the default, as CalculiX) moves slave nodes onto the master surface; the default tolerance is 2.5 % of the mean master face size; slave nodes beyond it are named and refused |
//! | `*BOUNDARY` | `node or NSET, first[, last[, 0]]` or ENCASTRE, PINNED, XSYMM, ...; in the model data and in steps up to the first frequency step (they persist, as in CalculiX); a non-zero value is an error; a DOF no element gives the node (rotations of solid nodes) is dropped with one warning; a coupling's reference node has all six |
//! | `*EQUATION` | `count`, then `node, DOF, coefficient` triples (up to four a line); the first term's DOF is eliminated, exactly ([`flexbody_fem::Equation`]); nodes are numbers or one-node sets |
//! | `*MPC` | PLANE (first three nodes the plane, the others held in it), STRAIGHT (first two the line), BEAM (constant distance), linearised as CalculiX's ([`flexbody_fem::MpcKind`]); one MPC a card, node sets allowed |
//! | `*RIGID BODY, REF NODE=, NSET= or ELSET=[, ROT NODE=]` | a rigid coupling of the reference node (6 DOFs) to the members; a `*BOUNDARY` on the ROT NODE's translations fixes the reference node's rotations |
//! | `*DISTRIBUTING COUPLING, ELSET=` + a DCOUP3D element | a distributing coupling (RBE3) of the element's node to the listed nodes or node sets with their weights |
//! | steps | the model is the one of the first `*FREQUENCY` step: `*BOUNDARY` and loads of later steps are skipped with one warning; a `*STEP, PERTURBATION` frequency step after a step with loads (`*CLOAD`, `*DLOAD`, `*DSLOAD`, `*TEMPERATURE`) is refused: CalculiX adds the preload's stress stiffening there |
//! | `*STEP`, `*END STEP`, `*STATIC`, `*FREQUENCY`, outputs, loads, `*HEADING`, `*AMPLITUDE`, `*TEMPERATURE` (a frequency step uses the initial temperature), `*PLASTIC`, `*EXPANSION`, `*CONDUCTIVITY`, ... | skipped, listed in [`Deck::skipped`] (one note on the command line): they do not change K, M or D of the linear model (`*FREQUENCY` ignores damping, as in CalculiX) |
//! | `*CONTACT PAIR, INTERACTION=, TYPE=NODE TO SURFACE or SURFACE TO SURFACE[, ADJUST=]` + `*SURFACE INTERACTION, NAME=` + `*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=TIED` | `slave surface, master surface` lines: tied contact, read as a `*TIE` (exact, where CalculiX uses penalty springs); ADJUST=distance moves slave nodes within it onto the master; any other behaviour (nonlinear contact) is refused |
//! | `*TRANSFORM, NSET=, TYPE=R or C` | points a, b as in `*ORIENTATION`: `*BOUNDARY` and `*EQUATION` name local DOFs at the set's nodes (see `transform.rs`), and so do a reduction's interface DOFs there (`Model::local_axes`); the last `*TRANSFORM` naming a node holds |
//! | `*KINEMATIC COUPLING`, `*MATRIX ASSEMBLE`, `*MATRIX INPUT`, `*CONTACT`, `*SHELL SECTION`, `*MEMBRANE SECTION`, `*BEAM GENERAL SECTION`, `*NORMAL`, `*ROTARY INERTIA`, `*HYPERELASTIC`, `*USER MATERIAL`, `*NGEN`, ... | refused: ignoring them would change K or M |
//! | unknown keywords | refused, naming the file, the line and the nearest known keyword when one is close (`*BOUNDRY`: did you mean `*BOUNDARY`?); with [`DeckOptions::allow_unknown`] skipped and collected in [`Deck::unknown`] |
//!
//! Errors name the file and line that is wrong (an included file's own line)
//! and the element, node, set or material. The model is checked as a whole
//! after reading: [`Model::new`](flexbody_fem::Model::new) (undefined nodes)
//! and [`Element::validate`](flexbody_fem::Element::validate) (zero length,
//! beam orientation, inverted or flat solids), each error at its element's
//! line.

mod build;
mod cards;
mod catalogue;
mod constraints;
mod contact;
mod elasticity;
mod keywords;
mod known;
mod properties;
mod steps;
mod temperature;
#[cfg(test)]
mod tests;
mod transform;
mod unknown;

pub use catalogue::{Catalogue, MaterialEntry, SectionEntry};
pub use unknown::{DeckOptions, UnknownKeyword, UnknownKeywords};

use crate::InputError;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A model read from an Abaqus/CalculiX input deck.
#[derive(Clone, Debug)]
pub struct Deck {
    pub path: PathBuf,
    /// Nodes, elements (with their dashpots and material damping), node
    /// sets (upper-case names), fixed DOFs, couplings and the model's
    /// Rayleigh damping of `*MODAL DAMPING, RAYLEIGH`.
    pub model: flexbody_fem::Model,
    /// Element sets (ELSET name -> element ids), upper-case names.
    pub element_sets: BTreeMap<String, Vec<usize>>,
    /// Element-based surfaces (`*SURFACE, TYPE=ELEMENT`) as written, by
    /// upper-case name, for the master surface of a model file's tie.
    pub element_surfaces: BTreeMap<String, Vec<SurfaceFaces>>,
    /// Materials and sections by name.
    pub catalogue: Catalogue,
    /// What was ignored or read otherwise than named, and may matter:
    /// ignored parameters, fixed DOFs no element has, steps after the
    /// frequency step, element names read as other types, node numbers
    /// past those a type uses.
    pub warnings: Vec<String>,
    /// Keywords skipped because they do not change the linear K, M or D,
    /// with the line of first use: `"*STEP (line 40)"`.
    pub skipped: Vec<String>,
    /// Unknown keywords skipped (only under
    /// [`DeckOptions::allow_unknown`]; otherwise they are errors).
    pub unknown: UnknownKeywords,
}

impl Deck {
    /// The warnings for the user, each naming the deck:
    /// `part.inp: *BOUNDARY (line 36): 12 fixed DOF(s) ignored ...`.
    pub fn warning_lines(&self) -> Vec<String> {
        self.warnings
            .iter()
            .map(|w| format!("{}: {w}", self.path.display()))
            .collect()
    }

    /// The one note listing the routine keywords skipped, if any:
    /// `part.inp: skipped, as they do not change the linear K, M or D:
    /// *STEP (line 40), *FREQUENCY (line 41)`.
    pub fn skipped_note(&self) -> Option<String> {
        (!self.skipped.is_empty()).then(|| {
            format!(
                "{}: skipped, as they do not change the linear K, M or D: {}",
                self.path.display(),
                self.skipped.join(", ")
            )
        })
    }
}

/// One line of an element-based `*SURFACE`: the faces `face` (S1 is 1) of
/// an element or of every element of an element set.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SurfaceFaces {
    /// An element number, or an element set's upper-case name.
    pub elements: String,
    /// The face number, 1 to 6, in Abaqus/CalculiX numbering
    /// ([`flexbody_fem::tie::solid_face`]).
    pub face: usize,
}

/// Reads and checks a deck file.
pub fn read_deck(path: &Path, options: &DeckOptions) -> Result<Deck, InputError> {
    let bytes = crate::text::read_bytes(path)?;
    parse_deck(path, &String::from_utf8_lossy(&bytes), options)
}

/// Parses and checks the text of a deck; `path` names it in errors and
/// `*INCLUDE` files are found relative to its folder.
pub fn parse_deck(path: &Path, text: &str, options: &DeckOptions) -> Result<Deck, InputError> {
    let (files, cards) = cards::read_cards(path, text)?;
    let mut reader = keywords::Reader::new(&files, *options);
    reader.read(&cards)?;
    let unknown = std::mem::take(&mut reader.unknown);
    let catalogue = Catalogue::of(&reader);
    let skipped = std::mem::take(&mut reader.skipped);
    let element_surfaces = reader
        .element_surfaces
        .iter()
        .map(|(surface, lines)| {
            let faces = lines
                .iter()
                .map(|(elements, face, _)| SurfaceFaces {
                    elements: cards::name(elements),
                    face: *face,
                })
                .collect();
            (surface.clone(), faces)
        })
        .collect();
    let built = build::build(reader)?;
    Ok(Deck {
        path: path.to_path_buf(),
        model: built.model,
        element_sets: built.element_sets,
        element_surfaces,
        catalogue,
        warnings: built.warnings,
        skipped,
        unknown,
    })
}
