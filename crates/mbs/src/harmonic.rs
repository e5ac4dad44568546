//! Assembly of the linear MBS equations (report eq. 11) and their harmonic
//! steady state: `(K - Omega^2 M + i Omega D) q = f`.

use crate::body::{FlexibleBody, RigidBody, Row};
use crate::connection::{Connection, Endpoint, Track};
use crate::MbsError;
use faer::linalg::solvers::Solve;
use faer::sparse::Triplet;
use faer::Mat;
use flexbody_fem::{Dof, DofKind};
use flexbody_linalg::{sparse, SparseMat};

/// A linear multibody system.
#[derive(Clone, Debug, Default)]
pub struct System<'a> {
    pub flexible: Vec<FlexibleBody<'a>>,
    pub rigid: Vec<RigidBody>,
    pub connections: Vec<Connection>,
    pub track: Option<Track>,
}

/// The assembled equations of motion (eq. 11): `M q'' + D q' + K q = f`,
/// with the complex amplitude `f = f_re + i f_im` of the base excitation
/// through the springs (damper loads depend on Omega and are added by
/// [`harmonic_response`]).
#[derive(Clone, Debug)]
pub struct Assembled {
    pub mass: SparseMat,
    pub damping: SparseMat,
    pub stiffness: SparseMat,
    pub load_re: Vec<f64>,
    pub load_im: Vec<f64>,
}

/// Steady-state response at one frequency; complex amplitudes as (re, im).
#[derive(Clone, Debug)]
pub struct HarmonicResponse {
    /// Excitation frequency Omega (rad/s).
    pub omega: f64,
    /// FE displacement amplitudes of each flexible body: (re, im).
    pub flexible: Vec<(Vec<f64>, Vec<f64>)>,
    /// Coordinates of each flexible body (q): (re, im).
    pub flexible_coords: Vec<(Vec<f64>, Vec<f64>)>,
    /// Coordinates of each rigid body: (re, im).
    pub rigid: Vec<(Vec<f64>, Vec<f64>)>,
    /// Force amplitude in each connection (N), tension positive: (re, im).
    pub forces: Vec<(f64, f64)>,
}

/// Translation rows of one endpoint over all coordinates, and its
/// prescribed displacement (complex, per component).
struct EndpointMotion {
    rows: [Row; 3],
    prescribed: [(f64, f64); 3],
}

/// Kinematics of one connection: the elongation `v = g q + v_p`, with the
/// row `g` over all coordinates and the prescribed part `v_p` (complex).
struct Kinematics {
    row: Row,
    prescribed: (f64, f64),
}

/// Coordinate offsets of the bodies in the system vector.
struct Layout {
    flexible: Vec<usize>,
    rigid: Vec<usize>,
    len: usize,
}

