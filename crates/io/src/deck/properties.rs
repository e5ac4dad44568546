//! Materials (`*MATERIAL`, `*ELASTIC`, `*DENSITY`, `*DAMPING`), the
//! keywords that give elements their properties (`*SOLID SECTION`, `*SHELL
//! SECTION`, `*BEAM SECTION`, `*MASS`, `*SPRING`, `*DASHPOT`), and the model's Rayleigh
//! damping (`*MODAL DAMPING, RAYLEIGH`), as read; they are assigned to
//! elements in `build.rs`.
//!
//! Beam sections follow CalculiX/Abaqus: local 1 is the n1 direction of the
//! second data line (default `(0, 0, -1)`), local 2 is `t x n1`. flexbody's
//! local y is n1 and local z is n2, so the first dimension (`a` of RECT and
//! BOX) is the width along y and the second (`b`) the height along z.

use super::cards::{Card, DataLine, Files, Loc};
use super::elasticity::{ElasticKind, Table};
use super::keywords::Reader;
use crate::InputError;
use flexbody_fem::element::{ElementType, SectionKind};
use flexbody_fem::section::SectionConstants;
use flexbody_fem::{DofKind, Rayleigh, SectionShape};

/// Default n1 direction of a beam section (CalculiX and Abaqus).
const DEFAULT_N1: [f64; 3] = [0.0, 0.0, -1.0];

/// A `*MATERIAL` block: elasticity (its kind and table) and density (a
/// table), with the cards that gave them.
#[derive(Clone, Debug)]
pub(super) struct RawMaterial {
    pub name: String,
    pub loc: Loc,
    pub elastic: Option<(ElasticKind, Table, Loc)>,
    pub density: Option<(Table, Loc)>,
    /// Rayleigh damping of `*DAMPING, ALPHA=, BETA=`.
    pub damping: Option<(Rayleigh, Loc)>,
}

/// What a property keyword gives its elements.
#[derive(Clone, Debug)]
pub(super) enum SectionData {
    Solid,
    Shell {
        /// Thickness (m).
        thickness: f64,
        /// Abaqus' `OFFSET=`: where the nodes lie from the mid-surface along
        /// the normal, in thicknesses.
        offset: f64,
    },
    Beam {
        constants: SectionConstants,
        /// Local 1 direction (flexbody's local y).
        n1: [f64; 3],
    },
    Mass(f64),
    /// Data lines of `*SPRING`: their layout depends on the spring type.
    Spring(Vec<DataLine>),
    /// Data lines of `*DASHPOT`: their layout depends on the dashpot type.
    Dashpot(Vec<DataLine>),
}

impl SectionData {
    /// True if elements of type `t` take their properties from this.
    pub fn accepts(&self, t: &ElementType) -> bool {
        matches!(
            (self, t.section),
            (SectionData::Solid, SectionKind::Solid)
                | (SectionData::Shell { .. }, SectionKind::Shell)
                | (SectionData::Beam { .. }, SectionKind::Beam)
                | (SectionData::Mass(_), SectionKind::Mass)
                | (SectionData::Spring(_), SectionKind::Spring { .. })
                | (SectionData::Dashpot(_), SectionKind::Dashpot { .. })
        )
    }
}

/// A property keyword and the element set it applies to.
#[derive(Clone, Debug)]
pub(super) struct RawSection {
    /// `"*SOLID SECTION"` etc., for messages.
    pub keyword: String,
    pub elset: String,
    pub material: Option<String>,
    /// `ORIENTATION=` of a `*SOLID SECTION`.
    pub orientation: Option<String>,
    pub data: SectionData,
    pub loc: Loc,
}

/// A spring's or dashpot's DOFs (none for SPRINGA and DASHPOTA) and its
/// stiffness (N/m) or damping coefficient (N s/m).
#[derive(Copy, Clone, Debug)]
pub(super) struct DiscreteProperties {
    pub first: Option<DofKind>,
    pub second: Option<DofKind>,
    pub value: f64,
}

