//! What a spatch pipeline reports about its run, in the pieces every
//! pipeline (`spatch-convert`, `spatch-cloud`) and the shared JSON report
//! (`spatch-eval`, docs/report-schema.md) have in common: the sizes of the
//! scene it wrote ([`Counts`]) and the wall time of each of its stages
//! ([`StageTime`]), kept by one [`StageClock`] in both pipelines.
//!
//! ```
//! use spatch_report::{Counts, StageTime};
//! # use glam::{DVec3, Vec3};
//! # use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};
//! # let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01)?;
//! # let patch = Patch::new(frame, GridSize::new(3, 3)?, vec![0; 9], None)?;
//! # let scene = Scene::new(DVec3::ZERO, ColourChannel::None, vec![patch])?;
//! let counts = Counts::of(&scene, 120);
//! assert_eq!((counts.patches, counts.nodes, counts.filled_nodes), (1, 9, 9));
//! let stage = StageTime { name: "encode", seconds: 0.002 };
//! assert_eq!(stage.name, "encode");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

use serde::{Deserialize, Serialize};
use spatch_format::Scene;

/// Sizes of a scene and of its encoded file.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    /// Patches.
    pub patches: usize,
    /// Grid nodes of all patches, filled or not.
    pub nodes: usize,
    /// Non-empty nodes.
    pub filled_nodes: usize,
    /// Bytes of the encoded `.spatch` file.
    pub bytes: usize,
}

impl Counts {
    /// The counts of `scene`, encoded in `bytes` bytes.
    pub fn of(scene: &Scene, bytes: usize) -> Self {
        Self {
            patches: scene.patches().len(),
            nodes: scene.node_count(),
            filled_nodes: scene.filled_node_count(),
            bytes,
        }
    }
}

/// Wall time of one stage of a pipeline.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StageTime {
    /// Stage name, e.g. `load`, `segment`, `range_images` or `encode`.
    pub name: &'static str,
    /// Wall time in seconds.
    pub seconds: f64,
}

/// The wall time of a pipeline's stages, in the order they first ran: the one stage clock
/// of the mesh (`spatch-convert`) and point-cloud (`spatch-cloud`) pipelines.
///
/// A stage that runs in several pieces (the cloud's range images and extraction, tile by
/// tile) adds up under one name.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StageClock {
    stages: Vec<StageTime>,
}

impl StageClock {
    /// A clock with no stage yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs `work` as stage `name` and records its wall time.
    pub fn time<T>(&mut self, name: &'static str, work: impl FnOnce() -> T) -> T {
        let start = std::time::Instant::now();
        let out = work();
        self.add(name, start.elapsed().as_secs_f64());
        out
    }

    /// Adds `seconds` to stage `name` (a new stage goes last).
    pub fn add(&mut self, name: &'static str, seconds: f64) {
        match self.stages.iter_mut().find(|s| s.name == name) {
            Some(stage) => stage.seconds += seconds,
            None => self.stages.push(StageTime { name, seconds }),
        }
    }

    /// The stages so far.
    pub fn stages(&self) -> &[StageTime] {
        &self.stages
    }

    /// The sum of the stages' times (seconds).
    pub fn total(&self) -> f64 {
        self.stages.iter().map(|s| s.seconds).sum()
    }

    /// The stages, in order.
    pub fn into_stages(self) -> Vec<StageTime> {
        self.stages
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};
    use spatch_format::{ColourChannel, Frame, GridSize, Patch, EMPTY};

    #[test]
    fn a_stage_in_pieces_adds_up_in_first_run_order() {
        let mut clock = StageClock::new();
        assert_eq!(clock.time("load", || 7), 7);
        clock.add("extract", 0.25);
        clock.add("range_images", 0.5);
        clock.add("extract", 0.25);
        let names: Vec<&str> = clock.stages().iter().map(|s| s.name).collect();
        assert_eq!(names, ["load", "extract", "range_images"]);
        assert_eq!(clock.stages()[1].seconds, 0.5);
        let load = clock.stages()[0].seconds;
        assert!(load >= 0.0);
        // The total sums the stages in their order, so the expectation adds in that order.
        assert_eq!(clock.total(), load + 0.5 + 0.5);
        assert_eq!(clock.into_stages().len(), 3);
    }

    #[test]
    fn counts_of_a_scene_leave_out_empty_nodes_and_serialize_flat() {
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01).unwrap();
        let grid = GridSize::new(3, 2).unwrap();
        let patch = |empty: usize| {
            let mut d = vec![5u16; 6];
            d[..empty].fill(EMPTY);
            Patch::new(frame, grid, d, None).unwrap()
        };
        let scene = Scene::new(DVec3::ZERO, ColourChannel::None, vec![patch(0), patch(2)]).unwrap();
        let counts = Counts::of(&scene, 77);
        assert_eq!(
            counts,
            Counts {
                patches: 2,
                nodes: 12,
                filled_nodes: 10,
                bytes: 77
            }
        );
        let json = serde_json::to_string(&counts).unwrap();
        assert_eq!(
            json,
            r#"{"patches":2,"nodes":12,"filled_nodes":10,"bytes":77}"#
        );
        assert_eq!(serde_json::from_str::<Counts>(&json).unwrap(), counts);
    }
}
