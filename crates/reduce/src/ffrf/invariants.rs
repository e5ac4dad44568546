//! The mass invariants of the floating frame (`mass`, `mdCM`, `J`, `Ct`,
//! `Cr`, `Me`, `Gr`, `Ge`, `Oe` with their first orders; the table of the
//! [module docs](super)) from the full mass matrix and the elastic modes.

use super::{ElasticBasis, FfrfError};
use crate::modes::rigid::rigid_body_transformation;
use faer::Mat;
use flexbody_fem::{Model, Substructure};
use rayon::prelude::*;
use std::collections::HashMap;

/// The mass invariants of the FFRF (see the module docs for the formulas).
#[derive(Clone, Debug)]
pub struct MassInvariants {
    /// Total mass (kg).
    pub mass: f64,
    /// `int x0 dm` (kg m), 3.
    pub md_cm: [f64; 3],
    /// First order of `mdCM`: `int Phi_k dm`, one per mode.
    pub md_cm1: Vec<[f64; 3]>,
    /// Inertia tensor about the frame origin (kg m^2).
    pub j: [[f64; 3]; 3],
    /// First order of `J`, one 3 x 3 per mode.
    pub j1: Vec<[[f64; 3]; 3]>,
    /// `Ct` (nq x 3).
    pub ct: Mat<f64>,
    /// `Cr` (nq x 3).
    pub cr: Mat<f64>,
    /// First order of `Cr`, one nq x 3 per mode.
    pub cr1: Vec<Mat<f64>>,
    /// `Me` (nq x nq).
    pub me: Mat<f64>,
    /// `Gr` (3 x 3nq).
    pub gr: Mat<f64>,
    /// `Ge` (nq x 3nq).
    pub ge: Mat<f64>,
    /// `Oe` (nq x 6).
    pub oe: Mat<f64>,
    /// First order of `Oe`, one nq x 6 per mode.
    pub oe1: Vec<Mat<f64>>,
}

/// Node fields for the products of two fields: translational part of `M`
/// condensed to one scalar coupling per node pair.
struct NodeMass {
    /// Node coordinates, one per node with translational DOFs.
    coords: Vec<[f64; 3]>,
    /// Equations of `ux, uy, uz` per node.
    equations: Vec<[Option<usize>; 3]>,
    /// `S` as (p, q, value) triplets.
    coupling: Vec<(usize, usize, f64)>,
}

impl NodeMass {
    fn new(sub: &Substructure) -> Self {
        let mut index: HashMap<u64, usize> = HashMap::new();
        let mut coords = Vec::new();
        let mut equations: Vec<[Option<usize>; 3]> = Vec::new();
        let mut node_of = vec![usize::MAX; sub.dof_map.len()];
        for (i, dof) in sub.dof_map.dofs().iter().enumerate() {
            if dof.kind.is_rotation() {
                continue;
            }
            let p = *index.entry(dof.node).or_insert_with(|| {
                coords.push(sub.node_coordinates(dof.node).unwrap_or([0.0; 3]));
                equations.push([None; 3]);
                coords.len() - 1
            });
            equations[p][dof.kind.index()] = Some(i);
            node_of[i] = p;
        }
        // Per node q, the sums of its columns' entries in rows of the same
        // direction, by row node p: a sparse accumulator (`slot[p]` is p's
        // place in `row` while q is summed).
        let dofs = sub.dof_map.dofs();
        let m = sub.matrices.mass.as_ref();
        let mut slot = vec![usize::MAX; coords.len()];
        let mut row: Vec<(usize, f64, u32)> = Vec::new();
        let mut coupling = Vec::new();
        for (q, columns) in equations.iter().enumerate() {
            for &j in columns.iter().flatten() {
                let kind = dofs[j].kind;
                for (i, v) in m.row_idx_of_col(j).zip(m.val_of_col(j)) {
                    if dofs[i].kind != kind {
                        continue;
                    }
                    let p = node_of[i];
                    if slot[p] == usize::MAX {
                        slot[p] = row.len();
                        row.push((p, 0.0, 0));
                    }
                    let e = &mut row[slot[p]];
                    e.1 += *v;
                    e.2 += 1;
                }
            }
            row.sort_unstable_by_key(|e| e.0);
            for &(p, s, c) in &row {
                slot[p] = usize::MAX;
                coupling.push((p, q, s / c as f64));
            }
            row.clear();
        }
        Self {
            coords,
            equations,
            coupling,
        }
    }

    /// A mode's translations per node.
    fn field(&self, shapes: &Mat<f64>, k: usize) -> Vec<[f64; 3]> {
        self.equations
            .iter()
            .map(|eq| std::array::from_fn(|d| eq[d].map_or(0.0, |i| shapes[(i, k)])))
            .collect()
    }

