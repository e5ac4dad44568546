//! Meshes built in code: a structured block of C3D8 hexahedra, for
//! examples, benchmarks and tests that need a solid without a deck; a
//! block of any solid kind with its interior nodes moved at random, for
//! patch tests and closed-form solid load cases; a straight line of beam
//! elements; and one element of every registered type, for tests that
//! must cover them all.

use crate::element::solid::topology::{hex_cell, HEX20_EDGES, TET10_EDGES, WEDGE15_EDGES};
use crate::element::{element_types, ElementType, SectionKind, SectionValues};
use crate::element::{Beam, PlanarBeam, Solid, SolidKind};
use crate::{BeamProperties, Dof, Element, FemError, Material, Model, Node, NodeId};
use std::collections::BTreeMap;

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
        self.elements_of(|_| material.clone())
    }

    /// The cells as C3D8 elements numbered from 1, element `e + 1` of
    /// `material(e)`.
    pub fn elements_of(&self, material: impl Fn(usize) -> Material) -> Vec<Element> {
        let [nx, ny, nz] = self.cells;
        let mut elements = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    elements.push(Element::Solid(Solid {
                        id: elements.len() + 1,
                        kind: SolidKind::C3D8,
                        nodes: hex_cell(i, j, k, |at| self.node(at)),
                        material: material(elements.len()),
                    }));
                }
            }
        }
        elements
    }
}

/// A block of `cells[0] x cells[1] x cells[2]` hexahedral cells over
/// `size` (m) from `origin`, each cell one element of `kind` (C3D8, C3D20,
/// C3D20R), two wedges (C3D6, C3D15) or six tetrahedra (C3D4, C3D10: the Kuhn
/// subdivision along the cell's diagonal from its corner at the lowest x,
/// y, z to the opposite one, conforming), its interior nodes moved at
/// random. Zero distortions give a regular mesh.
#[derive(Clone, Debug)]
pub struct SolidBlock {
    pub kind: SolidKind,
    pub cells: [usize; 3],
    pub origin: [f64; 3],
    pub size: [f64; 3],
    /// How far an interior grid point moves at most, as a fraction of the
    /// cell size along each axis.
    pub corner_distortion: f64,
    /// How far an interior mid-edge node of a quadratic kind moves at most
    /// off the midpoint of its (moved) ends, likewise: curved edges.
    pub edge_distortion: f64,
    /// Seed of the deterministic random moves.
    pub seed: u64,
}

/// The mesh of a [`SolidBlock`], by node index `n` (from 0; node id `n +
/// 1`): the grid points with x fastest, then y, then z, then the mid-edge
/// nodes in the order the elements first use them.
#[derive(Clone, Debug)]
pub struct SolidMesh {
    pub kind: SolidKind,
    /// Coordinates (m).
    pub coords: Vec<[f64; 3]>,
    /// Positions before the random moves, in units of the block's size
    /// from its origin: 0 or 1 on its faces.
    pub reference: Vec<[f64; 3]>,
    /// The node indices of each element, in the kind's node order.
    pub elements: Vec<Vec<usize>>,
    /// The mid-edge node of the edge between two nodes (smaller index
    /// first).
    pub mid: BTreeMap<(usize, usize), usize>,
}

