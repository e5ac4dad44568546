//! Interface points on faces: a reference node with 6 DOFs coupled to a set
//! of nodes, rigidly (RBE2, Abaqus *KINEMATIC COUPLING) or by distribution
//! (RBE3, Abaqus *DISTRIBUTING COUPLING). Both become exact linear
//! constraints `u_d = sum_k c_k u_k` that eliminate dependent DOFs.
//!
//! - Rigid: every DOF of every set node follows the point as a rigid body
//!   (eq. 12): `u_i = u_P + theta_P x (x_i - x_P)`, `theta_i = theta_P`.
//! - Distributing: the point moves as the weighted least-squares rigid fit of
//!   the set's translations, `[u_P; theta_P] = N^-1 sum_i w_i G_i^T u_i` with
//!   `G_i = [I | -(x_i - x_P) x]`, `N = sum_i w_i G_i^T G_i`; loads at the
//!   point reach the set as `R^T f` without stiffening it. The point's six
//!   DOFs stay independent: six set DOFs (a regular choice, as Nastran's UM
//!   set) become dependent instead, so the constraint adds no stiffness and
//!   every reduction method can use the point as an interface.

use crate::dof::{Dof, DofKind};
use crate::model::NodeId;
use crate::FemError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How the point is coupled to its set.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CouplingKind {
    /// RBE2 / kinematic coupling.
    Rigid,
    /// RBE3 / distributing coupling.
    Distributing,
}

/// A coupling of reference node `point` (6 DOFs) to `nodes`.
#[derive(Clone, Debug, PartialEq)]
pub struct Coupling {
    pub name: String,
    pub kind: CouplingKind,
    pub point: NodeId,
    pub nodes: Vec<NodeId>,
    /// Weights of the set nodes (distributing); `None`: all 1.
    pub weights: Option<Vec<f64>>,
}

/// Dependent DOFs as combinations of independent ones.
pub type Constraints = BTreeMap<Dof, Vec<(Dof, f64)>>;

