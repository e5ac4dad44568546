//! The vehicle model in time and frequency (report section 4 with the
//! reduced frame of 6.6): the flexible body (reduced, or the full FE model
//! as the reference), rigid bodies and connections of a model file, run
//! with its `[simulation]` and `[frf]` tables. Section forces come from the
//! Ritz coordinates by eq. 25 with `q''`.

use crate::fem::{Element, FemError, Substructure};
use crate::linalg::memory::Budget;
use crate::linalg::progress::Progress;
use crate::mbs::time::{simulate, TimeResponse};
use crate::mbs::{damped_modes, harmonic_response, DampedMode, FlexibleBody, MbsError, System};
use crate::reduce::{reduce_reporting, ReduceError, ReducedBody};
use crate::scenario::{BodySource, ModelFile, SimulationSpec};
use std::path::Path;

/// Named histories sampled at common times (SI units).
#[derive(Clone, Debug, Default)]
pub struct Histories {
    pub times: Vec<f64>,
    /// `(name, values)`: body coordinates, connection forces, section forces.
    pub columns: Vec<(String, Vec<f64>)>,
    /// What each of `columns` records, one entry per column.
    pub kinds: Vec<HistoryKind>,
}

/// What a history records.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum HistoryKind {
    /// A coordinate of a rigid body (m or rad).
    RigidBody,
    /// A displacement of the flexible body at an interface DOF (m or rad).
    Interface,
    /// The force of a connection (N).
    Connection,
    /// Shear force `Qz` at an element's start (N).
    StartShear,
    /// Bending moment `My` at an element's start (N m).
    StartMoment,
    /// Shear force `Qz` at an element's end (N).
    EndShear,
    /// Bending moment `My` at an element's end (N m).
    EndMoment,
    /// Von Mises stress at a node of a solid (or on a shell's surface) (Pa).
    VonMises,
}

impl Histories {
    /// The `(name, values)` of every column of `kind`, in column order.
    pub fn of_kind(&self, kind: HistoryKind) -> Vec<(&str, &[f64])> {
        self.columns
            .iter()
            .zip(&self.kinds)
            .filter(|(_, k)| **k == kind)
            .map(|((n, v), _)| (n.as_str(), v.as_slice()))
            .collect()
    }

    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// The smallest and largest value of each column, by name.
    pub fn ranges(&self) -> Vec<(&str, f64, f64)> {
        self.columns
            .iter()
            .map(|(name, v)| {
                let (lo, hi) = v
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                        (a.min(*x), b.max(*x))
                    });
                (name.as_str(), lo, hi)
            })
            .collect()
    }
}

/// A vehicle model ready to run: its model file, the assembled FE model,
/// and the reduced body (none when the full FE model runs, the reference).
pub struct Vehicle {
    pub file: ModelFile,
    pub sub: Substructure,
    pub body: Option<ReducedBody>,
}

impl Vehicle {
    /// Reads the model file at `path` (it must have a `[simulation]`
    /// table) and assembles its model; the full FE model runs until
    /// [`Vehicle::reduced`]. A `mesh` deck with an unknown keyword is
    /// refused.
    pub fn read(path: &Path) -> Result<Self, SimulationError> {
        Self::read_with(path, &crate::io::deck::DeckOptions::default())
    }

    /// [`Vehicle::read`] with the `mesh` deck read with `options`.
    pub fn read_with(
        path: &Path,
        options: &crate::io::deck::DeckOptions,
    ) -> Result<Self, SimulationError> {
        let file = crate::scenario::read_model_file_with(path, options)?;
        if file.simulation.is_none() {
            return Err(SimulationError::NoSimulation(path.display().to_string()));
        }
        let sub = Substructure::from_model(&file.model).map_err(SimulationError::Model)?;
        Ok(Self {
            file,
            sub,
            body: None,
        })
    }

    /// The vehicle with the flexible body its `[simulation]` table names:
    /// reduced as it says, or read from a reduced-body file.
    /// The reduction's solves are held to `budget`.
    pub fn reduced(
        mut self,
        budget: Budget,
        progress: &dyn Progress,
    ) -> Result<Self, SimulationError> {
        let spec =
            self.file.simulation.as_ref().ok_or_else(|| {
                SimulationError::NoSimulation(self.file.path.display().to_string())
            })?;
        self.body = Some(simulation_body(
            &self.file, &self.sub, spec, budget, progress,
        )?);
        Ok(self)
    }

