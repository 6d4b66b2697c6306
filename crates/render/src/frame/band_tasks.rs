//! What the bands of a frame are handed: each band its buffers and its
//! rows of the image ([`BandTask`]), all bands the frame's planned work and
//! the resolve pass's inputs ([`band_job`]); how a pool thread runs one
//! ([`run_band_task`]).
//!
//! Cost: O(bands) per frame.

use std::sync::{Mutex, PoisonError};

use glam::Vec3;

use crate::camera::View;
use crate::fixed::{attr_from_bits, attr_to_bits};
use crate::frame::occlusion_skip::SkipTiles;
use crate::frame::tiles::{render_band, BandJob, Bins};
use crate::isa::Isa;
use crate::plan::work::{ChunkWork, FrameSetup};
use crate::prepare::patch::PreparedPatch;
use crate::raster::band::{Band, Sample};
use crate::shade::phong_items::PhongItems;
use crate::shade::resolve::Resolve;

/// One band's buffers and its rows of the image, handed to a thread.
pub(crate) struct BandTask<'a> {
    pub(crate) index: usize,
    pub(crate) band: &'a mut Band,
    pub(crate) skip: &'a mut SkipTiles,
    pub(crate) rgba: &'a mut [[u8; 4]],
    pub(crate) eye_depth: &'a mut [f32],
    pub(crate) y0: i32,
    pub(crate) rows: i32,
}

/// Pairs each of `count` bands of `tile_rows` rows of a `width × height`
/// image with its rows of the image buffers.
pub(crate) fn band_tasks<'a>(
    (bands, skips): (&'a mut Vec<Band>, &'a mut [SkipTiles]),
    count: usize,
    tile_rows: u32,
    (width, height): (u32, u32),
    rgba: &'a mut [[u8; 4]],
    eye_depth: &'a mut [f32],
) -> Vec<BandTask<'a>> {
    bands.resize_with(count, Band::default);
    let n = (tile_rows * width) as usize;
    let rows = rgba.chunks_mut(n).zip(eye_depth.chunks_mut(n));
    (bands.iter_mut().zip(skips).zip(rows).enumerate())
        .map(|(index, ((band, skip), (rgba, eye_depth)))| {
            let y0 = index as u32 * tile_rows;
            BandTask {
                index,
                band,
                skip,
                rgba,
                eye_depth,
                y0: y0 as i32,
                rows: (height - y0).min(tile_rows) as i32,
            }
        })
        .collect()
}

/// What every band of a frame reads: the planned chunks and their bins,
/// the frame's drawing options and the resolve pass's inputs (`phong`,
/// the prepared `patches`, the bands' instruction set `isa`).
pub(crate) fn band_job<'a>(
    setup: &FrameSetup<'_>,
    view: &View,
    (chunks, bins): (&'a [ChunkWork], &'a Bins),
    (phong, patches): (&'a PhongItems<'a>, &'a [PreparedPatch]),
    isa: Isa,
) -> BandJob<'a> {
    let options = setup.options;
    BandJob {
        chunks,
        bins,
        shading: options.shading,
        cells: options.cells,
        occlusion_skip: options.occlusion_skip,
        depth_map: (setup.z_scale, setup.z_offset),
        has_grids: patches.iter().any(|p| p.colour_grid.is_some()),
        resolve: Resolve {
            shading: options.shading,
            items: &bins.all_items,
            chunks,
            phong,
            patches,
            material: setup.material,
            base_albedo: Vec3::from_array(
                setup
                    .base_colour
                    .to_array()
                    .map(|c| attr_from_bits(attr_to_bits(c))),
            ),
            background: options.background,
            near: view.near as f32,
            far: view.far as f32,
            isa,
        },
    }
}

/// Draws and resolves one band `task` of `job` on the calling pool thread: the band
/// borrows that thread's sample store from `thread_samples` for the time of the draw, is
/// sized to its rows of an image `width` wide (with `apron` rows on each side), and runs
/// with the job's instruction set.
pub(crate) fn run_band_task(
    task: BandTask<'_>,
    job: &BandJob<'_>,
    thread_samples: &[Mutex<Vec<Sample>>],
    (width, apron): (i32, i32),
) {
    let BandTask {
        index,
        band,
        skip,
        rgba,
        eye_depth,
        y0,
        rows,
    } = task;
    let thread = rayon::current_thread_index().unwrap_or(0);
    let mut samples = thread_samples[thread.min(thread_samples.len() - 1)]
        .lock()
        .unwrap_or_else(PoisonError::into_inner);
    band.swap_samples(&mut samples);
    band.size_for(y0, rows, width, apron);
    band.thread = thread;
    job.resolve.isa.run(
        #[inline(always)]
        || render_band((band, skip), index, job, rgba, eye_depth),
    );
    band.swap_samples(&mut samples);
}
