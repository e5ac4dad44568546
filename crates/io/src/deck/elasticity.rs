//! `*ELASTIC` of every `TYPE=` CalculiX reads for solids, `*DENSITY`, both
//! with temperature tables, and `*ORIENTATION`, as CalculiX 2.20 reads them.
//!
//! | `TYPE=` | constants of one record (one temperature) | lines |
//! | --- | --- | --- |
//! | `ISO` (default) | `E, nu` | 1 |
//! | `ORTHO` | `D1111, D1122, D2222, D1133, D2233, D3333, D1212, D1313` / `D2323` | 2 |
//! | `ENGINEERING CONSTANTS` | `E1, E2, E3, nu12, nu13, nu23, G12, G13` / `G23` | 2 |
//! | `ANISO` | `D1111, D1122, D2222, D1133, D2233, D3333, D1112, D2212` / `D3312, D1212, D1113, D2213, D3313, D1213, D1313, D1123` / `D2223, D3323, D1223, D1323, D2323` | 3 |
//!
//! The temperature follows the last constant of a record (blank: 0). Several
//! records make a table with strictly increasing temperatures; the values
//! at the model temperature are interpolated linearly between records and
//! held constant beyond the first and last; without an initial temperature
//! CalculiX 2.20 takes the first record (checked with ccx; see
//! `temperature.rs`).
//! Tensor components `Dijkl` are the entries of the Voigt matrix with
//! engineering shear strains ([`flexbody_fem::anisotropy`]).

use super::cards::{Card, DataLine, Files, Loc};
use crate::InputError;
use flexbody_fem::anisotropy::{Anisotropy, Orientation, Voigt};

/// Constants per line of a multi-line record (CalculiX reads 8 a line).
const PER_LINE: usize = 8;

/// The kind of an `*ELASTIC` card.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(super) enum ElasticKind {
    Isotropic,
    Orthotropic,
    EngineeringConstants,
    Anisotropic,
}

impl ElasticKind {
    /// The kind of `TYPE=t` (CalculiX accepts abbreviations of 4 letters
    /// and more: `ISO`, `ORTHO`, `ENGINEERING CONSTANTS`, `ANISO`).
    pub fn parse(t: &str) -> Option<Self> {
        let t: String = t.to_uppercase().split_whitespace().collect();
        match t.as_str() {
            "ISO" | "ISOTROPIC" => Some(Self::Isotropic),
            "ORTHO" | "ORTHOTROPIC" => Some(Self::Orthotropic),
            "ENGINEERINGCONSTANTS" => Some(Self::EngineeringConstants),
            "ANISO" | "ANISOTROPIC" => Some(Self::Anisotropic),
            _ => None,
        }
    }

    /// Constants of one record (without the temperature).
    pub const fn constants(self) -> usize {
        match self {
            Self::Isotropic => 2,
            Self::Orthotropic | Self::EngineeringConstants => 9,
            Self::Anisotropic => 21,
        }
    }

    /// Data lines of one record.
    pub const fn lines(self) -> usize {
        self.constants() / PER_LINE + 1
    }

    /// For messages.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Isotropic => "ISO",
            Self::Orthotropic => "ORTHO",
            Self::EngineeringConstants => "ENGINEERING CONSTANTS",
            Self::Anisotropic => "ANISO",
        }
    }

    /// `isotropic`, `orthotropic` or `anisotropic`, for summaries.
    pub const fn class(self) -> &'static str {
        match self {
            Self::Isotropic => "isotropic",
            Self::Orthotropic | Self::EngineeringConstants => "orthotropic",
            Self::Anisotropic => "anisotropic",
        }
    }
}

/// One record of a table: its constants, temperature and first line.
#[derive(Clone, Debug)]
pub(super) struct Record {
    pub values: Vec<f64>,
    pub temperature: f64,
    pub loc: Loc,
}

