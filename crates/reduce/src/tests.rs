//! Properties every mode type and method must have (report section 5),
//! on small free models built in code.

use crate::method::{free_body_rigid_modes, interface_equations};
use crate::modes::*;
use crate::{reduce, Method, ReduceError, Reduction};
use faer::Mat;
use flexbody_fem::element::{Beam, PlanarBeam};
use flexbody_fem::{
    assemble, BeamProperties, BeamTheory, Dof, DofKind, Element, Material, Model, Node,
    SectionShape, Substructure, SystemMatrices,
};
use flexbody_linalg::sparse::{max_abs, project};
use flexbody_linalg::LinalgError;
use std::collections::BTreeMap;

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
    let nodes = (0..=n)
        .map(|i| Node {
            id: i as u64 + 1,
            coords: [2.5 * i as f64 / n as f64, 0.0, 0.0],
        })
        .collect();
    let elements = (0..n)
        .map(|i| {
            Element::PlanarBeam(PlanarBeam {
                id: i + 1,
                nodes: [i as u64 + 1, i as u64 + 2],
                properties: props(),
            })
        })
        .collect();
    Model::new(nodes, elements, BTreeMap::new(), vec![], None).unwrap()
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
    Model::new(nodes, elements, BTreeMap::new(), vec![], None).unwrap()
}

fn uz(nodes: &[u64]) -> Vec<Dof> {
    nodes.iter().map(|&n| Dof::new(n, DofKind::Uz)).collect()
}

fn setup(model: &Model) -> (SystemMatrices, RigidModes) {
    let sub = Substructure::from_model(model).unwrap();
    let rigid = free_body_rigid_modes(&sub).unwrap();
    (sub.matrices, rigid)
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
        let (s, rigid) = setup(&model);
        let map = model.dof_map();
        let h = interface_equations(&sub(&model), &interface).unwrap();
        let loads = unit_loads(map.len(), &h);
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
    let model = planar_beam(20);
    let (s, rigid) = setup(&model);
    let map = model.dof_map();
    let h = interface_equations(&sub(&model), &uz(&[1, 21, 7, 15])).unwrap();
    let loads = unit_loads(map.len(), &h);
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
    let model = planar_beam(20);
    let (s, rigid) = setup(&model);
    let map = model.dof_map();
    let h = interface_equations(&sub(&model), &uz(&[1, 21, 7, 15])).unwrap();
    let loads = unit_loads(map.len(), &h);
    let support = statically_determinate_support(&rigid, &[0, 1]);
    let t = inertia_relief_attachment_modes(&s.stiffness, &s.mass, &rigid, &loads, &support, map)
        .unwrap();
    let phi = eigenmodes(&s.stiffness, &s.mass, 5)
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
    let model = planar_beam(20);
    let (s, rigid) = setup(&model);
    let map = model.dof_map();
    let h = interface_equations(&sub(&model), &uz(&[1, 21, 7, 15])).unwrap();
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
    use flexbody_linalg::shift_invert::ShiftedPencil;
    use flexbody_linalg::sparse::add_scaled;
    let model = l_frame();
    let (s, rigid) = setup(&model);
    let map = model.dof_map();
    let nodes = [1u64, 5, 9];
    let dofs: Vec<Dof> = nodes
        .iter()
        .flat_map(|&n| DofKind::ALL.map(|k| Dof::new(n, k)))
        .collect();
    let h = interface_equations(&sub(&model), &dofs).unwrap();
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
    let pencil = ShiftedPencil::analyze(&supported, &s.mass, Ordering::Auto).unwrap();
    let factor = pencil.factorize(0.0).unwrap();
    let interior: Vec<usize> = (0..map.len()).filter(|i| !h.contains(i)).collect();
    let psi = constraint_modes_by_flexibility(&pencil, &factor, &h, &interior)
        .expect("the refinements reach round-off");
    let want = constraint_modes(&s.stiffness, &h, map, &rigid).unwrap();
    let err = max_abs((&psi - &want).as_ref()) / max_abs(want.as_ref());
    assert!(err < 1e-12, "{err:e}");
}

