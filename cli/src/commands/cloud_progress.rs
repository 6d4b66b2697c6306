//! The cloud pipeline's progress counts on the command's progress bar: each new stage
//! starts a step, and a stage of several units (range images, extraction passes) shows
//! its count.

use std::sync::Mutex;

use spatch_cloud::{Progress as CloudProgress, Stage};

use crate::progress::Progress;

/// Turns [`CloudProgress`] reports (from any worker thread) into steps and counts.
pub(crate) struct CloudSteps<'a> {
    bar: &'a Progress,
    /// The stage the bar shows now.
    current: Mutex<Option<Stage>>,
}

impl<'a> CloudSteps<'a> {
    /// Reports onto `bar`.
    pub(crate) fn new(bar: &'a Progress) -> Self {
        CloudSteps {
            bar,
            current: Mutex::new(None),
        }
    }

    /// One report of the pipeline: a step when its stage is new, then its count.
    pub(crate) fn report(&self, p: CloudProgress) {
        let mut current = self.current.lock().unwrap_or_else(|e| e.into_inner());
        if *current != Some(p.stage) {
            *current = Some(p.stage);
            self.bar.step(p.stage.name());
        }
        if p.total > 1 {
            self.bar.count(p.done, p.total);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(steps: &CloudSteps<'_>, stage: Stage, done: usize, total: usize) {
        steps.report(CloudProgress { stage, done, total });
    }

    #[test]
    fn a_step_per_stage_however_many_counts_it_reports() {
        let bar = Progress::hidden(4);
        let steps = CloudSteps::new(&bar);
        report(&steps, Stage::Sort, 1, 1);
        for done in 1..=6 {
            report(&steps, Stage::RangeImages, done, 6);
        }
        report(&steps, Stage::Extract, 1, 2);
        report(&steps, Stage::Extract, 2, 2);
        assert_eq!(bar.steps_started(), 3);
    }
}
