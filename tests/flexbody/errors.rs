//! Error paths the README promises that no other test triggers: each fails
//! with exit code 2 (or its typed error, for the library), names what is
//! wrong, and leaves no output behind.

use super::support::{fails_with, flexbody, mid_span_interface, reduce_args, run_ok, stderr};
use flexbody::fem::{Dof, DofKind, Substructure};
use flexbody::reduce::{reduce, ForceGroup, Method, ReduceError, Reduction};
use flexbody::scenario::read_model_file;
use std::path::{Path, PathBuf};

/// A chain of `n` masses on springs of 1e4 N/m, held at both ends, in
/// Matrix Market files (`K.mtx`, `M.mtx`, `dofs.txt` in `dir`), with the
/// coupling between DOFs `weak` and `weak + 1` set to `coupling`. Returns
/// the three paths and the number of negative eigenvalues of `K` by the
/// signs of the pivots of its `LDL^T` (Sylvester's law of inertia, on the
/// tridiagonal matrix directly).
fn chain_files(dir: &Path, n: usize, weak: usize, coupling: f64) -> ([String; 3], usize) {
    let off = |i: usize| if i == weak { coupling } else { -1e4 };
    let mut k = format!(
        "%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {}\n",
        2 * n - 1
    );
    for i in 0..n {
        k += &format!("{} {} 2e4\n", i + 1, i + 1);
        if i + 1 < n {
            k += &format!("{} {} {:e}\n", i + 2, i + 1, off(i));
        }
    }
    let mut m = format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {n}\n");
    let mut dofs = String::new();
    for i in 0..n {
        m += &format!("{} {} 1\n", i + 1, i + 1);
        dofs += &format!("{} uz\n", i + 1);
    }
    let mut negative = 0;
    let mut pivot = 2e4;
    for i in 0..n {
        if i > 0 {
            pivot = 2e4 - off(i - 1) * off(i - 1) / pivot;
        }
        negative += usize::from(pivot < 0.0);
    }
    let paths = [("K.mtx", k), ("M.mtx", m), ("dofs.txt", dofs)].map(|(name, text)| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_string_lossy().into_owned()
    });
    (paths, negative)
}

/// The bound in "lie below BOUND (1/s^2)" of an error message.
fn bound_in(message: &str) -> f64 {
    message
        .split("lie below ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no bound in: {message}"))
}

#[test]
fn an_indefinite_stiffness_is_an_error_that_counts_its_negative_eigenvalues() {
    // A coupling of -5e4 between two springs of 1e4 N/m: no diagonal entry
    // is negative (the reader takes the file), but K is indefinite.
    let dir = tempfile::tempdir().unwrap();
    let n = 400;
    let ([k, m, dofs], negative) = chain_files(dir.path(), n, n / 2 - 1, -5e4);
    assert_eq!(negative, 1, "the pivots of the chain");
    let count = format!("{negative} eigenvalue(s) of K phi = lambda M phi lie below");
    let needles = [count.as_str(), "K is not positive semi-definite"];
    let matrices = ["--mass", m.as_str(), "--dofs", dofs.as_str()];
    // 2 of 400 modes take the Lanczos path, whose bound is its shift
    // -1e-6 trace(K) / trace(M) = -2e-2; 150 the dense one, whose bound is
    // -1e-8 of the largest eigenvalue, between 7e4 (the Rayleigh quotient
    // of the two coupled DOFs) and 8e4 (Gershgorin).
    for (modes, low, high) in [("2", -2.0001e-2, -1.9999e-2), ("150", -8e-4, -7e-4)] {
        let mut args = vec!["modes", k.as_str(), "--count", modes];
        args.extend(matrices);
        fails_with(&args, &needles);
        let bound = bound_in(&stderr(&flexbody(&args)));
        assert!(low <= bound && bound <= high, "{modes} modes: {bound:e}");
    }
    let out = dir.path().join("body.json");
    let mut args = reduce_args(&k, "craig-bampton", "2", &out, &["--interface", "1"]);
    args.extend(matrices.map(String::from));
    fails_with(&args, &needles);
    assert!(!out.exists());
    // Nothing else is left beside the inputs.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);
    // The same chain with a coupling of -1e4 is positive definite: the
    // error is the coupling's.
    let ([k, ..], negative) = chain_files(dir.path(), n, n / 2 - 1, -1e4);
    assert_eq!(negative, 0);
    let mut args = vec!["modes", k.as_str(), "--count", "2"];
    args.extend(matrices);
    run_ok(&args);
}