impl Coupling {
    /// The constraints of this coupling. `coords` gives node positions,
    /// `active(node)` the DOF kinds a node has.
    pub fn constraints(
        &self,
        coords: &dyn Fn(NodeId) -> Option<[f64; 3]>,
        active: &dyn Fn(NodeId) -> Vec<DofKind>,
    ) -> Result<Constraints, FemError> {
        let bad = |reason: String| FemError::InvalidCoupling {
            name: self.name.clone(),
            reason,
        };
        if self.nodes.is_empty() {
            return Err(bad("its node set is empty".into()));
        }
        let p = coords(self.point)
            .ok_or_else(|| bad(format!("reference node {} does not exist", self.point)))?;
        let mut seen = std::collections::BTreeSet::new();
        for n in &self.nodes {
            if coords(*n).is_none() {
                return Err(bad(format!("node {n} does not exist")));
            }
            if *n == self.point {
                return Err(bad(format!(
                    "the reference node {n} is also in its own set"
                )));
            }
            if !seen.insert(*n) {
                return Err(bad(format!("node {n} is listed twice")));
            }
        }
        let pdof = |k: DofKind| Dof::new(self.point, k);
        let mut out = Constraints::new();
        match self.kind {
            CouplingKind::Rigid => {
                for &n in &self.nodes {
                    let x = coords(n).unwrap_or(p);
                    let r = [x[0] - p[0], x[1] - p[1], x[2] - p[2]];
                    for k in active(n) {
                        let terms: Vec<(Dof, f64)> = match k {
                            DofKind::Ux => vec![
                                (pdof(DofKind::Ux), 1.0),
                                (pdof(DofKind::Ry), r[2]),
                                (pdof(DofKind::Rz), -r[1]),
                            ],
                            DofKind::Uy => vec![
                                (pdof(DofKind::Uy), 1.0),
                                (pdof(DofKind::Rx), -r[2]),
                                (pdof(DofKind::Rz), r[0]),
                            ],
                            DofKind::Uz => vec![
                                (pdof(DofKind::Uz), 1.0),
                                (pdof(DofKind::Rx), r[1]),
                                (pdof(DofKind::Ry), -r[0]),
                            ],
                            rot => vec![(pdof(rot), 1.0)],
                        };
                        out.insert(
                            Dof::new(n, k),
                            terms.into_iter().filter(|(_, c)| *c != 0.0).collect(),
                        );
                    }
                }
            }
            CouplingKind::Distributing => {
                let w = match &self.weights {
                    Some(w) if w.len() != self.nodes.len() => {
                        return Err(bad(format!(
                            "{} weights for {} nodes",
                            w.len(),
                            self.nodes.len()
                        )))
                    }
                    Some(w) if w.iter().any(|x| !(x.is_finite() && *x > 0.0)) => {
                        return Err(bad("weights must be positive".into()))
                    }
                    Some(w) => w.clone(),
                    None => vec![1.0; self.nodes.len()],
                };
                // Set DOFs (translations) and the fit R (6 x 3n).
                let mut set_dofs = Vec::new();
                let mut g_rows: Vec<[f64; 6]> = Vec::new();
                let mut weight = Vec::new();
                for (&n, &wi) in self.nodes.iter().zip(&w) {
                    let x = coords(n).unwrap_or(p);
                    let r = [x[0] - p[0], x[1] - p[1], x[2] - p[2]];
                    let kinds = active(n);
                    for (a, k) in [DofKind::Ux, DofKind::Uy, DofKind::Uz]
                        .into_iter()
                        .enumerate()
                    {
                        if !kinds.contains(&k) {
                            return Err(bad(format!("node {n} has no DOF {k} (distributing couplings need translations)")));
                        }
                        // Row a of G_i = [I | -[r]x]: u_a = u_P,a + (theta x r)_a.
                        let mut g = [0.0; 6];
                        g[a] = 1.0;
                        match a {
                            0 => {
                                g[4] = r[2];
                                g[5] = -r[1];
                            }
                            1 => {
                                g[3] = -r[2];
                                g[5] = r[0];
                            }
                            _ => {
                                g[3] = r[1];
                                g[4] = -r[0];
                            }
                        }
                        set_dofs.push(Dof::new(n, k));
                        g_rows.push(g);
                        weight.push(wi);
                    }
                }
                let mut normal = [[0.0; 6]; 6];
                for (g, wi) in g_rows.iter().zip(&weight) {
                    for a in 0..6 {
                        for b in 0..6 {
                            normal[a][b] += wi * g[a] * g[b];
                        }
                    }
                }
                let inv = invert6(&normal).ok_or_else(|| {
                    bad("its nodes are collinear (or a single point): the rotation about their line is undetermined; use more nodes off the line or a rigid coupling".into())
                })?;
                // R = N^-1 [w_i G_i^T]: column j of R for set DOF j.
                let rcols: Vec<[f64; 6]> = g_rows
                    .iter()
                    .zip(&weight)
                    .map(|(g, wi)| {
                        std::array::from_fn(|a| (0..6).map(|b| inv[a][b] * wi * g[b]).sum())
                    })
                    .collect();
                // Six dependent set DOFs: greedy pivoting for a regular R_d.
                let dep = pick_columns(&rcols)
                    .ok_or_else(|| bad("no six set DOFs determine the point's motion".into()))?;
                let rd: [[f64; 6]; 6] =
                    std::array::from_fn(|a| std::array::from_fn(|k| rcols[dep[k]][a]));
                let rd_inv =
                    invert6(&rd).ok_or_else(|| bad("singular choice of dependent DOFs".into()))?;
                // u_d = R_d^-1 (u_P - sum_{j indep} R_j u_j).
                for (k, &dk) in dep.iter().enumerate() {
                    let mut terms: Vec<(Dof, f64)> = (0..6)
                        .map(|a| (pdof(DofKind::ALL[a]), rd_inv[k][a]))
                        .filter(|(_, c)| c.abs() > 0.0)
                        .collect();
                    for (j, dof) in set_dofs.iter().enumerate() {
                        if dep.contains(&j) {
                            continue;
                        }
                        let c: f64 = -(0..6).map(|a| rd_inv[k][a] * rcols[j][a]).sum::<f64>();
                        if c != 0.0 {
                            terms.push((*dof, c));
                        }
                    }
                    out.insert(set_dofs[dk], terms);
                }
            }
        }
        Ok(out)
    }
}

