//! The sparse eigen path of `eigenmodes` on solid models built in code:
//! it equals the dense solver, finds repeated frequencies with their full
//! multiplicity, and a mechanism is reported through `reduce`.

use faer::Mat;
use flexbody_fem::element::solid::{Solid, SolidKind};
use flexbody_fem::{Dof, DofKind, Element, Material, Model, Node, Substructure};
use flexbody_linalg::lanczos::{lanczos, LanczosParams, Wanted};
use flexbody_linalg::progress::NoProgress;
use flexbody_linalg::sparse;
use flexbody_reduce::modes::eigen::{eigenmodes_with, EigenSolver, SPARSE_FROM};
use flexbody_reduce::{reduce, Method, ReduceError, Reduction};
use std::collections::BTreeMap;

/// A steel C3D8 bar of `nx * ny * nz` elements over `size` (m). With
/// `dangling`, one more element hangs on the corner node at
/// `(size_x, 0, 0)` by that node alone: it can rotate about it (a
/// mechanism with 3 zero-frequency modes besides the 6 rigid ones).
fn block(nx: usize, ny: usize, nz: usize, size: [f64; 3], dangling: bool) -> Substructure {
    block_held(nx, ny, nz, size, dangling, false)
}

/// [`block`], with `clamped` every DOF of its end x = 0 fixed.
fn block_held(
    nx: usize,
    ny: usize,
    nz: usize,
    size: [f64; 3],
    dangling: bool,
    clamped: bool,
) -> Substructure {
    let id = |i: usize, j: usize, k: usize| (1 + i + (nx + 1) * (j + (ny + 1) * k)) as u64;
    let mut nodes = Vec::new();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                nodes.push(Node {
                    id: id(i, j, k),
                    coords: [
                        size[0] * i as f64 / nx as f64,
                        size[1] * j as f64 / ny as f64,
                        size[2] * k as f64 / nz as f64,
                    ],
                });
            }
        }
    }
    let steel = Material::new(2.1e11, 0.3, 7850.0).unwrap();
    let mut elements = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                elements.push(Element::Solid(Solid {
                    id: elements.len() + 1,
                    kind: SolidKind::C3D8,
                    nodes: vec![
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ],
                    material: steel.clone(),
                }));
            }
        }
    }
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
    let model = Model::new(nodes, elements, BTreeMap::new(), fixed, None).unwrap();
    Substructure::from_model(&model).unwrap()
}

fn assert_close(got: &[f64], want: &[f64], tol: f64) {
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

#[test]
fn sparse_path_equals_dense_on_a_solid_bar() {
    // 10 x 3 x 3 C3D8: 528 DOFs, free; 20 modes (6 rigid).
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, 20, EigenSolver::Dense).unwrap();
    let sparse = eigenmodes_with(k, m, 20, EigenSolver::Sparse).unwrap();
    assert_close(&sparse.values, &dense.values, 1e-10);
    // The same modes: |phi_s^T M phi_d| = 1 on the simple elastic ones.
    let overlap = sparse.vectors.transpose() * m * &dense.vectors;
    for j in 6..19 {
        let v = &dense.values;
        let simple = (v[j] - v[j - 1]).abs() > 1e-6 * v[j] && (v[j + 1] - v[j]).abs() > 1e-6 * v[j];
        if simple {
            assert!((overlap[(j, j)].abs() - 1.0).abs() < 1e-8, "mode {j}");
        }
    }
}

/// `eigenmodes_owned` (the solver takes K and M and drops them once it
/// holds its compact copy) gives the dense solver's modes and residuals at
/// round-off, for a count and for a band.
#[test]
fn owned_matrices_give_the_same_modes_and_their_residuals() {
    use flexbody_reduce::modes::eigen::{eigenmodes_owned, Band};
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, 20, EigenSolver::Dense).unwrap();
    let (modes, residuals) = eigenmodes_owned(k.clone(), m.clone(), Band::Lowest(20)).unwrap();
    assert_close(&modes.values, &dense.values, 1e-10);
    assert_eq!(residuals.len(), 20);
    assert!(residuals.iter().all(|r| *r < 1e-8), "{residuals:?}");
    // The band up to midway between modes 12 and 13: exactly 12 modes.
    let v = &dense.values;
    let hz = 0.5 * (v[11].sqrt() + v[12].sqrt()) / (2.0 * std::f64::consts::PI);
    let (band, _) = eigenmodes_owned(k.clone(), m.clone(), Band::BelowHz(hz)).unwrap();
    assert_close(&band.values, &dense.values[..12], 1e-10);
}

