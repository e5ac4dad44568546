//! Damping: dashpots (`*DASHPOT`), material Rayleigh damping (`*DAMPING,
//! ALPHA=, BETA=`) and the model's Rayleigh damping (`*MODAL DAMPING,
//! RAYLEIGH`), into the damping matrix D; and what is refused.

use super::*;
use flexbody_fem::element::{AxialDashpot, Dashpot};
use flexbody_fem::{assemble, Model, Rayleigh};
use flexbody_linalg::Mat;

/// The assembled D of a deck's model, dense.
fn damping_of(deck: &Deck) -> Mat<f64> {
    assemble(&deck.model)
        .unwrap()
        .damping
        .expect("the model has damping")
        .to_dense()
}

/// `sum_e (alpha_e M_e + beta_e K_e)` at the model's equations, by hand
/// from the element matrices, with `rayleigh(e)` each element's values.
fn rayleigh_by_hand(model: &Model, rayleigh: impl Fn(usize) -> Rayleigh) -> Mat<f64> {
    let n = model.dof_map().len();
    let mut d = Mat::<f64>::zeros(n, n);
    for e in model.elements() {
        let r = rayleigh(e.id());
        let em = e.matrices(model).unwrap();
        let eq: Vec<Option<usize>> = em
            .dofs
            .iter()
            .map(|x| model.dof_map().index_of(*x))
            .collect();
        for (a, ia) in eq.iter().enumerate() {
            for (b, ib) in eq.iter().enumerate() {
                if let (Some(i), Some(j)) = (ia, ib) {
                    d[(*i, *j)] += r.alpha * em.mass[(a, b)] + r.beta * em.stiffness[(a, b)];
                }
            }
        }
    }
    d
}

fn max_abs(a: &Mat<f64>) -> f64 {
    flexbody_linalg::sparse::max_abs(a.as_ref())
}

/// The two bricks with the upper one of a second material `ALU`: the
/// material cards of both are `steel` and `alu` (their `*DAMPING` lines).
fn two_materials(steel: &str, alu: &str) -> String {
    BRICKS
        .replace("*ELSET, ELSET=all\nlower, 2\n", "*ELSET, ELSET=upper\n2\n")
        .replace(
            "*DENSITY\n7850.\n*SOLID SECTION, ELSET=ALL, MATERIAL=STEEL\n",
            &format!(
                "*DENSITY\n7850.\n{steel}*MATERIAL, NAME=ALU\n*ELASTIC\n7.0e10, 0.33\n\
                 *DENSITY\n2700.\n{alu}\
                 *SOLID SECTION, ELSET=LOWER, MATERIAL=STEEL\n\
                 *SOLID SECTION, ELSET=UPPER, MATERIAL=ALU\n"
            ),
        )
}

#[test]
fn dashpots_along_a_line_to_ground_and_between_dofs() {
    // DASHPOTA from the beam's tip (1, 0, 0) to a node at (1, 2, 2) that
    // a *BOUNDARY holds: the grounded end of the dashpot.
    let text = BEAM.to_string()
        + "*NODE\n9, 1.0, 2.0, 2.0\n*BOUNDARY\n9, 1, 3\n\
           *ELEMENT, TYPE=DASHPOTA, ELSET=DA\n20, 3, 9\n*DASHPOT, ELSET=DA\n\n1.5e3\n\
           *ELEMENT, TYPE=DASHPOT1, ELSET=D1\n21, 3\n*DASHPOT, ELSET=D1\n6\n40.\n\
           *ELEMENT, TYPE=DASHPOT2, ELSET=D2\n22, 2, 3\n*DASHPOT, ELSET=D2\n2, 2\n700., 0.\n";
    let deck = parse(&text).unwrap();
    let find = |id: usize| deck.model.elements().iter().find(|e| e.id() == id).unwrap();
    assert_eq!(
        find(20),
        &Element::AxialDashpot(AxialDashpot {
            id: 20,
            nodes: [3, 9],
            coefficient: 1.5e3
        })
    );
    assert_eq!(
        find(21),
        &Element::Dashpot(Dashpot {
            id: 21,
            first: Dof::new(3, DofKind::Rz),
            second: None,
            coefficient: 40.0
        })
    );
    assert_eq!(
        find(22),
        &Element::Dashpot(Dashpot {
            id: 22,
            first: Dof::new(2, DofKind::Uy),
            second: Some(Dof::new(3, DofKind::Uy)),
            coefficient: 700.0
        })
    );
    // Dashpots create no DOFs: node 9 has none, the beam's 12 remain.
    assert_eq!(deck.model.dof_map().len(), 12);
    // D = c e e^T at the tip's translations (e = (0, 2, 2)/sqrt 8), the
    // scalar ones on their DOFs; nothing else.
    let d = damping_of(&deck);
    let eq = |n: u64, k: DofKind| deck.model.dof_map().index_of(Dof::new(n, k)).unwrap();
    let e = [0.0, 0.5_f64.sqrt(), 0.5_f64.sqrt()];
    let mut want = Mat::<f64>::zeros(12, 12);
    let t = [DofKind::Ux, DofKind::Uy, DofKind::Uz].map(|k| eq(3, k));
    for i in 0..3 {
        for j in 0..3 {
            want[(t[i], t[j])] += 1.5e3 * e[i] * e[j];
        }
    }
    want[(eq(3, DofKind::Rz), eq(3, DofKind::Rz))] += 40.0;
    let (a, b) = (eq(2, DofKind::Uy), eq(3, DofKind::Uy));
    want[(a, a)] += 700.0;
    want[(b, b)] += 700.0;
    want[(a, b)] -= 700.0;
    want[(b, a)] -= 700.0;
    assert!(max_abs(&(&d - &want)) < 1e-12 * 1.5e3);
}