impl SolidBlock {
    /// Builds the mesh.
    pub fn mesh(&self) -> SolidMesh {
        let [nx, ny, nz] = self.cells;
        let mut rng = Xorshift::new(self.seed);
        let mut mesh = SolidMesh {
            kind: self.kind,
            coords: Vec::new(),
            reference: Vec::new(),
            elements: Vec::new(),
            mid: BTreeMap::new(),
        };
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    let at = [i, j, k];
                    let r = [0, 1, 2].map(|c| at[c] as f64 / self.cells[c] as f64);
                    let inside = (0..3).all(|c| at[c] > 0 && at[c] < self.cells[c]);
                    let amplitude = if inside { self.corner_distortion } else { 0.0 };
                    let shift = self.shift(amplitude, rng.vec3());
                    mesh.reference.push(r);
                    mesh.coords
                        .push([0, 1, 2].map(|c| self.origin[c] + self.size[c] * r[c] + shift[c]));
                }
            }
        }
        let grid = |[i, j, k]: [usize; 3]| i + (nx + 1) * (j + (ny + 1) * k);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    // The corner at bit pattern `b` (x: bit 0, y: bit 1, z: bit 2).
                    let v = |b: usize| grid([i + (b & 1), j + ((b >> 1) & 1), k + (b >> 2)]);
                    let hex = hex_cell(i, j, k, grid);
                    match self.kind {
                        SolidKind::C3D8 | SolidKind::C3D8I | SolidKind::C3D8R => {
                            mesh.elements.push(hex)
                        }
                        SolidKind::C3D20 | SolidKind::C3D20R => {
                            let mut e = hex.clone();
                            for (a, b) in HEX20_EDGES {
                                e.push(self.mid_node(&mut mesh, hex[a], hex[b], &mut rng));
                            }
                            mesh.elements.push(e);
                        }
                        SolidKind::C3D4 | SolidKind::C3D10 => {
                            for (p0, p1) in [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)] {
                                let mut t = vec![v(0), v(1 << p0), v((1 << p0) | (1 << p1)), v(7)];
                                if tet_volume(&mesh.coords, &t) < 0.0 {
                                    t.swap(1, 2);
                                }
                                if self.kind == SolidKind::C3D10 {
                                    let corners = t.clone();
                                    for (a, b) in TET10_EDGES {
                                        t.push(
                                            self.mid_node(
                                                &mut mesh, corners[a], corners[b], &mut rng,
                                            ),
                                        );
                                    }
                                }
                                mesh.elements.push(t);
                            }
                        }
                        SolidKind::C3D6 | SolidKind::C3D15 => {
                            for wedge in [
                                vec![v(0), v(1), v(3), v(4), v(5), v(7)],
                                vec![v(0), v(3), v(2), v(4), v(7), v(6)],
                            ] {
                                let mut e = wedge.clone();
                                if self.kind == SolidKind::C3D15 {
                                    for (a, b) in WEDGE15_EDGES {
                                        e.push(
                                            self.mid_node(&mut mesh, wedge[a], wedge[b], &mut rng),
                                        );
                                    }
                                }
                                mesh.elements.push(e);
                            }
                        }
                    }
                }
            }
        }
        mesh
    }

    /// A random move: `amplitude` cell sizes times `d` (components in `[-1,
    /// 1)`) along each axis.
    fn shift(&self, amplitude: f64, d: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|c| amplitude * self.size[c] / self.cells[c] as f64 * d[c])
    }

    /// The mid-edge node between nodes `a` and `b`, added at the midpoint
    /// of their coordinates (moved off it if interior) on first use.
    fn mid_node(&self, mesh: &mut SolidMesh, a: usize, b: usize, rng: &mut Xorshift) -> usize {
        let key = (a.min(b), a.max(b));
        if let Some(&m) = mesh.mid.get(&key) {
            return m;
        }
        let r = [0, 1, 2].map(|c| 0.5 * (mesh.reference[a][c] + mesh.reference[b][c]));
        let inside = r.iter().all(|&v| v > 0.0 && v < 1.0);
        let amplitude = if inside { self.edge_distortion } else { 0.0 };
        let shift = self.shift(amplitude, rng.vec3());
        mesh.reference.push(r);
        mesh.coords
            .push([0, 1, 2].map(|c| 0.5 * (mesh.coords[a][c] + mesh.coords[b][c]) + shift[c]));
        mesh.mid.insert(key, mesh.coords.len() - 1);
        mesh.coords.len() - 1
    }
}

impl SolidMesh {
    /// True if node `n` lay on a face of the block before the moves.
    pub fn on_boundary(&self, n: usize) -> bool {
        self.reference[n].iter().any(|&v| v == 0.0 || v == 1.0)
    }

    /// The nodes, node index `n` as node id `n + 1`.
    pub fn nodes(&self) -> Vec<Node> {
        self.coords
            .iter()
            .enumerate()
            .map(|(n, x)| Node {
                id: n as NodeId + 1,
                coords: *x,
            })
            .collect()
    }

    /// The elements of `material`, numbered from 1, on the node ids of
    /// [`Self::nodes`].
    pub fn elements(&self, material: &Material) -> Vec<Element> {
        self.elements
            .iter()
            .enumerate()
            .map(|(e, nodes)| {
                Element::Solid(Solid {
                    id: e + 1,
                    kind: self.kind,
                    nodes: nodes.iter().map(|&n| n as NodeId + 1).collect(),
                    material: material.clone(),
                })
            })
            .collect()
    }
}

