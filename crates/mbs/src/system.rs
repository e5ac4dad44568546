//! A linear multibody system with flexible and rigid bodies: coordinate
//! layout, connection kinematics (report eq. 8-9) and assembly of the
//! equations of motion (eq. 11).

use crate::body::{FlexibleBody, RigidBody, Row};
use crate::connection::{Connection, Endpoint, Track};
use crate::MbsError;
use faer::sparse::Triplet;
use flexbody_fem::{Dof, DofKind};
use flexbody_linalg::{sparse, SparseMat};

/// A multibody system.
#[derive(Clone, Debug, Default)]
pub struct System<'a> {
    pub flexible: Vec<FlexibleBody<'a>>,
    pub rigid: Vec<RigidBody>,
    pub connections: Vec<Connection>,
    /// The harmonic track profile (frequency domain; the time domain takes
    /// a profile and a speed, see [`crate::time::Excitation`]).
    pub track: Option<Track>,
}

/// Coordinate offsets of the bodies in the system vector.
#[derive(Clone, Debug)]
pub struct Layout {
    pub flexible: Vec<usize>,
    pub rigid: Vec<usize>,
    pub len: usize,
}

/// Kinematics of one connection: the elongation `v = g x + v_p`, with the
/// row `g` over all coordinates and the prescribed part
/// `v_p = sum_k c_k z(s_k)`: `tracks` holds `(x_k, c_k)` for each end on the
/// track (wheel position x_k along the vehicle, coefficient `±d_z`).
#[derive(Clone, Debug)]
pub struct Kinematics {
    pub row: Row,
    pub tracks: Vec<(f64, f64)>,
}

impl Kinematics {
    /// `g x` for a coordinate vector.
    pub fn apply(&self, x: &[f64]) -> f64 {
        self.row.iter().map(|&(i, g)| g * x[i]).sum()
    }
}

/// The assembled equations of motion: `M x'' + D x' + K x = f`.
#[derive(Clone, Debug)]
pub struct Assembled {
    pub mass: SparseMat,
    pub damping: SparseMat,
    pub stiffness: SparseMat,
}

impl System<'_> {
    /// Offsets of each body's coordinates.
    pub fn layout(&self) -> Layout {
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

    /// Translation rows of one endpoint, those along a zero component of
    /// `d` left empty for a flexible body, and, for a track end, its wheel
    /// position x. Errors name `name`, the connection or force at `e`.
    pub(crate) fn endpoint(
        &self,
        name: &str,
        e: &Endpoint,
        d: [f64; 3],
        layout: &Layout,
    ) -> Result<([Row; 3], Option<f64>), MbsError> {
        let none: [Row; 3] = [vec![], vec![], vec![]];
        match e {
            Endpoint::Ground => Ok((none, None)),
            Endpoint::Track { x } => Ok((none, Some(*x))),
            Endpoint::Rigid { body, point } => {
                let b = self.rigid.get(*body).ok_or(MbsError::UnknownRigidBody {
                    connection: name.to_owned(),
                    body: *body,
                })?;
                let at = layout.rigid[*body];
                let rows = b
                    .point_rows(*point)
                    .map(|r| r.into_iter().map(|(i, v)| (i + at, v)).collect());
                Ok((rows, None))
            }
            Endpoint::Flexible { body, node } => {
                let b = self
                    .flexible
                    .get(*body)
                    .ok_or(MbsError::UnknownFlexibleBody {
                        connection: name.to_owned(),
                        body: *body,
                    })?;
                let at = layout.flexible[*body];
                let mut rows = none;
                for (a, kind) in [DofKind::Ux, DofKind::Uy, DofKind::Uz]
                    .into_iter()
                    .enumerate()
                {
                    if d[a] == 0.0 {
                        continue;
                    }
                    let row = b
                        .dof_row(Dof::new(*node, kind))
                        .ok_or(MbsError::MissingDof {
                            connection: name.to_owned(),
                            node: *node,
                            dof: kind.name(),
                        })?;
                    rows[a] = row.into_iter().map(|(i, v)| (i + at, v)).collect();
                }
                Ok((rows, None))
            }
        }
    }

    /// `v_n = d^T (u_b - u_a)` (eq. 9) of connection `c`.
    pub fn kinematics(&self, c: &Connection, layout: &Layout) -> Result<Kinematics, MbsError> {
        let d = flexbody_reduce::method::unit(c.direction).ok_or_else(|| MbsError::Invalid {
            connection: c.name.clone(),
            what: "direction is zero".into(),
        })?;
        c.law.validate().map_err(|what| MbsError::Invalid {
            connection: c.name.clone(),
            what,
        })?;
        let (ra, ta) = self.endpoint(&c.name, &c.a, d, layout)?;
        let (rb, tb) = self.endpoint(&c.name, &c.b, d, layout)?;
        let mut row: Row = Vec::new();
        for (a, da) in d.iter().enumerate() {
            row.extend(rb[a].iter().map(|&(i, v)| (i, da * v)));
            row.extend(ra[a].iter().map(|&(i, v)| (i, -da * v)));
        }
        // The track moves along global z.
        let mut tracks = Vec::new();
        if let Some(x) = tb {
            tracks.push((x, d[2]));
        }
        if let Some(x) = ta {
            tracks.push((x, -d[2]));
        }
        if !tracks.is_empty() && self.track.is_none() {
            return Err(MbsError::NoTrack(c.name.clone()));
        }
        Ok(Kinematics { row, tracks })
    }

    /// Kinematics of every connection, in order.
    pub fn all_kinematics(&self, layout: &Layout) -> Result<Vec<Kinematics>, MbsError> {
        self.connections
            .iter()
            .map(|c| self.kinematics(c, layout))
            .collect()
    }

    /// The equations of motion (eq. 11): body matrices on the diagonal,
    /// connection stiffness `c_n g_n g_n^T` and damping `b_n g_n g_n^T`
    /// coupling them. Nonlinear connections enter with their tangent at rest
    /// when `tangent_at_rest` is set, else not at all (the time integrator
    /// adds their forces itself).
    pub fn assemble(
        &self,
        kinematics: &[Kinematics],
        tangent_at_rest: bool,
    ) -> Result<Assembled, MbsError> {
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
        for (c, kin) in self.connections.iter().zip(kinematics) {
            if !c.law.is_linear() && !tangent_at_rest {
                continue;
            }
            let (stiffness, damping) = c.law.linearized();
            for &(i, gi) in &kin.row {
                for &(j, gj) in &kin.row {
                    k.push(Triplet::new(i, j, stiffness * gi * gj));
                    if damping != 0.0 {
                        d.push(Triplet::new(i, j, damping * gi * gj));
                    }
                }
            }
        }
        Ok(Assembled {
            mass: sparse::from_triplets(n, n, &m)?,
            damping: sparse::from_triplets(n, n, &d)?,
            stiffness: sparse::from_triplets(n, n, &k)?,
        })
    }
}
