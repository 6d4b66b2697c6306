//! The order in which the threads take the bands: heaviest planned work
//! first, each thread taking the next band from a shared counter as soon as
//! it is free (greedy list scheduling, "longest first").
//!
//! Why: a band is the unit a thread takes, and the bunny's silhouette fills
//! its 500² frame's bands very unevenly (0.3 to 9.5 M instructions). A
//! parallel iterator over the bands in row order first gives each thread
//! half of the rows, so one thread drew the two heaviest bands alone
//! (25.7 M of the 41.2 M). Taken heaviest first, the light bands fill in the
//! gaps at the end and the busiest thread comes within a light band of half
//! the total.
//!
//! The work of a row is estimated from the plan: the samples of the pieces
//! crossing it (spread evenly over each piece's rows), the area of its
//! triangles, and a fixed cost per pixel for the clear and the resolve. The
//! order changes only who draws a band and when, never what it draws: the
//! image does not depend on it.
//!
//! Cost: O(items + triangles + rows + bands log bands).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

use crate::plan::work::{ChunkWork, Item};
use crate::raster::triangle_raster::ScreenTriangle;

/// Estimated cost of one pixel's clear and resolve, in samples.
const PIXEL_COST: f64 = 0.5;

/// Estimated work per band and the bands, heaviest first.
#[derive(Debug, Default)]
pub(crate) struct BandOrder {
    /// Work per row, then per band (scratch).
    rows: Vec<f64>,
    /// Estimated work of each band, in samples.
    pub(crate) work: Vec<f64>,
    /// Band indices, heaviest first (ties: top first).
    pub(crate) order: Vec<usize>,
}

impl BandOrder {
    /// Estimates the work of `bands` bands of `tile_rows` rows of
    /// `width × height` and orders them, heaviest first.
    pub(crate) fn plan(
        &mut self,
        chunks: &[ChunkWork],
        (width, height): (u32, u32),
        tile_rows: u32,
        bands: usize,
    ) {
        self.estimate_rows(chunks, width, height);
        self.work.clear();
        self.work.extend(
            self.rows
                .chunks(tile_rows as usize)
                .map(|band| band.iter().sum::<f64>()),
        );
        self.work.resize(bands, 0.0);
        self.order.clear();
        self.order.extend(0..bands);
        let work = &self.work;
        self.order
            .sort_by(|&a, &b| work[b].total_cmp(&work[a]).then(a.cmp(&b)));
    }

    /// The planned work of each row into `rows`.
    fn estimate_rows(&mut self, chunks: &[ChunkWork], width: u32, height: u32) {
        // A difference array: +w at a piece's first row, -w after its last.
        let diff = &mut self.rows;
        diff.clear();
        diff.resize(height as usize + 1, 0.0);
        let last = height as i32 - 1;
        let mut spread = |y0: i32, y1: i32, work: f64| {
            let (a, b) = (y0.max(0), y1.min(last));
            if a <= b {
                let per_row = work / (y1 - y0 + 1) as f64;
                diff[a as usize] += per_row;
                diff[b as usize + 1] -= per_row;
            }
        };
        for chunk in chunks {
            for item in &chunk.items {
                spread(item.y0, item.y1, item_samples(item));
            }
            for tri in &chunk.triangles {
                spread(tri.y0, tri.y1, triangle_area(tri));
            }
        }
        let mut run = 0.0;
        for d in diff.iter_mut() {
            run += *d;
            *d = run + PIXEL_COST * width as f64;
        }
        diff.truncate(height as usize);
    }
}

/// Runs `f` on every task on the threads of `pool`, each thread taking
/// the next task of `order` (indices into `tasks`) when it is free.
pub(crate) fn run_in_order<T: Send>(
    pool: &rayon::ThreadPool,
    tasks: Vec<T>,
    order: &[usize],
    f: impl Fn(T) + Sync,
) {
    // One lock per task, taken once by the thread that claimed it.
    let slots: Vec<Mutex<Option<T>>> = tasks.into_iter().map(|t| Mutex::new(Some(t))).collect();
    let next = AtomicUsize::new(0);
    pool.broadcast(|_| {
        while let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
            let task = slots[i]
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .take();
            if let Some(task) = task {
                f(task);
            }
        }
    });
}

/// Samples a piece places, about: its nodes times the sub-nodes per cell.
fn item_samples(item: &Item) -> f64 {
    let (cols, rows) = (item.cols as f64, item.rows as f64);
    cols * rows * item.nu as f64 * item.nv as f64
}

/// Pixels a triangle covers, about.
fn triangle_area(tri: &ScreenTriangle) -> f64 {
    let [a, b, c] = tri.v;
    let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    0.5 * cross.abs() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn item(y0: i32, y1: i32, cols: u16, rows: u16) -> Item {
        Item {
            cols,
            rows,
            y0,
            y1,
            ..Item::for_tests()
        }
    }

    #[test]
    fn bands_are_ordered_by_the_samples_of_their_rows() {
        // 4 bands of 10 rows of width 10 (5 per row for clear and resolve):
        // a piece over rows 15..=24 puts 500 samples in band 1 and in band
        // 2; one over rows 30..=31 puts 300 in band 3; one partly above the
        // image counts only its rows on screen (100 of 200 in band 0).
        let mut chunk = ChunkWork::default();
        chunk.items.push(item(15, 24, 25, 40));
        chunk.items.push(item(30, 31, 10, 30));
        chunk.items.push(item(-10, 9, 10, 20));
        let mut order = BandOrder::default();
        order.plan(std::slice::from_ref(&chunk), (10, 40), 10, 4);
        assert_eq!(order.work, [150.0, 550.0, 550.0, 350.0]);
        assert_eq!(order.order, [1, 2, 3, 0]);
    }

    #[test]
    fn every_task_runs_once_on_any_pool() {
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool");
            let mut seen = vec![0u32; 7];
            let tasks: Vec<(usize, &mut u32)> = seen.iter_mut().enumerate().collect();
            run_in_order(&pool, tasks, &[3, 0, 6, 1, 5, 2, 4], |(i, n)| {
                *n += 1 + i as u32
            });
            assert_eq!(seen, [1, 2, 3, 4, 5, 6, 7], "{threads} threads");
        }
    }

    #[test]
    fn a_short_last_band_and_triangles_count() {
        // 25 rows in 3 bands (10, 10, 5); a triangle of area 50 over rows
        // 20..=24 makes the short band the heaviest.
        let mut chunk = ChunkWork::default();
        let v = [[0.0, 20.0, 0.5], [10.0, 20.0, 0.5], [0.0, 30.0, 0.5]];
        chunk.triangles.push(ScreenTriangle {
            v,
            a: Default::default(),
            frame: 0,
            flat: 0,
            grid: false,
            y0: 20,
            y1: 24,
            x0: 0,
            x1: 9,
        });
        let mut order = BandOrder::default();
        order.plan(std::slice::from_ref(&chunk), (2, 25), 10, 3);
        assert_eq!(order.work, [10.0, 10.0, 55.0]);
        assert_eq!(order.order, [2, 0, 1]);
    }
}
