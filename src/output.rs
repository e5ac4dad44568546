//! What the reduced-body files hold besides the body, computed before any
//! writer of [`export`](crate::export) sees it: the SID content (the
//! floating-frame invariants of [`reduce::ffrf`](crate::reduce::ffrf) and
//! the recovery rows of [`recover::recovery_matrix`] in the elastic
//! coordinates), the MBDyn content (the same elastic modes at the mesh's
//! nodes, with their lumped masses from [`fem::lumped`](crate::fem::lumped)),
//! the nodes that the JSON document and the Matrix Market index list (with
//! coordinates and the same lumped masses),
//! the VTU file's mode fields (the body's eigenmodes and their
//! nodal stresses), and the Matrix Market index's accuracy figures (from
//! the comparison with the full model).

use crate::export::mbdyn::FemNode;
use crate::export::mtx::Metadata;
use crate::export::vtk::{check_mesh, ModeFields};
use crate::export::{BodyNode, BodyOutput, ExportError, Format, ModalFem, Sid};
use crate::fem::{FemError, Model, Substructure};
use crate::recover::{self, ModalStress};
use crate::reduce::ffrf::{FfrfError, FloatingFrame};
use crate::reduce::ReducedBody;
use crate::report::FrequencyComparison;
use faer::Mat;

/// Why the content of a body's file could not be computed.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The body has no floating-frame description.
    #[error(transparent)]
    Ffrf(#[from] FfrfError),
    /// The lumped masses of the MBDyn, JSON or Matrix Market file failed.
    #[error("lumped masses: {0}")]
    Lumped(FemError),
    /// The SID's recovery rows failed.
    #[error("stress recovery: {0}")]
    Recovery(FemError),
    /// The reduced eigenproblem of the VTU's modes failed.
    #[error("eigenmodes of the reduced body: {0}")]
    Modes(crate::linalg::LinalgError),
    /// The VTU's modal stresses failed.
    #[error("modal stresses: {0}")]
    ModalStress(FemError),
    /// The body and the mesh do not fit together.
    #[error(transparent)]
    Export(#[from] ExportError),
}

/// What [`export::write`](crate::export::write) formats for `body`,
/// reduced from `sub` (and `model`, the mesh if known), in `format`: the
/// SID content for [`Format::Sid`] ([`sid`]), the MBDyn content for
/// [`Format::Mbdyn`] ([`mbdyn`]), the nodes for JSON and the Matrix
/// Market index ([`body_nodes`]) and `metadata` for the index.
pub fn body_output<'a>(
    sub: &Substructure,
    model: Option<&Model>,
    body: &'a ReducedBody,
    format: Format,
    metadata: Metadata,
) -> Result<BodyOutput<'a>, OutputError> {
    let sid = match format {
        Format::Sid => Some(sid(sub, model, body)?),
        Format::Json | Format::Mtx | Format::Mbdyn => None,
    };
    let mbdyn = match format {
        Format::Mbdyn => Some(mbdyn(sub, model, body)?),
        Format::Json | Format::Mtx | Format::Sid => None,
    };
    let nodes = match format {
        Format::Json | Format::Mtx => body_nodes(sub, model, body)?,
        Format::Sid | Format::Mbdyn => Vec::new(),
    };
    Ok(BodyOutput {
        body,
        nodes,
        sid,
        mbdyn,
        metadata,
    })
}

/// The nodes a JSON body or a Matrix Market index lists for `body`,
/// reduced from `sub`: with the mesh `model`, every node of the mesh (fixed
/// ones too), its coordinates and its HRZ lumped masses, which sum to the
/// mesh's mass in each direction; without it, the nodes of the body's DOFs
/// with the coordinates `sub` has (`--coords`) and no masses.
pub fn body_nodes(
    sub: &Substructure,
    model: Option<&Model>,
    body: &ReducedBody,
) -> Result<Vec<BodyNode>, OutputError> {
    let Some(model) = model else {
        let ids: std::collections::BTreeSet<_> =
            body.dof_map.dofs().iter().map(|d| d.node).collect();
        return Ok(ids
            .into_iter()
            .map(|id| BodyNode {
                id,
                coords: sub.node_coordinates(id),
                mass: None,
            })
            .collect());
    };
    check_mesh(model, body)?;
    let masses = crate::fem::lumped::lumped_masses(model).map_err(OutputError::Lumped)?;
    Ok(model
        .nodes()
        .iter()
        .map(|n| BodyNode {
            id: n.id,
            coords: Some(n.coords),
            mass: masses.get(&n.id).copied(),
        })
        .collect())
}