/// The records of a material option, temperatures strictly increasing.
#[derive(Clone, Debug)]
pub(super) struct Table {
    pub records: Vec<Record>,
}

impl Table {
    /// Reads `card`'s data lines as records of `constants` values over
    /// `lines` lines each (`what` names the card and material in errors).
    pub fn read(
        files: &Files,
        card: &Card,
        constants: usize,
        lines: usize,
        what: &str,
    ) -> Result<Table, InputError> {
        if card.data.is_empty() {
            return Err(files.error(card.loc, format!("{what} has no data line")));
        }
        if !card.data.len().is_multiple_of(lines) {
            let last = &card.data[card.data.len() - 1];
            return Err(files.error(
                last.loc,
                format!(
                    "{what}: {} data lines, expected a multiple of {lines} \
                     ({constants} constants and a temperature per record)",
                    card.data.len()
                ),
            ));
        }
        let mut records: Vec<Record> = Vec::new();
        for chunk in card.data.chunks(lines) {
            let record = read_record(files, chunk, constants, what)?;
            if let Some(prev) = records.last() {
                if record.temperature.is_nan() || record.temperature <= prev.temperature {
                    return Err(files.error(
                        record.loc,
                        format!(
                            "{what}: temperature {} does not follow {} of the line before \
                             (temperatures must increase strictly)",
                            record.temperature, prev.temperature
                        ),
                    ));
                }
            }
            records.push(record);
        }
        Ok(Table { records })
    }

    /// The values at `temperature`: linear between records, constant beyond
    /// the ends; the first record without a temperature (as CalculiX); with
    /// the record whose line gets blamed for bad values.
    pub fn at(&self, temperature: Option<f64>) -> (Vec<f64>, Loc) {
        let r = &self.records;
        let first = &r[0];
        let Some(temperature) = temperature else {
            return (first.values.clone(), first.loc);
        };
        if r.len() == 1 || temperature <= first.temperature {
            return (first.values.clone(), first.loc);
        }
        let last = &r[r.len() - 1];
        if temperature >= last.temperature {
            return (last.values.clone(), last.loc);
        }
        let k = r
            .iter()
            .position(|x| x.temperature > temperature)
            .unwrap_or(1);
        let (a, b) = (&r[k - 1], &r[k]);
        let t = (temperature - a.temperature) / (b.temperature - a.temperature);
        let values = a
            .values
            .iter()
            .zip(&b.values)
            .map(|(x, y)| x + t * (y - x))
            .collect();
        (values, a.loc)
    }

    /// True if the values depend on the temperature.
    pub fn is_table(&self) -> bool {
        self.records.len() > 1
    }
}

/// One record from its lines: `PER_LINE` constants on each line but the
/// last, which holds the rest and the temperature.
fn read_record(
    files: &Files,
    lines: &[DataLine],
    constants: usize,
    what: &str,
) -> Result<Record, InputError> {
    let mut values = Vec::with_capacity(constants);
    let mut temperature = 0.0;
    for (l, line) in lines.iter().enumerate() {
        let last = l + 1 == lines.len();
        let here = if last {
            constants - PER_LINE * l
        } else {
            PER_LINE
        };
        let given = line
            .fields
            .iter()
            .rposition(|f| !f.is_empty())
            .map_or(0, |i| i + 1);
        let most = if last { here + 1 } else { here };
        if given > most {
            return Err(files.error(
                line.loc,
                format!(
                    "{what}: {given} values on this line, expected at most {most} \
                     ({here} constants{})",
                    if last { " and a temperature" } else { "" }
                ),
            ));
        }
        for i in 0..here {
            let k = values.len() + 1;
            values.push(line.float(files, i, &format!("{what}: constant {k} of {constants}"))?);
        }
        if last {
            temperature = line.float_or(files, here, &format!("{what}: temperature"), 0.0)?;
        }
    }
    Ok(Record {
        values,
        temperature,
        loc: lines[0].loc,
    })
}

