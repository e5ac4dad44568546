//! Properties every mode type and method must have (report section 5),
//! on small free models built in code.

use crate::method::{free_body_rigid_modes, interface_equations};
use crate::modes::*;
use crate::ReduceError;
use faer::Mat;
use flexbody_fem::element::Beam;
use flexbody_fem::mesh::{BeamLine, BeamLineKind};
use flexbody_fem::{
    BeamProperties, BeamTheory, Dof, DofKind, Element, Material, Model, Node, SectionShape,
    Substructure, SystemMatrices,
};
use flexbody_linalg::sparse::{max_abs, project};

mod bodies;
mod mechanisms;

fn props() -> BeamProperties {
    let s = SectionShape::Box {
        width: 0.24,
        height: 0.20,
        wall: 0.012,
    };
    BeamProperties::new(
        Material::new(2.1e11, 0.3, 6800.0).unwrap(),
        s.constants().unwrap(),
        BeamTheory::EulerBernoulli,
    )
}

/// Free planar beam along x, `n` elements over 2.5 m, nodes 1..=n+1.
fn planar_beam(n: usize) -> Model {
    BeamLine {
        cells: n,
        start: [0.0; 3],
        end: [2.5, 0.0, 0.0],
        kind: BeamLineKind::Planar,
        properties: props(),
    }
    .model(vec![])
    .unwrap()
}

/// Free 3D L-frame: 4 beams along x, then 4 along y; nodes 1..=9.
fn l_frame() -> Model {
    let mut nodes = Vec::new();
    for i in 0..=4 {
        nodes.push(Node {
            id: i + 1,
            coords: [0.5 * i as f64, 0.0, 0.2],
        });
    }
    for i in 1..=4 {
        nodes.push(Node {
            id: 5 + i,
            coords: [2.0, 0.4 * i as f64, 0.2],
        });
    }
    let elements = (0..8)
        .map(|i| {
            Element::Beam(Beam {
                id: i + 1,
                nodes: [i as u64 + 1, i as u64 + 2],
                properties: BeamProperties::new(
                    props().material,
                    props().section,
                    BeamTheory::Timoshenko,
                ),
                orientation: [0.0, 0.0, 1.0],
            })
        })
        .collect();
    Model::of(nodes, elements).build().unwrap()
}

fn uz(nodes: &[u64]) -> Vec<Dof> {
    nodes.iter().map(|&n| Dof::new(n, DofKind::Uz)).collect()
}

fn setup(model: &Model) -> (SystemMatrices, RigidModes) {
    let sub = Substructure::from_model(model).unwrap();
    let rigid = free_body_rigid_modes(&sub).unwrap();
    (sub.matrices, rigid)
}

/// A free model with an interface: the model, its matrices and
/// rigid-body modes, the interface's equations `h` and unit loads on them.
fn free(
    model: Model,
    interface: &[Dof],
) -> (Model, SystemMatrices, RigidModes, Vec<usize>, Mat<f64>) {
    let (s, rigid) = setup(&model);
    let h = interface_equations(&sub(&model), interface).unwrap();
    let loads = unit_loads(model.dof_map().len(), &h);
    (model, s, rigid, h, loads)
}

/// The free planar beam of 20 elements with the interface uz at nodes 1,
/// 21, 7 and 15.
fn beam_on_four_points() -> (Model, SystemMatrices, RigidModes, Vec<usize>, Mat<f64>) {
    free(planar_beam(20), &uz(&[1, 21, 7, 15]))
}

fn sub(model: &Model) -> Substructure {
    Substructure::from_model(model).unwrap()
}

fn identity_error(a: &Mat<f64>) -> f64 {
    let n = a.nrows();
    max_abs((a - Mat::<f64>::identity(n, n)).as_ref())
}

#[test]
fn rigid_body_modes_carry_no_strain_and_are_m_orthonormal() {
    for (model, count) in [(planar_beam(20), 2), (l_frame(), 6)] {
        let (s, rigid) = setup(&model);
        assert_eq!(rigid.count(), count);
        assert!(crate::modes::rigid::strain_energy_ratio(&s.stiffness, &rigid) < 1e-13);
        let g = project(&s.mass, rigid.vectors.as_ref());
        assert!(
            identity_error(&g) < 1e-13,
            "T_st^T M T_st = I: {}",
            identity_error(&g)
        );
    }
    let (_, rigid) = setup(&planar_beam(20));
    assert_eq!(rigid.motions, vec!["uz", "ry"]);
}

