//! The reduced body in the floating frame of reference formulation (FFRF):
//! elastic coordinates and the mass invariants that a SID file carries.
//!
//! The reference frame is the model's global frame (origin and axes). A
//! material point at `x0` moves to `x = x0 + Phi q` in that frame, with
//! `Phi` the elastic mode shapes (m x nq) and `q` the elastic coordinates.
//!
//! **Elastic coordinates.** If the body's basis `T` spans the rigid-body
//! motions `R` (eq. 12-13; free, free-residual, Craig-Bampton and Guyan
//! bodies of a free model do), the frame carries that motion and the elastic
//! modes must not: `T` is projected onto the M-orthogonal complement of `R`
//! (mean-axis, or Tisserand, conditions `R^T M Phi = 0`),
//! `T_e = T (I - A C)` with `C = R_o^T M T`, `A = M_red^-1 C^T` and `R_o` the
//! M-orthonormal rigid-body modes, which drops `n_rigid` directions of the
//! span. The remaining span is diagonalised, `K_e x = w^2 M_e x`, so that
//! `Phi = T E` has `Phi^T M Phi = I` and `Phi^T K Phi = diag(w^2)`: the
//! elastic eigenmodes of the reduced body, with the same non-zero
//! frequencies. If `T` does not span `R` (a supported model), the frame is
//! fixed and `Phi` is the diagonalised `T` itself.
//!
//! **Invariants** (`dm = rho dV`; `a~` is the cross-product matrix of `a`;
//! `<a, b> = a^T M b` with the full, consistent mass matrix `M`):
//!
//! | name | size | zero order (m0) | first order (m1, per `q_k`) |
//! | --- | --- | --- | --- |
//! | mass | 1 | `int dm = <t_d, t_d>` | - |
//! | mdCM | 3 x 1 | `int x0 dm` | `int Phi_k dm` |
//! | J | 3 x 3 | `int x0~^T x0~ dm = <r_a, r_b>` | `-int (x0~ Phi_k~ + Phi_k~ x0~) dm` |
//! | Ct | nq x 3 | `int Phi^T dm = Phi^T M [t_x t_y t_z]` | - |
//! | Cr | nq x 3 | `int (x0 x Phi_k)^T dm = Phi^T M [r_x r_y r_z]` | row k: `int (Phi_l x Phi_k)^T dm` |
//! | Me | nq x nq | `Phi^T M Phi` | - |
//! | Gr | 3 x 3nq | block k: `-2 int x0~ Phi_k~ dm` | - |
//! | Ge | nq x 3nq | block l, row k: `-2 int (Phi_k x Phi_l)^T dm` | - |
//! | Oe | nq x 6 | row k: `[S11 S22 S33 2S12 2S23 2S31]`, `S = sym int Phi_k x0^T dm - I int Phi_k . x0 dm` | the same with `x0 -> Phi_l` |
//! | Ke | nq x nq | `Phi^T K Phi` | - |
//! | De | nq x nq | `Phi^T D Phi` | - |
//!
//! `t_d` and `r_a` are the rigid-body translations and rotations about the
//! frame origin (eq. 12, with rotation DOFs), so mass, `mdCM`, `J`, `Ct` and
//! `Cr` (m0) are exact for every element type, rotary inertia of beams
//! included. The products of two fields (`J`, `Cr` m1, `Gr`, `Ge`, `Oe`)
//! use the translational part of `M` node by node,
//! `int a b^T dm = sum_pq a_p (S b)_q^T` with `S_pq` the translational
//! mass coupling of nodes p and q: exact for solids (isoparametric, consistent
//! mass), an approximation without rotary terms for beams.

use crate::ExportError;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use flexbody_fem::{DofKind, Substructure};
use flexbody_linalg::orthonormal::m_orthonormalize;
use flexbody_reduce::modes::rigid::rigid_body_transformation;
use flexbody_reduce::ReducedBody;
use rayon::prelude::*;
use std::collections::HashMap;

/// Below this M-norm (squared, relative) a rigid-body mode counts as
/// contained in the span of the basis.
const SPAN_TOLERANCE: f64 = 1e-6;

