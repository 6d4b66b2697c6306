//! The draw items of a frame as the Phong resolve pass reads them: per
//! item its level's prepared normals and albedos from the piece's first
//! node on and its shade frame, and the bilinear weights of the sub-nodes
//! of every subdivision the frame uses. Built once per frame, after
//! planning and binning. A flat frame is resolved the same way, from its
//! levels' cell normals ([`LevelShading::flat`]) with every weight on a
//! sample's first corner: each pixel gets its cell's normal and its first
//! corner's albedo.
//!
//! Cost: O(items) per frame, plus `(nu + 1) · (nv + 1)` weights per
//! distinct subdivision.

use glam::{Vec2, Vec4};

use crate::lighting::{byte_lanes, ShadeFrame};
use crate::options::Shading;
use crate::plan::work::{ChunkWork, Item};
#[cfg(doc)]
use crate::prepare::level_shading::LevelShading;
use crate::prepare::patch::PreparedPatch;
use crate::shade::colour_grid::{grid_place, GridPlace};

/// Flag of [`Lane::frame`]: the pixel takes the base albedo.
pub(crate) const BASE_ALBEDO: u32 = 1 << 31;

/// The shading inputs of one pixel of a group of four.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Lane {
    /// Normal (`xyz`, not unit) and albedo red (`w`, unless the base albedo).
    pub(crate) normal_red: Vec4,
    /// Albedo green and blue (unless the base albedo).
    pub(crate) green_blue: Vec2,
    /// Shade frame index, with [`BASE_ALBEDO`] for the base albedo.
    pub(crate) frame: u32,
}

/// What the Phong resolve pass needs of every draw item of a frame, by
/// index (as [`crate::shade::resolve::Resolve::items`]), and the bilinear weights of the
/// sub-nodes of every subdivision the frame uses. Built once per frame.
/// Why a flat table: where patches overlap, a third of the sphere's pixels
/// change item, and the item → chunk → item → patch → level lookups cost
/// ~70 instructions each (callgrind, `profile_sphere 500 1`).
#[derive(Debug, Default)]
pub(crate) struct PhongItems<'a> {
    pub(crate) items: Vec<PhongItem<'a>>,
    /// True when no item has colours (all take the base albedo).
    pub(crate) uncoloured: bool,
    /// True when some item is shaded from the level below its nodes'
    /// (coarse geometry): the resolve pass then maps sub-nodes through
    /// [`Self::offsets`].
    pub(crate) shifted: bool,
    /// Per item, where it lies on its patch's colour grid; empty when no
    /// item's patch has one (the resolve then skips the lookup).
    pub(crate) grids: Vec<Option<GridPlace<'a>>>,
    /// The shade frames' light and half vectors and directions to the eye
    /// (`w` = 0), by frame index.
    /// Why vectors: lanes of different frames are gathered by transposes
    /// (callgrind, `profile_sphere 500 1`: 60 % of the sphere's groups of
    /// four mix frames where patches overlap).
    pub(crate) frames: Vec<[Vec4; 3]>,
    /// Per subdivision `nu × nv` and shading shift, the weights of
    /// sub-node `(a, b)` at `a * (nv + 1) + b`, each splat over four lanes.
    pub(crate) weights: Vec<[Vec4; 4]>,
    /// Per entry of [`Self::weights`], the shading cell's offset within
    /// the 2 × 2 shading cells of a coarse-geometry cell: `dj << 16 | di`
    /// (0 without a shift; see [`sub_node_place`]).
    pub(crate) offsets: Vec<u32>,
}

