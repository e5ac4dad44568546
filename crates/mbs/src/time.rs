//! Response in time: HHT-alpha integration (Hilber, Hughes & Taylor 1977;
//! Newmark's trapezoidal rule for alpha = 0) of
//! `M x'' + D x' + K x + sum_n g_n F_n(g_n x + v_p, g_n x' + v_p') = f(t)`
//! with Newton iterations for the nonlinear connections, at a fixed step or
//! with step control by the local error estimate of Zienkiewicz & Xie.
//!
//! Linear connections are part of K and D; every connection's prescribed
//! elongation `v_p(t) = sum_k c_k z(V t + x_k)` comes from the track profile
//! under wheel k, at vehicle speed V (the delay between wheelsets is
//! `(x_j - x_k) / V`).

use crate::body::Row;
use crate::connection::Endpoint;
use crate::linear_solve::Factor;
use crate::system::{Assembled, Kinematics, System};
use crate::MbsError;
use faer::sparse::Triplet;
use faer::Mat;
use flexbody_linalg::memory::Budget;
use flexbody_linalg::{sparse, SparseMat};
use serde::{Deserialize, Serialize};

/// Smallest step, as a fraction of the requested one, that cutbacks and
/// step control may reach.
const MIN_STEP_FRACTION: f64 = 1.0 / 1024.0;

/// A track profile z(s) (m) along the track coordinate s (m).
#[derive(Clone, Debug, PartialEq)]
pub enum Profile {
    /// `a cos(2 pi s / L_w)`.
    Cosine { amplitude: f64, wavelength: f64 },
    /// Linear interpolation in a table of `(s, z)`, s ascending (from a CSV
    /// file); the simulation must stay within its range.
    Table { s: Vec<f64>, z: Vec<f64> },
}

impl Profile {
    /// `(z(s), dz/ds)`.
    pub fn at(&self, s: f64) -> (f64, f64) {
        match self {
            Profile::Cosine {
                amplitude,
                wavelength,
            } => {
                let k = 2.0 * std::f64::consts::PI / wavelength;
                (amplitude * (k * s).cos(), -amplitude * k * (k * s).sin())
            }
            Profile::Table { s: ss, z } => {
                let n = ss.len();
                let i = ss.partition_point(|x| *x <= s).clamp(1, n - 1) - 1;
                let slope = (z[i + 1] - z[i]) / (ss[i + 1] - ss[i]);
                (z[i] + slope * (s - ss[i]), slope)
            }
        }
    }

    /// The range of s the profile covers.
    pub fn range(&self) -> (f64, f64) {
        match self {
            Profile::Cosine { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Profile::Table { s, .. } => (s[0], s[s.len() - 1]),
        }
    }
}

/// A force history F(t) (N).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum History {
    /// `amplitude sin(2 pi frequency t + phase)`.
    Harmonic {
        amplitude: f64,
        frequency_hz: f64,
        #[serde(default)]
        phase: f64,
    },
    /// Linear interpolation in `[t, F]` rows; held constant outside.
    Table(Vec<[f64; 2]>),
}

impl History {
    pub fn at(&self, t: f64) -> f64 {
        match self {
            History::Harmonic {
                amplitude,
                frequency_hz,
                phase,
            } => amplitude * (2.0 * std::f64::consts::PI * frequency_hz * t + phase).sin(),
            History::Table(rows) => {
                if rows.is_empty() {
                    return 0.0;
                }
                let i = rows.partition_point(|r| r[0] <= t);
                if i == 0 {
                    rows[0][1]
                } else if i == rows.len() {
                    rows[i - 1][1]
                } else {
                    let (a, b) = (rows[i - 1], rows[i]);
                    a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0])
                }
            }
        }
    }
}

/// A force acting at a point of a body, along `direction`.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeForce {
    pub name: String,
    /// A flexible node or a rigid-body point.
    pub at: Endpoint,
    pub direction: [f64; 3],
    pub history: History,
}

/// What drives the system in time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Excitation {
    /// Vehicle speed V (m/s).
    pub speed: f64,
    /// The track under the wheels (`None`: the system's harmonic track as a
    /// cosine profile, if any).
    pub profile: Option<Profile>,
    /// Fade-in time (s): the track amplitude rises as
    /// `(1 - cos(pi t / ramp)) / 2` so that the start does not ring the
    /// high modes; 0 for none.
    pub ramp: f64,
    pub forces: Vec<TimeForce>,
}

