//! Progress of a conversion: counts per stage, for a caller that shows them.
//!
//! [`cloud_to_scene_with_progress`](crate::cloud_to_scene_with_progress) calls the caller's
//! function with a [`Progress`] whenever a unit of work ends: once per sequential stage, once
//! per range image (view of a tile) and once per view and pass of the extraction. Calls may
//! come from worker threads (range images are built in parallel), so the function is `Sync`;
//! `done` only grows within a stage.

use std::sync::atomic::{AtomicUsize, Ordering};

/// A stage of the pipeline, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Stage {
    /// Non-finite points dropped.
    Filter,
    /// Points put in Morton order.
    Sort,
    /// The point spacing estimated.
    Spacing,
    /// Normals (from the file or by PCA).
    Normals,
    /// Points moved onto their block's plane.
    Consensus,
    /// Points assigned to spatial tiles, outliers dropped.
    Tiles,
    /// Range images drawn (one unit per view of each tile).
    RangeImages,
    /// Patches cut (one unit per view, pass and tile).
    Extract,
    /// The `.spatch` bytes encoded.
    Encode,
}

impl Stage {
    /// The stage's name in the report (`range_images`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Stage::Filter => "filter",
            Stage::Sort => "sort",
            Stage::Spacing => "spacing",
            Stage::Normals => "normals",
            Stage::Consensus => "consensus",
            Stage::Tiles => "tiles",
            Stage::RangeImages => "range_images",
            Stage::Extract => "extract",
            Stage::Encode => "encode",
        }
    }
}

/// How far one stage has come.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// The stage.
    pub stage: Stage,
    /// Units done (`1..=total`).
    pub done: usize,
    /// Units the stage has.
    pub total: usize,
}

/// A caller's progress function (see the module documentation).
pub type ProgressFn<'a> = &'a (dyn Fn(Progress) + Sync);

/// Counts the units of one stage and reports each to a `ProgressFn`.
pub(crate) struct StageCounter<'a> {
    stage: Stage,
    total: usize,
    done: AtomicUsize,
    report: ProgressFn<'a>,
}

impl<'a> StageCounter<'a> {
    /// A counter of `total` units of `stage`.
    pub(crate) fn new(stage: Stage, total: usize, report: ProgressFn<'a>) -> Self {
        StageCounter {
            stage,
            total,
            done: AtomicUsize::new(0),
            report,
        }
    }

    /// One more unit done.
    pub(crate) fn step(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        (self.report)(Progress {
            stage: self.stage,
            done: done.min(self.total),
            total: self.total,
        });
    }
}
