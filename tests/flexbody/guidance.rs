//! What the command line tells a user who has not read the manual: a study
//! that cannot measure anything is refused, a failing case is reported
//! without hiding the others, a missing choice is named with the option
//! that makes it, and every file written is announced.

use super::support::{
    fails_with, flexbody, mid_span_interface, reduce_args, run_ok, stderr, variant,
};

/// The study table's rows on stdout, as lines.
fn stdout_lines(o: &std::process::Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(str::to_owned)
        .collect()
}

#[test]
fn a_study_with_nothing_that_excites_the_model_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // The side beam on its springs, but the primary springs go to ground:
    // nothing moves, and every error would print as 0.
    let text = super::side_beam_text().replace("to = \"track\"", "to = \"ground\"");
    let grounded = dir.path().join("grounded.toml");
    std::fs::write(&grounded, text).unwrap();
    fails_with(
        &["study", grounded.to_str().unwrap(), "--no-plots"],
        &["grounded.toml", "nothing to compare", "to = \"track\""],
    );
    // A track that does not move.
    let still = variant(
        dir.path(),
        "still.toml",
        "amplitude = 1.0",
        "amplitude = 0.0",
    );
    fails_with(
        &["study", &still, "--no-plots"],
        &["still.toml", "amplitude is 0"],
    );
    // Track springs without stiffness: connected, yet the full model
    // does not move.
    let loose = super::side_beam_text().replacen(
        "to = \"track\"\ndirection = [0.0, 0.0, 1.0]\nstiffness = 1.0e6",
        "to = \"track\"\ndirection = [0.0, 0.0, 1.0]\nstiffness = 0.0",
        2,
    );
    let loose_path = dir.path().join("loose.toml");
    std::fs::write(&loose_path, loose).unwrap();
    fails_with(
        &["study", loose_path.to_str().unwrap(), "--no-plots"],
        &["loose.toml", "response is zero at every Omega"],
    );
}

