//! A substructure: what a reduction needs of one component, whether it came
//! from a mesh or only from matrices.

use crate::assembly::{assemble, SystemMatrices};
use crate::dof::{Dof, DofMap};
use crate::element::Element;
use crate::model::{Model, NodeId};
use crate::FemError;
use std::collections::HashMap;

/// Whether the component is held by boundary conditions.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Support {
    /// Free in space: rigid-body modes exist.
    Free,
    /// Held (fixed DOFs or springs to ground): K is regular.
    Supported,
    /// Unknown (matrices only): decided from the null space of K.
    Unknown,
}

/// DOFs, node positions (when known), support and assembled matrices of a
/// component.
#[derive(Clone, Debug)]
pub struct Substructure {
    pub dof_map: DofMap,
    /// Node coordinates (m) for rigid-body modes from geometry (eq. 12);
    /// empty when only matrices are known.
    pub coordinates: HashMap<NodeId, [f64; 3]>,
    pub support: Support,
    pub matrices: SystemMatrices,
}

impl Substructure {
    /// Assembles a mesh model.
    pub fn from_model(model: &Model) -> Result<Self, FemError> {
        let supported = model.fixed_dofs().next().is_some()
            || model
                .elements()
                .iter()
                .any(|e| matches!(e, Element::Spring(s) if s.second.is_none()));
        Ok(Self {
            dof_map: model.dof_map().clone(),
            coordinates: model.nodes().iter().map(|n| (n.id, n.coords)).collect(),
            support: if supported {
                Support::Supported
            } else {
                Support::Free
            },
            matrices: assemble(model)?,
        })
    }

    /// Matrices without a mesh (node positions unknown unless given).
    pub fn from_matrices(
        dof_map: DofMap,
        matrices: SystemMatrices,
        coordinates: HashMap<NodeId, [f64; 3]>,
    ) -> Self {
        Self {
            dof_map,
            coordinates,
            support: Support::Unknown,
            matrices,
        }
    }

    /// Number of equations.
    pub fn len(&self) -> usize {
        self.dof_map.len()
    }

    pub fn is_empty(&self) -> bool {
        self.dof_map.is_empty()
    }

    /// Coordinates of every node that has DOFs, if all are known.
    pub fn node_coordinates(&self, node: NodeId) -> Option<[f64; 3]> {
        self.coordinates.get(&node).copied()
    }

    /// True if every DOF's node has coordinates.
    pub fn has_geometry(&self) -> bool {
        self.dof_map
            .dofs()
            .iter()
            .all(|d| self.coordinates.contains_key(&d.node))
    }

    /// Mean position of the nodes that carry DOFs (m).
    pub fn centroid(&self) -> [f64; 3] {
        let mut nodes: Vec<NodeId> = self.dof_map.dofs().iter().map(|d| d.node).collect();
        nodes.dedup();
        let mut c = [0.0; 3];
        let mut count = 0.0;
        for n in nodes {
            if let Some(x) = self.coordinates.get(&n) {
                for (ck, xk) in c.iter_mut().zip(x) {
                    *ck += xk;
                }
                count += 1.0;
            }
        }
        c.map(|v| if count > 0.0 { v / count } else { 0.0 })
    }

    /// Equation number of a DOF, or an error naming what asked for it.
    pub fn equation(&self, dof: Dof, what: &str) -> Result<usize, FemError> {
        self.dof_map.index_of(dof).ok_or(FemError::UnknownDof {
            what: what.into(),
            node: dof.node,
            dof: dof.kind,
        })
    }
}
