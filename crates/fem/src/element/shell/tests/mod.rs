//! Tests of the MITC shells: single elements (rigid-body modes on warped
//! geometry, patch tests, stresses, bad input), plates against published
//! frequencies, a thin cantilever against beam theory, and a ring of
//! shells against the closed form of a curved beam.

mod element;
mod plates;

use super::{Shell, ShellKind};
use crate::dof::{Dof, DofKind};
use crate::element::Element;
use crate::model::{Model, Node, NodeId};
use crate::section::Material;
use crate::{assemble, SystemMatrices};
use flexbody_linalg::eigen::Wanted;
use flexbody_linalg::memory::Budget;
use flexbody_linalg::progress::NoProgress;
use flexbody_linalg::solver::{eigen, Solver};

/// Steel of the NAFEMS plate tests: E = 200 GPa, nu = 0.3, rho = 8000.
fn nafems_steel() -> Material {
    Material::new(200e9, 0.3, 8000.0).unwrap()
}

/// A structured mesh over the grid `(i, j)`, `0 <= i <= nx`, `0 <= j <= ny`,
/// node positions from `at(i, j)`: S4 cells, or each cell cut into two S3
/// along the diagonal from `(i, j)` to `(i + 1, j + 1)`. Node ids are
/// `1 + i + (nx + 1) j`.
struct Grid {
    nx: usize,
    ny: usize,
    nodes: Vec<Node>,
    elements: Vec<Element>,
}

impl Grid {
    fn new(
        kind: ShellKind,
        [nx, ny]: [usize; 2],
        material: &Material,
        thickness: f64,
        at: impl Fn(usize, usize) -> [f64; 3],
    ) -> Self {
        let id = |i: usize, j: usize| (1 + i + (nx + 1) * j) as NodeId;
        let mut nodes = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                nodes.push(Node {
                    id: id(i, j),
                    coords: at(i, j),
                });
            }
        }
        let mut cells: Vec<Vec<NodeId>> = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                match kind {
                    ShellKind::S4 => cells.push(vec![a, b, c, d]),
                    ShellKind::S3 => {
                        cells.push(vec![a, b, c]);
                        cells.push(vec![a, c, d]);
                    }
                }
            }
        }
        let elements = cells
            .into_iter()
            .enumerate()
            .map(|(e, nodes)| {
                Element::Shell(Shell {
                    id: e + 1,
                    kind,
                    nodes,
                    material: material.clone(),
                    thickness,
                    offset: 0.0,
                })
            })
            .collect();
        Self {
            nx,
            ny,
            nodes,
            elements,
        }
    }

    fn id(&self, i: usize, j: usize) -> NodeId {
        (1 + i + (self.nx + 1) * j) as NodeId
    }

    /// Every node with its grid indices.
    fn each(&self) -> impl Iterator<Item = (usize, usize, NodeId)> + '_ {
        (0..=self.ny).flat_map(move |j| (0..=self.nx).map(move |i| (i, j, self.id(i, j))))
    }

    fn model(&self, fixed: Vec<Dof>) -> Model {
        Model::of(self.nodes.clone(), self.elements.clone())
            .fixed(fixed)
            .build()
            .unwrap()
    }
}

/// The lowest `count` frequencies (Hz) of a model.
fn frequencies(model: &Model, count: usize) -> Vec<f64> {
    let SystemMatrices {
        stiffness, mass, ..
    } = assemble(model).unwrap();
    let found = eigen(
        &stiffness,
        &mass,
        Wanted::Lowest(count),
        Solver::Auto,
        Budget::MACHINE,
        &NoProgress,
    )
    .unwrap();
    found
        .pairs
        .values
        .iter()
        .map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect()
}

/// `dofs` at `node`.
fn at(node: NodeId, dofs: &[DofKind]) -> impl Iterator<Item = Dof> + '_ {
    dofs.iter().map(move |&k| Dof::new(node, k))
}

/// The largest relative difference of `got` from `want`, printed.
fn worst(case: &str, got: &[f64], want: &[f64]) -> f64 {
    let mut w = 0.0_f64;
    for (k, (g, r)) in got.iter().zip(want).enumerate() {
        let e = (g - r) / r;
        eprintln!(
            "{case} mode {}: {g:.5} Hz against {r:.5} ({:+.3} %)",
            k + 1,
            100.0 * e
        );
        w = w.max(e.abs());
    }
    w
}

/// Nodal element map for tests that place loads: equation of a DOF.
fn equation(model: &Model, node: NodeId, kind: DofKind) -> usize {
    model.dof_map().index_of(Dof::new(node, kind)).unwrap()
}
