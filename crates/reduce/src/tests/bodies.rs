//! Reduced bodies of every method: symmetric matrices, frequency bounds,
//! complete bases, matrices without geometry and modal damping.

use super::{identity_error, l_frame, planar_beam, props, sub, uz};
use crate::method::free_body_rigid_modes;
use crate::modes::*;
use crate::{reduce, Method, ReduceError, Reduction};
use flexbody_fem::{assemble, Dof, DofKind, Model, Substructure};
use flexbody_linalg::sparse::{max_abs, project};
use flexbody_linalg::LinalgError;

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
        assert_eq!(max_abs((&k - &body.stiffness).as_ref()), 0.0, "{method}");
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
    let full = eigenmodes(&s.stiffness, &s.mass, Wanted::Lowest(body.r()))
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
    let full = eigenmodes(&s.stiffness, &s.mass, Wanted::Lowest(n))
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
    let fixed = Model::of(model.nodes().to_vec(), model.elements().to_vec())
        .fixed(vec![Dof::new(1, DofKind::Uz), Dof::new(1, DofKind::Ry)])
        .build()
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
    let element = Model::of(model.nodes()[..2].to_vec(), model.elements()[..1].to_vec())
        .build()
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
