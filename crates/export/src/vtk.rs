//! VTK output for ParaView: the mesh as an unstructured grid (`.vtu`, ASCII
//! XML) with the eigenmodes of the reduced body and their stresses as point
//! data.
//!
//! Cells: each element's own ([`Element::vtk_cell`]): solids as VTK
//! hexahedra (C3D8: 12), quadratic hexahedra (C3D20, C3D20R: 25),
//! tetrahedra (C3D4: 10), quadratic tetrahedra (C3D10: 24) and wedges
//! (C3D6: 13); beams and two-node springs as lines (3); point masses and
//! grounded springs as vertices (1). The Abaqus node order is VTK's for
//! all kinds except the wedge, whose triangles VTK orders the other way
//! round (`[0, 2, 1, 3, 5, 4]`).
//!
//! Point data, for each eigenmode `k` of the reduced body (`K_red x = w^2
//! M_red x`, shape `T x`, M-normalised): `mode kk` (displacement vector, m
//! per unit modal coordinate), `mode kk rotation` (rad, models with
//! rotation DOFs), and for solids `mode kk stress` (6 components, Voigt
//! `sxx syy szz sxy syz szx`, Pa) and `mode kk von Mises` (Pa), averaged at
//! the nodes. Field data `frequencies_hz` lists the modes' frequencies.
//! Nodes without a DOF or stress get zeros. The modes and their stresses
//! come computed, as [`ModeFields`].

use crate::float_text::push_exp;
use crate::{write_atomically, ExportError};
use faer::Mat;
use flexbody_fem::{Dof, DofKind, Element, Model, NodeId};
use flexbody_reduce::ReducedBody;
use std::collections::HashMap;
use std::fmt::Write as _;
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

/// A `DataArray` of `values`, `3 components` per line; blocks of lines are
/// formatted in parallel.
fn data_array(s: &mut String, name: &str, components: usize, values: &[f64]) {
    use rayon::prelude::*;
    const LINES: usize = 2048;
    let _ = write!(
        s,
        "        <DataArray type=\"Float64\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">\n          "
    );
    let per_line = 3 * components.max(1);
    let blocks: Vec<String> = values
        .par_chunks(per_line * LINES)
        .map(|block| {
            let mut t = String::new();
            for (l, line) in block.chunks(per_line).enumerate() {
                if l > 0 {
                    t.push('\n');
                }
                for (i, v) in line.iter().enumerate() {
                    if i > 0 {
                        t.push(' ');
                    }
                    push_exp(&mut t, *v);
                }
            }
            t
        })
        .collect();
    s.push_str(&blocks.join("\n"));
    s.push_str("\n        </DataArray>\n");
}

