//! `spatch render --bench N`: N frames after a warm-up, the median and the
//! minimum per frame and per stage (the planning's stages with
//! `--stage-times` or `--stats`).

use std::collections::BTreeMap;

use serde::Serialize;
use spatch_render::{Camera, PreparedScene, RenderStats, Renderer};

use crate::failure::render_failure;

/// Median and minimum of one stage over the frames, in milliseconds.
#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct StageTimes {
    pub(crate) median_ms: f64,
    pub(crate) min_ms: f64,
}

/// What `--bench` measured.
#[derive(Debug, Clone, Serialize)]
pub(crate) struct BenchReport {
    /// Frames timed (after the warm-up).
    pub(crate) frames: usize,
    /// Worker threads.
    pub(crate) threads: usize,
    /// `WIDTHxHEIGHT`.
    pub(crate) size: String,
    /// Stage name → times (`frame` is the whole frame; `*_cpu` are summed over threads).
    pub(crate) ms: BTreeMap<&'static str, StageTimes>,
    /// The stages in table order.
    #[serde(skip)]
    order: Vec<&'static str>,
}

impl BenchReport {
    /// The human table.
    pub(crate) fn table(&self) -> String {
        let mut text = format!(
            "{} frames at {}, {} threads (ms; *_cpu summed over threads)\n",
            self.frames, self.size, self.threads
        );
        text += &format!("{:<20} {:>10} {:>10}\n", "stage", "median", "min");
        for name in &self.order {
            let t = self.ms[name];
            text += &format!("{name:<20} {:>10.3} {:>10.3}\n", t.median_ms, t.min_ms);
        }
        text
    }
}

/// Median and minimum of a list of times (not empty).
fn median_min(mut v: Vec<f64>) -> (f64, f64) {
    v.sort_by(f64::total_cmp);
    (v[v.len() / 2], v[0])
}

/// How each stage's time is read from a frame's statistics.
type Pick = fn(&RenderStats) -> f64;

/// The planning stages timed only with
/// [`spatch_render::RenderOptions::stage_times`].
const PLANNING_STAGES: [&str; 5] = [
    "cull_cpu",
    "split_cpu",
    "traverse_cpu",
    "normals_cpu",
    "triangle_setup_cpu",
];

/// The stages of the table, in order.
const STAGES: [(&str, Pick); 13] = [
    ("frame", |s| s.times_ms.total_wall),
    ("plan_wall", |s| s.times_ms.plan_wall),
    ("bin_wall", |s| s.times_ms.bin_wall),
    ("raster_wall", |s| s.times_ms.raster_wall),
    ("gather_wall", |s| s.times_ms.gather_wall),
    ("cull_cpu", |s| s.times_ms.cull),
    ("split_cpu", |s| s.times_ms.split),
    ("traverse_cpu", |s| s.times_ms.traverse),
    ("normals_cpu", |s| s.times_ms.normals),
    ("triangle_setup_cpu", |s| s.times_ms.triangle_setup),
    ("cells_cpu", |s| s.times_ms.cells),
    ("triangles_cpu", |s| s.times_ms.triangles),
    ("resolve_cpu", |s| s.times_ms.resolve),
];

/// Renders one warm-up frame and `frames` timed ones (at least one), calling
/// `on_frame(k)` after the k-th.
pub(crate) fn bench(
    renderer: &mut Renderer,
    scene: &PreparedScene,
    camera: &Camera,
    frames: usize,
    on_frame: &dyn Fn(usize),
) -> anyhow::Result<BenchReport> {
    let frames = frames.max(1);
    // Warm-up: the first frame of the caller, and one more.
    let warm = renderer.render(scene, camera).map_err(render_failure)?;
    renderer.recycle(warm.image);
    let mut all: Vec<RenderStats> = Vec::with_capacity(frames);
    for k in 0..frames {
        let out = renderer.render(scene, camera).map_err(render_failure)?;
        renderer.recycle(out.image);
        all.push(out.stats);
        on_frame(k + 1);
    }
    // Without stage times the planning stages read 0: left out.
    let timed = renderer.options().stage_times;
    let stages = STAGES
        .iter()
        .filter(|(name, _)| timed || !PLANNING_STAGES.contains(name));
    let mut ms = BTreeMap::new();
    for &(name, pick) in stages.clone() {
        let (median_ms, min_ms) = median_min(all.iter().map(pick).collect());
        ms.insert(name, StageTimes { median_ms, min_ms });
    }
    Ok(BenchReport {
        frames,
        threads: renderer.threads(),
        size: format!("{}x{}", camera.width(), camera.height()),
        ms,
        order: stages.map(|(name, _)| *name).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::median_min;

    #[test]
    fn median_and_min_of_unsorted_times() {
        assert_eq!(median_min(vec![3.0, 1.0, 2.0]), (2.0, 1.0));
        assert_eq!(median_min(vec![5.0]), (5.0, 5.0));
    }
}