#[test]
fn inertia_relief_loads_are_self_equilibrated_and_modes_solve_the_free_body() {
    for (model, interface) in [
        (planar_beam(20), uz(&[1, 21, 7, 15])),
        (
            l_frame(),
            vec![
                Dof::new(1, DofKind::Uz),
                Dof::new(9, DofKind::Ux),
                Dof::new(5, DofKind::Ry),
            ],
        ),
    ] {
        let (model, s, rigid, h, loads) = free(model, &interface);
        let map = model.dof_map();
        let p_g = self_equilibrated_loads(&s.mass, &rigid, &loads);
        // Report: 0 = T_st^T G^T P_1.
        let work = rigid.vectors.transpose() * &p_g;
        assert!(
            max_abs(work.as_ref()) < 1e-14 * max_abs(rigid.vectors.as_ref()),
            "{work:?}"
        );
        let first = map.dof(h[0]).node;
        let preferred: Vec<usize> = map.node_dofs(first).into_iter().map(|(_, i)| i).collect();
        let support = statically_determinate_support(&rigid, &preferred);
        assert_eq!(support, preferred, "all DOFs of the first interface node");
        let t =
            inertia_relief_attachment_modes(&s.stiffness, &s.mass, &rigid, &loads, &support, map)
                .unwrap();
        // Self-equilibrated loads need no support reactions: K t = P_g everywhere.
        let residual = &s.stiffness * &t - &p_g;
        assert!(
            max_abs(residual.as_ref()) < 1e-8 * max_abs(p_g.as_ref()),
            "{}",
            max_abs(residual.as_ref())
        );
        // And the rigid part is removed: T_st^T M t = 0.
        let c = rigid.vectors.transpose() * (&s.mass * &t);
        assert!(max_abs(c.as_ref()) < 1e-12 * max_abs(t.as_ref()) * rigid.vectors.norm_max());
    }
}

#[test]
fn any_statically_determinate_support_gives_the_same_modes() {
    let (model, s, rigid, _, loads) = beam_on_four_points();
    let map = model.dof_map();
    let at_node_1 = interface_equations(
        &sub(&model),
        &[Dof::new(1, DofKind::Uz), Dof::new(1, DofKind::Ry)],
    )
    .unwrap();
    let two_points = interface_equations(&sub(&model), &uz(&[4, 18])).unwrap();
    let a = inertia_relief_attachment_modes(&s.stiffness, &s.mass, &rigid, &loads, &at_node_1, map)
        .unwrap();
    let b =
        inertia_relief_attachment_modes(&s.stiffness, &s.mass, &rigid, &loads, &two_points, map)
            .unwrap();
    assert!(max_abs((&a - &b).as_ref()) < 1e-9 * max_abs(a.as_ref()));
}

#[test]
fn supports_that_constrain_or_do_not_fix_the_body_are_refused() {
    let model = planar_beam(20);
    let (s, rigid) = setup(&model);
    let map = model.dof_map();
    let loads = unit_loads(map.len(), &[0]);
    let three = interface_equations(&sub(&model), &uz(&[1, 11, 21])).unwrap();
    let err = inertia_relief_attachment_modes(&s.stiffness, &s.mass, &rigid, &loads, &three, map)
        .unwrap_err();
    assert!(
        matches!(
            err,
            ReduceError::SupportCount {
                given: 3,
                needed: 2,
                ..
            }
        ),
        "{err}"
    );
    let rotations = interface_equations(
        &sub(&model),
        &[Dof::new(1, DofKind::Ry), Dof::new(21, DofKind::Ry)],
    )
    .unwrap();
    let err =
        inertia_relief_attachment_modes(&s.stiffness, &s.mass, &rigid, &loads, &rotations, map)
            .unwrap_err();
    assert!(
        matches!(err, ReduceError::SupportNotDeterminate(_)),
        "{err}"
    );
}

