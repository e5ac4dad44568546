//! Point masses and springs.

use super::*;

#[test]
fn mass_and_spring_elements() {
    let text = BEAM.to_string()
        + "*ELEMENT, TYPE=MASS, ELSET=TIP\n10, 3\n*MASS, ELSET=TIP\n12.5\n\
           *ELEMENT, TYPE=SPRING1, ELSET=S1\n11, 3\n*SPRING, ELSET=S1\n3\n1.0e6\n\
           *ELEMENT, TYPE=SPRING2, ELSET=S2\n12, 2, 3\n*SPRING, ELSET=S2\n2, 6\n2.0e6\n\
           *ELEMENT, TYPE=SPRINGA, ELSET=SA\n13, 1, 3\n*SPRING, ELSET=SA\n\n3.0e6\n";
    let deck = parse(&text).unwrap();
    let find = |id: usize| {
        deck.model
            .elements()
            .iter()
            .find(|e| e.id() == id)
            .unwrap()
            .clone()
    };
    assert_eq!(
        find(10),
        Element::PointMass(PointMass {
            id: 10,
            node: 3,
            mass: 12.5,
            inertia: [0.0; 6]
        })
    );
    assert_eq!(
        find(11),
        Element::Spring(Spring {
            id: 11,
            first: Dof::new(3, DofKind::Uz),
            second: None,
            stiffness: 1.0e6
        })
    );
    assert_eq!(
        find(12),
        Element::Spring(Spring {
            id: 12,
            first: Dof::new(2, DofKind::Uy),
            second: Some(Dof::new(3, DofKind::Rz)),
            stiffness: 2.0e6
        })
    );
    assert_eq!(
        find(13),
        Element::AxialSpring(AxialSpring {
            id: 13,
            nodes: [1, 3],
            stiffness: 3.0e6
        })
    );
}

#[test]
fn spring_and_mass_errors() {
    let base = BEAM.to_string() + "*ELEMENT, TYPE=SPRING1, ELSET=S1\n11, 3\n";
    assert_error(
        &(base.clone() + "*SPRING, ELSET=S1\n1.0e6\n"),
        "*SPRING",
        &["SPRING1", "DOF"],
    );
    assert_error(
        &(base.clone() + "*SPRING, ELSET=S1\n7\n1.0e6\n"),
        "7",
        &["DOF 7"],
    );
    assert_error(
        &(base.clone() + "*SPRING, ELSET=S1\n3\n-1.0e6\n"),
        "-1.0e6",
        &["stiffness"],
    );
    assert_error(
        &(base.clone() + "*SPRING, ELSET=S1, NONLINEAR\n3\n1., 0.1\n"),
        "*SPRING",
        &["NONLINEAR"],
    );
    assert_error(&base, "11, 3", &["element 11", "*SPRING"]);
    // *MASS on a spring element.
    assert_error(
        &(base + "*MASS, ELSET=S1\n2.0\n"),
        "*MASS",
        &["element 11", "SPRING1", "*SPRING"],
    );
}
