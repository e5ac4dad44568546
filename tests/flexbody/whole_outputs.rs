//! Outputs are written whole or not at all, and only as regular files: a
//! body folder whose write fails (a full disk) keeps its previous body
//! whole instead of mixing two, and `--out` never turns a device, a FIFO
//! or a symbolic link into a file (`--follow-symlinks` writes through a
//! link). An output folder that cannot take the command's first file is
//! refused before the computation, naming that file.

use super::support::{fails_with, flexbody, hex_beam_deck, reduce_args, run_ok, stderr};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// The files of a folder, by name, with their bytes.
fn contents(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

#[test]
fn a_failed_write_leaves_the_body_folder_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body");
    let deck = hex_beam_deck();
    run_ok(&reduce_args(&deck, "free", "6", &out, &["--format", "mtx"]));
    let before = contents(&out);
    assert!(before.contains_key("basis.mtx") && before.contains_key("index.json"));
    // A Craig-Bampton body into the same folder, with files limited to
    // 8 KiB: its mass and stiffness fit, its basis (84 x 18) does not, as
    // on a disk that fills up. SIGXFSZ ignored, the write fails with EFBIG.
    let args = reduce_args(
        &deck,
        "craig-bampton",
        "6",
        &out,
        &["--format", "mtx", "--interface", "1,13,79"],
    );
    let o = Command::new("bash")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 8; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_flexbody"))
        .args(&args)
        .output()
        .unwrap();
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("basis.mtx") && err.contains("cannot write"),
        "{err}"
    );
    // The old body, byte for byte, and no temporary file left.
    assert_eq!(contents(&out), before);
    let o = run_ok(&["inspect", out.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("free"));
}

#[test]
fn out_replaces_only_regular_files() {
    let dir = tempfile::tempdir().unwrap();
    let deck = hex_beam_deck();
    let target = dir.path().join("target.json");
    std::fs::write(&target, "keep").unwrap();
    let link = dir.path().join("link.json");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let fifo = dir.path().join("fifo.json");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let mut special = vec![link.clone(), fifo.clone()];
    // A character device, where this user may make one (a copy of
    // /dev/null, as an attacker would hand it over).
    let device = dir.path().join("null.json");
    let made = Command::new("cp")
        .arg("-a")
        .arg("/dev/null")
        .arg(&device)
        .status()
        .is_ok_and(|s| s.success());
    if made {
        special.push(device.clone());
    }
    for path in &special {
        fails_with(
            &reduce_args(&deck, "free", "6", path, &[]),
            &["not a regular file"],
        );
        let kind = std::fs::symlink_metadata(path).unwrap().file_type();
        assert!(!kind.is_file(), "{} became a file", path.display());
    }
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep");
    // With --follow-symlinks, the file a link leads to is written and the
    // link kept; a loop of links is an error naming the link.
    let mut args = reduce_args(&deck, "free", "6", &link, &[]);
    args.insert(0, "--follow-symlinks".into());
    run_ok(&args);
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::read_to_string(&target)
        .unwrap()
        .contains("flexbody-reduced-body"));
    std::fs::write(&target, "keep").unwrap();
    let (a, b) = (dir.path().join("a.json"), dir.path().join("b.json"));
    std::os::unix::fs::symlink(&b, &a).unwrap();
    std::os::unix::fs::symlink(&a, &b).unwrap();
    let mut args = reduce_args(&deck, "free", "6", &a, &[]);
    args.insert(0, "--follow-symlinks".into());
    fails_with(
        &args,
        &["a.json: the symbolic link leads to", "cannot be resolved"],
    );
    // A regular file is replaced, as before.
    let o = flexbody(&reduce_args(&deck, "free", "6", &target, &[]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&target)
        .unwrap()
        .contains("flexbody-reduced-body"));
}

#[test]
fn an_output_folder_that_cannot_take_its_first_file_names_it() {
    // A folder where `histories.csv` (or `frf.csv`) should go: the run
    // stops before the computation and names that file, not another.
    let dir = tempfile::tempdir().unwrap();
    let vehicle = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/vehicle.toml");
    for (command, first) in [("simulate", "histories.csv"), ("frf", "frf.csv")] {
        let out = dir.path().join(command);
        std::fs::create_dir_all(out.join(first)).unwrap();
        fails_with(
            &[
                command,
                vehicle.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
            &[&format!("{first}: cannot write: it is a folder")],
        );
    }
}
