//! The body integrals of the invariants from the mesh, element by element
//! ([`MassDistribution`]): the whole body's mass, fixed DOFs included, and
//! products of two fields with each element's own shape functions (a
//! beam's rotations and rotary inertia included).
//!
//! The fields are the positions `x0` and the mode shapes `Phi_k`, the
//! latter read at every DOF of the model through
//! [`Model::value_terms`]: zero at a fixed DOF, a combination at one a
//! coupling or an equation eliminated.

use super::invariants::{cross_of, Integrals};
use super::FfrfError;
use faer::Mat;
use flexbody_fem::element::{MassDistribution, MassPoint};
use flexbody_fem::{Dof, DofKind, Model, NodeId, ValueTerms};
use rayon::prelude::*;
use std::collections::HashMap;

/// The integrals over the mesh `model` of the positions and of the mode
/// shapes `phi` (rows: the model's equations): `int f dm` and
/// `int f g^T dm` for every pair of the fields `x0, Phi_1, ..., Phi_nq`.
pub(super) fn mesh_integrals(model: &Model, phi: &Mat<f64>) -> Result<Integrals, FfrfError> {
    let distributions: Vec<MassDistribution> = model
        .elements()
        .par_iter()
        .map(|e| e.mass_distribution(model))
        .collect::<Result<_, _>>()
        .map_err(FfrfError::Mass)?;
    let nf = phi.ncols() + 1;
    let fields = Fields { model, phi };
    let mut sums = Sums::new(nf);
    nodal_part(&fields, &distributions, &mut sums);
    for (e, d) in model.elements().iter().zip(&distributions) {
        if let MassDistribution::Points(points) = d {
            let dofs = e.dofs();
            let values: Vec<Vec<f64>> = dofs.iter().map(|&d| fields.at(d)).collect();
            for point in points {
                sums.add_point(point, &values);
            }
        }
    }
    Ok(sums.into_integrals())
}

/// The fields at a DOF: `x0` has no DOF values (its nodal values are the
/// coordinates), the modes their rows of `phi`.
struct Fields<'a> {
    model: &'a Model,
    phi: &'a Mat<f64>,
}

impl Fields<'_> {
    /// `Phi_1 .. Phi_nq` at `dof` (zero where fixed).
    fn at(&self, dof: Dof) -> Vec<f64> {
        let terms = self.model.value_terms(dof);
        (0..self.phi.ncols())
            .map(|k| match &terms {
                ValueTerms::Equation(i) => self.phi[(*i, k)],
                ValueTerms::Combination(t) => t.iter().map(|(i, c)| c * self.phi[(*i, k)]).sum(),
                ValueTerms::Fixed => 0.0,
            })
            .collect()
    }
}

/// Running sums: the mass, `int f dm` per field and `int f g^T dm` as one
/// matrix of 3 x 3 blocks (block `(f, g)`; field 0 is `x0`).
struct Sums {
    mass: f64,
    first: Vec<[f64; 3]>,
    products: Mat<f64>,
}

impl Sums {
    fn new(nf: usize) -> Self {
        Self {
            mass: 0.0,
            first: vec![[0.0; 3]; nf],
            products: Mat::zeros(3 * nf, 3 * nf),
        }
    }

    /// A rigid slice: `m u_f u_g^T + L_f R L_g^T` with `L = theta~` for a
    /// mode, `L = I` for `x0`, and `R = tr(J)/2 I - J`.
    fn add_point(&mut self, p: &MassPoint, values: &[Vec<f64>]) {
        let nf = self.first.len();
        let apply = |map: &Mat<f64>, k: usize| -> [f64; 3] {
            std::array::from_fn(|d| (0..values.len()).map(|j| map[(d, j)] * values[j][k]).sum())
        };
        // Translations and section maps of every field at the point.
        let mut u = vec![p.position];
        let mut l = vec![[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]];
        for k in 0..nf - 1 {
            u.push(apply(&p.translation, k));
            l.push(skew(apply(&p.rotation, k)));
        }
        let trace = p.inertia[0][0] + p.inertia[1][1] + p.inertia[2][2];
        let r: [[f64; 3]; 3] = std::array::from_fn(|a| {
            std::array::from_fn(|b| f64::from(u8::from(a == b)) * trace / 2.0 - p.inertia[a][b])
        });
        let lr: Vec<[[f64; 3]; 3]> = l.iter().map(|lf| mul(lf, &r)).collect();
        self.mass += p.mass;
        for (first, uf) in self.first.iter_mut().zip(&u) {
            for (slot, v) in first.iter_mut().zip(uf) {
                *slot += p.mass * v;
            }
        }
        for f in 0..nf {
            for g in 0..nf {
                for a in 0..3 {
                    for b in 0..3 {
                        let section: f64 = (0..3).map(|c| lr[f][a][c] * l[g][b][c]).sum();
                        self.products[(3 * f + a, 3 * g + b)] +=
                            p.mass * u[f][a] * u[g][b] + section;
                    }
                }
            }
        }
    }

