//! The FE model of one component: nodes, elements, node sets, boundary
//! conditions, couplings, linear constraints and Rayleigh damping.

use crate::constraint::Equation;
use crate::coupling::{Constraints, Coupling};
use crate::dof::{Dof, DofKind, DofMap};
use crate::element::Element;
use crate::id_hash::{id_map, IdMap};
use crate::local_axes::Axes;
use crate::FemError;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// User node number (as in the model file).
pub type NodeId = u64;

/// A node with global coordinates (m).
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    pub id: NodeId,
    pub coords: [f64; 3],
}

/// Rayleigh damping `D = alpha M + beta K` (alpha in 1/s, beta in s). A
/// key besides `alpha` and `beta` is refused when read.
#[derive(Copy, Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rayleigh {
    pub alpha: f64,
    pub beta: f64,
}

/// A DOF's value in a vector `u` over the equations ([`Model::value_terms`]).
#[derive(Clone, Debug, PartialEq)]
pub enum ValueTerms {
    /// `u[i]`: the DOF is equation `i`.
    Equation(usize),
    /// `sum c u[i]` over `(i, c)`: a DOF coupled by a constraint.
    Combination(Vec<(usize, f64)>),
    /// Zero: a fixed DOF.
    Fixed,
}

impl ValueTerms {
    /// The value in `u` ([`Model::value`]).
    pub fn of(&self, u: &[f64]) -> f64 {
        match self {
            ValueTerms::Equation(i) => u[*i],
            ValueTerms::Combination(terms) => terms.iter().map(|(i, c)| c * u[*i]).sum(),
            ValueTerms::Fixed => 0.0,
        }
    }
}

/// A linear FE model. Built with [`Model::new`], which checks that every
/// element refers to existing nodes; immutable afterwards.
#[derive(Clone, Debug)]
pub struct Model {
    nodes: Vec<Node>,
    node_index: IdMap<NodeId, usize>,
    elements: Vec<Element>,
    node_sets: BTreeMap<String, Vec<NodeId>>,
    fixed: BTreeSet<Dof>,
    rayleigh: Option<Rayleigh>,
    couplings: Vec<Coupling>,
    equations: Vec<Equation>,
    local_axes: BTreeMap<NodeId, Axes>,
    /// Dependent DOFs of the couplings and equations as combinations of
    /// free DOFs, eliminated from the DOF map.
    constraints: Constraints,
    dof_map: DofMap,
}

/// A model's parts by name, for [`Model::of`]: the nodes and elements,
/// then whatever else the model has.
///
/// ```
/// # use flexbody_fem::{Dof, DofKind, Element, Model, Node};
/// # use flexbody_fem::element::Spring;
/// let nodes = vec![Node { id: 1, coords: [0.0; 3] }];
/// let spring = Spring { id: 1, first: Dof::new(1, DofKind::Ux), second: None, stiffness: 1e3 };
/// let model = Model::of(nodes, vec![Element::from(spring)])
///     .fixed(vec![])
///     .build()?;
/// assert_eq!(model.dof_map().len(), 1);
/// # Ok::<(), flexbody_fem::FemError>(())
/// ```
#[derive(Clone, Debug)]
pub struct ModelParts {
    nodes: Vec<Node>,
    elements: Vec<Element>,
    node_sets: BTreeMap<String, Vec<NodeId>>,
    fixed: Vec<Dof>,
    rayleigh: Option<Rayleigh>,
    couplings: Vec<Coupling>,
    equations: Vec<Equation>,
    local_axes: BTreeMap<NodeId, Axes>,
}

impl ModelParts {
    /// The named node sets.
    pub fn node_sets(self, node_sets: BTreeMap<String, Vec<NodeId>>) -> Self {
        Self { node_sets, ..self }
    }

    /// The DOFs held at zero.
    pub fn fixed(self, fixed: Vec<Dof>) -> Self {
        Self { fixed, ..self }
    }

    /// Rayleigh damping `D = alpha M + beta K`.
    pub fn rayleigh(self, rayleigh: Rayleigh) -> Self {
        Self {
            rayleigh: Some(rayleigh),
            ..self
        }
    }

    /// Interface points coupled to node sets ([`Model::with_couplings`]).
    /// Given here, the couplings' reference nodes have their 6 DOFs from
    /// the start, so elements that only load DOFs (point masses) may sit
    /// on them.
    pub fn couplings(self, couplings: Vec<Coupling>) -> Self {
        Self { couplings, ..self }
    }

    /// Linear constraints among DOFs ([`Equation`]): each eliminates its
    /// first DOF.
    pub fn equations(self, equations: Vec<Equation>) -> Self {
        Self { equations, ..self }
    }

    /// Nodal coordinate systems (`*TRANSFORM`): the DOFs a user names at
    /// these nodes for the interface of a reduction are along the local
    /// axes ([`Model::local_axes`]). The model's own DOFs stay global.
    pub fn local_axes(self, local_axes: BTreeMap<NodeId, Axes>) -> Self {
        Self { local_axes, ..self }
    }