/// Integration settings.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct TimeSettings {
    /// Time step h (s); with `adaptive`, the first step.
    pub step: f64,
    /// End time (s).
    pub duration: f64,
    /// HHT alpha in [-1/3, 0]: 0 is the trapezoidal rule (no numerical
    /// damping), negative values damp high frequencies.
    pub alpha: f64,
    /// Step control by the local error estimate, relative to the largest
    /// displacement so far.
    pub adaptive: Option<f64>,
    /// Newton tolerance on the residual, relative to the force scale.
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Most steps a run may take, counting steps cut back and retried
    /// ([`DEFAULT_MAX_STEPS`] unless raised): `duration / step` above it is
    /// refused before the run, and a run whose cutbacks or step control
    /// take more steps stops with an error.
    pub max_steps: usize,
}

/// The steps a run may take unless `max_steps` says otherwise: 10^7, a
/// 1000 s run at a 0.1 ms step.
pub const DEFAULT_MAX_STEPS: usize = 10_000_000;

/// The smallest step-control tolerance: the local error estimate of a
/// smaller one is round-off, so the control would cut every step to its
/// floor.
pub const MIN_ADAPTIVE_TOLERANCE: f64 = 1e-12;

impl Default for TimeSettings {
    fn default() -> Self {
        Self {
            step: 1e-3,
            duration: 1.0,
            alpha: -0.05,
            adaptive: None,
            tolerance: 1e-10,
            max_iterations: 25,
            max_steps: DEFAULT_MAX_STEPS,
        }
    }
}

impl TimeSettings {
    /// Checks the settings; the message names what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.step.is_finite() && self.step > 0.0) {
            return Err(format!("time step {} must be positive", self.step));
        }
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return Err(format!("duration {} must be positive", self.duration));
        }
        if self.step > self.duration {
            return Err(format!(
                "time step {} is longer than the duration {}",
                self.step, self.duration
            ));
        }
        if !(-1.0 / 3.0..=0.0).contains(&self.alpha) {
            return Err(format!(
                "HHT alpha {} is outside [-1/3, 0], where the scheme is unconditionally stable and second-order accurate",
                self.alpha
            ));
        }
        if let Some(tol) = self.adaptive {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(format!("step-control tolerance {tol} must be positive"));
            }
            if tol < MIN_ADAPTIVE_TOLERANCE {
                return Err(format!(
                    "step-control tolerance {tol:e} is below {MIN_ADAPTIVE_TOLERANCE:e}, where the \
                     local error estimate is round-off and every step would be cut to its floor"
                ));
            }
        }
        let steps = self.duration / self.step;
        if steps > self.max_steps as f64 {
            return Err(format!(
                "duration {:e} s at step {:e} s is {steps:.3e} steps, more than the {} a run may \
                 take; lengthen the step, shorten the duration or raise max_steps",
                self.duration, self.step, self.max_steps
            ));
        }
        Ok(())
    }

    /// The memory the recorded history of a run of `coordinates`
    /// coordinates and `connections` connections takes at `duration / step`
    /// steps (a run with step control may take more or fewer).
    pub fn history_bytes(&self, coordinates: usize, connections: usize) -> u64 {
        let per_step = (3 * coordinates + connections + 3) * std::mem::size_of::<f64>()
            + 4 * std::mem::size_of::<Vec<f64>>();
        let steps = (self.duration / self.step).ceil() + 1.0;
        (steps * per_step as f64).min(u64::MAX as f64) as u64
    }
}

/// The state of the system: coordinates, velocities, accelerations.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub a: Vec<f64>,
}

/// Histories of a simulation, one entry per output time.
#[derive(Clone, Debug)]
pub struct TimeResponse {
    pub times: Vec<f64>,
    pub states: Vec<State>,
    /// Connection forces (N, tension positive), per time, per connection.
    pub forces: Vec<Vec<f64>>,
    /// Total energy (J): kinetic plus stored in bodies and connections.
    pub energy: Vec<f64>,
    /// Newton iterations taken to reach each state.
    pub iterations: Vec<usize>,
}

/// The integrator's view of a system.
struct Equations<'s> {
    system: &'s System<'s>,
    lin: Assembled,
    kins: Vec<Kinematics>,
    /// Force rows for the time forces: `(row, history)`.
    loads: Vec<(Row, History)>,
    speed: f64,
    profile: Option<Profile>,
    ramp: f64,
    nonlinear: Vec<usize>,
    n: usize,
}