    /// `S b` per node.
    fn apply(&self, b: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut out = vec![[0.0; 3]; b.len()];
        for &(p, q, s) in &self.coupling {
            for d in 0..3 {
                out[p][d] += s * b[q][d];
            }
        }
        out
    }
}

/// `int a b^T dm` from `a` and `S b`.
fn outer(a: &[[f64; 3]], sb: &[[f64; 3]]) -> [[f64; 3]; 3] {
    let mut p = [[0.0; 3]; 3];
    for (x, y) in a.iter().zip(sb) {
        for i in 0..3 {
            for j in 0..3 {
                p[i][j] += x[i] * y[j];
            }
        }
    }
    p
}

fn trace(p: &[[f64; 3]; 3]) -> f64 {
    p[0][0] + p[1][1] + p[2][2]
}

/// `int a x b dm` from `P = int a b^T dm`.
pub(super) fn cross_of(p: &[[f64; 3]; 3]) -> [f64; 3] {
    [p[1][2] - p[2][1], p[2][0] - p[0][2], p[0][1] - p[1][0]]
}

/// Row of `Oe` from `P = int Phi_k y^T dm`.
fn oe_row(p: &[[f64; 3]; 3]) -> [f64; 6] {
    let tr = trace(p);
    let s = |i: usize, j: usize| 0.5 * (p[i][j] + p[j][i]) - if i == j { tr } else { 0.0 };
    [
        s(0, 0),
        s(1, 1),
        s(2, 2),
        2.0 * s(0, 1),
        2.0 * s(1, 2),
        2.0 * s(2, 0),
    ]
}

/// The integrals over the body that the invariants are made of: the mass,
/// `int x0 dm`, `int Phi_k dm`, and the products `P(a, b) = int a b^T dm`
/// of the positions and the modes.
pub(super) struct Integrals {
    pub mass: f64,
    /// `int x0 dm`.
    pub md_cm: [f64; 3],
    /// `int Phi_k dm`, per mode.
    pub first: Vec<[f64; 3]>,
    /// `P(x0, x0)`.
    pub x_x: [[f64; 3]; 3],
    /// `int x0 x Phi_k dm`, per mode.
    pub cross: Vec<[f64; 3]>,
    /// `P(x0, Phi_k)`, per mode.
    pub x_phi: Vec<[[f64; 3]; 3]>,
    /// `P(Phi_k, Phi_l)`, `[k][l]`.
    pub phi_phi: Vec<Vec<[[f64; 3]; 3]>>,
}

/// The invariants of the elastic modes `basis` of a body reduced from
/// `sub` (see the [module docs](super) for the formulas). With the mesh
/// `model` of `sub`, the integrals run over its elements
/// ([`MassDistribution`](flexbody_fem::element::MassDistribution)): the
/// whole body's mass, fixed DOFs included, and each element's own shape
/// functions (beams: rotations and rotary inertia). Without one (matrix
/// input), over the mass matrix of `sub`: its DOFs' mass only, and the
/// products of two fields from its translational part node by node.
pub fn mass_invariants(
    sub: &Substructure,
    model: Option<&Model>,
    basis: &ElasticBasis,
) -> Result<MassInvariants, FfrfError> {
    let m = &sub.matrices.mass;
    let phi = &basis.shapes;
    if phi.nrows() != sub.dof_map.len() {
        return Err(FfrfError::ShapeRows {
            rows: phi.nrows(),
            dofs: sub.dof_map.len(),
        });
    }
    let integrals = match model {
        Some(model) => super::mesh_integrals::mesh_integrals(model, phi)?,
        None => matrix_integrals(sub, phi)?,
    };
    if !(integrals.mass > 0.0 && integrals.mass.is_finite()) {
        return Err(FfrfError::NoTranslationalMass);
    }
    let mut me = phi.transpose() * flexbody_linalg::sparse::symmetric_mul(m, phi.as_ref());
    flexbody_linalg::sparse::symmetrize(&mut me);
    Ok(from_integrals(integrals, me))
}

