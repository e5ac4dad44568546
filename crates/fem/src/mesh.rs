//! Meshes built in code: a structured block of C3D8 hexahedra, for
//! examples, benchmarks and tests that need a solid without a deck; and one
//! element of every registered type, for tests that must cover them all.

use crate::element::solid::topology::hex_cell;
use crate::element::{element_types, ElementType, SectionKind, SectionValues};
use crate::element::{Solid, SolidKind};
use crate::{Element, FemError, Material, Node, NodeId};

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

/// One element of every registered type ([`element_types`], in that
/// order), built through the registry: element `i + 1` is of type `i`, on
/// nodes `100 (i + 1) + 1, ..` at the type's reference positions shifted
/// by `3 i` m along x. An element that creates no DOFs (a point mass)
/// sits on the first nodes of element 1 instead, which must create DOFs
/// there.
#[derive(Clone, Debug)]
pub struct EveryElementType {
    pub nodes: Vec<Node>,
    /// Each element with its type.
    pub elements: Vec<(&'static ElementType, Element)>,
}

impl EveryElementType {
    /// Builds the elements, each with the section values `section` gives
    /// for its type's section kind.
    pub fn new(section: impl Fn(SectionKind) -> SectionValues) -> Result<Self, FemError> {
        let mut nodes = Vec::new();
        let mut elements: Vec<(&'static ElementType, Element)> = Vec::new();
        for (i, t) in element_types().enumerate() {
            let id = i + 1;
            let own: Vec<NodeId> = (1..=t.nodes).map(|a| (100 * id + a) as NodeId).collect();
            let values = section(t.section);
            let mut element = (t.build)(id, &own, &values)?;
            if element.creates_dofs() {
                let shift = 3.0 * i as f64;
                nodes.extend(own.iter().zip(t.reference_nodes).map(|(&n, x)| Node {
                    id: n,
                    coords: [x[0] + shift, x[1], x[2]],
                }));
            } else {
                let host = elements
                    .first()
                    .map(|(_, e)| e.nodes())
                    .filter(|host| host.len() >= t.nodes)
                    .ok_or_else(|| FemError::InvalidElement {
                        element: id,
                        reason: "creates no DOFs and has no element to sit on".into(),
                    })?;
                element = (t.build)(id, &host[..t.nodes], &values)?;
            }
            elements.push((t, element));
        }
        Ok(Self { nodes, elements })
    }

    /// [`Self::new`] with the sections of [`sample_section`].
    pub fn sample() -> Result<Self, FemError> {
        Self::new(sample_section)
    }
}

/// Section values for tests, by kind: steel (E = 210 GPa, nu = 0.3, rho =
/// 7850 kg/m^3); beams a 50 mm wide, 80 mm high rectangle with local y
/// along global y; masses of 12.5 kg; springs of 1e6 N/m on `uy` (as many
/// DOFs as the kind names).
pub fn sample_section(kind: SectionKind) -> SectionValues {
    let material = Material::new(2.1e11, 0.3, 7850.0).expect("valid constants");
    match kind {
        SectionKind::Solid => SectionValues::Solid { material },
        SectionKind::Beam => SectionValues::Beam {
            material,
            constants: crate::SectionShape::Rect {
                width: 0.05,
                height: 0.08,
            }
            .constants()
            .expect("valid dimensions"),
            orientation: [0.0, 1.0, 0.0],
        },
        SectionKind::Mass => SectionValues::Mass { mass: 12.5 },
        SectionKind::Spring { dofs } => SectionValues::Spring {
            dofs: [0, 1].map(|k| (k < dofs).then_some(crate::DofKind::Uy)),
            stiffness: 1.0e6,
        },
    }
}
