//! The figures the command line reports about a model and its reduced
//! body, each a plain value: the mass of the model along each axis
//! (`t^T M t` for a unit translation `t`), its natural frequencies with a
//! diagnosis of mechanisms, and the comparison of a reduced body's
//! frequencies with the full model's (eigenvalues of `K_red`, `M_red`
//! against those of `K`, `M`, eq. 5-7), the size of a sparse factor, and
//! the study's table.

use crate::fem::{DofKind, Substructure, Support};
use crate::input::Component;
use crate::linalg::memory::Budget;
use crate::linalg::progress::Progress;
use crate::linalg::solver::{eigen, Solver};
use crate::linalg::{memory, ordering::Ordering, pencil::Pencil, LinalgError};
use crate::reduce::modes::{eigenmodes_owned, rigid_motion_count, Wanted, ZERO_GAP};
use crate::reduce::{ReduceError, ReducedBody};
use crate::study::{fmt_omega, StudyResult};
use std::fmt;

/// The mass of `sub` along x, y and z: `t^T M t` for the unit translation
/// `t` along each axis (1 at every translational DOF of that axis, 0
/// elsewhere).
pub fn mass_along_axes(sub: &Substructure) -> [f64; 3] {
    [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|kind| mass_along(sub, kind))
}

/// `t^T M t` for the unit translation `t` along `kind`.
fn mass_along(sub: &Substructure, kind: DofKind) -> f64 {
    let map = &sub.dof_map;
    let t: Vec<f64> = map
        .dofs()
        .iter()
        .map(|d| (d.kind == kind) as u8 as f64)
        .collect();
    let r = sub.matrices.mass.as_ref();
    (0..map.len())
        .map(|j| {
            r.row_idx_of_col(j)
                .zip(r.val_of_col(j))
                .map(|(i, v)| t[i] * v * t[j])
                .sum::<f64>()
        })
        .sum::<f64>()
}

/// More zero frequencies among a model's lowest modes than its support
/// allows: the sign of a mechanism (parts not connected, DOFs no element
/// stiffens) or of supports that leave rigid-body motions free.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Mechanism {
    /// A free body with `zero` zero frequencies, more than its `rigid`
    /// rigid-body motions.
    Free {
        zero: usize,
        rigid: usize,
        /// Every mode computed was zero.
        all: bool,
    },
    /// A held body (fixed DOFs or springs to ground) with `zero` zero
    /// frequencies.
    Held {
        zero: usize,
        /// Every mode computed was zero.
        all: bool,
    },
}

impl fmt::Display for Mechanism {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let count = |zero: usize, all: bool| {
            if all {
                format!("all {zero} modes computed have")
            } else {
                format!("{zero} modes have")
            }
        };
        match *self {
            Mechanism::Free { zero, rigid, all } => write!(
                f,
                "{} zero frequency, more than the {rigid} rigid-body motions of a free body: \
                 the model has a mechanism (parts not connected, or DOFs that no element stiffens)",
                count(zero, all)
            ),
            Mechanism::Held { zero, all } => write!(
                f,
                "{} zero frequency although the model is held (fixed DOFs or springs to \
                 ground): its supports leave rigid-body motions free, or it has a mechanism \
                 (parts not connected, or DOFs that no element stiffens)",
                count(zero, all)
            ),
        }
    }
}

/// The mechanism the lowest eigenvalues `values` show, if any: more
/// round-off zeros (below a gap of [`ZERO_GAP`] to the next) than `rigid`
/// for a free body, any for a held one; nothing for matrices whose support
/// is unknown.
pub fn diagnose_mechanism(values: &[f64], support: Support, rigid: usize) -> Option<Mechanism> {
    let top = values.last().copied().unwrap_or(0.0);
    let zero = crate::linalg::eigen::leading_zeros(values, top, ZERO_GAP);
    let all = zero == values.len();
    match support {
        Support::Free if zero > rigid => Some(Mechanism::Free { zero, rigid, all }),
        Support::Supported if zero > 0 => Some(Mechanism::Held { zero, all }),
        _ => None,
    }
}