impl<'a> PhongItems<'a> {
    /// The table for the draw items `items` (`(chunk, item)`) of `chunks`,
    /// which refer to `patches` and `frames`; empty for Gouraud.
    pub(crate) fn new(
        shading: Shading,
        items: &[(u32, u32)],
        chunks: &[ChunkWork],
        patches: &'a [PreparedPatch],
        frames: &[ShadeFrame],
    ) -> Self {
        let mut table = Self::default();
        if shading == Shading::Gouraud {
            return table;
        }
        let flat = shading == Shading::Flat;
        table.frames = frames
            .iter()
            .map(|f| [f.light.extend(0.0), f.half.extend(0.0), f.view.extend(0.0)])
            .collect();
        let mut built: Vec<(u16, u16, u8, u32)> = Vec::new();
        table.items.reserve(items.len());
        for &(c, i) in items {
            let item = &chunks[c as usize].items[i as usize];
            let (nu, nv, shift) = (item.nu, item.nv, item.shade_shift);
            let key = (nu, nv, shift);
            let start = match built.iter().find(|&&(u, v, h, _)| (u, v, h) == key) {
                Some(&(_, _, _, start)) => start,
                None => {
                    let start = table.weights.len() as u32;
                    for a in 0..=nu as u32 {
                        for b in 0..=nv as u32 {
                            let (w, offset) = match flat {
                                true => ([1.0, 0.0, 0.0, 0.0], 0),
                                false => sub_node_place(a, b, nu as u32, nv as u32, shift as u32),
                            };
                            table.weights.push(w.map(Vec4::splat));
                            table.offsets.push(offset);
                        }
                    }
                    built.push((nu, nv, shift, start));
                    start
                }
            };
            let entry = PhongItem::new(item, patches, &table.frames, (start, flat));
            table.items.push(entry);
        }
        table.uncoloured = table.items.iter().all(|item| item.colours.is_empty());
        table.shifted = table.items.iter().any(|item| item.shift != 0);
        // Flat shading keeps its cells' colours, not the colour grids'.
        if !flat && patches.iter().any(|p| p.colour_grid.is_some()) {
            table.grids = items
                .iter()
                .map(|&(c, i)| grid_place(patches, &chunks[c as usize].items[i as usize]))
                .collect();
            table.uncoloured = false;
        }
        table
    }
}

/// A draw item as the Phong resolve pass reads it: its level's prepared
/// normals and albedos from the piece's first node on.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PhongItem<'a> {
    /// The light vector of the item's shade frame (`w` = 0).
    pub(crate) light: Vec4,
    /// The half vector of the item's shade frame (`w` = 0).
    pub(crate) half: Vec4,
    /// The direction to the eye of the item's shade frame (`w` = 0; zero
    /// when one-sided).
    pub(crate) view: Vec4,
    pub(crate) normals: &'a [Vec4],
    /// The level's prepared albedos from the piece's first node on; empty
    /// for the base albedo. Why in the item: the pixel's item is read
    /// anyway, so its albedos need no second lookup by item index.
    pub(crate) colours: &'a [[u8; 4]],
    /// Nodes per row of the shading grid (`u16`: index sums cannot overflow, no
    /// checks).
    pub(crate) cols: u16,
    /// Weights per row of the item's weight table (`nv + 1`).
    pub(crate) stride: u16,
    /// The item's shading shift (1: coarse geometry, a cell holds 2 × 2
    /// shading cells).
    pub(crate) shift: u32,
    /// Where the item's weights start in [`PhongItems::weights`].
    pub(crate) weights: u32,
    /// The item's shade frame, with [`BASE_ALBEDO`] for an item without
    /// colours.
    pub(crate) frame: u32,
}