impl Reader<'_> {
    pub(super) fn material(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["NAME"]);
        let name = card.require_name(self.files, "NAME")?;
        if let Some(m) = self.materials.iter().find(|m| m.name == name) {
            return Err(self.files.error(
                card.loc,
                format!(
                    "material '{name}' is defined twice (first on {})",
                    self.files.describe(m.loc)
                ),
            ));
        }
        self.materials.push(RawMaterial {
            name,
            loc: card.loc,
            elastic: None,
            density: None,
            damping: None,
        });
        self.current_material = Some(self.materials.len() - 1);
        Ok(())
    }

    /// The material a material option belongs to.
    fn material_of(&self, card: &Card) -> Result<usize, InputError> {
        self.current_material.ok_or_else(|| {
            self.files.error(
                card.loc,
                format!("{} must follow a *MATERIAL line", card.display),
            )
        })
    }

    pub(super) fn elastic(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["TYPE"]);
        let t = card.value("TYPE").unwrap_or("ISO");
        let kind = ElasticKind::parse(t).ok_or_else(|| {
            self.files.error(
                card.loc,
                format!(
                    "*ELASTIC, TYPE={t}: not supported (supported: ISO, ORTHO, \
                     ENGINEERING CONSTANTS, ANISO)"
                ),
            )
        })?;
        let m = self.material_of(card)?;
        let name = self.materials[m].name.clone();
        let what = format!("*ELASTIC, TYPE={} of material '{name}'", kind.name());
        let table = Table::read(self.files, card, kind.constants(), kind.lines(), &what)?;
        if self.materials[m].elastic.is_some() {
            return Err(self.files.error(
                card.loc,
                format!("material '{name}' has two *ELASTIC cards"),
            ));
        }
        self.materials[m].elastic = Some((kind, table, card.loc));
        Ok(())
    }

    pub(super) fn density(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &[]);
        let m = self.material_of(card)?;
        let name = self.materials[m].name.clone();
        let what = format!("*DENSITY of material '{name}'");
        let table = Table::read(self.files, card, 1, 1, &what)?;
        if self.materials[m].density.is_some() {
            return Err(self.files.error(
                card.loc,
                format!("material '{name}' has two *DENSITY cards"),
            ));
        }
        self.materials[m].density = Some((table, card.loc));
        Ok(())
    }

    pub(super) fn orientation(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["NAME", "SYSTEM"]);
        let (name, o) = super::elasticity::orientation(self.files, card)?;
        if let Some((_, _, first)) = self.orientations.iter().find(|(n, _, _)| *n == name) {
            return Err(self.files.error(
                card.loc,
                format!(
                    "orientation '{name}' is defined twice (first on {})",
                    self.files.describe(*first)
                ),
            ));
        }
        self.orientations.push((name, o, card.loc));
        Ok(())
    }

    /// `*DAMPING, ALPHA=, BETA=` (Abaqus material Rayleigh damping, no
    /// data line). `STRUCTURAL=` (hysteretic damping, CalculiX's form) and
    /// `COMPOSITE=` are refused: flexbody's D is viscous.
    pub(super) fn damping(&mut self, card: &Card) -> Result<(), InputError> {
        let files = self.files;
        if card.has("STRUCTURAL") {
            return Err(files.error(
                card.loc,
                "*DAMPING, STRUCTURAL=: structural (hysteretic) damping is a complex \
                 stiffness, which flexbody's viscous damping matrix D cannot hold; give \
                 viscous Rayleigh damping with *DAMPING, ALPHA=..., BETA=... (for a loss \
                 factor g near the frequency f: BETA = g / (2 pi f))",
            ));
        }
        if card.has("COMPOSITE") {
            return Err(files.error(
                card.loc,
                "*DAMPING, COMPOSITE=: composite modal damping is not supported \
                 (give ALPHA= and BETA=)",
            ));
        }
        self.check_params(card, &["ALPHA", "BETA"]);
        let m = self
            .current_material
            .ok_or_else(|| files.error(card.loc, "*DAMPING must follow a *MATERIAL line"))?;
        if let Some(line) = card.data.first() {
            return Err(files.error(
                line.loc,
                "*DAMPING takes no data line (give ALPHA= and BETA= on the keyword line)",
            ));
        }
        let name = self.materials[m].name.clone();
        let coefficient = |key: &str| -> Result<f64, InputError> {
            let Some(v) = card.value(key) else {
                return Ok(0.0);
            };
            let what = format!("*DAMPING of material '{name}': {key}");
            let x = super::cards::parse_float(v).ok_or_else(|| {
                files.error(
                    card.loc,
                    format!(
                        "{what} should be a number, got '{v}'",
                        v = crate::text::excerpt(v)
                    ),
                )
            })?;
            flexbody_fem::require_non_negative(what, x)
                .map_err(|e| files.error(card.loc, e.to_string()))
        };
        let (alpha, beta) = (coefficient("ALPHA")?, coefficient("BETA")?);
        if !card.has("ALPHA") && !card.has("BETA") {
            return Err(files.error(
                card.loc,
                format!("*DAMPING of material '{name}' gives neither ALPHA= nor BETA="),
            ));
        }
        if let Some((_, first)) = self.materials[m].damping {
            return Err(files.error(
                card.loc,
                format!(
                    "material '{name}' has two *DAMPING cards (first on {})",
                    files.describe(first)
                ),
            ));
        }
        self.materials[m].damping = Some((Rayleigh { alpha, beta }, card.loc));
        Ok(())
    }

    /// `*MODAL DAMPING, RAYLEIGH` (CalculiX, in a step): the model's
    /// Rayleigh damping `D = alpha M + beta K` from the data line `first
    /// mode, last mode, alpha, beta` (the modes are not used). Damping
    /// ratios per mode range (without `RAYLEIGH`) are refused: they are not
    /// a damping matrix of the FE model.
    pub(super) fn modal_damping(&mut self, card: &Card) -> Result<(), InputError> {
        let files = self.files;
        if !card.has("RAYLEIGH") {
            return Err(files.error(
                card.loc,
                "*MODAL DAMPING with damping ratios per mode range is not supported: the \
                 ratios belong to the modes of the full model, not to a damping matrix D \
                 that a reduced body keeps; give *MODAL DAMPING, RAYLEIGH (alpha M + beta K), \
                 or damping ratios of the reduced body's modes in the model file \
                 (`modal_damping` of `[simulation]`)",
            ));
        }
        self.check_params(card, &["RAYLEIGH"]);
        let layout = "the data line is 'first mode, last mode, alpha, beta' (the modes are \
                      not used)";
        let line = match card.data.as_slice() {
            [line] => line,
            [] => {
                return Err(files.error(
                    card.loc,
                    format!("*MODAL DAMPING, RAYLEIGH has no data line ({layout})"),
                ))
            }
            [_, second, ..] => {
                return Err(files.error(
                    second.loc,
                    format!("*MODAL DAMPING, RAYLEIGH: one data line expected ({layout})"),
                ))
            }
        };
        if line.get(2).is_none_or(str::is_empty) && line.get(3).is_none_or(str::is_empty) {
            return Err(files.error(
                line.loc,
                format!(
                    "*MODAL DAMPING, RAYLEIGH: alpha and beta are missing: {layout}, so \
                     'alpha, beta' alone would be read as alpha = beta = 0"
                ),
            ));
        }
        let value = |i: usize, what: &str| -> Result<f64, InputError> {
            let what = format!("*MODAL DAMPING, RAYLEIGH: {what}");
            let x = line.float_or(files, i, &what, 0.0)?;
            flexbody_fem::require_non_negative(what, x)
                .map_err(|e| files.error(line.loc, e.to_string()))
        };
        let rayleigh = Rayleigh {
            alpha: value(2, "alpha (1/s, on M)")?,
            beta: value(3, "beta (s, on K)")?,
        };
        if let Some((first, loc)) = self.modal_rayleigh {
            if first != rayleigh {
                return Err(files.error(
                    card.loc,
                    format!(
                        "a second *MODAL DAMPING, RAYLEIGH with other values (first on {}): \
                         flexbody's model has one damping matrix for all steps",
                        files.describe(loc)
                    ),
                ));
            }
        }
        self.modal_rayleigh = Some((rayleigh, card.loc));
        Ok(())
    }

    fn push_section(
        &mut self,
        card: &Card,
        material: Option<String>,
        data: SectionData,
    ) -> Result<(), InputError> {
        let elset = card.require_name(self.files, "ELSET")?;
        let orientation = match data {
            SectionData::Solid => card.value("ORIENTATION").map(super::cards::name),
            _ => None,
        };
        self.sections.push(RawSection {
            keyword: card.display.clone(),
            elset,
            material,
            orientation,
            data,
            loc: card.loc,
        });
        Ok(())
    }

    pub(super) fn solid_section(&mut self, card: &Card) -> Result<(), InputError> {
        // ORIENTATION turns anisotropic materials (isotropic ones are the
        // same in every axes); the data line (thickness of 2D elements)
        // does not apply.
        self.check_params(card, &["ELSET", "MATERIAL", "ORIENTATION", "CONTROLS"]);
        let material = card.require_name(self.files, "MATERIAL")?;
        self.push_section(card, Some(material), SectionData::Solid)
    }

    /// `*SHELL SECTION, ELSET=, MATERIAL=[, OFFSET=][, ORIENTATION=]` with
    /// the thickness on its data line (a second value, the number of
    /// integration points through the thickness, does not apply: the
    /// linear elastic section is integrated exactly). Composite layups and
    /// nodal thicknesses are refused.
    pub(super) fn shell_section(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(
            card,
            &[
                "ELSET",
                "MATERIAL",
                "OFFSET",
                "ORIENTATION",
                "SECTIONINTEGRATION",
                "CONTROLS",
                "POISSON",
            ],
        );
        let files = self.files;
        for (key, what) in [
            (
                "COMPOSITE",
                "composite layups are not supported (give one material and thickness)",
            ),
            (
                "NODALTHICKNESS",
                "nodal thicknesses are not supported (give the thickness)",
            ),
        ] {
            if card.has(key) {
                return Err(files.error(card.loc, format!("*SHELL SECTION, {what}")));
            }
        }
        let offset = match card.value("OFFSET") {
            None => 0.0,
            Some(v) if v.eq_ignore_ascii_case("SPOS") => 0.5,
            Some(v) if v.eq_ignore_ascii_case("SNEG") => -0.5,
            Some(v) => super::cards::parse_float(v)
                .filter(|o| o.is_finite())
                .ok_or_else(|| {
                    files.error(
                        card.loc,
                        format!("*SHELL SECTION, OFFSET={v}: not a number, SPOS or SNEG"),
                    )
                })?,
        };
        let material = card.require_name(files, "MATERIAL")?;
        let line = card.data.first().ok_or_else(|| {
            files.error(
                card.loc,
                "*SHELL SECTION needs a data line with the thickness (m)",
            )
        })?;
        if card.data.len() > 1 {
            return Err(files.error(
                card.data[1].loc,
                "*SHELL SECTION: a second data line is a composite layup, which is not supported",
            ));
        }
        let thickness = line.float(files, 0, "*SHELL SECTION: the thickness")?;
        if !(thickness.is_finite() && thickness > 0.0) {
            return Err(files.error(
                line.loc,
                format!("*SHELL SECTION: the thickness must be positive, got {thickness}"),
            ));
        }
        self.push_section(
            card,
            Some(material),
            SectionData::Shell { thickness, offset },
        )
    }

    pub(super) fn beam_section(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(
            card,
            &[
                "ELSET",
                "MATERIAL",
                "SECTION",
                "ORIENTATION",
                "OFFSET1",
                "OFFSET2",
                "POISSON",
                "TEMPERATURE",
            ],
        );
        let files = self.files;
        if card.has("NODALTHICKNESS") {
            return Err(files.error(
                card.loc,
                "*BEAM SECTION, NODAL THICKNESS: not supported (give the dimensions)",
            ));
        }
        for key in ["OFFSET1", "OFFSET2"] {
            if let Some(v) = card.value(key) {
                if super::cards::parse_float(v) != Some(0.0) {
                    return Err(files.error(
                        card.loc,
                        format!("*BEAM SECTION, {key}={v}: offset sections are not supported"),
                    ));
                }
            }
        }
        let material = card.require_name(files, "MATERIAL")?;
        let kind = card.require_name(files, "SECTION")?;
        let dims = card.data.first().ok_or_else(|| {
            files.error(
                card.loc,
                "*BEAM SECTION needs a data line with the section dimensions",
            )
        })?;
        let shape = beam_shape(files, &kind, dims, card.loc)?;
        let constants = shape
            .constants()
            .map_err(|e| files.error(dims.loc, format!("*BEAM SECTION, SECTION={kind}: {e}")))?;
        let n1 = match card.data.get(1) {
            None => DEFAULT_N1,
            Some(line) => {
                let mut v = [0.0; 3];
                for (k, c) in v.iter_mut().enumerate() {
                    *c = line.float_or(
                        files,
                        k,
                        &format!("*BEAM SECTION: n1 component {}", k + 1),
                        0.0,
                    )?;
                }
                if v.iter().map(|c| c * c).sum::<f64>().sqrt() < 1e-10 {
                    return Err(files.error(
                        line.loc,
                        "*BEAM SECTION: the n1 direction (local 1 axis) is a zero vector",
                    ));
                }
                v
            }
        };
        self.push_section(card, Some(material), SectionData::Beam { constants, n1 })
    }

    pub(super) fn mass(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["ELSET"]);
        let line = card.data.first().ok_or_else(|| {
            self.files
                .error(card.loc, "*MASS needs a data line with the mass (kg)")
        })?;
        let mass = line.float(self.files, 0, "*MASS: mass")?;
        flexbody_fem::require_non_negative("*MASS: mass (kg)", mass)
            .map_err(|e| self.files.error(line.loc, e.to_string()))?;
        self.push_section(card, None, SectionData::Mass(mass))
    }

    pub(super) fn spring(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["ELSET"]);
        if card.has("NONLINEAR") {
            return Err(self.files.error(
                card.loc,
                "*SPRING, NONLINEAR: not supported (give a linear stiffness)",
            ));
        }
        if card.has("ORIENTATION") {
            return Err(self.files.error(
                card.loc,
                "*SPRING, ORIENTATION: not supported; ignoring it would change the \
                 stiffness matrix (spring DOFs in local directions)",
            ));
        }
        self.push_section(card, None, SectionData::Spring(card.data.clone()))
    }

    pub(super) fn dashpot(&mut self, card: &Card) -> Result<(), InputError> {
        self.check_params(card, &["ELSET"]);
        if card.has("NONLINEAR") {
            return Err(self.files.error(
                card.loc,
                "*DASHPOT, NONLINEAR: not supported (give a linear coefficient)",
            ));
        }
        if card.has("ORIENTATION") {
            return Err(self.files.error(
                card.loc,
                "*DASHPOT, ORIENTATION: not supported; ignoring it would change the \
                 damping matrix (dashpot DOFs in local directions)",
            ));
        }
        self.push_section(card, None, SectionData::Dashpot(card.data.clone()))
    }
}

