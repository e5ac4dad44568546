//! Values that are numbers but not physics are refused where they are
//! read, naming the file and line: inertia tensors that are not positive
//! semi-definite or not finite (once accepted, or failing late as a
//! singular matrix at some node), and a band `--fmax` that is no frequency
//! (`cli_modes.rs`); and the messages that say so name each cause once
//! and no empty line number, and quote no more than a short excerpt of a
//! huge line.

use super::support::fails_with;
use std::path::PathBuf;

fn vehicle() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/vehicle.toml");
    std::fs::read_to_string(path).unwrap()
}

/// `text` with `from` replaced by `to`, written to `dir/name`.
fn write(dir: &std::path::Path, name: &str, text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from}");
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn a_rigid_body_inertia_must_be_positive_semi_definite_and_finite() {
    let dir = tempfile::tempdir().unwrap();
    let text = vehicle();
    let line = text
        .lines()
        .position(|l| l.starts_with("[[rigid_body]]"))
        .unwrap()
        + 1;
    let from = "inertia = [0.0, 4000.0, 0.0, 0.0, 0.0, 0.0]";
    for (to, rule) in [
        (
            "inertia = [0.0, -4000.0, 0.0, 0.0, 0.0, 0.0]",
            "moments not negative",
        ),
        (
            "inertia = [10.0, 4000.0, 10.0, 300.0, 0.0, 0.0]",
            "products of inertia",
        ),
    ] {
        let model = write(dir.path(), "v.toml", &text, from, to);
        fails_with(
            &[
                "simulate",
                &model,
                "--out",
                dir.path().join("out").to_str().unwrap(),
            ],
            &[
                &format!("v.toml:{line}"),
                "inertia of rigid body 'car_body'",
                rule,
            ],
        );
    }
    // NaN is refused where it is written, as every number of the file.
    let model = write(
        dir.path(),
        "v.toml",
        &text,
        from,
        "inertia = [0.0, nan, 0.0, 0.0, 0.0, 0.0]",
    );
    let out = dir.path().join("out");
    fails_with(
        &["simulate", &model, "--out", out.to_str().unwrap()],
        &[&format!(
            "v.toml:{}: NaN for `inertia[1]` in [[rigid_body]] 'car_body' is not a finite number",
            line + 3
        )],
    );
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_point_mass_inertia_must_be_positive_semi_definite_and_finite() {
    let dir = tempfile::tempdir().unwrap();
    let text = vehicle();
    // A point mass on the side beam's first node, after the last table of
    // the file's FE model.
    let anchor = "[[rigid_body]]";
    for (inertia, rule) in [
        ("[1.0, 1.0, -1.0, 0.0, 0.0, 0.0]", "moments not negative"),
        ("[1.0, 1.0, 1.0, 0.0, 0.0, 5.0]", "products of inertia"),
        (
            "[1.0, inf, 1.0, 0.0, 0.0, 0.0]",
            "inf for `inertia[1]` in [[element]] id 9001",
        ),
    ] {
        let mass = format!(
            "[[element]]\ntype = \"point-mass\"\nid = 9001\nnode = 1\nmass = 2.0\n\
             inertia = {inertia}\n\n{anchor}"
        );
        let model = write(dir.path(), "m.toml", &text, anchor, &mass);
        fails_with(&["info", &model], &["m.toml:", rule]);
    }
}

#[test]
fn a_message_names_each_cause_once_and_no_empty_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.json"), "{\"format\": \"x\"}").unwrap();
    let text = vehicle().replace("modes = 1\n", "");
    let from = "method = \"free-residual\"";
    let model = write(dir.path(), "v.toml", &text, from, "body = \"bad.json\" #");
    let o = super::support::flexbody(&[
        "simulate",
        &model,
        "--out",
        dir.path().join("o").to_str().unwrap(),
    ]);
    let err = super::support::stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.matches("missing field").count(), 1, "{err}");
    assert!(err.contains("reading the reduced body: "), "{err}");
    // A model without DOFs has no line to name: `file: message`.
    let deck = dir.path().join("nodes.inp");
    std::fs::write(&deck, "*NODE\n1, 0, 0, 0\n").unwrap();
    fails_with(
        &["info", deck.to_str().unwrap()],
        &["nodes.inp: the model has no DOFs"],
    );
}