#[test]
fn an_interface_that_leaves_a_mechanism_names_the_free_dofs() {
    let model = planar_beam(20);
    let err = reduce(
        &sub(&model),
        &Reduction::new(Method::CraigBampton, 1, uz(&[11])),
    )
    .unwrap_err();
    match &err {
        ReduceError::Mechanism { interface, free } => {
            assert_eq!(interface, &uz(&[11]));
            // Pitch about node 11 moves the beam ends most.
            assert!(
                free[..2].contains(&Dof::new(1, DofKind::Uz))
                    && free[..2].contains(&Dof::new(21, DofKind::Uz)),
                "{free:?}"
            );
        }
        other => panic!("expected a mechanism, got {other}"),
    }
    assert!(err.to_string().contains("node 1 uz"), "{err}");
}

/// Two planar beams of 4 elements (nodes 1-5 and 101-105) that share no
/// node: 4 zero frequencies where a planar body has 2 rigid-body motions.
fn two_unconnected_beams() -> Model {
    let one = planar_beam(4);
    let mut nodes = one.nodes().to_vec();
    let mut elements = one.elements().to_vec();
    for n in one.nodes() {
        nodes.push(Node {
            id: n.id + 100,
            coords: [n.coords[0] + 3.0, 0.0, 0.0],
        });
    }
    for (i, e) in one.elements().iter().enumerate() {
        if let Element::PlanarBeam(b) = e {
            elements.push(Element::PlanarBeam(PlanarBeam {
                id: 100 + i,
                nodes: [b.nodes[0] + 100, b.nodes[1] + 100],
                properties: b.properties.clone(),
            }));
        }
    }
    Model::new(nodes, elements, BTreeMap::new(), vec![], None).unwrap()
}

#[test]
fn two_unconnected_beams_are_a_mechanism_of_the_free_body() {
    let err = reduce(
        &sub(&two_unconnected_beams()),
        &Reduction::new(Method::Free, 6, vec![]),
    )
    .unwrap_err();
    assert!(
        matches!(err, ReduceError::FreeMechanism { rigid: 2, .. }),
        "{err}"
    );
}

#[test]
fn an_interface_that_holds_the_rigid_motions_names_the_bodys_own_mechanism() {
    // Node 1 and 5 hold heave and pitch of the whole (eq. 12-13), but the
    // second beam is free: K_NN is singular there, and another method is
    // no way out (free-residual counts 4 zero modes).
    let model = two_unconnected_beams();
    for method in [Method::CraigBampton, Method::Guyan, Method::ElasticResidual] {
        let mut spec = Reduction::new(
            method,
            if method == Method::Guyan { 0 } else { 2 },
            uz(&[1, 5]),
        );
        spec.springs = [1, 5]
            .map(|node| crate::GroundSpring {
                node,
                direction: [0.0, 0.0, 1.0],
                stiffness: 1e6,
            })
            .to_vec();
        let err = reduce(&sub(&model), &spec).unwrap_err();
        match &err {
            ReduceError::BodyMechanism {
                interface,
                dof,
                rigid,
            } => {
                assert_eq!(interface, &uz(&[1, 5]), "{method}");
                assert!((101..=105).contains(&dof.node), "{method}: {dof}");
                assert_eq!(*rigid, 2);
            }
            other => panic!("{method}: expected the body's mechanism, got {other}"),
        }
        let text = err.to_string();
        assert!(text.contains("hold all 2 rigid-body motions"), "{text}");
        assert!(!text.contains("free-residual"), "{text}");
    }
    let err = reduce(
        &sub(&model),
        &Reduction::new(Method::FreeResidual, 2, uz(&[1, 5])),
    )
    .unwrap_err();
    assert!(
        matches!(err, ReduceError::FreeMechanism { zero: 4, rigid: 2 }),
        "{err}"
    );
}

#[test]
fn a_body_of_its_rigid_modes_alone_has_zero_frequencies() {
    // `free` with as many modes as rigid-body motions: K_red is round-off
    // with negative eigenvalues, M_red the body's mass and inertia.
    let model = l_frame();
    let s = sub(&model);
    let body = reduce(&s, &Reduction::new(Method::Free, 6, vec![])).unwrap();
    let f = body.frequencies_hz().unwrap();
    assert_eq!(f.len(), 6);
    let elastic = reduce(&s, &Reduction::new(Method::Free, 7, vec![])).unwrap();
    let first = elastic.frequencies_hz().unwrap()[6];
    assert!(f.iter().all(|x| *x < 1e-4 * first), "{f:?} against {first}");
}

