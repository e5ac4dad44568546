//! VTK output for ParaView: the mesh as an unstructured grid (`.vtu`,
//! [`vtu`](crate::vtu): zlib-compressed binary by default, or ASCII) with
//! the eigenmodes of the reduced body and their stresses as point data.
//!
//! Cells: each element's own ([`Element::vtk_cell`]): solids as VTK
//! hexahedra (C3D8, C3D8I: 12), quadratic hexahedra (C3D20, C3D20R: 25),
//! tetrahedra (C3D4: 10), quadratic tetrahedra (C3D10: 24), wedges (C3D6:
//! 13) and quadratic wedges (C3D15: 26); shells as quadrilaterals (S4: 9)
//! and triangles (S3: 5); beams and two-node springs as
//! lines (3); point masses and grounded springs as vertices (1). The Abaqus
//! node order is VTK's for all kinds except the wedges, whose triangles VTK
//! orders the other way round (`[0, 2, 1, 3, 5, 4]`, and the mid-edge
//! nodes with them).
//!
//! Point data, for each eigenmode `k` of the reduced body (`K_red x = w^2
//! M_red x`, shape `T x`, M-normalised): `mode kk` (displacement vector, m
//! per unit modal coordinate), `mode kk rotation` (rad, models with
//! rotation DOFs), and for solids `mode kk stress` (6 components, Voigt
//! `sxx syy szz sxy syz szx`, Pa) and `mode kk von Mises` (Pa), averaged at
//! the nodes; for shells the same on each surface, `mode kk stress top`,
//! `... middle`, `... bottom` and their von Mises; `node id` (Int64) gives each point's node number. Field data
//! `frequencies_hz` lists the modes' frequencies.
//! Nodes without a DOF or stress get zeros. The modes and their stresses
//! come computed, as [`ModeFields`]. A non-finite value is refused, naming
//! the array and the node (or mode), before the file is touched.

use crate::vtu::{Cells, DataArray, Encoding, Section, UnstructuredGrid, Values};
use crate::{write_atomically, ExportError};
use faer::Mat;
use flexbody_fem::element::StressLayer;
use flexbody_fem::{Dof, DofKind, Element, Model, NodeId};
use flexbody_reduce::ReducedBody;
use std::collections::HashMap;
use std::path::Path;

/// VTK cell type and node order (indices into the element's nodes), as
/// the element gives them ([`Element::vtk_cell`]).
fn cell_of(e: &Element) -> Option<(u8, &'static [usize])> {
    e.vtk_cell().map(|c| (c.cell_type, c.order))
}

/// The VTK cell type of each element that becomes a cell, in model order.
pub fn cell_types(model: &Model) -> Vec<u8> {
    model
        .elements()
        .iter()
        .filter_map(|e| cell_of(e).map(|c| c.0))
        .collect()
}

/// The point data of the VTU file: the eigenmodes of a reduced body and
/// their stresses at the mesh's nodes.
#[derive(Clone, Debug)]
pub struct ModeFields {
    /// The body in its eigenmodes (`ReducedBody::orthonormalized`): column
    /// k of the basis is mode k, M-normalised, and `modes[k]` carries its
    /// frequency.
    pub modes: ReducedBody,
    /// The stress points: nodes with stresses (those of solids and shells),
    /// ascending, one entry per layer at the node.
    pub stress_nodes: Vec<NodeId>,
    /// The layer of each entry of `stress_nodes`: a solid's volume, or a
    /// shell's bottom, middle or top surface.
    pub stress_layers: Vec<StressLayer>,
    /// Per entry of `stress_nodes`, the 6 x r modal stresses (Voigt `sxx
    /// syy szz sxy syz szx`, Pa per unit modal coordinate), averaged at the
    /// node.
    pub stress: Vec<Mat<f64>>,
}

/// Checks that `body` was reduced from `model`: the same DOFs.
pub fn check_mesh(model: &Model, body: &ReducedBody) -> Result<(), ExportError> {
    if body.dof_map.dofs() != model.dof_map().dofs() {
        return Err(ExportError::Model(format!(
            "the body has {} DOFs and the model {}, or they differ",
            body.dof_map.len(),
            model.dof_map().len()
        )));
    }
    Ok(())
}