impl System<'_> {
    fn layout(&self) -> Layout {
        let mut at = 0;
        let mut next = |len: usize| {
            let o = at;
            at += len;
            o
        };
        let flexible = self.flexible.iter().map(|b| next(b.len())).collect();
        let rigid = self.rigid.iter().map(|b| next(b.len())).collect();
        Layout {
            flexible,
            rigid,
            len: at,
        }
    }

    fn endpoint(
        &self,
        c: &Connection,
        e: &Endpoint,
        d: [f64; 3],
        layout: &Layout,
    ) -> Result<EndpointMotion, MbsError> {
        let at_rest = |prescribed| EndpointMotion {
            rows: [vec![], vec![], vec![]],
            prescribed,
        };
        let zero = [(0.0, 0.0); 3];
        match e {
            Endpoint::Ground => Ok(at_rest(zero)),
            Endpoint::Track { x } => {
                let track = self
                    .track
                    .ok_or_else(|| MbsError::NoTrack(c.name.clone()))?;
                Ok(at_rest([(0.0, 0.0), (0.0, 0.0), track.amplitude_at(*x)]))
            }
            Endpoint::Rigid { body, point } => {
                let b = self.rigid.get(*body).ok_or(MbsError::UnknownRigidBody {
                    connection: c.name.clone(),
                    body: *body,
                })?;
                let at = layout.rigid[*body];
                let rows = b
                    .point_rows(*point)
                    .map(|r| r.into_iter().map(|(i, v)| (i + at, v)).collect());
                Ok(EndpointMotion {
                    rows,
                    prescribed: zero,
                })
            }
            Endpoint::Flexible { body, node } => {
                let b = self
                    .flexible
                    .get(*body)
                    .ok_or(MbsError::UnknownFlexibleBody {
                        connection: c.name.clone(),
                        body: *body,
                    })?;
                let at = layout.flexible[*body];
                let kinds = [DofKind::Ux, DofKind::Uy, DofKind::Uz];
                let mut rows: [Row; 3] = [vec![], vec![], vec![]];
                for (a, kind) in kinds.into_iter().enumerate() {
                    if d[a] == 0.0 {
                        continue;
                    }
                    let row = b
                        .dof_row(Dof::new(*node, kind))
                        .ok_or(MbsError::MissingDof {
                            connection: c.name.clone(),
                            node: *node,
                            dof: kind.name(),
                        })?;
                    rows[a] = row.into_iter().map(|(i, v)| (i + at, v)).collect();
                }
                Ok(EndpointMotion {
                    rows,
                    prescribed: zero,
                })
            }
        }
    }

    /// `v_n = d^T (u_b - u_a)` (eq. 9) as a row over the coordinates plus
    /// the prescribed part.
    fn kinematics(&self, c: &Connection, layout: &Layout) -> Result<Kinematics, MbsError> {
        let d = flexbody_reduce::method::unit(c.direction).ok_or_else(|| MbsError::Invalid {
            connection: c.name.clone(),
            what: "direction is zero".into(),
        })?;
        let valid = |v: f64| v.is_finite() && v >= 0.0;
        if !(valid(c.stiffness) && valid(c.damping)) {
            return Err(MbsError::Invalid {
                connection: c.name.clone(),
                what: format!(
                    "stiffness {} and damping {} must be finite and not negative",
                    c.stiffness, c.damping
                ),
            });
        }
        let ea = self.endpoint(c, &c.a, d, layout)?;
        let eb = self.endpoint(c, &c.b, d, layout)?;
        let mut row: Row = Vec::new();
        let mut prescribed = (0.0, 0.0);
        for (a, da) in d.iter().enumerate() {
            row.extend(eb.rows[a].iter().map(|&(i, v)| (i, da * v)));
            row.extend(ea.rows[a].iter().map(|&(i, v)| (i, -da * v)));
            prescribed.0 += da * (eb.prescribed[a].0 - ea.prescribed[a].0);
            prescribed.1 += da * (eb.prescribed[a].1 - ea.prescribed[a].1);
        }
        Ok(Kinematics { row, prescribed })
    }

    /// The equations of motion of the system (eq. 11): body matrices on the
    /// diagonal, spring stiffness `c_n g_n g_n^T` (eq. 10-11) coupling them.
    pub fn assemble(&self) -> Result<Assembled, MbsError> {
        self.assemble_with_kinematics().map(|(a, _)| a)
    }

    /// [`System::assemble`], also returning each connection's kinematics.
    fn assemble_with_kinematics(&self) -> Result<(Assembled, Vec<Kinematics>), MbsError> {
        let layout = self.layout();
        let n = layout.len;
        let (mut m, mut d, mut k) = (Vec::new(), Vec::new(), Vec::new());
        for (b, &at) in self.flexible.iter().zip(&layout.flexible) {
            let [tm, td, tk] = b.triplets(at);
            m.extend(tm);
            d.extend(td);
            k.extend(tk);
        }
        for (b, &at) in self.rigid.iter().zip(&layout.rigid) {
            m.extend(b.mass_triplets(at));
        }
        let (mut load_re, mut load_im) = (vec![0.0; n], vec![0.0; n]);
        let mut kins = Vec::with_capacity(self.connections.len());
        for c in &self.connections {
            let kin = self.kinematics(c, &layout)?;
            for &(i, gi) in &kin.row {
                for &(j, gj) in &kin.row {
                    k.push(Triplet::new(i, j, c.stiffness * gi * gj));
                    if c.damping != 0.0 {
                        d.push(Triplet::new(i, j, c.damping * gi * gj));
                    }
                }
                // v = g q + v_p; the spring's energy c v^2 / 2 gives the
                // stiffness c g g^T and the load -c g v_p of the prescribed
                // motion.
                load_re[i] -= c.stiffness * gi * kin.prescribed.0;
                load_im[i] -= c.stiffness * gi * kin.prescribed.1;
            }
            kins.push(kin);
        }
        let assembled = Assembled {
            mass: sparse::from_triplets(n, n, &m)?,
            damping: sparse::from_triplets(n, n, &d)?,
            stiffness: sparse::from_triplets(n, n, &k)?,
            load_re,
            load_im,
        };
        Ok((assembled, kins))
    }
}