/// The vehicle example with each `(from, to)` replaced once, written to
/// `dir/name`.
fn vehicle_variant(dir: &Path, name: &str, edits: &[(&str, &str)]) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/vehicle.toml");
    let mut text = std::fs::read_to_string(path).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{from}");
        text = text.replacen(from, to, 1);
    }
    let out = dir.join(name);
    std::fs::write(&out, text).unwrap();
    out
}

#[test]
fn simulate_and_frf_take_away_the_folders_they_made_when_the_body_cannot_be_read() {
    // The body file is read after the output folder is made.
    let dir = tempfile::tempdir().unwrap();
    let model = vehicle_variant(
        dir.path(),
        "v.toml",
        &[
            ("method = \"free-residual\"", "body = \"missing.json\""),
            ("modes = 1\n", ""),
        ],
    );
    let new = dir.path().join("new");
    let out = new.join("deeper");
    for command in ["simulate", "frf"] {
        fails_with(
            &[
                command,
                model.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            &["missing.json", "cannot read"],
        );
        assert!(!new.exists(), "{command} left its folder");
    }
    // An existing folder stays, with what it held.
    std::fs::create_dir(&new).unwrap();
    std::fs::write(new.join("keep.txt"), "kept").unwrap();
    fails_with(
        &[
            "simulate",
            model.to_str().unwrap(),
            "--out",
            new.to_str().unwrap(),
        ],
        &["missing.json"],
    );
    let left: Vec<_> = std::fs::read_dir(&new).unwrap().collect();
    assert_eq!(left.len(), 1, "{left:?}");
}

#[test]
fn force_groups_are_refused_by_every_method_with_constraint_modes() {
    let file = read_model_file(&super::side_beam_path()).unwrap();
    let sub = Substructure::from_model(&file.model).unwrap();
    let uz = |n| Dof::new(n, DofKind::Uz);
    for (method, name) in [
        (Method::CraigBampton, "craig-bampton"),
        (Method::Guyan, "guyan"),
        (Method::ElasticResidual, "elastic-residual"),
    ] {
        let modes = if method == Method::Guyan { 0 } else { 1 };
        let mut spec = Reduction::new(method, modes, file.interface.clone());
        spec.force_groups = vec![ForceGroup {
            name: "primary in phase".into(),
            loads: vec![(uz(1), 1.0), (uz(21), 1.0)],
        }];
        let err = reduce(&sub, &spec).unwrap_err();
        assert!(
            matches!(err, ReduceError::ForceGroupsNotApplicable(n) if n == name),
            "{method}: {err}"
        );
        assert!(err.to_string().contains(&format!("method {name}")), "{err}");
        // Without the groups the same reduction succeeds.
        spec.force_groups.clear();
        assert!(reduce(&sub, &spec).is_ok(), "{method}");
    }
}

#[test]
fn guyan_and_elastic_residual_name_the_dofs_an_interface_leaves_free() {
    // One interface DOF at mid-span holds heave but not pitch: K_NN is
    // singular, and the beam's ends move most in the pitch about node 11.
    let dir = tempfile::tempdir().unwrap();
    let model = mid_span_interface(dir.path());
    let out = dir.path().join("b.json");
    for (method, modes) in [("guyan", "0"), ("elastic-residual", "1")] {
        fails_with(
            &reduce_args(&model, method, modes, &out, &[]),
            &[
                "the interface DOFs (node 11 uz) leave a mechanism",
                "node 1 uz",
                "node 21 uz",
            ],
        );
        assert!(!out.exists(), "{method}");
    }
}
