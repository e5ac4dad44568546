//! A substructure: what a reduction needs of one component, whether it came
//! from a mesh or only from matrices.

use crate::assembly::{assemble, SystemMatrices};
use crate::dof::{Dof, DofMap};
use crate::element::Element;
use crate::local_axes::{Axes, AxesChange};
use crate::model::{Model, NodeId};
use crate::FemError;
use std::collections::{BTreeMap, HashMap};

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
    /// Nodes whose equations are along local axes ([`Substructure::in_local_axes`]);
    /// empty: every equation is along a global axis.
    pub local_axes: BTreeMap<NodeId, Axes>,
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
            local_axes: BTreeMap::new(),
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
            local_axes: BTreeMap::new(),
        }
    }

    /// The substructure over local DOFs at the nodes of `axes` (report
    /// eq. 1 under the orthogonal change of basis `u = T u'` of
    /// [`AxesChange`]): `K' = T^T K T`, `M' = T^T M T`, `D' = T^T D T`, the
    /// same DOF names, which at these nodes mean the local axes. Returns the
    /// change too, to turn a basis over the new equations back to global
    /// rows (`Phi = T Phi'`). Nodes already along local axes are refused.
    pub fn in_local_axes(
        &self,
        axes: &BTreeMap<NodeId, Axes>,
    ) -> Result<(Substructure, AxesChange), FemError> {
        if let Some(node) = self.local_axes.keys().next() {
            return Err(FemError::LocalAxes(format!(
                "node {node}: the substructure is along local axes already"
            )));
        }
        let change = AxesChange::new(&self.dof_map, axes)?;
        let m = &self.matrices;
        let matrices = SystemMatrices {
            stiffness: change.congruence(&m.stiffness)?,
            mass: change.congruence(&m.mass)?,
            damping: m
                .damping
                .as_ref()
                .map(|d| change.congruence(d))
                .transpose()?,
        };
        let local_axes = axes
            .iter()
            .filter(|(n, _)| !self.dof_map.node_dofs(**n).is_empty())
            .map(|(n, r)| (*n, *r))
            .collect();
        Ok((
            Substructure {
                dof_map: self.dof_map.clone(),
                coordinates: self.coordinates.clone(),
                support: self.support,
                matrices,
                local_axes,
            },
            change,
        ))
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