/// Harmonic steady state at `omega` (rad/s).
pub fn harmonic_response(system: &System, omega: f64) -> Result<HarmonicResponse, MbsError> {
    let layout = system.layout();
    let n = layout.len;
    let (
        Assembled {
            mass,
            damping,
            stiffness,
            mut load_re,
            mut load_im,
        },
        kins,
    ) = system.assemble_with_kinematics()?;
    // Damper loads of the prescribed motion: -b g (i Omega v_p).
    for (c, kin) in system.connections.iter().zip(&kins) {
        for &(i, gi) in &kin.row {
            load_re[i] += omega * c.damping * gi * kin.prescribed.1;
            load_im[i] -= omega * c.damping * gi * kin.prescribed.0;
        }
    }
    let a = sparse::add_scaled(&stiffness, -omega * omega, &mass)?;
    let damped = damping.compute_nnz() > 0 && omega != 0.0;
    let (q_re, q_im) = if damped || load_im.iter().any(|v| *v != 0.0) {
        // [A  -B; B  A] [x; y] = [f_re; f_im], B = Omega D.
        let mut t = Vec::new();
        for e in sparse::triplets_of(&a, 1.0) {
            t.push(Triplet::new(e.row, e.col, e.val));
            t.push(Triplet::new(e.row + n, e.col + n, e.val));
        }
        for e in sparse::triplets_of(&damping, omega) {
            t.push(Triplet::new(e.row, e.col + n, -e.val));
            t.push(Triplet::new(e.row + n, e.col, e.val));
        }
        let big = sparse::from_triplets(2 * n, 2 * n, &t)?;
        let rhs: Vec<f64> = load_re.iter().chain(load_im.iter()).copied().collect();
        let x = solve(&big, &rhs, omega)?;
        (x[..n].to_vec(), x[n..].to_vec())
    } else {
        (solve(&a, &load_re, omega)?, vec![0.0; n])
    };
    let part = |at: usize, len: usize| (q_re[at..at + len].to_vec(), q_im[at..at + len].to_vec());
    let flexible_coords: Vec<(Vec<f64>, Vec<f64>)> = system
        .flexible
        .iter()
        .zip(&layout.flexible)
        .map(|(b, &at)| part(at, b.len()))
        .collect();
    let flexible = system
        .flexible
        .iter()
        .zip(&flexible_coords)
        .map(|(b, (re, im))| (b.displacements(re), b.displacements(im)))
        .collect();
    let rigid = system
        .rigid
        .iter()
        .zip(&layout.rigid)
        .map(|(b, &at)| part(at, b.len()))
        .collect();
    let forces = system
        .connections
        .iter()
        .zip(&kins)
        .map(|(c, kin)| {
            let v_re = kin.row.iter().map(|&(i, g)| g * q_re[i]).sum::<f64>() + kin.prescribed.0;
            let v_im = kin.row.iter().map(|&(i, g)| g * q_im[i]).sum::<f64>() + kin.prescribed.1;
            // F = (c + i Omega b) v.
            (
                c.stiffness * v_re - omega * c.damping * v_im,
                c.stiffness * v_im + omega * c.damping * v_re,
            )
        })
        .collect();
    Ok(HarmonicResponse {
        omega,
        flexible,
        flexible_coords,
        rigid,
        forces,
    })
}

