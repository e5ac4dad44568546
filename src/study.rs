//! The report's comparison (section 6): each reduction method against the
//! full model ("Vergleichslösung"), both coupled into the same MBS and solved
//! and recovered the same way, at each excitation frequency.
//!
//! Accuracy figures, per case and Omega, each `max |reduced - reference| /
//! max |reference|` with complex amplitudes compared by modulus:
//! - `err_w`: displacement uz at the nodes;
//! - `err_force`: the connection (interface) forces;
//! - beams: `err_m`, `err_q`: bending moment My and shear force Qz at the
//!   element ends;
//! - solids and shells: `err_vm`: von Mises stress (of the in-phase part)
//!   at the most stressed points (nodes; a shell's on each surface), those
//!   where the reference reaches half its peak.

use crate::fem::FemError;
use crate::fem::{DofKind, Substructure};
use crate::linalg::memory::Budget;
use crate::linalg::progress::Progress;
use crate::mbs::{harmonic_response, FlexibleBody, MbsError};
use crate::recover::{harmonic_section_forces, nodal_values};
use crate::reduce::{reduce_reporting, Method, ReduceError};
use crate::scenario::{CaseSpec, ModelFile, StudySpec};
use serde::Serialize;

/// A quantity along the beam: positions (m) and complex amplitudes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Field {
    pub x: Vec<f64>,
    pub re: Vec<f64>,
    pub im: Vec<f64>,
}

impl Field {
    /// `max |self - reference| / max |reference|` (moduli of complex
    /// values); NaN where a value is NaN, never a NaN passed over.
    pub fn relative_error(&self, reference: &Field) -> f64 {
        let scale = reference
            .re
            .iter()
            .zip(&reference.im)
            .map(|(a, b)| a.hypot(*b))
            .fold(0.0, max_or_nan);
        let diff = self
            .re
            .iter()
            .zip(&self.im)
            .zip(reference.re.iter().zip(&reference.im))
            .map(|((a, b), (c, d))| (a - c).hypot(b - d))
            .fold(0.0, max_or_nan);
        if scale > 0.0 {
            diff / scale
        } else {
            diff
        }
    }
}

/// Displacement w(x), bending moment M(x), shear force Q(x) and connection
/// forces of one harmonic state.
#[derive(Clone, Debug, Default)]
pub struct BeamResponse {
    pub w: Field,
    pub m: Field,
    pub q: Field,
    /// Connection force amplitudes (N), (re, im).
    pub forces: Vec<(f64, f64)>,
    /// Von Mises stress (Pa) of the in-phase part at the stress points:
    /// the nodes of solids, and of shells on each surface (node ids in
    /// `stress_nodes`); empty without either.
    pub von_mises: Vec<f64>,
    pub stress_nodes: Vec<u64>,
}

impl BeamResponse {
    /// True when nothing moves: every displacement, section force, stress
    /// and connection force is zero.
    pub fn is_zero(&self) -> bool {
        let zero = |v: &[f64]| v.iter().all(|x| *x == 0.0);
        [&self.w, &self.m, &self.q]
            .iter()
            .all(|f| zero(&f.re) && zero(&f.im))
            && self.forces.iter().all(|f| f.0 == 0.0 && f.1 == 0.0)
            && zero(&self.von_mises)
    }

    /// Relative error of the connection forces against `reference`.
    pub fn force_error(&self, reference: &BeamResponse) -> f64 {
        let field = |r: &BeamResponse| Field {
            x: vec![],
            re: r.forces.iter().map(|f| f.0).collect(),
            im: r.forces.iter().map(|f| f.1).collect(),
        };
        field(self).relative_error(&field(reference))
    }

    /// Relative error of von Mises at the most stressed nodes of the
    /// reference (where it reaches half its peak); `None` without solids
    /// or shells.
    pub fn von_mises_error(&self, reference: &BeamResponse) -> Option<f64> {
        let peak = reference
            .von_mises
            .iter()
            .copied()
            .fold(0.0_f64, max_or_nan);
        if reference.von_mises.is_empty() || peak == 0.0 {
            return None;
        }
        let err = reference
            .von_mises
            .iter()
            .zip(&self.von_mises)
            .filter(|(r, _)| **r >= 0.5 * peak)
            .map(|(r, s)| (r - s).abs())
            .fold(0.0, max_or_nan);
        Some(err / peak)
    }
}