/// The cross-section of `*BEAM SECTION, SECTION=kind` from its first data line.
fn beam_shape(
    files: &Files,
    kind: &str,
    dims: &DataLine,
    card_loc: Loc,
) -> Result<SectionShape, InputError> {
    let dim = |i: usize, what: &str| {
        dims.float(files, i, &format!("*BEAM SECTION, SECTION={kind}: {what}"))
    };
    Ok(match kind {
        "RECT" => SectionShape::Rect {
            width: dim(0, "a (along local 1)")?,
            height: dim(1, "b (along local 2)")?,
        },
        "CIRC" => {
            let r = dim(0, "radius")?;
            let r2 = dims.float_or(files, 1, "*BEAM SECTION, SECTION=CIRC: second radius", r)?;
            if r2 != r {
                return Err(files.error(
                    dims.loc,
                    format!("*BEAM SECTION, SECTION=CIRC: radii {r} and {r2} differ; elliptical sections are not supported"),
                ));
            }
            SectionShape::Circ { radius: r }
        }
        "PIPE" => SectionShape::Pipe {
            radius: dim(0, "outer radius")?,
            wall: dim(1, "wall thickness")?,
        },
        "BOX" => {
            let a = dim(0, "a (along local 1)")?;
            let b = dim(1, "b (along local 2)")?;
            let walls = [dim(2, "t1")?, dim(3, "t2")?, dim(4, "t3")?, dim(5, "t4")?];
            let t = walls[0];
            if walls.iter().any(|w| (w - t).abs() > 1e-12 * t.abs()) {
                return Err(files.error(
                    dims.loc,
                    format!("*BEAM SECTION, SECTION=BOX: walls {walls:?} differ; only equal walls are supported"),
                ));
            }
            SectionShape::Box {
                width: a,
                height: b,
                wall: t,
            }
        }
        other => {
            return Err(files.error(
                card_loc,
                format!(
                "*BEAM SECTION, SECTION={other}: not supported (supported: RECT, CIRC, PIPE, BOX)"
            ),
            ))
        }
    })
}

