//! Sizes and work bounded before they are taken: a count in a file's header
//! that the file cannot hold, a range or a line count whose storage would
//! exceed the memory left, a run of more steps, points or included files
//! than any model needs, and a huge line, each refused at once with exit
//! code 2, a short message and little memory, never an abort, a panic or a
//! run until killed.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How a run of the command ended.
struct Run {
    /// Exit code; `None` when killed by a signal (an abort) or at the
    /// deadline.
    code: Option<i32>,
    /// The first 64 KiB of the standard error, and its length.
    stderr: String,
    stderr_bytes: u64,
    /// Peak resident memory (MiB).
    peak_mib: u64,
    timed_out: bool,
}

/// Runs `flexbody args` in `dir`, killed after `limit`, its standard error
/// to a file (a 2 GiB message would fill a pipe).
fn run_within(dir: &Path, args: &[&str], limit: Duration) -> Run {
    let err_path = dir.join("stderr.txt");
    let err_file = std::fs::File::create(&err_path).unwrap();
    // Reaped by `wait4` below, which also gives its peak memory.
    #[allow(clippy::zombie_processes)]
    let mut child = Command::new(env!("CARGO_BIN_EXE_flexbody"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(err_file)
        .spawn()
        .expect("run flexbody");
    let pid = child.id() as libc::pid_t;
    let start = Instant::now();
    let mut status = 0;
    // SAFETY: rusage is plain data, filled in by wait4.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let mut timed_out = false;
    loop {
        // SAFETY: waits for our own child, without blocking.
        let done = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
        if done == pid {
            break;
        }
        if start.elapsed() > limit && !timed_out {
            timed_out = true;
            child.kill().unwrap();
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let stderr_bytes = std::fs::metadata(&err_path).unwrap().len();
    let mut head = Vec::new();
    use std::io::Read;
    std::fs::File::open(&err_path)
        .unwrap()
        .take(1 << 16)
        .read_to_end(&mut head)
        .unwrap();
    Run {
        code: libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status)),
        stderr: String::from_utf8_lossy(&head).into_owned(),
        stderr_bytes,
        peak_mib: usage.ru_maxrss as u64 / 1024,
        timed_out,
    }
}

/// Asserts a refusal: exit code 2 within the deadline, a message of at
/// most `max_bytes` holding each of `needles`, at most `max_mib` resident.
fn refused(run: &Run, needles: &[&str], max_bytes: u64, max_mib: u64) {
    assert!(!run.timed_out, "still running at the deadline");
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    for n in needles {
        assert!(run.stderr.contains(n), "expected '{n}' in: {}", run.stderr);
    }
    assert!(
        run.stderr_bytes <= max_bytes,
        "{} bytes on stderr: {}",
        run.stderr_bytes,
        &run.stderr[..run.stderr.len().min(400)]
    );
    assert!(run.peak_mib <= max_mib, "peak {} MiB", run.peak_mib);
}

const MINUTE: Duration = Duration::from_secs(60);

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn example(name: &str) -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name);
    std::fs::read_to_string(path).unwrap()
}

/// `text` with the one line starting with `key =` replaced by `line`.
fn with_line(text: &str, key: &str, line: &str) -> String {
    let old = text
        .lines()
        .find(|l| l.starts_with(&format!("{key} =")))
        .unwrap_or_else(|| panic!("no '{key} =' line"));
    text.replacen(old, line, 1)
}

/// Matrix Market K and M of two equations with `k_size` as K's size line,
/// and the DOF list, as `info` arguments.
fn matrix_market_info(dir: &Path, k_size: &str) -> Vec<String> {
    let head = "%%MatrixMarket matrix coordinate real symmetric\n";
    let k = write(dir, "k.mtx", &format!("{head}{k_size}\n1 1 4\n2 2 5\n"));
    let m = write(dir, "m.mtx", &format!("{head}2 2 2\n1 1 1\n2 2 1\n"));
    let d = write(dir, "dofs.txt", "1 ux\n1 uy\n");
    [
        "info".into(),
        k.display().to_string(),
        "--mass".into(),
        m.display().to_string(),
        "--dofs".into(),
        d.display().to_string(),
    ]
    .to_vec()
}

fn strs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

#[test]
fn a_matrix_market_entry_count_beyond_the_file_is_refused_before_storage() {
    let dir = tempfile::tempdir().unwrap();
    // usize::MAX entries aborted on "capacity overflow"; 10^9 entries took
    // a 32 GB allocation.
    for count in ["18446744073709551615", "1000000000"] {
        let args = matrix_market_info(dir.path(), &format!("2 2 {count}"));
        let run = run_within(dir.path(), &strs(&args), MINUTE);
        refused(
            &run,
            &[
                "k.mtx:2:",
                &format!("{count} entries announced, but the file of"),
            ],
            400,
            200,
        );
    }
    // The file's own count still reads.
    let args = matrix_market_info(dir.path(), "2 2 2");
    let run = run_within(dir.path(), &strs(&args), MINUTE);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
}