impl Equations<'_> {
    /// `v_p` and `v_p'` of connection `k` at time t.
    fn prescribed(&self, k: usize, t: f64) -> (f64, f64) {
        let Some(p) = &self.profile else {
            return (0.0, 0.0);
        };
        let (r, dr) = if self.ramp > 0.0 && t < self.ramp {
            let w = std::f64::consts::PI / self.ramp;
            (0.5 * (1.0 - (w * t).cos()), 0.5 * w * (w * t).sin())
        } else {
            (1.0, 0.0)
        };
        self.kins[k].tracks.iter().fold((0.0, 0.0), |acc, &(x, c)| {
            let (z, dz) = p.at(self.speed * t + x);
            (
                acc.0 + c * r * z,
                acc.1 + c * (r * self.speed * dz + dr * z),
            )
        })
    }

    /// Elongation and rate of connection k.
    fn elongation(&self, k: usize, x: &[f64], v: &[f64], t: f64) -> (f64, f64) {
        let (vp, vpd) = self.prescribed(k, t);
        (self.kins[k].apply(x) + vp, self.kins[k].apply(v) + vpd)
    }

    /// Internal minus external force `r(x, v, t) = D v + K x + g F_nl - f(t)`,
    /// where the linear connections' prescribed motion is part of f.
    fn residual_force(&self, x: &[f64], v: &[f64], t: f64) -> Vec<f64> {
        let mut r = vec![0.0; self.n];
        add_mul(&mut r, &self.lin.stiffness, x);
        add_mul(&mut r, &self.lin.damping, v);
        for (k, c) in self.system.connections.iter().enumerate() {
            let kin = &self.kins[k];
            if c.law.is_linear() {
                let (vp, vpd) = self.prescribed(k, t);
                let (ck, cb) = c.law.linearized();
                let f = ck * vp + cb * vpd;
                for &(i, g) in &kin.row {
                    r[i] += g * f;
                }
            } else {
                let (e, ed) = self.elongation(k, x, v, t);
                let f = c.law.force(e, ed);
                for &(i, g) in &kin.row {
                    r[i] += g * f;
                }
            }
        }
        for (row, h) in &self.loads {
            let f = h.at(t);
            for &(i, g) in row {
                r[i] -= g * f;
            }
        }
        r
    }

    /// `M + c_v D_t + c_x K_t` with the nonlinear tangents at (x, v, t).
    fn jacobian(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        c_v: f64,
        c_x: f64,
    ) -> Result<SparseMat, MbsError> {
        let mut trip = sparse::triplets_of(&self.lin.mass, 1.0);
        trip.extend(sparse::triplets_of(&self.lin.damping, c_v));
        trip.extend(sparse::triplets_of(&self.lin.stiffness, c_x));
        for &k in &self.nonlinear {
            let (e, ed) = self.elongation(k, x, v, t);
            let (kv, kd) = self.system.connections[k].law.tangent(e, ed);
            let w = c_x * kv + c_v * kd;
            if w != 0.0 {
                for &(i, gi) in &self.kins[k].row {
                    for &(j, gj) in &self.kins[k].row {
                        trip.push(Triplet::new(i, j, w * gi * gj));
                    }
                }
            }
        }
        Ok(sparse::from_triplets(self.n, self.n, &trip)?)
    }

    /// Connection forces at a state.
    fn forces(&self, x: &[f64], v: &[f64], t: f64) -> Vec<f64> {
        self.system
            .connections
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let (e, ed) = self.elongation(k, x, v, t);
                c.law.force(e, ed)
            })
            .collect()
    }

    /// Kinetic energy plus the energy stored in the bodies and connections.
    fn energy(&self, s: &State, t: f64) -> f64 {
        let kinetic = 0.5 * dot(&s.v, &mul(&self.lin.mass, &s.v));
        // Body strain energy: K without the linear connections' part.
        let mut stored = 0.5 * dot(&s.x, &mul(&self.lin.stiffness, &s.x));
        for (k, c) in self.system.connections.iter().enumerate() {
            let (e, _) = self.elongation(k, &s.x, &s.v, t);
            if c.law.is_linear() {
                let ge = self.kins[k].apply(&s.x);
                stored -= c.law.potential(ge);
            }
            stored += c.law.potential(e);
        }
        kinetic + stored
    }
}

