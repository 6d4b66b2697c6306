//! The tiled framebuffer: work sorted into bands of rows, each band
//! rasterized and resolved by one thread of the pool.
//!
//! Binning: each draw item and triangle goes to every band its rows touch,
//! in planning order, so every band draws its work in the same order
//! whatever the number of threads — the image is identical for 1 and N
//! threads. A band clears its own small buffers (which stay in cache),
//! draws, then shades its pixels; bands share nothing mutable.
//!
//! Cost: O(items + triangles) for binning (counting sort into CSR arrays),
//! plus the drawing itself; cells straddling a band edge are visited by
//! both bands, rows outside a band are skipped before any sample.

use std::time::Instant;

use crate::frame::image::finite_count;
use crate::frame::occlusion_skip::SkipTiles;
use crate::options::{CellScheme, Shading};
use crate::plan::work::{ChunkWork, Item};
use crate::raster::band::{
    Band, BandTarget, FlatPayload, GouraudPayload, GridGouraudPayload, GridPhongPayload, Payload,
    PhongPayload, PATCH_SAMPLE,
};
use crate::raster::band_box::{band_box, PixelBox};
use crate::raster::cell_bilinear::{draw_cells_bilinear, draw_nodes, BilinearPiece};
use crate::raster::cell_edges::draw_cells_open;
use crate::raster::cell_quarters::draw_quartered_cells;
use crate::raster::cell_smooth::draw_cells_smooth;
use crate::raster::centre_piece::draw_cells_centres;
use crate::raster::gap_fill::fill_band_gaps;
use crate::raster::splat::{draw_splats, SplatPiece};
use crate::raster::triangle_raster::{draw_triangle, ScreenTriangle};
use crate::shade::resolve::{resolve_box, Resolve};

/// Work per band in CSR form: `(chunk, index)` references.
#[derive(Debug, Default)]
pub(crate) struct Bins {
    /// Every draw item, in planning order (a patch sample's item index).
    pub(crate) all_items: Vec<(u32, u32)>,
    item_starts: Vec<u32>,
    items: Vec<(u32, u32)>,
    tri_starts: Vec<u32>,
    tris: Vec<(u32, u32)>,
}

fn band_range(y0: i32, y1: i32, rows: i32, bands: usize) -> std::ops::Range<usize> {
    let last = bands as i32 - 1;
    let a = (y0.max(0) / rows).min(last);
    let b = (y1.max(0) / rows).min(last);
    if y1 < 0 || a > b {
        0..0
    } else {
        a as usize..b as usize + 1
    }
}

fn fill_csr<T>(
    chunks: &[ChunkWork],
    list: impl Fn(&ChunkWork) -> &[T],
    rows_of: impl Fn(&T) -> (i32, i32),
    tile_rows: i32,
    bands: usize,
    starts: &mut Vec<u32>,
    refs: &mut Vec<(u32, u32)>,
) {
    // Each reference is (chunk, index) here; items are renumbered below.
    starts.clear();
    starts.resize(bands + 1, 0);
    for chunk in chunks {
        for x in list(chunk) {
            let (y0, y1) = rows_of(x);
            for b in band_range(y0, y1, tile_rows, bands) {
                starts[b + 1] += 1;
            }
        }
    }
    for b in 0..bands {
        starts[b + 1] += starts[b];
    }
    refs.clear();
    refs.resize(starts[bands] as usize, (0, 0));
    let mut cursor: Vec<u32> = starts[..bands].to_vec();
    for (c, chunk) in chunks.iter().enumerate() {
        for (k, x) in list(chunk).iter().enumerate() {
            let (y0, y1) = rows_of(x);
            for b in band_range(y0, y1, tile_rows, bands) {
                refs[cursor[b] as usize] = (c as u32, k as u32);
                cursor[b] += 1;
            }
        }
    }
}