#[test]
fn residual_modes_are_m_and_k_orthogonal_to_the_kept_eigenmodes() {
    let (model, s, rigid, _, loads) = beam_on_four_points();
    let map = model.dof_map();
    let support = statically_determinate_support(&rigid, &[0, 1]);
    let t = inertia_relief_attachment_modes(&s.stiffness, &s.mass, &rigid, &loads, &support, map)
        .unwrap();
    let phi = eigenmodes(&s.stiffness, &s.mass, Wanted::Lowest(5))
        .unwrap()
        .slice(2, 5)
        .vectors;
    let res = residual_modes(&t, &phi, &s.mass);
    let m_c = phi.transpose() * (&s.mass * &res);
    let k_c = phi.transpose() * (&s.stiffness * &res);
    let k_scale = max_abs((phi.transpose() * (&s.stiffness * &t)).as_ref());
    assert!(max_abs(m_c.as_ref()) < 1e-12 * max_abs((phi.transpose() * (&s.mass * &t)).as_ref()));
    assert!(
        max_abs(k_c.as_ref()) < 1e-9 * k_scale,
        "{} vs {k_scale}",
        max_abs(k_c.as_ref())
    );
}

#[test]
fn constraint_modes_are_unit_displacements_with_interior_equilibrium() {
    let (model, s, rigid, h, _) = beam_on_four_points();
    let map = model.dof_map();
    let t = constraint_modes(&s.stiffness, &h, map, &rigid).unwrap();
    let kt = &s.stiffness * &t;
    let k_scale = flexbody_linalg::sparse::max_abs_diagonal(&s.stiffness);
    for j in 0..h.len() {
        for (k, &hk) in h.iter().enumerate() {
            assert_eq!(t[(hk, j)], if j == k { 1.0 } else { 0.0 });
        }
        for i in (0..map.len()).filter(|i| !h.contains(i)) {
            assert!(
                kt[(i, j)].abs() < 1e-14 * k_scale,
                "interior force {} at {}",
                kt[(i, j)],
                map.dof(i)
            );
        }
    }
}

#[test]
fn soft_springs_give_the_constraint_modes_by_refinement() {
    // The L-frame on springs of 10 N/m in x, y and z at its ends and its
    // corner (its beams' stiffness is about 1e8): X = (K + C)^-1 [0; I]
    // is a rigid motion of about 1/c plus the elastic part X X_H^-1 keeps,
    // which round-off blurs to about 1e-7. The refinements against the
    // interior equilibrium bring the constraint modes back to round-off.
    use crate::modes::elastic_interface::constraint_modes_by_flexibility;
    use flexbody_linalg::ordering::Ordering;
    use flexbody_linalg::pencil::Pencil;
    use flexbody_linalg::sparse::add_scaled;
    let model = l_frame();
    let nodes = [1u64, 5, 9];
    let dofs: Vec<Dof> = nodes
        .iter()
        .flat_map(|&n| DofKind::ALL.map(|k| Dof::new(n, k)))
        .collect();
    let (model, s, rigid, h, _) = free(model, &dofs);
    let map = model.dof_map();
    let springs: Vec<crate::GroundSpring> = nodes
        .iter()
        .flat_map(|&node| {
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(|direction| {
                crate::GroundSpring {
                    node,
                    direction,
                    stiffness: 10.0,
                }
            })
        })
        .collect();
    let c = crate::method::support_stiffness(&sub(&model), &springs).unwrap();
    let supported = add_scaled(&s.stiffness, 1.0, &c).unwrap();
    let pencil = Pencil::analyze(
        &supported,
        &s.mass,
        None,
        Ordering::Auto,
        &flexbody_linalg::progress::NoProgress,
    )
    .unwrap();
    let factor = pencil
        .factorize(0.0, &flexbody_linalg::progress::NoProgress)
        .unwrap();
    let interior: Vec<usize> = (0..map.len()).filter(|i| !h.contains(i)).collect();
    let psi = constraint_modes_by_flexibility(
        &pencil,
        &factor,
        &h,
        &interior,
        &flexbody_linalg::progress::NoProgress,
    )
    .expect("the refinements reach round-off");
    let want = constraint_modes(&s.stiffness, &h, map, &rigid).unwrap();
    let err = max_abs((&psi - &want).as_ref()) / max_abs(want.as_ref());
    assert!(err < 1e-12, "{err:e}");
}
