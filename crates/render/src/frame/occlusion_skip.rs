//! The occlusion skip: a band leaves out a piece that the pixels it has
//! already drawn hide entirely.
//!
//! Input: the band's draw items, each with its screen box and a lower bound
//! of its samples' depths ([`Item::z_near`], from its projected nodes).
//! The band is cut into square tiles of [`TILE`] pixels; each tile keeps
//! its farthest depth, recomputed from the band's pixels only when a test
//! needs it after a piece touched the tile. A tile with an empty pixel has
//! the far plane as its farthest depth, so it hides nothing.
//!
//! Invariant (why the image does not change): a piece is skipped only when
//! its nearest depth is strictly behind the farthest depth of every tile its
//! box (one pixel wider each side) touches. Every sample it would place is
//! then strictly behind its pixel, and fails the depth test. Pieces keep
//! their planning order: drawn nearest first, the bunny skipped 2.6 times
//! as many, but which of two pieces placing the same depth in a pixel shows
//! then depends on the order, and the tie rule that fixes it cost more
//! than the extra skips saved (docs/algorithms/render.md, "Occlusion skip").
//!
//! Cost: per tested piece one look per tile of its box, and one pass over
//! a tile's pixels per (piece drawn, tile) pair that a later test reads.

use crate::fixed::Z_FAR;
use crate::plan::work::Item;
use crate::raster::band::Sample;

/// Tile side in pixels, as a shift.
const TILE_SHIFT: i32 = 3;
/// Tile side in pixels.
pub(crate) const TILE: i32 = 1 << TILE_SHIFT;

/// The tiles of one band and the pieces it skipped.
#[derive(Debug, Default)]
pub(crate) struct SkipTiles {
    y0: i32,
    rows: i32,
    width: i32,
    /// Tiles per row of tiles.
    across: usize,
    /// Per tile, its farthest depth (valid when not `stale`).
    far: Vec<i32>,
    /// Per tile, whether a piece drew in it since `far` was computed.
    stale: Vec<bool>,
    /// Pieces skipped in the band.
    pub(crate) skipped: u64,
}

impl SkipTiles {
    /// Starts a band of rows `y0..y0 + rows` of `width`: every tile empty.
    pub(crate) fn begin(&mut self, y0: i32, rows: i32, width: i32) {
        self.y0 = y0;
        self.rows = rows;
        self.width = width;
        self.across = (width + TILE - 1) as usize >> TILE_SHIFT;
        let tiles = self.across * ((rows + TILE - 1) as usize >> TILE_SHIFT);
        self.far.clear();
        self.far.resize(tiles, Z_FAR);
        self.stale.clear();
        self.stale.resize(tiles, false);
        self.skipped = 0;
    }

    /// The tiles `[tx0, tx1] × [ty0, ty1]` that `item`'s box, one pixel
    /// wider each side, touches in the band; `None` when it touches none.
    fn tiles_of(&self, item: &Item) -> Option<[usize; 4]> {
        let x0 = (item.x0 - 1).max(0);
        let x1 = (item.x1 + 1).min(self.width - 1);
        let y0 = (item.y0 - 1 - self.y0).max(0);
        let y1 = (item.y1 + 1 - self.y0).min(self.rows - 1);
        (x0 <= x1 && y0 <= y1).then(|| [x0, x1, y0, y1].map(|v| (v >> TILE_SHIFT) as usize))
    }

    /// Whether the pixels `px` of the band hide every sample `item` could
    /// place (see the module header); counts it as skipped if so.
    pub(crate) fn hidden(&mut self, px: &[Sample], item: &Item) -> bool {
        let Some([tx0, tx1, ty0, ty1]) = self.tiles_of(item) else {
            return false;
        };
        if item.z_near == i32::MIN {
            return false;
        }
        let tiles = |across: usize| {
            (ty0..=ty1).flat_map(move |ty| (tx0..=tx1).map(move |tx| (tx, ty, ty * across + tx)))
        };
        // Why two passes: a tile known to be open (often still empty)
        // answers before any stale tile is read again.
        let (far, stale) = (&self.far, &self.stale);
        if tiles(self.across).any(|(_, _, k)| !stale[k] && far[k] >= item.z_near) {
            return false;
        }
        for (tx, ty, k) in tiles(self.across) {
            if self.stale[k] {
                self.far[k] = self.farthest(px, tx, ty);
                self.stale[k] = false;
                if self.far[k] >= item.z_near {
                    return false;
                }
            }
        }
        self.skipped += 1;
        true
    }

    /// Marks the tiles `item` may have drawn in as stale.
    pub(crate) fn drawn(&mut self, item: &Item) {
        let Some([tx0, tx1, ty0, ty1]) = self.tiles_of(item) else {
            return;
        };
        for ty in ty0..=ty1 {
            let row = ty * self.across;
            self.stale[row + tx0..=row + tx1].fill(true);
        }
    }

    /// The farthest depth of tile `(tx, ty)` in the band's pixels `px`.
    fn farthest(&self, px: &[Sample], tx: usize, ty: usize) -> i32 {
        let w = self.width as usize;
        let x0 = tx << TILE_SHIFT;
        let x1 = (x0 + TILE as usize).min(w);
        let y0 = ty << TILE_SHIFT;
        let y1 = (y0 + TILE as usize).min(self.rows as usize);
        (y0..y1)
            .flat_map(|y| &px[y * w + x0..y * w + x1])
            .fold(i32::MIN, |m, s| m.max(s.depth))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn item(x: [i32; 2], y: [i32; 2], z_near: i32) -> Item {
        Item {
            y0: y[0],
            y1: y[1],
            x0: x[0],
            x1: x[1],
            z_near,
            ..Item::for_tests()
        }
    }

    /// A 32 × 16 band at row 16: the left half drawn at depth 100 hides a
    /// piece behind it only while the piece's box (one pixel wider) stays
    /// in the drawn tiles and its nearest depth is strictly behind.
    #[test]
    fn a_piece_is_hidden_only_behind_full_tiles_nearer_than_it() {
        let (w, rows) = (32, 16);
        let mut tiles = SkipTiles::default();
        tiles.begin(16, rows, w);
        let mut px = vec![Sample::EMPTY; (w * rows) as usize];
        let wall = item([0, 15], [16, 31], 0);
        assert!(!tiles.hidden(&px, &wall), "an empty band hides nothing");
        for y in 0..rows {
            for x in 0..16 {
                px[(y * w + x) as usize].depth = 100;
            }
        }
        tiles.drawn(&wall);
        assert!(tiles.hidden(&px, &item([2, 12], [18, 28], 101)));
        assert!(
            !tiles.hidden(&px, &item([2, 12], [18, 28], 100)),
            "ties draw"
        );
        assert!(
            !tiles.hidden(&px, &item([2, 15], [18, 28], 500)),
            "reaches x = 16"
        );
        px[(5 * w + 3) as usize].depth = 400;
        tiles.drawn(&item([3, 3], [21, 21], 0));
        assert!(
            !tiles.hidden(&px, &item([2, 6], [18, 22], 300)),
            "a far pixel"
        );
        assert!(tiles.hidden(&px, &item([2, 6], [18, 22], 401)));
        assert_eq!(tiles.skipped, 2);
    }
}
