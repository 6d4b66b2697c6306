//! The cloud pipeline's progress counts on the command's progress bar: each new stage
//! starts a step, and a stage of several units (range images, extraction passes) shows
//! its count.

use std::sync::Mutex;

use spatch_cloud::{Progress as CloudProgress, Stage};

use crate::progress::Progress;

/// Turns [`CloudProgress`] reports (from any worker thread) into steps and counts.
pub(crate) struct CloudSteps<'a> {
    bar: &'a Progress,
    /// The stages started so far (the last is the one the bar shows) and the largest
    /// count shown for it.
    shown: Mutex<(Vec<Stage>, usize)>,
}

impl<'a> CloudSteps<'a> {
    /// Reports onto `bar`.
    pub(crate) fn new(bar: &'a Progress) -> Self {
        CloudSteps {
            bar,
            shown: Mutex::new((Vec::new(), 0)),
        }
    }

    /// One report of the pipeline: a step when its stage is new, then its count. Tiles
    /// alternate range images and extraction, and worker threads report out of order, so
    /// only the newest stage's counts are shown, and only growing ones.
    pub(crate) fn report(&self, p: CloudProgress) {
        let mut shown = self.shown.lock().unwrap_or_else(|e| e.into_inner());
        let (stages, largest) = &mut *shown;
        if !stages.contains(&p.stage) {
            stages.push(p.stage);
            *largest = 0;
            self.bar.step(p.stage.name());
        }
        if stages.last() == Some(&p.stage) && p.total > 1 && p.done > *largest {
            *largest = p.done;
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
        report(&steps, Stage::Extract, 1, 4);
        // A second tile's range images: no new step.
        report(&steps, Stage::RangeImages, 1, 6);
        report(&steps, Stage::Extract, 2, 4);
        report(&steps, Stage::Encode, 1, 1);
        assert_eq!(bar.steps_started(), 4);
    }
}