/// The point data of the VTU file: the eigenmodes of a reduced body and
/// their stresses at the mesh's nodes.
#[derive(Clone, Debug)]
pub struct ModeFields {
    /// The body in its eigenmodes (`ReducedBody::orthonormalized`): column
    /// k of the basis is mode k, M-normalised, and `modes[k]` carries its
    /// frequency.
    pub modes: ReducedBody,
    /// The nodes with stresses (those of solids), ascending.
    pub stress_nodes: Vec<NodeId>,
    /// Per node of `stress_nodes`, the 6 x r modal stresses (Voigt `sxx syy
    /// szz sxy syz szx`, Pa per unit modal coordinate), averaged at the node.
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

/// The VTU text of `model` with the mode `fields` of a body reduced from it
/// (see the module docs).
pub fn vtu_text(model: &Model, fields: &ModeFields) -> Result<String, ExportError> {
    let modes = &fields.modes;
    check_mesh(model, modes)?;
    let nodes = model.nodes();
    let point_of: HashMap<u64, usize> = nodes.iter().enumerate().map(|(i, n)| (n.id, i)).collect();
    let r = modes.r();
    let np = nodes.len();
    let cells: Vec<(u8, Vec<usize>)> = model
        .elements()
        .iter()
        .filter_map(|e| {
            let (t, order) = cell_of(e)?;
            let en = e.nodes();
            Some((t, order.iter().map(|&i| point_of[&en[i]]).collect()))
        })
        .collect();
    // Each node's equations of ux, uy, uz, rx, ry, rz, and its row of the
    // modal stresses.
    let equations: Vec<[Option<usize>; 6]> = nodes
        .iter()
        .map(|n| DofKind::ALL.map(|d| modes.dof_map.index_of(Dof::new(n.id, d))))
        .collect();
    let value = |p: usize, d: usize, k: usize| equations[p][d].map_or(0.0, |i| modes.basis[(i, k)]);
    let has_rotations = modes.dof_map.dofs().iter().any(|d| d.kind.is_rotation());
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <UnstructuredGrid>\n");
    s.push_str("    <FieldData>\n");
    let frequencies: Vec<f64> = modes
        .modes
        .iter()
        .map(|m| match m {
            flexbody_reduce::ModeKind::Orthonormal { frequency_hz } => *frequency_hz,
            _ => 0.0,
        })
        .collect();
    let _ = writeln!(
        s,
        "      <DataArray type=\"Float64\" Name=\"frequencies_hz\" NumberOfTuples=\"{r}\" format=\"ascii\">"
    );
    let f: Vec<String> = frequencies.iter().map(|f| format!("{f:e}")).collect();
    let _ = writeln!(
        s,
        "        {}\n      </DataArray>\n    </FieldData>",
        f.join(" ")
    );
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{}\">",
        cells.len()
    );
    s.push_str("      <PointData>\n");
    let _ = writeln!(
        s,
        "        <DataArray type=\"Int64\" Name=\"node id\" format=\"ascii\">"
    );
    let ids: Vec<String> = nodes.iter().map(|n| n.id.to_string()).collect();
    let _ = writeln!(s, "          {}\n        </DataArray>", ids.join(" "));
    // (The modal stresses' nodes ascend.)
    let stress_rows: Vec<Option<usize>> = nodes
        .iter()
        .map(|n| fields.stress_nodes.binary_search(&n.id).ok())
        .collect();
    for k in 0..r {
        let name = format!("mode {:02}", k + 1);
        let field = |first: usize| -> Vec<f64> {
            (0..np)
                .flat_map(|p| [0, 1, 2].map(|d| value(p, first + d, k)))
                .collect()
        };
        data_array(&mut s, &name, 3, &field(0));
        if has_rotations {
            data_array(&mut s, &format!("{name} rotation"), 3, &field(3));
        }
        if !fields.stress_nodes.is_empty() {
            let sigma: Vec<[f64; 6]> = stress_rows
                .iter()
                .map(|row| {
                    row.map_or([0.0; 6], |i| {
                        let m: &Mat<f64> = &fields.stress[i];
                        std::array::from_fn(|c| m[(c, k)])
                    })
                })
                .collect();
            let flat: Vec<f64> = sigma.iter().flatten().copied().collect();
            data_array(&mut s, &format!("{name} stress"), 6, &flat);
            let von_mises: Vec<f64> = sigma.iter().map(flexbody_fem::element::von_mises).collect();
            data_array(&mut s, &format!("{name} von Mises"), 1, &von_mises);
        }
    }
    s.push_str("      </PointData>\n      <Points>\n");
    let coordinates: Vec<f64> = nodes.iter().flat_map(|n| n.coords).collect();
    data_array(&mut s, "coordinates", 3, &coordinates);
    s.push_str("      </Points>\n      <Cells>\n");
    let conn: Vec<String> = cells
        .iter()
        .flat_map(|c| c.1.iter().map(|i| i.to_string()))
        .collect();
    let _ = writeln!(
        s,
        "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n          {}\n        </DataArray>",
        conn.join(" ")
    );
    let mut offset = 0;
    let offsets: Vec<String> = cells
        .iter()
        .map(|c| {
            offset += c.1.len();
            offset.to_string()
        })
        .collect();
    let _ = writeln!(
        s,
        "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n          {}\n        </DataArray>",
        offsets.join(" ")
    );
    let types: Vec<String> = cells.iter().map(|c| c.0.to_string()).collect();
    let _ = writeln!(
        s,
        "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n          {}\n        </DataArray>",
        types.join(" ")
    );
    s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    Ok(s)
}

/// Writes the VTU file of `model` with the mode `fields` to `path`,
/// atomically.
pub fn write_vtu(model: &Model, fields: &ModeFields, path: &Path) -> Result<(), ExportError> {
    let text = vtu_text(model, fields)?;
    write_atomically(path, |out| out.write_all(text.as_bytes()))
}