    /// The flexible body the MBS runs: the reduced body, or the full FE
    /// model where there is none.
    pub fn flexible(&self) -> FlexibleBody<'_> {
        match &self.body {
            Some(body) => FlexibleBody::Reduced(body),
            None => FlexibleBody::Full {
                dof_map: &self.sub.dof_map,
                matrices: &self.sub.matrices,
            },
        }
    }

    /// What runs, for titles: "reduced body" or "full FE model".
    pub fn label(&self) -> &'static str {
        if self.body.is_some() {
            "reduced body"
        } else {
            "full FE model"
        }
    }
}

/// Errors of a simulation or FRF, naming the stage.
#[derive(Debug, thiserror::Error)]
pub enum SimulationError {
    #[error("{0}: the model file has no [simulation] table")]
    NoSimulation(String),
    #[error("{0}: the model file has no [frf] table")]
    NoFrf(String),
    #[error(transparent)]
    Input(#[from] crate::io::InputError),
    #[error(transparent)]
    Model(FemError),
    #[error("reducing the flexible body: {0}")]
    Reduce(#[from] ReduceError),
    #[error("reading the reduced body: {0}")]
    Body(#[from] crate::export::ExportError),
    #[error("modal damping: {0}")]
    Damping(flexbody_linalg::LinalgError),
    #[error(transparent)]
    Mbs(#[from] MbsError),
    #[error("recovery: {0}")]
    Recovery(#[from] FemError),
    #[error(
        "the reduced body's DOFs do not match the model's ({0}): it was not made from this model"
    )]
    Mismatch(String),
}

/// The flexible body of a simulation: reduced as the file says (with modal
/// damping), or read from a reduced-body file; the reduction's solves are
/// held to `budget`.
pub fn simulation_body(
    file: &ModelFile,
    sub: &Substructure,
    spec: &SimulationSpec,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<ReducedBody, SimulationError> {
    let body = match &spec.body {
        BodySource::Reduce { method, modes } => {
            let mut r = crate::input::file_reduction(file, *method, *modes, file.interface.clone());
            r.memory = budget;
            reduce_reporting(sub, &r, progress)?
        }
        BodySource::File(path) => {
            let body = crate::export::read_json(path)?;
            if body.dof_map.dofs() != sub.dof_map.dofs() {
                return Err(SimulationError::Mismatch(path.display().to_string()));
            }
            body
        }
    };
    if spec.modal_damping.is_empty() {
        Ok(body)
    } else {
        body.with_modal_damping(&spec.modal_damping)
            .map_err(SimulationError::Damping)
    }
}

/// Runs the `[simulation]` of `file` with `body` (a reduced body or the full
/// model) and returns its histories.
pub fn run_simulation(
    file: &ModelFile,
    body: FlexibleBody<'_>,
) -> Result<Histories, SimulationError> {
    let spec = file
        .simulation
        .as_ref()
        .ok_or_else(|| SimulationError::NoSimulation(file.path.display().to_string()))?;
    let sys = file.system(body);
    let response = simulate(&sys, &spec.excitation, &spec.settings, None)?;
    let mut h = histories(file, &sys, &response, &spec.record)?;
    if !spec.record_nodes.is_empty() {
        let stresses = stress_histories(file, body, &response, &spec.record_nodes)?;
        h.kinds
            .extend(std::iter::repeat_n(HistoryKind::VonMises, stresses.len()));
        h.columns.extend(stresses);
    }
    Ok(h)
}

/// Body coordinates, connection forces and section forces of a run.
fn histories(
    file: &ModelFile,
    sys: &System,
    r: &TimeResponse,
    record: &[usize],
) -> Result<Histories, SimulationError> {
    let layout = sys.layout();
    let mut columns: Vec<(String, Vec<f64>)> = Vec::new();
    let mut kinds = Vec::new();
    let body = sys.flexible[0];
    let q_at = layout.flexible[0];
    for (b, at) in sys.rigid.iter().zip(&layout.rigid) {
        for (k, kind) in b.active.iter().enumerate() {
            let unit = if kind.is_rotation() { "rad" } else { "m" };
            columns.push((
                format!("{}.{} ({unit})", b.name, kind),
                r.states.iter().map(|s| s.x[at + k]).collect(),
            ));
            kinds.push(HistoryKind::RigidBody);
        }
    }
    // Displacements of the flexible body's interface DOFs (u_j = T_j q,
    // eq. 8), along the local axes at a node that has them.
    for dof in &file.interface {
        let (row, along) = match file.model.local_axes().get(&dof.node) {
            Some(r) => (local_row(&body, r, *dof), " local"),
            None => (body.dof_row(*dof), ""),
        };
        if let Some(row) = row {
            let unit = if dof.kind.is_rotation() { "rad" } else { "m" };
            columns.push((
                format!("{dof}{along} ({unit})"),
                r.states
                    .iter()
                    .map(|s| row.iter().map(|&(i, g)| g * s.x[q_at + i]).sum())
                    .collect(),
            ));
            kinds.push(HistoryKind::Interface);
        }
    }
    for (k, c) in sys.connections.iter().enumerate() {
        columns.push((
            format!("{} (N)", c.name),
            r.forces.iter().map(|f| f[k]).collect(),
        ));
        kinds.push(HistoryKind::Connection);
    }
    // Section forces (eq. 25): u = T q, a = T q''.
    let elements: Vec<&Element> = record
        .iter()
        .filter_map(|id| file.model.elements().iter().find(|e| e.id() == *id))
        .collect();
    let mut section: Vec<Vec<f64>> = vec![Vec::with_capacity(r.times.len()); 4 * elements.len()];
    for s in &r.states {
        let n = body.len();
        let u = body.displacements(&s.x[q_at..q_at + n]);
        let a = body.displacements(&s.a[q_at..q_at + n]);
        for (k, e) in elements.iter().enumerate() {
            let dofs = e.dofs();
            let pick =
                |v: &[f64]| -> Vec<f64> { dofs.iter().map(|d| file.model.value(*d, v)).collect() };
            let f = e
                .section_forces(&file.model, &pick(&u), &pick(&a))?
                .unwrap_or_default();
            section[4 * k].push(f.start[2]);
            section[4 * k + 1].push(f.start[4]);
            section[4 * k + 2].push(f.end[2]);
            section[4 * k + 3].push(f.end[4]);
        }
    }
    for (k, e) in elements.iter().enumerate() {
        for (c, (name, kind)) in [
            ("start Qz (N)", HistoryKind::StartShear),
            ("start My (N m)", HistoryKind::StartMoment),
            ("end Qz (N)", HistoryKind::EndShear),
            ("end My (N m)", HistoryKind::EndMoment),
        ]
        .iter()
        .enumerate()
        {
            columns.push((
                format!("element {} {name}", e.id()),
                std::mem::take(&mut section[4 * k + c]),
            ));
            kinds.push(*kind);
        }
    }
    Ok(Histories {
        times: r.times.clone(),
        columns,
        kinds,
    })
}

/// Transfer functions from the track amplitude to each connection force and
/// to the recorded section forces, over the `[frf]` band: `(f_hz, name,
/// magnitude per metre of track amplitude, phase rad)`.
#[derive(Clone, Debug, Default)]
pub struct Transfer {
    pub frequencies_hz: Vec<f64>,
    /// `(name, magnitude, phase)` per output; magnitude per unit track amplitude.
    pub outputs: Vec<(String, Vec<f64>, Vec<f64>)>,
}

impl Transfer {
    /// The CSV columns: magnitude and phase of each output.
    pub fn columns(&self) -> Vec<(String, Vec<f64>)> {
        let mut columns = Vec::new();
        for (name, mag, phase) in &self.outputs {
            columns.push((format!("|{name}|"), mag.clone()));
            columns.push((format!("phase {name} (rad)"), phase.clone()));
        }
        columns
    }
}

/// The damped modes of a coupled system, or why they were not computed
/// (too large for the dense solver, or not all resolved).
pub fn coupled_modes_if_dense(
    file: &ModelFile,
    body: FlexibleBody<'_>,
) -> Result<Result<Vec<DampedMode>, MbsError>, SimulationError> {
    match coupled_modes(file, body) {
        Err(SimulationError::Mbs(
            e @ (MbsError::TooLargeForDense { .. } | MbsError::UnresolvedModes { .. }),
        )) => Ok(Err(e)),
        other => other.map(Ok),
    }
}

/// The `[frf]` sweep of `file` with `body`.
pub fn run_frf(file: &ModelFile, body: FlexibleBody<'_>) -> Result<Transfer, SimulationError> {
    let spec = file
        .frf
        .as_ref()
        .ok_or_else(|| SimulationError::NoFrf(file.path.display().to_string()))?;
    let record = file
        .simulation
        .as_ref()
        .map(|s| s.record.clone())
        .unwrap_or_default();
    let sys = file.system(body);
    let amplitude = file.track.map_or(1.0, |t| t.amplitude);
    let [lo, hi] = spec.band_hz;
    let freqs: Vec<f64> = (0..spec.points)
        .map(|k| lo + (hi - lo) * k as f64 / (spec.points - 1) as f64)
        .collect();
    let mut outputs: Vec<(String, Vec<f64>, Vec<f64>)> = sys
        .connections
        .iter()
        .map(|c| (format!("{} (N/m)", c.name), vec![], vec![]))
        .collect();
    for id in &record {
        outputs.push((format!("element {id} end Qz (N/m)"), vec![], vec![]));
        outputs.push((format!("element {id} end My (N m/m)"), vec![], vec![]));
    }
    for f in &freqs {
        let omega = 2.0 * std::f64::consts::PI * f;
        let r = harmonic_response(&sys, omega)?;
        let mut push = |k: usize, re: f64, im: f64| {
            outputs[k].1.push(re.hypot(im) / amplitude);
            outputs[k].2.push(im.atan2(re));
        };
        for (k, (re, im)) in r.forces.iter().enumerate() {
            push(k, *re, *im);
        }
        let (u_re, u_im) = &r.flexible[0];
        let f_re = crate::recover::harmonic_section_forces(&file.model, u_re, omega)?;
        let f_im = crate::recover::harmonic_section_forces(&file.model, u_im, omega)?;
        for (j, id) in record.iter().enumerate() {
            let k = sys.connections.len() + 2 * j;
            let (a, b) = (
                f_re.iter().find(|e| e.element == *id),
                f_im.iter().find(|e| e.element == *id),
            );
            if let (Some(a), Some(b)) = (a, b) {
                push(k, a.forces.end[2], b.forces.end[2]);
                push(k + 1, a.forces.end[4], b.forces.end[4]);
            }
        }
    }
    Ok(Transfer {
        frequencies_hz: freqs,
        outputs,
    })
}

/// Damped modes (eq. 21) of the coupled system with `body`.
pub fn coupled_modes(
    file: &ModelFile,
    body: FlexibleBody<'_>,
) -> Result<Vec<DampedMode>, SimulationError> {
    Ok(damped_modes(&file.system(body))?)
}

/// Von Mises histories at the nodes of solids (and shells, one column per
/// surface): for a reduced body from the modal stress matrices (`sigma =
/// T_sigma q`, eq. 25 for solids), for the full model from the
/// displacements.
fn stress_histories(
    file: &ModelFile,
    body: FlexibleBody<'_>,
    r: &TimeResponse,
    nodes: &[u64],
) -> Result<Vec<(String, Vec<f64>)>, SimulationError> {
    let n = body.len();
    let modal = match body {
        FlexibleBody::Reduced(b) => Some(crate::recover::ModalStress::new(&file.model, b)?),
        FlexibleBody::Full { .. } => None,
    };
    let mut columns: Vec<(String, Vec<f64>)> = Vec::new();
    // The stress points of the recorded nodes, found at the first state.
    let mut points: Vec<usize> = Vec::new();
    for (step, s) in r.states.iter().enumerate() {
        let q = &s.x[..n];
        let stresses = match &modal {
            Some(m) => m.stresses(q),
            None => crate::recover::nodal_stresses(&file.model, &body.displacements(q))?,
        };
        if step == 0 {
            for id in nodes {
                for (i, (node, layer)) in stresses.nodes.iter().zip(&stresses.layers).enumerate() {
                    if node == id {
                        let name = match layer.name() {
                            "" => format!("node {id} von Mises (Pa)"),
                            l => format!("node {id} {l} von Mises (Pa)"),
                        };
                        points.push(i);
                        columns.push((name, Vec::with_capacity(r.states.len())));
                    }
                }
            }
        }
        let vm = stresses.von_mises();
        for (column, &i) in columns.iter_mut().zip(&points) {
            column.1.push(vm[i]);
        }
    }
    Ok(columns)
}

/// The row of the local component `dof` at a node with axes `r`:
/// `sum_j R_ji row_j` over the global rows of its family.
fn local_row(
    body: &crate::mbs::FlexibleBody,
    r: &crate::fem::Axes,
    dof: crate::fem::Dof,
) -> Option<Vec<(usize, f64)>> {
    let i = dof.kind.index() % 3;
    let mut sum: std::collections::BTreeMap<usize, f64> = Default::default();
    for (j, kind) in crate::fem::transform::family(dof.kind)
        .into_iter()
        .enumerate()
    {
        for (c, v) in body.dof_row(crate::fem::Dof::new(dof.node, kind))? {
            *sum.entry(c).or_default() += r[j][i] * v;
        }
    }
    Some(sum.into_iter().filter(|(_, v)| *v != 0.0).collect())
}