#[test]
fn a_cube_has_its_repeated_frequencies_with_full_multiplicity() {
    // A 6 x 6 x 6 C3D8 cube (1029 DOFs): by symmetry, 2- and 3-fold
    // frequencies. The sparse path (Auto at this size) must give each of
    // them as often as the dense solver and the Sturm count.
    let s = block(6, 6, 6, [0.3, 0.3, 0.3], false);
    assert!(s.len() >= SPARSE_FROM);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, 40, EigenSolver::Dense)
        .unwrap()
        .values;
    let count = (24..40)
        .find(|&c| dense[c] > dense[c - 1] * (1.0 + 1e-6))
        .unwrap();
    let repeated = (7..count)
        .filter(|&i| (dense[i] - dense[i - 1]).abs() < 1e-8 * dense[i])
        .count();
    assert!(repeated >= 6, "{dense:?}");
    let found = lanczos(
        k,
        m,
        Wanted::Lowest(count),
        &LanczosParams::default(),
        &NoProgress,
    )
    .unwrap();
    let sturm = found.sturm.unwrap();
    assert_eq!(sturm.count, count, "{sturm:?}");
    assert_eq!(sturm.found, count);
    assert_close(&found.pairs.values, &dense[..count], 1e-10);
    // Auto takes the sparse path here and agrees.
    let auto = flexbody_reduce::modes::eigenmodes(k, m, count).unwrap();
    assert_close(&auto.values, &dense[..count], 1e-10);
    let g: Mat<f64> = auto.vectors.transpose() * m * &auto.vectors;
    for i in 0..count {
        for j in 0..count {
            let d = if i == j { 1.0 } else { 0.0 };
            assert!((g[(i, j)] - d).abs() < 1e-10);
        }
    }
}

#[test]
fn a_mechanism_is_reported_with_its_zero_mode_count() {
    // A bar with one element hanging on a single node: 9 zero-frequency
    // modes (6 rigid + 3 rotations of the element about that node).
    let s = block(12, 4, 4, [1.2, 0.2, 0.2], true);
    assert!(s.len() >= SPARSE_FROM, "{} DOFs", s.len());
    let found = lanczos(
        &s.matrices.stiffness,
        &s.matrices.mass,
        Wanted::Lowest(12),
        &LanczosParams::default(),
        &NoProgress,
    )
    .unwrap();
    let v = &found.pairs.values;
    let zero = v.iter().filter(|l| l.abs() < 1e-6 * v[11]).count();
    assert_eq!(zero, 9, "{v:?}");
    // Every free method names the count, on the sparse path (1053 DOFs)
    // and the dense one (69 DOFs), K and M lent or handed over: `free`
    // with no more modes than rigid ones (once reduced silently), with one
    // more (once "7 zero-frequency modes", all it had computed), and
    // free-residual (once only "K on the support is singular at a DOF").
    let small = block(3, 1, 1, [0.3, 0.1, 0.1], true);
    assert!(small.len() < SPARSE_FROM);
    let interface: Vec<Dof> = [DofKind::Ux, DofKind::Uy, DofKind::Uz]
        .map(|k| Dof::new(1, k))
        .to_vec();
    for model in [&s, &small] {
        // A band of 1 mHz holds the rigid-body modes alone (0 modes asked).
        for (method, modes) in [
            (Method::Free, 12),
            (Method::Free, 6),
            (Method::Free, 7),
            (Method::Free, 0),
            (Method::FreeResidual, 4),
            (Method::FreeResidual, 0),
        ] {
            let mut spec = Reduction::new(method, modes, interface.clone());
            if modes == 0 {
                spec.max_frequency_hz = Some(1e-3);
            }
            let lent = reduce(model, &spec);
            let given = flexbody_reduce::reduce_keeping(
                &mut model.clone(),
                &spec,
                flexbody_reduce::Keep::Neither,
            );
            for result in [lent, given] {
                match result {
                    Err(ReduceError::FreeMechanism { zero, rigid }) => {
                        assert_eq!((zero, rigid), (9, 6), "{method} {modes}");
                    }
                    other => panic!("{method} {modes}: got {:?}", other.map(|b| b.r())),
                }
            }
        }
        // Clamped at its end x = 0, the bar is held, the element is not:
        // K_NN is singular at a DOF of the element, which Craig-Bampton
        // names as the body's own mechanism (once "use the free-residual
        // method", which refuses it as above).
        let face: Vec<Dof> = model
            .dof_map
            .dofs()
            .iter()
            .filter(|d| model.coordinates[&d.node][0] == 0.0)
            .copied()
            .collect();
        let spec = Reduction::new(Method::CraigBampton, 4, face.clone());
        match reduce(model, &spec) {
            Err(ReduceError::BodyMechanism {
                interface,
                dof,
                rigid,
            }) => {
                assert_eq!((interface, rigid), (face, 6));
                assert!(dof.node >= 1_000_000, "{dof}");
            }
            other => panic!("Craig-Bampton: got {:?}", other.map(|b| b.r())),
        }
        // Matrices without node positions: the rigid-body modes come from
        // K's null space, which holds 9 zeros where 6 at most are rigid.
        let bare = Substructure::from_matrices(
            model.dof_map.clone(),
            model.matrices.clone(),
            Default::default(),
        );
        match flexbody_reduce::method::free_body_rigid_modes(&bare) {
            Err(ReduceError::FreeMechanism { zero, rigid }) => assert_eq!((zero, rigid), (9, 6)),
            other => panic!("matrices alone: got {:?}", other.map(|r| r.count())),
        }
    }
}