#[test]
fn a_huge_line_is_not_echoed_whole() {
    let dir = tempfile::tempdir().unwrap();
    // A 3 MB coordinate in a deck, as a corrupted or hostile file has it.
    let deck = dir.path().join("big.inp");
    let huge = "9".repeat(3_000_000);
    std::fs::write(&deck, format!("*NODE\n1, {huge}, 0, 0\n")).unwrap();
    let o = super::support::flexbody(&["info", deck.to_str().unwrap()]);
    let err = super::support::stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(err.len() < 500, "{} bytes", err.len());
    // Longer than a line may be (1 MiB): refused as it is read.
    assert!(
        err.starts_with("error: ")
            && err.contains("big.inp:2: the line is at least")
            && err.contains("bytes long, more than the 1048576 a line"),
        "{}",
        &err[..200]
    );
    // Shorter, it is a field longer than a deck's 80 characters, quoted as
    // an excerpt of its start.
    let huge = "9".repeat(900_000);
    std::fs::write(&deck, format!("*NODE\n1, {huge}, 0, 0\n")).unwrap();
    let o = super::support::flexbody(&["info", deck.to_str().unwrap()]);
    let err = super::support::stderr(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(err.len() < 400, "{} bytes", err.len());
    assert!(
        err.contains("big.inp:2: *NODE: '999")
            && err.contains("999... (900000 bytes)' is longer than 80 characters"),
        "{}",
        &err[..200]
    );
}

#[test]
fn a_number_no_model_holds_is_refused_where_it_is_read() {
    // Finite but absurd: a 1e300 m track amplitude gave NaN in every
    // section-force column of frf.csv with exit code 0.
    let dir = tempfile::tempdir().unwrap();
    let text = vehicle();
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    let amplitude = write(
        dir.path(),
        "a.toml",
        &text,
        "amplitude = 0.01",
        "amplitude = 1e300",
    );
    fails_with(
        &["frf", &amplitude, "--out", out],
        &["a.toml:40: 1e300 for `amplitude` in [track] is beyond 1e100 in magnitude"],
    );
    assert!(!dir.path().join("out").exists(), "no output folder is left");
    // NaN and inf anywhere, read into whatever: a force table, a
    // connection's track_x (once failing late as a singular dynamic
    // stiffness, with no location).
    let table = text.clone()
        + "\n[[force]]\nname = \"kick\"\nnode = 11\ndirection = [0.0, 0.0, 1.0]\n\
           table = [[0.0, 0.0], [0.1, nan]]\n";
    let table = write(dir.path(), "f.toml", &table, "", "");
    fails_with(
        &["simulate", &table, "--out", out],
        &["f.toml:112: NaN for `table[1][1]` in [[force]] 'kick' is not a finite number"],
    );
    let track_x = write(
        dir.path(),
        "x.toml",
        &text,
        "name = \"primary_front\"",
        "name = \"primary_front\"\ntrack_x = -inf",
    );
    fails_with(
        &["frf", &track_x, "--out", out],
        &["x.toml:53: -inf for `track_x` in [[connection]] 'primary_front' is not a finite number"],
    );
}

#[test]
fn a_model_without_mass_is_refused_as_such_before_any_solve() {
    // Density 0 failed as "the stiffness matrix of the supported body is
    // singular at node 2 ry", a wrong cause.
    let dir = tempfile::tempdir().unwrap();
    let model = write(
        dir.path(),
        "d.toml",
        &vehicle(),
        "density = 6800.0",
        "density = 0.0",
    );
    let out = dir.path().join("out");
    fails_with(
        &["frf", &model, "--out", out.to_str().unwrap()],
        &["the mass matrix is zero"],
    );
}

/// A body of the side beam written in `format` to `dir/name`, and its text
/// (none for a folder).
fn side_beam_body(dir: &std::path::Path, name: &str, format: &str) -> PathBuf {
    let model = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam.toml");
    let out = dir.join(name);
    super::support::run_ok(&super::support::reduce_args(
        &model,
        "craig-bampton",
        "4",
        &out,
        &["--format", format],
    ));
    out
}

/// `path`'s text with the line starting (after its indentation) with
/// `start` replaced by `with`, written to `to`.
fn edit_line(path: &std::path::Path, start: &str, with: &str, to: &std::path::Path) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut done = false;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            if !done && l.trim_start().starts_with(start) {
                done = true;
                with.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    assert!(done, "no line starts with {start}");
    std::fs::write(to, lines.join("\n") + "\n").unwrap();
}

#[test]
fn a_body_file_that_describes_no_body_is_refused_before_use() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let inspect = |p: &std::path::Path, needles: &[&str]| {
        fails_with(&["inspect", p.to_str().unwrap()], needles);
    };
    // JSON: a non-symmetric mass (accepted, with a wrong mass in the
    // summary), a basis entry of 1e308 (inf and NaN in histories.csv).
    let json = side_beam_body(d, "b.json", "json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    doc["mass"][0][1] = serde_json::json!(doc["mass"][0][1].as_f64().unwrap() + 5.0);
    let nonsymmetric = d.join("nonsymmetric.json");
    std::fs::write(&nonsymmetric, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    inspect(
        &nonsymmetric,
        &["block 'mass': the matrix is not symmetric: entry (2, 1)"],
    );
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    doc["basis"][3][2] = serde_json::json!(1e308);
    let huge = d.join("huge.json");
    std::fs::write(&huge, serde_json::to_string_pretty(&doc).unwrap()).unwrap();
    inspect(&huge, &["block 'basis': entry (4, 3) is 1e308"]);
    let text = vehicle().replace("modes = 1\n", "");
    let model = write(
        d,
        "v.toml",
        &text,
        "method = \"free-residual\"",
        &format!("body = {:?} #", huge.to_str().unwrap()),
    );
    let out = d.join("out");
    fails_with(
        &["simulate", &model, "--out", out.to_str().unwrap()],
        &["huge.json", "entry (4, 3) is 1e308"],
    );
    assert!(!out.exists());
    // SID: mass NaN (a NaN mass and centre of mass in the summary), a
    // duplicated entry hiding a missing one, a non-symmetric modal mass.
    let sid = side_beam_body(d, "b.sid", "sid");
    let nan = d.join("nan.sid");
    edit_line(&sid, "mass =", "  mass = NaN", &nan);
    inspect(
        &nan,
        &["nan.sid: line 6, block 'refmod': mass: 'NaN' is not a finite number"],
    );
    let text = std::fs::read_to_string(&sid).unwrap();
    let me = text.find("\nMe\n").expect("an Me block");
    let (head, tail) = text.split_at(me);
    let first = tail
        .lines()
        .find(|l| l.trim_start().starts_with("m0(1, 1)"))
        .unwrap();
    let second = tail
        .lines()
        .find(|l| l.trim_start().starts_with("m0(1, 2)"))
        .unwrap();
    let duplicated = d.join("duplicated.sid");
    std::fs::write(
        &duplicated,
        head.to_string() + &tail.replacen(second, first, 1),
    )
    .unwrap();
    inspect(
        &duplicated,
        &["block 'Me': m0(1, 1) is given twice (first at line"],
    );
    let asymmetric = d.join("asymmetric.sid");
    std::fs::write(
        &asymmetric,
        head.to_string() + &tail.replacen(second, "    m0(1, 2) = 7.5e0", 1),
    )
    .unwrap();
    inspect(&asymmetric, &["block 'Me': m0 is not symmetric"]);
    // A node given twice: the second node's id made the first one's.
    let mut frames = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim_start().starts_with("rframe"));
    let ((first_line, first), (second_line, second)) =
        (frames.next().unwrap(), frames.next().unwrap());
    let twice = d.join("twice.sid");
    std::fs::write(&twice, text.replacen(second, first, 1)).unwrap();
    inspect(
        &twice,
        &[&format!(
            "line {}, block 'node': node {} is given twice (first at line {})",
            second_line + 1,
            first.split('\'').nth(1).unwrap(),
            first_line + 1
        )],
    );
    // Matrix Market folder: a NaN mass entry (a NaN mass in the summary).
    let folder = side_beam_body(d, "body", "mtx");
    let mass = folder.join("mass.mtx");
    let text = std::fs::read_to_string(&mass).unwrap();
    let first_value = text.lines().nth(3).unwrap().to_string();
    std::fs::write(&mass, text.replacen(&first_value, "NaN", 1)).unwrap();
    inspect(&folder, &["mass.mtx: line 4: 'NaN' is not a finite number"]);
}

#[test]
fn deck_and_matrix_numbers_beyond_1e100_are_refused_with_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("far.inp");
    std::fs::write(&deck, "*NODE\n1, 0, 0, 0\n2, 1e200, 0, 0\n").unwrap();
    fails_with(
        &["info", deck.to_str().unwrap()],
        &["far.inp:3: node 2: coordinate 1: expected a finite number (at most 1e100 in magnitude), got '1e200'"],
    );
    let k = dir.path().join("k.mtx");
    std::fs::write(
        &k,
        "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1e150\n2 2 1.0\n",
    )
    .unwrap();
    let m = dir.path().join("m.mtx");
    std::fs::write(
        &m,
        "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 1.0\n2 2 1.0\n",
    )
    .unwrap();
    let dofs = dir.path().join("dofs.txt");
    std::fs::write(
        &dofs,
        "1 ux
2 ux
",
    )
    .unwrap();
    fails_with(
        &[
            "modes",
            k.to_str().unwrap(),
            "--mass",
            m.to_str().unwrap(),
            "--dofs",
            dofs.to_str().unwrap(),
        ],
        &["k.mtx:3", "1e150 is beyond 1e100 in magnitude"],
    );
}

#[test]
fn a_negative_study_frequency_is_refused_at_its_line() {
    // Found by the model_file fuzz target: the error named no line.
    let dir = tempfile::tempdir().unwrap();
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let from = "omegas = [0.006283185307179587, 122.0]";
    let line = text.lines().position(|l| l.starts_with(from)).unwrap() + 1;
    let model = write(
        dir.path(),
        "s.toml",
        &text,
        from,
        "omegas = [0.006283185307179587, -1122.0]",
    );
    fails_with(
        &[
            "study",
            &model,
            "--out",
            dir.path().join("out").to_str().unwrap(),
        ],
        &[&format!(
            "s.toml:{line}: study: omega -1122 must be a finite frequency >= 0"
        )],
    );
}