#[test]
fn one_damped_material_equals_the_models_rayleigh_damping() {
    let (alpha, beta) = (2.5, 3.0e-5);
    let material = BRICKS.replace(
        "*DENSITY\n7850.\n",
        &format!("*DENSITY\n7850.\n*DAMPING, ALPHA={alpha}, BETA={beta}\n"),
    );
    let global = BRICKS.replace(
        "*FREQUENCY\n10\n",
        &format!("*FREQUENCY\n10\n*MODAL DAMPING, RAYLEIGH\n1, 10, {alpha}, {beta}\n"),
    );
    let by_material = parse(&material).unwrap();
    let by_model = parse(&global).unwrap();
    assert_eq!(by_material.model.rayleigh(), None);
    assert_eq!(by_model.model.rayleigh(), Some(Rayleigh { alpha, beta }));
    let (a, b) = (damping_of(&by_material), damping_of(&by_model));
    assert!(max_abs(&(&a - &b)) <= 1e-12 * max_abs(&b));
    assert!(
        !by_material.warnings.iter().any(|w| w.contains("DAMPING")),
        "{:?}",
        by_material.warnings
    );
}

#[test]
fn two_damped_materials_give_each_element_its_own_rayleigh_damping() {
    let steel = Rayleigh {
        alpha: 1.0,
        beta: 2.0e-5,
    };
    let alu = Rayleigh {
        alpha: 4.0,
        beta: 0.0,
    };
    let text = two_materials(
        "*DAMPING, ALPHA=1.0, BETA=2.0e-5\n",
        "*DAMPING, ALPHA=4.0\n",
    );
    let deck = parse(&text).unwrap();
    let d = damping_of(&deck);
    let want = rayleigh_by_hand(&deck.model, |e| if e == 1 { steel } else { alu });
    assert!(max_abs(&(&d - &want)) <= 1e-13 * max_abs(&want));
    // CalculiX would apply one *DAMPING to all: the deck is told.
    assert!(
        deck.warnings
            .iter()
            .any(|w| w.contains("per material") && w.contains("CalculiX")),
        "{:?}",
        deck.warnings
    );
    // One damped, one not: the undamped element adds nothing.
    let deck = parse(&two_materials("", "*DAMPING, ALPHA=4.0\n")).unwrap();
    let want = rayleigh_by_hand(
        &deck.model,
        |e| if e == 1 { Rayleigh::default() } else { alu },
    );
    assert!(max_abs(&(&damping_of(&deck) - &want)) <= 1e-13 * max_abs(&want));
    let about_damping = deck.warnings.iter().filter(|w| w.contains("*DAMPING"));
    assert_eq!(about_damping.count(), 1, "{:?}", deck.warnings);
}