#[test]
fn a_failing_case_is_reported_and_the_others_still_run() {
    let dir = tempfile::tempdir().unwrap();
    // An interface at mid-span only: held there, the beam is a mechanism,
    // so the Craig-Bampton cases fail; the free cases do not need it.
    let m = mid_span_interface(dir.path());
    let o = flexbody(&["study", &m, "--no-plots"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let lines = stdout_lines(&o);
    let rows = |method: &str| {
        lines
            .iter()
            .filter(|l| l.split_whitespace().next() == Some(method))
            .cloned()
            .collect::<Vec<_>>()
    };
    // Both free cases with two frequencies each ran to the end.
    assert_eq!(rows("free").len(), 6, "{lines:#?}");
    assert!(rows("free").iter().all(|l| !l.contains("FAILED")));
    // Each Craig-Bampton case is one failed row naming the mechanism.
    let cb = rows("craig-bampton");
    assert_eq!(cb.len(), 2, "{lines:#?}");
    assert!(cb
        .iter()
        .all(|l| l.contains("FAILED: the interface DOFs (node 11 uz) leave a mechanism")));
    let err = stderr(&o);
    assert!(err.contains("study cases failed"), "{err}");

    // The HTML report lists them too, and the command names the page.
    let page = dir.path().join("report.html");
    let o = flexbody(&[
        "study",
        &m,
        "--no-plots",
        "--report",
        page.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stdout).contains("report: "));
    let html = std::fs::read_to_string(&page).unwrap();
    let failed = &html[html
        .find("<h2>Failed cases</h2>")
        .expect("a failed-cases list")..];
    assert!(failed.contains(
        "craig-bampton, 13 eigenmodes</b>: the interface DOFs (node 11 uz) leave a mechanism"
    ));

    // --json lists the failures beside the rows.
    let o = flexbody(&["study", &m, "--no-plots", "--json"]);
    assert_eq!(o.status.code(), Some(2));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let failed = doc["failed"].as_array().unwrap();
    assert!(failed
        .iter()
        .any(|f| f["method"] == "craig-bampton"
            && f["error"].as_str().unwrap().contains("mechanism")));
    assert!(!doc["cases"].as_array().unwrap().is_empty());
}

/// The hex beam deck (6 C3D8, 0.6 m along x) with a kinematic coupling at
/// each end face, reference nodes 9001 (x = 0) and 9002 (x = 0.6), and
/// its nodes at x = 0.1 held when `clamped`.
fn two_point_deck(dir: &std::path::Path, clamped: bool) -> String {
    let text = std::fs::read_to_string(super::support::hex_beam_deck()).unwrap();
    let step = text.find("*STEP").unwrap();
    let bc = if clamped {
        "*NSET, NSET=NEAR\n3, 29, 81, 107\n*BOUNDARY\nNEAR, 1, 3\n"
    } else {
        ""
    };
    let deck = format!(
        "{}*NODE\n9001, 0.0, 0.05, 0.05\n9002, 0.6, 0.05, 0.05\n\
         *NSET, NSET=LEFT\n1, 27, 79, 105\n*NSET, NSET=RIGHT\n13, 39, 91, 117\n\
         *SURFACE, NAME=SLEFT, TYPE=NODE\nLEFT\n*SURFACE, NAME=SRIGHT, TYPE=NODE\nRIGHT\n\
         *COUPLING, REF NODE=9001, SURFACE=SLEFT, CONSTRAINT NAME=C_LEFT\n*KINEMATIC\n1, 6\n\
         *COUPLING, REF NODE=9002, SURFACE=SRIGHT, CONSTRAINT NAME=C_RIGHT\n*KINEMATIC\n1, 6\n\
         {bc}{}",
        &text[..step],
        &text[step..]
    );
    let path = dir.join(if clamped {
        "clamped.inp"
    } else {
        "two_point.inp"
    });
    std::fs::write(&path, deck).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn coupling_reference_nodes_are_the_default_interface_and_the_command_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let deck = two_point_deck(dir.path(), false);
    let out = dir.path().join("cb.json");
    let o = run_ok(&reduce_args(&deck, "craig-bampton", "2", &out, &[]));
    let err = stderr(&o);
    assert!(
        err.contains("interface: the reference nodes of the couplings (node 9001, 9002)"),
        "{err}"
    );
    // Both points held with all six DOFs: r = 2 + 12, and the body's
    // interface is what --interface 9001,9002 gives.
    let named = dir.path().join("named.json");
    run_ok(&reduce_args(
        &deck,
        "craig-bampton",
        "2",
        &named,
        &["--interface", "9001,9002"],
    ));
    let inspect = |p: &std::path::Path| {
        let o = run_ok(&["inspect", p.to_str().unwrap(), "--json"]);
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let (by_default, by_name) = (inspect(&out), inspect(&named));
    assert_eq!(by_default["r"], 14);
    assert_eq!(by_default["interface_dofs"], by_name["interface_dofs"]);
    assert_eq!(
        by_default["interface_nodes"],
        serde_json::json!([9001, 9002])
    );
    assert_eq!(by_default["frequencies_hz"], by_name["frequencies_hz"]);
}

#[test]
fn a_missing_interface_or_a_wrong_set_name_says_what_to_give() {
    let deck = super::support::hex_beam_deck();
    let deck = deck.to_str().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("b.json");
    let out = out.to_str().unwrap();
    // No couplings and no interface: the option that gives one is named.
    fails_with(
        &[
            "reduce",
            deck,
            "--method",
            "craig-bampton",
            "--modes",
            "2",
            "--out",
            out,
        ],
        &[
            "needs interface DOFs",
            "--interface",
            "the model has no node sets",
        ],
    );
    // A wrong set name lists the sets there are.
    let coupled = two_point_deck(dir.path(), false);
    fails_with(
        &[
            "reduce",
            &coupled,
            "--method",
            "guyan",
            "--interface",
            "LEFTT",
            "--out",
            out,
        ],
        &[
            "'LEFTT' is neither a node set nor a node number",
            "LEFT (4 nodes)",
            "RIGHT (4 nodes)",
        ],
    );
}

#[test]
fn reduce_needs_a_number_of_modes_except_for_guyan() {
    let dir = tempfile::tempdir().unwrap();
    let deck = two_point_deck(dir.path(), false);
    let out = dir.path().join("b.json");
    let out = out.to_str().unwrap();
    // Without --modes, a method with eigenmodes asks for them (it used to
    // take 0 silently).
    fails_with(
        &["reduce", &deck, "--method", "craig-bampton", "--out", out],
        &["needs --modes N", "--fmax F"],
    );
    // Guyan takes none: static condensation on the 12 interface DOFs.
    run_ok(&["reduce", &deck, "--method", "guyan", "--out", out]);
    let o = run_ok(&["inspect", out, "--json"]);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["method"], "guyan");
    assert_eq!(doc["r"], 12);
}

#[test]
fn help_explains_the_methods_and_stays_short() {
    let o = run_ok(&["reduce", "--help"]);
    let help = String::from_utf8_lossy(&o.stdout).into_owned();
    for method in [
        "free",
        "craig-bampton",
        "elastic-residual",
        "free-residual",
        "guyan",
    ] {
        assert!(
            help.lines().any(|l| l.trim_start().starts_with(method)),
            "no line on {method} in:\n{help}"
        );
    }
    assert!(help.contains("JSON, SID or Matrix Market"), "{help}");
    // The global options' texts are a line each, not a paragraph repeated
    // in every subcommand (an option's block ends at a blank line).
    let block = |name: &str| {
        let start = help
            .find(name)
            .unwrap_or_else(|| panic!("{name} in {help}"));
        let rest = &help[start..];
        rest[..rest.find("\n\n").unwrap_or(rest.len())].to_string()
    };
    assert!(
        block("--max-memory").len() < 200,
        "{}",
        block("--max-memory")
    );
    assert!(
        block("--allow-unknown").len() < 200,
        "{}",
        block("--allow-unknown")
    );
}

#[test]
fn inspect_prints_json_that_agrees_with_its_text() {
    let dir = tempfile::tempdir().unwrap();
    let deck = two_point_deck(dir.path(), false);
    let out = dir.path().join("body.json");
    let out = out.to_str().unwrap();
    run_ok(&reduce_args(&deck, "free-residual", "3", out, &[]));
    let text = String::from_utf8_lossy(&run_ok(&["inspect", out]).stdout).into_owned();
    let doc: serde_json::Value =
        serde_json::from_slice(&run_ok(&["inspect", out, "--json"]).stdout).unwrap();
    assert_eq!(doc["method"], "free-residual");
    let r = doc["r"].as_u64().unwrap();
    assert!(text.contains(&format!("r: {r}")), "{text}");
    // The hex beam: 0.6 x 0.1 x 0.1 m of steel (7850 kg/m^3).
    let mass = doc["mass_kg"].as_f64().unwrap();
    assert!(
        (mass - 0.6 * 0.1 * 0.1 * 7850.0).abs() < 1e-9 * mass,
        "{mass}"
    );
    let f = doc["frequencies_hz"].as_array().unwrap();
    assert_eq!(f.len() as u64, r);
    // The rigid-body modes come first, at zero frequency.
    assert!(f[..6].iter().all(|x| x.as_f64().unwrap().abs() < 1e-3));
}

#[test]
fn info_lists_sets_couplings_materials_sections_fixed_dofs_and_the_full_mass() {
    let dir = tempfile::tempdir().unwrap();
    let deck = two_point_deck(dir.path(), true);
    let o = run_ok(&["info", &deck]);
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    for needle in [
        "node sets: LEFT (4 nodes), NEAR (4 nodes), RIGHT (4 nodes)",
        "element sets: EALL (6 elements)",
        "C_LEFT (kinematic, reference node 9001, 4 nodes)",
        "C_RIGHT (kinematic, reference node 9002, 4 nodes)",
        "materials: STEEL (E 2.1e11 Pa, nu 3e-1, density 7.85e3 kg/m^3)",
        "sections: *SOLID SECTION on EALL (6 elements), material STEEL",
        "fixed DOFs: ",
    ] {
        assert!(text.contains(needle), "'{needle}' not in:\n{text}");
    }
    // Held at x = 0.1, the free DOFs carry less than the whole mass; the
    // full mass is the whole beam's.
    let numbers = |prefix: &str| -> Vec<f64> {
        let line = text.lines().find(|l| l.starts_with(prefix)).unwrap();
        line.rsplit(": ")
            .next()
            .unwrap()
            .split(", ")
            .map(|v| v.parse().unwrap())
            .collect()
    };
    let whole = 0.6 * 0.1 * 0.1 * 7850.0;
    let full = numbers("full mass along x, y, z");
    assert!(
        full.iter().all(|m| (m - whole).abs() < 1e-9 * whole),
        "{full:?}"
    );
    let free = numbers("mass along x, y, z (kg), free DOFs");
    assert!(free.iter().all(|m| *m < 0.95 * whole), "{free:?}");
}

#[test]
fn progress_lines_reach_logs_and_quiet_silences_them() {
    let dir = tempfile::tempdir().unwrap();
    let deck = two_point_deck(dir.path(), false);
    // stderr is a pipe here, as in a log; lines every 0 s instead of 3 s
    // so that a short run shows them.
    let run = |quiet: bool| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_flexbody"));
        cmd.env("FLEXBODY_PROGRESS_EVERY", "0")
            .args(["modes", &deck, "--count", "4"]);
        if quiet {
            cmd.arg("--quiet");
        }
        let o = cmd.output().unwrap();
        assert!(o.status.success());
        stderr(&o)
    };
    let log = run(false);
    let lines: Vec<&str> = log.lines().filter(|l| l.starts_with('[')).collect();
    assert!(lines.len() >= 2, "{log}");
    // Each line starts with the seconds since the start.
    for l in &lines {
        let seconds = l[1..].split(" s]").next().unwrap().trim();
        assert!(seconds.parse::<f64>().is_ok(), "{l}");
    }
    assert!(log.contains("ordering 72 equations"), "{log}");
    assert!(run(true).lines().all(|l| !l.starts_with('[')));
}

#[test]
fn simulate_frf_and_mtx_bodies_announce_every_file_they_write() {
    let dir = tempfile::tempdir().unwrap();
    let vehicle =
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples/vehicle.toml");
    let out = dir.path().join("frf");
    let o = run_ok(&[
        "frf",
        vehicle.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let said = String::from_utf8_lossy(&o.stdout).into_owned();
    for file in std::fs::read_dir(&out).unwrap() {
        let name = file.unwrap().file_name().to_string_lossy().into_owned();
        assert!(said.contains(&name), "{name} not announced in:\n{said}");
    }
    let deck = two_point_deck(dir.path(), false);
    let body = dir.path().join("body.mtx");
    let o = run_ok(&reduce_args(
        &deck,
        "guyan",
        "0",
        &body,
        &["--format", "mtx"],
    ));
    let said = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(body.is_dir());
    assert!(said.contains("body.mtx (a folder"), "{said}");
}

#[test]
fn the_test_command_ends_with_one_summary_over_all_test_groups() {
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/test.sh");
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("cargo.log");
    let summarize = |text: &str| {
        std::fs::write(&log, text).unwrap();
        let o = std::process::Command::new("bash")
            .arg(&script)
            .arg("--summarize")
            .arg(&log)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).trim().to_string(),
        )
    };
    // Two groups as cargo prints them, the last a crate's doc tests.
    let passing = "running 3 tests\n\
        test result: ok. 3 passed; 0 failed; 1 ignored; 0 measured; 0 filtered out; finished in 0.10s\n\
        Doc-tests flexbody_fem\n\
        test result: ok. 0 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; finished in 0.00s\n";
    assert_eq!(
        summarize(passing),
        (
            Some(0),
            "all tests: 3 passed, 0 failed, 1 ignored (2 test groups)".into()
        )
    );
    let failing = format!(
        "{passing}test result: FAILED. 5 passed; 2 failed; 0 ignored; 0 measured; 0 filtered out; finished in 1.00s\n"
    );
    assert_eq!(
        summarize(&failing),
        (
            Some(1),
            "all tests: 8 passed, 2 failed, 1 ignored (3 test groups)".into()
        )
    );
}

#[test]
fn routine_skipped_keywords_take_one_line_so_that_warnings_stand_out() {
    let deck = super::support::hex_beam_deck();
    let o = run_ok(&["modes", deck.to_str().unwrap(), "--count", "2", "--quiet"]);
    let err = stderr(&o);
    // *STEP, *FREQUENCY and *END STEP: one note, no warning.
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].starts_with("note: "), "{err}");
    for keyword in [
        "*STEP (line 45)",
        "*FREQUENCY (line 46)",
        "*END STEP (line 48)",
    ] {
        assert!(lines[0].contains(keyword), "{keyword} in {err}");
    }
    // A misspelt keyword is no note but an error naming the nearest one.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(&deck)
        .unwrap()
        .replace("*STEP\n*FREQUENCY\n", "*STEP\n*FREQENCY\n");
    let bad = dir.path().join("bad.inp");
    std::fs::write(&bad, text).unwrap();
    fails_with(
        &["modes", bad.to_str().unwrap()],
        &["bad.inp:46", "*FREQENCY", "*FREQUENCY"],
    );
}

