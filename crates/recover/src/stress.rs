//! Stresses of solid and shell elements from the Ritz coordinates (report
//! eq. 25 for solids): element stresses at the nodes, averaged over the
//! elements that share a node, and the von Mises equivalent stress. The
//! elements with stresses are those whose [`Element::has_stresses`] holds;
//! each gives its nodal stresses through [`Element::stresses`], on the
//! layers of [`Element::stress_layers`] (a solid's volume; a shell's
//! bottom, middle and top surfaces), and a stress point is a node on a
//! layer. Stresses are linear in u = T q, so modal stress matrices
//! `T_sigma` (6 x r per stress point) give `sigma = T_sigma q` from the r
//! coordinates alone.

use faer::Mat;
use flexbody_fem::element::{von_mises, StressLayer};
use flexbody_fem::{Dof, Element, FemError, Model, NodeId, ValueTerms};
use flexbody_reduce::ReducedBody;
use std::collections::{BTreeMap, HashMap};

/// Elements whose stresses are computed (in parallel) before they are
/// summed at their nodes: 60 MB of results at a time for C3D8 and 38 basis
/// columns (48 bytes per node and column).
const ELEMENTS_PER_BATCH: usize = 4096;

/// Averaged nodal stresses (Pa, Voigt `[sxx, syy, szz, sxy, syz, szx]`) at
/// the stress points: node and layer, ascending by node, then layer.
#[derive(Clone, Debug, PartialEq)]
pub struct NodalStresses {
    /// Nodes of elements with stresses, one entry per layer at the node.
    pub nodes: Vec<NodeId>,
    /// The layer of each entry of `nodes`.
    pub layers: Vec<StressLayer>,
    pub stress: Vec<[f64; 6]>,
}

impl NodalStresses {
    /// Von Mises stress at each stress point (Pa).
    pub fn von_mises(&self) -> Vec<f64> {
        self.stress.iter().map(von_mises).collect()
    }

    /// The stress point with the largest von Mises stress and that stress.
    pub fn peak_von_mises(&self) -> Option<(NodeId, StressLayer, f64)> {
        self.nodes
            .iter()
            .zip(&self.layers)
            .zip(self.von_mises())
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|((n, l), v)| (*n, *l, v))
    }
}

/// Averaged nodal stresses of all elements with stresses for
/// displacements `u` (over the model's equations; fixed DOFs are zero).
pub fn nodal_stresses(model: &Model, u: &[f64]) -> Result<NodalStresses, FemError> {
    let mut sum: BTreeMap<(NodeId, StressLayer), ([f64; 6], usize)> = BTreeMap::new();
    for e in model.elements().iter().filter(|e| e.has_stresses()) {
        let u_e: Vec<f64> = e.dofs().iter().map(|d: &Dof| model.value(*d, u)).collect();
        let Some(stresses) = e.stresses(model, &u_e, 1)? else {
            continue;
        };
        let nodes = e.nodes();
        for (l, layer) in e.stress_layers().iter().enumerate() {
            let on_layer = &stresses[l * nodes.len()..(l + 1) * nodes.len()];
            for (node, sigma) in nodes.iter().zip(on_layer) {
                let entry = sum.entry((*node, *layer)).or_insert(([0.0; 6], 0));
                for (acc, v) in entry.0.iter_mut().zip(sigma) {
                    *acc += v;
                }
                entry.1 += 1;
            }
        }
    }
    Ok(NodalStresses {
        nodes: sum.keys().map(|k| k.0).collect(),
        layers: sum.keys().map(|k| k.1).collect(),
        stress: sum
            .values()
            .map(|(s, c)| s.map(|v| v / *c as f64))
            .collect(),
    })
}

/// Modal stress matrices of a reduced body: `sigma(point) = T_sigma(point) q`
/// at each stress point (node and layer, as [`NodalStresses`]).
#[derive(Clone, Debug)]
pub struct ModalStress {
    pub nodes: Vec<NodeId>,
    pub layers: Vec<StressLayer>,
    /// One 6 x r matrix per stress point.
    pub matrices: Vec<Mat<f64>>,
}

impl ModalStress {
    /// Stresses of every basis column, one column of `T_sigma` each: per
    /// element, its geometry once for all columns, the elements in
    /// parallel; the same values as [`nodal_stresses`] of each column, bit
    /// for bit (each point sums its elements in the model's order).
    pub fn new(model: &Model, body: &ReducedBody) -> Result<Self, FemError> {
        use rayon::prelude::*;
        let r = body.r();
        let stressed: Vec<&Element> = model
            .elements()
            .iter()
            .filter(|e| e.has_stresses())
            .collect();
        let mut points: Vec<(NodeId, StressLayer)> = stressed
            .iter()
            .flat_map(|e| {
                let nodes = e.nodes();
                e.stress_layers()
                    .iter()
                    .flat_map(move |l| nodes.clone().into_iter().map(move |n| (n, *l)))
            })
            .collect();
        points.sort_unstable();
        points.dedup();
        let position: HashMap<(NodeId, StressLayer), usize> =
            points.iter().enumerate().map(|(k, &p)| (p, k)).collect();
        // Per point and column, the sum over its elements; per point, their count.
        let mut sum = vec![[0.0; 6]; points.len() * r];
        let mut count = vec![0usize; points.len()];
        let element_stresses = |e: &&Element| {
            let terms: Vec<ValueTerms> = e.dofs().iter().map(|d| model.value_terms(*d)).collect();
            let mut u_e = Vec::with_capacity(terms.len() * r);
            for j in 0..r {
                let u = body.basis.col_as_slice(j);
                u_e.extend(terms.iter().map(|t| t.of(u)));
            }
            e.stresses(model, &u_e, r)
        };
        for chunk in stressed.chunks(ELEMENTS_PER_BATCH) {
            let stresses: Vec<_> = chunk.par_iter().map(element_stresses).collect();
            for (e, st) in chunk.iter().zip(stresses) {
                let Some(st) = st? else { continue };
                let element_nodes = e.nodes();
                let nn = element_nodes.len();
                let layers = e.stress_layers();
                let nl = layers.len();
                for (l, layer) in layers.iter().enumerate() {
                    for (a, node) in element_nodes.iter().enumerate() {
                        let k = position[&(*node, *layer)];
                        count[k] += 1;
                        for j in 0..r {
                            for (acc, v) in sum[k * r + j].iter_mut().zip(st[(j * nl + l) * nn + a])
                            {
                                *acc += v;
                            }
                        }
                    }
                }
            }
        }
        let matrices = (0..points.len())
            .map(|k| Mat::from_fn(6, r, |c, j| sum[k * r + j][c] / count[k] as f64))
            .collect();
        Ok(Self {
            nodes: points.iter().map(|p| p.0).collect(),
            layers: points.iter().map(|p| p.1).collect(),
            matrices,
        })
    }

    /// Nodal stresses from the Ritz coordinates `q`.
    pub fn stresses(&self, q: &[f64]) -> NodalStresses {
        NodalStresses {
            nodes: self.nodes.clone(),
            layers: self.layers.clone(),
            stress: self
                .matrices
                .iter()
                .map(|t| std::array::from_fn(|c| (0..q.len()).map(|j| t[(c, j)] * q[j]).sum()))
                .collect(),
        }
    }
}