impl<'a> PhongItem<'a> {
    /// The entry of `item` (of a patch of `patches`, shaded in one of
    /// `frames`) whose weights start at `weights`, from its level's
    /// flat-shading inputs when `flat`.
    fn new(
        item: &Item,
        patches: &'a [PreparedPatch],
        frames: &[[Vec4; 3]],
        (weights, flat): (u32, bool),
    ) -> Self {
        let patch = &patches[item.frame as usize];
        let m = item.level as usize;
        let shift = item.shade_shift as usize;
        let (cols, shading) = match (flat, shift) {
            (true, _) => (patch.level(m).cols, patch.flat_shading(m)),
            (false, 0) => (patch.level(m).cols, patch.shading(m)),
            (false, _) => ((patch.level(m).cols - 1) * 2 + 1, patch.fine_shading(m)),
        };
        debug_assert!(!flat || shift == 0, "coarse geometry is Phong's alone");
        let start = (item.j0 as usize * cols + item.i0 as usize) << shift;
        let uniform = item.uniform_albedo || shading.colours.is_empty();
        let [light, half, view] = frames[item.frame as usize];
        let colours: &[[u8; 4]] = if uniform {
            &[]
        } else {
            &shading.colours[start..]
        };
        Self {
            light,
            half,
            view,
            normals: &shading.normals[start..],
            colours,
            cols: cols as u16,
            stride: item.nv + 1,
            shift: shift as u32,
            weights,
            frame: item.frame | if uniform { BASE_ALBEDO } else { 0 },
        }
    }

    /// The normal interpolated at sample `sub` (`w` unused): the same
    /// operations in the same order as `phong_reference`.
    #[inline(always)]
    /// `SHIFTED` false: no item of the frame has a shift.
    pub(crate) fn normal<const SHIFTED: bool>(
        &self,
        sub: u32,
        weights: &[[Vec4; 4]],
        offsets: &[u32],
    ) -> Vec4 {
        let (k, w) = self.corner(sub, weights, offsets, SHIFTED);
        bilinear(self.normals, k, self.cols as usize, w, |n| n)
    }

    /// The normal and albedo interpolated at sample `sub`: the same
    /// operations in the same order as `phong_reference`. `SHIFTED` false:
    /// no item of the frame has a shift.
    #[inline(always)]
    pub(crate) fn interpolate<const SHIFTED: bool>(
        &self,
        sub: u32,
        weights: &[[Vec4; 4]],
        offsets: &[u32],
    ) -> Lane {
        let (k, w) = self.corner(sub, weights, offsets, SHIFTED);
        let cols = self.cols as usize;
        let mut lane = Lane {
            normal_red: bilinear(self.normals, k, cols, w, |n| n),
            green_blue: Vec2::ZERO,
            frame: self.frame,
        };
        if self.frame & BASE_ALBEDO == 0 {
            let c = bilinear(self.colours, k, cols, w, byte_lanes);
            lane.normal_red.w = c.x;
            lane.green_blue = Vec2::new(c.y, c.z);
        }
        lane
    }

    /// The normal and the albedo (`xyz`) interpolated at sample `sub` of
    /// an item with colours: [`Self::interpolate`]'s values, as two
    /// vectors for the eight-pixel groups' transposes
    /// ([`crate::shade::resolve_wide`]).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(crate) fn normal_colour<const SHIFTED: bool>(
        &self,
        sub: u32,
        weights: &[[Vec4; 4]],
        offsets: &[u32],
    ) -> (Vec4, Vec4) {
        let (k, w) = self.corner(sub, weights, offsets, SHIFTED);
        let cols = self.cols as usize;
        let normal = bilinear(self.normals, k, cols, w, |n| n);
        (normal, bilinear(self.colours, k, cols, w, byte_lanes))
    }
}

impl PhongItem<'_> {
    /// The first corner (index into the item's normals) of the shading
    /// cell of sample `sub`, and the corners' weights there (`may_shift`
    /// false: the item has no shift).
    #[inline(always)]
    fn corner<'w>(
        &self,
        sub: u32,
        weights: &'w [[Vec4; 4]],
        offsets: &[u32],
        may_shift: bool,
    ) -> (usize, &'w [Vec4; 4]) {
        let cols = self.cols as usize;
        let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
        let (a, b) = (((sub >> 8) & 0xff) as usize, (sub & 0xff) as usize);
        let entry = self.weights as usize + a * self.stride as usize + b;
        // Why `may_shift` (a constant in the hot path) and the branch:
        // without a shift (the default) the offset's load and shifts cost
        // 1 M instructions per bunny frame, the branch alone 0.4 M
        // (callgrind, 500²).
        if !may_shift || self.shift == 0 {
            return (cj * cols + ci, &weights[entry]);
        }
        let o = offsets[entry] as usize;
        let shift = self.shift;
        let k = ((cj << shift) + (o >> 16)) * cols + (ci << shift) + (o & 0xffff);
        (k, &weights[entry])
    }
}

