//! Progress of long work from Python: a spinner on stderr with the stage
//! of the linear algebra (ordering, factorising, Lanczos steps) where
//! stderr is a terminal, nothing otherwise (a notebook, a pipe, a log).

use flexbody::linalg::progress::{describe, Progress, Stage};
use std::io::IsTerminal;

/// The spinner of one call; cleared when dropped.
pub struct Spinner(Option<indicatif::ProgressBar>);

impl Spinner {
    /// A spinner saying `what` where stderr is a terminal.
    pub fn new(what: &str) -> Self {
        if !std::io::stderr().is_terminal() {
            return Self(None);
        }
        let bar = indicatif::ProgressBar::new_spinner();
        bar.set_message(what.to_string());
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
        Self(Some(bar))
    }
}

impl Progress for Spinner {
    fn report(&self, stage: &Stage) {
        if let Some(bar) = &self.0 {
            bar.set_message(describe(stage));
        }
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        if let Some(bar) = &self.0 {
            bar.finish_and_clear();
        }
    }
}
