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

/// A structured mesh of `nx x ny` cells over the grid `(i, j)`, `0 <= i <=
/// nx`, `0 <= j <= ny`, node positions from `at(i, j)` (fractional `i, j`
/// for the mid-side nodes of S6): S4 cells, or each cell cut into two S3
/// or S6 along its diagonal from `(i, j)` to `(i + 1, j + 1)`. Nodes lie
/// on the half-step grid `(I, J) = (2 i, 2 j)` for S6, id `1 + I + (2 nx +
/// 1) J`, else on the grid itself, id `1 + i + (nx + 1) j`.
struct Grid {
    nx: usize,
    quadratic: bool,
    /// Every node with its grid position `(i, j)`.
    positions: Vec<(f64, f64, NodeId)>,
    nodes: Vec<Node>,
    elements: Vec<Element>,
}

impl Grid {
    fn new(
        kind: ShellKind,
        [nx, ny]: [usize; 2],
        material: &Material,
        thickness: f64,
        at: impl Fn(f64, f64) -> [f64; 3],
    ) -> Self {
        let quadratic = kind.is_quadratic();
        let steps = if quadratic { 2 } else { 1 };
        let (cols, rows) = (steps * nx, steps * ny);
        let hid = |a: usize, b: usize| (1 + a + (cols + 1) * b) as NodeId;
        let mut cells: Vec<Vec<NodeId>> = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (a0, b0) = (steps * i, steps * j);
                let corner = |di: usize, dj: usize| hid(a0 + steps * di, b0 + steps * dj);
                let (a, b, c, d) = (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
                let mid = |di: usize, dj: usize| hid(a0 + di, b0 + dj);
                match kind {
                    ShellKind::S4 => cells.push(vec![a, b, c, d]),
                    ShellKind::S3 => {
                        cells.push(vec![a, b, c]);
                        cells.push(vec![a, c, d]);
                    }
                    ShellKind::S8 => {
                        cells.push(vec![a, b, c, d, mid(1, 0), mid(2, 1), mid(1, 2), mid(0, 1)])
                    }
                    ShellKind::S6 => {
                        cells.push(vec![a, b, c, mid(1, 0), mid(2, 1), mid(1, 1)]);
                        cells.push(vec![a, c, d, mid(1, 1), mid(1, 2), mid(0, 1)]);
                    }
                }
            }
        }
        let mut used: Vec<NodeId> = cells.iter().flatten().copied().collect();
        used.sort_unstable();
        used.dedup();
        let mut positions = Vec::new();
        let mut nodes = Vec::new();
        for b in 0..=rows {
            for a in 0..=cols {
                let id = hid(a, b);
                if used.binary_search(&id).is_ok() {
                    let (i, j) = (a as f64 / steps as f64, b as f64 / steps as f64);
                    positions.push((i, j, id));
                    nodes.push(Node {
                        id,
                        coords: at(i, j),
                    });
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
            quadratic,
            positions,
            nodes,
            elements,
        }
    }

    /// The node at the grid corner `(i, j)`.
    fn id(&self, i: usize, j: usize) -> NodeId {
        let steps = if self.quadratic { 2 } else { 1 };
        (1 + steps * i + (steps * self.nx + 1) * steps * j) as NodeId
    }

    /// Every node with its grid position.
    fn each(&self) -> impl Iterator<Item = (f64, f64, NodeId)> + '_ {
        self.positions.iter().copied()
    }

    /// Closes the grid into a ring along i: the nodes at `i = nx` become
    /// those at `i = 0`.
    fn close_along_i(&mut self) {
        let nx = self.nx as f64;
        let first: Vec<(f64, NodeId)> = self
            .positions
            .iter()
            .filter(|p| p.0 == 0.0)
            .map(|p| (p.1, p.2))
            .collect();
        let last: Vec<(NodeId, NodeId)> = self
            .positions
            .iter()
            .filter(|p| p.0 == nx)
            .map(|p| (p.2, first.iter().find(|f| f.0 == p.1).unwrap().1))
            .collect();
        for e in &mut self.elements {
            if let Element::Shell(s) = e {
                for node in &mut s.nodes {
                    if let Some((_, f)) = last.iter().find(|(l, _)| l == node) {
                        *node = *f;
                    }
                }
            }
        }
        self.nodes.retain(|n| last.iter().all(|(l, _)| *l != n.id));
        self.positions.retain(|p| p.0 != nx);
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