#[test]
fn a_long_stiff_beam_is_no_mechanism() {
    // 2100 planar beam elements of 1.2 mm under a 0.2 m section: the
    // stiffness spans 13 decades, and the two rigid-body zeros come out at
    // about 30 and 70 (1/s^2) against a first elastic eigenvalue of 2.45e6.
    // Both free methods keep it, at the free-free Euler-Bernoulli beam's
    // first frequency (beta L = 4.730041), to the round-off this
    // conditioning allows.
    let model = planar_beam(2100);
    let p = props();
    let (ei, rho_a) = (
        p.material.youngs_modulus * p.section.iy,
        p.material.density * p.section.area,
    );
    let beta_l: f64 = 4.730_040_744_862_704;
    let exact =
        beta_l.powi(2) / (2.0 * std::f64::consts::PI * 2.5_f64.powi(2)) * (ei / rho_a).sqrt();
    let s = sub(&model);
    for method in [Method::Free, Method::FreeResidual] {
        let interface = vec![Dof::new(1, DofKind::Uz), Dof::new(2101, DofKind::Uz)];
        let modes = if method == Method::Free { 4 } else { 2 };
        let body = reduce(&s, &Reduction::new(method, modes, interface)).unwrap();
        let f = body.frequencies_hz().unwrap();
        // Rigid: lambda below 1e-4 of the first elastic one.
        assert!(f[1] < 1e-2 * exact, "{method:?}: {f:?}");
        assert!(
            (f[2] - exact).abs() < 1e-5 * exact,
            "{method:?}: {} vs {exact}",
            f[2]
        );
    }
}

#[test]
fn reduced_matrices_are_symmetric_and_orthonormalisation_keeps_the_spectrum() {
    let model = l_frame();
    let s = assemble(&model).unwrap();
    let interface = vec![
        Dof::new(1, DofKind::Uz),
        Dof::new(1, DofKind::Ux),
        Dof::new(9, DofKind::Uz),
        Dof::new(5, DofKind::Uy),
    ];
    for method in Method::ALL {
        let modes = match method {
            Method::Free => 10,
            Method::Guyan => 0,
            _ => 3,
        };
        let mut spec = Reduction::new(method, modes, interface.clone());
        spec.springs = interface
            .iter()
            .map(|d| crate::GroundSpring {
                node: d.node,
                direction: match d.kind {
                    DofKind::Ux => [1.0, 0.0, 0.0],
                    DofKind::Uy => [0.0, 1.0, 0.0],
                    _ => [0.0, 0.0, 1.0],
                },
                stiffness: 1e6,
            })
            .collect();
        if method == Method::CraigBampton
            || method == Method::Guyan
            || method == Method::ElasticResidual
        {
            // Four translations do not hold a 3D frame: a mechanism.
            assert!(
                matches!(
                    reduce(&sub(&model), &spec),
                    Err(ReduceError::Mechanism { .. })
                ),
                "{method}"
            );
            continue;
        }
        let body = reduce(&sub(&model), &spec).unwrap();
        for m in [&body.mass, &body.stiffness] {
            assert_eq!(max_abs((m - m.transpose()).as_ref()), 0.0);
        }
        // The free (not supported) K was reduced.
        let k = project(&s.stiffness, body.basis.as_ref());
        assert_eq!(max_abs((&k - &body.stiffness).as_ref()), 0.0);
        let o = body.orthonormalized().unwrap();
        assert!(identity_error(&o.mass) < 1e-10);
        let (f1, f2) = (body.frequencies_hz().unwrap(), o.frequencies_hz().unwrap());
        for (a, b) in f1.iter().zip(&f2).skip(6) {
            assert!((a - b).abs() < 1e-9 * a, "{a} vs {b}");
        }
    }
}

