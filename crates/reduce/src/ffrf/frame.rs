//! The floating frame of a reduced body as one plain value: its elastic
//! coordinates, its mass invariants and the nodes the frame carries.

use super::{elastic_basis, mass_invariants, ElasticBasis, FfrfError, MassInvariants};
use crate::ReducedBody;
use faer::Mat;
use flexbody_fem::{Dof, DofKind, Model, NodeId, Substructure};
use std::collections::BTreeSet;

/// A node that the floating frame carries (an interface node of the body).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameNode {
    /// Node id of the FE model.
    pub id: NodeId,
    /// Position `x0` in the undeformed body (m); the origin where the model
    /// has no coordinates for the node.
    pub position: [f64; 3],
    /// The node's rows of `Phi` for `ux, uy, uz` (3 x nq, [`node_rows`]):
    /// the node moves to `x0 + phi q`.
    pub translations: Mat<f64>,
    /// The node's rows of `Phi` for `rx, ry, rz` (3 x nq, zero rows where
    /// the node has no rotation DOF): its orientation is `I + (psi q)~`.
    pub rotations: Mat<f64>,
    /// The node's local axes where the body's interface DOFs there are
    /// along them ([`ReducedBody::local_axes`]): the node frame is then
    /// `(I + (psi q)~) R`. `translations` and `rotations` stay in global
    /// components.
    pub axes: Option<flexbody_fem::Axes>,
}

/// A reduced body in the floating frame of reference formulation: what a
/// SID file holds besides the recovery rows (see the [module
/// docs](super)).
#[derive(Clone, Debug)]
pub struct FloatingFrame {
    /// The elastic coordinates: `Phi = T E`, `Me`, `Ke`, `De` and the
    /// frequencies of the elastic modes.
    pub elastic: ElasticBasis,
    /// The mass invariants of the elastic modes: integrals over the mass
    /// matrix of the model the frame was computed from.
    pub invariants: MassInvariants,
    /// The body's interface nodes, ascending by id.
    pub nodes: Vec<FrameNode>,
}

impl FloatingFrame {
    /// The floating frame of `body`, reduced from `sub` (of the mesh
    /// `model`, if known): `sub` gives the mass matrix of the elastic
    /// coordinates and the node coordinates (of the rigid-body motions and
    /// of the frame nodes), `model` the body integrals of the invariants
    /// ([`mass_invariants`]); `body` its basis, reduced matrices and
    /// interface.
    pub fn new(
        sub: &Substructure,
        model: Option<&Model>,
        body: &ReducedBody,
    ) -> Result<Self, FfrfError> {
        let elastic = elastic_basis(sub, body)?;
        let invariants = mass_invariants(sub, model, &elastic)?;
        let ids: BTreeSet<NodeId> = body.interface.iter().map(|d| d.node).collect();
        let nodes = ids
            .into_iter()
            .map(|id| {
                let (translations, rotations) = node_rows(body, &elastic.shapes, id);
                FrameNode {
                    id,
                    position: sub.node_coordinates(id).unwrap_or([0.0; 3]),
                    translations,
                    rotations,
                    axes: body.local_axes.get(&id).copied(),
                }
            })
            .collect();
        Ok(Self {
            elastic,
            invariants,
            nodes,
        })
    }

    /// Number of elastic coordinates, nq.
    pub fn nq(&self) -> usize {
        self.elastic.shapes.ncols()
    }
}

/// Rows of the translations (`ux, uy, uz`) and rotations (`rx, ry, rz`) of
/// `node` in `shapes` (3 x nq each; absent DOFs are zero rows).
pub fn node_rows(body: &ReducedBody, shapes: &Mat<f64>, node: NodeId) -> (Mat<f64>, Mat<f64>) {
    let row = |kind: DofKind, k: usize| {
        body.dof_map
            .index_of(Dof::new(node, kind))
            .map_or(0.0, |i| shapes[(i, k)])
    };
    let nq = shapes.ncols();
    (
        Mat::from_fn(3, nq, |d, k| row(DofKind::ALL[d], k)),
        Mat::from_fn(3, nq, |d, k| row(DofKind::ALL[3 + d], k)),
    )
}
