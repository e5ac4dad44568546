//! Stresses of solid elements from the Ritz coordinates (report eq. 25 for
//! solids): element stresses at the nodes, averaged over the elements that
//! share a node, and the von Mises equivalent stress. The elements with
//! stresses are those whose [`Element::has_stresses`] holds; each gives its
//! nodal stresses through [`Element::stresses`]. Stresses are linear in
//! u = T q, so modal stress matrices `T_sigma` (6 x r per node) give
//! `sigma = T_sigma q` from the r coordinates alone.

use faer::Mat;
use flexbody_fem::element::von_mises;
use flexbody_fem::{Dof, Element, FemError, Model, NodeId, ValueTerms};
use flexbody_reduce::ReducedBody;
use std::collections::{BTreeMap, HashMap};

/// Elements whose stresses are computed (in parallel) before they are
/// summed at their nodes: 60 MB of results at a time for C3D8 and 38 basis
/// columns (48 bytes per node and column).
const ELEMENTS_PER_BATCH: usize = 4096;

/// Averaged nodal stresses (Pa, Voigt `[sxx, syy, szz, sxy, syz, szx]`).
#[derive(Clone, Debug, PartialEq)]
pub struct NodalStresses {
    /// Nodes of solid elements, ascending.
    pub nodes: Vec<NodeId>,
    pub stress: Vec<[f64; 6]>,
}

impl NodalStresses {
    /// Von Mises stress at each node (Pa).
    pub fn von_mises(&self) -> Vec<f64> {
        self.stress.iter().map(von_mises).collect()
    }

    /// The node with the largest von Mises stress and that stress.
    pub fn peak_von_mises(&self) -> Option<(NodeId, f64)> {
        self.nodes
            .iter()
            .zip(self.von_mises())
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(n, v)| (*n, v))
    }
}

/// Averaged nodal stresses of all solid elements for displacements `u`
/// (over the model's equations; fixed DOFs are zero).
pub fn nodal_stresses(model: &Model, u: &[f64]) -> Result<NodalStresses, FemError> {
    let mut sum: BTreeMap<NodeId, ([f64; 6], usize)> = BTreeMap::new();
    for e in model.elements().iter().filter(|e| e.has_stresses()) {
        let u_e: Vec<f64> = e.dofs().iter().map(|d: &Dof| model.value(*d, u)).collect();
        let Some(stresses) = e.stresses(model, &u_e, 1)? else {
            continue;
        };
        for (node, sigma) in e.nodes().iter().zip(stresses) {
            let entry = sum.entry(*node).or_insert(([0.0; 6], 0));
            for (acc, v) in entry.0.iter_mut().zip(sigma) {
                *acc += v;
            }
            entry.1 += 1;
        }
    }
    Ok(NodalStresses {
        nodes: sum.keys().copied().collect(),
        stress: sum
            .values()
            .map(|(s, c)| s.map(|v| v / *c as f64))
            .collect(),
    })
}

/// Modal stress matrices of a reduced body: `sigma(node) = T_sigma(node) q`.
#[derive(Clone, Debug)]
pub struct ModalStress {
    pub nodes: Vec<NodeId>,
    /// One 6 x r matrix per node.
    pub matrices: Vec<Mat<f64>>,
}

impl ModalStress {
    /// Stresses of every basis column, one column of `T_sigma` each: per
    /// element, its geometry once for all columns, the elements in
    /// parallel; the same values as [`nodal_stresses`] of each column, bit
    /// for bit (each node sums its elements in the model's order).
    pub fn new(model: &Model, body: &ReducedBody) -> Result<Self, FemError> {
        use rayon::prelude::*;
        let r = body.r();
        let solids: Vec<&Element> = model
            .elements()
            .iter()
            .filter(|e| e.has_stresses())
            .collect();
        let mut nodes: Vec<NodeId> = solids.iter().flat_map(|e| e.nodes()).collect();
        nodes.sort_unstable();
        nodes.dedup();
        let position: HashMap<NodeId, usize> =
            nodes.iter().enumerate().map(|(k, &n)| (n, k)).collect();
        // Per node and column, the sum over its elements; per node, their count.
        let mut sum = vec![[0.0; 6]; nodes.len() * r];
        let mut count = vec![0usize; nodes.len()];
        let element_stresses = |e: &&Element| {
            let terms: Vec<ValueTerms> = e.dofs().iter().map(|d| model.value_terms(*d)).collect();
            let mut u_e = Vec::with_capacity(terms.len() * r);
            for j in 0..r {
                let u = body.basis.col_as_slice(j);
                u_e.extend(terms.iter().map(|t| t.of(u)));
            }
            e.stresses(model, &u_e, r)
        };
        for chunk in solids.chunks(ELEMENTS_PER_BATCH) {
            let stresses: Vec<_> = chunk.par_iter().map(element_stresses).collect();
            for (e, st) in chunk.iter().zip(stresses) {
                let Some(st) = st? else { continue };
                let element_nodes = e.nodes();
                let nn = element_nodes.len();
                for (a, node) in element_nodes.iter().enumerate() {
                    let k = position[node];
                    count[k] += 1;
                    for j in 0..r {
                        for (acc, v) in sum[k * r + j].iter_mut().zip(st[j * nn + a]) {
                            *acc += v;
                        }
                    }
                }
            }
        }
        let matrices = (0..nodes.len())
            .map(|k| Mat::from_fn(6, r, |c, j| sum[k * r + j][c] / count[k] as f64))
            .collect();
        Ok(Self { nodes, matrices })
    }

    /// Nodal stresses from the Ritz coordinates `q`.
    pub fn stresses(&self, q: &[f64]) -> NodalStresses {
        NodalStresses {
            nodes: self.nodes.clone(),
            stress: self
                .matrices
                .iter()
                .map(|t| std::array::from_fn(|c| (0..q.len()).map(|j| t[(c, j)] * q[j]).sum()))
                .collect(),
        }
    }
}