/// The unstructured grid of `model` with the mode `fields` of a body
/// reduced from it (see the module docs).
pub fn vtu_grid(model: &Model, fields: &ModeFields) -> Result<UnstructuredGrid, ExportError> {
    let modes = &fields.modes;
    check_mesh(model, modes)?;
    let nodes = model.nodes();
    let point_of: HashMap<u64, usize> = nodes.iter().enumerate().map(|(i, n)| (n.id, i)).collect();
    let r = modes.r();
    let np = nodes.len();
    let mut cells = Cells::default();
    for e in model.elements() {
        let Some((t, order)) = cell_of(e) else {
            continue;
        };
        let en = e.nodes();
        cells
            .connectivity
            .extend(order.iter().map(|&i| point_of[&en[i]] as i64));
        cells.offsets.push(cells.connectivity.len() as i64);
        cells.types.push(t);
    }
    // Each node's equations of ux, uy, uz, rx, ry, rz, and its row of the
    // modal stresses.
    let equations: Vec<[Option<usize>; 6]> = nodes
        .iter()
        .map(|n| DofKind::ALL.map(|d| modes.dof_map.index_of(Dof::new(n.id, d))))
        .collect();
    let value = |p: usize, d: usize, k: usize| equations[p][d].map_or(0.0, |i| modes.basis[(i, k)]);
    let has_rotations = modes.dof_map.dofs().iter().any(|d| d.kind.is_rotation());
    let frequencies: Vec<f64> = modes
        .modes
        .iter()
        .map(|m| match m {
            flexbody_reduce::ModeKind::Orthonormal { frequency_hz } => *frequency_hz,
            _ => 0.0,
        })
        .collect();
    let mut point_data = vec![DataArray::new(
        "node id",
        1,
        Values::Int64(nodes.iter().map(|n| n.id as i64).collect()),
    )];
    // Per layer present, the row of each point's node (the modal stresses'
    // points ascend by node, then layer).
    let mut layers: Vec<StressLayer> = fields.stress_layers.clone();
    layers.sort_unstable();
    layers.dedup();
    let stress_rows: Vec<(StressLayer, Vec<Option<usize>>)> = layers
        .iter()
        .map(|&layer| {
            let rows = nodes
                .iter()
                .map(|n| {
                    let at = fields.stress_nodes.partition_point(|&m| m < n.id);
                    (at..fields.stress_nodes.len())
                        .take_while(|&i| fields.stress_nodes[i] == n.id)
                        .find(|&i| fields.stress_layers[i] == layer)
                })
                .collect();
            (layer, rows)
        })
        .collect();
    for k in 0..r {
        let name = format!("mode {:02}", k + 1);
        let field = |first: usize| -> Values {
            Values::Float64(
                (0..np)
                    .flat_map(|p| [0, 1, 2].map(|d| value(p, first + d, k)))
                    .collect(),
            )
        };
        point_data.push(DataArray::new(name.clone(), 3, field(0)));
        if has_rotations {
            point_data.push(DataArray::new(format!("{name} rotation"), 3, field(3)));
        }
        for (layer, rows) in &stress_rows {
            let sigma: Vec<[f64; 6]> = rows
                .iter()
                .map(|row| {
                    row.map_or([0.0; 6], |i| {
                        let m: &Mat<f64> = &fields.stress[i];
                        std::array::from_fn(|c| m[(c, k)])
                    })
                })
                .collect();
            let von_mises: Vec<f64> = sigma.iter().map(flexbody_fem::element::von_mises).collect();
            let flat: Vec<f64> = sigma.into_iter().flatten().collect();
            let suffix = match layer.name() {
                "" => String::new(),
                l => format!(" {l}"),
            };
            point_data.push(DataArray::new(
                format!("{name} stress{suffix}"),
                6,
                Values::Float64(flat),
            ));
            point_data.push(DataArray::new(
                format!("{name} von Mises{suffix}"),
                1,
                Values::Float64(von_mises),
            ));
        }
    }
    Ok(UnstructuredGrid {
        field_data: vec![DataArray::new(
            "frequencies_hz",
            1,
            Values::Float64(frequencies),
        )],
        point_data,
        points: nodes.iter().flat_map(|n| n.coords).collect(),
        cells,
    })
}

/// Writes the VTU file of `model` with the mode `fields` to `path` in
/// `encoding`, atomically; a non-finite value is an error naming the array
/// and the node (or, for the frequencies, the mode), and nothing is
/// written.
pub fn write_vtu(
    model: &Model,
    fields: &ModeFields,
    encoding: Encoding,
    path: &Path,
) -> Result<(), ExportError> {
    let grid = vtu_grid(model, fields)?;
    if let Some(bad) = grid.first_non_finite() {
        let place = match bad.section {
            Section::FieldData => format!("mode {}", bad.tuple + 1),
            Section::PointData | Section::Points => {
                format!("node {}", model.nodes()[bad.tuple].id)
            }
        };
        return Err(ExportError::Format {
            path: path.to_path_buf(),
            message: format!(
                "refusing to write a non-finite value: array \"{}\" at {place}",
                bad.array
            ),
        });
    }
    write_atomically(path, |out| grid.write(encoding, out))
}
