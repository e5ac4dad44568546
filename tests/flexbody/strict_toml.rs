//! Strict model files: every table of a model file, of the FE model and of
//! the scenario, refuses a key it does not know, and every enum a value it
//! does not know, naming the key or value, its line, its table and the
//! nearest valid spelling; never a default in its place.

use super::support::{flexbody, reduce_args, stderr};
use flexbody::scenario::{parse_model_file, read_model_file};
use std::path::{Path, PathBuf};

/// A model file with every table: a model of 3D beams, a planar beam, a
/// point mass and springs, a coupling, an equation and an MPC, damping
/// (a tie, which needs a deck's solids, is in `model_constraints.rs`); an interface with force
/// groups, a track, a rigid body, a connection, a study, a simulation with
/// a force history, and an FRF band.
const EVERY_TABLE: &str = r#"title = "Every table of a model file"
nodes = [[6, 2.5, 0.0, 0.0], [7, 3.0, 0.0, 0.0], [8, 3.5, 0.0, 0.0]]

[[material]]
name = "steel"
youngs_modulus = 2.1e11
poisson_ratio = 0.3
density = 7850.0

[[section]]
name = "tube"
shape = "pipe"
radius = 0.05
wall = 0.005

[[section]]
name = "web"
shape = "general"
area = 1e-3
iy = 1e-6
iz = 1e-6
torsion = 2e-6
shear_area_y = 8e-4

[[beam_line]]
element = "beam"
theory = "timoshenko"
from = [0.0, 0.0, 0.0]
to = [2.0, 0.0, 0.0]
elements = 4
first_node = 1
material = "steel"
section = "tube"
orientation = [0.0, 1.0, 0.0]
set = "line"

[[element]]
type = "beam"
id = 101
nodes = [5, 6]
material = "steel"
section = "web"
orientation = [0.0, 1.0, 0.0]
theory = "euler-bernoulli"

[[element]]
type = "planar-beam"
id = 102
nodes = [7, 8]
material = "steel"
section = "tube"

[[element]]
type = "point-mass"
id = 103
node = 6
mass = 10.0
inertia = [0.1, 0.1, 0.1, 0.0, 0.0, 0.0]

[[element]]
type = "spring"
id = 104
dof = { node = 6, dof = "uz" }
to = { node = 7, dof = "uz" }
stiffness = 1.0e6

[sets]
ends = [1, 5]

[[boundary]]
node = 1
dofs = ["ux", "uy", "uz", "rx", "ry", "rz"]

[[coupling]]
name = "tip"
kind = "rigid"
point = 1001
nodes = [4, 5]

[[equation]]
name = "level"
terms = [{ node = 3, dof = "uz", coefficient = 1.0 }, { node = 2, dof = "uz", coefficient = -1.0 }]

[[mpc]]
kind = "beam"
nodes = [2, 3]

[damping]
alpha = 0.1
beta = 1e-5

[interface]
dofs = [{ node = 1001, dof = "uz" }, { node = 8, dof = "uz" }]
force_groups = [{ name = "lift", loads = [{ node = 1001, dof = "uz", value = 1.0 }] }]

[track]
amplitude = 0.01
wavelength = 2.0

[[rigid_body]]
name = "cab"
mass = 100.0
center = [1.0, 0.0, 1.0]
dofs = ["uz"]

[[connection]]
name = "mount"
node = 1001
to = "cab"
direction = [0.0, 0.0, 1.0]
law = "linear"
stiffness = 1.0e5

[study]
omegas = [10.0]
cases = [{ method = "craig-bampton", modes = 2 }]

[simulation]
method = "craig-bampton"
modes = 2
speed = 10.0
duration = 0.01
step = 0.001

[[force]]
name = "push"
node = 6
direction = [0.0, 0.0, 1.0]
harmonic = { amplitude = 1.0, frequency_hz = 5.0 }

[frf]
band_hz = [1.0, 10.0]
points = 5
"#;

/// One misspelling: `from` (once in [`EVERY_TABLE`]) becomes `to`; the
/// error names `needle` (which `to` holds once) at its line, `place`, and
/// suggests `nearest`.
struct Misspelt {
    from: &'static str,
    to: &'static str,
    needle: &'static str,
    place: &'static str,
    nearest: &'static str,
}

