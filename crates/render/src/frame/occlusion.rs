//! How much of what a frame draws ends up hidden: the pieces of the last
//! frame drawn again one at a time, each into a cleared scratch band, and
//! merged into the band with the depth test of the drawing paths.
//!
//! A **fragment** is a pixel a piece writes (its own samples in the pixel
//! counted once: several samples of one piece in a pixel are the surface's
//! sampling density, not occlusion). A fragment is **hidden** when it fails
//! the depth test against an earlier piece's or a later piece overwrites
//! it; the rest are the visible pixels. A piece whose fragments in a band
//! are all hidden is **hidden in the band**: the most a per-piece depth test
//! (a piece's nearest depth against a band's or tile's farthest) could skip
//! there.
//!
//! With the occlusion skip ([`crate::frame::occlusion_skip`]), the same
//! test picks the pieces the frame skipped; their fragments are counted
//! (all must be hidden).
//!
//! For `--stats` only (it redraws the frame piece by piece); triangles are
//! not counted.
//!
//! Cost: O(pieces × rows × width) over the bands a piece touches.

use serde::Serialize;

use crate::fixed::Z_FAR;
use crate::frame::occlusion_skip::SkipTiles;
use crate::frame::tiles::{draw_item, Bins};
use crate::options::CellScheme;
use crate::plan::work::ChunkWork;
use crate::raster::band::Band;

/// Occlusion counts of one frame (see the module header).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct OcclusionStats {
    /// Pixels written by pieces, each piece's pixel once.
    pub fragments: u64,
    /// Fragments behind an earlier piece's or overwritten by a later one.
    pub hidden_fragments: u64,
    /// Hidden fragments in % of the fragments.
    pub hidden_percent: f64,
    /// Hidden fragments more than 1/256 of the near-far depth range
    /// behind the fragment that hides them, in % of the fragments: hidden by
    /// another part of the surface rather than by an overlapping patch of
    /// the same part.
    pub hidden_behind_percent: f64,
    /// (piece, band) pairs with at least one fragment.
    pub piece_bands: u64,
    /// Of those, pairs whose fragments are all hidden.
    pub piece_bands_hidden: u64,
    /// Fragments of the pairs hidden in the band, in % of the fragments.
    pub hidden_piece_fragments_percent: f64,
    /// (piece, band) pairs the occlusion skip left out (0 without it).
    pub skipped_pieces: u64,
    /// Fragments of those pairs: drawn here, left out by the frame.
    pub skipped_fragments: u64,
    /// Skipped fragments in % of the fragments.
    pub skipped_fragments_percent: f64,
    /// Skipped fragments that would have shown when drawn: 0 (else the
    /// skip test is wrong; the tests check it).
    pub skipped_fragments_shown: u64,
}

/// Depth gap, in fixed-point depth units (1/256 of the near-far range),
/// above which a hidden fragment counts as behind another surface.
pub(crate) const BEHIND: i32 = Z_FAR >> 8;

/// The frame's geometry and work, as the bands drew it.
pub(crate) struct Frame<'a> {
    pub(crate) chunks: &'a [ChunkWork],
    pub(crate) bins: &'a Bins,
    pub(crate) cells: CellScheme,
    pub(crate) width: i32,
    pub(crate) height: i32,
    pub(crate) tile_rows: i32,
    /// The frame drew with the occlusion skip.
    pub(crate) skip: bool,
    /// Rows its bands drew above and below their own (the gap fill's).
    pub(crate) apron: i32,
}

/// Per band: the pixels so far and what each piece wrote.
#[derive(Default)]
struct Scratch {
    merged: Band,
    piece: Band,
    /// Per pixel of the band, the piece that shows there (index into
    /// `written`), or `u32::MAX`.
    owner: Vec<u32>,
    /// Per piece of the band: fragments, and pixels it still shows.
    written: Vec<(u64, u64)>,
    /// The occlusion skip's tiles, as the band drew them.
    skip: SkipTiles,
}