/// Six times the signed volume of the tetrahedron on the first four nodes
/// `t` of `coords`.
fn tet_volume(coords: &[[f64; 3]], t: &[usize]) -> f64 {
    let d = |k: usize| [0, 1, 2].map(|c| coords[t[k]][c] - coords[t[0]][c]);
    let (a, b, c) = (d(1), d(2), d(3));
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Deterministic pseudo-random numbers in `[-1, 1)` (xorshift).
pub(crate) struct Xorshift(u64);

impl Xorshift {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    pub(crate) fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    pub(crate) fn vec3(&mut self) -> [f64; 3] {
        [self.next(), self.next(), self.next()]
    }
}

/// The two-node beam element a [`BeamLine`] is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BeamLineKind {
    /// [`PlanarBeam`]s (DOFs `uz`, `ry`); the line must run along x.
    Planar,
    /// 3D [`Beam`]s whose local y axis lies towards `orientation` (global
    /// components).
    Spatial { orientation: [f64; 3] },
}

/// A straight line of `cells` two-node beam elements of `kind` and
/// `properties` from `start` to `end` (m). Nodes `1..=cells + 1` lie
/// equally spaced from `start` to `end`; element `i + 1` runs from node `i
/// + 1` to node `i + 2`.
#[derive(Clone, Debug)]
pub struct BeamLine {
    pub cells: usize,
    pub start: [f64; 3],
    pub end: [f64; 3],
    pub kind: BeamLineKind,
    pub properties: BeamProperties,
}

impl BeamLine {
    /// The nodes, node `i + 1` at `start + (end - start) i / cells`.
    pub fn nodes(&self) -> Vec<Node> {
        (0..=self.cells)
            .map(|i| Node {
                id: i as NodeId + 1,
                coords: [0, 1, 2].map(|k| {
                    self.start[k] + (self.end[k] - self.start[k]) * i as f64 / self.cells as f64
                }),
            })
            .collect()
    }

    /// The elements, numbered from 1, each running forward along the line.
    pub fn elements(&self) -> Vec<Element> {
        self.elements_reversed(|_| false)
    }

    /// The elements, numbered from 1; element `i + 1` runs backwards (from
    /// node `i + 2` to node `i + 1`) where `reversed(i)`, else forward.
    pub fn elements_reversed(&self, reversed: impl Fn(usize) -> bool) -> Vec<Element> {
        (0..self.cells)
            .map(|i| {
                let mut nodes = [i as NodeId + 1, i as NodeId + 2];
                if reversed(i) {
                    nodes.reverse();
                }
                let properties = self.properties.clone();
                match self.kind {
                    BeamLineKind::Planar => Element::PlanarBeam(PlanarBeam {
                        id: i + 1,
                        nodes,
                        properties,
                    }),
                    BeamLineKind::Spatial { orientation } => Element::Beam(Beam {
                        id: i + 1,
                        nodes,
                        properties,
                        orientation,
                    }),
                }
            })
            .collect()
    }

    /// The line as a model of its forward elements with the DOFs `fixed`
    /// held: no node sets, no damping.
    pub fn model(&self, fixed: Vec<Dof>) -> Result<Model, FemError> {
        Model::of(self.nodes(), self.elements())
            .fixed(fixed)
            .build()
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
/// 7850 kg/m^3); shells 10 mm thick; beams a 50 mm wide, 80 mm high
/// rectangle with local y along global y; masses of 12.5 kg; springs of
/// 1e6 N/m and dashpots of 2e3 N s/m on `uy` (as many DOFs as the kind
/// names).
pub fn sample_section(kind: SectionKind) -> SectionValues {
    let material = Material::new(2.1e11, 0.3, 7850.0).expect("valid constants");
    match kind {
        SectionKind::Solid => SectionValues::Solid { material },
        SectionKind::Shell => SectionValues::Shell {
            material,
            thickness: 0.01,
            offset: 0.0,
        },
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
        SectionKind::Dashpot { dofs } => SectionValues::Dashpot {
            dofs: [0, 1].map(|k| (k < dofs).then_some(crate::DofKind::Uy)),
            coefficient: 2.0e3,
        },
    }
}