#[test]
fn damping_that_flexbody_cannot_hold_is_refused_at_its_line() {
    let with_material =
        |card: &str| BRICKS.replace("*DENSITY\n7850.\n", &format!("*DENSITY\n7850.\n{card}"));
    assert_error(
        &with_material("*DAMPING, STRUCTURAL=0.02\n"),
        "*DAMPING, STRUCTURAL=0.02",
        &["structural", "ALPHA", "BETA", "viscous"],
    );
    assert_error(
        &with_material("*DAMPING, ALPHA=-1\n"),
        "*DAMPING, ALPHA=-1",
        &["ALPHA", "-1"],
    );
    assert_error(
        &with_material("*DAMPING\n"),
        "*DAMPING",
        &["neither ALPHA= nor BETA="],
    );
    let in_step =
        |card: &str| BRICKS.replace("*FREQUENCY\n10\n", &format!("*FREQUENCY\n10\n{card}"));
    assert_error(
        &in_step("*MODAL DAMPING\n1, 10, 0.02\n"),
        "*MODAL DAMPING",
        &["ratios per mode", "RAYLEIGH", "modal_damping"],
    );
    assert_error(
        &in_step("*MODAL DAMPING, RAYLEIGH\n0.5, 1e-4\n"),
        "0.5, 1e-4",
        &["first mode, last mode, alpha, beta", "alpha = beta = 0"],
    );
    let both = with_material("*DAMPING, ALPHA=1\n").replace(
        "*FREQUENCY\n10\n",
        "*FREQUENCY\n10\n*MODAL DAMPING, RAYLEIGH\n,,1,0\n",
    );
    assert_error(
        &both,
        "*MODAL DAMPING, RAYLEIGH",
        &["read last", "give one"],
    );
    let twice = in_step("*MODAL DAMPING, RAYLEIGH\n,,1,0\n*MODAL DAMPING, RAYLEIGH\n,,2,0\n");
    let (line, message) = error_of(&twice);
    assert_eq!(line, line_of(&twice, ",,2,0") - 1, "{message}");
    assert!(message.contains("second *MODAL DAMPING"), "{message}");
}

#[test]
fn dashpot_errors_name_their_line() {
    let base = BEAM.to_string() + "*ELEMENT, TYPE=DASHPOTA, ELSET=DA\n20, 1, 3\n";
    assert_error(
        &(base.clone() + "*DASHPOT, ELSET=NOPE\n\n1.0\n"),
        "*DASHPOT, ELSET=NOPE",
        &["element set 'NOPE' is not defined"],
    );
    assert_error(
        &(base.clone() + "*DASHPOT, ELSET=DA\n\n-5.0\n"),
        "-5.0",
        &["*DASHPOT: coefficient", "-5"],
    );
    assert_error(
        &(base.clone() + "*DASHPOT, ELSET=DA\n\n5.0, 10.\n"),
        "5.0, 10.",
        &["frequency-dependent"],
    );
    assert_error(
        &(base.clone() + "*DASHPOT, ELSET=DA, NONLINEAR\n\n5.0\n"),
        "*DASHPOT, ELSET=DA, NONLINEAR",
        &["NONLINEAR"],
    );
    // A dashpot on a spring element set, and a spring on a dashpot set.
    assert_error(
        &(base.clone() + "*SPRING, ELSET=DA\n\n5.0\n"),
        "*SPRING, ELSET=DA",
        &["DASHPOTA", "*DASHPOT"],
    );
    // An end on a node nothing gives DOFs and no *BOUNDARY holds.
    let loose = BEAM.to_string()
        + "*NODE\n9, 1.0, 2.0, 2.0\n\
           *ELEMENT, TYPE=DASHPOTA, ELSET=DA\n20, 3, 9\n*DASHPOT, ELSET=DA\n\n1.0\n";
    assert_error(
        &loose,
        "20, 3, 9",
        &["node 9", "*BOUNDARY", "creates no DOFs"],
    );
    // A dashpot on no DOF at all.
    let nowhere = BEAM.to_string()
        + "*NODE\n9, 1.0, 2.0, 2.0\n\
           *ELEMENT, TYPE=DASHPOT1, ELSET=D1\n21, 9\n*DASHPOT, ELSET=D1\n1\n1.0\n";
    assert_error(&nowhere, "21, 9", &["element 21", "creates none"]);
}
