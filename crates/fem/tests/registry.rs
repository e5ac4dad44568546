//! The element registry: one element of every registered type, built
//! through the registry alone ([`EveryElementType`]), assembled in one
//! model, and checked for what every element type promises: symmetric
//! matrices, no strain under a rigid translation, the assembled mass the
//! sum of the elements' masses, recovery that answers as the element says
//! it does, and a VTK cell over the nodes of every solid.

use faer::Mat;
use flexbody_fem::element::{element_types, ElementType, SectionKind};
use flexbody_fem::mesh::{sample_section, EveryElementType};
use flexbody_fem::{assemble, Dof, DofKind, Element, Model};
use std::collections::HashSet;

fn every_type() -> (EveryElementType, Model) {
    let every = EveryElementType::sample().unwrap();
    let elements = every.elements.iter().map(|(_, e)| e.clone()).collect();
    let model = Model::of(every.nodes.clone(), elements).build().unwrap();
    (every, model)
}

/// The name of an element's variant; the match lists every variant, so
/// that a new one must be added here and to the registry check below.
fn variant(e: &Element) -> &'static str {
    match e {
        Element::PlanarBeam(_) => "PlanarBeam",
        Element::Beam(_) => "Beam",
        Element::QuadraticBeam(_) => "QuadraticBeam",
        Element::PointMass(_) => "PointMass",
        Element::Spring(_) => "Spring",
        Element::AxialSpring(_) => "AxialSpring",
        Element::Solid(_) => "Solid",
        Element::Shell(_) => "Shell",
        Element::Dashpot(_) => "Dashpot",
        Element::AxialDashpot(_) => "AxialDashpot",
    }
}

/// Element values of `dofs` for a unit translation along `kind`.
fn translation(dofs: &[Dof], kind: DofKind) -> Vec<f64> {
    dofs.iter().map(|d| (d.kind == kind) as u8 as f64).collect()
}

fn quadratic_form(a: &Mat<f64>, x: &[f64]) -> f64 {
    (0..a.nrows())
        .map(|i| (0..a.ncols()).map(|j| x[i] * a[(i, j)] * x[j]).sum::<f64>())
        .sum()
}

fn max_abs(a: &Mat<f64>) -> f64 {
    (0..a.nrows())
        .flat_map(|i| (0..a.ncols()).map(move |j| (i, j)))
        .fold(0.0_f64, |m, (i, j)| m.max(a[(i, j)].abs()))
}

#[test]
fn the_registry_names_each_type_once_and_finds_it_by_name() {
    let mut seen = HashSet::new();
    for t in element_types() {
        assert!(seen.insert(t.name.to_ascii_uppercase()), "{} twice", t.name);
        assert_eq!(t.name, t.name.to_ascii_uppercase(), "names are upper case");
        assert_eq!(t.reference_nodes.len(), t.nodes, "{}", t.name);
        let found = ElementType::find(&t.name.to_ascii_lowercase()).unwrap();
        assert_eq!(found.name, t.name);
    }
    // Aliases are found by `resolve` only.
    assert!(ElementType::find("C3D8RH").is_none());
}

#[test]
fn every_element_variant_is_built_through_the_registry() {
    let (every, _) = every_type();
    let built: HashSet<&str> = every.elements.iter().map(|(_, e)| variant(e)).collect();
    // Planar beams are read from model files only; decks have no name for
    // them.
    let expected: HashSet<&str> = [
        "Beam",
        "QuadraticBeam",
        "PointMass",
        "Spring",
        "AxialSpring",
        "Solid",
        "Shell",
        "Dashpot",
        "AxialDashpot",
    ]
    .into();
    assert_eq!(built, expected);
    for (i, (t, e)) in every.elements.iter().enumerate() {
        assert_eq!(e.id(), i + 1, "{}", t.name);
        assert_eq!(e.nodes().len(), t.nodes, "{}", t.name);
    }
}

#[test]
fn a_section_of_another_kind_is_an_error_naming_the_element() {
    for t in element_types() {
        let nodes: Vec<u64> = (1..=t.nodes as u64).collect();
        let other = match t.section {
            SectionKind::Mass => sample_section(SectionKind::Solid),
            _ => sample_section(SectionKind::Mass),
        };
        let err = (t.build)(7, &nodes, &other).unwrap_err().to_string();
        assert!(err.contains("element 7") && err.contains(t.name), "{err}");
    }
}

