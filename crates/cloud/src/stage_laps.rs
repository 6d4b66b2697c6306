//! The conversion's stage clock: consecutive stages timed on one [`StageClock`], each
//! sequential one reported to the progress callback as it ends.

use std::time::Instant;

use spatch_report::StageClock;

use crate::progress::{Progress, ProgressFn, Stage};

/// Times consecutive stages on the shared [`StageClock`] and reports each sequential one as
/// done.
pub(crate) struct StageLaps<'a> {
    last: Instant,
    pub(crate) clock: StageClock,
    pub(crate) progress: ProgressFn<'a>,
}

impl<'a> StageLaps<'a> {
    pub(crate) fn new(progress: ProgressFn<'a>) -> StageLaps<'a> {
        StageLaps {
            last: Instant::now(),
            clock: StageClock::new(),
            progress,
        }
    }

    /// Ends the sequential stage `stage`.
    pub(crate) fn lap(&mut self, stage: Stage) {
        let now = Instant::now();
        self.record(stage.name(), (now - self.last).as_secs_f64());
        self.last = now;
        (self.progress)(Progress {
            stage,
            done: 1,
            total: 1,
        });
    }

    /// Adds `seconds` to the stage `name` (the stages of the tiles alternate), and restarts
    /// the clock.
    pub(crate) fn record(&mut self, name: &'static str, seconds: f64) {
        self.clock.add(name, seconds);
        self.last = Instant::now();
    }
}
