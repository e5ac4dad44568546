//! Builders the test modules share: running the `flexbody` command,
//! variants of the bundled examples, and a reduced CalculiX hex beam.

use flexbody::fem::{Dof, DofKind, Model, Substructure};
use flexbody::input::{load, MatrixFiles};
use flexbody::reduce::{reduce, Method, ReducedBody, Reduction};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `flexbody` binary with `args`.
pub(crate) fn flexbody(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flexbody"))
        .args(args)
        .output()
        .expect("run flexbody")
}

/// The standard error of `o` as text.
pub(crate) fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `args` expecting exit code 2 and a message containing all `needles`.
pub(crate) fn fails_with(args: &[&str], needles: &[&str]) {
    let o = flexbody(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "{args:?}: expected '{n}' in: {err}");
    }
}

/// The solid side beam example (1668 DOFs, the sparse solver).
pub(crate) fn solid_side_beam() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam_solid.toml")
}

/// The side beam with `from` replaced by `to`, written to `dir/name`.
pub(crate) fn variant(dir: &Path, name: &str, from: &str, to: &str) -> String {
    let text = super::side_beam_text();
    assert!(text.contains(from), "{from}");
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_string_lossy().into_owned()
}

/// The CalculiX hex-element beam of `tests/fixtures/calculix/hex_beam`: its
/// matrices and its mesh.
pub(crate) fn hex_beam() -> (Substructure, Model) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/calculix/hex_beam/hex_beam.inp");
    let c = load(&path, &MatrixFiles::default()).unwrap();
    (c.sub, c.model.unwrap())
}

/// Every DOF of `nodes` that `sub` has.
fn all_dofs(sub: &Substructure, nodes: &[u64]) -> Vec<Dof> {
    nodes
        .iter()
        .flat_map(|&n| DofKind::ALL.into_iter().map(move |k| Dof::new(n, k)))
        .filter(|d| sub.dof_map.index_of(*d).is_some())
        .collect()
}

/// `sub` reduced by `method` with `modes`, its interface every DOF of `nodes`.
pub(crate) fn reduce_with(
    sub: &Substructure,
    method: Method,
    modes: usize,
    nodes: &[u64],
) -> ReducedBody {
    reduce(sub, &Reduction::new(method, modes, all_dofs(sub, nodes))).unwrap()
}