/// Directions of the projected span with a mass below this fraction of the
/// largest are dropped (they were rigid-body motion).
const RANK_TOLERANCE: f64 = 1e-10;

/// Elastic coordinates of a reduced body in the FFRF.
#[derive(Clone, Debug)]
pub struct ElasticBasis {
    /// `E` (r x nq): `Phi = T E`, `q_body = E q`.
    pub transform: Mat<f64>,
    /// `Phi` (m x nq), rows in the body's DOF order.
    pub shapes: Mat<f64>,
    /// `Phi^T M Phi` (the identity to round-off).
    pub mass: Mat<f64>,
    /// `Phi^T K Phi` (diagonal to round-off).
    pub stiffness: Mat<f64>,
    /// `Phi^T D Phi` if the body has damping.
    pub damping: Option<Mat<f64>>,
    /// Natural frequencies of the elastic modes (Hz), ascending.
    pub frequencies_hz: Vec<f64>,
    /// Whether rigid-body motion was removed (free frame) or not (fixed).
    pub floating: bool,
}

fn invalid(message: String) -> ExportError {
    ExportError::Model(message)
}

/// Symmetric eigen-decomposition (ascending) of a small dense matrix.
fn sym_eigen(a: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>), ExportError> {
    let n = a.nrows();
    if n == 0 {
        return Ok((Vec::new(), Mat::zeros(0, 0)));
    }
    let mut s = a.clone();
    flexbody_linalg::sparse::symmetrize(&mut s);
    flexbody_linalg::eigen::symmetric_eigen(s.as_ref())
        .map_err(|e| invalid(format!("eigen-decomposition failed: {e}")))
}

/// Checks that the body belongs to the substructure.
fn check_match(sub: &Substructure, body: &ReducedBody) -> Result<(), ExportError> {
    if sub.dof_map.dofs() != body.dof_map.dofs() {
        return Err(invalid(format!(
            "the body has {} DOFs and the model {}, or they differ: reduce this model again",
            body.dof_map.len(),
            sub.dof_map.len()
        )));
    }
    if !sub.has_geometry() {
        return Err(invalid(
            "the model has no node coordinates; the FFRF invariants need them".into(),
        ));
    }
    Ok(())
}