impl Bins {
    /// Sorts the work of `chunks` into `bands` bands of `tile_rows` rows,
    /// each with `apron` rows more above and below.
    pub(crate) fn fill(&mut self, chunks: &[ChunkWork], tile_rows: u32, bands: usize, apron: i32) {
        let rows = tile_rows as i32;
        self.all_items.clear();
        for (c, chunk) in chunks.iter().enumerate() {
            self.all_items
                .extend((0..chunk.items.len() as u32).map(|k| (c as u32, k)));
        }
        fill_csr(
            chunks,
            |c| &c.items,
            |i: &Item| (i.y0 - apron, i.y1 + apron),
            rows,
            bands,
            &mut self.item_starts,
            &mut self.items,
        );
        // Renumber item references as indices into `all_items`.
        let mut first = Vec::with_capacity(chunks.len());
        let mut total = 0u32;
        for chunk in chunks {
            first.push(total);
            total += chunk.items.len() as u32;
        }
        for r in &mut self.items {
            *r = (0, first[r.0 as usize] + r.1);
        }
        fill_csr(
            chunks,
            |c| &c.triangles,
            |t: &ScreenTriangle| (t.y0 - apron, t.y1 + apron),
            rows,
            bands,
            &mut self.tri_starts,
            &mut self.tris,
        );
    }

    /// Indices into `all_items` of the items touching `band`.
    pub(crate) fn items_of(&self, band: usize) -> impl Iterator<Item = &u32> + '_ {
        self.items[self.item_starts[band] as usize..self.item_starts[band + 1] as usize]
            .iter()
            .map(|(_, id)| id)
    }

    /// Items and triangles binned to `band`.
    pub(crate) fn counts(&self, band: usize) -> (u32, u32) {
        (
            self.item_starts[band + 1] - self.item_starts[band],
            self.tri_starts[band + 1] - self.tri_starts[band],
        )
    }

    fn tris_of(&self, band: usize) -> &[(u32, u32)] {
        &self.tris[self.tri_starts[band] as usize..self.tri_starts[band + 1] as usize]
    }
}

/// What every band needs to draw.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BandJob<'a> {
    pub(crate) chunks: &'a [ChunkWork],
    pub(crate) bins: &'a Bins,
    pub(crate) shading: Shading,
    pub(crate) cells: CellScheme,
    /// Skip the pieces hidden by those drawn before them
    /// ([`crate::frame::occlusion_skip`]).
    pub(crate) occlusion_skip: bool,
    pub(crate) depth_map: (f32, f32),
    /// Some patch of the frame has a colour grid (its cell triangles read
    /// it: [`draw_grid_triangles`]).
    pub(crate) has_grids: bool,
    pub(crate) resolve: Resolve<'a>,
}

#[inline(always)]
pub(crate) fn draw_item(
    t: &mut BandTarget<'_>,
    chunk: &ChunkWork,
    k: u32,
    id: u32,
    cells: CellScheme,
) {
    let item = &chunk.items[k as usize];
    let (cols, rows) = (item.cols as usize, item.rows as usize);
    let first = item.first as usize;
    let nodes = &chunk.nodes[first..first + cols * rows];
    let (nu, nv) = (item.nu as u32, item.nv as u32);
    let id = id | PATCH_SAMPLE;
    if item.splat[0] > 0 {
        let s = item.spans as usize;
        let piece = SplatPiece {
            nodes,
            spans: &chunk.row_spans[s..s + rows - 1],
            cols,
            rows,
            half: item.splat,
        };
        draw_splats(t, &piece, id);
    } else if nu == 1 && nv == 1 {
        draw_nodes(t, nodes, cols, rows, id);
    } else if cells == CellScheme::Smooth {
        draw_cells_smooth(t, nodes, cols, rows, nu, nv, id);
    } else {
        let f = item.flags as usize;
        let flags = &chunk.cell_flags[f..f + (cols - 1) * (rows - 1)];
        let s = item.spans as usize;
        let spans = &chunk.row_spans[s..s + rows - 1];
        let piece = BilinearPiece {
            nodes,
            flags,
            spans,
            cols,
            rows,
            inside_columns: item.inside_columns,
        };
        if let Some(style) = item.centres {
            draw_cells_centres(t, &piece, style, id);
        } else if item.open_sides {
            draw_cells_open(t, &piece, nu, nv, id);
        } else {
            draw_cells_bilinear(t, &piece, nu, nv, id);
        }
        if !chunk.quartered_ranges.is_empty() {
            let ranges = &chunk.quartered_ranges;
            if let Ok(r) = ranges.binary_search_by_key(&k, |r| r.item) {
                let [q0, q1] = ranges[r].cells.map(|q| q as usize);
                draw_quartered_cells(t, &piece, &chunk.quartered[q0..q1], [nu, nv], id);
            }
        }
    }
}