/// The larger of `a` and `b`, NaN if either is (`f64::max` passes over a
/// NaN, which would make a failed response look exact).
fn max_or_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// One row of the study table.
#[derive(Clone, Debug, Serialize)]
pub struct CaseRow {
    pub method: Method,
    pub r: usize,
    /// Excitation frequency (rad/s).
    pub omega: f64,
    pub err_w: f64,
    /// Bending moment (beam models).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub err_m: Option<f64>,
    /// Shear force (beam models).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub err_q: Option<f64>,
    /// Connection (interface) forces.
    pub err_force: f64,
    /// Von Mises at the most stressed nodes (models with solids or shells).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub err_vm: Option<f64>,
}

/// A case's result at one frequency, with the curves behind the errors.
#[derive(Clone, Debug)]
pub struct CaseResult {
    pub case: CaseSpec,
    pub row: CaseRow,
    pub reduced: BeamResponse,
}

/// A case that could not be reduced or solved, and why (the whole chain
/// of causes, e.g. the mechanism a Craig-Bampton interface leaves).
#[derive(Clone, Debug, Serialize)]
pub struct CaseFailure {
    pub method: Method,
    pub modes: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fmax: Option<f64>,
    pub error: String,
}

/// The whole study: the reference per frequency, then every case that
/// ran, and the cases that failed (a failing case does not stop the
/// others).
#[derive(Clone, Debug)]
pub struct StudyResult {
    pub title: Option<String>,
    /// `(omega, reference response)` per excitation frequency.
    pub references: Vec<(f64, BeamResponse)>,
    pub cases: Vec<CaseResult>,
    pub failures: Vec<CaseFailure>,
}

impl StudyResult {
    pub fn rows(&self) -> Vec<CaseRow> {
        self.cases.iter().map(|c| c.row.clone()).collect()
    }

    /// The error that measures a case at `omega` against r, one series of
    /// `(r, error)` points per method: von Mises for solid models, the shear
    /// force Q for beam models, else the connection forces (errors floored
    /// at 1e-17 for a logarithmic axis). Returns what the error is of, and
    /// the series.
    pub fn convergence(&self, omega: f64) -> (&'static str, Vec<Series>) {
        let mut series: Vec<Series> = Vec::new();
        for c in self.cases.iter().filter(|c| c.row.omega == omega) {
            let err = c
                .row
                .err_vm
                .or(c.row.err_q)
                .unwrap_or(c.row.err_force)
                .max(1e-17);
            let name = c.row.method.name().to_string();
            match series.iter_mut().find(|(n, _)| *n == name) {
                Some((_, pts)) => pts.push((c.row.r as f64, err)),
                None => series.push((name, vec![(c.row.r as f64, err)])),
            }
        }
        let what = if self.cases.iter().any(|c| c.row.err_vm.is_some()) {
            "von Mises at the most stressed nodes"
        } else {
            "shear force Q"
        };
        (what, series)
    }

    /// The reference response at `omega`.
    pub fn reference(&self, omega: f64) -> Option<&BeamResponse> {
        self.references
            .iter()
            .find(|(o, _)| *o == omega)
            .map(|(_, r)| r)
    }
}

/// A named line of `(x, y)` points.
pub type Series = (String, Vec<(f64, f64)>);