const fn m(
    from: &'static str,
    to: &'static str,
    needle: &'static str,
    place: &'static str,
    nearest: &'static str,
) -> Misspelt {
    Misspelt {
        from,
        to,
        needle,
        place,
        nearest,
    }
}

/// A misspelt key of each table of the FE model.
const MODEL_KEYS: &[Misspelt] = &[
    m("title =", "titel =", "titel", "at the top level", "title"),
    m(
        "nodes = [[6",
        "node = [[6",
        "node",
        "at the top level",
        "nodes",
    ),
    m(
        "[damping]",
        "[dampng]",
        "dampng",
        "at the top level",
        "damping",
    ),
    m(
        "poisson_ratio",
        "poisson_ration",
        "poisson_ration",
        "in [[material]] 'steel'",
        "poisson_ratio",
    ),
    m(
        "wall = 0.005",
        "wal = 0.005",
        "wal",
        "in [[section]] 'tube'",
        "wall",
    ),
    m(
        "shear_area_y",
        "shear_area_yy",
        "shear_area_yy",
        "in [[section]] 'web'",
        "shear_area_y",
    ),
    m(
        "first_node",
        "first_nod",
        "first_nod",
        "in [[beam_line]] number 1",
        "first_node",
    ),
    m(
        "orientation = [0.0, 1.0, 0.0]\ntheory",
        "orientaton = [0.0, 1.0, 0.0]\ntheory",
        "orientaton",
        "in [[element]] id 101",
        "orientation",
    ),
    m(
        "section = \"tube\"\n\n",
        "sectoin = \"tube\"\n\n",
        "sectoin",
        "in [[element]] id 102",
        "section",
    ),
    m(
        "inertia = [0.1",
        "inertial = [0.1",
        "inertial",
        "in [[element]] id 103",
        "inertia",
    ),
    m(
        "stiffness = 1.0e6",
        "stifness = 1.0e6",
        "stifness",
        "in [[element]] id 104",
        "stiffness",
    ),
    m(
        "{ node = 7,",
        "{ nod = 7,",
        "nod",
        "in `to` of [[element]] id 104",
        "node",
    ),
    m(
        "ends = [1, 5]\n\n[[boundary]]\nnode",
        "ends = [1, 5]\n\n[[boundary]]\nnoode",
        "noode",
        "in [[boundary]] number 1",
        "node",
    ),
    m(
        "point = 1001",
        "pont = 1001",
        "pont",
        "in [[coupling]] 'tip'",
        "point",
    ),
    m(
        "coefficient = -1.0",
        "coefficent = -1.0",
        "coefficent",
        "in `terms[1]` of [[equation]] 'level'",
        "coefficient",
    ),
    m(
        "nodes = [2, 3]",
        "node = [2, 3]",
        "node",
        "in [[mpc]] number 1",
        "nodes",
    ),
    m(
        "beta = 1e-5",
        "betta = 1e-5",
        "betta",
        "in [damping]",
        "beta",
    ),
];

/// A misspelt key of each table of the scenario.
const SCENARIO_KEYS: &[Misspelt] = &[
    m("[frf]", "[frff]", "frff", "at the top level", "frf"),
    m(
        "force_groups",
        "force_group",
        "force_group",
        "in [interface]",
        "force_groups",
    ),
    m(
        "{ node = 8,",
        "{ nde = 8,",
        "nde",
        "in `dofs[1]` of [interface]",
        "node",
    ),
    m(
        "loads =",
        "load =",
        "load",
        "in `force_groups[0]` of [interface]",
        "loads",
    ),
    m(
        "value = 1.0",
        "valeu = 1.0",
        "valeu",
        "in `force_groups[0].loads[0]` of [interface]",
        "value",
    ),
    m(
        "wavelength",
        "wave_length",
        "wave_length",
        "in [track]",
        "wavelength",
    ),
    m(
        "center",
        "centre",
        "centre",
        "in [[rigid_body]] 'cab'",
        "center",
    ),
    m("law =", "lwa =", "lwa", "in [[connection]] 'mount'", "law"),
    m("omegas", "omega", "omega", "in [study]", "omegas"),
    m(
        "modes = 2 }",
        "mode = 2 }",
        "mode",
        "in `cases[0]` of [study]",
        "modes",
    ),
    m(
        "duration",
        "duraton",
        "duraton",
        "in [simulation]",
        "duration",
    ),
    m(
        "harmonic",
        "harmonc",
        "harmonc",
        "in [[force]] 'push'",
        "harmonic",
    ),
    m(
        "frequency_hz",
        "frequncy_hz",
        "frequncy_hz",
        "in `harmonic` of [[force]] 'push'",
        "frequency_hz",
    ),
    m("points = 5", "pionts = 5", "pionts", "in [frf]", "points"),
];

