//! Three-node beams (B32) through the deck reader and `flexbody modes`:
//! a cantilever against Timoshenko theory (a fine mesh of B31, which is
//! exact for end loads and converges to it) and against CalculiX 2.20,
//! which expands each beam into a brick (C3D20) and so is no beam element.

use super::support::{calculix_frequencies, our_frequencies, skip_without_peer};

/// A steel cantilever, 1 m along x, 40 mm x 60 mm (the 40 mm side along
/// y), clamped at node 1, of `n` elements of `kind` (B31 or B32); a
/// `*FREQUENCY` step asking for `count` modes.
fn cantilever_deck(kind: &str, n: usize, count: usize) -> String {
    let per = if kind == "B32" { 2 } else { 1 };
    let mut t = String::from("*NODE\n");
    for k in 0..=per * n {
        t += &format!("{}, {:.15e}, 0, 0\n", k + 1, k as f64 / (per * n) as f64);
    }
    t += &format!("*ELEMENT, TYPE={kind}, ELSET=EB\n");
    for e in 0..n {
        let nodes: Vec<String> = (0..=per).map(|j| (per * e + j + 1).to_string()).collect();
        t += &format!("{}, {}\n", e + 1, nodes.join(", "));
    }
    t += &format!(
        "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n\
         *BEAM SECTION, ELSET=EB, MATERIAL=STEEL, SECTION=RECT\n0.04, 0.06\n0., 1., 0.\n\
         *BOUNDARY\n1, 1, 6\n*STEP\n*FREQUENCY\n{count}\n*END STEP\n"
    );
    t
}

#[test]
fn b32_cantilever_against_timoshenko_theory_and_calculix() {
    // Eight modes: bending in both planes, the torsion mode (6th) and the
    // first axial one are among them.
    let count = 8;
    let dir = tempfile::tempdir().unwrap();
    for (name, kind, n) in [("b32", "B32", 10), ("b31_fine", "B31", 400)] {
        std::fs::write(
            dir.path().join(format!("{name}.inp")),
            cantilever_deck(kind, n, count),
        )
        .unwrap();
    }
    let ours = our_frequencies(dir.path(), count, "b32");
    let theory = our_frequencies(dir.path(), count, "b31_fine");
    let apart = |a: &[f64]| -> Vec<f64> {
        a.iter()
            .zip(&theory)
            .map(|(x, t)| (x - t) / t)
            .collect::<Vec<_>>()
    };
    let ours_error = apart(&ours);
    eprintln!("B32, 10 elements, from Timoshenko theory: {ours_error:?}");
    // Measured: within 7.5e-4 in the first seven modes, 2.7e-3 in the
    // eighth (the third bending mode of the weak plane, on 10 elements).
    assert!(
        ours_error.iter().all(|e| e.abs() < 4e-3),
        "{ours:?} vs {theory:?}"
    );
    let Some(ccx) = calculix_frequencies(dir.path(), "b32_ccx", &cantilever_deck("B32", 10, count))
    else {
        skip_without_peer("b32_cantilever_against_calculix", "ccx (CalculiX)");
        return;
    };
    let ccx_error = apart(&ccx[..count]);
    eprintln!("CalculiX's expanded B32, from Timoshenko theory: {ccx_error:?}");
    // CalculiX's bricks are stiffer (measured): bending 0.7 % to 3.6 %
    // above theory, the torsion mode 8.5 % (one brick across the section);
    // flexbody is the nearer to theory in every mode.
    for (k, (c, o)) in ccx_error.iter().zip(&ours_error).enumerate() {
        assert!(
            *c > 0.0 && *c < if k == 5 { 0.09 } else { 0.04 } && o.abs() < c.abs(),
            "mode {}: CalculiX {c:.2e}, flexbody {o:.2e}",
            k + 1
        );
    }
}
