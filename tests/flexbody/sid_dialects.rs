//! SID files written by other programs (`tests/fixtures/sid/`): welib's
//! `Beam2SID` and PY_SID (the EMBS Modelica library). Each is read into
//! flexbody's conventions, checked against the numbers in its text, written
//! again by flexbody's writer and read back; `flexbody convert` and
//! `inspect` on them; and broken or unknown files refused at their line.

use super::support::{fails_with, reduce_args, run_ok};
use flexbody::export::sid::{parse_sid_dialect, read_sid, read_sid_dialect, write_sid, Taylor};
use flexbody::export::{read_json, Dialect, Sid};
use std::path::{Path, PathBuf};

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/sid")
        .join(name)
}

fn welib() -> PathBuf {
    fixture("welib_clamped_beam.sid")
}

fn py_sid() -> PathBuf {
    fixture("pysid_balken1m.SID_FEM")
}

/// The value of `key` (e.g. `m1(1, 1, 2)`, spaces ignored) in the `nth`
/// (0-based) block named `block` of `text`, read from the text alone: an
/// independent reading to hold the reader's result against. Fortran `D`
/// exponents are read as `E`.
fn value_in(text: &str, block: &str, nth: usize, key: &str) -> f64 {
    let squeeze = |s: &str| s.chars().filter(|c| !c.is_whitespace()).collect::<String>();
    let key = squeeze(key);
    let end = format!("end {block}");
    let mut seen = 0;
    let mut inside = false;
    for line in text.lines().map(str::trim) {
        if line == block {
            inside = seen == nth;
            seen += 1;
        } else if line == end {
            inside = false;
        } else if inside {
            if let Some((k, v)) = line.split_once('=') {
                if squeeze(k) == key {
                    return v.trim().replace('D', "e").parse().unwrap();
                }
            }
        }
    }
    panic!("no {key} in block {block} #{nth}");
}

/// Every Taylor block of `a` and `b`, entry by entry, within `tol` of the
/// block's largest entry (the frame nodes' blocks included).
fn assert_same_blocks(a: &Sid, b: &Sid, tol: f64) {
    let pairs = |s: &Sid| -> Vec<(String, Taylor)> {
        let mut v: Vec<(String, Taylor)> = s
            .quantities()
            .iter()
            .map(|(n, t)| (n.to_string(), (*t).clone()))
            .collect();
        for node in &s.nodes {
            for (n, t) in [
                ("origin", &node.origin),
                ("phi", &node.phi),
                ("psi", &node.psi),
                ("AP", &node.ap),
            ] {
                v.push((format!("node {} {n}", node.id), t.clone()));
            }
        }
        v
    };
    let (pa, pb) = (pairs(a), pairs(b));
    assert_eq!(pa.len(), pb.len());
    for ((name, ta), (_, tb)) in pa.iter().zip(&pb) {
        assert_eq!(
            (ta.nrow, ta.ncol, ta.m1.len()),
            (tb.nrow, tb.ncol, tb.m1.len()),
            "{name}"
        );
        for (ma, mb) in std::iter::once((&ta.m0, &tb.m0)).chain(ta.m1.iter().zip(&tb.m1)) {
            let scale = ma.norm_max().max(f64::MIN_POSITIVE);
            for j in 0..ma.ncols() {
                for i in 0..ma.nrows() {
                    let d = (ma[(i, j)] - mb[(i, j)]).abs();
                    assert!(
                        d <= tol * scale,
                        "{name} ({i}, {j}): {} vs {}",
                        ma[(i, j)],
                        mb[(i, j)]
                    );
                }
            }
        }
    }
    assert_eq!(a.refmod, b.refmod);
    assert_eq!(
        a.nodes.iter().map(|n| n.id).collect::<Vec<_>>(),
        b.nodes.iter().map(|n| n.id).collect::<Vec<_>>()
    );
}

/// `sid` written by flexbody's writer and read back: the same blocks, and
/// the file is in flexbody's dialect.
fn round_trip(sid: &Sid) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("again.sid");
    write_sid(sid, &path).unwrap();
    let (back, dialect) = read_sid_dialect(&path).unwrap();
    assert_eq!(dialect, Dialect::Flexbody);
    // The writer's numbers read back to the same bits, so the tolerance is
    // zero; the comparison entry by entry names the block that differs.
    assert_same_blocks(sid, &back, 0.0);
    assert_eq!(&back, sid);
}

