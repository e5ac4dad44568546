//! Stresses of shells on their three surfaces: a strip in pure bending
//! against beam theory (exact for the element: constant curvature), and
//! the modal stress matrices against the nodal stresses of the fields
//! they combine.

use faer::linalg::solvers::Solve;
use faer::Mat;
use flexbody_fem::element::{Shell, ShellKind, StressLayer};
use flexbody_fem::{assemble, Dof, DofKind, Element, Material, Model, Node, NodeId};
use flexbody_recover::{nodal_stresses, ModalStress};
use flexbody_reduce::{Method, ModeKind, ReducedBody};

const LENGTH: f64 = 1.0;
const WIDTH: f64 = 0.1;
const THICKNESS: f64 = 0.004;

/// A strip `LENGTH x WIDTH` of S4 (or S3, two per cell) in the x-y plane,
/// `n x 1` cells, steel with nu = 0 (so that it bends as a beam), clamped
/// at x = 0. Node ids: `1 + i + (n + 1) j`.
fn strip(kind: ShellKind, n: usize) -> Model {
    let material = Material::new(2.1e11, 0.0, 7850.0).unwrap();
    let id = |i: usize, j: usize| (1 + i + (n + 1) * j) as NodeId;
    let mut nodes = Vec::new();
    for j in 0..=1 {
        for i in 0..=n {
            nodes.push(Node {
                id: id(i, j),
                coords: [LENGTH * i as f64 / n as f64, WIDTH * j as f64, 0.0],
            });
        }
    }
    let mut cells = Vec::new();
    for i in 0..n {
        let (a, b, c, d) = (id(i, 0), id(i + 1, 0), id(i + 1, 1), id(i, 1));
        match kind {
            ShellKind::S4 => cells.push(vec![a, b, c, d]),
            ShellKind::S3 => {
                cells.push(vec![a, b, c]);
                cells.push(vec![a, c, d]);
            }
            ShellKind::S6 | ShellKind::S8 => unreachable!("strips of S3 and S4 only"),
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
                thickness: THICKNESS,
                offset: 0.0,
            })
        })
        .collect();
    let fixed = [id(0, 0), id(0, 1)]
        .iter()
        .flat_map(|&n| DofKind::ALL.map(|k| Dof::new(n, k)))
        .collect();
    Model::of(nodes, elements).fixed(fixed).build().unwrap()
}

/// The static displacement of `model` under a moment `m` (N m) about y at
/// the tip x = L, half on each tip node.
fn bent(model: &Model, n: usize, m: f64) -> Vec<f64> {
    let k = assemble(model).unwrap().stiffness.to_dense();
    let mut f = Mat::<f64>::zeros(k.nrows(), 1);
    for j in 0..=1 {
        let node = (1 + n + (n + 1) * j) as NodeId;
        let eq = model
            .dof_map()
            .index_of(Dof::new(node, DofKind::Ry))
            .unwrap();
        f[(eq, 0)] = 0.5 * m;
    }
    let u = k.full_piv_lu().solve(&f);
    (0..k.nrows()).map(|i| u[(i, 0)]).collect()
}

#[test]
fn strip_in_pure_bending_gives_m_c_over_i_on_its_faces() {
    // A moment M about +y turns the tip by theta_y > 0, which moves the
    // top face (z = +t/2, u = z theta_y) along +x: sxx = +M (t/2) / I on
    // top, -M (t/2) / I at the bottom, 0 in the middle, everywhere along
    // the strip (a constant moment).
    let m = 3.0;
    let i = WIDTH * THICKNESS.powi(3) / 12.0;
    let face = m * THICKNESS / 2.0 / i;
    for kind in [ShellKind::S4, ShellKind::S3] {
        let n = 8;
        let model = strip(kind, n);
        let s = nodal_stresses(&model, &bent(&model, n, m)).unwrap();
        assert_eq!(s.nodes.len(), 3 * model.nodes().len(), "{kind:?}");
        for ((node, layer), sigma) in s.nodes.iter().zip(&s.layers).zip(&s.stress) {
            let want = match layer {
                StressLayer::Top => face,
                StressLayer::Bottom => -face,
                StressLayer::Middle => 0.0,
                StressLayer::Volume => panic!("a shell gives no volume stress"),
            };
            assert!(
                (sigma[0] - want).abs() < 1e-8 * face,
                "{kind:?} node {node} {layer:?}: sxx {} against {want}",
                sigma[0]
            );
            for (c, other) in sigma.iter().enumerate().skip(1) {
                assert!(
                    other.abs() < 1e-8 * face,
                    "{kind:?} node {node} {layer:?} [{c}]: {other}"
                );
            }
        }
        let (_, layer, peak) = s.peak_von_mises().unwrap();
        assert!(layer != StressLayer::Middle && (peak - face).abs() < 1e-8 * face);
    }
}

#[test]
fn modal_stresses_of_shells_combine_the_fields_nodal_stresses() {
    // Two displacement fields (bending under a tip moment, and a tip
    // moment of the other sign plus an in-plane stretch) as a two-column
    // basis: T_sigma q equals the nodal stresses of T q on every layer.
    let n = 6;
    let model = strip(ShellKind::S4, n);
    let u1 = bent(&model, n, 2.0);
    let ux_tip: Vec<usize> = (0..=1)
        .map(|j| {
            let node = (1 + n + (n + 1) * j) as NodeId;
            model
                .dof_map()
                .index_of(Dof::new(node, DofKind::Ux))
                .unwrap()
        })
        .collect();
    let mut u2 = bent(&model, n, -1.0);
    for eq in ux_tip {
        u2[eq] += 1e-4;
    }
    let dofs = model.dof_map().len();
    let body = ReducedBody {
        method: Method::Free,
        dof_map: model.dof_map().clone(),
        basis: Mat::from_fn(dofs, 2, |i, j| if j == 0 { u1[i] } else { u2[i] }),
        mass: Mat::identity(2, 2),
        stiffness: Mat::identity(2, 2),
        damping: None,
        modes: vec![ModeKind::Eigen { frequency_hz: 0.0 }; 2],
        interface: vec![],
        local_axes: Default::default(),
    };
    let q = [0.7, -1.3];
    let u: Vec<f64> = (0..dofs).map(|i| q[0] * u1[i] + q[1] * u2[i]).collect();
    let full = nodal_stresses(&model, &u).unwrap();
    let modal = ModalStress::new(&model, &body).unwrap().stresses(&q);
    assert_eq!((&modal.nodes, &modal.layers), (&full.nodes, &full.layers));
    let scale = full
        .stress
        .iter()
        .flatten()
        .fold(0.0_f64, |a, v| a.max(v.abs()));
    for (a, b) in modal.stress.iter().zip(&full.stress) {
        for c in 0..6 {
            assert!(
                (a[c] - b[c]).abs() < 1e-12 * scale,
                "{} against {}",
                a[c],
                b[c]
            );
        }
    }
}
