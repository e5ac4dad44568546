//! `ModalRecovery` of reduced bodies against statics and d'Alembert.

use crate::beams::*;
use crate::common::{load_vector, solve};
use flexbody_fem::{BeamTheory, Dof, DofKind, SectionForces, Substructure};
use flexbody_recover::ModalRecovery;
use flexbody_reduce::{reduce, Method, ModeKind, Reduction};

/// Modal section-force matrices of a Craig-Bampton body (interface: the
/// six tip DOFs, so the constraint modes hold the static response to tip
/// loads): `S_K q` with `K_red q = T^T f` must give the statics of the
/// cantilever at every element.
#[test]
fn modal_recovery_of_a_craig_bampton_cantilever_matches_statics() {
    let l = 1.5;
    let kind = Kind::Beam(BeamTheory::Timoshenko);
    let (a, dir, _) = skew();
    let b = combine(&[(1.0, a), (l, dir)]);
    let n = 6;
    let tip = n as u64 + 1;
    let model = cantilever(kind, n, l, skew(), |i| i % 3 == 2);
    let substructure = Substructure::from_model(&model).unwrap();
    let interface = all_dofs(kind, tip);
    let body = reduce(
        &substructure,
        &Reduction::new(Method::CraigBampton, 3, interface),
    )
    .unwrap();
    let force = [1.2e3, -2.5e3, 0.8e3];
    let moment = [150.0, -90.0, 220.0];
    let f = load_vector(&model, &node_loads(tip, force, moment));
    let r = body.r();
    let t = |i: usize, j: usize| body.basis[(i, j)];
    let f_red: Vec<f64> = (0..r)
        .map(|j| (0..f.len()).map(|i| t(i, j) * f[i]).sum())
        .collect();
    let k_red: Vec<Vec<f64>> = (0..r)
        .map(|i| (0..r).map(|j| body.stiffness[(i, j)]).collect())
        .collect();
    let q = solve(k_red, f_red);
    let recovery = ModalRecovery::new(&model, &body).unwrap();
    assert_eq!(recovery.elements.len(), n);
    let point_loads = tip_load_and_reaction(a, b, force, moment);
    let zero = vec![0.0; r];
    let mut got = Vec::new();
    let mut want = Vec::new();
    for (k, &id) in recovery.elements.iter().enumerate() {
        let e = element(&model, id);
        let nodes = e.nodes();
        got.push(recovery.forces(k, &q, &zero));
        want.push(statics(
            model.coords(nodes[0]),
            model.coords(nodes[1]),
            &frame(&model, e),
            &point_loads,
        ));
    }
    let dev = deviation(&got, &want);
    // measured 3.6e-12.
    assert!(dev < 3e-11, "deviation {dev:e}");
}

/// Modal section-force matrices of a free-residual body (rigid-body modes
/// plus inertia-relief attachment modes of the tip DOFs): the quasi-static
/// reduced state under tip loads — rigid accelerations `q''_R` and elastic
/// coordinates `q_E` from `M_red q'' + K_red q = T^T f` — must give the
/// d'Alembert forces of the accelerated beam through `S_K q + S_M q''`.
#[test]
fn modal_recovery_of_a_free_residual_body_matches_dalembert() {
    let (l, n) = (2.0, 8);
    for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
        let kind = Kind::Beam(theory);
        let model = along_x(kind, n, l, vec![]);
        let tip = n as u64 + 1;
        let sub = Substructure::from_model(&model).unwrap();
        let body = reduce(
            &sub,
            &Reduction::new(Method::FreeResidual, 3, all_dofs(kind, tip)),
        )
        .unwrap();
        let loads = [3.0e3, -2.0e3, 1.5e3, 400.0];
        let f = load_vector(
            &model,
            &[DofKind::Ux, DofKind::Uy, DofKind::Uz, DofKind::Rx]
                .iter()
                .zip(loads)
                .map(|(k, v)| (Dof::new(tip, *k), v))
                .collect::<Vec<_>>(),
        );
        let r = body.r();
        let rigid: Vec<bool> = body
            .modes
            .iter()
            .map(|m| matches!(m, ModeKind::Rigid { .. }))
            .collect();
        assert_eq!(rigid.iter().filter(|r| **r).count(), 6);
        // Unknowns: q''_j of the rigid columns, q_j of the others.
        let a_mat: Vec<Vec<f64>> = (0..r)
            .map(|i| {
                (0..r)
                    .map(|j| {
                        if rigid[j] {
                            body.mass[(i, j)]
                        } else {
                            body.stiffness[(i, j)]
                        }
                    })
                    .collect()
            })
            .collect();
        let f_red: Vec<f64> = (0..r)
            .map(|j| (0..f.len()).map(|i| body.basis[(i, j)] * f[i]).sum())
            .collect();
        let x = solve(a_mat, f_red);
        let q: Vec<f64> = (0..r).map(|j| if rigid[j] { 0.0 } else { x[j] }).collect();
        let q_dd: Vec<f64> = (0..r).map(|j| if rigid[j] { x[j] } else { 0.0 }).collect();
        let acc = Accelerated::new(&kind.properties(), l, loads);
        let recovery = ModalRecovery::new(&model, &body).unwrap();
        let mut got = Vec::new();
        let mut want = Vec::new();
        for (k, &id) in recovery.elements.iter().enumerate() {
            let nodes = element(&model, id).nodes();
            got.push(recovery.forces(k, &q, &q_dd));
            want.push(SectionForces {
                start: acc.section_forces(model.coords(nodes[0])[0]),
                end: acc.section_forces(model.coords(nodes[1])[0]),
            });
        }
        let dev = deviation(&got, &want);
        // measured 2.4e-14.
        assert!(dev < 1e-12, "{theory:?}: deviation {dev:e}");
    }
}