    fn into_integrals(self) -> Integrals {
        let nf = self.first.len();
        let block = |f: usize, g: usize| -> [[f64; 3]; 3] {
            std::array::from_fn(|a| std::array::from_fn(|b| self.products[(3 * f + a, 3 * g + b)]))
        };
        Integrals {
            mass: self.mass,
            md_cm: self.first[0],
            first: self.first[1..].to_vec(),
            x_x: block(0, 0),
            cross: (1..nf).map(|k| cross_of(&block(0, k))).collect(),
            x_phi: (1..nf).map(|k| block(0, k)).collect(),
            phi_phi: (1..nf)
                .map(|k| (1..nf).map(|l| block(k, l)).collect())
                .collect(),
        }
    }
}

/// The elements of the nodal form: `sum_pq S_pq f_p g_q^T` over the
/// nodes they touch, as one product `F^T (S F)` of the fields side by side
/// (node rows; column `3 f + a`: direction `a` of field `f`).
fn nodal_part(fields: &Fields<'_>, distributions: &[MassDistribution], sums: &mut Sums) {
    let nf = sums.first.len();
    let mut index: HashMap<NodeId, usize> = HashMap::new();
    let mut nodes = Vec::new();
    let mut coupling: Vec<(usize, usize, f64)> = Vec::new();
    for d in distributions {
        if let MassDistribution::Nodal {
            nodes: own,
            coupling: s,
        } = d
        {
            let at: Vec<usize> = own
                .iter()
                .map(|n| {
                    *index.entry(*n).or_insert_with(|| {
                        nodes.push(*n);
                        nodes.len() - 1
                    })
                })
                .collect();
            for (p, &gp) in at.iter().enumerate() {
                for (q, &gq) in at.iter().enumerate() {
                    coupling.push((gp, gq, s[(p, q)]));
                }
            }
        }
    }
    if nodes.is_empty() {
        return;
    }
    // One sum per node pair.
    coupling.par_sort_unstable_by_key(|&(p, q, _)| (p, q));
    coupling.dedup_by(|next, kept| {
        let same = (next.0, next.1) == (kept.0, kept.1);
        if same {
            kept.2 += next.2;
        }
        same
    });
    let f = {
        let per_node: Vec<Vec<f64>> = nodes
            .par_iter()
            .map(|&n| {
                let x = fields.model.coords(n);
                let mut row = vec![0.0; 3 * nf];
                row[..3].copy_from_slice(&x);
                for a in 0..3 {
                    let v = fields.at(Dof::new(n, DofKind::ALL[a]));
                    for (k, value) in v.into_iter().enumerate() {
                        row[3 * (k + 1) + a] = value;
                    }
                }
                row
            })
            .collect();
        Mat::from_fn(nodes.len(), 3 * nf, |p, c| per_node[p][c])
    };
    let mut sf = Mat::<f64>::zeros(nodes.len(), 3 * nf);
    for &(p, q, s) in &coupling {
        sums.mass += s;
        for c in 0..3 * nf {
            sf[(p, c)] += s * f[(q, c)];
        }
    }
    sums.products += f.transpose() * &sf;
    for p in 0..nodes.len() {
        for (fi, first) in sums.first.iter_mut().enumerate() {
            for (a, slot) in first.iter_mut().enumerate() {
                *slot += sf[(p, 3 * fi + a)];
            }
        }
    }
}

fn skew(v: [f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

fn mul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}