/// Why out of line (so compiled for the portable target, not the band's
/// instruction set): inlined into the band, it made the perfect sphere's
/// frame, which draws no triangle, 1.03 times slower (the band function's
/// layout); `draw_triangle` needs no library call in either.
fn draw_triangles<const N: usize, P: Payload<N>>(
    t: &mut BandTarget<'_>,
    job: &BandJob<'_>,
    refs: &[(u32, u32)],
    payload_of: impl Fn(&ScreenTriangle) -> P,
) {
    for &(c, k) in refs {
        let tri = &job.chunks[c as usize].triangles[k as usize];
        draw_triangle(t, tri, job.depth_map, &payload_of(tri));
    }
}

/// [`draw_triangles`] for Gouraud and Phong in a frame whose patches have
/// colour grids: the cell triangles of such a patch read its grid per
/// sample ([`ScreenTriangle::grid`]), the others draw as usual. Out of
/// line as [`draw_triangles`] is.
fn draw_grid_triangles(t: &mut BandTarget<'_>, job: &BandJob<'_>, refs: &[(u32, u32)]) {
    let patches = job.resolve.patches;
    for &(c, k) in refs {
        let tri = &job.chunks[c as usize].triangles[k as usize];
        let grid = tri
            .grid
            .then(|| patches.get(tri.frame as usize))
            .flatten()
            .and_then(|p| p.colour_grid.as_ref());
        match (job.shading, grid) {
            (Shading::Phong, Some(grid)) => {
                let payload = GridPhongPayload {
                    frame: tri.frame,
                    grid,
                };
                draw_triangle::<6, _>(t, tri, job.depth_map, &payload);
            }
            (Shading::Phong, None) => {
                draw_triangle::<6, _>(t, tri, job.depth_map, &PhongPayload(tri.frame))
            }
            (_, Some(grid)) => {
                draw_triangle::<6, _>(t, tri, job.depth_map, &GridGouraudPayload(grid))
            }
            (_, None) => draw_triangle::<3, _>(t, tri, job.depth_map, &GouraudPayload),
        }
    }
}

/// Draws the pieces of band number `index` in planning order, leaving out
/// those the pixels already drawn hide ([`crate::frame::occlusion_skip`]).
#[inline(always)]
fn draw_unhidden_pieces(
    t: &mut BandTarget<'_>,
    index: usize,
    job: &BandJob<'_>,
    skip: &mut SkipTiles,
) {
    skip.begin(t.y0, t.rows, t.width);
    for &id in job.bins.items_of(index) {
        let (c, i) = job.bins.all_items[id as usize];
        let chunk = &job.chunks[c as usize];
        let item = &chunk.items[i as usize];
        if !skip.hidden(t.px, item) {
            draw_item(t, chunk, i, id, job.cells);
            skip.drawn(item);
        }
    }
}

/// The pixel boxes (`[x0, x1, y0, y1]`, inclusive) of the draw items and
/// triangles binned to band number `index`.
#[inline(always)]
fn work_boxes<'a>(job: &'a BandJob<'_>, index: usize) -> impl Iterator<Item = [i32; 4]> + 'a {
    let items = job.bins.items_of(index).map(|&id| {
        let (c, k) = job.bins.all_items[id as usize];
        let item = &job.chunks[c as usize].items[k as usize];
        [item.x0, item.x1, item.y0, item.y1]
    });
    let tris = job.bins.tris_of(index).iter().map(|&(c, k)| {
        let tri = &job.chunks[c as usize].triangles[k as usize];
        [tri.x0, tri.x1, tri.y0, tri.y1]
    });
    items.chain(tris)
}