#[test]
fn py_sid_is_read_into_flexbody_conventions() {
    let text = std::fs::read_to_string(py_sid()).unwrap();
    let (sid, dialect) = parse_sid_dialect(&text).unwrap();
    assert_eq!(dialect, Dialect::PySid);
    assert_eq!(sid.refmod.mass, 0.784999999999);
    assert_eq!(sid.nq(), 1);
    assert_eq!(
        sid.nodes.iter().map(|n| n.id).collect::<Vec<_>>(),
        [6022, 6023, 6024]
    );
    // J is written as the column [xx, yy, zz, xy, xz, yz] (the order in
    // which EMBS's `EMBS_Body` rebuilds the tensor); it is read as the
    // symmetric 3 x 3 tensor.
    let at = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    for (row, &(i, j)) in at.iter().enumerate() {
        let key = format!("m0({}, 1)", row + 1);
        let want = value_in(&text, "J", 0, &key);
        assert_eq!(sid.j.m0[(i, j)], want, "J {key}");
        assert_eq!(sid.j.m0[(j, i)], want, "J {key}");
        let key = format!("m1({}, 1, 1)", row + 1);
        assert_eq!(
            sid.j.m1[0][(i, j)],
            value_in(&text, "J", 0, &key),
            "J {key}"
        );
    }
    // An independent check of that order from the file's own Oe, which
    // PY_SID writes as flexbody does ([S11, S22, S33, 2 S12, 2 S23, 2 S31]
    // with S = -J1 / 2): Oe m0 = -[J1xx/2, J1yy/2, J1zz/2, J1xy, J1yz, J1zx].
    let j1 = &sid.j.m1[0];
    let from_j = [
        -j1[(0, 0)] / 2.0,
        -j1[(1, 1)] / 2.0,
        -j1[(2, 2)] / 2.0,
        -j1[(0, 1)],
        -j1[(1, 2)],
        -j1[(2, 0)],
    ];
    for (c, want) in from_j.iter().enumerate() {
        let got = sid.oe.m0[(0, c)];
        assert!(
            (got - want).abs() <= 1e-9 * j1.norm_max(),
            "Oe(1, {}): {got} vs {want}",
            c + 1
        );
    }
    // m1 is indexed (row, mode, column): AP's m1(1, 1, 2) of node 6022 is
    // row 1, column 2 of the first coordinate's matrix (psi~: -psi_z).
    assert_eq!(
        sid.nodes[0].ap.m1[0][(0, 1)],
        value_in(&text, "AP", 0, "m1(1, 1, 2)")
    );
    assert_eq!(sid.nodes[0].ap.m1[0][(0, 1)], -sid.nodes[0].psi.m0[(2, 0)]);
    assert_eq!(
        sid.cr.m1[0][(0, 2)],
        value_in(&text, "Cr", 0, "m1(1, 1, 3)")
    );
    assert_eq!(
        sid.oe.m1[0][(0, 4)],
        value_in(&text, "Oe", 0, "m1(1, 1, 5)")
    );
    // Entries not listed are zero; structure 4 is the identity, 1 diagonal.
    assert_eq!(sid.nodes[0].origin.m0[(2, 0)], 0.0);
    assert_eq!(sid.nodes[1].ap.m0, faer::Mat::<f64>::identity(3, 3));
    assert_eq!(sid.nodes[1].ap.m1[0].norm_max(), 0.0);
    assert_eq!(sid.me.m0[(0, 0)], 1.0);
    assert_eq!(sid.ke.m0[(0, 0)], value_in(&text, "Ke", 0, "m0(1, 1)"));
    // ksigma (a zero initial-stress vector) becomes no recovery rows.
    assert_eq!((sid.ksigma.nrow, sid.ksigma.ncol), (0, 1));
    // 8.360 Hz, as its name says.
    let f = sid.frequencies_hz().unwrap();
    assert!((f[0] - 8.360).abs() < 1e-3, "{f:?}");
    round_trip(&sid);
}

