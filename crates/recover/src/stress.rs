//! Stresses of solid elements from the Ritz coordinates (report eq. 25 for
//! solids): element stresses at the nodes, averaged over the elements that
//! share a node, and the von Mises equivalent stress. Stresses are linear in
//! u = T q, so modal stress matrices `T_sigma` (6 x r per node) give
//! `sigma = T_sigma q` from the r coordinates alone.

use faer::Mat;
use flexbody_fem::element::von_mises;
use flexbody_fem::{Dof, Element, FemError, Model, NodeId};
use flexbody_reduce::ReducedBody;
use std::collections::BTreeMap;

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
    for e in model.elements() {
        let Element::Solid(s) = e else { continue };
        let coords: Vec<[f64; 3]> = s.nodes.iter().map(|&n| model.coords(n)).collect();
        let u_e: Vec<f64> = e.dofs().iter().map(|d: &Dof| model.value(*d, u)).collect();
        for (node, sigma) in s.nodes.iter().zip(s.nodal_stresses(&coords, &u_e)?) {
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
    /// Stresses of every basis column, one column of `T_sigma` each.
    pub fn new(model: &Model, body: &ReducedBody) -> Result<Self, FemError> {
        let r = body.r();
        let m = body.basis.nrows();
        let mut columns = Vec::with_capacity(r);
        for j in 0..r {
            let t: Vec<f64> = (0..m).map(|i| body.basis[(i, j)]).collect();
            columns.push(nodal_stresses(model, &t)?);
        }
        let nodes = columns.first().map_or_else(Vec::new, |c| c.nodes.clone());
        let matrices = (0..nodes.len())
            .map(|k| Mat::from_fn(6, r, |c, j| columns[j].stress[k][c]))
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