/// Draws band number `index` and resolves it into its rows of the image
/// (`rgba`, `eye_depth`).
/// Why `#[inline(always)]` here and in its stages: they run inside the
/// kernels' instruction-set wrapper (`crate::isa`).
#[inline(always)]
pub(crate) fn render_band(
    (band, skip): (&mut Band, &mut SkipTiles),
    index: usize,
    job: &BandJob<'_>,
    rgba: &mut [[u8; 4]],
    eye_depth: &mut [f32],
) {
    // Only the part of the band (and its apron) its work can touch is
    // cleared, drawn and resolved (`raster::band_box`). The occlusion skip
    // reads whole tiles of the band, so it keeps the whole band.
    let (first, all) = band.buffer_rows();
    let drawn = PixelBox::whole(first, all, band.width);
    let reach = if job.occlusion_skip {
        drawn
    } else {
        band_box(work_boxes(job, index), drawn)
    };
    band.clear_box(reach);
    let start = Instant::now();
    draw_band_items(band, skip, index, job);
    let cells_done = Instant::now();
    draw_band_triangles(band, index, job);
    let tris_done = Instant::now();
    // The gap fill is timed with the resolve.
    if band.apron > 0 {
        fill_band_gaps(band, reach);
    }
    resolve_band(band, reach, job, rgba, eye_depth);
    band.times.cells = (cells_done - start).as_nanos() as u64;
    band.times.triangles = (tris_done - cells_done).as_nanos() as u64;
    band.times.resolve = tris_done.elapsed().as_nanos() as u64;
}

/// Draws the patch pieces binned to band `index` (those the occlusion skip
/// finds hidden left out when it is on).
#[inline(always)]
fn draw_band_items(band: &mut Band, skip: &mut SkipTiles, index: usize, job: &BandJob<'_>) {
    if job.occlusion_skip {
        draw_unhidden_pieces(&mut band.target(), index, job, skip);
        return;
    }
    let mut t = band.target();
    for &id in job.bins.items_of(index) {
        let (c, k) = job.bins.all_items[id as usize];
        let chunk = &job.chunks[c as usize];
        draw_item(&mut t, chunk, k, id, job.cells);
    }
}

/// Draws the triangles binned to band `index` with the payload of the
/// frame's shading.
#[inline(always)]
fn draw_band_triangles(band: &mut Band, index: usize, job: &BandJob<'_>) {
    let mut t = band.target();
    let refs = job.bins.tris_of(index);
    match job.shading {
        Shading::Flat => draw_triangles::<0, _>(&mut t, job, refs, |tri| FlatPayload(tri.flat)),
        _ if job.has_grids => draw_grid_triangles(&mut t, job, refs),
        Shading::Gouraud => draw_triangles::<3, _>(&mut t, job, refs, |_| GouraudPayload),
        Shading::Phong => draw_triangles::<6, _>(&mut t, job, refs, |tri| PhongPayload(tri.frame)),
    }
}

/// Resolves the band's own rows of `reach` into its rows of the image and
/// counts the pixels that show a surface (the rest of the rows get the
/// background).
#[inline(always)]
fn resolve_band(
    band: &mut Band,
    reach: PixelBox,
    job: &BandJob<'_>,
    rgba: &mut [[u8; 4]],
    eye_depth: &mut [f32],
) {
    let whole = PixelBox::whole(band.y0, band.rows, band.width);
    let (y0, y1) = (reach.y0.max(whole.y0), reach.y1.min(whole.y1));
    let touched = PixelBox {
        y0,
        y1: y1.max(y0),
        ..reach
    };
    resolve_box(
        &job.resolve,
        band.samples(),
        whole,
        touched,
        rgba,
        eye_depth,
    );
    // Why here: the rows are still in the cache, and the count runs on the
    // pool; over the whole image afterwards it was a serial pass (1000²:
    // four megabytes read again after the frame). Only the box can show
    // a surface.
    let w = band.width as usize;
    let box_rows = (touched.y0 - whole.y0) as usize..(touched.y1 - whole.y0) as usize;
    let (x0, x1) = (touched.x0 as usize, touched.x1 as usize);
    band.covered = box_rows
        .map(|k| finite_count(&eye_depth[k * w + x0..k * w + x1]) as u64)
        .sum();
}