/// The natural frequencies of a model and what they say about it.
#[derive(Clone, Debug, PartialEq)]
pub struct NaturalFrequencies {
    /// DOFs of the model.
    pub dofs: usize,
    /// Frequencies (Hz), lowest first.
    pub frequencies_hz: Vec<f64>,
    /// `||K phi - lambda M phi|| / ||K phi||` of each mode; for rigid-body
    /// modes, whose `K phi` is itself round-off, relative to `||K|| ||phi||`.
    pub residuals: Vec<f64>,
    /// A mechanism the zero frequencies show ([`diagnose_mechanism`]).
    pub mechanism: Option<Mechanism>,
}

/// The modes of `component` in `band` (a count beyond the model's DOFs is
/// cut to them), within the memory `budget` leaves. The component is
/// consumed: its `K` and `M` go to the solver, which drops them once it
/// holds its compact copy.
pub fn natural_frequencies(
    component: Component,
    band: Wanted,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<NaturalFrequencies, ReduceError> {
    let dofs = component.sub.len();
    let band = band.map_count(|count| count.min(dofs));
    // A free body's rigid-body motions (eq. 12-13), against which its zero
    // frequencies are counted (from geometry: no products with K or M on
    // the way to the solver); none where it is held.
    let support = component.sub.support;
    let rigid = match support {
        Support::Free => rigid_motion_count(&component.sub),
        _ => 0,
    };
    let matrices = component.into_matrices();
    crate::linalg::memory::release_free_memory();
    let (modes, residuals) =
        eigenmodes_owned(matrices.stiffness, matrices.mass, band, budget, progress)?;
    Ok(NaturalFrequencies {
        dofs,
        frequencies_hz: modes.frequencies_hz(),
        residuals,
        mechanism: diagnose_mechanism(&modes.values, support, rigid),
    })
}

/// Whether a reduction is compared with the full model's frequencies.
#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Check {
    /// Models up to 20000 DOFs (the comparison is one more eigen solve of
    /// the full model)
    Auto,
    /// Models of any size
    Always,
    /// No comparison
    Never,
}

impl Check {
    /// Largest model that [`Check::Auto`] compares.
    pub const AUTO_UP_TO: usize = 20_000;

    /// Whether a model of `dofs` DOFs is compared.
    pub fn compares(self, dofs: usize) -> bool {
        match self {
            Check::Always => true,
            Check::Never => false,
            Check::Auto => dofs <= Check::AUTO_UP_TO,
        }
    }
}

/// A reduced body's natural frequencies, and the full model's lowest as
/// many where they were computed.
#[derive(Clone, Debug, PartialEq)]
pub struct FrequencyComparison {
    /// Frequencies of `K_red`, `M_red` (Hz), lowest first.
    pub reduced_hz: Vec<f64>,
    /// The full model's lowest `min(r, DOFs)` frequencies (Hz).
    pub full_hz: Option<Vec<f64>>,
}

impl FrequencyComparison {
    /// `(mode number from 1, |reduced - full| / full)` of every full-model
    /// frequency above 1e-6 of the highest (rigid-body zeros have no
    /// relative error; the highest reduced frequencies, those of static
    /// modes, are far off by nature). Empty without the full model's.
    pub fn relative_errors(&self) -> Vec<(usize, f64)> {
        let Some(full_hz) = &self.full_hz else {
            return Vec::new();
        };
        let top = full_hz.iter().fold(0.0_f64, |m, f| m.max(*f));
        full_hz
            .iter()
            .zip(&self.reduced_hz)
            .enumerate()
            .filter(|(_, (f, _))| **f > 1e-6 * top)
            .map(|(k, (f, r))| (k + 1, (r - f).abs() / f))
            .collect()
    }
}

