//! Reduction methods on one factorisation equal the separate solvers.

use crate::models::*;
use crate::reference;
use faer::Mat;
use flexbody_fem::{Dof, DofKind};
use flexbody_linalg::progress::NoProgress;
use flexbody_linalg::sparse;
use flexbody_reduce::modes::eigen::{eigenmodes_with, Solver, Wanted, SPARSE_FROM};
use flexbody_reduce::{reduce, Method, Reduction};

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
        flexbody_reduce::modes::Wanted::Lowest(12),
    )
    .unwrap();
    let psi_ref = reference::constraint_modes(k, &boundary);
    let scale = psi_ref.norm_max();
    assert!((&psi - &psi_ref).norm_max() < 1e-12 * scale);
    let interior: Vec<usize> = (0..s.len()).filter(|i| !boundary.contains(i)).collect();
    let k_nn = flexbody_linalg::sparse::submatrix(k, &interior, &interior);
    let m_nn = flexbody_linalg::sparse::submatrix(m, &interior, &interior);
    let dense = eigenmodes_with(&k_nn, &m_nn, Wanted::Lowest(12), Solver::Dense).unwrap();
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
        statically_determinate_support, unit_loads, Wanted,
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
    let (t_a, all) = inertia_relief_and_free_modes(
        k,
        m,
        &rigid,
        &loads,
        &support,
        &s.dof_map,
        Wanted::Lowest(16),
    )
    .unwrap();
    let want = reference::inertia_relief_attachment_modes(k, m, &rigid, &loads, &support);
    assert!((&t_a - &want).norm_max() < 1e-10 * want.norm_max());
    let alone =
        inertia_relief_attachment_modes(k, m, &rigid, &loads, &support, &s.dof_map).unwrap();
    assert!((&alone - &want).norm_max() < 1e-10 * want.norm_max());
    // The held factor is the Lanczos operator too (shift 0, rigid-body
    // modes deflated): the modes are the dense solver's, M-orthonormal, and
    // eigenvectors of (K, M) to round-off.
    let dense = eigenmodes_with(k, m, Wanted::Lowest(16), Solver::Dense).unwrap();
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
        attachment_modes, inertia_relief_and_free_modes, unit_loads, RigidModes, Wanted,
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
        inertia_relief_and_free_modes(k, m, &rigid, &loads, &[], &s.dof_map, Wanted::Lowest(12))
            .unwrap();
    let want = reference::attachment_modes(k, &loads);
    assert!((&t_a - &want).norm_max() < 1e-10 * want.norm_max());
    let alone = attachment_modes(k, &loads, &s.dof_map).unwrap();
    assert!((&alone - &want).norm_max() < 1e-10 * want.norm_max());
    let dense = eigenmodes_with(k, m, Wanted::Lowest(12), Solver::Dense).unwrap();
    assert_close(&all.values, &dense.values, 1e-10);
    let g: Mat<f64> = all.vectors.transpose() * sparse::symmetric_mul(m, all.vectors.as_ref());
    assert!((g - Mat::<f64>::identity(12, 12)).norm_max() < 1e-10);
    // Through `reduce`, with K and M handed over: the same body.
    let interface: Vec<Dof> = boundary.iter().map(|&i| s.dof_map.dof(i)).collect();
    let spec = Reduction::new(Method::FreeResidual, 6, interface);
    let lent = reduce(&s, &spec).unwrap();
    let body = flexbody_reduce::reduce_keeping(
        &mut s.clone(),
        &spec,
        flexbody_reduce::Keep::Neither,
        &NoProgress,
    )
    .unwrap();
    assert_eq!(body.r(), 12 + 6);
    assert!(body.basis == lent.basis && body.stiffness == lent.stiffness);
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
        constraint_modes, elastic_residual_modes, rigid_body_modes, Wanted,
    };
    let s = block(10, 3, 3, [1.0, 0.2, 0.2], false);
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let corners = [1u64, 11, 34, 44];
    let boundary: Vec<usize> = (0..s.len())
        .filter(|&i| corners.contains(&s.dof_map.dof(i).node))
        .collect();
    assert_eq!(boundary.len(), 12);
    let rigid = rigid_body_modes(&s, [0.5, 0.1, 0.1]);
    let psi_ref = reference::constraint_modes(k, &boundary);
    let alone = constraint_modes(k, &boundary, &s.dof_map, &rigid).unwrap();
    assert!((&alone - &psi_ref).norm_max() < 1e-10 * psi_ref.norm_max());
    let one = vec![flexbody_reduce::GroundSpring {
        node: 1,
        direction: [1.0, 0.0, 0.0],
        stiffness: 1e7,
    }];
    for (springs, rigid_like) in [(springs_at(&corners, 1e7), 0), (one, 5)] {
        let c = support_stiffness(&s, &springs).unwrap();
        let (psi, phi) =
            elastic_residual_modes(k, m, &c, &boundary, &s.dof_map, &rigid, Wanted::Lowest(12))
                .unwrap();
        assert!(
            (&psi - &psi_ref).norm_max() < 1e-10 * psi_ref.norm_max(),
            "{}",
            (&psi - &psi_ref).norm_max() / psi_ref.norm_max()
        );
        let supported = sparse::add_scaled(k, 1.0, &c).unwrap();
        let dense = eigenmodes_with(&supported, m, Wanted::Lowest(12), Solver::Dense).unwrap();
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
        let body = reduce_keeping(&mut given, &spec, Keep::Neither, &NoProgress).unwrap();
        assert_eq!(given.matrices.stiffness.nrows(), 0, "{method}");
        assert_eq!(given.matrices.mass.nrows(), 0, "{method}");
        assert!(body.basis == lent.basis, "{method}");
        assert!(body.stiffness == lent.stiffness, "{method}");
        assert!(body.mass == lent.mass, "{method}");
        // K alone handed over (for the SID's invariants): M stays as it was.
        let mut kept = s.clone();
        let with_mass = reduce_keeping(&mut kept, &spec, Keep::Mass, &NoProgress).unwrap();
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
    let (k, m) = (&s.matrices.stiffness, &s.matrices.mass);
    let want = reference::constraint_modes(k, &boundary);
    for method in [Method::Guyan, Method::ElasticResidual] {
        let mut spec = Reduction::new(method, 0, interface.clone());
        spec.springs = springs_at(&[1, 11, 34, 44], 1e7);
        let body = reduce_keeping(&mut s.clone(), &spec, Keep::Neither, &NoProgress).unwrap();
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
    let body = reduce_keeping(&mut s.clone(), &spec, Keep::Neither, &NoProgress).unwrap();
    assert_eq!(body.r(), 6 + 12);
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
            Wanted::Lowest(16),
            Solver::Dense,
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
