//! Interfaces that leave a mechanism, bodies that are one, and a long stiff
//! beam that is none.

use super::{l_frame, planar_beam, props, sub, uz};
use crate::{reduce, Method, ReduceError, Reduction};
use flexbody_fem::element::PlanarBeam;
use flexbody_fem::{Dof, DofKind, Element, Model, Node};

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
    Model::of(nodes, elements).build().unwrap()
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