#[test]
fn a_file_of_two_gib_of_nul_bytes_is_refused_after_its_first_mib() {
    let dir = tempfile::tempdir().unwrap();
    let args = matrix_market_info(dir.path(), "2 2 2");
    // A sparse file: 2 GiB long, no disk taken.
    let k = std::fs::File::create(dir.path().join("k.mtx")).unwrap();
    k.set_len(2 << 30).unwrap();
    let run = run_within(dir.path(), &strs(&args), MINUTE);
    refused(
        &run,
        &["k.mtx:1: the line is at least", "\\0\\0\\0"],
        500,
        100,
    );
    // The same for a model file and for the track profile it names.
    let huge = |name: &str| {
        let f = std::fs::File::create(dir.path().join(name)).unwrap();
        f.set_len(2 << 30).unwrap();
    };
    huge("model.toml");
    let run = run_within(dir.path(), &["modes", "model.toml"], MINUTE);
    refused(&run, &["model.toml:1: the line is at least"], 500, 100);
    let vehicle =
        example("vehicle.toml").replace("[simulation]", "[simulation]\nprofile = \"profile.csv\"");
    write(dir.path(), "vehicle.toml", &vehicle);
    huge("profile.csv");
    let run = run_within(
        dir.path(),
        &["simulate", "vehicle.toml", "--out", "run"],
        MINUTE,
    );
    refused(&run, &["profile.csv:1: the line is at least"], 500, 100);
}

#[test]
fn a_deck_name_longer_than_80_characters_is_refused_with_an_excerpt() {
    let dir = tempfile::tempdir().unwrap();
    // A material name of 1 MB was quoted whole by "material '...' is not
    // defined".
    let name = "M".repeat(1_000_000);
    let deck = format!(
        "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*ELEMENT, TYPE=B31, ELSET=E\n1, 1, 2\n\
         *BEAM SECTION, ELSET=E, MATERIAL={name}, SECTION=RECT\n0.1, 0.1\n"
    );
    write(dir.path(), "long.inp", &deck);
    let run = run_within(dir.path(), &["modes", "long.inp"], MINUTE);
    refused(
        &run,
        &["long.inp:6:", "is longer than 80 characters"],
        400,
        200,
    );
}

#[test]
fn a_sid_block_of_4294967296_rows_is_refused_before_storage() {
    let dir = tempfile::tempdir().unwrap();
    let model = super::side_beam_path();
    let sid = dir.path().join("b.sid");
    let args = super::support::reduce_args(&model, "free", "4", &sid, &["--format", "sid"]);
    super::support::run_ok(&args);
    let text = std::fs::read_to_string(&sid).unwrap();
    // The first block (a node's origin, 3 x 1) now says 2^32 rows.
    std::fs::write(&sid, text.replacen("nrow = 3", "nrow = 4294967296", 1)).unwrap();
    let run = run_within(dir.path(), &["inspect", "b.sid"], MINUTE);
    refused(
        &run,
        &[
            "b.sid: line",
            "block 'origin': is 4294967296 x 1, expected 3 x 1",
        ],
        400,
        200,
    );
}

#[test]
fn an_mtx_body_whose_size_line_says_100000_by_100000_is_refused_before_storage() {
    let dir = tempfile::tempdir().unwrap();
    let model = super::side_beam_path();
    let body = dir.path().join("body");
    let args = super::support::reduce_args(&model, "free", "4", &body, &["--format", "mtx"]);
    super::support::run_ok(&args);
    let mass = body.join("mass.mtx");
    let text = std::fs::read_to_string(&mass).unwrap();
    // An array file of 10^10 values in a few hundred bytes, and a
    // coordinate file of none: the dense matrix is 80 GB either way.
    let array = text.replacen("\n4 4\n", "\n100000 100000\n", 1);
    let coordinate = "%%MatrixMarket matrix coordinate real general\n100000 100000 0\n";
    for (content, needle) in [
        (
            array.as_str(),
            "the matrix is 100000 x 100000, the index says 4 x 4",
        ),
        (
            coordinate,
            "the matrix is 100000 x 100000, the index says 4 x 4",
        ),
    ] {
        std::fs::write(&mass, content).unwrap();
        let run = run_within(dir.path(), &["inspect", "body"], MINUTE);
        refused(&run, &["mass.mtx: line", needle], 400, 200);
    }
}