/// The frequencies of `body`, with the full model's lowest `r` from one
/// more eigen solve of `sub` when `compare` (which needs `sub`'s stiffness
/// and mass), within the memory `budget` leaves.
pub fn compare_frequencies(
    sub: &Substructure,
    body: &ReducedBody,
    compare: bool,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<FrequencyComparison, ReduceError> {
    let reduced_hz = body.frequencies_hz()?;
    let full_hz = if compare {
        let count = body.r().min(sub.len());
        let (k, m) = (&sub.matrices.stiffness, &sub.matrices.mass);
        let found = eigen(k, m, Wanted::Lowest(count), Solver::Auto, budget, progress)?;
        Some(found.pairs.frequencies_hz())
    } else {
        None
    };
    Ok(FrequencyComparison {
        reduced_hz,
        full_hz,
    })
}

/// The study table as the command line prints it: the title, a line on the
/// reference (`dofs` DOFs of the full model), a header, and a row per case
/// with the relative errors of w, M and Q (beam models), the connection
/// forces and von Mises (solid models).
pub fn study_table(result: &StudyResult, dofs: usize) -> String {
    let mut lines = Vec::new();
    if let Some(t) = &result.title {
        lines.push(t.clone());
    }
    lines.push(format!(
        "reference: full model, {dofs} DOFs; errors: max |reduced - reference| / max |reference|"
    ));
    let rows = result.rows();
    let beams = rows.first().is_some_and(|r| r.err_m.is_some());
    let solids = rows.first().is_some_and(|r| r.err_vm.is_some());
    let mut header = format!(
        "{:<18} {:>4} {:>14} {:>10}",
        "method", "r", "Omega (rad/s)", "err w"
    );
    if beams {
        header += &format!(" {:>10} {:>10}", "err M", "err Q");
    }
    header += &format!(" {:>10}", "err F");
    if solids {
        header += &format!(" {:>10}", "err vm");
    }
    lines.push(header);
    for row in &rows {
        let mut line = format!(
            "{:<18} {:>4} {:>14} {:>10.2e}",
            row.method.name(),
            row.r,
            fmt_omega(row.omega),
            row.err_w
        );
        if let (Some(m), Some(q)) = (row.err_m, row.err_q) {
            line += &format!(" {m:>10.2e} {q:>10.2e}");
        }
        line += &format!(" {:>10.2e}", row.err_force);
        if let Some(v) = row.err_vm {
            line += &format!(" {v:>10.2e}");
        }
        lines.push(line);
    }
    for f in &result.failures {
        let modes = match f.fmax {
            Some(hz) => format!("< {hz} Hz"),
            None => f.modes.to_string(),
        };
        lines.push(format!(
            "{:<18} {:>4} FAILED: {}",
            f.method.name(),
            modes,
            f.error
        ));
    }
    lines.join("\n")
}

/// The size of the sparse `LDL^T` factor of `K - sigma M`, from its
/// ordering and symbolic analysis (no numeric factorisation).
#[derive(Clone, Debug)]
pub struct FactorSize {
    /// "AMD" or "METIS nested dissection".
    pub ordering: &'static str,
    /// Entries of `L`.
    pub entries: usize,
    /// Floating-point operations per numeric factorisation.
    pub flops: f64,
    /// Time of the ordering and analysis (s).
    pub seconds: f64,
}

/// Orders and analyses the factor of `sub`'s `K - sigma M`.
pub fn factor_size(sub: &Substructure) -> Result<FactorSize, LinalgError> {
    let start = std::time::Instant::now();
    let (k, m) = (&sub.matrices.stiffness, &sub.matrices.mass);
    let pencil = Pencil::analyze(
        k,
        m,
        None,
        Ordering::Auto,
        &flexbody_linalg::progress::NoProgress,
    )?;
    Ok(FactorSize {
        ordering: match pencil.ordering() {
            Ordering::Amd => "AMD",
            _ => "METIS nested dissection",
        },
        entries: pencil.factor_len(),
        flops: pencil.factor_flops(),
        seconds: start.elapsed().as_secs_f64(),
    })
}

impl fmt::Display for FactorSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let flops = if self.flops >= 1e9 {
            format!("{:.1} GFlop", self.flops * 1e-9)
        } else {
            format!("{:.1} MFlop", self.flops * 1e-6)
        };
        write!(
            f,
            "factor of K - sigma M ({}): {} entries of L ({}), \
             {flops} per factorisation; ordered and analysed in {:.3} s",
            self.ordering,
            self.entries,
            memory::bytes_text((self.entries * std::mem::size_of::<f64>()) as u64),
            self.seconds
        )
    }
}