#[test]
fn craig_bampton_from_one_factorisation_equals_the_separate_solvers() {
    // 10 x 3 x 3 C3D8 (528 DOFs) clamped at the 16 nodes of its end x = 0:
    // the shared path (K_NN factorised once for the constraint modes and
    // the Lanczos operator at shift 0) against constraint modes from their
    // own LDL^T and the dense fixed-interface eigen solver.
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let boundary: Vec<usize> = (0..s.len())
        .filter(|&i| {
            let node = s.dof_map.dof(i).node;
            s.coordinates[&node][0] == 0.0
        })
        .collect();
    assert_eq!(boundary.len(), 48);
    let rigid = flexbody_reduce::modes::rigid_body_modes(&s, [0.0; 3]);
    let (psi, phi) = flexbody_reduce::modes::craig_bampton_modes(
        k,
        m,
        &boundary,
        &s.dof_map,
        &rigid,
        flexbody_reduce::modes::Band::Lowest(12),
    )
    .unwrap();
    let psi_ref =
        flexbody_reduce::modes::constraint_modes(k, &boundary, &s.dof_map, &rigid).unwrap();
    let scale = psi_ref.norm_max();
    assert!((&psi - &psi_ref).norm_max() < 1e-12 * scale);
    let interior: Vec<usize> = (0..s.len()).filter(|i| !boundary.contains(i)).collect();
    let k_nn = flexbody_linalg::sparse::submatrix(k, &interior, &interior);
    let m_nn = flexbody_linalg::sparse::submatrix(m, &interior, &interior);
    let dense = eigenmodes_with(&k_nn, &m_nn, 12, EigenSolver::Dense).unwrap();
    assert_close(&phi.values, &dense.values, 1e-10);
    // Zero at the interface, M-orthonormal.
    for &b in &boundary {
        assert!((0..12).all(|j| phi.vectors[(b, j)] == 0.0));
    }
    let g: Mat<f64> = phi.vectors.transpose() * m * &phi.vectors;
    assert!((g - Mat::<f64>::identity(12, 12)).norm_max() < 1e-10);
}

#[test]
fn free_residual_modes_from_one_analysis_equal_the_separate_solvers() {
    // The same bar, free, loaded at the 4 corner nodes of its end x = 0:
    // inertia-relief attachment modes from K held on the support inside the
    // pencil of K - sigma M (the shared path) against K_ff's own LDL^T;
    // the free eigenmodes against the dense solver.
    use flexbody_reduce::modes::{
        inertia_relief_and_free_modes, inertia_relief_attachment_modes, rigid_body_modes,
        statically_determinate_support, unit_loads, Band,
    };
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let corner = |y: f64, z: f64| {
        (0..s.len())
            .filter(|&i| {
                let x = s.coordinates[&s.dof_map.dof(i).node];
                x[0] == 0.0 && (x[1] - y).abs() < 1e-12 && (x[2] - z).abs() < 1e-12
            })
            .collect::<Vec<_>>()
    };
    let boundary: Vec<usize> = [(0.0, 0.0), (0.2, 0.0), (0.0, 0.2), (0.2, 0.2)]
        .iter()
        .flat_map(|&(y, z)| corner(y, z))
        .collect();
    assert_eq!(boundary.len(), 12);
    let rigid = rigid_body_modes(&s, [0.5, 0.1, 0.1]);
    let support = statically_determinate_support(&rigid, &boundary[..3]);
    let loads = unit_loads(s.len(), &boundary);
    let (t_a, all) =
        inertia_relief_and_free_modes(k, m, &rigid, &loads, &support, &s.dof_map, Band::Lowest(16))
            .unwrap();
    let want = inertia_relief_attachment_modes(k, m, &rigid, &loads, &support, &s.dof_map).unwrap();
    assert!((&t_a - &want).norm_max() < 1e-10 * want.norm_max());
    // The held factor is the Lanczos operator too (shift 0, rigid-body
    // modes deflated): the modes are the dense solver's, M-orthonormal, and
    // eigenvectors of (K, M) to round-off.
    let dense = eigenmodes_with(k, m, 16, EigenSolver::Dense).unwrap();
    assert_close(&all.values, &dense.values, 1e-10);
    let g: Mat<f64> = all.vectors.transpose() * sparse::symmetric_mul(m, all.vectors.as_ref());
    assert!((g - Mat::<f64>::identity(16, 16)).norm_max() < 1e-10);
    let residuals = flexbody_linalg::lanczos::residuals(
        k,
        m,
        &all.values,
        all.vectors.as_ref(),
        &sparse::diagonal(k),
    );
    assert!(residuals.iter().all(|&r| r < 1e-8), "{residuals:?}");
}

#[test]
fn free_residual_of_a_supported_body_from_one_factorisation() {
    // The bar clamped at its end x = 0 and loaded at the 4 corner nodes of
    // its end x = 1: no rigid-body modes, so plain attachment modes K^-1 P
    // (eq. 18) and the eigenmodes, both from one factor of K (the Lanczos
    // at shift 0), against K's own LDL^T and the dense solver.
    use flexbody_reduce::modes::{
        attachment_modes, inertia_relief_and_free_modes, unit_loads, Band, RigidModes,
    };
    let s = block_held(10, 3, 3, [1.0, 0.2, 0.2], false, true);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    assert!(s.len() >= SPARSE_FROM);
    let boundary: Vec<usize> = (0..s.len())
        .filter(|&i| [11u64, 44, 143, 176].contains(&s.dof_map.dof(i).node))
        .collect();
    assert_eq!(boundary.len(), 12);
    let rigid = RigidModes {
        vectors: Mat::zeros(s.len(), 0),
        motions: vec![],
    };
    let loads = unit_loads(s.len(), &boundary);
    let (t_a, all) =
        inertia_relief_and_free_modes(k, m, &rigid, &loads, &[], &s.dof_map, Band::Lowest(12))
            .unwrap();
    let want = attachment_modes(k, &loads, &s.dof_map).unwrap();
    assert!((&t_a - &want).norm_max() < 1e-10 * want.norm_max());
    let dense = eigenmodes_with(k, m, 12, EigenSolver::Dense).unwrap();
    assert_close(&all.values, &dense.values, 1e-10);
    let g: Mat<f64> = all.vectors.transpose() * sparse::symmetric_mul(m, all.vectors.as_ref());
    assert!((g - Mat::<f64>::identity(12, 12)).norm_max() < 1e-10);
    // Through `reduce`, with K and M handed over: the same body.
    let interface: Vec<Dof> = boundary.iter().map(|&i| s.dof_map.dof(i)).collect();
    let spec = Reduction::new(Method::FreeResidual, 6, interface);
    let lent = reduce(&s, &spec).unwrap();
    let body =
        flexbody_reduce::reduce_keeping(&mut s.clone(), &spec, flexbody_reduce::Keep::Neither)
            .unwrap();
    assert_eq!(body.r(), 12 + 6);
    assert!(body.basis == lent.basis && body.stiffness == lent.stiffness);
}

