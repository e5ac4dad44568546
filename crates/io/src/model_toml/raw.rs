//! The model sections of a TOML model file as written, with source spans.
//! Checked and turned into a [`flexbody_fem::Model`] by [`super::build`].

use flexbody_fem::{BeamTheory, CouplingKind, DofKind, MpcKind, Rayleigh, SectionShape};
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

/// The top-level keys that describe the FE model ([`super::MODEL_KEYS`]).
/// Other top-level tables (interface, MBS, study) are the caller's: they
/// are skipped here, after [`super::parse_model_toml`] has refused keys
/// that neither the caller nor this struct knows.
#[derive(Deserialize)]
pub(crate) struct RawModel {
    pub title: Option<String>,
    /// An Abaqus/CalculiX deck with the FE model (relative to this file).
    pub mesh: Option<Spanned<String>>,
    #[serde(default)]
    pub coupling: Vec<Spanned<RawCoupling>>,
    #[serde(default)]
    pub material: Vec<RawMaterial>,
    #[serde(default)]
    pub section: Vec<Spanned<RawSection>>,
    #[serde(default)]
    pub nodes: Vec<Spanned<(u64, f64, f64, f64)>>,
    #[serde(default)]
    pub beam_line: Vec<Spanned<RawBeamLine>>,
    #[serde(default)]
    pub element: Vec<Spanned<RawElement>>,
    #[serde(default)]
    pub sets: BTreeMap<String, Spanned<Vec<u64>>>,
    #[serde(default)]
    pub boundary: Vec<Spanned<RawBoundary>>,
    #[serde(default)]
    pub equation: Vec<Spanned<RawEquation>>,
    #[serde(default)]
    pub mpc: Vec<Spanned<RawMpc>>,
    #[serde(default)]
    pub tie: Vec<Spanned<RawTie>>,
    pub damping: Option<Rayleigh>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMaterial {
    pub name: Spanned<String>,
    pub youngs_modulus: Spanned<f64>,
    #[serde(default = "default_poisson")]
    pub poisson_ratio: Spanned<f64>,
    pub density: Spanned<f64>,
}

fn default_poisson() -> Spanned<f64> {
    Spanned::new(0..0, 0.3)
}

/// A `[[section]]`: its name and its shape's keys, none besides them (a
/// misspelt `shear_area_y` is an error, not a default).
pub(crate) struct RawSection {
    pub name: String,
    pub shape: SectionShape,
}

impl<'de> Deserialize<'de> for RawSection {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let mut table = toml::Table::deserialize(d)?;
        let name = match table.remove("name") {
            Some(toml::Value::String(name)) => name,
            Some(_) => return Err(D::Error::custom("section name must be a string")),
            None => return Err(D::Error::missing_field("name")),
        };
        // The shape's own fields only: `SectionShape` denies the others.
        // Its error (an unknown key or shape) is located and named by
        // `TomlSource::parse`.
        let shape = SectionShape::deserialize(toml::Value::Table(table))
            .map_err(|e| D::Error::custom(e.message()))?;
        Ok(RawSection { name, shape })
    }
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub(crate) enum BeamKind {
    PlanarBeam,
    Beam,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawBeamLine {
    pub element: BeamKind,
    #[serde(default)]
    pub theory: BeamTheory,
    #[serde(default)]
    pub rotary_inertia: Option<bool>,
    /// Start point (m); or the position of `start_node`.
    #[serde(default)]
    pub from: Option<[f64; 3]>,
    /// End point (m); or the position of `end_node`.
    #[serde(default)]
    pub to: Option<[f64; 3]>,
    /// An existing node the line starts at (a joint).
    #[serde(default)]
    pub start_node: Option<u64>,
    /// An existing node the line ends at (a joint).
    #[serde(default)]
    pub end_node: Option<u64>,
    pub elements: usize,
    /// Point `i` of the line is node `first_node + i` unless it is an
    /// existing node; needed when the line makes a new node.
    #[serde(default)]
    pub first_node: Option<u64>,
    /// Whether a point of the line that coincides with an existing node is
    /// that node (default); `false` keeps coincident nodes apart (a hinge
    /// of springs).
    #[serde(default = "default_share")]
    pub share_nodes: bool,
    #[serde(default)]
    pub first_element: Option<usize>,
    pub material: Spanned<String>,
    pub section: Spanned<String>,
    #[serde(default)]
    pub orientation: Option<[f64; 3]>,
    #[serde(default)]
    pub set: Option<String>,
}

fn default_share() -> bool {
    true
}

/// One DOF as a TOML table: `{ node = 7, dof = "uz" }`.
#[derive(Deserialize, Clone, Copy, Debug, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DofEntry {
    pub node: u64,
    pub dof: DofKind,
}

impl DofEntry {
    pub fn dof(self) -> flexbody_fem::Dof {
        flexbody_fem::Dof::new(self.node, self.dof)
    }
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case", deny_unknown_fields)]
pub(crate) enum RawElement {
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
    /// An S3 or S4 shell: three or four nodes, a material and a thickness
    /// (m), the nodes `offset` thicknesses from the mid-surface (Abaqus'
    /// `OFFSET=`, default 0).
    Shell {
        id: usize,
        nodes: Vec<u64>,
        material: String,
        thickness: f64,
        #[serde(default)]
        offset: f64,
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
        dof: DofEntry,
        #[serde(default)]
        to: Option<DofEntry>,
        stiffness: f64,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawBoundary {
    pub node: u64,
    pub dofs: Vec<DofKind>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawCoupling {
    pub name: String,
    pub kind: CouplingKind,
    /// The interface point: a new node with 6 DOFs.
    pub point: u64,
    /// Its position (m); default: the centroid of the set.
    #[serde(default)]
    pub position: Option<[f64; 3]>,
    #[serde(default)]
    pub set: Option<String>,
    #[serde(default)]
    pub nodes: Option<Vec<u64>>,
    #[serde(default)]
    pub weights: Option<Vec<f64>>,
}

/// An `[[equation]]`: `sum_k c_k u_k = 0`, the first term's DOF dependent
/// (eliminated), as `*EQUATION`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawEquation {
    #[serde(default)]
    pub name: Option<String>,
    pub terms: Vec<Spanned<RawTerm>>,
}

/// One term of an `[[equation]]`: `{ node = 7, dof = "uz", coefficient = 1.0 }`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTerm {
    pub node: u64,
    pub dof: DofKind,
    pub coefficient: f64,
}

/// An `[[mpc]]`: CalculiX's linearised `*MPC` of `kind` on `nodes` (the
/// defining nodes first, as [`MpcKind`] says).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMpc {
    #[serde(default)]
    pub name: Option<String>,
    pub kind: MpcKind,
    pub nodes: Vec<u64>,
}

/// A `[[tie]]`: slave nodes (`set` or `nodes`) held on master solid faces
/// (`master`, an element surface of the deck, and/or the exterior faces of
/// the deck's element set `master_elements`), as `*TIE`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTie {
    pub name: String,
    #[serde(default)]
    pub set: Option<String>,
    #[serde(default)]
    pub nodes: Option<Vec<u64>>,
    #[serde(default)]
    pub master: Option<String>,
    #[serde(default)]
    pub master_elements: Option<String>,
    /// Largest distance (m) of a slave node from the master surface;
    /// default: [`flexbody_fem::Tie`]'s.
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// Move the slave nodes onto the master surface (CalculiX's ADJUST).
    #[serde(default = "default_adjust")]
    pub adjust: bool,
}

fn default_adjust() -> bool {
    true
}

#[cfg(test)]
mod tests {
    use super::RawModel;
    use crate::model_toml::MODEL_KEYS;
    use crate::TomlSource;
    use std::path::Path;

    #[test]
    fn every_model_key_is_read_and_no_other() {
        // A date is no valid value of any model key: each key is refused
        // with it, so each is read by `RawModel` (not skipped).
        for key in MODEL_KEYS {
            let text = format!("{key} = 1979-05-27\n");
            let src = TomlSource::new(Path::new("m.toml"), &text);
            assert!(src.parse::<RawModel>().is_err(), "`{key}` is skipped");
        }
        // Any other key is skipped by `RawModel`: the caller's, or refused
        // by `parse_model_toml` before.
        let src = TomlSource::new(Path::new("m.toml"), "interface = 1979-05-27\n");
        assert!(src.parse::<RawModel>().is_ok());
    }
}