/// A misspelt value of each enum a model file names.
const VALUES: &[Misspelt] = &[
    m(
        "\"pipe\"",
        "\"pipes\"",
        "pipes",
        "for `shape` in [[section]] 'tube'",
        "pipe",
    ),
    m(
        "\"timoshenko\"",
        "\"timoshenk\"",
        "timoshenk",
        "for `theory` in [[beam_line]] number 1",
        "timoshenko",
    ),
    m(
        "element = \"beam\"",
        "element = \"bem\"",
        "bem",
        "for `element` in [[beam_line]] number 1",
        "beam",
    ),
    m(
        "\"point-mass\"",
        "\"pointmass\"",
        "pointmass",
        "for `type` in [[element]] id 103",
        "point-mass",
    ),
    m(
        "\"euler-bernoulli\"",
        "\"euler-bernouli\"",
        "euler-bernouli",
        "for `theory` in [[element]] id 101",
        "euler-bernoulli",
    ),
    m(
        "dof = \"uz\" }\nto",
        "dof = \"uzz\" }\nto",
        "uzz",
        "for `dof` in `dof` of [[element]] id 104",
        "uz",
    ),
    m(
        "\"uy\", \"uz\"",
        "\"uy\", \"yz\"",
        "yz",
        "for `dofs[2]` in [[boundary]] number 1",
        "uz",
    ),
    m(
        "kind = \"beam\"",
        "kind = \"beem\"",
        "beem",
        "for `kind` in [[mpc]] number 1",
        "beam",
    ),
    m(
        "\"rigid\"",
        "\"rigd\"",
        "rigd",
        "for `kind` in [[coupling]] 'tip'",
        "rigid",
    ),
    m(
        "dofs = [\"uz\"]",
        "dofs = [\"zu\"]",
        "zu",
        "for `dofs[0]` in [[rigid_body]] 'cab'",
        "uz",
    ),
    m(
        "\"craig-bampton\", modes",
        "\"craig-bamton\", modes",
        "craig-bamton",
        "for `method` in `cases[0]` of [study]",
        "craig-bampton",
    ),
    m(
        "\"craig-bampton\"\nmodes",
        "\"craig_bampton\"\nmodes",
        "craig_bampton",
        "for `method` in [simulation]",
        "craig-bampton",
    ),
];

/// [`EVERY_TABLE`] with `case` applied, and the line of its needle
/// (counted here, from where `from` was).
fn misspelt(case: &Misspelt) -> (String, usize) {
    assert_eq!(EVERY_TABLE.matches(case.from).count(), 1, "{}", case.from);
    let start = EVERY_TABLE.find(case.from).unwrap();
    let text = EVERY_TABLE.replacen(case.from, case.to, 1);
    let needle = case.to.find(case.needle).expect("the needle is in `to`");
    (
        text.clone(),
        text[..start + needle].matches('\n').count() + 1,
    )
}

/// Each case is refused, naming its needle as an unknown `what` at its
/// line, its place and its nearest valid spelling.
fn check(cases: &[Misspelt], what: &str) {
    for case in cases {
        let (text, line) = misspelt(case);
        let err = parse_model_file(Path::new("m.toml"), &text)
            .err()
            .unwrap_or_else(|| panic!("`{}` was read", case.to))
            .to_string();
        for needle in [
            format!("m.toml:{line}: unknown {what} `{}`", case.needle),
            case.place.to_string(),
            format!("did you mean `{}`?", case.nearest),
        ] {
            assert!(err.contains(&needle), "expected '{needle}' in: {err}");
        }
    }
}