/// Springs of `stiffness` in x, y and z at each of `nodes`, as
/// `elastic-residual` takes them.
fn springs_at(nodes: &[u64], stiffness: f64) -> Vec<flexbody_reduce::GroundSpring> {
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

#[test]
fn elastic_residual_modes_from_one_factorisation_equal_the_separate_solvers() {
    // The bar on springs at the 4 corner nodes of its end x = 0 (the
    // interface). Springs in x, y and z there hold the body: K + C is
    // regular, and its one factor gives the constraint modes as
    // X X_H^-1 (X = (K + C)^-1 [0; I]) and the Lanczos operator at shift
    // 0. One spring in x holds nothing: the constraint modes come from the
    // pencil held at the interface, the Lanczos runs at a negative shift.
    // Both against K_NN's own LDL^T and the dense solver of K + C.
    use flexbody_reduce::method::support_stiffness;
    use flexbody_reduce::modes::{
        constraint_modes, elastic_residual_modes, rigid_body_modes, Band,
    };
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let corners = [1u64, 11, 34, 44];
    let boundary: Vec<usize> = (0..s.len())
        .filter(|&i| corners.contains(&s.dof_map.dof(i).node))
        .collect();
    assert_eq!(boundary.len(), 12);
    let rigid = rigid_body_modes(&s, [0.5, 0.1, 0.1]);
    let psi_ref = constraint_modes(k, &boundary, &s.dof_map, &rigid).unwrap();
    let one = vec![flexbody_reduce::GroundSpring {
        node: 1,
        direction: [1.0, 0.0, 0.0],
        stiffness: 1e7,
    }];
    for (springs, rigid_like) in [(springs_at(&corners, 1e7), 0), (one, 5)] {
        let c = support_stiffness(&s, &springs).unwrap();
        let (psi, phi) =
            elastic_residual_modes(k, m, &c, &boundary, &s.dof_map, &rigid, Band::Lowest(12))
                .unwrap();
        assert!(
            (&psi - &psi_ref).norm_max() < 1e-10 * psi_ref.norm_max(),
            "{}",
            (&psi - &psi_ref).norm_max() / psi_ref.norm_max()
        );
        let supported = sparse::add_scaled(k, 1.0, &c).unwrap();
        let dense = eigenmodes_with(&supported, m, 12, EigenSolver::Dense).unwrap();
        // The motions the springs leave free are at zero frequency.
        let zero = dense.values.iter().filter(|l| **l < 1.0).count();
        assert_eq!(zero, rigid_like);
        assert_close(&phi.values, &dense.values, 1e-10);
        let g: Mat<f64> = phi.vectors.transpose() * sparse::symmetric_mul(m, phi.vectors.as_ref());
        assert!((g - Mat::<f64>::identity(12, 12)).norm_max() < 1e-10);
        let residuals = flexbody_linalg::lanczos::residuals(
            &supported,
            m,
            &phi.values,
            phi.vectors.as_ref(),
            &sparse::diagonal(&supported),
        );
        assert!(residuals.iter().all(|&r| r < 1e-8), "{residuals:?}");
    }
}

/// `reduce_keeping` with `Keep::Neither` (K and M handed over, dropped once
/// the solver holds its compact copy) and `Keep::Mass` (K alone) give
/// `reduce`'s body bit for bit, for every method, and leave 0 x 0 matrices
/// behind; the reduced K and M from the compact copy
/// (for Craig-Bampton the interior's copy bordered by the interface) are
/// `T^T K T` and `T^T M T` of the full matrices.
#[test]
fn handing_k_and_m_over_gives_the_same_body() {
    use flexbody_reduce::{reduce_keeping, GroundSpring, Keep};
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    assert!(s.len() - 12 >= SPARSE_FROM);
    // The 4 corner nodes of the end x = 0 (nodes 1, 11, 34, 44).
    let interface: Vec<Dof> = [1u64, 11, 34, 44]
        .iter()
        .flat_map(|&n| [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|k| Dof::new(n, k)))
        .collect();
    // One spring, which holds nothing, and springs that hold the body (the
    // elastic-residual method's two paths).
    let one = vec![GroundSpring {
        node: 1,
        direction: [1.0, 0.0, 0.0],
        stiffness: 1e7,
    }];
    let runs = Method::ALL
        .into_iter()
        .map(|method| (method, one.clone()))
        .chain([(Method::ElasticResidual, springs_at(&[1, 11, 34, 44], 1e7))]);
    for (method, springs) in runs {
        let modes = if method == Method::Guyan { 0 } else { 10 };
        let mut spec = Reduction::new(method, modes, interface.clone());
        spec.springs = springs;
        let lent = reduce(&s, &spec).unwrap();
        let mut given = s.clone();
        let body = reduce_keeping(&mut given, &spec, Keep::Neither).unwrap();
        assert_eq!(given.matrices.stiffness.nrows(), 0, "{method}");
        assert_eq!(given.matrices.mass.nrows(), 0, "{method}");
        assert!(body.basis == lent.basis, "{method}");
        assert!(body.stiffness == lent.stiffness, "{method}");
        assert!(body.mass == lent.mass, "{method}");
        // K alone handed over (for the SID's invariants): M stays as it was.
        let mut kept = s.clone();
        let with_mass = reduce_keeping(&mut kept, &spec, Keep::Mass).unwrap();
        assert_eq!(kept.matrices.stiffness.nrows(), 0, "{method}");
        let (m, m0) = (kept.matrices.mass.as_ref(), s.matrices.mass.as_ref());
        assert!(m.col_ptr() == m0.col_ptr() && m.row_idx() == m0.row_idx());
        assert!(m.val() == m0.val(), "{method}");
        assert!(with_mass.basis == lent.basis, "{method}");
        assert!(with_mass.stiffness == lent.stiffness, "{method}");
        assert!(with_mass.mass == lent.mass, "{method}");
        let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
        for (got, want) in [
            (&body.stiffness, sparse::project(k, body.basis.as_ref())),
            (&body.mass, sparse::project(m, body.basis.as_ref())),
        ] {
            let scale = want.norm_max();
            assert!((got - &want).norm_max() < 1e-12 * scale, "{method}");
        }
    }
    // Without eigenmodes, Guyan and elastic-residual are the constraint
    // modes alone, from one factorisation of the interior.
    let boundary = flexbody_reduce::method::interface_equations(&s, &interface).unwrap();
    let rigid = flexbody_reduce::method::free_body_rigid_modes(&s).unwrap();
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let want = flexbody_reduce::modes::constraint_modes(k, &boundary, &s.dof_map, &rigid).unwrap();
    for method in [Method::Guyan, Method::ElasticResidual] {
        let mut spec = Reduction::new(method, 0, interface.clone());
        spec.springs = springs_at(&[1, 11, 34, 44], 1e7);
        let body = reduce_keeping(&mut s.clone(), &spec, Keep::Neither).unwrap();
        assert!(
            (&body.basis - &want).norm_max() < 1e-12 * want.norm_max(),
            "{method}"
        );
        let mass = sparse::project(m, want.as_ref());
        assert!((&body.mass - &mass).norm_max() < 1e-12 * mass.norm_max());
    }
    // A band below the first elastic mode: the rigid-body modes and the
    // residual inertia-relief attachment modes alone.
    let mut spec = Reduction::new(Method::FreeResidual, 0, interface);
    spec.max_frequency_hz = Some(1.0);
    let body = reduce_keeping(&mut s.clone(), &spec, Keep::Neither).unwrap();
    assert_eq!(body.r(), 6 + 12);
}

/// Times both paths (run with `--release -- --ignored --nocapture`).
#[test]
#[ignore]
fn time_dense_against_sparse() {
    for (nx, ny, nz) in [
        (4, 2, 2),
        (6, 3, 3),
        (10, 3, 3),
        (10, 4, 4),
        (14, 5, 4),
        (20, 5, 5),
    ] {
        let s = block(nx, ny, nz, [1.0, 0.2, 0.2], false);
        let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
        let t = std::time::Instant::now();
        let d = eigenmodes_with(k, m, 20, EigenSolver::Dense).unwrap();
        let td = t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let sp = eigenmodes_with(k, m, 20, EigenSolver::Sparse).unwrap();
        let ts = t.elapsed().as_secs_f64();
        let err = d
            .values
            .iter()
            .zip(&sp.values)
            .skip(6)
            .map(|(a, b)| ((a - b) / a).abs())
            .fold(0.0, f64::max);
        println!(
            "{} DOFs: dense {td:.3} s, sparse {ts:.3} s, max rel diff {err:e}",
            s.len()
        );
    }
}

/// A slender bar (1107 DOFs) and 150 modes on a basis of only 24 vectors
/// more than that (a basis held small to save memory): each restart keeps
/// little room to grow, and the first run stops converging new pairs
/// before it has them all. It hands the rest over to the Sturm check's
/// shift above the band (and, stalling again, to shifts below it): every
/// mode, counted by the inertia, with residuals below 1e-7, M-orthonormal,
/// and the dense solver's frequencies; the same for a band, which counts
/// first.
#[test]
fn a_stalled_run_finishes_on_shifts_above_the_band() {
    let s = block(40, 2, 2, [2.0, 0.05, 0.05], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let count = 150;
    let params = LanczosParams {
        basis_size: count + 24,
        ..Default::default()
    };
    let found = lanczos(k, m, Wanted::Lowest(count), &params, &NoProgress).unwrap();
    let sturm = found.sturm.unwrap();
    assert!(sturm.found_first < count, "{sturm:?}");
    assert!(
        sturm.count >= count && sturm.found == sturm.count,
        "{sturm:?}"
    );
    assert_eq!(found.pairs.values.len(), count);
    let worst = found.residuals.iter().copied().fold(0.0, f64::max);
    assert!(worst < 1e-7, "{:?}", found.residuals);
    let x = &found.pairs.vectors;
    let g: Mat<f64> = x.transpose() * m * x;
    let dev = (&g - Mat::<f64>::identity(count, count)).norm_max();
    assert!(dev < 1e-12, "{dev:e}");
    let dense = eigenmodes_with(k, m, count, EigenSolver::Dense).unwrap();
    assert_close(&found.pairs.values, &dense.values, 1e-9);
    // The band up to midway between modes 140 and 141: counted first, then
    // the stalled run finishes on a factor at the band's bound.
    let v = &dense.values;
    let bound = 0.5 * (v[139] + v[140]);
    let band = lanczos(k, m, Wanted::Below(bound), &params, &NoProgress).unwrap();
    let sturm = band.sturm.unwrap();
    assert_eq!(sturm.count, 140, "{sturm:?}");
    assert!(sturm.found_first < 140, "{sturm:?}");
    assert_eq!(band.pairs.values.len(), 140);
    assert!(
        band.residuals.iter().all(|r| *r < 1e-7),
        "{:?}",
        band.residuals
    );
    assert_close(&band.pairs.values, &v[..140], 1e-9);
}

/// 250 modes of the slender bar on a basis of only 16 vectors more: 187
/// restarts, two runs. However slowly a run converges, a mode is accepted
/// at the round-off floor of its operator and no higher: every residual
/// below 1e-7 (a rule that raised the floor where estimates stopped
/// falling accepted the top ones at up to 9.6e-5 here).
#[test]
fn a_slow_run_on_a_small_basis_accepts_no_mode_above_its_floor() {
    let s = block(40, 2, 2, [2.0, 0.05, 0.05], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let count = 250;
    let params = LanczosParams {
        basis_size: count + 16,
        ..Default::default()
    };
    let found = lanczos(k, m, Wanted::Lowest(count), &params, &NoProgress).unwrap();
    let sturm = found.sturm.unwrap();
    assert!(
        sturm.found == sturm.count && sturm.count >= count,
        "{sturm:?}"
    );
    let worst = found.residuals.iter().copied().fold(0.0, f64::max);
    assert!(worst < 1e-7, "{:?}", found.residuals);
    let dense = eigenmodes_with(k, m, count, EigenSolver::Dense).unwrap();
    assert_close(&found.pairs.values, &dense.values, 1e-9);
}

/// The 20 lowest modes of the 6 x 6 x 6 cube with the default basis: the
/// 6 rigid-body modes converge in 3 sweeps, the elastic ones, a decade per
/// sweep, after the first restart. Sweeps while the basis still grows are
/// no stall (they once counted as one and handed this run over to the
/// Sturm check's factor with only the rigid-body modes found: 27 sweeps
/// instead of 18).
#[test]
fn sweeps_before_the_first_restart_are_no_stall() {
    let s = block(6, 6, 6, [0.3, 0.3, 0.3], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let count = 20;
    let params = LanczosParams::default();
    let found = lanczos(k, m, Wanted::Lowest(count), &params, &NoProgress).unwrap();
    let sturm = found.sturm.unwrap();
    assert!(found.stats.restarts > 0, "{:?}", found.stats);
    assert_eq!(found.stats.runs, 1, "{sturm:?}");
    assert_eq!(sturm.found_first, sturm.count, "{sturm:?}");
    let dense = eigenmodes_with(k, m, count, EigenSolver::Dense).unwrap();
    assert_close(&found.pairs.values, &dense.values, 1e-10);
}

/// More modes than a Lanczos basis holds: for 600 of the 6 x 6 x 6 cube's
/// 1029 the basis would span the model, and a Krylov space that exhausts
/// it is round-off in its last blocks (900 of them once came with
/// residuals of 0.7, and with hundreds more eigenvalues below the Sturm
/// bound than it has). Such a count, or a band that holds one, goes to
/// the dense solver, ascending and accurate; half the modes and fewer
/// stay with Lanczos.
#[test]
fn a_count_whose_basis_would_span_the_model_is_solved_densely() {
    let s = block(6, 6, 6, [0.3, 0.3, 0.3], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let n = k.nrows();
    let dense = eigenmodes_with(k, m, n, EigenSolver::Dense).unwrap().values;
    let params = LanczosParams::default();
    let ascending = |v: &[f64]| v.windows(2).all(|w| w[0] <= w[1]);
    // The first count from 600 on that ends a cluster of equal frequencies.
    let count = (600..n)
        .find(|&c| dense[c] > dense[c - 1] * (1.0 + 1e-6))
        .unwrap();
    let found = lanczos(k, m, Wanted::Lowest(count), &params, &NoProgress).unwrap();
    assert!(
        found.stats.dense && found.stats.runs == 0,
        "{:?}",
        found.stats
    );
    assert_close(&found.pairs.values, &dense[..count], 1e-10);
    let worst = |r: &[f64]| r.iter().copied().fold(0.0, f64::max);
    assert!(
        worst(&found.residuals) < 1e-10,
        "{:e}",
        worst(&found.residuals)
    );
    // A band with that many modes: counted, then solved densely.
    let bound = 0.5 * (dense[count - 1] + dense[count]);
    let band = lanczos(k, m, Wanted::Below(bound), &params, &NoProgress).unwrap();
    assert!(band.stats.dense);
    assert_eq!(band.sturm.unwrap().count, count);
    assert_close(&band.pairs.values, &dense[..count], 1e-10);
    // Every mode (a bound above the highest, 84.6 kHz).
    let all = lanczos(k, m, Wanted::Below(1e20), &params, &NoProgress).unwrap();
    assert_eq!(all.sturm.unwrap().count, n);
    assert_close(&all.pairs.values, &dense, 1e-10);
    assert!(ascending(&all.pairs.values));
    assert!(worst(&all.residuals) < 1e-10, "{:e}", worst(&all.residuals));
    // Lanczos keeps 490 modes: its basis of 1012 leaves room.
    let lanczos_490 = lanczos(k, m, Wanted::Lowest(490), &params, &NoProgress).unwrap();
    assert!(!lanczos_490.stats.dense && lanczos_490.stats.runs >= 1);
    assert!(ascending(&lanczos_490.pairs.values));
    assert!(worst(&lanczos_490.residuals) < 1e-7);
    assert_close(&lanczos_490.pairs.values, &dense[..490], 1e-9);
}

/// A band whose bound is an eigenvalue to round-off: the Sturm count and
/// the modes found may place that one on either side of it, and neither
/// is an error; the modes returned are the lowest ones.
#[test]
fn a_band_bounded_on_an_eigenvalue_is_no_error() {
    let s = block(40, 2, 2, [2.0, 0.05, 0.05], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let dense = eigenmodes_with(k, m, 40, EigenSolver::Dense)
        .unwrap()
        .values;
    let params = LanczosParams::default();
    for i in 8..36 {
        let band = lanczos(k, m, Wanted::Below(dense[i]), &params, &NoProgress).unwrap();
        let len = band.pairs.values.len();
        assert!(len + 2 >= i && len <= i + 2, "{i}: {len}");
        assert_close(&band.pairs.values, &dense[..len], 1e-10);
    }
}

/// A bar of `nx` C3D8 elements (0.1 x 0.05 x 0.05 m each) whose element
/// `e` (from 0) has the density `density(e)`.
fn bar_of_densities(nx: usize, density: impl Fn(usize) -> f64) -> Substructure {
    let id = |i: usize, j: usize, k: usize| (1 + i + (nx + 1) * (j + 2 * k)) as u64;
    let mut nodes = Vec::new();
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..=nx {
                let x = [0.1 * i as f64, 0.05 * j as f64, 0.05 * k as f64];
                nodes.push(Node {
                    id: id(i, j, k),
                    coords: x,
                });
            }
        }
    }
    let elements = (0..nx)
        .map(|i| {
            Element::Solid(Solid {
                id: i + 1,
                kind: SolidKind::C3D8,
                nodes: vec![
                    id(i, 0, 0),
                    id(i + 1, 0, 0),
                    id(i + 1, 1, 0),
                    id(i, 1, 0),
                    id(i, 0, 1),
                    id(i + 1, 0, 1),
                    id(i + 1, 1, 1),
                    id(i, 1, 1),
                ],
                material: Material::new(2.1e11, 0.3, density(i)).unwrap(),
            })
        })
        .collect();
    let model = Model::new(nodes, elements, BTreeMap::new(), vec![], None).unwrap();
    Substructure::from_model(&model).unwrap()
}

/// DOFs that carry no mass (the last element of a bar of density 0) have
/// no finite eigenvalue. A band gives the finite ones below it: those of
/// K condensed on the DOFs with mass (exact for them, eq. 15), and a count
/// beyond them says how many there are. A model without any mass is
/// refused by name on both paths.
#[test]
fn massless_dofs_have_no_eigenvalue_and_a_band_gives_the_finite_ones() {
    use faer::linalg::solvers::Solve;
    use flexbody_reduce::modes::{eigenmodes, eigenmodes_in, Band};
    let s = bar_of_densities(2, |e| if e == 0 { 7850.0 } else { 0.0 });
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let n = s.len();
    // Equations of the 4 nodes at x = 0.2 m, which only the massless
    // element holds, and the others.
    let light: Vec<usize> = (0..n)
        .filter(|&i| s.node_coordinates(s.dof_map.dof(i).node).unwrap()[0] > 0.15)
        .collect();
    let heavy: Vec<usize> = (0..n).filter(|i| !light.contains(i)).collect();
    assert_eq!((light.len(), heavy.len()), (12, 24));
    let (kd, md) = (sparse::to_dense(k), sparse::to_dense(m));
    let block = |a: &Mat<f64>, r: &[usize], c: &[usize]| {
        Mat::from_fn(r.len(), c.len(), |i, j| a[(r[i], c[j])])
    };
    let k_ss = block(&kd, &light, &light);
    let k_sm = block(&kd, &light, &heavy);
    let x = k_ss.llt(faer::Side::Lower).unwrap().solve(&k_sm);
    let mut condensed = block(&kd, &heavy, &heavy) - k_sm.transpose() * &x;
    sparse::symmetrize(&mut condensed);
    let want = flexbody_linalg::eigen::generalized_symmetric(
        condensed.as_ref(),
        block(&md, &heavy, &heavy).as_ref(),
    )
    .unwrap()
    .values;
    let got = eigenmodes_in(k, m, Band::BelowHz(1e9)).unwrap().values;
    assert_eq!(got.len(), 24);
    let top = want[23];
    for (g, w) in got.iter().zip(&want) {
        assert!(
            (g - w).abs() < 1e-10 * w.abs().max(1e-6 * top),
            "{g} vs {w}"
        );
    }
    match eigenmodes(k, m, 30) {
        Err(ReduceError::NotEnoughModes {
            requested: 30,
            available: 24,
        }) => {}
        other => panic!("got {:?}", other.map(|p| p.values.len())),
    }
    // No mass at all: 36 DOFs (dense) and 372 (Lanczos).
    for nx in [2, 30] {
        let s = bar_of_densities(nx, |_| 0.0);
        let err = eigenmodes(&s.matrices.stiffness, &s.matrices.mass, 6).unwrap_err();
        assert!(err.to_string().contains("the mass matrix is zero"), "{err}");
    }
}

/// Springs that leave rigid-body motions free (none, or one spring in x)
/// make those motions zero-frequency eigenmodes of K + C, which the
/// constraint modes span already: elastic-residual keeps them out and its
/// e eigenmodes are elastic ones. The basis is independent (once it was
/// not: the dense solve of the reduced body failed, the Lanczos path gave
/// spurious near-zero frequencies), the free reduced body has
/// its 6 rigid-body zeros and elastic frequencies above the full model's;
/// without springs the 10 eigenmodes are the free body's, so its first 10
/// elastic frequencies are the full model's, to round-off.
#[test]
fn elastic_residual_keeps_rigid_motions_the_springs_leave_free_out_of_the_basis() {
    use flexbody_reduce::GroundSpring;
    for (nx, ny, nz) in [(10, 3, 3), (3, 1, 1)] {
        let s = block(nx, ny, nz, [1.0, 0.2, 0.2], false);
        // Three corners of the end x = 0 hold the body statically.
        let corners = [1, (nx + 1) * ny + 1, (nx + 1) * (ny + 1) * nz + 1];
        let interface: Vec<Dof> = corners
            .iter()
            .flat_map(|&n| [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|k| Dof::new(n as u64, k)))
            .collect();
        let full = eigenmodes_with(
            &s.matrices.stiffness,
            &s.matrices.mass,
            16,
            EigenSolver::Dense,
        )
        .unwrap()
        .frequencies_hz();
        let one = GroundSpring {
            node: 1,
            direction: [1.0, 0.0, 0.0],
            stiffness: 1e7,
        };
        for springs in [vec![], vec![one]] {
            let mut spec = Reduction::new(Method::ElasticResidual, 10, interface.clone());
            spec.springs = springs.clone();
            let body = reduce(&s, &spec).unwrap();
            assert_eq!(body.r(), 9 + 10);
            // The Gram matrix of the basis columns scaled to unit length: a
            // dependent basis has an eigenvalue at round-off (the residual
            // modes' high-frequency parts, small beside their rigid-body
            // parts, put the smallest at 3e-9 here).
            let t = &body.basis;
            let norms: Vec<f64> = (0..19).map(|j| t.col(j).norm_l2()).collect();
            let gram = t.transpose() * t;
            let scaled = Mat::from_fn(19, 19, |i, j| gram[(i, j)] / (norms[i] * norms[j]));
            let lowest = scaled.self_adjoint_eigenvalues(faer::Side::Lower).unwrap();
            assert!(lowest[0] > 1e-12, "{lowest:?}");
            let f = body.frequencies_hz().unwrap();
            assert_eq!(f.len(), 19);
            assert!(f[..6].iter().all(|x| *x < 1e-2) && f[6] > 100.0, "{f:?}");
            for (got, want) in f[6..16].iter().zip(&full[6..16]) {
                assert!(*got >= want * (1.0 - 1e-10), "{got} below {want}");
                if springs.is_empty() {
                    assert!((got - want).abs() < 1e-8 * want, "{got} vs {want}");
                }
            }
        }
    }
}

/// A stiffness with a negative eigenvalue (a chain of unit masses on
/// springs of 1e4 N/m, one of them -3e4 N/m: -5.1e4 1/s^2) is refused on
/// the dense path (40 DOFs; it once showed that mode as 0 Hz) and on the
/// Lanczos path (400 DOFs; once "dimension mismatch"), naming the count.
#[test]
fn an_indefinite_stiffness_is_refused_on_both_paths() {
    use faer::sparse::Triplet;
    use flexbody_linalg::LinalgError;
    use flexbody_reduce::modes::{eigenmodes, eigenmodes_in, Band};
    for n in [40, 400] {
        let spring = |i: usize| if i == n / 2 { -3e4 } else { 1e4 };
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, spring(i) + spring(i + 1)));
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -spring(i + 1)));
                t.push(Triplet::new(i + 1, i, -spring(i + 1)));
            }
        }
        let k = sparse::from_triplets(n, n, &t).unwrap();
        let ones: Vec<_> = (0..n).map(|i| Triplet::new(i, i, 1.0)).collect();
        let m = sparse::from_triplets(n, n, &ones).unwrap();
        for result in [
            eigenmodes(&k, &m, 5),
            eigenmodes_in(&k, &m, Band::BelowHz(1.0)),
        ] {
            match result {
                Err(ReduceError::Linalg(LinalgError::NotSemiDefinite { count: 1, .. })) => {}
                other => panic!("{n} DOFs: got {:?}", other.map(|p| p.values)),
            }
        }
    }
}