/// Sparse LU solve with a residual check (a singular dynamic stiffness
/// shows up as a non-finite or inaccurate solution).
fn solve(a: &SparseMat, b: &[f64], omega: f64) -> Result<Vec<f64>, MbsError> {
    let n = b.len();
    let lu = a.sp_lu().map_err(|_| MbsError::Singular { omega })?;
    let rhs = Mat::from_fn(n, 1, |i, _| b[i]);
    let x = lu.solve(rhs.as_ref());
    let r = a * &x - &rhs;
    let finite = (0..n).all(|i| x[(i, 0)].is_finite());
    let a_max = a.as_ref().val().iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let scale = a_max * x.norm_max() + rhs.norm_max();
    let accurate = r.norm_max() <= 1e-8 * scale; // false for NaN too
    if !finite || !accurate {
        return Err(MbsError::Singular { omega });
    }
    Ok((0..n).map(|i| x[(i, 0)]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rigid mass on a spring-damper over the track: the closed form
    /// `x = (k + i Omega b) z / (k - m Omega^2 + i Omega b)`.
    #[test]
    fn rigid_mass_on_a_damped_track_spring_matches_the_closed_form() {
        let (m, k, b, a, wavelength, x) = (500.0, 2.0e5, 3.0e3, 0.01, 4.0, 0.7);
        let system = System {
            flexible: vec![],
            rigid: vec![RigidBody {
                name: "mass".into(),
                mass: m,
                inertia: [1.0; 6],
                center: [x, 0.0, 0.5],
                active: vec![DofKind::Uz],
            }],
            connections: vec![Connection {
                name: "spring".into(),
                a: Endpoint::Track { x },
                b: Endpoint::Rigid {
                    body: 0,
                    point: [x, 0.0, 0.5],
                },
                direction: [0.0, 0.0, 1.0],
                stiffness: k,
                damping: b,
            }],
            track: Some(Track {
                amplitude: a,
                wavelength,
            }),
        };
        for omega in [0.0, 5.0, 20.0, 80.0] {
            let r = harmonic_response(&system, omega).unwrap();
            let phase = 2.0 * std::f64::consts::PI * x / wavelength;
            let z = (a * phase.cos(), a * phase.sin());
            // (k + i w b) z / (k - m w^2 + i w b), complex arithmetic by hand.
            let num = (k * z.0 - omega * b * z.1, k * z.1 + omega * b * z.0);
            let den = (k - m * omega * omega, omega * b);
            let d2 = den.0 * den.0 + den.1 * den.1;
            let want = (
                (num.0 * den.0 + num.1 * den.1) / d2,
                (num.1 * den.0 - num.0 * den.1) / d2,
            );
            let got = (r.rigid[0].0[0], r.rigid[0].1[0]);
            assert!(
                (got.0 - want.0).abs() + (got.1 - want.1).abs() < 1e-12 * a,
                "{omega}: {got:?} vs {want:?}"
            );
            // Tension F pulls the mass back: m x'' = -F, so F = m Omega^2 x.
            let f = r.forces[0];
            assert!(
                (f.0 - m * omega * omega * got.0).abs() < 1e-9 * k * a,
                "{f:?}"
            );
            assert!(
                (f.1 - m * omega * omega * got.1).abs() < 1e-9 * k * a,
                "{f:?}"
            );
        }
    }

    #[test]
    fn undamped_resonance_is_reported() {
        let (m, k) = (2.0, 8.0);
        let system = System {
            rigid: vec![RigidBody {
                name: "mass".into(),
                mass: m,
                inertia: [0.0; 6],
                center: [0.0; 3],
                active: vec![DofKind::Uz],
            }],
            connections: vec![Connection {
                name: "spring".into(),
                a: Endpoint::Ground,
                b: Endpoint::Rigid {
                    body: 0,
                    point: [0.0; 3],
                },
                direction: [0.0, 0.0, 1.0],
                stiffness: k,
                damping: 0.0,
            }],
            ..Default::default()
        };
        assert!(matches!(
            harmonic_response(&system, 2.0),
            Err(MbsError::Singular { .. })
        ));
    }
}