/// The integrals from the mass matrix of `sub` alone: `mass`, `mdCM`, `J`,
/// `int Phi_k dm` and `int x0 x Phi_k dm` from its products with the
/// rigid-body motions (exact for every element type on the DOFs it has),
/// the other products from its translational part node by node
/// ([`NodeMass`]).
fn matrix_integrals(sub: &Substructure, phi: &Mat<f64>) -> Result<Integrals, FfrfError> {
    let m = &sub.matrices.mass;
    let nq = phi.ncols();
    let rigid = rigid_body_transformation(sub, [0.0; 3]);
    let mr = flexbody_linalg::sparse::symmetric_mul(m, rigid.as_ref());
    let rr = rigid.transpose() * &mr; // 6 x 6
    let dir_mass = [rr[(0, 0)], rr[(1, 1)], rr[(2, 2)]];
    let mass = dir_mass.iter().copied().fold(0.0, f64::max);
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(FfrfError::NoTranslationalMass);
    }
    // <r_b, t_c> = m_c (c0~)_{bc}: the first moment from the rows of the
    // directions that carry mass.
    let mut md_cm = [0.0; 3];
    for (a, slot) in md_cm.iter_mut().enumerate() {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        let denominator = dir_mass[b] + dir_mass[c];
        if denominator > 0.0 {
            *slot = mass * (rr[(3 + c, b)] - rr[(3 + b, c)]) / denominator;
        }
    }
    // J = tr(P) I - P, so P(x0, x0) = tr(J)/2 I - J.
    let j: [[f64; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|b| rr[(3 + a, 3 + b)]));
    let x_x = std::array::from_fn(|a| {
        std::array::from_fn(|b| if a == b { trace(&j) / 2.0 } else { 0.0 } - j[a][b])
    });
    let mphi = flexbody_linalg::sparse::symmetric_mul(m, phi.as_ref());
    let coupling = mphi.transpose() * &rigid; // nq x 6

    let nodes = NodeMass::new(sub);
    let x0 = nodes.coords.clone();
    let fields: Vec<Vec<[f64; 3]>> = (0..nq).map(|k| nodes.field(phi, k)).collect();
    let sfields: Vec<Vec<[f64; 3]>> = fields.par_iter().map(|f| nodes.apply(f)).collect();
    let x_phi: Vec<[[f64; 3]; 3]> = sfields.iter().map(|sf| outer(&x0, sf)).collect();
    // P(Phi_k, Phi_l), [k][l]: all of them as one product F^T (S F), the
    // fields side by side (column 3 k + a: direction a of mode k).
    let side_by_side =
        |f: &[Vec<[f64; 3]>]| Mat::from_fn(nodes.coords.len(), 3 * nq, |p, c| f[c / 3][p][c % 3]);
    let products = side_by_side(&fields).transpose() * side_by_side(&sfields);
    let phi_phi = (0..nq)
        .map(|k| {
            (0..nq)
                .map(|l| {
                    std::array::from_fn(|a| {
                        std::array::from_fn(|b| products[(3 * k + a, 3 * l + b)])
                    })
                })
                .collect()
        })
        .collect();
    Ok(Integrals {
        mass,
        md_cm,
        first: (0..nq)
            .map(|k| std::array::from_fn(|a| coupling[(k, a)]))
            .collect(),
        x_x,
        cross: (0..nq)
            .map(|k| std::array::from_fn(|a| coupling[(k, 3 + a)]))
            .collect(),
        x_phi,
        phi_phi,
    })
}

/// The invariants from the body integrals and `Me`.
fn from_integrals(i: Integrals, me: Mat<f64>) -> MassInvariants {
    let nq = i.first.len();
    let p = &i.x_x;
    let j = std::array::from_fn(|a| {
        std::array::from_fn(|b| if a == b { trace(p) } else { 0.0 } - p[a][b])
    });
    let ct = Mat::from_fn(nq, 3, |k, a| i.first[k][a]);
    let cr = Mat::from_fn(nq, 3, |k, a| i.cross[k][a]);
    let j1 = i
        .x_phi
        .iter()
        .map(|p| {
            let tr = trace(p);
            std::array::from_fn(|a| {
                std::array::from_fn(|b| (if a == b { 2.0 * tr } else { 0.0 }) - p[a][b] - p[b][a])
            })
        })
        .collect();
    let cr1 = (0..nq)
        .map(|l| Mat::from_fn(nq, 3, |k, a| cross_of(&i.phi_phi[l][k])[a]))
        .collect();
    let gr = Mat::from_fn(3, 3 * nq, |a, col| {
        let (k, b) = (col / 3, col % 3);
        let p = &i.x_phi[k];
        -2.0 * (p[b][a] - if a == b { trace(p) } else { 0.0 })
    });
    let ge = Mat::from_fn(nq, 3 * nq, |k, col| {
        let (l, a) = (col / 3, col % 3);
        -2.0 * cross_of(&i.phi_phi[k][l])[a]
    });
    // P(Phi_k, x0) = P(x0, Phi_k)^T.
    let transposed = |p: &[[f64; 3]; 3]| std::array::from_fn(|a| std::array::from_fn(|b| p[b][a]));
    let oe = Mat::from_fn(nq, 6, |k, c| oe_row(&transposed(&i.x_phi[k]))[c]);
    let oe1 = (0..nq)
        .map(|l| Mat::from_fn(nq, 6, |k, c| oe_row(&i.phi_phi[k][l])[c]))
        .collect();
    MassInvariants {
        mass: i.mass,
        md_cm: i.md_cm,
        md_cm1: i.first,
        j,
        j1,
        ct,
        cr,
        cr1,
        me,
        gr,
        ge,
        oe,
        oe1,
    }
}
