//! Solid bars and blocks built in code, springs to ground, and a
//! comparison of frequency lists.

use flexbody_fem::element::solid::{Solid, SolidKind};
use flexbody_fem::mesh::BrickBlock;
use flexbody_fem::{Dof, DofKind, Element, Material, Model, Node, Substructure};

/// A steel C3D8 bar of `nx * ny * nz` elements over `size` (m). With
/// `dangling`, one more element hangs on the corner node at
/// `(size_x, 0, 0)` by that node alone: it can rotate about it (a
/// mechanism with 3 zero-frequency modes besides the 6 rigid ones).
pub(crate) fn block(
    nx: usize,
    ny: usize,
    nz: usize,
    size: [f64; 3],
    dangling: bool,
) -> Substructure {
    block_held(nx, ny, nz, size, dangling, false)
}

/// [`block`], with `clamped` every DOF of its end x = 0 fixed.
pub(crate) fn block_held(
    nx: usize,
    ny: usize,
    nz: usize,
    size: [f64; 3],
    dangling: bool,
    clamped: bool,
) -> Substructure {
    let grid = BrickBlock {
        cells: [nx, ny, nz],
        origin: [0.0; 3],
        size,
    };
    let id = |i: usize, j: usize, k: usize| grid.node([i, j, k]);
    let mut nodes = grid.nodes();
    let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
    let mut elements = grid.elements(&steel);
    if dangling {
        // The cube [L, L+h] x [-h, 0] x [-h, 0]; its 8th node is (L, 0, 0).
        let (l, h) = (size[0], size[0] / nx as f64);
        let first = 1_000_000u64;
        let corners = [
            [l, -h, -h],
            [l + h, -h, -h],
            [l + h, 0.0, -h],
            [l, 0.0, -h],
            [l, -h, 0.0],
            [l + h, -h, 0.0],
            [l + h, 0.0, 0.0],
        ];
        let mut ids = Vec::new();
        for (c, x) in corners.iter().enumerate() {
            nodes.push(Node {
                id: first + c as u64,
                coords: *x,
            });
            ids.push(first + c as u64);
        }
        ids.push(id(nx, 0, 0));
        elements.push(Element::Solid(Solid {
            id: elements.len() + 1,
            kind: SolidKind::C3D8,
            nodes: ids,
            material: steel,
        }));
    }
    let mut fixed = Vec::new();
    if clamped {
        for k in 0..=nz {
            for j in 0..=ny {
                let node = id(0, j, k);
                fixed.extend(
                    [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|kind| Dof::new(node, kind)),
                );
            }
        }
    }
    let model = Model::of(nodes, elements).fixed(fixed).build().unwrap();
    Substructure::from_model(&model).unwrap()
}

pub(crate) fn assert_close(got: &[f64], want: &[f64], tol: f64) {
    assert_eq!(got.len(), want.len());
    let elastic = want.iter().copied().find(|l| *l > 1.0).unwrap();
    for (g, w) in got.iter().zip(want) {
        let scale = if w.abs() < 1e-6 * elastic {
            elastic
        } else {
            w.abs()
        };
        assert!(
            (g - w).abs() <= tol * scale,
            "{g} vs {w}\n{got:?}\n{want:?}"
        );
    }
}

/// Springs of `stiffness` in x, y and z at each of `nodes`, as
/// `elastic-residual` takes them.
pub(crate) fn springs_at(nodes: &[u64], stiffness: f64) -> Vec<flexbody_reduce::GroundSpring> {
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    nodes
        .iter()
        .flat_map(|&node| {
            axes.map(|direction| flexbody_reduce::GroundSpring {
                node,
                direction,
                stiffness,
            })
        })
        .collect()
}

/// A bar of `nx` C3D8 elements (0.1 x 0.05 x 0.05 m each) whose element
/// `e` (from 0) has the density `density(e)`.
pub(crate) fn bar_of_densities(nx: usize, density: impl Fn(usize) -> f64) -> Substructure {
    let bar = BrickBlock {
        cells: [nx, 1, 1],
        origin: [0.0; 3],
        size: [0.1 * nx as f64, 0.05, 0.05],
    };
    let elements = bar.elements_of(|e| Material::new(2.1e11, 0.3, density(e)).unwrap());
    let model = Model::of(bar.nodes(), elements).build().unwrap();
    Substructure::from_model(&model).unwrap()
}
