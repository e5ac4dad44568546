//! `flexbody modes` on the solid side beam (the sparse solver): counts,
//! frequency bands, and agreement with the dense solver.

use super::support::{
    fails_with, flexbody, reduce_args, run_ok, solid_side_beam, stderr, stdout_json,
};

#[test]
fn many_modes_of_the_solid_converge_to_the_dense_ones() {
    // 200 of the 1668 modes of the solid side beam take the sparse Lanczos
    // solver (12 % of the spectrum, stiffness over 4 decades of theta);
    // 1000 take the dense one. Before converged Ritz pairs were locked the
    // Lanczos run lost and found them again until its step limit; before
    // free-residual chose its solver by the mode count, 1500 modes took
    // minutes there. Before the eigen-decompositions of both solvers were
    // scaled to unit size (faer's divide and conquer is not
    // scale-invariant), the run stalled at a false round-off floor and the
    // two solvers agreed to 1e-8 with residuals up to 5e-7; now 64 sweeps
    // at the first shift give residuals of 2e-8 and agree to 3e-12.
    let model = solid_side_beam();
    let run = |count: &str| -> (Vec<f64>, Vec<f64>) {
        let o = run_ok(&["modes", model.to_str().unwrap(), "--json", "--count", count]);
        let doc = stdout_json(&o);
        let get = |k: &str| serde_json::from_value(doc[k].clone()).unwrap();
        (get("frequencies_hz"), get("residuals"))
    };
    let (sparse, residuals) = run("200");
    let (dense, _) = run("1000");
    assert_eq!(sparse.len(), 200);
    for (a, b) in sparse.iter().zip(&dense).skip(6) {
        assert!((a - b).abs() <= 1e-10 * b, "{a} vs {b}");
    }
    assert!(residuals.iter().all(|r| *r < 1e-7), "{residuals:?}");
    // Free-residual keeps its 200 eigenmodes of the held operator, and 1500
    // take the dense solver.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body.json");
    for modes in ["1500", "200"] {
        run_ok(&reduce_args(
            &model,
            "free-residual",
            modes,
            &out,
            &["--check", "never"],
        ));
    }
    let body: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let reduced: Vec<f64> = serde_json::from_value(body["frequencies_hz"].clone()).unwrap();
    for (a, b) in reduced.iter().zip(&dense).take(206).skip(6) {
        assert!((a - b).abs() <= 1e-8 * b, "{a} vs {b}");
    }
}

/// `flexbody modes MODEL --json EXTRA..`: the frequencies (Hz) and residuals.
fn modes_json(model: &std::path::Path, extra: &[&str]) -> (Vec<f64>, Vec<f64>) {
    let mut args = vec!["modes", model.to_str().unwrap(), "--json"];
    args.extend_from_slice(extra);
    let doc = stdout_json(&run_ok(&args));
    let column = |key: &str| serde_json::from_value::<Vec<f64>>(doc[key].clone()).unwrap();
    (column("frequencies_hz"), column("residuals"))
}

#[test]
fn modes_below_a_frequency_are_the_lowest_ones_up_to_it() {
    // The solid side beam (1668 DOFs, the sparse solver): --fmax 700 Hz
    // gives exactly the modes of --count 12 that lie below 700 Hz.
    let model = solid_side_beam();
    let (lowest, _) = modes_json(&model, &["--count", "12"]);
    let (band, _) = modes_json(&model, &["--fmax", "700"]);
    let below: Vec<f64> = lowest.iter().copied().filter(|f| *f < 700.0).collect();
    assert!(below.len() > 6 && below.len() < 12, "{lowest:?}");
    assert_eq!(band.len(), below.len());
    for (a, b) in band.iter().zip(&below) {
        if *b < 1.0 {
            // Rigid-body modes: round-off frequencies.
            assert!(*a < 1e-2, "{a} vs {b}");
        } else {
            assert!((a - b).abs() <= 1e-9 * b, "{a} vs {b}");
        }
    }
    // A band that is no frequency is refused, by `reduce` as by `modes`
    // (NaN once asked `reduce` for no eigenmode at all).
    let m = model.to_str().unwrap();
    for args in [
        vec!["modes", m, "--fmax=-3"],
        vec!["modes", m, "--fmax", "nan"],
        vec![
            "reduce",
            m,
            "--method",
            "free",
            "--fmax",
            "nan",
            "--out",
            "never.json",
        ],
        vec![
            "reduce",
            m,
            "--method",
            "craig-bampton",
            "--fmax",
            "inf",
            "--out",
            "never.json",
        ],
    ] {
        let o = flexbody(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&o).contains("is not a positive frequency in Hz"),
            "{}",
            stderr(&o)
        );
    }
    assert!(!std::path::Path::new("never.json").exists());
}

#[test]
fn a_band_above_every_mode_gives_all_of_them_accurately() {
    // The solid side beam's 1668 modes, all below 1e6 Hz: too many for a
    // Lanczos basis, so the dense solver gives them (they once came from a
    // Krylov space of the whole model with residuals of 0.1 and out of
    // order). They equal --count over the whole model.
    let model = solid_side_beam();
    let (band, residuals) = modes_json(&model, &["--fmax", "1e6"]);
    let (every, _) = modes_json(&model, &["--count", "100000"]);
    assert_eq!(band.len(), 1668);
    let worst = residuals.iter().copied().fold(0.0, f64::max);
    assert!(worst < 1e-7, "largest residual {worst:e}");
    assert!(band.windows(2).all(|w| w[0] <= w[1]));
    for (a, b) in band.iter().zip(&every).skip(6) {
        assert!((a - b).abs() <= 1e-10 * b, "{a} vs {b}");
    }
    fails_with(
        &["modes", model.to_str().unwrap(), "--count", "0"],
        &["--count must be at least 1"],
    );
}
