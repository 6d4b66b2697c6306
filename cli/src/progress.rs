//! Progress on standard error: a bar with counts, elapsed time and an ETA,
//! shown only when standard error is a terminal and `-q` was not given.
//!
//! A command's work is a list of named steps (the pipeline's stages); the
//! bar counts them (`[3/9] segment`) and, inside a step whose library
//! reports counts (frames rendered, views measured, scenes read, patches
//! fitted), counts those instead (`fit 120/400`), with an ETA from the
//! rate so far.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// Set by `-q/--quiet`: no progress and no summary.
static QUIET: AtomicBool = AtomicBool::new(false);

/// Records `-q/--quiet` for the whole run.
pub(crate) fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Whether `-q/--quiet` was given.
pub(crate) fn is_quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// The bar's layout: what, position of length, the current step, times.
const TEMPLATE: &str =
    "{prefix}: [{bar:24}] {pos}/{len} {msg} ({elapsed_precise}, ETA {eta_precise})";

/// A progress bar on standard error, or nothing when it would not be seen.
pub(crate) struct Progress {
    bar: Option<ProgressBar>,
    /// Steps of the whole command (the bar's length between counted steps).
    steps: u64,
    /// Steps started so far.
    step: AtomicU64,
}

impl Progress {
    /// A bar labelled `what` over `steps` named steps; nothing when standard
    /// error is not a terminal or the run is quiet.
    pub(crate) fn new(what: &str, steps: usize) -> Self {
        let shown = !is_quiet() && std::io::stderr().is_terminal();
        Self::shown_if(shown, what, steps)
    }

    /// The bar when `shown`, else the silent one (tests use both).
    fn shown_if(shown: bool, what: &str, steps: usize) -> Self {
        let steps = steps.max(1) as u64;
        let bar = shown.then(|| {
            let bar = ProgressBar::new(steps);
            if let Ok(style) = ProgressStyle::with_template(TEMPLATE) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_prefix(what.to_owned());
            bar.enable_steady_tick(Duration::from_millis(200));
            bar
        });
        Self {
            bar,
            steps,
            step: AtomicU64::new(0),
        }
    }

    /// Starts the next step, named `name`: the bar counts steps again.
    pub(crate) fn step(&self, name: &str) {
        let done = self.step.fetch_add(1, Ordering::Relaxed);
        if let Some(bar) = &self.bar {
            // Position first: a draw between the two never shows a count past the length.
            bar.set_position(done);
            bar.set_length(self.steps.max(done + 1));
            bar.reset_eta();
            bar.set_message(name.to_owned());
        }
    }

    /// Inside the current step, `done` of `total` items are finished: the bar
    /// counts items until the next step. Callable from worker threads.
    pub(crate) fn count(&self, done: usize, total: usize) {
        if let Some(bar) = &self.bar {
            if bar.length() != Some(total as u64) {
                bar.set_length(total as u64);
                bar.reset_eta();
            }
            bar.set_position(done as u64);
        }
    }

    /// A bar that is never drawn, over `steps` steps (for other modules' tests).
    #[cfg(test)]
    pub(crate) fn hidden(steps: usize) -> Self {
        Self::shown_if(false, "test", steps)
    }

    /// Whether the bar is drawn (a terminal, not quiet).
    #[cfg(test)]
    fn is_shown(&self) -> bool {
        self.bar.is_some()
    }

    /// Steps started so far.
    #[cfg(test)]
    pub(crate) fn steps_started(&self) -> u64 {
        self.step.load(Ordering::Relaxed)
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hidden_bar_counts_steps_and_draws_nothing() {
        let progress = Progress::shown_if(false, "x", 3);
        progress.step("load");
        progress.count(5, 10);
        progress.step("write");
        assert!(!progress.is_shown());
        assert_eq!(progress.steps_started(), 2);
    }

    #[test]
    fn a_shown_bar_switches_between_steps_and_counts() {
        let progress = Progress::shown_if(true, "x", 4);
        let bar = progress.bar.clone().expect("shown");
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
        progress.step("load");
        assert_eq!((bar.position(), bar.length()), (0, Some(4)));
        progress.step("fit");
        progress.count(30, 120);
        assert_eq!((bar.position(), bar.length()), (30, Some(120)));
        progress.step("encode");
        assert_eq!((bar.position(), bar.length()), (2, Some(4)));
        // More steps than announced stretch the bar instead of overflowing it.
        progress.step("a");
        progress.step("b");
        assert_eq!((bar.position(), bar.length()), (4, Some(5)));
    }
}
