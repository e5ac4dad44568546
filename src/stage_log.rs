//! The command line's view of long work: a spinner on a terminal; in pipes
//! and logs a timed line per stage, at most one every few seconds; every
//! stage with `--verbose`; nothing with `--quiet`. A factorisation shows
//! the percent of its work done and the time left.

use flexbody::linalg::progress::{describe, NoProgress, Progress, Stage};
use std::sync::Arc;

/// The running factorisation, for the percent and the time left of its
/// `Factoring` reports: "factorising K - sigma M, ...: 40 %, about 150 s
/// left".
#[derive(Default)]
struct FactorClock(std::sync::Mutex<Option<Factorizing>>);

struct Factorizing {
    start: std::time::Instant,
    what: String,
    /// Tenths reported so far (the `--verbose` log's steps).
    tenths: u64,
}

impl FactorClock {
    /// The line of `stage`, and for a `Factoring` report whether it starts
    /// a new tenth of the work.
    fn line(&self, stage: &Stage) -> (String, bool) {
        let mut running = self.0.lock().unwrap_or_else(|e| e.into_inner());
        match stage {
            Stage::Factorization { .. } => {
                let what = describe(stage);
                *running = Some(Factorizing {
                    start: std::time::Instant::now(),
                    what: what.clone(),
                    tenths: 0,
                });
                (what, false)
            }
            Stage::Factoring { done, .. } => match running.as_mut() {
                Some(f) => {
                    let seconds = f.start.elapsed().as_secs_f64();
                    let left = seconds * (1.0 - done) / done.max(1e-6);
                    let tenths = (done * 10.0).floor() as u64;
                    let new_tenth = tenths > f.tenths;
                    f.tenths = f.tenths.max(tenths);
                    let line = format!("{}: {:.0} %, about {left:.0} s left", f.what, 100.0 * done);
                    (line, new_tenth)
                }
                None => (describe(stage), false),
            },
            Stage::Factorized { .. } => {
                *running = None;
                (describe(stage), false)
            }
            _ => (describe(stage), false),
        }
    }
}

/// Progress of long linear-algebra work (ordering, factorisation, Lanczos
/// iterations, solves) as a spinner on a terminal; nothing in pipes.
struct Spinner(indicatif::ProgressBar, FactorClock);

impl Progress for Spinner {
    fn report(&self, stage: &Stage) {
        self.0.set_message(self.1.line(stage).0);
        self.0.tick();
    }
}

/// How much the command says about its progress.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Mode {
    /// `--quiet`: nothing.
    Quiet,
    /// A spinner on a terminal, else a line every few seconds.
    Normal,
    /// `--verbose`: every stage, with the resident memory.
    Verbose,
}

impl Mode {
    pub fn of(verbose: bool, quiet: bool) -> Mode {
        match (verbose, quiet) {
            (true, _) => Mode::Verbose,
            (false, true) => Mode::Quiet,
            (false, false) => Mode::Normal,
        }
    }
}

/// Seconds between two progress lines in a pipe or log, unless the
/// environment variable `FLEXBODY_PROGRESS_EVERY` gives another number.
const EVERY_SECONDS: f64 = 3.0;

/// The timed stderr lines of a run: with `--verbose` every stage, with the
/// seconds since the program started and the resident memory (for logs
/// and profiling); otherwise, where stderr is not a terminal, the stage
/// of the moment once at least `every` seconds have passed since the last
/// line (so a short run says nothing).
struct Lines {
    start: std::time::Instant,
    verbose: bool,
    every: f64,
    /// Seconds since `start` of the last line written.
    last: std::sync::Mutex<f64>,
}

impl Lines {
    fn write(&self, line: &str) {
        let now = self.start.elapsed().as_secs_f64();
        if self.verbose {
            eprintln!("[{now:8.2} s {}] {line}", resident_memory());
            return;
        }
        let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
        if now - *last >= self.every {
            *last = now;
            eprintln!("[{now:8.1} s] {line}");
        }
    }
}

/// The log lines of this run, where there are any, for [`step`].
static LINES: std::sync::OnceLock<Lines> = std::sync::OnceLock::new();

/// The spinner of this run on a terminal, for [`step`].
static SPINNER: std::sync::OnceLock<indicatif::ProgressBar> = std::sync::OnceLock::new();

/// Clears the spinner, if there is one, before the command's last words.
pub fn finish() {
    if let Some(bar) = SPINNER.get() {
        bar.finish_and_clear();
    }
}

/// A stage of the command itself (not the linear algebra), e.g. where a
/// reduction ends and its output begins, for the log or the spinner.
pub fn step(line: &str) {
    if let Some(lines) = LINES.get() {
        lines.write(line);
    }
    if let Some(bar) = SPINNER.get() {
        bar.set_message(line.to_string());
    }
}

/// The linear algebra's stages as log lines: a factorisation of a TFlop or
/// more at every tenth with `--verbose`, at every report otherwise (the
/// log keeps one every few seconds).
struct StageLog(FactorClock);

impl Progress for StageLog {
    fn report(&self, stage: &Stage) {
        let (line, new_tenth) = self.0.line(stage);
        let verbose = LINES.get().is_some_and(|l| l.verbose);
        if let Stage::Factoring { flops, .. } = stage {
            if verbose && (!new_tenth || *flops < 1e12) {
                return;
            }
        }
        step(&line);
    }
}

/// Resident and peak memory of this process (Linux `/proc`), e.g.
/// `1.21/2.05 GB`; empty where `/proc` is not there.
fn resident_memory() -> String {
    let gb = |bytes: u64| bytes as f64 / (1u64 << 30) as f64;
    flexbody::linalg::memory::process_memory().map_or(String::new(), |(now, peak)| {
        format!("{:5.2}/{:5.2} GB", gb(now), gb(peak))
    })
}

/// The progress display the library's solvers report to, by `mode`: a
/// spinner on a terminal (stderr), else timed lines; every stage with
/// `--verbose`; nothing when quiet. Dropping it clears the spinner.
pub fn install(mode: Mode, start: std::time::Instant) -> Arc<dyn Progress> {
    use std::io::IsTerminal;
    let log = |verbose: bool| -> Arc<dyn Progress> {
        let every = std::env::var("FLEXBODY_PROGRESS_EVERY")
            .ok()
            .and_then(|v| v.parse::<f64>().ok())
            .filter(|v| v.is_finite() && *v >= 0.0)
            .unwrap_or(EVERY_SECONDS);
        let _ = LINES.set(Lines {
            start,
            verbose,
            every,
            last: std::sync::Mutex::new(0.0),
        });
        Arc::new(StageLog(FactorClock::default()))
    };
    match mode {
        Mode::Quiet => Arc::new(NoProgress),
        Mode::Verbose => log(true),
        Mode::Normal if std::io::stderr().is_terminal() => {
            let bar = indicatif::ProgressBar::new_spinner()
                .with_finish(indicatif::ProgressFinish::AndClear);
            bar.enable_steady_tick(std::time::Duration::from_millis(120));
            let _ = SPINNER.set(bar.clone());
            Arc::new(Spinner(bar, FactorClock::default()))
        }
        Mode::Normal => log(false),
    }
}