/// An excitation frequency as a short text: at most six decimals, no
/// trailing zeros (`122`, `12.5`).
pub fn fmt_omega(omega: f64) -> String {
    let s = format!("{omega:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Errors of the study, naming the case.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error("{0}: the model file has no [study] table")]
    NoStudy(String),
    #[error("{path}: [study] has nothing to compare: {why}; every response and every error would be zero")]
    NoExcitation { path: String, why: String },
    #[error("reference solution: {0}")]
    Reference(String),
    #[error("case {method} with modes = {modes}")]
    Reduce {
        method: Method,
        modes: usize,
        #[source]
        source: ReduceError,
    },
    #[error("case {method} with modes = {modes}: {message}")]
    Case {
        method: Method,
        modes: usize,
        message: String,
    },
}

/// Errors of one harmonic solution and its recovery.
#[derive(Debug, thiserror::Error)]
pub enum ResponseError {
    #[error(transparent)]
    Mbs(#[from] MbsError),
    #[error("recovery: {0}")]
    Recovery(#[from] FemError),
}

/// Runs the study of `file` (its `[study]` table).
pub fn run_study(
    file: &ModelFile,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<StudyResult, StudyError> {
    let spec = file
        .study
        .as_ref()
        .ok_or_else(|| StudyError::NoStudy(file.path.display().to_string()))?;
    run_cases(file, spec, budget, progress)
}

/// Runs the given cases of a study on `file`.
pub fn run_cases(
    file: &ModelFile,
    spec: &StudySpec,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<StudyResult, StudyError> {
    check_excitation(file)?;
    let sub =
        Substructure::from_model(&file.model).map_err(|e| StudyError::Reference(e.to_string()))?;
    let full = FlexibleBody::Full {
        dof_map: &sub.dof_map,
        matrices: &sub.matrices,
    };
    let references = spec
        .omegas
        .iter()
        .map(|&omega| {
            respond(file, full, omega)
                .map(|r| (omega, r))
                .map_err(|e| StudyError::Reference(e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if references.iter().all(|(_, r)| r.is_zero()) {
        return Err(no_excitation(
            file,
            "the full model's response is zero at every Omega",
        ));
    }
    let mut cases = Vec::new();
    let mut failures = Vec::new();
    for case in &spec.cases {
        match run_case(file, &sub, case, &references, budget, progress) {
            Ok(results) => cases.extend(results),
            Err(e) => failures.push(CaseFailure {
                method: case.method,
                modes: case.modes,
                fmax: case.fmax,
                error: match &e {
                    StudyError::Reduce { source, .. } => causes(source),
                    StudyError::Case { message, .. } => message.clone(),
                    other => causes(other),
                },
            }),
        }
    }
    Ok(StudyResult {
        title: file.title.clone(),
        references,
        cases,
        failures,
    })
}

/// One case at every excitation frequency, against the references.
fn run_case(
    file: &ModelFile,
    sub: &Substructure,
    case: &CaseSpec,
    references: &[(f64, BeamResponse)],
    budget: Budget,
    progress: &dyn Progress,
) -> Result<Vec<CaseResult>, StudyError> {
    let body = reduce_case(file, sub, case, budget, progress)?;
    let mut results = Vec::new();
    for (omega, reference) in references {
        let reduced =
            respond(file, FlexibleBody::Reduced(&body), *omega).map_err(|e| StudyError::Case {
                method: case.method,
                modes: case.modes,
                message: e.to_string(),
            })?;
        let row = CaseRow {
            method: case.method,
            r: body.r(),
            omega: *omega,
            err_w: reduced.w.relative_error(&reference.w),
            err_m: (!reference.m.x.is_empty()).then(|| reduced.m.relative_error(&reference.m)),
            err_q: (!reference.q.x.is_empty()).then(|| reduced.q.relative_error(&reference.q)),
            err_force: reduced.force_error(reference),
            err_vm: reduced.von_mises_error(reference),
        };
        let errors = [
            Some(row.err_w),
            row.err_m,
            row.err_q,
            Some(row.err_force),
            row.err_vm,
        ];
        if errors.into_iter().flatten().any(|e| !e.is_finite()) {
            return Err(StudyError::Case {
                method: case.method,
                modes: case.modes,
                message: format!(
                    "the response at Omega = {omega} rad/s is not finite (reduced or reference)"
                ),
            });
        }
        results.push(CaseResult {
            case: case.clone(),
            row,
            reduced,
        });
    }
    Ok(results)
}

/// An error and its causes on one line: "case craig-bampton with modes =
/// 1: the interface DOFs ... leave a mechanism".
fn causes(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let next = s.to_string();
        if !text.contains(&next) {
            text = format!("{text}: {next}");
        }
        source = s.source();
    }
    text
}

/// Refuses a study whose MBS has nothing that excites it: only the track
/// excites the harmonic MBS (report eq. 11), through connections to it
/// with a vertical component.
fn check_excitation(file: &ModelFile) -> Result<(), StudyError> {
    use crate::mbs::Endpoint;
    let to_track = file
        .connections
        .iter()
        .any(|c| matches!(c.a, Endpoint::Track { .. }) || matches!(c.b, Endpoint::Track { .. }));
    let why = match &file.track {
        None => Some("there is no [track] table, the only excitation of the study"),
        Some(t) if t.amplitude == 0.0 => Some("the track's amplitude is 0"),
        Some(_) if !to_track => Some("no [[connection]] goes to the track (to = \"track\")"),
        Some(_) => None,
    };
    match why {
        Some(why) => Err(no_excitation(file, why)),
        None => Ok(()),
    }
}

fn no_excitation(file: &ModelFile, why: &str) -> StudyError {
    StudyError::NoExcitation {
        path: file.path.display().to_string(),
        why: why.to_string(),
    }
}

/// The reduction of one case, with the file's interface, support and (for
/// elastic-residual) its connections as elastic supports.
pub fn reduce_case(
    file: &ModelFile,
    sub: &Substructure,
    case: &CaseSpec,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<crate::reduce::ReducedBody, StudyError> {
    let mut spec =
        crate::input::file_reduction(file, case.method, case.modes, file.interface.clone());
    spec.max_frequency_hz = case.fmax;
    spec.memory = budget;
    reduce_reporting(sub, &spec, progress).map_err(|source| StudyError::Reduce {
        method: case.method,
        modes: case.modes,
        source,
    })
}

/// The MBS of `file` around `body`, solved at `omega`, recovered (eq. 25).
pub fn respond(
    file: &ModelFile,
    body: FlexibleBody<'_>,
    omega: f64,
) -> Result<BeamResponse, ResponseError> {
    let system = file.system(body);
    let response = harmonic_response(&system, omega)?;
    let (u_re, u_im) = &response.flexible[0];
    let model = &file.model;
    let w_re = nodal_values(model, u_re, DofKind::Uz);
    let w_im = nodal_values(model, u_im, DofKind::Uz);
    let w = Field {
        x: w_re.iter().map(|(c, _)| c[0]).collect(),
        re: w_re.iter().map(|(_, v)| *v).collect(),
        im: w_im.iter().map(|(_, v)| *v).collect(),
    };
    let f_re = harmonic_section_forces(model, u_re, omega)?;
    let f_im = harmonic_section_forces(model, u_im, omega)?;
    let field = |component: usize| {
        let mut f = Field::default();
        for (a, b) in f_re.iter().zip(&f_im) {
            f.x.extend([a.start[0], a.end[0]]);
            f.re.extend([a.forces.start[component], a.forces.end[component]]);
            f.im.extend([b.forces.start[component], b.forces.end[component]]);
        }
        f
    };
    let has_stresses = model.elements().iter().any(|e| e.has_stresses());
    let (von_mises, stress_nodes) = if has_stresses {
        let s = crate::recover::nodal_stresses(model, u_re)?;
        (s.von_mises(), s.nodes)
    } else {
        (vec![], vec![])
    };
    Ok(BeamResponse {
        w,
        m: field(4),
        q: field(2),
        forces: response.forces,
        von_mises,
        stress_nodes,
    })
}

#[cfg(test)]
mod tests {
    use super::Field;

    #[test]
    fn a_nan_in_a_response_makes_its_error_nan_not_zero() {
        let field = |re: Vec<f64>| Field {
            x: vec![0.0; re.len()],
            im: vec![0.0; re.len()],
            re,
        };
        let reference = field(vec![1.0, 2.0, 4.0]);
        assert_eq!(field(vec![1.0, 2.0, 3.0]).relative_error(&reference), 0.25);
        assert!(field(vec![1.0, f64::NAN, 4.0])
            .relative_error(&reference)
            .is_nan());
        assert!(reference
            .relative_error(&field(vec![f64::NAN, 2.0, 4.0]))
            .is_nan());
    }
}