/// The elasticity matrix in material axes from the constants of `kind`
/// (`kind` not isotropic).
pub(super) fn voigt(kind: ElasticKind, v: &[f64]) -> Result<Voigt, String> {
    let mut c = [[0.0; 6]; 6];
    let mut set = |i: usize, j: usize, x: f64| {
        c[i][j] = x;
        c[j][i] = x;
    };
    match kind {
        ElasticKind::Isotropic => return Err("isotropic constants have no Voigt form here".into()),
        ElasticKind::Orthotropic => {
            set(0, 0, v[0]);
            set(0, 1, v[1]);
            set(1, 1, v[2]);
            set(0, 2, v[3]);
            set(1, 2, v[4]);
            set(2, 2, v[5]);
            set(3, 3, v[6]);
            set(5, 5, v[7]);
            set(4, 4, v[8]);
        }
        ElasticKind::EngineeringConstants => {
            return Anisotropy::engineering([v[0], v[1], v[2]], v[3], v[4], v[5], v[6], v[7], v[8])
                .map_err(|e| e.to_string());
        }
        ElasticKind::Anisotropic => {
            // CalculiX's index order 11, 22, 33, 12, 13, 23 in flexbody's
            // Voigt positions; the constants run down the columns of the
            // upper triangle.
            const POSITION: [usize; 6] = [0, 1, 2, 3, 5, 4];
            let mut k = 0;
            for (col, &pc) in POSITION.iter().enumerate() {
                for &pr in &POSITION[..=col] {
                    set(pr, pc, v[k]);
                    k += 1;
                }
            }
        }
    }
    Ok(c)
}

/// Reads `*ORIENTATION`: `NAME=`, `SYSTEM=R` (default) or `C`; points `a`
/// and `b`; an optional line `axis, angle (degrees)` turning a rectangular
/// system about its local axis.
pub(super) fn orientation(files: &Files, card: &Card) -> Result<(String, Orientation), InputError> {
    let name = card.require_name(files, "NAME")?;
    let system = card.value("SYSTEM").unwrap_or("R").to_uppercase();
    let what = format!("*ORIENTATION '{name}'");
    let line = card.data.first().ok_or_else(|| {
        files.error(
            card.loc,
            format!("{what} needs a data line with points a and b"),
        )
    })?;
    let mut p = [0.0; 6];
    for (i, v) in p.iter_mut().enumerate() {
        *v = line.float_or(
            files,
            i,
            &format!("{what}: coordinate {} of a, b", i + 1),
            0.0,
        )?;
    }
    let (a, b) = ([p[0], p[1], p[2]], [p[3], p[4], p[5]]);
    let built = match system.chars().next() {
        Some('R') => Orientation::rectangular(a, b),
        Some('C') => Orientation::cylindrical(a, b),
        _ => {
            return Err(files.error(
                card.loc,
                format!("{what}: SYSTEM={system}: expected RECTANGULAR or CYLINDRICAL"),
            ))
        }
    };
    let mut o = built.map_err(|e| files.error(line.loc, format!("{what}: {e}")))?;
    if let Some(second) = card.data.get(1) {
        let axis = second.id(files, 0, &format!("{what}: rotation axis"))?;
        if !(1..=3).contains(&axis) {
            return Err(files.error(
                second.loc,
                format!("{what}: rotation axis {axis}: expected 1, 2 or 3"),
            ));
        }
        let angle = second.float(files, 1, &format!("{what}: rotation angle (degrees)"))?;
        o = o
            .rotated(axis as usize - 1, angle.to_radians())
            .map_err(|e| files.error(second.loc, format!("{what}: {e}")))?;
    }
    if let Some(extra) = card.data.get(2) {
        return Err(files.error(
            extra.loc,
            format!("{what}: at most two data lines (points a, b; axis and angle)"),
        ));
    }
    Ok((name, o))
}