/// Counts the occlusion of `frame` (see the module header).
pub(crate) fn measure(frame: &Frame<'_>) -> OcclusionStats {
    let mut counts = OcclusionStats::default();
    let mut hidden_piece_fragments = 0;
    let mut behind = 0;
    let mut s = Scratch::default();
    let bands = (frame.height + frame.tile_rows - 1) / frame.tile_rows;
    for b in 0..bands {
        let y0 = b * frame.tile_rows;
        let rows = (frame.height - y0).min(frame.tile_rows);
        // The band's buffer, its apron included, as the frame drew it; only
        // its own rows are counted.
        s.merged.reset(y0, rows, frame.width, frame.apron);
        s.piece.reset(y0, rows, frame.width, frame.apron);
        let (first, all) = s.merged.buffer_rows();
        let w = frame.width as usize;
        let own = frame.apron as usize * w..(frame.apron + rows) as usize * w;
        s.owner.clear();
        s.owner.resize(all as usize * w, u32::MAX);
        s.written.clear();
        s.skip.begin(first, all, frame.width);
        for &id in frame.bins.items_of(b as usize) {
            let (c, k) = frame.bins.all_items[id as usize];
            let chunk = &frame.chunks[c as usize];
            let item = &chunk.items[k as usize];
            let skipped = frame.skip && s.skip.hidden(s.merged.target().px, item);
            // The piece's rows in the buffer.
            let r0 = (item.y0 - first).clamp(0, all) as usize;
            let r1 = (item.y1 + 1 - first).clamp(0, all) as usize;
            draw_item(&mut s.piece.target(), chunk, k, id, frame.cells);
            behind += merge_piece(&mut s, r0 * w..r1 * w, own.clone(), &mut counts);
            s.piece.clear_rows(r0..r1);
            if skipped {
                let (fragments, shown) = s.written[s.written.len() - 1];
                counts.skipped_pieces += 1;
                counts.skipped_fragments += fragments;
                counts.skipped_fragments_shown += shown;
            } else if frame.skip {
                s.skip.drawn(item);
            }
        }
        for &(fragments, shown) in &s.written {
            counts.piece_bands += u64::from(fragments > 0);
            if fragments > 0 && shown == 0 {
                counts.piece_bands_hidden += 1;
                hidden_piece_fragments += fragments;
            }
        }
    }
    let pct = |v: u64| 100.0 * v as f64 / counts.fragments.max(1) as f64;
    counts.hidden_percent = pct(counts.hidden_fragments);
    counts.hidden_behind_percent = pct(behind);
    counts.hidden_piece_fragments_percent = pct(hidden_piece_fragments);
    counts.skipped_fragments_percent = pct(counts.skipped_fragments);
    counts
}

/// Merges the piece just drawn (in pixels `span` of the band's buffer)
/// into the band: the depth test per fragment, counted where it falls in
/// the band's own pixels `own`. Returns the fragments hidden more than
/// [`BEHIND`] behind.
fn merge_piece(
    s: &mut Scratch,
    span: std::ops::Range<usize>,
    own: std::ops::Range<usize>,
    counts: &mut OcclusionStats,
) -> u64 {
    let mut behind = 0;
    let me = s.written.len() as u32;
    s.written.push((0, 0));
    let first = span.start;
    let merged = &mut s.merged.target().px[span.clone()];
    let piece = &s.piece.all_samples()[span.clone()];
    let owners = &mut s.owner[span];
    let pixels = piece.iter().zip(merged.iter_mut().zip(owners));
    for (i, (p, (m, owner))) in pixels.enumerate() {
        if p.depth == Z_FAR {
            continue;
        }
        if !own.contains(&(first + i)) {
            // The apron: merged for the skip's tiles, counted by its band.
            if p.depth < m.depth {
                *m = *p;
            }
            continue;
        }
        counts.fragments += 1;
        s.written[me as usize].0 += 1;
        if p.depth < m.depth {
            if *owner != u32::MAX {
                counts.hidden_fragments += 1;
                behind += u64::from(m.depth - p.depth > BEHIND);
                s.written[*owner as usize].1 -= 1;
            }
            *m = *p;
            *owner = me;
            s.written[me as usize].1 += 1;
        } else {
            counts.hidden_fragments += 1;
            behind += u64::from(p.depth - m.depth > BEHIND);
        }
    }
    behind
}

#[cfg(test)]
mod tests {
    use crate::{Culling, PreparedScene, RenderOptions, Renderer};

    /// The visible fragments are the covered pixels; with back faces
    /// culled a tenth of the sphere's fragments at most is hidden behind
    /// another surface (the conservative cone test keeps some back cells
    /// at the silhouette), without culling the far half is (54 % at 120²).
    /// (Without the gap fill, which covers pixels no fragment drew.)
    #[test]
    fn fragments_left_visible_are_the_covered_pixels() {
        let prepared = PreparedScene::default_sphere();
        let camera = prepared.auto_camera(120, 120).expect("camera");
        for (culling, behind) in [(Culling::Back, 0.0..15.0), (Culling::None, 40.0..65.0)] {
            let options = RenderOptions {
                culling,
                threads: 2,
                gap_fill: false,
                ..Default::default()
            };
            let mut renderer = Renderer::new(options).expect("renderer");
            assert_eq!(renderer.occlusion().fragments, 0);
            let out = renderer.render(&prepared, &camera).expect("frame");
            let c = renderer.occlusion();
            assert!(c.fragments > out.stats.covered_pixels, "{culling:?}");
            assert_eq!(c.fragments - c.hidden_fragments, out.stats.covered_pixels);
            assert!(
                behind.contains(&c.hidden_behind_percent),
                "{culling:?}: {c:?}"
            );
        }
    }
}
