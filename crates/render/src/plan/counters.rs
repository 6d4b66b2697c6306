//! What planning and drawing count per chunk of work: patches culled,
//! split and drawn by each path, nodes, normals, triangles, and CPU time
//! per planning stage. Chunks are fixed (independent of the thread
//! count), so the summed counts are deterministic; they become the
//! public [`RenderStats`](crate::RenderStats).

use std::time::Instant;

use crate::prepare::mip::MAX_MIP_LEVELS;
use crate::prepare::normal_buffer::NormalCounts;

/// Counters of one chunk of work (summed into [`crate::RenderStats`]).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Counters {
    pub(crate) patches: u64,
    pub(crate) culled_frustum: u64,
    pub(crate) culled_backface: u64,
    pub(crate) cells_backface: u64,
    pub(crate) split: u64,
    pub(crate) split_pieces: u64,
    pub(crate) pieces_dropped: u64,
    pub(crate) clipped_cells: u64,
    pub(crate) oversized_pieces: u64,
    pub(crate) optimized: u64,
    pub(crate) interpolated: u64,
    pub(crate) splatted: u64,
    pub(crate) mip: [u64; MAX_MIP_LEVELS],
    pub(crate) patch_nodes: u64,
    pub(crate) interpolated_nodes: u64,
    pub(crate) normals: NormalCounts,
    pub(crate) triangles: u64,
    pub(crate) triangles_clipped: u64,
    pub(crate) triangles_culled: u64,
    pub(crate) cull_ns: u64,
    pub(crate) split_ns: u64,
    pub(crate) traverse_ns: u64,
    pub(crate) normals_ns: u64,
    pub(crate) setup_ns: u64,
}

impl std::ops::AddAssign<&Counters> for Counters {
    fn add_assign(&mut self, o: &Counters) {
        self.patches += o.patches;
        self.culled_frustum += o.culled_frustum;
        self.culled_backface += o.culled_backface;
        self.cells_backface += o.cells_backface;
        self.split += o.split;
        self.split_pieces += o.split_pieces;
        self.pieces_dropped += o.pieces_dropped;
        self.clipped_cells += o.clipped_cells;
        self.oversized_pieces += o.oversized_pieces;
        self.optimized += o.optimized;
        self.interpolated += o.interpolated;
        self.splatted += o.splatted;
        for (a, b) in self.mip.iter_mut().zip(o.mip) {
            *a += b;
        }
        self.patch_nodes += o.patch_nodes;
        self.interpolated_nodes += o.interpolated_nodes;
        self.normals.needed += o.normals.needed;
        self.normals.computed_per_patch_buffer += o.normals.computed_per_patch_buffer;
        self.normals.computed_ordered_buffer += o.normals.computed_ordered_buffer;
        self.triangles += o.triangles;
        self.triangles_clipped += o.triangles_clipped;
        self.triangles_culled += o.triangles_culled;
        self.cull_ns += o.cull_ns;
        self.split_ns += o.split_ns;
        self.traverse_ns += o.traverse_ns;
        self.normals_ns += o.normals_ns;
        self.setup_ns += o.setup_ns;
    }
}

/// The clock of a chunk's stage timers ([`Counters`]): each stage reads
/// it once, where it ends, and is charged the time since the previous
/// stage ended (its lap), so planning time is split between the stages
/// with no gaps. Why laps rather than a start and a stop per stage: a
/// clock read costs about 25 ns here, and a drawn patch took eight of
/// them (about 5 % of a one-thread bunny frame at 500²); laps take three.
/// Why a clock that may be off ([`crate::RenderOptions::stage_times`]):
/// even three reads per patch were about 1.5 % of a bunny frame at 500²
/// with 2 threads (frame ratio 0.984–0.985 without them,
/// `bench/compare_binaries.py`, 12 rounds of 30 frames; 43.87 → 43.15 M
/// instructions, the mannequin 38.25 → 38.00 M), paid by every frame
/// whether anyone read the stage times or not.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct StageClock {
    /// The end of the previous lap; `None` when the clock is off (the
    /// default, until a frame's reset starts it).
    last: Option<Instant>,
}

impl StageClock {
    /// A clock started now when `on`, else one whose laps read 0 and no
    /// clock.
    pub(crate) fn new(on: bool) -> Self {
        StageClock {
            last: on.then(Instant::now),
        }
    }

    /// Nanoseconds since the previous lap (or the clock's start); a new
    /// lap begins. 0 when the clock is off.
    #[inline]
    pub(crate) fn lap(&mut self) -> u64 {
        let Some(last) = self.last else {
            return 0;
        };
        let now = Instant::now();
        let ns = now.duration_since(last).as_nanos() as u64;
        self.last = Some(now);
        ns
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    /// Laps split the time between the clock's start and its last lap:
    /// each at least its own stage's time, together no more than the whole
    /// (a lap that did not start a new one would count earlier stages again).
    #[test]
    fn laps_split_the_time_without_gaps_or_overlap() {
        let outer = Instant::now();
        let mut clock = StageClock::new(true);
        let mut sum = 0;
        for _ in 0..3 {
            std::thread::sleep(Duration::from_millis(2));
            let lap = clock.lap();
            assert!(lap >= 2_000_000, "{lap} ns");
            sum += lap;
        }
        let whole = outer.elapsed().as_nanos() as u64;
        assert!(sum >= 6_000_000 && sum <= whole, "{sum} of {whole} ns");
    }

    /// A clock that is off reads nothing: every lap is 0.
    #[test]
    fn a_clock_that_is_off_laps_zero() {
        let mut clock = StageClock::new(false);
        std::thread::sleep(Duration::from_millis(1));
        assert_eq!(clock.lap(), 0);
        assert_eq!(clock.lap(), 0);
    }
}
