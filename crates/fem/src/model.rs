//! The FE model of one component: nodes, elements, node sets, boundary
//! conditions and Rayleigh damping.

use crate::dof::{Dof, DofKind, DofMap};
use crate::element::Element;
use crate::FemError;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// User node number (as in the model file).
pub type NodeId = u64;

/// A node with global coordinates (m).
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub id: NodeId,
    pub coords: [f64; 3],
}

/// Rayleigh damping `D = alpha M + beta K` (alpha in 1/s, beta in s).
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Rayleigh {
    pub alpha: f64,
    pub beta: f64,
}

/// A linear FE model. Built with [`Model::new`], which checks that every
/// element refers to existing nodes; immutable afterwards.
#[derive(Clone, Debug)]
pub struct Model {
    nodes: Vec<Node>,
    node_index: HashMap<NodeId, usize>,
    elements: Vec<Element>,
    node_sets: BTreeMap<String, Vec<NodeId>>,
    fixed: BTreeSet<Dof>,
    rayleigh: Option<Rayleigh>,
    dof_map: DofMap,
}

impl Model {
    /// Builds and checks a model.
    pub fn new(
        nodes: Vec<Node>,
        elements: Vec<Element>,
        node_sets: BTreeMap<String, Vec<NodeId>>,
        fixed: Vec<Dof>,
        rayleigh: Option<Rayleigh>,
    ) -> Result<Self, FemError> {
        let mut node_index = HashMap::with_capacity(nodes.len());
        for (i, n) in nodes.iter().enumerate() {
            if node_index.insert(n.id, i).is_some() {
                return Err(FemError::DuplicateNode(n.id));
            }
            for c in n.coords {
                if !c.is_finite() {
                    return Err(FemError::InvalidValue {
                        what: format!("coordinate of node {}", n.id),
                        rule: "finite",
                        value: c,
                    });
                }
            }
        }
        for e in &elements {
            for node in e.nodes() {
                if !node_index.contains_key(&node) {
                    return Err(FemError::UnknownNode {
                        element: e.id(),
                        node,
                    });
                }
            }
        }
        for (name, set) in &node_sets {
            for node in set {
                if !node_index.contains_key(node) {
                    return Err(FemError::UnknownNodeIn {
                        what: format!("node set '{name}'"),
                        node: *node,
                    });
                }
            }
        }
        if let Some(r) = rayleigh {
            crate::require_non_negative("Rayleigh alpha", r.alpha)?;
            crate::require_non_negative("Rayleigh beta", r.beta)?;
        }
        let mut model = Self {
            nodes,
            node_index,
            elements,
            node_sets,
            fixed: fixed.into_iter().collect(),
            rayleigh,
            dof_map: DofMap::default(),
        };
        model.dof_map = model.build_dof_map()?;
        Ok(model)
    }

    /// Free DOFs: those the stiffness-carrying elements create, minus the
    /// fixed ones. Point masses only load DOFs that exist.
    fn build_dof_map(&self) -> Result<DofMap, FemError> {
        let mut active: BTreeSet<(usize, DofKind)> = BTreeSet::new();
        for e in &self.elements {
            if e.creates_dofs() {
                for d in e.dofs() {
                    active.insert((self.node_index[&d.node], d.kind));
                }
            }
        }
        for e in &self.elements {
            if let Element::PointMass(m) = e {
                if !DofKind::ALL
                    .iter()
                    .any(|k| active.contains(&(self.node_index[&m.node], *k)))
                {
                    return Err(FemError::MassWithoutDof { node: m.node });
                }
            }
        }
        for d in &self.fixed {
            let Some(&idx) = self.node_index.get(&d.node) else {
                return Err(FemError::UnknownNodeIn {
                    what: "boundary condition".into(),
                    node: d.node,
                });
            };
            if !active.contains(&(idx, d.kind)) {
                return Err(FemError::UnknownDof {
                    what: "boundary condition".into(),
                    node: d.node,
                    dof: d.kind,
                });
            }
        }
        let dofs: Vec<Dof> = active
            .into_iter()
            .map(|(i, k)| Dof::new(self.nodes[i].id, k))
            .filter(|d| !self.fixed.contains(d))
            .collect();
        if dofs.is_empty() {
            return Err(FemError::Empty);
        }
        Ok(DofMap::new(dofs))
    }

    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    pub fn node_sets(&self) -> &BTreeMap<String, Vec<NodeId>> {
        &self.node_sets
    }

    /// DOFs held fixed by boundary conditions.
    pub fn fixed_dofs(&self) -> impl Iterator<Item = &Dof> {
        self.fixed.iter()
    }

    pub fn rayleigh(&self) -> Option<Rayleigh> {
        self.rayleigh
    }

    /// Equation numbering of the free DOFs.
    pub fn dof_map(&self) -> &DofMap {
        &self.dof_map
    }

    /// The node with user id `id`.
    pub fn node(&self, id: NodeId) -> Option<&Node> {
        self.node_index.get(&id).map(|&i| &self.nodes[i])
    }

    /// Coordinates of node `id` (the node must exist: ids come from a
    /// checked model).
    pub fn coords(&self, id: NodeId) -> [f64; 3] {
        self.nodes[self.node_index[&id]].coords
    }

    /// Equation number of a DOF, or an error naming what asked for it.
    pub fn equation(&self, dof: Dof, what: &str) -> Result<usize, FemError> {
        if self.node(dof.node).is_none() {
            return Err(FemError::UnknownNodeIn {
                what: what.into(),
                node: dof.node,
            });
        }
        self.dof_map.index_of(dof).ok_or(FemError::UnknownDof {
            what: what.into(),
            node: dof.node,
            dof: dof.kind,
        })
    }

    /// Mean of the node coordinates (m): the reference point of the
    /// rigid-body modes.
    pub fn centroid(&self) -> [f64; 3] {
        let n = self.nodes.len().max(1) as f64;
        let mut c = [0.0; 3];
        for node in &self.nodes {
            for (ck, xk) in c.iter_mut().zip(node.coords) {
                *ck += xk / n;
            }
        }
        c
    }
}