#[test]
fn welib_is_read_into_flexbody_conventions() {
    let text = std::fs::read_to_string(welib()).unwrap();
    let (sid, dialect) = parse_sid_dialect(&text).unwrap();
    assert_eq!(dialect, Dialect::Welib);
    assert_eq!(sid.refmod.mass, 157.0);
    assert_eq!(sid.nq(), 4);
    assert_eq!(sid.refmod.ielastq[0], "Eigen Mode    0");
    assert_eq!(
        sid.nodes.iter().map(|n| n.id).collect::<Vec<_>>(),
        (1..=11).collect::<Vec<_>>()
    );
    // m1 per coordinate, as flexbody's: mdCM m1(2, 1, 1) is row 2 of q_1.
    assert_eq!(
        sid.md_cm.m1[0][(1, 0)],
        value_in(&text, "mdCM", 0, "m1(2, 1, 1)")
    );
    assert_eq!(sid.md_cm.m1[0][(1, 0)], 61.464747);
    // Symmetric blocks (structure 2) list their lower triangle.
    assert_eq!(sid.j.m0[(1, 1)], 209.333333);
    assert_eq!(sid.ke.m0[(0, 2)], value_in(&text, "Ke", 0, "m0(3, 1)"));
    assert_eq!(sid.ke.m0[(0, 2)], -0.000006);
    assert_eq!(sid.ke.m0[(3, 3)], value_in(&text, "Ke", 0, "m0(4, 4)"));
    // The tip's phi is of order 1 in this file; it is kept.
    assert_eq!(sid.nodes[10].phi.order, 1);
    assert_eq!(
        sid.nodes[10].phi.m1[2][(0, 0)],
        value_in(&text, "phi", 10, "m1(1, 1, 3)")
    );
    assert_eq!((sid.ksigma.nrow, sid.ksigma.ncol), (0, 4));
    assert_eq!(sid.de.m0.norm_max(), 0.0);
    round_trip(&sid);
}

#[test]
fn convert_and_inspect_read_every_dialect() {
    let dir = tempfile::tempdir().unwrap();
    for (input, dialect) in [(py_sid(), "PY_SID (EMBS)"), (welib(), "welib (Beam2SID)")] {
        let o = run_ok(&["inspect".as_ref(), input.as_os_str()]);
        let summary = String::from_utf8_lossy(&o.stdout);
        assert!(
            summary.contains(&format!("dialect: {dialect}")),
            "{summary}"
        );
        let out = dir.path().join("converted.sid");
        let o = run_ok(&[
            "convert".as_ref(),
            input.as_os_str(),
            "--format".as_ref(),
            "sid".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        assert!(String::from_utf8_lossy(&o.stdout).contains(dialect));
        let (back, written) = read_sid_dialect(&out).unwrap();
        assert_eq!(written, Dialect::Flexbody);
        assert_eq!(back, read_sid(&input).unwrap());
        let o = run_ok(&["inspect".as_ref(), out.as_os_str(), "--json".as_ref()]);
        let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(doc["dialect"], "flexbody");
    }
}

#[test]
fn convert_json_to_matrix_market_and_back() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let model = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam.toml");
    let json = d.join("b.json");
    run_ok(&reduce_args(&model, "craig-bampton", "4", &json, &[]));
    let folder = d.join("b_mtx");
    let again = d.join("again.json");
    let convert = |from: &Path, format: &str, to: &Path| {
        run_ok(&[
            "convert".as_ref(),
            from.as_os_str(),
            "--format".as_ref(),
            format.as_ref(),
            "--out".as_ref(),
            to.as_os_str(),
        ]);
    };
    convert(&json, "mtx", &folder);
    assert!(folder.join("index.json").is_file());
    convert(&folder, "json", &again);
    let (a, b) = (read_json(&json).unwrap(), read_json(&again).unwrap());
    assert_eq!(
        (a.method, &a.modes, &a.interface),
        (b.method, &b.modes, &b.interface)
    );
    let dofs = |body: &flexbody::reduce::ReducedBody| {
        (0..body.dof_map.len())
            .map(|i| body.dof_map.dof(i))
            .collect::<Vec<_>>()
    };
    assert_eq!(dofs(&a), dofs(&b));
    // Both formats write numbers that read back to the same bits; 1e-15 of
    // each matrix's largest entry states the round-off allowed.
    for (name, x, y) in [
        ("basis", &a.basis, &b.basis),
        ("mass", &a.mass, &b.mass),
        ("stiffness", &a.stiffness, &b.stiffness),
    ] {
        assert_eq!((x.nrows(), x.ncols()), (y.nrows(), y.ncols()), "{name}");
        let d = (x - y).norm_max();
        assert!(d <= 1e-15 * x.norm_max(), "{name}: differs by {d}");
    }
    assert_eq!(a.damping.is_some(), b.damping.is_some());
}

#[test]
fn convert_refuses_what_a_format_cannot_hold() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("body.json");
    let args = |input: &Path, format: &str, out: &Path| {
        vec![
            "convert".to_string(),
            input.display().to_string(),
            "--format".into(),
            format.into(),
            "--out".into(),
            out.display().to_string(),
        ]
    };
    // A SID has no full basis.
    fails_with(
        &args(&py_sid(), "json", &out),
        &[
            "a SID cannot be converted to the json format",
            "flexbody reduce MODEL",
        ],
    );
    assert!(!out.exists());
    // A body's SID needs the model.
    let model = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/side_beam.toml");
    let json = dir.path().join("b.json");
    run_ok(&reduce_args(&model, "craig-bampton", "2", &json, &[]));
    let sid = dir.path().join("b.sid");
    fails_with(
        &args(&json, "sid", &sid),
        &[
            "a reduced body cannot be converted to the sid format",
            "--format sid",
        ],
    );
    assert!(!sid.exists());
}

