//! Damping from decks (dashpots, material `*DAMPING, ALPHA=, BETA=`,
//! `*MODAL DAMPING, RAYLEIGH`) into the damping matrix D: the damped modes
//! of report eq. 21 against the analytic single-DOF oscillator, through the
//! full model and a reduced body; `info` naming the damping; and the decks
//! refused with exit code 2 at their line.

use super::support::{fails_with, reduce_with, run_ok};
use flexbody::input::{load, MatrixFiles};
use flexbody::mbs::{damped_modes, FlexibleBody, System};
use flexbody::reduce::Method;
use std::path::{Path, PathBuf};

/// Mass m (kg) on node 2, a SPRINGA k (N/m) and a DASHPOTA c (N s/m)
/// from node 1 (held) along x; node 2 moves along x only: one DOF.
fn oscillator(m: f64, k: f64, c: f64) -> String {
    format!(
        "*NODE\n1, 0, 0, 0\n2, 0.5, 0, 0\n\
         *ELEMENT, TYPE=SPRINGA, ELSET=SPRING\n1, 1, 2\n*SPRING, ELSET=SPRING\n\n{k}\n\
         *ELEMENT, TYPE=DASHPOTA, ELSET=DAMPER\n2, 1, 2\n*DASHPOT, ELSET=DAMPER\n\n{c}\n\
         *ELEMENT, TYPE=MASS, ELSET=M\n3, 2\n*MASS, ELSET=M\n{m}\n\
         *BOUNDARY\n1, 1, 3\n2, 2, 3\n\
         *STEP\n*FREQUENCY\n1\n*END STEP\n"
    )
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_mass_spring_dashpot_deck_has_the_analytic_damped_eigenvalue() {
    let (m, k, c) = (2.0_f64, 8.0e4_f64, 60.0_f64);
    let omega = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let want = (-zeta * omega, omega * (1.0 - zeta * zeta).sqrt());
    let dir = tempfile::tempdir().unwrap();
    let deck = write(dir.path(), "sdof.inp", &oscillator(m, k, c));
    let component = load(&deck, &MatrixFiles::default()).unwrap();
    let sub = &component.sub;
    assert_eq!(sub.dof_map.len(), 1, "ux of node 2 only");
    let full = System {
        flexible: vec![FlexibleBody::Full {
            dof_map: &sub.dof_map,
            matrices: &sub.matrices,
        }],
        ..Default::default()
    };
    let body = reduce_with(sub, Method::Free, 1, &[]);
    let reduced = System {
        flexible: vec![FlexibleBody::Reduced(&body)],
        ..Default::default()
    };
    for system in [full, reduced] {
        let modes = damped_modes(&system).unwrap();
        assert_eq!(modes.len(), 1, "{modes:?}");
        let (re, im) = modes[0].eigenvalue;
        assert!((re - want.0).abs() < 1e-10 * omega, "{re} vs {}", want.0);
        assert!((im - want.1).abs() < 1e-10 * omega, "{im} vs {}", want.1);
        assert!((modes[0].damping_ratio - zeta).abs() < 1e-10);
    }
    let o = run_ok(&["info", deck.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("damping: 1 dashpots (c 6e1 N s/m)"), "{out}");
}

#[test]
fn modal_rayleigh_damping_gives_the_analytic_damping_ratio() {
    // Rayleigh damping alpha M + beta K of the oscillator (the model's,
    // of *MODAL DAMPING, RAYLEIGH): zeta = alpha / (2 omega) + beta omega / 2.
    let (m, k) = (2.0_f64, 8.0e4_f64);
    let omega = (k / m).sqrt();
    let (alpha, beta) = (4.0, 1.0e-4);
    let zeta = alpha / (2.0 * omega) + beta * omega / 2.0;
    let text = oscillator(m, k, 0.0).replace(
        "*FREQUENCY\n1\n",
        &format!("*FREQUENCY\n1\n*MODAL DAMPING, RAYLEIGH\n1, 1, {alpha}, {beta}\n"),
    );
    let dir = tempfile::tempdir().unwrap();
    let deck = write(dir.path(), "rayleigh.inp", &text);
    let component = load(&deck, &MatrixFiles::default()).unwrap();
    let sub = &component.sub;
    let modes = damped_modes(&System {
        flexible: vec![FlexibleBody::Full {
            dof_map: &sub.dof_map,
            matrices: &sub.matrices,
        }],
        ..Default::default()
    })
    .unwrap();
    assert!((modes[0].damping_ratio - zeta).abs() < 1e-12, "{modes:?}");
    let o = run_ok(&["info", deck.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("damping: Rayleigh alpha 4e0 1/s, beta 1e-4 s (whole model)"),
        "{out}"
    );
}

#[test]
fn damping_decks_flexbody_cannot_hold_exit_2_naming_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let base = oscillator(2.0, 8.0e4, 60.0);
    let with_material = base.clone()
        + "*ELEMENT, TYPE=B31, ELSET=BEAM\n4, 1, 2\n\
           *MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850\n\
           *DAMPING, STRUCTURAL=0.02\n\
           *BEAM SECTION, ELSET=BEAM, MATERIAL=STEEL, SECTION=CIRC\n0.01\n";
    let cases = [
        (
            "structural.inp",
            with_material,
            "*DAMPING, STRUCTURAL=0.02",
            vec!["structural", "ALPHA=", "BETA="],
        ),
        (
            "elset.inp",
            base.replace("*DASHPOT, ELSET=DAMPER", "*DASHPOT, ELSET=DAMPERS"),
            "*DASHPOT, ELSET=DAMPERS",
            vec!["element set 'DAMPERS' is not defined"],
        ),
        (
            "negative.inp",
            base.replace("\n60\n", "\n-60\n"),
            "-60",
            vec!["*DASHPOT: coefficient", "-60"],
        ),
        (
            "ratios.inp",
            base.replace(
                "*FREQUENCY\n1\n",
                "*FREQUENCY\n1\n*MODAL DAMPING\n1, 5, 0.02\n",
            ),
            "*MODAL DAMPING",
            vec!["ratios per mode", "RAYLEIGH"],
        ),
    ];
    for (name, text, line_text, needles) in cases {
        let line = text
            .lines()
            .position(|l| l == line_text)
            .unwrap_or_else(|| panic!("{name}: no line '{line_text}'"))
            + 1;
        let path = write(dir.path(), name, &text);
        let at = format!("{name}:{line}:");
        let mut all = vec![at.as_str()];
        all.extend(needles.iter().copied());
        fails_with(&["info", path.to_str().unwrap()], &all);
    }
}

#[test]
fn a_model_files_damping_replaces_the_decks_modal_rayleigh_and_keeps_its_dashpots() {
    let dir = tempfile::tempdir().unwrap();
    let text = oscillator(2.0, 8.0e4, 60.0).replace(
        "*FREQUENCY\n1\n",
        "*FREQUENCY\n1\n*MODAL DAMPING, RAYLEIGH\n1, 1, 9.0, 0.0\n",
    );
    write(dir.path(), "sdof.inp", &text);
    let model = write(
        dir.path(),
        "model.toml",
        "mesh = \"sdof.inp\"\n\n[damping]\nalpha = 3.0\nbeta = 0.0\n",
    );
    let o = run_ok(&["info", model.to_str().unwrap()]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("damping: Rayleigh alpha 3e0 1/s, beta 0e0 s (whole model); 1 dashpots"),
        "{out}"
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("[damping] replaces the deck's *MODAL DAMPING only"),
        "{err}"
    );
}
