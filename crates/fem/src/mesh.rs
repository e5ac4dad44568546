//! Meshes built in code: a structured block of C3D8 hexahedra, for
//! examples, benchmarks and tests that need a solid without a deck.

use crate::element::solid::topology::hex_cell;
use crate::element::{Solid, SolidKind};
use crate::{Element, Material, Node, NodeId};

/// A block of `cells[0] x cells[1] x cells[2]` C3D8 cells over `size` (m)
/// from `origin`. Grid point `[i, j, k]` is node [`BrickBlock::node`]`([i, j,
/// k])`; the nodes and the cells (elements `1..`) run with x fastest, then
/// y, then z.
#[derive(Clone, Debug)]
pub struct BrickBlock {
    pub cells: [usize; 3],
    pub origin: [f64; 3],
    pub size: [f64; 3],
}

impl BrickBlock {
    /// The node of grid point `[i, j, k]`: `1 + i + (nx + 1) (j + (ny + 1) k)`.
    pub fn node(&self, [i, j, k]: [usize; 3]) -> NodeId {
        let [nx, ny, _] = self.cells;
        (1 + i + (nx + 1) * (j + (ny + 1) * k)) as NodeId
    }

    /// The grid points, at `origin + size * i / n` along each axis.
    pub fn nodes(&self) -> Vec<Node> {
        let [nx, ny, nz] = self.cells;
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    let at = [i, j, k];
                    nodes.push(Node {
                        id: self.node(at),
                        coords: [0, 1, 2].map(|a| {
                            self.origin[a] + self.size[a] * at[a] as f64 / self.cells[a] as f64
                        }),
                    });
                }
            }
        }
        nodes
    }

    /// The cells as C3D8 elements of `material`, numbered from 1.
    pub fn elements(&self, material: &Material) -> Vec<Element> {
        let [nx, ny, nz] = self.cells;
        let mut elements = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    elements.push(Element::Solid(Solid {
                        id: elements.len() + 1,
                        kind: SolidKind::C3D8,
                        nodes: hex_cell(i, j, k, |at| self.node(at)),
                        material: material.clone(),
                    }));
                }
            }
        }
        elements
    }
}