/// The PY_SID file with `from` replaced by `to` (once), written to
/// `dir/name`; its path, and the 1-based number of the line edited.
fn py_sid_variant(dir: &Path, name: &str, from: &str, to: &str) -> (PathBuf, usize) {
    let text = std::fs::read_to_string(py_sid()).unwrap();
    let at = text.find(from).unwrap_or_else(|| panic!("no '{from}'"));
    let line = text[..at].matches('\n').count() + 1;
    let path = dir.join(name);
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
    (path, line)
}

#[test]
fn broken_py_sid_files_and_unknown_dialects_are_refused_at_their_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let inspect = |path: &Path, needles: &[&str]| {
        fails_with(&["inspect".as_ref(), path.as_os_str()], needles);
    };
    // Truncated inside Gr: the last line is named.
    let text = std::fs::read_to_string(py_sid()).unwrap();
    let gr = text.find("Gr\n").unwrap();
    let cut = gr + text[gr..].find("m0( 2, 2)").unwrap();
    let truncated = d.join("truncated.SID_FEM");
    std::fs::write(&truncated, &text[..cut]).unwrap();
    let last = text[..cut].lines().count();
    inspect(
        &truncated,
        &[&format!(
            "truncated.SID_FEM: line {last}, block 'Gr': the file ends inside block 'Gr'"
        )],
    );
    // nelastq = 2 (with a second name) while the arrays are of one mode:
    // the first block says so.
    let (two, _) = py_sid_variant(
        d,
        "two.SID_FEM",
        "nelastq                         =     1",
        "nelastq = 2\nielastq(2) = Eigen Mode    2 :   9.0 Hz",
    );
    let origin_end = std::fs::read_to_string(&two)
        .unwrap()
        .lines()
        .position(|l| l.trim() == "end origin")
        .unwrap()
        + 1;
    inspect(
        &two,
        &[&format!(
            "line {origin_end}, block 'origin': nq = 1, but refmod has nelastq = 2"
        )],
    );
    // The counts line must match the file: 4 nodes claimed.
    let (counts, _) = py_sid_variant(d, "counts.SID_FEM", "    3   1    :", "    4   1    :");
    inspect(&counts, &["line 1, block 'header': the counts line gives 4 nodes and 1 modes, the file has 3 nodes"]);
    // A block keyword no dialect has.
    let (unknown_block, line) = py_sid_variant(d, "block.SID_FEM", "Gr\n", "Gx\n");
    inspect(
        &unknown_block,
        &[&format!("line {line}, block 'modal': unknown block 'Gx'")],
    );
    // An unknown dialect: neither 'part' nor a counts line then 'part'.
    let (unknown, _) = py_sid_variant(d, "unknown.SID_FEM", " part ", " model ");
    inspect(
        &unknown,
        &[
            "line 2, block 'part': not a SID in a known dialect",
            "found 'model'",
        ],
    );
    let other = d.join("other.sid");
    std::fs::write(&other, "# a comment\n\nmodal\npart\n").unwrap();
    inspect(
        &other,
        &[
            "other.sid: line 3, block 'part': not a SID in a known dialect",
            "found 'modal'",
        ],
    );
    // flexbody's own dialect keeps its strict count: an entry removed from
    // the (converted) PY_SID file is missing, not zero.
    let strict = d.join("strict.sid");
    run_ok(&[
        "convert".as_ref(),
        py_sid().as_os_str(),
        "--format".as_ref(),
        "sid".as_ref(),
        "--out".as_ref(),
        strict.as_os_str(),
    ]);
    let text = std::fs::read_to_string(&strict).unwrap();
    let gone = text.replacen("  m0(1, 2) = ", "# m0(1, 2) = ", 1);
    std::fs::write(&strict, gone).unwrap();
    inspect(&strict, &["m0 entries, expected"]);
}
