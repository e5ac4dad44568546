//! `flexbody modes --modes N --fmax HZ`: the lowest N modes below HZ, at
//! most N, on the beam (the dense solver) and the solid side beam (the
//! sparse one).

use super::support::{run_ok, solid_side_beam};
use std::path::PathBuf;

/// The rows `(mode, f (Hz))` of `flexbody modes MODEL ARGS..`, after its
/// `DOFs` line and header.
fn rows(model: &std::path::Path, args: &[&str]) -> Vec<(usize, f64)> {
    let mut all = vec!["modes", model.to_str().unwrap()];
    all.extend_from_slice(args);
    let o = run_ok(&all);
    let text = String::from_utf8(o.stdout).unwrap();
    let mut lines = text.lines();
    assert!(lines.next().unwrap().ends_with(" DOFs"), "{text}");
    assert!(lines.next().unwrap().contains("f (Hz)"), "{text}");
    lines
        .map(|l| {
            let w: Vec<&str> = l.split_whitespace().collect();
            assert_eq!(w.len(), 3, "{text}");
            (w[0].parse().unwrap(), w[1].parse().unwrap())
        })
        .collect()
}

#[test]
fn modes_with_a_count_and_a_band_are_the_lowest_of_the_band() {
    // The free side beam: 2 rigid-body modes at 0 Hz, then the free-free
    // Euler-Bernoulli beam's f_n = (beta_n L)^2 / (2 pi L^2)
    // sqrt(EI / rho A), beta L = 4.7300, 7.8532, 10.9956 (Blevins, table
    // 8-1): 249, 687 and 1347 Hz with the box 0.24 x 0.20 m, wall 0.012 m,
    // E = 2.1e11 Pa, rho = 6800 kg/m^3, L = 2.5 m of the example.
    let beam = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam.toml");
    let (b, h, t, l) = (0.24_f64, 0.20_f64, 0.012, 2.5);
    let area = b * h - (b - 2.0 * t) * (h - 2.0 * t);
    let iy = (b * h.powi(3) - (b - 2.0 * t) * (h - 2.0 * t).powi(3)) / 12.0;
    let f1 = 4.7300_f64.powi(2) / (2.0 * std::f64::consts::PI * l * l)
        * (2.1e11 * iy / (6800.0 * area)).sqrt();
    let check = |got: &[(usize, f64)], elastic: usize| {
        assert_eq!(got.len(), 2 + elastic, "{got:?}");
        for (i, (mode, f)) in got.iter().enumerate() {
            assert_eq!(*mode, i + 1);
            if i < 2 {
                assert!(*f < 1e-2, "{got:?}");
            }
        }
        if elastic > 0 {
            assert!((got[2].1 - f1).abs() < 1e-4 * f1, "{got:?} vs {f1}");
        }
    };
    // Four modes below 1000 Hz, the count takes 3; two below 100 Hz, fewer
    // than the count; --modes is --count.
    check(&rows(&beam, &["--modes", "3", "--fmax", "1000"]), 1);
    check(&rows(&beam, &["--fmax", "1000", "--count", "3"]), 1);
    check(&rows(&beam, &["--modes", "3", "--fmax", "100"]), 0);
    check(&rows(&beam, &["--modes", "30", "--fmax", "300"]), 1);
    // Without --modes the band is whole: 4 modes, not a default count's.
    assert_eq!(rows(&beam, &["--fmax", "1000"]).len(), 4);
    assert_eq!(rows(&beam, &["--fmax", "1e7"]).len(), 42);

    // The solid side beam (1668 DOFs, the sparse solver): the lowest 12 cut
    // at 700 Hz, then to 8; and to 20, fewer than lie below 700 Hz.
    let solid = solid_side_beam();
    let lowest = rows(&solid, &["--count", "12"]);
    let below: Vec<f64> = lowest.iter().map(|r| r.1).filter(|f| *f < 700.0).collect();
    assert!(below.len() > 8 && below.len() < 12, "{lowest:?}");
    for count in [8, 20] {
        let got = rows(&solid, &["--modes", &count.to_string(), "--fmax", "700"]);
        assert_eq!(got.len(), count.min(below.len()), "{got:?}");
        for ((mode, f), (i, want)) in got.iter().zip(below.iter().enumerate()) {
            assert_eq!(*mode, i + 1);
            // Six rigid-body modes at round-off, the rest to the printed digits.
            assert!(
                (f - want).abs() <= 1e-2_f64.max(1e-6 * want),
                "{f} vs {want}"
            );
        }
    }
}