/// The SID of `body`, reduced from `sub`: its floating frame (elastic
/// coordinates and mass invariants from the mass matrix and node
/// coordinates of `sub`) and, if `model` (the mesh) is known, its recovery
/// rows `ksigma` in the elastic coordinates (stresses of solids and
/// shells, else section forces of beams).
pub fn sid(
    sub: &Substructure,
    model: Option<&Model>,
    body: &ReducedBody,
) -> Result<Sid, OutputError> {
    let frame = FloatingFrame::new(sub, model, body)?;
    let ksigma = match model {
        Some(model) => frame
            .elastic
            .elastic_rows(recover::recovery_matrix(model, body).map_err(OutputError::Recovery)?),
        None => Mat::zeros(0, frame.nq()),
    };
    Ok(Sid::new(frame, ksigma))
}

/// The MBDyn modal FEM file of `body`, reduced from `sub`: the elastic
/// modes of its floating frame (mean axes, so that MBDyn's modal node
/// carries the rigid-body motion), the rigid inertia from its invariants
/// and, with the mesh `model`, every node of the mesh (a node a coupling
/// or tie made dependent moving with its constraint) and its HRZ lumped
/// masses (MBDyn builds the inertia coupling of rigid and elastic motion
/// from the lumped masses of the nodes the file lists, so the file lists
/// them all). Without a mesh, the interface nodes alone and no lumped
/// masses. MBDyn takes one translational mass per node: each node's
/// largest of `mx, my, mz` is written in all three (they are equal for
/// solids and 3D beams; a planar beam has `uz` only). An error without
/// node coordinates.
pub fn mbdyn(
    sub: &Substructure,
    model: Option<&Model>,
    body: &ReducedBody,
) -> Result<ModalFem, OutputError> {
    if !sub.has_geometry() {
        return Err(ExportError::Model(
            "MBDyn's modal FEM file needs the nodes' coordinates (record groups 5-7), and \
             matrices alone have none: give them with `--coords NODES.txt`, or reduce the \
             model file or deck the matrices came from"
                .into(),
        )
        .into());
    }
    let frame = FloatingFrame::new(sub, model, body)?;
    let masses = model
        .map(crate::fem::lumped::lumped_masses)
        .transpose()
        .map_err(OutputError::Lumped)?;
    let nodes: Vec<FemNode> = match (model, &masses) {
        (Some(model), Some(masses)) => {
            check_mesh(model, body)?;
            masses
                .keys()
                .map(|&id| FemNode::of_model(model, id))
                .collect()
        }
        _ => frame
            .nodes
            .iter()
            .map(|n| FemNode::of_dofs(n.id, n.position, &body.dof_map))
            .collect(),
    };
    let lumped = masses.map(|masses| {
        masses
            .into_values()
            .map(|[mx, my, mz, jx, jy, jz]| {
                let m = mx.max(my).max(mz);
                [m, m, m, jx, jy, jz]
            })
            .collect()
    });
    Ok(ModalFem::new(frame, nodes, lumped))
}

/// The VTU file's fields of `body` on its mesh `model`: the eigenmodes of
/// the reduced body (`K_red x = w^2 M_red x`, shapes `T x`, M-normalised)
/// and their stresses averaged at the nodes of solids and shells.
pub fn mode_fields(model: &Model, body: &ReducedBody) -> Result<ModeFields, OutputError> {
    check_mesh(model, body)?;
    let modes = body.orthonormalized().map_err(OutputError::Modes)?;
    let stress = ModalStress::new(model, &modes).map_err(OutputError::ModalStress)?;
    Ok(ModeFields {
        modes,
        stress_nodes: stress.nodes,
        stress_layers: stress.layers,
        stress: stress.matrices,
    })
}

/// The accuracy figures of a Matrix Market index: the full model's
/// frequencies, if computed, and the relative error of each reduced one
/// (`relative frequency error, mode kk`).
pub fn index_metadata(comparison: &FrequencyComparison) -> Metadata {
    Metadata {
        full_frequencies_hz: comparison.full_hz.clone(),
        accuracy: comparison
            .relative_errors()
            .into_iter()
            .map(|(k, e)| (format!("relative frequency error, mode {k:02}"), e))
            .collect(),
    }
}
