//! Bodies of the MBS: flexible (reduced or full FE) and rigid.

use faer::sparse::Triplet;
use flexbody_fem::{Dof, DofKind, DofMap, SystemMatrices};
use flexbody_linalg::sparse::triplets_of;
use flexbody_reduce::ReducedBody;

/// A sparse row: `(coordinate, coefficient)` pairs.
pub type Row = Vec<(usize, f64)>;

/// A flexible body as the MBS sees it.
#[derive(Clone, Copy, Debug)]
pub enum FlexibleBody<'a> {
    /// Ritz coordinates q of a reduced body.
    Reduced(&'a ReducedBody),
    /// The unreduced FE model: coordinates are its DOFs (the reference).
    Full {
        dof_map: &'a DofMap,
        matrices: &'a SystemMatrices,
    },
}

impl FlexibleBody<'_> {
    /// Number of coordinates.
    pub fn len(&self) -> usize {
        match self {
            FlexibleBody::Reduced(b) => b.r(),
            FlexibleBody::Full { dof_map, .. } => dof_map.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Mass, damping and stiffness entries at coordinate offset `at`.
    pub(crate) fn triplets(&self, at: usize) -> [Vec<Triplet<usize, usize, f64>>; 3] {
        let shift = |t: Vec<Triplet<usize, usize, f64>>| {
            t.into_iter()
                .map(|e| Triplet::new(e.row + at, e.col + at, e.val))
                .collect::<Vec<_>>()
        };
        match self {
            FlexibleBody::Reduced(b) => {
                let dense = |m: &faer::Mat<f64>| {
                    let mut t = Vec::with_capacity(m.nrows() * m.ncols());
                    for j in 0..m.ncols() {
                        for i in 0..m.nrows() {
                            if m[(i, j)] != 0.0 {
                                t.push(Triplet::new(i + at, j + at, m[(i, j)]));
                            }
                        }
                    }
                    t
                };
                [
                    dense(&b.mass),
                    b.damping.as_ref().map(dense).unwrap_or_default(),
                    dense(&b.stiffness),
                ]
            }
            FlexibleBody::Full { matrices, .. } => [
                shift(triplets_of(&matrices.mass, 1.0)),
                shift(
                    matrices
                        .damping
                        .as_ref()
                        .map(|d| triplets_of(d, 1.0))
                        .unwrap_or_default(),
                ),
                shift(triplets_of(&matrices.stiffness, 1.0)),
            ],
        }
    }

    /// The displacement of one FE DOF as a row over the body's coordinates
    /// (`T_j` rows, eq. 8); `None` if the body has no such DOF.
    pub fn dof_row(&self, dof: Dof) -> Option<Row> {
        match self {
            FlexibleBody::Reduced(b) => b.row_of(dof).map(|r| {
                r.into_iter()
                    .enumerate()
                    .filter(|(_, v)| *v != 0.0)
                    .collect()
            }),
            FlexibleBody::Full { dof_map, .. } => dof_map.index_of(dof).map(|i| vec![(i, 1.0)]),
        }
    }

    /// FE displacements `u` from the body's coordinates.
    pub fn displacements(&self, coords: &[f64]) -> Vec<f64> {
        match self {
            FlexibleBody::Reduced(b) => b.displacements(coords),
            FlexibleBody::Full { .. } => coords.to_vec(),
        }
    }

    /// The body's DOF map (rows of `u`).
    pub fn dof_map(&self) -> &DofMap {
        match self {
            FlexibleBody::Reduced(b) => &b.dof_map,
            FlexibleBody::Full { dof_map, .. } => dof_map,
        }
    }
}

/// A rigid body: mass (kg), inertia tensor about its centre of mass (kg m^2,
/// `[ixx, iyy, izz, ixy, iyz, ixz]`), centre of mass (m). Its coordinates are
/// the motions `(u, v, w, bx, by, bz)` of the centre of mass (eq. 12), or the
/// subset in `active` (others held at zero, e.g. `uz, ry` in a planar model).
#[derive(Clone, Debug, PartialEq)]
pub struct RigidBody {
    pub name: String,
    pub mass: f64,
    pub inertia: [f64; 6],
    pub center: [f64; 3],
    pub active: Vec<DofKind>,
}

impl RigidBody {
    pub fn len(&self) -> usize {
        self.active.len()
    }

    pub fn is_empty(&self) -> bool {
        self.active.is_empty()
    }

    /// Mass matrix entries at coordinate offset `at`.
    pub(crate) fn mass_triplets(&self, at: usize) -> Vec<Triplet<usize, usize, f64>> {
        let [ixx, iyy, izz, ixy, iyz, ixz] = self.inertia;
        let tensor = [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]];
        let mut t = Vec::new();
        for (a, ka) in self.active.iter().enumerate() {
            for (b, kb) in self.active.iter().enumerate() {
                let v = match (ka.is_rotation(), kb.is_rotation()) {
                    (false, false) if ka == kb => self.mass,
                    (true, true) => tensor[ka.index() - 3][kb.index() - 3],
                    _ => 0.0,
                };
                if v != 0.0 {
                    t.push(Triplet::new(at + a, at + b, v));
                }
            }
        }
        t
    }

    /// Rows of `R_i` (eq. 12, first three rows) for the translation of
    /// `point`, over the body's active coordinates.
    pub fn point_rows(&self, point: [f64; 3]) -> [Row; 3] {
        let r = [
            point[0] - self.center[0],
            point[1] - self.center[1],
            point[2] - self.center[2],
        ];
        // u_p = u + beta x r.
        let full = [
            [1.0, 0.0, 0.0, 0.0, r[2], -r[1]],
            [0.0, 1.0, 0.0, -r[2], 0.0, r[0]],
            [0.0, 0.0, 1.0, r[1], -r[0], 0.0],
        ];
        full.map(|row| {
            self.active
                .iter()
                .enumerate()
                .filter(|(_, k)| row[k.index()] != 0.0)
                .map(|(a, k)| (a, row[k.index()]))
                .collect()
        })
    }
}
