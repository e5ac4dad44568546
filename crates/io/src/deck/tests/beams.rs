//! B31 beams and their `*BEAM SECTION`s.

use super::*;

#[test]
fn b31_beam_with_a_rect_section() {
    let deck = parse(BEAM).unwrap();
    let expected = SectionShape::Rect {
        width: 0.04,
        height: 0.06,
    }
    .constants()
    .unwrap();
    for e in deck.model.elements() {
        let Element::Beam(b) = e else {
            panic!("not a beam: {e:?}")
        };
        assert_eq!(b.properties.section, expected);
        assert_eq!(b.properties.theory, BeamTheory::Timoshenko);
        assert!(b.properties.rotary_inertia);
        assert_eq!(b.orientation, [0.0, 1.0, 0.0]);
        assert_eq!(b.properties.material.youngs_modulus, 2.1e11);
    }
    // a = 0.04 along local y (n1), b = 0.06 along local z.
    assert!((expected.area - 0.0024).abs() < 1e-15);
    assert!((expected.iy - 0.04 * 0.06f64.powi(3) / 12.0).abs() < 1e-18);
    assert!((expected.iz - 0.06 * 0.04f64.powi(3) / 12.0).abs() < 1e-18);
    assert_eq!(deck.model.fixed_dofs().count(), 6);
    assert_eq!(deck.model.dof_map().len(), 12);
    assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
}

#[test]
fn b32_beams_straight_and_curved_with_their_middle_node_second() {
    // Two elements: straight, then a quarter arc of radius 1 about
    // (1, 0, 1), in the x-z plane (local y, the orientation, normal to it).
    let text = BEAM
        .replace(
            "3, 1.0, 0, 0\n",
            "3, 1.0, 0, 0\n4, 1.7071067811865475, 0, 0.2928932188134524\n5, 2.0, 0, 1.0\n",
        )
        .replace("TYPE=B31", "TYPE=B32")
        .replace("1, 1, 2\n2, 2, 3\n", "1, 1, 2, 3\n2, 3, 4, 5\n");
    let deck = parse(&text).unwrap();
    let elements = deck.model.elements();
    assert_eq!(elements.len(), 2);
    for (e, nodes) in elements.iter().zip([[1, 2, 3], [3, 4, 5]]) {
        let Element::QuadraticBeam(b) = e else {
            panic!("not a B32: {e:?}")
        };
        assert_eq!(b.nodes, nodes);
        assert_eq!(b.orientation, [0.0, 1.0, 0.0]);
    }
    // Five nodes of 6 DOFs, node 1 clamped.
    assert_eq!(deck.model.dof_map().len(), 24);
    assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
    // A B32 line with two nodes names the element and the count.
    let short = text.replace("1, 1, 2, 3\n", "1, 1, 3\n");
    assert_error(&short, "1, 1, 3", &["element 1 has 2 nodes", "B32 needs 3"]);
}

fn beam_with_section(section: &str, dims: &str) -> String {
    BEAM.replace(
        "SECTION=RECT\n0.04, 0.06\n0., 1., 0.\n",
        &format!("SECTION={section}\n{dims}\n"),
    )
}

#[test]
fn beam_sections_circ_pipe_box_and_the_default_n1() {
    let cases = [
        ("CIRC", "0.02", SectionShape::Circ { radius: 0.02 }),
        (
            "PIPE",
            "0.05, 0.004",
            SectionShape::Pipe {
                radius: 0.05,
                wall: 0.004,
            },
        ),
        (
            "BOX",
            "0.24, 0.20, 0.012, 0.012, 0.012, 0.012",
            SectionShape::Box {
                width: 0.24,
                height: 0.20,
                wall: 0.012,
            },
        ),
    ];
    for (name, dims, shape) in cases {
        let deck = parse(&beam_with_section(name, dims)).unwrap();
        let Element::Beam(b) = &deck.model.elements()[0] else {
            panic!("not a beam")
        };
        assert_eq!(b.properties.section, shape.constants().unwrap(), "{name}");
        assert_eq!(b.orientation, [0.0, 0.0, -1.0], "{name}");
    }
}

#[test]
fn beam_section_errors() {
    let text = beam_with_section("BOX", "0.24, 0.20, 0.012, 0.01, 0.012, 0.012");
    assert_error(&text, "0.24, 0.20", &["BOX", "equal walls"]);
    let text = beam_with_section("CIRC", "0.02, 0.03");
    assert_error(&text, "0.02, 0.03", &["elliptical"]);
    let text = beam_with_section("HEX", "0.02, 0.03");
    assert_error(&text, "*BEAM SECTION", &["SECTION=HEX", "not supported"]);
    let text = beam_with_section("RECT", "0.04, -0.06");
    assert_error(&text, "0.04, -0.06", &["rect height"]);
    // The default n1 (0, 0, -1) is parallel to a beam along z.
    let text = beam_with_section("CIRC", "0.02")
        .replace("2, 0.5, 0, 0", "2, 0, 0, 0.5")
        .replace("3, 1.0, 0, 0", "3, 0, 0, 1.0");
    assert_error(&text, "1, 1, 2", &["element 1", "parallel"]);
}