#[test]
fn eight_generate_lines_of_50_million_nodes_are_refused_before_they_are_expanded() {
    let dir = tempfile::tempdir().unwrap();
    // A 400-byte deck that expanded to 400 million set entries (9.6 GB).
    let mut deck =
        String::from("*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*ELEMENT, TYPE=B31, ELSET=B\n1, 1, 2\n");
    for k in 0..8 {
        deck.push_str(&format!("*NSET, NSET=S{k}, GENERATE\n1, 50000000\n"));
    }
    write(dir.path(), "gen.inp", &deck);
    let run = run_within(dir.path(), &["info", "gen.inp"], MINUTE);
    refused(
        &run,
        &[
            "gen.inp:7: GENERATE: 1 to 50000000 in steps of 1 is 50000000 node numbers",
            "the deck's *NODE cards have 2 data lines",
        ],
        400,
        200,
    );
}

#[test]
fn a_beam_line_of_a_billion_elements_is_refused_before_storage() {
    let dir = tempfile::tempdir().unwrap();
    let text = with_line(
        &example("side_beam.toml"),
        "elements",
        "elements = 1000000000",
    );
    write(dir.path(), "beam.toml", &text);
    let run = run_within(dir.path(), &["info", "beam.toml"], MINUTE);
    refused(
        &run,
        &[
            "beam.toml:",
            "beam_line: 1000000000 beam elements (at least 4096 bytes each) needs",
            "more memory",
        ],
        400,
        200,
    );
}

#[test]
fn time_steps_and_frf_points_beyond_any_run_are_refused_when_the_file_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let vehicle = example("vehicle.toml");
    let cases = [
        (
            "step",
            "step = 1e-300",
            "is 1.500e300 steps, more than the 10000000",
        ),
        (
            "duration",
            "duration = 1e99",
            "is 4.000e102 steps, more than the 10000000",
        ),
        (
            "alpha",
            "alpha = -0.05\nadaptive = 1e-300",
            "tolerance 1e-300 is below 1e-12",
        ),
        (
            "points",
            "points = 1000000000",
            "1000000000 points, more than the 10000000",
        ),
    ];
    for (key, line, needle) in cases {
        write(dir.path(), "v.toml", &with_line(&vehicle, key, line));
        let run = run_within(dir.path(), &["info", "v.toml"], MINUTE);
        refused(&run, &["v.toml:", needle], 400, 200);
    }
    // The limit is the file's to raise.
    let raised = with_line(&vehicle, "step", "step = 1e-8\nmax_steps = 200000000");
    write(dir.path(), "v.toml", &raised);
    let run = run_within(dir.path(), &["info", "v.toml"], MINUTE);
    assert_eq!(run.code, Some(0), "{}", run.stderr);
}

#[test]
fn an_include_tree_that_expands_without_end_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    // 13 files, each including the next four times: no cycle, 12 levels
    // deep, 4^12 reads of the last file.
    for k in 0..13 {
        let mut text = format!("** part {k}\n");
        if k < 12 {
            for _ in 0..4 {
                text.push_str(&format!("*INCLUDE, INPUT=p{}.inp\n", k + 1));
            }
        }
        write(dir.path(), &format!("p{k}.inp"), &text);
    }
    write(
        dir.path(),
        "deck.inp",
        "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n*INCLUDE, INPUT=p0.inp\n",
    );
    let run = run_within(dir.path(), &["info", "deck.inp"], MINUTE);
    refused(
        &run,
        &[
            "*INCLUDE of 'p",
            "more than 10000 times",
            "include each file once",
        ],
        600,
        300,
    );
}

#[test]
fn a_device_or_a_pipe_named_by_an_input_is_not_read() {
    let dir = tempfile::tempdir().unwrap();
    // /dev/urandom has no end (its lines are short, so only memory would
    // stop the read); a pipe or a terminal as /dev/stdin waits for input.
    write(dir.path(), "random.inp", "*INCLUDE, INPUT=/dev/urandom\n");
    let run = run_within(dir.path(), &["modes", "random.inp"], MINUTE);
    refused(
        &run,
        &[
            "random.inp:1: *INCLUDE: cannot read '/dev/urandom'",
            "not a regular file",
        ],
        400,
        100,
    );
    let model = example("side_beam_solid.toml");
    let mesh_line = model.lines().find(|l| l.starts_with("mesh =")).unwrap();
    write(
        dir.path(),
        "stdin.toml",
        &model.replacen(mesh_line, "mesh = \"/dev/stdin\"", 1),
    );
    let run = run_within(dir.path(), &["modes", "stdin.toml"], MINUTE);
    refused(&run, &["/dev/stdin", "not a regular file"], 400, 100);
}
