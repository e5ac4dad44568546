//! `--max-memory`: a factor, a Lanczos basis or a dense solve beyond the
//! budget is refused before it starts, naming what it needs; `info --factor`
//! gives the factor's size.

use super::support::{fails_with, flexbody, reduce_args, run_ok, solid_side_beam, stderr};
use std::path::Path;

#[test]
fn a_factor_beyond_max_memory_is_refused_before_factorising() {
    // The solid side beam (the sparse solver). Under a budget of 1 MiB the
    // process already holds more than that: the factor is refused with its
    // size before any storage is taken, and no body is written.
    let model = solid_side_beam();
    let model = model.to_str().unwrap();
    fails_with(
        &budgeted_modes("0.001", "10"),
        &[
            "the LDL^T factor of",
            "entries of L) needs",
            "are left (--max-memory 1.0 MiB with",
            "coarser mesh",
        ],
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body.json");
    let out = out.to_str().unwrap();
    fails_with(
        &reduce_args(model, "free-residual", "6", out, &["--max-memory", "0.001"]),
        &["entries of L) needs", "--max-memory 1.0 MiB"],
    );
    assert!(!Path::new(out).exists());
    // A budget with room changes nothing; a budget must be positive.
    let o = flexbody(&[
        "--max-memory",
        "64",
        "modes",
        model,
        "--count",
        "10",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    fails_with(
        &["--max-memory", "0", "modes", model],
        &["'0' is not a positive number of GiB"],
    );
}

#[test]
fn a_lanczos_basis_beyond_max_memory_is_refused_before_factorising() {
    // 400 modes of the 1668-DOF solid side beam take the sparse solver
    // with a basis of 1264 vectors (17 MB), its factor 1.5 MB. A budget
    // of 25.6 MiB leaves room for the factor, not for both: refused,
    // naming the modes and vectors.
    fails_with(
        &budgeted_modes("0.025", "400"),
        &[
            "a Lanczos run for 400 modes (1264 vectors of 1668 equations, \
             with the LDL^T factor's 1.5 MiB) needs",
            "(--max-memory 25.6 MiB with",
        ],
    );
    // The figure it needs, from the sizes alone: 1264 f64 vectors of n
    // equations (n = 1668: three DOFs per node of the model's mesh) plus
    // the factor it names. The factor holds at least the lower triangle of
    // K's pattern (fill-in only adds) and at most the dense n (n + 1) / 2
    // entries, 8 bytes each.
    let (n, lower) = stiffness_pattern(&solid_side_beam());
    assert_eq!(n, 1668);
    let o = flexbody(&budgeted_modes("0.025", "400"));
    let err = stderr(&o);
    let factor = mib_after(&err, "the LDL^T factor's ");
    assert!(
        factor >= (lower * 8) as f64 / MIB && factor <= (n * (n + 1) / 2 * 8) as f64 / MIB,
        "factor {factor} MiB, K's lower triangle {lower} entries: {err}"
    );
    let needs = mib_after(&err, ") needs ");
    // The vectors, as docs/numerics.md counts them for N modes in blocks
    // of b = 8: the basis of 2 N + 4 b, the working blocks 4 b and the N
    // modes found.
    let (modes, block) = (400, 8);
    let vectors = (2 * modes + 4 * block) + 4 * block + modes;
    assert_eq!(vectors, 1264, "the count the message names");
    let basis = (vectors * n * 8) as f64 / MIB;
    // Both figures are printed to 0.1 MiB.
    assert!(
        (needs - (basis + factor)).abs() <= 0.1,
        "needs {needs} MiB = basis {basis} MiB + factor {factor} MiB: {err}"
    );
    // Fewer modes fit the same budget.
    run_ok(&budgeted_modes("0.025", "10"));
}

/// The arguments of `flexbody --max-memory BUDGET modes MODEL --count COUNT`
/// on the solid side beam.
fn budgeted_modes(budget: &str, count: &str) -> Vec<String> {
    let model = solid_side_beam();
    [
        "--max-memory",
        budget,
        "modes",
        model.to_str().unwrap(),
        "--count",
        count,
    ]
    .map(String::from)
    .to_vec()
}

const MIB: f64 = (1u64 << 20) as f64;

/// The number in MiB printed right after `key` in `text`.
fn mib_after(text: &str, key: &str) -> f64 {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("'{key}' in {text}"))
        + key.len();
    let rest = &text[at..];
    let value = rest.split(" MiB").next().unwrap();
    value
        .parse()
        .unwrap_or_else(|_| panic!("a number of MiB after '{key}': {rest}"))
}

/// Equations of a model file and the entries of the lower triangle
/// (diagonal included) of its assembled stiffness matrix.
fn stiffness_pattern(path: &Path) -> (usize, usize) {
    let file = flexbody::scenario::read_model_file(path).unwrap();
    let sub = flexbody::fem::Substructure::from_model(&file.model).unwrap();
    let k = sub.matrices.stiffness.as_ref();
    let lower = (0..k.ncols())
        .map(|j| k.row_idx_of_col(j).filter(|&i| i >= j).count())
        .sum();
    (sub.len(), lower)
}

#[test]
fn a_dense_eigen_solve_beyond_max_memory_is_refused_before_it_starts() {
    // 1000 of the 1668 modes of the solid side beam take the dense solver:
    // 12 matrices of 1668 x 1668 (267 MB; the run peaks at 265 MB). A
    // budget of 102 MiB is refused, naming the solve; 0.5 GiB is enough.
    fails_with(
        &budgeted_modes("0.1", "1000"),
        &[
            "the dense eigen solve of 1668 equations (12 matrices of 1668 x 1668) needs",
            "(--max-memory 102.4 MiB with",
        ],
    );
    // The figure it needs, from the sizes alone: 12 dense matrices of
    // n x n f64 entries (8 bytes each), n = 1668 equations of the mesh.
    let (n, _) = stiffness_pattern(&solid_side_beam());
    let o = flexbody(&budgeted_modes("0.1", "1000"));
    let needs = mib_after(&stderr(&o), ") needs ");
    let dense = (12 * n * n * 8) as f64 / MIB;
    assert!(
        (needs - dense).abs() <= 0.05,
        "needs {needs} MiB, 12 n^2 8 bytes = {dense} MiB"
    );
    run_ok(&budgeted_modes("0.5", "1000"));
}

#[test]
fn info_factor_gives_the_factor_that_modes_analyses() {
    // `info --factor` orders and analyses K - sigma M as the solver does:
    // the same entries of L as the `--verbose` log of `modes` reports.
    let model = solid_side_beam();
    let model = model.to_str().unwrap();
    let o = flexbody(&["info", model, "--factor"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let line = text
        .lines()
        .find(|l| l.starts_with("factor of K - sigma M"))
        .unwrap_or_else(|| panic!("no factor line in: {text}"));
    let entries: usize = line
        .split(": ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(line.contains("Flop per factorisation"), "{line}");
    assert!(text.contains("memory left: "), "{text}");
    let o = flexbody(&["--verbose", "modes", model, "--count", "8"]);
    let log = stderr(&o);
    assert!(o.status.success(), "{log}");
    assert!(
        log.contains(&format!("analysed: {entries} entries in L")),
        "{entries} vs {log}"
    );
    // Without --factor, no analysis.
    let o = flexbody(&["info", model]);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("entries of L"));
}