/// The elastic coordinates of `body` (see the module docs).
pub fn elastic_basis(sub: &Substructure, body: &ReducedBody) -> Result<ElasticBasis, ExportError> {
    check_match(sub, body)?;
    let mass_matrix = &sub.matrices.mass;
    let r = body.r();
    let t = &body.basis;
    let rigid = rigid_body_transformation(sub, [0.0; 3]);
    let rigid_o = m_orthonormalize(rigid.as_ref(), mass_matrix, 1e-8).vectors;
    let identity = Mat::<f64>::identity(r, r);
    let mut e0 = identity.clone();
    let mut floating = false;
    if rigid_o.ncols() > 0 {
        let mt = flexbody_linalg::sparse::symmetric_mul(mass_matrix, t.as_ref());
        let c = rigid_o.transpose() * &mt; // n_r x r
        let llt = body
            .mass
            .llt(Side::Lower)
            .map_err(|_| invalid("the reduced mass matrix is not positive definite".into()))?;
        let a = llt.solve(c.transpose()); // r x n_r
        let ca = &c * &a;
        let outside = (0..ca.nrows())
            .map(|i| (1.0 - ca[(i, i)]).abs())
            .fold(0.0, f64::max);
        if outside < SPAN_TOLERANCE {
            e0 = &identity - &a * &c;
            floating = true;
        }
    }
    // Columns that were rigid-body motion vanish; scale the others to unit
    // modal mass so that static modes (small in m/N) and eigenmodes (unit
    // modal mass) weigh the same in the rank decision.
    let mp = e0.transpose() * &body.mass * &e0;
    let kept_cols: Vec<usize> = (0..r)
        .filter(|&j| mp[(j, j)] > SPAN_TOLERANCE * SPAN_TOLERANCE * body.mass[(j, j)].abs())
        .filter(|&j| mp[(j, j)] > 0.0)
        .collect();
    if kept_cols.is_empty() {
        return Err(invalid(
            "the body has no elastic coordinates (only rigid-body modes)".into(),
        ));
    }
    let e0 = Mat::from_fn(r, kept_cols.len(), |i, j| {
        e0[(i, kept_cols[j])] / mp[(kept_cols[j], kept_cols[j])].sqrt()
    });
    let mp = e0.transpose() * &body.mass * &e0;
    let (s, u) = sym_eigen(&mp)?;
    let s_max = s.iter().copied().fold(0.0, f64::max);
    let keep: Vec<usize> = (0..s.len())
        .filter(|&i| s[i] > RANK_TOLERANCE * s_max)
        .collect();
    let w = Mat::from_fn(e0.ncols(), keep.len(), |i, j| {
        u[(i, keep[j])] / s[keep[j]].sqrt()
    });
    let ew = &e0 * &w;
    let kw = ew.transpose() * &body.stiffness * &ew;
    let (lambda, v) = sym_eigen(&kw)?;
    let transform = &ew * &v;
    let project = |m: &Mat<f64>| {
        let mut p = transform.transpose() * m * &transform;
        flexbody_linalg::sparse::symmetrize(&mut p);
        p
    };
    Ok(ElasticBasis {
        shapes: t * &transform,
        mass: project(&body.mass),
        stiffness: project(&body.stiffness),
        damping: body.damping.as_ref().map(project),
        frequencies_hz: lambda
            .iter()
            .map(|l| flexbody_linalg::eigen::frequency_hz(*l))
            .collect(),
        transform,
        floating,
    })
}

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
fn cross_of(p: &[[f64; 3]; 3]) -> [f64; 3] {
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

/// Computes the invariants of the elastic modes `basis` of `body`.
pub fn mass_invariants(
    sub: &Substructure,
    basis: &ElasticBasis,
) -> Result<MassInvariants, ExportError> {
    let m = &sub.matrices.mass;
    let phi = &basis.shapes;
    if phi.nrows() != sub.dof_map.len() {
        return Err(invalid(format!(
            "mode shapes have {} rows for {} DOFs",
            phi.nrows(),
            sub.dof_map.len()
        )));
    }
    let nq = phi.ncols();
    let rigid = rigid_body_transformation(sub, [0.0; 3]);
    let mr = flexbody_linalg::sparse::symmetric_mul(m, rigid.as_ref());
    let rr = rigid.transpose() * &mr; // 6 x 6
    let dir_mass = [rr[(0, 0)], rr[(1, 1)], rr[(2, 2)]];
    let mass = dir_mass.iter().copied().fold(0.0, f64::max);
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(invalid("the model has no translational mass".into()));
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
    let j: [[f64; 3]; 3] = std::array::from_fn(|a| std::array::from_fn(|b| rr[(3 + a, 3 + b)]));
    let mphi = flexbody_linalg::sparse::symmetric_mul(m, phi.as_ref());
    let coupling = mphi.transpose() * &rigid; // nq x 6
    let ct = Mat::from_fn(nq, 3, |k, a| coupling[(k, a)]);
    let cr = Mat::from_fn(nq, 3, |k, a| coupling[(k, 3 + a)]);
    let mut me = phi.transpose() * &mphi;
    flexbody_linalg::sparse::symmetrize(&mut me);
    let md_cm1 = (0..nq)
        .map(|k| std::array::from_fn(|a| ct[(k, a)]))
        .collect();

    let nodes = NodeMass::new(sub);
    let x0 = nodes.coords.clone();
    let sx0 = nodes.apply(&x0);
    let fields: Vec<Vec<[f64; 3]>> = (0..nq).map(|k| nodes.field(phi, k)).collect();
    let sfields: Vec<Vec<[f64; 3]>> = fields.par_iter().map(|f| nodes.apply(f)).collect();
    // P(x0, Phi_k) and P(Phi_k, x0).
    let x_phi: Vec<[[f64; 3]; 3]> = sfields.iter().map(|sf| outer(&x0, sf)).collect();
    let phi_x: Vec<[[f64; 3]; 3]> = fields.iter().map(|f| outer(f, &sx0)).collect();
    // P(Phi_k, Phi_l), [k][l]: all of them as one product F^T (S F), the
    // fields side by side (column 3 k + a: direction a of mode k).
    let side_by_side =
        |f: &[Vec<[f64; 3]>]| Mat::from_fn(nodes.coords.len(), 3 * nq, |p, c| f[c / 3][p][c % 3]);
    let products = side_by_side(&fields).transpose() * side_by_side(&sfields);
    let phi_phi: Vec<Vec<[[f64; 3]; 3]>> = (0..nq)
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

    let j1 = x_phi
        .iter()
        .map(|p| {
            let tr = trace(p);
            std::array::from_fn(|a| {
                std::array::from_fn(|b| (if a == b { 2.0 * tr } else { 0.0 }) - p[a][b] - p[b][a])
            })
        })
        .collect();
    let cr1 = (0..nq)
        .map(|l| Mat::from_fn(nq, 3, |k, a| cross_of(&phi_phi[l][k])[a]))
        .collect();
    let gr = Mat::from_fn(3, 3 * nq, |a, col| {
        let (k, b) = (col / 3, col % 3);
        let p = &x_phi[k];
        -2.0 * (p[b][a] - if a == b { trace(p) } else { 0.0 })
    });
    let ge = Mat::from_fn(nq, 3 * nq, |k, col| {
        let (l, a) = (col / 3, col % 3);
        -2.0 * cross_of(&phi_phi[k][l])[a]
    });
    let oe = Mat::from_fn(nq, 6, |k, c| oe_row(&phi_x[k])[c]);
    let oe1 = (0..nq)
        .map(|l| Mat::from_fn(nq, 6, |k, c| oe_row(&phi_phi[k][l])[c]))
        .collect();
    Ok(MassInvariants {
        mass,
        md_cm,
        md_cm1,
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
    })
}

/// Rows of the translations (`ux, uy, uz`) and rotations (`rx, ry, rz`) of
/// `node` in `shapes` (3 x nq each; absent DOFs are zero rows).
pub fn node_rows(body: &ReducedBody, shapes: &Mat<f64>, node: u64) -> (Mat<f64>, Mat<f64>) {
    let row = |kind: DofKind, k: usize| {
        body.dof_map
            .index_of(flexbody_fem::Dof::new(node, kind))
            .map_or(0.0, |i| shapes[(i, k)])
    };
    let nq = shapes.ncols();
    (
        Mat::from_fn(3, nq, |d, k| row(DofKind::ALL[d], k)),
        Mat::from_fn(3, nq, |d, k| row(DofKind::ALL[3 + d], k)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::Triplet;
    use flexbody_fem::{Dof, DofMap, SystemMatrices};
    use flexbody_reduce::{Method, ModeKind};

    /// Point masses (lumped mass): every invariant has a closed form,
    /// `int f dm = sum_i m_i f(x_i)`.
    const POINTS: [([f64; 3], f64); 5] = [
        ([0.1, 0.2, -0.3], 2.0),
        ([1.0, -0.5, 0.4], 1.5),
        ([-0.7, 0.3, 0.9], 3.0),
        ([0.4, 1.1, 0.2], 0.5),
        ([-0.2, -0.8, -0.6], 1.0),
    ];

    fn skew3(v: [f64; 3]) -> [[f64; 3]; 3] {
        [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
    }

    fn mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
    }

    fn point_model() -> (Substructure, ReducedBody) {
        let n = POINTS.len();
        let dofs: Vec<Dof> = (0..n as u64)
            .flat_map(|p| DofKind::ALL[..3].iter().map(move |k| Dof::new(p + 1, *k)))
            .collect();
        let m = 3 * n;
        let diag = |f: &dyn Fn(usize) -> f64| {
            let t: Vec<Triplet<usize, usize, f64>> =
                (0..m).map(|i| Triplet::new(i, i, f(i))).collect();
            flexbody_linalg::sparse::from_triplets(m, m, &t).unwrap()
        };
        let mass = diag(&|i| POINTS[i / 3].1);
        let stiffness = diag(&|i| 1.0 + i as f64);
        let coordinates = (0..n).map(|p| (p as u64 + 1, POINTS[p].0)).collect();
        let sub = Substructure::from_matrices(
            DofMap::new(dofs.clone()),
            SystemMatrices {
                stiffness,
                mass,
                damping: None,
            },
            coordinates,
        );
        // The six rigid-body motions plus three arbitrary fields.
        let rigid = rigid_body_transformation(&sub, [0.0; 3]);
        let basis = Mat::from_fn(m, 9, |i, j| {
            if j < 6 {
                rigid[(i, j)]
            } else {
                ((i * 7 + j * 3) % 11) as f64 / 11.0 - 0.4
            }
        });
        let reduced = |a: &flexbody_linalg::SparseMat| basis.transpose() * (a * &basis);
        let body = ReducedBody {
            method: Method::Free,
            dof_map: DofMap::new(dofs),
            mass: reduced(&sub.matrices.mass),
            stiffness: reduced(&sub.matrices.stiffness),
            damping: None,
            modes: vec![ModeKind::Eigen { frequency_hz: 0.0 }; 9],
            interface: vec![],
            basis,
        };
        (sub, body)
    }

    #[test]
    fn invariants_of_point_masses_have_their_closed_forms() {
        let (sub, body) = point_model();
        let basis = elastic_basis(&sub, &body).unwrap();
        assert!(basis.floating);
        let nq = basis.shapes.ncols();
        assert_eq!(nq, 3);
        let inv = mass_invariants(&sub, &basis).unwrap();
        let total: f64 = POINTS.iter().map(|p| p.1).sum();
        assert!((inv.mass - total).abs() < 1e-13 * total);
        for a in 0..3 {
            let s: f64 = POINTS.iter().map(|(x, m)| m * x[a]).sum();
            assert!((inv.md_cm[a] - s).abs() < 1e-13 * total, "mdCM {a}");
            for b in 0..3 {
                let s: f64 = POINTS
                    .iter()
                    .map(|(x, m)| {
                        let r2: f64 = x.iter().map(|v| v * v).sum();
                        m * (if a == b { r2 } else { 0.0 } - x[a] * x[b])
                    })
                    .sum();
                assert!((inv.j[a][b] - s).abs() < 1e-13 * total, "J {a} {b}");
            }
        }
        // Mean axes: no rigid-body part in the elastic modes.
        assert!(inv.ct.norm_max() < 1e-12 && inv.cr.norm_max() < 1e-12);
        let phi = |p: usize, k: usize| -> [f64; 3] {
            std::array::from_fn(|d| basis.shapes[(3 * p + d, k)])
        };
        for k in 0..nq {
            // Gr_k = -2 sum m x~ phi_k~; J1_k = -sum m (x~ phi~ + phi~ x~).
            let mut gr = [[0.0; 3]; 3];
            let mut j1 = [[0.0; 3]; 3];
            for (p, (x, m)) in POINTS.iter().enumerate() {
                let (xs, ps) = (skew3(*x), skew3(phi(p, k)));
                let (a, b) = (mul(xs, ps), mul(ps, xs));
                for i in 0..3 {
                    for j in 0..3 {
                        gr[i][j] -= 2.0 * m * a[i][j];
                        j1[i][j] -= m * (a[i][j] + b[i][j]);
                    }
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    assert!((inv.gr[(i, 3 * k + j)] - gr[i][j]).abs() < 1e-12, "Gr");
                    assert!((inv.j1[k][i][j] - j1[i][j]).abs() < 1e-12, "J1");
                }
            }
            for l in 0..nq {
                // Ge block l, row k = -2 sum m (phi_k x phi_l); Cr1 block l,
                // row k = sum m (phi_l x phi_k).
                let mut c = [0.0; 3];
                for (p, (_, m)) in POINTS.iter().enumerate() {
                    let (a, b) = (phi(p, k), phi(p, l));
                    c[0] += m * (a[1] * b[2] - a[2] * b[1]);
                    c[1] += m * (a[2] * b[0] - a[0] * b[2]);
                    c[2] += m * (a[0] * b[1] - a[1] * b[0]);
                }
                for (a, ca) in c.iter().enumerate() {
                    assert!((inv.ge[(k, 3 * l + a)] + 2.0 * ca).abs() < 1e-12, "Ge");
                    assert!((inv.cr1[l][(k, a)] + ca).abs() < 1e-12, "Cr1");
                }
            }
            // Oe: phi_k . (w x (w x x)) summed, for a test w.
            let w = [0.3, -1.2, 0.7];
            let wq = [
                w[0] * w[0],
                w[1] * w[1],
                w[2] * w[2],
                w[0] * w[1],
                w[1] * w[2],
                w[2] * w[0],
            ];
            let mut want = 0.0;
            for (p, (x, m)) in POINTS.iter().enumerate() {
                let ws = skew3(w);
                let wwx: [f64; 3] = std::array::from_fn(|i| {
                    (0..3)
                        .map(|j| (0..3).map(|l| ws[i][l] * ws[l][j]).sum::<f64>() * x[j])
                        .sum()
                });
                let f = phi(p, k);
                want += m * (0..3).map(|i| f[i] * wwx[i]).sum::<f64>();
            }
            let got: f64 = (0..6).map(|c| inv.oe[(k, c)] * wq[c]).sum();
            assert!((got - want).abs() < 1e-12, "Oe: {got} against {want}");
        }
        // Unit modal mass, diagonal stiffness.
        for i in 0..nq {
            for j in 0..nq {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((basis.mass[(i, j)] - want).abs() < 1e-12);
                if i != j {
                    assert!(basis.stiffness[(i, j)].abs() < 1e-9);
                }
            }
        }
    }

    /// A free steel C3D8 block of 3 x 2 x 2 elements (1.2 x 0.5 x 0.4 m)
    /// and its free reduction with 6 elastic modes.
    fn solid_block() -> (Substructure, ReducedBody) {
        use flexbody_fem::element::solid::{Solid, SolidKind};
        use flexbody_fem::{Element, Material, Model, Node};
        let (nx, ny, nz) = (3usize, 2usize, 2usize);
        let id = |i: usize, j: usize, k: usize| (1 + i + (nx + 1) * (j + (ny + 1) * k)) as u64;
        let mut nodes = Vec::new();
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    nodes.push(Node {
                        id: id(i, j, k),
                        coords: [0.4 * i as f64 - 0.3, 0.25 * j as f64 + 0.1, 0.2 * k as f64],
                    });
                }
            }
        }
        let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let mut elements = Vec::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    elements.push(Element::Solid(Solid {
                        id: elements.len() + 1,
                        kind: SolidKind::C3D8,
                        nodes: vec![
                            id(i, j, k),
                            id(i + 1, j, k),
                            id(i + 1, j + 1, k),
                            id(i, j + 1, k),
                            id(i, j, k + 1),
                            id(i + 1, j, k + 1),
                            id(i + 1, j + 1, k + 1),
                            id(i, j + 1, k + 1),
                        ],
                        material: steel.clone(),
                    }));
                }
            }
        }
        let model = Model::new(nodes, elements, Default::default(), vec![], None).unwrap();
        let sub = Substructure::from_model(&model).unwrap();
        let spec = flexbody_reduce::Reduction::new(Method::Free, 12, vec![]);
        let body = flexbody_reduce::reduce(&sub, &spec).unwrap();
        (sub, body)
    }

    #[test]
    fn invariants_of_a_solid_equal_their_products_with_the_full_mass_matrix() {
        // The products of two fields go node by node through the scalar
        // couplings S_pq (`NodeMass`). For a solid, M couples the same
        // direction of two nodes only, and equally in x, y and z, so
        // int a_i b_j dm is a^T M g with g carrying b's j-components in the
        // i-slots: every invariant of the module docs from M itself.
        let (sub, body) = solid_block();
        let basis = elastic_basis(&sub, &body).unwrap();
        assert!(basis.floating);
        let inv = mass_invariants(&sub, &basis).unwrap();
        let nq = basis.shapes.ncols();
        assert_eq!(nq, 6);
        let map = &sub.dof_map;
        let n = map.len();
        let slot = |i: usize| map.dof(i).kind.index();
        let position: Vec<f64> = (0..n)
            .map(|i| sub.node_coordinates(map.dof(i).node).unwrap()[slot(i)])
            .collect();
        let mode = |k: usize| -> Vec<f64> { (0..n).map(|i| basis.shapes[(i, k)]).collect() };
        // P(a, b)[i][j] = int a_i b_j dm.
        let m = &sub.matrices.mass;
        let p = |a: &[f64], b: &[f64]| -> [[f64; 3]; 3] {
            std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    let g = Mat::from_fn(n, 1, |r, _| {
                        if slot(r) != i {
                            return 0.0;
                        }
                        let d = map.dof(r);
                        let from = map
                            .index_of(Dof::new(d.node, DofKind::ALL[j]))
                            .expect("solid nodes carry ux, uy, uz");
                        b[from]
                    });
                    let mg = flexbody_linalg::sparse::symmetric_mul(m, g.as_ref());
                    (0..n).map(|r| a[r] * mg[(r, 0)]).sum()
                })
            })
        };
        let tr = |q: &[[f64; 3]; 3]| q[0][0] + q[1][1] + q[2][2];
        let cross = |q: &[[f64; 3]; 3], a: usize| {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            q[b][c] - q[c][b]
        };
        let oe_of = |q: &[[f64; 3]; 3]| {
            let s =
                |i: usize, j: usize| 0.5 * (q[i][j] + q[j][i]) - if i == j { tr(q) } else { 0.0 };
            [
                s(0, 0),
                s(1, 1),
                s(2, 2),
                2.0 * s(0, 1),
                2.0 * s(1, 2),
                2.0 * s(2, 0),
            ]
        };
        // Each invariant against its own largest entry.
        let mut worst = [0.0_f64; 6];
        let mut scale = [0.0_f64; 6];
        let mut check = |which: usize, got: f64, want: f64| {
            worst[which] = worst[which].max((got - want).abs());
            scale[which] = scale[which].max(want.abs());
        };
        let x0 = position.clone();
        for k in 0..nq {
            let fk = mode(k);
            let (xk, kx) = (p(&x0, &fk), p(&fk, &x0));
            for a in 0..3 {
                for b in 0..3 {
                    let delta = if a == b { 2.0 * tr(&xk) } else { 0.0 };
                    // J1_k = -int (x0~ phi_k~ + phi_k~ x0~) dm.
                    check(0, inv.j1[k][a][b], delta - kx[a][b] - xk[a][b]);
                    // Gr block k = -2 int x0~ phi_k~ dm.
                    check(1, inv.gr[(a, 3 * k + b)], -2.0 * kx[a][b] + delta);
                }
            }
            // Oe row k from int phi_k x0^T dm.
            for (c, want) in oe_of(&kx).iter().enumerate() {
                check(2, inv.oe[(k, c)], *want);
            }
            for l in 0..nq {
                let fl = mode(l);
                let (kl, lk) = (p(&fk, &fl), p(&fl, &fk));
                for a in 0..3 {
                    // Ge block l, row k = -2 int phi_k x phi_l dm; Cr1 for
                    // q_l, row k = int phi_l x phi_k dm.
                    check(3, inv.ge[(k, 3 * l + a)], -2.0 * cross(&kl, a));
                    check(4, inv.cr1[l][(k, a)], cross(&lk, a));
                }
                for (c, want) in oe_of(&kl).iter().enumerate() {
                    check(5, inv.oe1[l][(k, c)], *want);
                }
            }
        }
        for (name, (w, s)) in ["J1", "Gr", "Oe", "Ge", "Cr1", "Oe1"]
            .iter()
            .zip(worst.iter().zip(&scale))
        {
            assert!(*s > 0.0, "{name} vanishes: no test");
            assert!(w / s < 1e-12, "{name}: {w:e} of {s:e}");
        }
    }
}