#[test]
fn info_lists_what_a_model_file_and_its_deck_define() {
    // Beam lines: the file's own materials and sections, by name.
    let o = run_ok(&["info", super::side_beam_path().to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    for needle in [
        "node sets: beam (21 nodes), seats (4 nodes)",
        "materials: steel (E 2.1e11 Pa, nu 3e-1, density 6.8e3 kg/m^3)",
        "sections: box (20 elements), material steel",
    ] {
        assert!(text.contains(needle), "'{needle}' not in:\n{text}");
    }
    // A model file around a deck: the deck's sets, couplings, material and
    // section, as `info` on the deck itself lists them.
    let solid = super::support::solid_side_beam();
    let o = run_ok(&["info", solid.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let deck = solid.with_extension("inp");
    let o = run_ok(&["info", deck.to_str().unwrap()]);
    let deck_text = String::from_utf8_lossy(&o.stdout).into_owned();
    for prefix in ["element sets: ", "materials: ", "sections: ", "node sets: "] {
        let line = |t: &str| t.lines().find(|l| l.starts_with(prefix)).map(str::to_owned);
        assert_eq!(line(&text), line(&deck_text), "{prefix}");
        assert!(
            line(&text).is_some_and(|l| !l.ends_with("none")),
            "{prefix}: {text}"
        );
    }
    assert!(
        text.contains("primary_front (distributing, reference node 1001, 12 nodes)"),
        "{text}"
    );
}

/// The text of the repository's `path`.
fn repository_file(path: &str) -> String {
    std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)).unwrap()
}

#[test]
fn the_readme_synopsis_names_only_options_the_commands_take() {
    let readme = repository_file("README.md");
    // How to put the binary on the PATH.
    assert!(readme.contains("cargo install --path ."));
    // The synopsis block under "## Commands": every option of every line
    // is in that command's --help.
    let commands = &readme[readme.find("## Commands").unwrap()..];
    let block = &commands[commands.find("```sh\n").unwrap() + 6..];
    let block = &block[..block.find("```").unwrap()];
    let mut command = String::new();
    let mut checked = 0;
    for line in block.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        if words.first() == Some(&"flexbody") {
            command = words[1].to_string();
        }
        let help =
            String::from_utf8_lossy(&run_ok(&[command.as_str(), "--help"]).stdout).into_owned();
        for option in words.iter().filter_map(|w| {
            let w = w.trim_start_matches('[');
            w.starts_with("--")
                .then(|| w.trim_end_matches([']', ',']).split('|').next().unwrap())
        }) {
            assert!(
                help.contains(option),
                "README: `flexbody {command} {option}` is not in its --help"
            );
            checked += 1;
        }
    }
    assert!(checked >= 20, "{checked} options checked");
}

#[test]
fn examples_point_only_to_files_in_the_repository() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for entry in std::fs::read_dir(root.join("examples")).unwrap() {
        let path = entry.unwrap().path();
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue;
        };
        for word in text.split(|c: char| c.is_whitespace() || "()`\"',;".contains(c)) {
            let word = word.trim_end_matches(['.', ':']);
            if word.ends_with(".md") {
                assert!(
                    root.join(word).exists() || path.parent().unwrap().join(word).exists(),
                    "{} cites {word}, which is not in the repository",
                    path.display()
                );
            }
        }
    }
}
