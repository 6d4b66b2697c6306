//! `--bench-orbit N`: the frame times of an orbit, without a window.

use std::f64::consts::TAU;
use std::time::Instant;

use crate::error::ViewError;
use crate::event::Event;
use crate::orbit::ORBIT_RADIANS_PER_PIXEL;
use crate::settings::Quality;
use crate::viewer::Viewer;

/// What an orbit benchmark measured, in milliseconds of wall time per
/// frame (the whole [`Viewer::frame`] call, as the window waits for it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitBench {
    /// Frames timed.
    pub frames: usize,
    /// Median frame time.
    pub median_ms: f64,
    /// Worst frame time.
    pub worst_ms: f64,
    /// Median patches drawn.
    pub median_patches_drawn: u64,
}

/// Orbits once around the target in `frames` equal steps (after one
/// warm-up frame), rendering each at the moving quality.
pub fn bench_orbit(viewer: &mut Viewer, frames: usize) -> Result<OrbitBench, ViewError> {
    let frames = frames.max(1);
    let warm = viewer.frame(Quality::Moving)?;
    viewer.recycle(warm, Quality::Moving);
    let step = TAU / frames as f64 / ORBIT_RADIANS_PER_PIXEL;
    let mut times = Vec::with_capacity(frames);
    let mut drawn = Vec::with_capacity(frames);
    for _ in 0..frames {
        viewer.apply(Event::Orbit { dx: step, dy: 0.0 });
        let clock = Instant::now();
        let frame = viewer.frame(Quality::Moving)?;
        times.push(clock.elapsed().as_secs_f64() * 1e3);
        drawn.push(frame.patches_drawn());
        viewer.recycle(frame, Quality::Moving);
    }
    times.sort_by(f64::total_cmp);
    drawn.sort_unstable();
    Ok(OrbitBench {
        frames,
        median_ms: times[frames / 2],
        worst_ms: times[frames - 1],
        median_patches_drawn: drawn[frames / 2],
    })
}