    /// The checked model ([`Model::new`], then the couplings).
    pub fn build(self) -> Result<Model, FemError> {
        Model::assemble(self)
    }
}

impl Model {
    /// The parts of a model of `nodes` and `elements`, to add node sets,
    /// fixed DOFs and damping to by name and [`ModelParts::build`].
    pub fn of(nodes: Vec<Node>, elements: Vec<Element>) -> ModelParts {
        ModelParts {
            nodes,
            elements,
            node_sets: BTreeMap::new(),
            fixed: Vec::new(),
            rayleigh: None,
            couplings: Vec::new(),
            equations: Vec::new(),
            local_axes: BTreeMap::new(),
        }
    }

    /// Builds and checks a model without couplings.
    pub fn new(
        nodes: Vec<Node>,
        elements: Vec<Element>,
        node_sets: BTreeMap<String, Vec<NodeId>>,
        fixed: Vec<Dof>,
        rayleigh: Option<Rayleigh>,
    ) -> Result<Self, FemError> {
        Self::assemble(ModelParts {
            nodes,
            elements,
            node_sets,
            fixed,
            rayleigh,
            couplings: Vec::new(),
            equations: Vec::new(),
            local_axes: BTreeMap::new(),
        })
    }

    /// Builds and checks a model with its couplings, its DOF map built once.
    fn assemble(parts: ModelParts) -> Result<Self, FemError> {
        let ModelParts {
            nodes,
            elements,
            node_sets,
            fixed,
            rayleigh,
            couplings,
            equations,
            local_axes,
        } = parts;
        let mut node_index = id_map(nodes.len());
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
        for (node, r) in &local_axes {
            if !node_index.contains_key(node) {
                return Err(FemError::UnknownNodeIn {
                    what: "local axes (*TRANSFORM)".into(),
                    node: *node,
                });
            }
            crate::local_axes::check_axes(*node, r)?;
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
            couplings,
            equations,
            local_axes,
            constraints: Constraints::new(),
            dof_map: DofMap::default(),
        };
        model.dof_map = model.build_dof_map()?;
        Ok(model)
    }

    /// The model with interface points coupled to node sets (RBE2/RBE3):
    /// each point gets 6 DOFs, and the dependent DOFs of the couplings leave
    /// the DOF map (exact elimination). A point mass on a reference node
    /// that nothing else gives DOFs needs the couplings at construction
    /// ([`ModelParts::couplings`]): [`Model::new`] refuses it before.
    pub fn with_couplings(mut self, couplings: Vec<Coupling>) -> Result<Self, FemError> {
        self.couplings = couplings;
        self.dof_map = self.build_dof_map()?;
        Ok(self)
    }

    /// The couplings of the model.
    pub fn couplings(&self) -> &[Coupling] {
        &self.couplings
    }

    /// The linear constraints of the model, as given.
    pub fn equations(&self) -> &[Equation] {
        &self.equations
    }

    /// The nodes with a local coordinate system (`*TRANSFORM`) and its
    /// axes: where a reduction's interface names DOFs of these nodes, they
    /// are along the local axes ([`crate::local_axes`]).
    pub fn local_axes(&self) -> &BTreeMap<NodeId, Axes> {
        &self.local_axes
    }

