//! Recovery of section forces (report eq. 25):
//! `s_e = K_e T_e q + M_e T_e q''`, the element end forces including the
//! inertia term. The same functions serve the reduced body (u = T q) and the
//! full model (the reference, "Vergleichslösung"), so both are recovered the
//! same way. For a harmonic state at Omega, `q'' = -Omega^2 q`.

pub mod stress;

pub use stress::{nodal_stresses, ModalStress, NodalStresses};

use faer::Mat;
use flexbody_fem::{Dof, DofKind, FemError, Model, SectionForces, Substructure};
use flexbody_reduce::ReducedBody;
use serde::{Deserialize, Serialize};

/// Section forces of one beam element with the positions of its ends (m).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ElementForces {
    pub element: usize,
    pub start: [f64; 3],
    pub end: [f64; 3],
    pub forces: SectionForces,
}

/// Values of the model's DOFs from a vector over its equations (fixed DOFs:
/// 0; DOFs eliminated by couplings: from their constraints).
fn gather(model: &Model, dofs: &[Dof], u: &[f64]) -> Vec<f64> {
    dofs.iter().map(|d| model.value(*d, u)).collect()
}

/// Eq. 25 for every beam element: section forces from displacements `u`
/// and accelerations `a` (both over the model's equations).
pub fn section_forces(model: &Model, u: &[f64], a: &[f64]) -> Result<Vec<ElementForces>, FemError> {
    let mut out = Vec::new();
    for e in model.elements() {
        let dofs = e.dofs();
        let ue = gather(model, &dofs, u);
        let ae = gather(model, &dofs, a);
        if let Some(forces) = e.section_forces(model, &ue, &ae)? {
            let nodes = e.nodes();
            out.push(ElementForces {
                element: e.id(),
                start: model.coords(nodes[0]),
                end: model.coords(nodes[1]),
                forces,
            });
        }
    }
    Ok(out)
}

/// Section forces of a harmonic state `u` at `omega` (rad/s): `a = -omega^2 u`.
pub fn harmonic_section_forces(
    model: &Model,
    u: &[f64],
    omega: f64,
) -> Result<Vec<ElementForces>, FemError> {
    let a: Vec<f64> = u.iter().map(|v| -omega * omega * v).collect();
    section_forces(model, u, &a)
}

/// Nodal values of one DOF kind along the model, `(node coordinates, value)`,
/// in node order (nodes without that DOF are skipped; fixed DOFs give 0).
pub fn nodal_values(model: &Model, u: &[f64], kind: DofKind) -> Vec<([f64; 3], f64)> {
    model
        .nodes()
        .iter()
        .filter(|n| {
            let d = Dof::new(n.id, kind);
            model.dof_map().index_of(d).is_some()
                || !model.terms(d).is_empty()
                || model.fixed_dofs().any(|f| *f == d)
        })
        .map(|n| (n.coords, model.value(Dof::new(n.id, kind), u)))
        .collect()
}

/// Forces on the body at the given DOFs (N, or N m on rotations): the rows
/// of the equation of motion, `(K u + M a)_H`, i.e. what the surroundings
/// (connections, supports) exert there. Needs only the matrices, so it also
/// serves models read as matrices without a mesh.
pub fn interface_forces(
    sub: &Substructure,
    u: &[f64],
    a: &[f64],
    dofs: &[Dof],
) -> Result<Vec<f64>, FemError> {
    let k = &sub.matrices.stiffness;
    let m = &sub.matrices.mass;
    let (kr, mr) = (k.as_ref(), m.as_ref());
    dofs.iter()
        .map(|d| {
            let i = sub.equation(*d, "interface force")?;
            // Symmetric matrices: row i = column i.
            let ku: f64 = kr
                .row_idx_of_col(i)
                .zip(kr.val_of_col(i))
                .map(|(r, v)| v * u[r])
                .sum();
            let ma: f64 = mr
                .row_idx_of_col(i)
                .zip(mr.val_of_col(i))
                .map(|(r, v)| v * a[r])
                .sum();
            Ok(ku + ma)
        })
        .collect()
}

/// Modal section-force matrices of a reduced body (eq. 25 with `T_e`
/// folded in): per beam element, `S_K = K_e T_e` and `S_M = M_e T_e` as
/// 12 x r matrices (rows: start then end section forces `N Qy Qz T My Mz`),
/// so that `s_e = S_K q + S_M q''` needs only the r Ritz coordinates.
#[derive(Clone, Debug)]
pub struct ModalRecovery {
    pub elements: Vec<usize>,
    pub stiffness: Vec<Mat<f64>>,
    pub mass: Vec<Mat<f64>>,
}

impl ModalRecovery {
    pub fn new(model: &Model, body: &ReducedBody) -> Result<Self, FemError> {
        let r = body.r();
        let m = body.basis.nrows();
        let zero = vec![0.0; m];
        let mut per_mode_k = Vec::with_capacity(r);
        let mut per_mode_m = Vec::with_capacity(r);
        for j in 0..r {
            let t: Vec<f64> = (0..m).map(|i| body.basis[(i, j)]).collect();
            per_mode_k.push(section_forces(model, &t, &zero)?);
            per_mode_m.push(section_forces(model, &zero, &t)?);
        }
        let elements: Vec<usize> = per_mode_k
            .first()
            .map_or_else(Vec::new, |f| f.iter().map(|e| e.element).collect());
        let build = |per_mode: &Vec<Vec<ElementForces>>, e: usize| {
            Mat::from_fn(12, r, |i, j| {
                let f = &per_mode[j][e].forces;
                if i < 6 {
                    f.start[i]
                } else {
                    f.end[i - 6]
                }
            })
        };
        let stiffness = (0..elements.len()).map(|e| build(&per_mode_k, e)).collect();
        let mass = (0..elements.len()).map(|e| build(&per_mode_m, e)).collect();
        Ok(Self {
            elements,
            stiffness,
            mass,
        })
    }

    /// Section forces of element number `k` (position in `elements`) from
    /// `q` and `q''`.
    pub fn forces(&self, k: usize, q: &[f64], q_dd: &[f64]) -> SectionForces {
        let (s_k, s_m) = (&self.stiffness[k], &self.mass[k]);
        let v = |i: usize| -> f64 {
            (0..q.len())
                .map(|j| s_k[(i, j)] * q[j] + s_m[(i, j)] * q_dd[j])
                .sum()
        };
        SectionForces {
            start: std::array::from_fn(v),
            end: std::array::from_fn(|i| v(i + 6)),
        }
    }
}

/// The recovery matrix of `body` on `model`, one column per basis vector:
/// the modal stresses of the solids and shells if the model has any (6
/// rows per stress point: a solid's node, a shell's node on each surface;
/// Voigt `sxx syy szz sxy syz szx`, Pa, nodes ascending, as in
/// [`ModalStress`]), else the section forces of the beams (12 rows per
/// element, `N Qy Qz T My Mz` at start then end: `S_K = K_e T_e` of
/// [`ModalRecovery`]). No rows for a model with neither.
pub fn recovery_matrix(model: &Model, body: &ReducedBody) -> Result<Mat<f64>, FemError> {
    let stress = ModalStress::new(model, body)?;
    if !stress.nodes.is_empty() {
        let rows = 6 * stress.nodes.len();
        return Ok(Mat::from_fn(rows, body.r(), |i, j| {
            stress.matrices[i / 6][(i % 6, j)]
        }));
    }
    let beams = ModalRecovery::new(model, body)?;
    Ok(Mat::from_fn(12 * beams.elements.len(), body.r(), |i, j| {
        beams.stiffness[i / 12][(i % 12, j)]
    }))
}