/// The bilinear sum of a cell's corners `(0, 0), (1, 0), (0, 1), (1, 1)`,
/// the first at `values[k]` in rows of `cols` values, each as `lanes`
/// reads it, weighted by `w` in that order (the order `phong_reference`
/// sums in). Why one slice of the four corners: a single bounds check.
#[inline(always)]
fn bilinear<T: Copy>(
    values: &[T],
    k: usize,
    cols: usize,
    w: &[Vec4; 4],
    lanes: impl Fn(T) -> Vec4,
) -> Vec4 {
    let quad = &values[k..k + cols + 2];
    let at = |k: usize| lanes(quad[k]);
    at(0) * w[0] + at(1) * w[1] + at(cols) * w[2] + at(cols + 1) * w[3]
}

/// The corner weights of sub-node `(a, b)` of a cell cut `nu × nv` in its
/// shading cell, and that cell's offset `dj << 16 | di`: with `shift` 0
/// the cell itself ([`sub_node_weights`], offset 0); with `shift` 1 (coarse
/// geometry) the cell spans 2 × 2 shading cells, so the point `2a / nu`
/// lies in shading cell `min(⌊2a / nu⌋, 1)` at the rest.
pub(crate) fn sub_node_place(a: u32, b: u32, nu: u32, nv: u32, shift: u32) -> ([f32; 4], u32) {
    if shift == 0 {
        return (sub_node_weights(a, b, nu, nv), 0);
    }
    let split = |a: u32, n: u32| {
        let t = a << shift;
        let off = (t / n).min((1 << shift) - 1);
        (off, (t - off * n) as f32 / n as f32)
    };
    let ((di, s), (dj, t)) = (split(a, nu), split(b, nv));
    let w = [(1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t];
    (w, dj << 16 | di)
}

/// The bilinear weights of the corners `(0, 0), (1, 0), (0, 1), (1, 1)` at
/// sub-node `(a, b)` of a cell cut `nu × nv`.
#[inline(always)]
pub(crate) fn sub_node_weights(a: u32, b: u32, nu: u32, nv: u32) -> [f32; 4] {
    let s = a as f32 / nu as f32;
    let t = b as f32 / nv as f32;
    [(1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With a shift, each sub-node lands at `2a / nu` (and `2b / nv`) of
    /// its shading cells: the offset plus the weights' position gives it
    /// back, within one shading cell pair, and the weights sum to 1.
    #[test]
    fn shifted_sub_nodes_land_at_their_point_of_the_shading_cells() {
        for (nu, nv) in [(1, 1), (2, 3), (3, 2), (4, 4), (5, 7), (64, 1)] {
            for a in 0..=nu {
                for b in 0..=nv {
                    let (w, offset) = sub_node_place(a, b, nu, nv, 1);
                    let (di, dj) = ((offset & 0xffff) as f32, (offset >> 16) as f32);
                    assert!(di <= 1.0 && dj <= 1.0);
                    let (s, t) = (w[1] + w[3], w[2] + w[3]);
                    assert!((di + s - 2.0 * a as f32 / nu as f32).abs() < 1e-6);
                    assert!((dj + t - 2.0 * b as f32 / nv as f32).abs() < 1e-6);
                    assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
                }
            }
            assert_eq!(
                sub_node_place(1, 1, nu, nv, 0),
                (sub_node_weights(1, 1, nu, nv), 0)
            );
        }
    }
}