#[test]
fn free_residual_frequencies_bound_the_full_model_from_above() {
    // Rayleigh-Ritz: every reduced frequency is an upper bound of the full one.
    let model = planar_beam(20);
    let s = assemble(&model).unwrap();
    let body = reduce(
        &sub(&model),
        &Reduction::new(Method::FreeResidual, 2, uz(&[1, 21, 7, 15])),
    )
    .unwrap();
    let full = eigenmodes(&s.stiffness, &s.mass, body.r())
        .unwrap()
        .frequencies_hz();
    let red = body.frequencies_hz().unwrap();
    for (f, r) in full.iter().zip(&red).skip(2) {
        assert!(*r >= f * (1.0 - 1e-12), "{r} < {f}");
    }
    // The kept eigenmodes are reproduced exactly.
    for k in 2..4 {
        assert!((red[k] - full[k]).abs() < 1e-9 * full[k]);
    }
}

#[test]
fn a_basis_as_large_as_the_model_is_exact_and_a_larger_one_refused() {
    // The planar beam of 4 elements: 10 DOFs, 2 rigid-body modes, the
    // interface uz at both ends. Free-residual's 2 rigid, 2 residual and
    // 6 eigenmodes, and Craig-Bampton's 2 constraint and 8 eigenmodes,
    // span the whole space: the reduced frequencies are the full model's.
    // One eigenmode more would make the basis dependent.
    let model = planar_beam(4);
    let s = assemble(&model).unwrap();
    let n = s.stiffness.nrows();
    assert_eq!(n, 10);
    let full = eigenmodes(&s.stiffness, &s.mass, n)
        .unwrap()
        .frequencies_hz();
    for (method, others) in [(Method::FreeResidual, 4), (Method::CraigBampton, 2)] {
        let spec = |modes| Reduction::new(method, modes, uz(&[1, 5]));
        let body = reduce(&sub(&model), &spec(n - others)).unwrap();
        assert_eq!(body.r(), n);
        let red = body.frequencies_hz().unwrap();
        for (r, f) in red.iter().zip(&full).skip(2) {
            assert!((r - f).abs() < 1e-9 * f, "{method:?}: {r} vs {f}");
        }
        let err = reduce(&sub(&model), &spec(n - others + 1)).unwrap_err();
        assert!(
            matches!(
                err,
                ReduceError::BasisBeyondModel { modes, others: o, dofs: 10, .. }
                    if modes == n - others + 1 && o == others
            ),
            "{err}"
        );
        let text = err.to_string();
        assert!(
            text.contains(&format!("at most {} eigenmodes", n - others)),
            "{text}"
        );
    }
    // A band takes all 8 elastic modes: free-residual's 12 columns are
    // refused once the band's modes are known.
    let mut band = Reduction::new(Method::FreeResidual, 0, uz(&[1, 5]));
    band.max_frequency_hz = Some(1e9);
    let err = reduce(&sub(&model), &band).unwrap_err();
    assert!(
        matches!(
            err,
            ReduceError::BasisBeyondModel {
                modes: 8,
                others: 4,
                dofs: 10,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn matrices_without_geometry_reduce_to_the_same_body() {
    // Rigid-body modes from the null space of K instead of eq. 12: the same
    // span, so the same reduced frequencies.
    let model = planar_beam(20);
    let with_mesh = sub(&model);
    let bare = Substructure::from_matrices(
        with_mesh.dof_map.clone(),
        with_mesh.matrices.clone(),
        Default::default(),
    );
    assert_eq!(free_body_rigid_modes(&bare).unwrap().count(), 2);
    let spec = Reduction::new(Method::FreeResidual, 2, uz(&[1, 21, 7, 15]));
    let a = reduce(&with_mesh, &spec).unwrap().frequencies_hz().unwrap();
    let b = reduce(&bare, &spec).unwrap().frequencies_hz().unwrap();
    assert_eq!(a.len(), 8);
    for (x, y) in a.iter().zip(&b).skip(2) {
        assert!((x - y).abs() < 1e-8 * x, "{x} vs {y}");
    }
    // A supported model read as bare matrices has no rigid-body modes.
    let fixed = Model::new(
        model.nodes().to_vec(),
        model.elements().to_vec(),
        BTreeMap::new(),
        vec![Dof::new(1, DofKind::Uz), Dof::new(1, DofKind::Ry)],
        None,
    )
    .unwrap();
    let s = sub(&fixed);
    let bare =
        Substructure::from_matrices(s.dof_map.clone(), s.matrices.clone(), Default::default());
    assert_eq!(free_body_rigid_modes(&bare).unwrap().count(), 0);
}

#[test]
fn modal_damping_of_residual_modes_at_close_interface_nodes() {
    // Five interface DOFs, four of them within 17 mm at one end of the
    // 2100-element beam: their residual inertia-relief modes are nearly
    // alike, with masses 1e-17 of the beam's and eigenvalues up to 7e13
    // (1/s^2), 7 decades above the first elastic one. One combination
    // has a mass at round-off: it has no mode and stays undamped, every
    // other mode gets its ratio.
    let model = planar_beam(2100);
    let interface = uz(&[1, 2101, 7, 15, 11]);
    let body = reduce(
        &sub(&model),
        &Reduction::new(Method::FreeResidual, 1, interface),
    )
    .unwrap();
    assert_eq!(body.r(), 8);
    let pairs =
        flexbody_linalg::eigen::generalized_symmetric(body.stiffness.as_ref(), body.mass.as_ref())
            .unwrap();
    assert_eq!(pairs.values.len(), 7, "{:?}", pairs.values);
    // measured 7e13 (1/s^2)
    assert!(pairs.values[6] > 1e13, "{:?}", pairs.values);
    // Against independent values: the first elastic eigenvalue of a
    // free-free Euler-Bernoulli beam, (4.7300 / L)^4 EI / (rho A) (Blevins,
    // table 8-1; 2.45e6 1/s^2), lies 7 decades below (measured 2.9e7
    // times); and no Ritz value exceeds the largest eigenvalue of a single
    // element, a bound of every eigenvalue of the assembled pencil (Irons
    // and Treharne's element eigenvalue theorem).
    let p = props();
    let ei_rho_a = p.material.youngs_modulus * p.section.iy / (p.material.density * p.section.area);
    let first = (4.7300_f64 / 2.5).powi(4) * ei_rho_a;
    assert!(
        // measured 3.7e-5 (2100 elements, beta L to 5 digits)
        (pairs.values[2] - first).abs() < 1e-4 * first,
        "first elastic {} vs {first}",
        pairs.values[2]
    );
    assert!(pairs.values[6] > 1e7 * first, "{:?}", pairs.values);
    let element = Model::new(
        model.nodes()[..2].to_vec(),
        model.elements()[..1].to_vec(),
        BTreeMap::new(),
        vec![],
        None,
    )
    .unwrap();
    let e = sub(&element);
    let bound = flexbody_linalg::eigen::generalized_symmetric(
        e.matrices.stiffness.to_dense().as_ref(),
        e.matrices.mass.to_dense().as_ref(),
    )
    .unwrap()
    .values
    .into_iter()
    .fold(0.0_f64, f64::max);
    assert!(pairs.values[6] < bound, "{} vs {bound}", pairs.values[6]);
    let zeta = 0.02;
    let damped = body.with_modal_damping(&[zeta]).unwrap();
    let x = &pairs.vectors;
    let modal = x.transpose() * damped.damping.as_ref().unwrap() * x;
    for (i, l) in pairs.values.iter().enumerate() {
        let want = 2.0 * zeta * l.max(0.0).sqrt();
        assert!(
            (modal[(i, i)] - want).abs() < 1e-3 * want + 1e-12,
            "mode {i}: {} vs {want}",
            modal[(i, i)]
        );
    }
    // Per-mode ratios and an orthonormal basis need a mode for every
    // coordinate.
    let unresolved = |e: LinalgError| {
        matches!(
            e,
            LinalgError::MasslessDirections {
                modes: 7,
                coordinates: 8
            }
        )
    };
    assert!(unresolved(body.with_modal_damping(&[zeta; 8]).unwrap_err()));
    assert!(unresolved(body.orthonormalized().unwrap_err()));
}