/// Integrates `system` from `initial` (rest if `None`) over
/// `settings.duration`.
pub fn simulate(
    system: &System,
    excitation: &Excitation,
    settings: &TimeSettings,
    initial: Option<State>,
) -> Result<TimeResponse, MbsError> {
    settings.validate().map_err(MbsError::Settings)?;
    let layout = system.layout();
    let n = layout.len;
    Budget::MACHINE.ensure(
        settings.history_bytes(n, system.connections.len()),
        &format!(
            "the history of {:.0} steps of {n} coordinates",
            (settings.duration / settings.step).ceil()
        ),
    )?;
    let kins = system.all_kinematics(&layout)?;
    let lin = system.assemble(&kins, false)?;
    let profile = excitation.profile.clone().or_else(|| {
        system.track.map(|t| Profile::Cosine {
            amplitude: t.amplitude,
            wavelength: t.wavelength,
        })
    });
    if let Some(p) = &profile {
        let (lo, hi) = p.range();
        for (c, kin) in system.connections.iter().zip(&kins) {
            for &(x, _) in &kin.tracks {
                let (s0, s1) = (x, excitation.speed * settings.duration + x);
                if s0.min(s1) < lo || s0.max(s1) > hi {
                    return Err(MbsError::Invalid {
                        connection: c.name.clone(),
                        what: format!(
                            "the wheel travels s = {:.4} .. {:.4} m but the track profile covers {lo} .. {hi} m",
                            s0.min(s1),
                            s0.max(s1)
                        ),
                    });
                }
            }
        }
    }
    let loads = excitation
        .forces
        .iter()
        .map(|f| force_row(system, &layout, f).map(|r| (r, f.history.clone())))
        .collect::<Result<Vec<_>, _>>()?;
    let nonlinear = system
        .connections
        .iter()
        .enumerate()
        .filter(|(_, c)| !c.law.is_linear())
        .map(|(k, _)| k)
        .collect();
    let eq = Equations {
        system,
        lin,
        kins,
        loads,
        speed: excitation.speed,
        profile,
        ramp: excitation.ramp.max(0.0),
        nonlinear,
        n,
    };

    // Initial acceleration from the equations at t = 0.
    let mut state = initial.unwrap_or_else(|| State {
        x: vec![0.0; n],
        v: vec![0.0; n],
        a: vec![0.0; n],
    });
    if state.x.len() != n || state.v.len() != n {
        return Err(MbsError::Settings(format!(
            "initial state has {} coordinates, the system {n}",
            state.x.len()
        )));
    }
    // At rest under no force (the default start, with the excitation
    // ramped from zero) the acceleration is zero, also where M is singular
    // (massless DOFs: a shell's rotation about its normal).
    let r0 = eq.residual_force(&state.x, &state.v, 0.0);
    if r0.iter().any(|v| *v != 0.0) {
        state.a = solve(
            &eq.lin.mass,
            &r0.iter().map(|v| -v).collect::<Vec<_>>(),
            0.0,
        )?;
    } else {
        state.a = vec![0.0; n];
    }

    let alpha = settings.alpha;
    let gamma = 0.5 - alpha;
    let beta = 0.25 * (1.0 - alpha).powi(2);
    let mut t = 0.0;
    let mut h = settings.step;
    let mut response = TimeResponse {
        times: vec![0.0],
        forces: vec![eq.forces(&state.x, &state.v, 0.0)],
        energy: vec![eq.energy(&state, 0.0)],
        states: vec![state.clone()],
        iterations: vec![0],
    };
    let mut x_scale = state.x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut linear_jacobian: Option<(f64, Factor)> = None;
    let mut steps = 0;
    while t < settings.duration * (1.0 - 1e-12) {
        steps += 1;
        if steps > settings.max_steps {
            return Err(MbsError::Settings(format!(
                "{} steps (counting steps cut back and retried) reach only t = {t:.6e} s of \
                 {} s, at a step of {h:.3e} s: more than the max_steps = {} a run may take; \
                 loosen `adaptive`, lengthen the step or raise max_steps",
                settings.max_steps, settings.duration, settings.max_steps
            )));
        }
        h = h.min(settings.duration - t);
        let t1 = t + h;
        let r_n = eq.residual_force(&state.x, &state.v, t);
        let x_pred: Vec<f64> = (0..n)
            .map(|i| state.x[i] + h * state.v[i] + h * h * (0.5 - beta) * state.a[i])
            .collect();
        let v_pred: Vec<f64> = (0..n)
            .map(|i| state.v[i] + h * (1.0 - gamma) * state.a[i])
            .collect();
        let mut a = state.a.clone();
        let mut iterations = 0;
        let (c_v, c_x) = ((1.0 + alpha) * gamma * h, (1.0 + alpha) * beta * h * h);
        loop {
            let x1: Vec<f64> = (0..n).map(|i| x_pred[i] + beta * h * h * a[i]).collect();
            let v1: Vec<f64> = (0..n).map(|i| v_pred[i] + gamma * h * a[i]).collect();
            let r1 = eq.residual_force(&x1, &v1, t1);
            let ma = mul(&eq.lin.mass, &a);
            let res: Vec<f64> = (0..n)
                .map(|i| ma[i] + (1.0 + alpha) * r1[i] - alpha * r_n[i])
                .collect();
            let scale = norm(&ma)
                .max(norm(&r1))
                .max(norm(&r_n))
                .max(f64::MIN_POSITIVE);
            if iterations > 0 && norm(&res) <= settings.tolerance * scale {
                break;
            }
            if iterations == settings.max_iterations {
                break;
            }
            let neg: Vec<f64> = res.iter().map(|v| -v).collect();
            let da = if eq.nonlinear.is_empty() {
                // Linear: one factorisation per step size.
                if linear_jacobian.as_ref().is_none_or(|(hh, _)| *hh != h) {
                    let j = eq.jacobian(&x1, &v1, t1, c_v, c_x)?;
                    linear_jacobian = Some((h, Factor::new(&j, 0.0)?));
                }
                let factor = &linear_jacobian
                    .as_ref()
                    .map(|(_, f)| f)
                    .ok_or(MbsError::Singular { omega: 0.0 })?;
                let b = Mat::from_fn(n, 1, |i, _| neg[i]);
                let x = factor.solve(b.as_ref());
                (0..n).map(|i| x[(i, 0)]).collect::<Vec<f64>>()
            } else {
                let j = eq.jacobian(&x1, &v1, t1, c_v, c_x)?;
                solve(&j, &neg, 0.0)?
            };
            for i in 0..n {
                a[i] += da[i];
            }
            iterations += 1;
            // A linear step is solved exactly by one Newton step; otherwise
            // stop when the increment stagnates at round-off (the residual's
            // own scale is the net of large, cancelling terms).
            if eq.nonlinear.is_empty() || norm(&da) <= 1e-12 * norm(&a).max(f64::MIN_POSITIVE) {
                break;
            }
        }
        if iterations == settings.max_iterations {
            // Newton cycles at a kink of a force law (a bump stop closing):
            // cut the step back and retry.
            if h > settings.step * MIN_STEP_FRACTION {
                h *= 0.5;
                continue;
            }
            return Err(MbsError::NoConvergence {
                time: t1,
                iterations,
            });
        }
        let x1: Vec<f64> = (0..n).map(|i| x_pred[i] + beta * h * h * a[i]).collect();
        let v1: Vec<f64> = (0..n).map(|i| v_pred[i] + gamma * h * a[i]).collect();
        if let Some(tol) = settings.adaptive {
            // Zienkiewicz-Xie: e = h^2 (beta - 1/6) (a1 - a0).
            let e = (0..n)
                .map(|i| (h * h * (beta - 1.0 / 6.0) * (a[i] - state.a[i])).abs())
                .fold(0.0, f64::max);
            let scale = x_scale
                .max(x1.iter().fold(0.0_f64, |m, v| m.max(v.abs())))
                .max(1e-12);
            if e > tol * scale && h > settings.step * MIN_STEP_FRACTION {
                h *= 0.5;
                continue;
            }
            if e < 0.1 * tol * scale {
                h = (h * 1.5).min(settings.step * 100.0);
            }
        }
        if settings.adaptive.is_none() && h < settings.step {
            // Back towards the requested step after a cutback.
            h = (2.0 * h).min(settings.step);
        }
        t = t1;
        state = State { x: x1, v: v1, a };
        x_scale = x_scale.max(state.x.iter().fold(0.0_f64, |m, v| m.max(v.abs())));
        if !state.x.iter().all(|v| v.is_finite()) {
            return Err(MbsError::NoConvergence {
                time: t,
                iterations,
            });
        }
        response.times.push(t);
        response.forces.push(eq.forces(&state.x, &state.v, t));
        response.energy.push(eq.energy(&state, t));
        response.iterations.push(iterations);
        response.states.push(state.clone());
    }
    Ok(response)
}