/// Reads the `*SPRING` or `*DASHPOT` data lines (`card_loc`: the keyword
/// line) for elements of type `kind`, by the number of DOFs its section
/// names: none (SPRINGA, DASHPOTA): the value; one (SPRING1, DASHPOT1):
/// DOF, then the value; two (SPRING2, DASHPOT2): two DOFs, then the value
/// (CalculiX and Abaqus manuals, `*SPRING` and `*DASHPOT`; the blank first
/// line of SPRINGA and DASHPOTA is dropped with the other blank lines).
/// The value of a spring is its stiffness (N/m, positive); of a dashpot its
/// coefficient (N s/m, not negative), whose second field, a frequency, must
/// be empty or 0: frequency-dependent dashpots are refused.
pub(super) fn discrete_properties(
    files: &Files,
    card_loc: Loc,
    lines: &[DataLine],
    kind: &ElementType,
) -> Result<DiscreteProperties, InputError> {
    let (keyword, value_name, dof_count) = match kind.section {
        SectionKind::Dashpot { dofs } => ("*DASHPOT", "coefficient", dofs.min(2)),
        SectionKind::Spring { dofs } => ("*SPRING", "stiffness", dofs.min(2)),
        _ => ("*SPRING", "stiffness", 0),
    };
    let expected = if dof_count == 0 { 1 } else { 2 };
    let layout = match dof_count {
        0 => format!("one line with the {value_name}"),
        1 => format!("a line with the DOF (1-6), then a line with the {value_name}"),
        _ => format!("a line with the two DOFs (1-6), then a line with the {value_name}"),
    };
    let layout = format!("for {}: {layout}", kind.name);
    if lines.len() != expected {
        let loc = lines.get(expected).map_or(card_loc, |l| l.loc);
        return Err(files.error(
            loc,
            format!(
                "{keyword}: {} data lines, expected {expected} ({layout}; \
                 temperature-dependent values are not supported)",
                lines.len()
            ),
        ));
    }
    let mut dofs = [None, None];
    if dof_count > 0 {
        let line = &lines[0];
        let given = line.fields.iter().filter(|f| !f.is_empty()).count();
        if given != dof_count {
            return Err(files.error(line.loc, format!("{keyword}: expected {layout}")));
        }
        for (k, d) in dofs.iter_mut().take(dof_count).enumerate() {
            let dof = line.id(files, k, &format!("{keyword}: DOF"))?;
            if !(1..=6).contains(&dof) {
                return Err(files.error(
                    line.loc,
                    format!("{keyword}: DOF {dof}: only DOFs 1 to 6 (ux uy uz rx ry rz)"),
                ));
            }
            *d = Some(DofKind::ALL[dof as usize - 1]);
        }
    }
    let line = &lines[expected - 1];
    let what = format!("{keyword}: {value_name}");
    let value = line.float(files, 0, &what)?;
    if keyword == "*DASHPOT" {
        flexbody_fem::require_non_negative(format!("{what} (N s/m)"), value)
            .map_err(|e| files.error(line.loc, e.to_string()))?;
        let frequency = line.float_or(files, 1, "*DASHPOT: frequency", 0.0)?;
        if frequency != 0.0 {
            return Err(files.error(
                line.loc,
                format!(
                    "*DASHPOT: frequency {frequency}: frequency-dependent dashpots are not \
                     supported (leave the second field empty)"
                ),
            ));
        }
    } else {
        flexbody_fem::require_positive(what, value)
            .map_err(|e| files.error(line.loc, e.to_string()))?;
    }
    Ok(DiscreteProperties {
        first: dofs[0],
        second: dofs[1],
        value,
    })
}