#[test]
fn the_file_with_every_table_is_read() {
    let file = parse_model_file(Path::new("m.toml"), EVERY_TABLE).unwrap();
    assert!(file.study.is_some() && file.simulation.is_some() && file.frf.is_some());
    assert_eq!(file.rigid_bodies.len(), 1);
    assert_eq!(file.force_groups.len(), 1);
}

#[test]
fn a_misspelt_key_of_every_model_table_is_named_with_line_and_suggestion() {
    check(MODEL_KEYS, "key");
}

#[test]
fn a_misspelt_key_of_every_scenario_table_is_named_with_line_and_suggestion() {
    check(SCENARIO_KEYS, "key");
}

#[test]
fn a_misspelt_value_of_every_enum_is_named_with_line_and_suggestion() {
    check(VALUES, "value");
}

#[test]
fn a_misspelt_force_law_gets_a_suggestion() {
    let text = EVERY_TABLE.replacen("law = \"linear\"", "law = \"linaer\"", 1);
    let err = parse_model_file(Path::new("m.toml"), &text)
        .unwrap_err()
        .to_string();
    assert!(err.contains("unknown law 'linaer'"), "{err}");
    assert!(err.contains("did you mean `linear`?"), "{err}");
}

#[test]
fn a_misspelt_rigid_body_gets_a_suggestion() {
    let text = EVERY_TABLE.replacen("to = \"cab\"", "to = \"cap\"", 1);
    let err = parse_model_file(Path::new("m.toml"), &text)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(
            "goes to 'cap', which is neither ground, track nor a rigid body; did you mean 'cab'?"
        ),
        "{err}"
    );
}

#[test]
fn the_valid_keys_are_listed() {
    let (text, _) = misspelt(&MODEL_KEYS[4]);
    let err = parse_model_file(Path::new("m.toml"), &text)
        .unwrap_err()
        .to_string();
    assert!(err.ends_with("(valid keys: `radius`, `wall`)"), "{err}");
}

#[test]
fn the_cli_refuses_a_misspelt_key_with_exit_code_2_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for (name, case) in [("model", &MODEL_KEYS[5]), ("scenario", &SCENARIO_KEYS[1])] {
        let (text, line) = misspelt(case);
        let model = dir.path().join(format!("{name}.toml"));
        std::fs::write(&model, text).unwrap();
        let out = dir.path().join(format!("{name}.json"));
        let o = flexbody(&reduce_args(&model, "craig-bampton", "2", &out, &[]));
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(!err.contains("panicked"), "{err}");
        let at = format!("{name}.toml:{line}: unknown key `{}`", case.needle);
        assert!(err.contains(&at), "expected '{at}' in: {err}");
        assert!(
            err.contains(&format!("did you mean `{}`?", case.nearest)),
            "{err}"
        );
        assert!(!out.exists(), "{} was written", out.display());
    }
}

/// Every `.toml` file under `dir` but Cargo's, Python packaging's
/// (`pyproject.toml`) and tool configurations.
fn model_files(dir: &Path, found: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            if !name.starts_with('.') && name != "target" {
                model_files(&path, found);
            }
        } else if name.ends_with(".toml")
            && ![
                "Cargo.toml",
                "rustfmt.toml",
                "clippy.toml",
                "deny.toml",
                "rust-toolchain.toml",
                "pyproject.toml",
            ]
            .contains(&name.as_str())
        {
            found.push(path);
        }
    }
}

#[test]
fn every_model_file_in_the_repository_is_read() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    model_files(&root, &mut files);
    // The examples at least.
    for example in ["side_beam.toml", "side_beam_solid.toml", "vehicle.toml"] {
        assert!(
            files
                .iter()
                .any(|f| f.ends_with(Path::new("examples").join(example))),
            "{example} not found in {files:?}"
        );
    }
    for file in &files {
        if let Err(e) = read_model_file(file) {
            panic!("{}: {e}", file.display());
        }
    }
}