/// The row over all coordinates of a point's displacement along `direction`.
fn force_row(
    system: &System,
    layout: &crate::system::Layout,
    f: &TimeForce,
) -> Result<Row, MbsError> {
    let d = flexbody_reduce::method::unit(f.direction).ok_or_else(|| MbsError::Invalid {
        connection: f.name.clone(),
        what: "force direction is zero".into(),
    })?;
    if let Endpoint::Ground | Endpoint::Track { .. } = f.at {
        return Err(MbsError::Invalid {
            connection: f.name.clone(),
            what: "a force must act on a body".into(),
        });
    }
    let (rows, _) = system.endpoint(&f.name, &f.at, d, layout)?;
    let mut row = Row::new();
    for (r, da) in rows.into_iter().zip(d) {
        row.extend(r.into_iter().map(|(i, v)| (i, da * v)));
    }
    Ok(row)
}

fn mul(a: &SparseMat, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.nrows()];
    add_mul(&mut y, a, x);
    y
}

/// `y += A x` for a sparse A.
fn add_mul(y: &mut [f64], a: &SparseMat, x: &[f64]) {
    let r = a.as_ref();
    for (j, xj) in x.iter().enumerate() {
        if *xj == 0.0 {
            continue;
        }
        for (i, v) in r.row_idx_of_col(j).zip(r.val_of_col(j)) {
            y[i] += v * xj;
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    a.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// A solve with the Jacobian (symmetric `LDL^T` or LU, [`Factor`]).
fn solve(a: &SparseMat, b: &[f64], omega: f64) -> Result<Vec<f64>, MbsError> {
    let rhs = Mat::from_fn(b.len(), 1, |i, _| b[i]);
    let x = Factor::new(a, omega)?.solve(rhs.as_ref());
    let out: Vec<f64> = x.col(0).iter().copied().collect();
    if out.iter().all(|v| v.is_finite()) {
        Ok(out)
    } else {
        Err(MbsError::Singular { omega })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{harmonic_response, Connection, ForceLaw, RigidBody, Track};
    use flexbody_fem::DofKind;

    fn mass(name: &str, m: f64, z: f64) -> RigidBody {
        RigidBody {
            name: name.into(),
            mass: m,
            inertia: [0.0; 6],
            center: [0.0, 0.0, z],
            active: vec![DofKind::Uz],
        }
    }

    fn rigid(body: usize, z: f64) -> Endpoint {
        Endpoint::Rigid {
            body,
            point: [0.0, 0.0, z],
        }
    }

    /// Two masses on springs, a bump stop between them.
    fn two_masses(damping: f64, stop: bool) -> System<'static> {
        let mut connections = vec![
            Connection::linear(
                "lower",
                Endpoint::Ground,
                rigid(0, 0.0),
                [0.0, 0.0, 1.0],
                4e5,
                damping,
            ),
            Connection::linear(
                "upper",
                rigid(0, 0.0),
                rigid(1, 1.0),
                [0.0, 0.0, 1.0],
                1e5,
                0.0,
            ),
        ];
        if stop {
            connections.push(Connection {
                name: "stop".into(),
                a: rigid(0, 0.0),
                b: rigid(1, 1.0),
                direction: [0.0, 0.0, 1.0],
                law: ForceLaw::BumpStop {
                    clearance: 0.01,
                    stiffness: 2e6,
                },
            });
        }
        System {
            flexible: vec![],
            rigid: vec![mass("wheel", 50.0, 0.0), mass("body", 400.0, 1.0)],
            connections,
            track: None,
        }
    }

    fn released(dz: f64) -> State {
        State {
            x: vec![0.0, dz],
            v: vec![0.0, 0.0],
            a: vec![0.0, 0.0],
        }
    }

    /// The trapezoidal rule (`alpha = 0`) with `step` over `duration`.
    fn trapezoidal(step: f64, duration: f64) -> TimeSettings {
        TimeSettings {
            step,
            duration,
            alpha: 0.0,
            ..Default::default()
        }
    }

    /// `s` without excitation from the state `released(-0.05)`.
    fn from_released(s: &System, settings: &TimeSettings) -> TimeResponse {
        simulate(s, &Excitation::default(), settings, Some(released(-0.05))).unwrap()
    }

    /// The largest deviation of the energy of `r` from `e0`.
    fn energy_drift(r: &TimeResponse, e0: f64) -> f64 {
        r.energy.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max)
    }

    #[test]
    fn trapezoidal_rule_conserves_the_energy_of_a_linear_system() {
        let s = two_masses(0.0, false);
        let settings = trapezoidal(1e-3, 2.0);
        let r = from_released(&s, &settings);
        let e0 = r.energy[0];
        assert!(e0 > 0.0);
        let drift = energy_drift(&r, e0);
        assert!(drift < 1e-10 * e0, "{drift} of {e0}");
        assert!(
            r.iterations[1..].iter().all(|&k| k == 1),
            "a linear step takes one Newton iteration"
        );
    }

    #[test]
    fn a_bump_stop_engages_and_energy_stays_within_the_schemes_error() {
        let s = two_masses(0.0, true);
        let settings = trapezoidal(2e-4, 1.0);
        let r = from_released(&s, &settings);
        let stop: Vec<f64> = r.forces.iter().map(|f| f[2]).collect();
        assert!(stop.iter().any(|f| *f < -1e3), "the stop pushes");
        assert!(stop.contains(&0.0), "and opens again");
        let e0 = r.energy[0];
        let drift = energy_drift(&r, e0);
        assert!(drift < 2e-3 * e0, "{drift} of {e0}");
        // Halving the step cuts the drift about fourfold (second order).
        let fine = TimeSettings {
            step: 1e-4,
            ..settings
        };
        let r2 = from_released(&s, &fine);
        let drift2 = energy_drift(&r2, e0);
        assert!(drift2 < 0.5 * drift, "{drift2} vs {drift}");
    }

    #[test]
    fn damping_only_takes_energy_out() {
        // Linear with a viscous damper: the trapezoidal rule's energy balance
        // is exact, E_{n+1} - E_n = -h v_avg^T D v_avg, so E never grows.
        let s = two_masses(2e3, false);
        let settings = trapezoidal(5e-4, 1.0);
        let r = from_released(&s, &settings);
        for w in r.energy.windows(2) {
            assert!(w[1] <= w[0] * (1.0 + 1e-12), "{} -> {}", w[0], w[1]);
        }
        assert!(r.energy.last().unwrap() < &(0.9 * r.energy[0]));
        // Nonlinear: bump stop and friction-like damper, HHT damping; the
        // energy may wobble at the stop's kink within the scheme's error but
        // never exceeds its start and falls overall.
        let mut s = two_masses(0.0, true);
        s.connections.push(Connection {
            name: "friction".into(),
            a: rigid(0, 0.0),
            b: rigid(1, 1.0),
            direction: [0.0, 0.0, 1.0],
            law: ForceLaw::FrictionDamper {
                force: 300.0,
                velocity: 0.01,
            },
        });
        let settings = TimeSettings {
            alpha: -0.2,
            ..settings
        };
        let r = from_released(&s, &settings);
        let e0 = r.energy[0];
        assert!(r.energy.iter().all(|e| *e <= e0 * (1.0 + 1e-9)));
        assert!(r.energy.last().unwrap() < &(0.5 * e0));
    }

    #[test]
    fn steady_state_equals_the_harmonic_response() {
        // A damped mass on the track at speed V: after the transient the
        // response is the harmonic one at Omega = 2 pi V / L_w.
        let track = Track {
            amplitude: 0.01,
            wavelength: 5.0,
        };
        let s = System {
            flexible: vec![],
            rigid: vec![mass("m", 500.0, 0.5)],
            connections: vec![Connection::linear(
                "spring",
                Endpoint::Track { x: 0.7 },
                rigid(0, 0.5),
                [0.0, 0.0, 1.0],
                2e5,
                6e3,
            )],
            track: Some(track),
        };
        let speed = 30.0;
        let omega = 2.0 * std::f64::consts::PI * speed / track.wavelength;
        let h = harmonic_response(&s, omega).unwrap();
        let (re, im) = (h.rigid[0].0[0], h.rigid[0].1[0]);
        let period = 2.0 * std::f64::consts::PI / omega;
        let settings = TimeSettings {
            step: period / 400.0,
            duration: 40.0 * period,
            alpha: 0.0,
            ..Default::default()
        };
        let r = simulate(
            &s,
            &Excitation {
                speed,
                ..Default::default()
            },
            &settings,
            None,
        )
        .unwrap();
        let amp = re.hypot(im);
        let last = r.times.len() - 401;
        for k in last..r.times.len() {
            let t = r.times[k];
            let want = re * (omega * t).cos() - im * (omega * t).sin();
            assert!(
                (r.states[k].x[0] - want).abs() < 1e-3 * amp,
                "t = {t}: {} vs {want}",
                r.states[k].x[0]
            );
        }
    }

    #[test]
    fn a_force_history_moves_a_mass_to_its_static_deflection() {
        // A force ramped to F by a table settles a damped mass at F / k.
        let (m, k, f) = (10.0, 1e4, 250.0);
        let s = System {
            rigid: vec![mass("m", m, 0.0)],
            connections: vec![Connection::linear(
                "k",
                Endpoint::Ground,
                rigid(0, 0.0),
                [0.0, 0.0, 1.0],
                k,
                2.0 * (k * m).sqrt(),
            )],
            ..Default::default()
        };
        let push = Excitation {
            forces: vec![TimeForce {
                name: "push".into(),
                at: rigid(0, 0.0),
                direction: [0.0, 0.0, 1.0],
                history: History::Table(vec![[0.0, 0.0], [0.05, f]]),
            }],
            ..Default::default()
        };
        let settings = TimeSettings {
            step: 1e-3,
            duration: 1.0,
            alpha: 0.0,
            ..Default::default()
        };
        let r = simulate(&s, &push, &settings, None).unwrap();
        let last = r.states.last().unwrap().x[0];
        assert!((last - f / k).abs() < 1e-6 * f / k, "{last}");
        // The spring carries the force: tension F at rest.
        assert!((r.forces.last().unwrap()[0] - f).abs() < 1e-4 * f);
    }

    #[test]
    fn a_run_whose_step_control_takes_more_than_max_steps_stops_with_an_error() {
        let s = two_masses(0.0, false);
        // 100 steps of 1 ms asked for; the tightest tolerance cuts each to
        // its floor of step / 1024, so the run needs about 10^5 steps.
        let settings = TimeSettings {
            step: 1e-3,
            duration: 0.1,
            adaptive: Some(MIN_ADAPTIVE_TOLERANCE),
            max_steps: 1000,
            ..Default::default()
        };
        let e = simulate(&s, &Excitation::default(), &settings, Some(released(-0.05)))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("1000 steps (counting steps cut back and retried) reach only t =")
                && e.contains("raise max_steps"),
            "{e}"
        );
        // The same run with the steps it needs.
        let enough = TimeSettings {
            max_steps: 200_000,
            ..settings
        };
        let r = simulate(&s, &Excitation::default(), &enough, Some(released(-0.05))).unwrap();
        assert!(r.times.len() > 1000, "{} steps", r.times.len());
    }

    #[test]
    fn unusable_settings_and_profiles_are_named() {
        let s = two_masses(0.0, false);
        for (settings, needle) in [
            (
                TimeSettings {
                    step: 0.0,
                    ..Default::default()
                },
                "time step 0",
            ),
            (
                TimeSettings {
                    step: 2.0,
                    duration: 1.0,
                    ..Default::default()
                },
                "longer than the duration",
            ),
            (
                TimeSettings {
                    alpha: -0.5,
                    ..Default::default()
                },
                "outside [-1/3, 0]",
            ),
            (
                TimeSettings {
                    step: 1e-9,
                    duration: 1.0,
                    ..Default::default()
                },
                "is 1.000e9 steps, more than the 10000000 a run may take",
            ),
            (
                TimeSettings {
                    adaptive: Some(1e-300),
                    ..Default::default()
                },
                "tolerance 1e-300 is below 1e-12",
            ),
        ] {
            let e = simulate(&s, &Excitation::default(), &settings, None)
                .unwrap_err()
                .to_string();
            assert!(e.contains(needle), "{e}");
        }
        let track = System {
            connections: vec![Connection::linear(
                "w",
                Endpoint::Track { x: 0.0 },
                rigid(0, 0.0),
                [0.0, 0.0, 1.0],
                1e5,
                0.0,
            )],
            rigid: vec![mass("m", 10.0, 0.0)],
            track: Some(Track {
                amplitude: 0.0,
                wavelength: 1.0,
            }),
            flexible: vec![],
        };
        let short = Excitation {
            speed: 10.0,
            profile: Some(Profile::Table {
                s: vec![0.0, 1.0, 2.0],
                z: vec![0.0, 0.01, 0.0],
            }),
            ..Default::default()
        };
        let e = simulate(&track, &short, &TimeSettings::default(), None)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("connection 'w'") && e.contains("covers 0 .. 2 m"),
            "{e}"
        );
    }
}