#[test]
fn every_element_type_has_symmetric_matrices_and_no_strain_under_a_translation() {
    let (every, model) = every_type();
    for (t, e) in &every.elements {
        e.validate(&model).unwrap();
        let em = e.matrices(&model).unwrap();
        let n = em.dofs.len();
        assert!(n > 0, "{}", t.name);
        assert_eq!(em.damping.is_some(), e.has_damping(), "{}", t.name);
        for m in [&em.stiffness, &em.mass].into_iter().chain(&em.damping) {
            assert_eq!((m.nrows(), m.ncols()), (n, n), "{}", t.name);
            let scale = max_abs(m).max(f64::MIN_POSITIVE);
            let asymmetry = max_abs(&(m - m.transpose()));
            assert!(asymmetry <= 1e-14 * scale, "{}: {asymmetry:e}", t.name);
        }
        // An element over two or more nodes is strained by no rigid
        // translation; one over a single node is held to ground or carries
        // no stiffness.
        if e.nodes().len() < 2 {
            continue;
        }
        let scale = max_abs(&em.stiffness);
        for kind in [DofKind::Ux, DofKind::Uy, DofKind::Uz] {
            let u = translation(&em.dofs, kind);
            for i in 0..n {
                let f: f64 = (0..n).map(|j| em.stiffness[(i, j)] * u[j]).sum();
                assert!(f.abs() <= 1e-9 * scale, "{} {kind:?}: {f:e}", t.name);
            }
        }
    }
}

#[test]
fn the_assembled_mass_is_the_sum_of_the_element_masses() {
    let (every, model) = every_type();
    let m = assemble(&model).unwrap().mass.to_dense();
    for kind in [DofKind::Ux, DofKind::Uy, DofKind::Uz] {
        let t = translation(model.dof_map().dofs(), kind);
        let assembled = quadratic_form(&m, &t);
        let mut sum = 0.0;
        for (name, e) in every.elements.iter().map(|(t, e)| (t.name, e)) {
            let em = e.matrices(&model).unwrap();
            let own = quadratic_form(&em.mass, &translation(&em.dofs, kind));
            if matches!(name, "MASS") {
                assert_eq!(own, 12.5, "the point mass along {kind:?}");
            }
            sum += own;
        }
        assert!(sum > 0.0);
        assert!(
            (assembled - sum).abs() <= 1e-12 * sum,
            "{kind:?}: assembled {assembled}, elements {sum}"
        );
    }
}

#[test]
fn recovery_answers_as_each_element_says_and_a_translation_gives_nothing() {
    let (every, model) = every_type();
    for (t, e) in &every.elements {
        let dofs = e.dofs();
        let u = translation(&dofs, DofKind::Uz);
        let zero = vec![0.0; dofs.len()];
        let forces = e.section_forces(&model, &u, &zero).unwrap();
        assert_eq!(forces.is_some(), e.has_section_forces(), "{}", t.name);
        if let Some(f) = forces {
            for v in f.start.iter().chain(&f.end) {
                assert!(v.abs() < 1e-6, "{}: {f:?}", t.name);
            }
        }
        let stresses = e.stresses(&model, &u, 1).unwrap();
        assert_eq!(stresses.is_some(), e.has_stresses(), "{}", t.name);
        if let Some(s) = stresses {
            let points = e.nodes().len() * e.stress_layers().len();
            assert_eq!(s.len(), points, "{}", t.name);
            for v in s.iter().flatten() {
                assert!(v.abs() < 1e-3, "{}: {v:e} Pa", t.name);
            }
        }
    }
}

#[test]
fn every_solid_is_a_vtk_cell_over_all_its_nodes() {
    let (every, _) = every_type();
    for (t, e) in &every.elements {
        let Some(cell) = e.vtk_cell() else {
            assert_ne!(t.section, SectionKind::Solid, "{} has no cell", t.name);
            continue;
        };
        let n = e.nodes().len();
        let distinct: HashSet<usize> = cell.order.iter().copied().collect();
        assert_eq!(distinct.len(), cell.order.len(), "{}", t.name);
        assert!(cell.order.iter().all(|&a| a < n), "{}", t.name);
        if t.section == SectionKind::Solid {
            assert_eq!(cell.order.len(), n, "{}", t.name);
        }
    }
}
