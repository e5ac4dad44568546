//! Degrees of freedom: six kinds per node, and the map from (node, kind) to
//! equation numbers.

use crate::id_hash::{id_map, IdMap};
use crate::model::NodeId;
use serde::{Deserialize, Serialize};
use std::fmt;

/// A nodal DOF kind: translations `ux, uy, uz` (m) and rotations
/// `rx, ry, rz` (rad) about the global axes.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DofKind {
    Ux,
    Uy,
    Uz,
    Rx,
    Ry,
    Rz,
}

impl DofKind {
    /// All six kinds in their canonical order.
    pub const ALL: [DofKind; 6] = [
        DofKind::Ux,
        DofKind::Uy,
        DofKind::Uz,
        DofKind::Rx,
        DofKind::Ry,
        DofKind::Rz,
    ];

    /// Position 0..6 in [`DofKind::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// True for `rx, ry, rz`.
    pub fn is_rotation(self) -> bool {
        self.index() >= 3
    }

    /// Lower-case name as in model files (`"uz"`).
    pub fn name(self) -> &'static str {
        ["ux", "uy", "uz", "rx", "ry", "rz"][self.index()]
    }

    /// Parses `"ux"` .. `"rz"` (case-insensitive).
    pub fn parse(s: &str) -> Option<Self> {
        DofKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s))
    }
}

impl fmt::Display for DofKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One DOF: a node (user id) and a kind.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Dof {
    pub node: NodeId,
    pub kind: DofKind,
}

impl Dof {
    pub fn new(node: NodeId, kind: DofKind) -> Self {
        Self { node, kind }
    }
}

impl fmt::Display for Dof {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "node {} {}", self.node, self.kind)
    }
}

/// Equation numbering: the free (unconstrained) DOFs of a model, in node
/// order, kinds in canonical order within a node.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct DofMap {
    dofs: Vec<Dof>,
    #[serde(skip)]
    index: IdMap<Dof, usize>,
}

impl DofMap {
    /// Builds the map from a list of DOFs (equation `i` is `dofs[i]`).
    pub fn new(dofs: Vec<Dof>) -> Self {
        let mut index = id_map(dofs.len());
        index.extend(dofs.iter().enumerate().map(|(i, d)| (*d, i)));
        Self { dofs, index }
    }

    /// Number of equations.
    pub fn len(&self) -> usize {
        self.dofs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// The DOF of equation `i`.
    pub fn dof(&self, i: usize) -> Dof {
        self.dofs[i]
    }

    /// All DOFs, in equation order.
    pub fn dofs(&self) -> &[Dof] {
        &self.dofs
    }

    /// Equation number of `dof`, if it is free.
    pub fn index_of(&self, dof: Dof) -> Option<usize> {
        self.index.get(&dof).copied()
    }

    /// Equation numbers of all free DOFs of `node`, in kind order.
    pub fn node_dofs(&self, node: NodeId) -> Vec<(DofKind, usize)> {
        DofKind::ALL
            .into_iter()
            .filter_map(|k| self.index_of(Dof::new(node, k)).map(|i| (k, i)))
            .collect()
    }

    /// Rebuilds the lookup table after deserialisation.
    pub fn reindex(&mut self) {
        self.index = id_map(self.dofs.len());
        self.index
            .extend(self.dofs.iter().enumerate().map(|(i, d)| (*d, i)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup_and_names() {
        let map = DofMap::new(vec![Dof::new(7, DofKind::Uz), Dof::new(7, DofKind::Ry)]);
        assert_eq!(map.index_of(Dof::new(7, DofKind::Ry)), Some(1));
        assert_eq!(map.index_of(Dof::new(7, DofKind::Ux)), None);
        assert_eq!(DofKind::parse("RY"), Some(DofKind::Ry));
        assert_eq!(map.dof(0).to_string(), "node 7 uz");
    }
}