    /// Free DOFs: those the stiffness-carrying elements and coupling points
    /// create, minus the fixed ones and the couplings' dependent ones. Point
    /// masses only load DOFs that exist.
    fn build_dof_map(&mut self) -> Result<DofMap, FemError> {
        let mut active = Active::new(self.nodes.len());
        for e in &self.elements {
            if e.creates_dofs() {
                for d in e.dofs() {
                    active.insert((self.node_index[&d.node], d.kind));
                }
            }
        }
        for c in &self.couplings {
            let Some(&idx) = self.node_index.get(&c.point) else {
                return Err(FemError::InvalidCoupling {
                    name: c.name.clone(),
                    reason: format!("reference node {} does not exist", c.point),
                });
            };
            for k in DofKind::ALL {
                active.insert((idx, k));
            }
        }
        // An element that only loads DOFs others create must find some.
        for e in self.elements.iter().filter(|e| !e.creates_dofs()) {
            let loads_some = e
                .dofs()
                .iter()
                .any(|d| active.contains(&(self.node_index[&d.node], d.kind)));
            if !loads_some {
                return Err(match e {
                    Element::PointMass(m) => FemError::MassWithoutDof { node: m.node },
                    _ => FemError::InvalidElement {
                        element: e.id(),
                        reason: "no element or coupling gives its nodes the DOFs it acts on \
                                 (it creates none: it loads the DOFs of others)"
                            .into(),
                    },
                });
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
        // Coupling constraints, then the equations; chains resolved.
        let mut constraints = Constraints::new();
        let mut owner: std::collections::HashMap<Dof, String> = std::collections::HashMap::new();
        let exists = |d: &Dof| {
            self.node_index
                .get(&d.node)
                .is_some_and(|&i| active.contains(&(i, d.kind)))
        };
        {
            let coords = |n: NodeId| self.node_index.get(&n).map(|&i| self.nodes[i].coords);
            let kinds = |n: NodeId| -> Vec<DofKind> {
                self.node_index
                    .get(&n)
                    .map(|&i| {
                        DofKind::ALL
                            .into_iter()
                            .filter(|k| active.contains(&(i, *k)))
                            .collect()
                    })
                    .unwrap_or_default()
            };
            for c in &self.couplings {
                for (dof, terms) in c.constraints(&coords, &kinds)? {
                    if self.fixed.contains(&dof) {
                        return Err(FemError::InvalidCoupling {
                            name: c.name.clone(),
                            reason: format!("{dof} is both fixed and coupled"),
                        });
                    }
                    owner.insert(dof, format!("coupling '{}'", c.name));
                    if constraints.insert(dof, terms).is_some() {
                        return Err(FemError::InvalidCoupling {
                            name: c.name.clone(),
                            reason: format!("{dof} belongs to two couplings"),
                        });
                    }
                }
            }
        }
        for e in &self.equations {
            let (dof, terms) = e.solved()?;
            let bad = |reason: String| FemError::InvalidConstraint {
                name: e.name.clone(),
                reason,
            };
            for d in std::iter::once(&dof).chain(terms.iter().map(|(d, _)| d)) {
                if !self.node_index.contains_key(&d.node) {
                    return Err(bad(format!("node {} does not exist", d.node)));
                }
                if !exists(d) {
                    return Err(bad(format!(
                        "{d} is not a DOF of the model (no element gives node {} that DOF; \
                         solid nodes have no rotations)",
                        d.node
                    )));
                }
            }
            if self.fixed.contains(&dof) {
                return Err(bad(format!(
                    "its dependent (first) DOF {dof} is also fixed by a boundary condition; \
                     list another DOF first"
                )));
            }
            if let Some(other) = owner.get(&dof) {
                return Err(bad(format!(
                    "its dependent (first) DOF {dof} is already eliminated by {other} \
                     (over-constrained); list another DOF first"
                )));
            }
            owner.insert(dof, e.name.clone());
            constraints.insert(dof, terms);
        }
        let constraints = crate::constraint::resolve(constraints, &owner, &self.fixed)?;
        let dofs: Vec<Dof> = active
            .iter()
            .map(|(i, k)| Dof::new(self.nodes[i].id, k))
            .filter(|d| !self.fixed.contains(d) && !constraints.contains_key(d))
            .collect();
        self.constraints = constraints;
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

    /// A DOF's value as a combination of equations: one equation for a free
    /// DOF, none for a fixed one, the constraint's terms for a DOF a
    /// coupling eliminated.
    pub fn terms(&self, dof: Dof) -> Vec<(usize, f64)> {
        if let Some(i) = self.dof_map.index_of(dof) {
            return vec![(i, 1.0)];
        }
        match self.constraints.get(&dof) {
            Some(terms) => terms
                .iter()
                .filter_map(|(d, c)| self.dof_map.index_of(*d).map(|i| (i, *c)))
                .collect(),
            None => vec![],
        }
    }

    /// True if some DOF was eliminated by a coupling.
    pub fn has_constraints(&self) -> bool {
        !self.constraints.is_empty()
    }

    /// The value of any DOF of the model from a vector over its equations
    /// (fixed DOFs: 0; coupled DOFs: from their constraint).
    pub fn value(&self, dof: Dof, u: &[f64]) -> f64 {
        self.value_terms(dof).of(u)
    }

    /// How [`Self::value`] finds `dof`'s value in a vector over the
    /// equations, for many vectors at once: the gathers of one DOF.
    pub fn value_terms(&self, dof: Dof) -> ValueTerms {
        match self.dof_map.index_of(dof) {
            Some(i) => ValueTerms::Equation(i),
            None => self
                .constraints
                .get(&dof)
                .map_or(ValueTerms::Fixed, |terms| {
                    ValueTerms::Combination(
                        terms
                            .iter()
                            .filter_map(|(d, c)| self.dof_map.index_of(*d).map(|i| (i, *c)))
                            .collect(),
                    )
                }),
        }
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

/// The DOF kinds each node has, by node index: a set of `(node index,
/// kind)` that iterates in that order.
struct Active(Vec<u8>);

impl Active {
    fn new(nodes: usize) -> Self {
        Self(vec![0; nodes])
    }

    fn insert(&mut self, (node, kind): (usize, DofKind)) {
        self.0[node] |= 1 << kind.index();
    }

    fn contains(&self, &(node, kind): &(usize, DofKind)) -> bool {
        self.0[node] & (1 << kind.index()) != 0
    }

    fn iter(&self) -> impl Iterator<Item = (usize, DofKind)> + '_ {
        self.0.iter().enumerate().flat_map(|(node, &bits)| {
            DofKind::ALL
                .into_iter()
                .filter(move |k| bits & (1 << k.index()) != 0)
                .map(move |k| (node, k))
        })
    }
}