/// Six columns (of length 6) with a well-conditioned 6x6 submatrix, chosen
/// greedily by largest residual after projecting out the chosen ones.
fn pick_columns(cols: &[[f64; 6]]) -> Option<[usize; 6]> {
    let mut basis: Vec<[f64; 6]> = Vec::new();
    let mut chosen = Vec::new();
    let scale = cols.iter().map(norm).fold(0.0, f64::max);
    for _ in 0..6 {
        let residual = |c: &[f64; 6]| -> [f64; 6] {
            let mut v = *c;
            for q in &basis {
                let d: f64 = (0..6).map(|i| q[i] * v[i]).sum();
                for i in 0..6 {
                    v[i] -= d * q[i];
                }
            }
            v
        };
        let (best, v) = cols
            .iter()
            .enumerate()
            .filter(|(j, _)| !chosen.contains(j))
            .map(|(j, c)| (j, residual(c)))
            .max_by(|a, b| norm(&a.1).total_cmp(&norm(&b.1)))?;
        let n = norm(&v);
        if n <= 1e-10 * scale {
            return None;
        }
        basis.push(v.map(|x| x / n));
        chosen.push(best);
    }
    Some(std::array::from_fn(|k| chosen[k]))
}

fn norm(v: &[f64; 6]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Inverse of a 6x6 matrix by Gauss-Jordan with partial pivoting; `None` if
/// (numerically) singular.
fn invert6(a: &[[f64; 6]; 6]) -> Option<[[f64; 6]; 6]> {
    let mut m = *a;
    let mut inv = [[0.0; 6]; 6];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    let scale = a.iter().flatten().fold(0.0_f64, |s, x| s.max(x.abs()));
    for col in 0..6 {
        let piv = (col..6).max_by(|&x, &y| m[x][col].abs().total_cmp(&m[y][col].abs()))?;
        if m[piv][col].abs() <= 1e-12 * scale {
            return None;
        }
        m.swap(col, piv);
        inv.swap(col, piv);
        let d = m[col][col];
        for j in 0..6 {
            m[col][j] /= d;
            inv[col][j] /= d;
        }
        for r in 0..6 {
            if r != col {
                let f = m[r][col];
                if f != 0.0 {
                    for j in 0..6 {
                        m[r][j] -= f * m[col][j];
                        inv[r][j] -= f * inv[col][j];
                    }
                }
            }
        }
    }
    Some(inv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::BrickBlock;
    use crate::{assemble, Material, Model, Node};
    use faer::Mat;
    use flexbody_linalg::eigen::generalized_symmetric;
    use std::collections::BTreeMap;

    /// A C3D8 bar of `n` elements along x (0.1 m cubes, a [`BrickBlock`]),
    /// its far end x = 0.1 n held if `fixed_far_end`; the point is node 1000
    /// at the centre of the face x = 0.
    fn bar(n: usize, fixed_far_end: bool) -> Model {
        let bar = BrickBlock {
            cells: [n, 1, 1],
            origin: [0.0; 3],
            size: [0.1 * n as f64, 0.1, 0.1],
        };
        let mut nodes = bar.nodes();
        nodes.push(Node {
            id: 1000,
            coords: [0.0, 0.05, 0.05],
        });
        let material = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let fixed = if fixed_far_end {
            [[0, 0], [1, 0], [0, 1], [1, 1]]
                .iter()
                .flat_map(|&[j, k]| {
                    [DofKind::Ux, DofKind::Uy, DofKind::Uz]
                        .map(|d| Dof::new(bar.node([n, j, k]), d))
                })
                .collect()
        } else {
            vec![]
        };
        Model::of(nodes, bar.elements(&material))
            .fixed(fixed)
            .build()
            .unwrap()
    }

    /// The nodes of the face x = 0 of a [`bar`], which the couplings hold.
    fn face(model: &Model) -> Vec<NodeId> {
        model
            .nodes()
            .iter()
            .filter(|p| p.coords[0] == 0.0 && p.id != 1000)
            .map(|p| p.id)
            .collect()
    }

    fn coupled(model: Model, kind: CouplingKind) -> Model {
        let nodes = face(&model);
        model
            .with_couplings(vec![Coupling {
                name: "face".into(),
                kind,
                point: 1000,
                nodes,
                weights: None,
            }])
            .unwrap()
    }

    fn rigid(model: &Model, motion: [f64; 6]) -> Vec<f64> {
        let c = model.coords(1000);
        model
            .dof_map()
            .dofs()
            .iter()
            .map(|d| {
                let x = model.coords(d.node);
                let r = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
                let [u, v, w, a, b, g] = motion;
                match d.kind {
                    DofKind::Ux => u + b * r[2] - g * r[1],
                    DofKind::Uy => v - a * r[2] + g * r[0],
                    DofKind::Uz => w + a * r[1] - b * r[0],
                    DofKind::Rx => a,
                    DofKind::Ry => b,
                    DofKind::Rz => g,
                }
            })
            .collect()
    }

    #[test]
    fn a_rigid_coupling_moves_its_face_rigidly_without_strain() {
        let model = coupled(bar(3, false), CouplingKind::Rigid);
        assert_eq!(model.dof_map().len(), 16 * 3 - 12 + 6);
        let k = assemble(&model).unwrap().stiffness;
        for motion in [
            [0.0, 0.0, 0.0, 1e-3, 0.0, 0.0],
            [1e-3, 0.0, 0.0, 0.0, 2e-3, -1e-3],
        ] {
            let u = rigid(&model, motion);
            let ku = &k * Mat::from_fn(u.len(), 1, |i, _| u[i]);
            assert!(ku.norm_max() < 1e-12 * flexbody_linalg::sparse::max_abs_diagonal(&k) * 1e-3);
            // The face nodes, eliminated, follow the point as a rigid body.
            let c = model.coords(1000);
            for n in face(&model) {
                let x = model.coords(n);
                let want_w = motion[2] + motion[3] * (x[1] - c[1]) - motion[4] * (x[0] - c[0]);
                assert!((model.value(Dof::new(n, DofKind::Uz), &u) - want_w).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn a_distributing_coupling_adds_no_stiffness() {
        let plain = assemble(&bar(3, false)).unwrap();
        let model = coupled(bar(3, false), CouplingKind::Distributing);
        assert_eq!(
            model.dof_map().len(),
            16 * 3,
            "6 point DOFs in, 6 face DOFs out"
        );
        let with = assemble(&model).unwrap();
        let a = generalized_symmetric(
            plain.stiffness.to_dense().as_ref(),
            plain.mass.to_dense().as_ref(),
        )
        .unwrap();
        let b = generalized_symmetric(
            with.stiffness.to_dense().as_ref(),
            with.mass.to_dense().as_ref(),
        )
        .unwrap();
        for (x, y) in a.values.iter().zip(&b.values).skip(6) {
            assert!((x - y).abs() < 1e-8 * x, "{x} vs {y}");
        }
        // The point follows the face's mean motion: a translation of the face.
        let u: Vec<f64> = model
            .dof_map()
            .dofs()
            .iter()
            .map(|d| if d.kind == DofKind::Uz { 1.0 } else { 0.0 })
            .collect();
        let i = model
            .dof_map()
            .index_of(Dof::new(1000, DofKind::Uz))
            .unwrap();
        assert_eq!(u[i], 1.0);
        for n in face(&model) {
            assert!((model.value(Dof::new(n, DofKind::Uz), &u) - 1.0).abs() < 1e-12);
        }
    }

    /// Static load at the point of a cantilever: the element forces on the
    /// face nodes (the full mesh's interface forces) sum up to the load.
    #[test]
    fn both_couplings_pass_the_load_to_the_face_in_equilibrium() {
        for kind in [CouplingKind::Rigid, CouplingKind::Distributing] {
            let model = coupled(bar(4, true), kind);
            let s = assemble(&model).unwrap();
            let n = model.dof_map().len();
            let face = face(&model);
            let (fz, mx) = (1000.0, 30.0);
            let mut f = Mat::<f64>::zeros(n, 1);
            for (dof, load) in [(DofKind::Uz, fz), (DofKind::Rx, mx)] {
                let i = model.dof_map().index_of(Dof::new(1000, dof)).unwrap();
                f[(i, 0)] = load;
            }
            let u = flexbody_linalg::ldlt::Factor::of(&s.stiffness)
                .unwrap()
                .solve(f.as_ref());
            let u: Vec<f64> = (0..n).map(|i| u[(i, 0)]).collect();
            // Nodal forces of the elements on the face nodes.
            let mut node_force: BTreeMap<u64, [f64; 3]> = BTreeMap::new();
            for e in model.elements() {
                let em = e.matrices(&model).unwrap();
                let ue: Vec<f64> = em.dofs.iter().map(|d| model.value(*d, &u)).collect();
                for (a, d) in em.dofs.iter().enumerate() {
                    if face.contains(&d.node) {
                        let fa: f64 = (0..ue.len()).map(|b| em.stiffness[(a, b)] * ue[b]).sum();
                        node_force.entry(d.node).or_default()[d.kind.index()] += fa;
                    }
                }
            }
            let c = model.coords(1000);
            let (mut total_z, mut moment_x) = (0.0, 0.0);
            for (node, force) in &node_force {
                let x = model.coords(*node);
                total_z += force[2];
                moment_x += (x[1] - c[1]) * force[2] - (x[2] - c[2]) * force[1];
            }
            assert!((total_z - fz).abs() < 1e-8 * fz, "{kind:?}: {total_z}");
            assert!((moment_x - mx).abs() < 1e-8 * fz, "{kind:?}: {moment_x}");
        }
    }

    /// `u^T M v`.
    fn mass_product(m: &flexbody_linalg::SparseMat, u: &[f64], v: &[f64]) -> f64 {
        let mv = m * Mat::from_fn(v.len(), 1, |i, _| v[i]);
        u.iter().enumerate().map(|(i, x)| x * mv[(i, 0)]).sum()
    }

    /// A lumped mass with inertia on the reference node of a rigid spider
    /// (free-free): it adds to the rigid-body mass and to the rotary
    /// inertia about axes through the node, as a rigid body would.
    #[test]
    fn a_point_mass_on_a_reference_node_adds_to_the_rigid_body_mass() {
        let plain = bar(3, false);
        let (m, inertia) = (5.0, [0.2, 0.3, 0.4, 0.0, 0.0, 0.0]);
        let mut elements = plain.elements().to_vec();
        elements.push(
            crate::element::PointMass {
                id: 99,
                node: 1000,
                mass: m,
                inertia,
            }
            .into(),
        );
        let face = face(&plain);
        let refused = Model::of(plain.nodes().to_vec(), elements.clone()).build();
        assert!(
            matches!(refused, Err(FemError::MassWithoutDof { node: 1000 })),
            "without the coupling nothing carries the mass: {refused:?}"
        );
        let model = Model::of(plain.nodes().to_vec(), elements)
            .couplings(vec![Coupling {
                name: "face".into(),
                kind: CouplingKind::Rigid,
                point: 1000,
                nodes: face,
                weights: None,
            }])
            .build()
            .unwrap();
        let mass = assemble(&model).unwrap().mass;
        // The bar: 0.3 x 0.1 x 0.1 m of steel, the point at (0, 0.05, 0.05).
        let (rho_v, l, b) = (7850.0 * 0.3 * 0.1 * 0.1, 0.3, 0.1);
        for (motion, want) in [
            ([1.0, 0.0, 0.0, 0.0, 0.0, 0.0], rho_v + m),
            ([0.0, 0.0, 1.0, 0.0, 0.0, 0.0], rho_v + m),
            (
                [0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
                rho_v * (b * b + b * b) / 12.0 + inertia[0],
            ),
            (
                [0.0, 0.0, 0.0, 0.0, 1.0, 0.0],
                rho_v * (l * l / 3.0 + b * b / 12.0) + inertia[1],
            ),
        ] {
            let u = rigid(&model, motion);
            let got = mass_product(&mass, &u, &u);
            assert!(
                (got - want).abs() < 1e-12 * want,
                "{motion:?}: {got} vs {want}"
            );
        }
    }

    /// A lumped mass on the reference node of a distributing coupling
    /// (RBE3), whose DOFs the coupling eliminates: it moves with the face's
    /// mean motion and adds its mass to the rigid-body mass.
    #[test]
    fn a_point_mass_on_a_distributing_reference_node_is_carried_by_its_constraint() {
        let m = 5.0;
        let plain = bar(3, false);
        let mut elements = plain.elements().to_vec();
        elements.push(
            crate::element::PointMass {
                id: 99,
                node: 1000,
                mass: m,
                inertia: [0.0; 6],
            }
            .into(),
        );
        let model = Model::of(plain.nodes().to_vec(), elements)
            .couplings(vec![Coupling {
                name: "face".into(),
                kind: CouplingKind::Distributing,
                point: 1000,
                nodes: face(&plain),
                weights: None,
            }])
            .build()
            .unwrap();
        let mass = assemble(&model).unwrap().mass;
        let rho_v = 7850.0 * 0.3 * 0.1 * 0.1;
        for motion in [
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
        ] {
            let u: Vec<f64> = model
                .dof_map()
                .dofs()
                .iter()
                .map(|d| motion[d.kind.index()])
                .collect();
            let got = mass_product(&mass, &u, &u);
            let want = rho_v + m;
            assert!(
                (got - want).abs() < 1e-12 * want,
                "{motion:?}: {got} vs {want}"
            );
        }
    }

    /// Grounded dashpots on the face nodes of a rigid coupling, which the
    /// coupling eliminates: through the constraint, a rigid motion of the
    /// point damps as the face nodes' velocities say, `sum c v_n^2`.
    #[test]
    fn dashpots_on_coupled_nodes_act_through_the_constraint() {
        let c = 300.0;
        let plain = bar(3, false);
        let face = face(&plain);
        let mut elements = plain.elements().to_vec();
        for (i, n) in face.iter().enumerate() {
            elements.push(
                crate::element::Dashpot {
                    id: 200 + i,
                    first: Dof::new(*n, DofKind::Ux),
                    second: None,
                    coefficient: c,
                }
                .into(),
            );
        }
        let model = Model::of(plain.nodes().to_vec(), elements)
            .couplings(vec![Coupling {
                name: "face".into(),
                kind: CouplingKind::Rigid,
                point: 1000,
                nodes: face.clone(),
                weights: None,
            }])
            .build()
            .unwrap();
        let damping = assemble(&model).unwrap().damping.unwrap();
        // Translation along x: every face node at unit speed. Rotation
        // about z through the point (0, 0.05, 0.05): ux = -(y - 0.05).
        for (motion, want) in [
            ([1.0, 0.0, 0.0, 0.0, 0.0, 0.0], 4.0 * c),
            ([0.0, 0.0, 0.0, 0.0, 0.0, 1.0], 4.0 * c * 0.05 * 0.05),
            ([0.0, 0.0, 1.0, 0.0, 0.0, 0.0], 0.0),
        ] {
            let u = rigid(&model, motion);
            let got = mass_product(&damping, &u, &u);
            assert!(
                (got - want).abs() < 1e-12 * c,
                "{motion:?}: {got} vs {want}"
            );
        }
    }

    /// A bar held rigidly by a point at its centre, a mass `m` on the point
    /// and a spring `k` from the point's uz to ground: one elastic mode,
    /// `omega^2 = k / (m_bar + m)`, and five rigid-body modes.
    #[test]
    fn a_spring_on_a_massed_reference_node_has_the_analytic_frequency() {
        let block = BrickBlock {
            cells: [3, 1, 1],
            origin: [0.0; 3],
            size: [0.3, 0.1, 0.1],
        };
        let mut nodes = block.nodes();
        let members: Vec<NodeId> = nodes.iter().map(|n| n.id).collect();
        nodes.push(Node {
            id: 1000,
            coords: [0.15, 0.05, 0.05],
        });
        let material = Material::new(2.1e11, 0.3, 7850.0).unwrap();
        let (m, k) = (40.0, 3.0e5);
        let mut elements = block.elements(&material);
        elements.push(
            crate::element::PointMass {
                id: 98,
                node: 1000,
                mass: m,
                inertia: [0.0; 6],
            }
            .into(),
        );
        elements.push(
            crate::element::Spring {
                id: 99,
                first: Dof::new(1000, DofKind::Uz),
                second: None,
                stiffness: k,
            }
            .into(),
        );
        let model = Model::of(nodes, elements)
            .couplings(vec![Coupling {
                name: "all".into(),
                kind: CouplingKind::Rigid,
                point: 1000,
                nodes: members,
                weights: None,
            }])
            .build()
            .unwrap();
        assert_eq!(model.dof_map().len(), 6, "the point's DOFs only");
        let s = assemble(&model).unwrap();
        let eig =
            generalized_symmetric(s.stiffness.to_dense().as_ref(), s.mass.to_dense().as_ref())
                .unwrap();
        let want = k / (7850.0 * 0.3 * 0.1 * 0.1 + m);
        let top = eig.values[5];
        assert!((top - want).abs() < 1e-10 * want, "{top} vs {want}");
        for v in &eig.values[..5] {
            assert!(v.abs() < 1e-9 * want, "a rigid-body mode: {v}");
        }
    }

    #[test]
    fn bad_couplings_are_named() {
        let check = |c: Coupling, needle: &str| {
            let e = bar(2, false)
                .with_couplings(vec![c])
                .unwrap_err()
                .to_string();
            assert!(e.contains("coupling 'c'") && e.contains(needle), "{e}");
        };
        let c = |kind, nodes: Vec<u64>| Coupling {
            name: "c".into(),
            kind,
            point: 1000,
            nodes,
            weights: None,
        };
        check(c(CouplingKind::Rigid, vec![]), "empty");
        check(c(CouplingKind::Distributing, vec![1, 2, 3]), "collinear");
        check(
            c(CouplingKind::Rigid, vec![1, 77]),
            "node 77 does not exist",
        );
        let two = bar(2, false).with_couplings(vec![
            c(CouplingKind::Rigid, vec![1, 2]),
            Coupling {
                point: 12,
                ..c(CouplingKind::Rigid, vec![2, 3])
            },
        ]);
        let e = two.unwrap_err().to_string();
        assert!(e.contains("belongs to two couplings"), "{e}");
    }
}
