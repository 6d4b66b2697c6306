//! Albedo from a patch's colour grid at a patch sample's position.
//!
//! A patch sample names its item's level, the cell in the piece and the
//! sub-node `(a, b)` of the cell cut `nu × nv`; its position on the patch in
//! level-0 grid units is `((i0 + ci + a/nu)·2^m, (j0 + cj + b/nv)·2^m)`, where
//! the colour grid is read bilinearly ([`ColourGrid::albedo_at`]). Phong and
//! Gouraud take that albedo instead of the corners' interpolated one; Gouraud,
//! whose corners carry lit colours, scales the lit colour per channel by the
//! grid's albedo over the corners' interpolated albedo (exact where the light
//! only scales the albedo: unlit, ambient and diffuse; the specular part is
//! scaled too). Flat keeps one colour per cell.
//!
//! Cost: a few dozen instructions per pixel of a patch with a grid; nothing
//! for others (one table lookup).

use glam::Vec3;
use spatch_format::ColourGrid;

use crate::plan::work::Item;
use crate::prepare::patch::{grid_level, PreparedPatch};

/// Where an item's samples lie on its patch's colour grid.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GridPlace<'a> {
    pub(crate) grid: &'a ColourGrid,
    /// The piece's first node in level-0 grid units.
    pub(crate) i0: f32,
    pub(crate) j0: f32,
    /// The level's node spacing in level-0 nodes (`2^m`).
    pub(crate) step: f32,
    pub(crate) nu: f32,
    pub(crate) nv: f32,
}

impl GridPlace<'_> {
    /// The albedo (RGB in 0..=255) of sample `sub` (cell and sub-node bits
    /// as a patch sample carries them). Inlined so that it runs with the
    /// resolve's instruction set ([`crate::isa`]).
    #[inline(always)]
    pub(crate) fn albedo(&self, sub: u32) -> Vec3 {
        let (ci, cj) = ((sub >> 24) as f32, ((sub >> 16) & 0xff) as f32);
        let (a, b) = (((sub >> 8) & 0xff) as f32, (sub & 0xff) as f32);
        let x = self.i0 + (ci + a / self.nu) * self.step;
        let y = self.j0 + (cj + b / self.nv) * self.step;
        Vec3::from_array(self.grid.albedo_at(x, y))
    }
}

/// Where `item` (a piece of a patch of `patches`) lies on its patch's
/// colour grid, or `None` when the patch has none.
#[inline]
pub(crate) fn grid_place<'a>(patches: &'a [PreparedPatch], item: &Item) -> Option<GridPlace<'a>> {
    let grid = patches.get(item.frame as usize)?.colour_grid.as_ref()?;
    let step = (1u32 << grid_level(item.level as usize)) as f32;
    Some(GridPlace {
        grid,
        i0: f32::from(item.i0) * step,
        j0: f32::from(item.j0) * step,
        step,
        nu: f32::from(item.nu),
        nv: f32::from(item.nv),
    })
}

/// The albedo of sample `sub` of `item` interpolated from its cell's
/// corners with weights `w` (the patch's level colours; zero without).
#[inline]
pub(crate) fn corner_albedo(patch: &PreparedPatch, item: &Item, sub: u32, w: [f32; 4]) -> Vec3 {
    let level = patch.level(item.level as usize);
    let Some(colours) = &level.colours else {
        return Vec3::ZERO;
    };
    let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
    let k = (usize::from(item.j0) + cj) * level.cols + usize::from(item.i0) + ci;
    let c = |k: usize| {
        Vec3::new(
            f32::from(colours[k][0]),
            f32::from(colours[k][1]),
            f32::from(colours[k][2]),
        )
    };
    c(k) * w[0] + c(k + 1) * w[1] + c(k + level.cols) * w[2] + c(k + level.cols + 1) * w[3]
}

/// A lit colour `lit` whose albedo was `albedo` (interpolated from the
/// corners), relit for the albedo `fine` of a colour grid: per channel
/// `lit · fine / albedo`, or `lit` where the albedo is below one level (no
/// light factor can be recovered from black).
#[inline]
pub(crate) fn relight(lit: Vec3, albedo: Vec3, fine: Vec3) -> Vec3 {
    let ratio = |l: f32, a: f32, f: f32| if a >= 1.0 { l * f / a } else { l };
    Vec3::new(
        ratio(lit.x, albedo.x, fine.x),
        ratio(lit.y, albedo.y, fine.y),
        ratio(lit.z, albedo.z, fine.z),
    )
    .clamp(Vec3::ZERO, Vec3::splat(255.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use spatch_format::GridSize;

    #[test]
    fn a_sample_reads_the_grid_at_its_level_0_position() {
        let grid = GridSize::new(5, 2).unwrap();
        let samples = (0..9 * 3)
            .map(|k| [(k % 9) as u8 * 10, 0, 0, 255])
            .collect();
        let g = ColourGrid::new(grid, 2, samples).unwrap();
        // Level 1 (step 2), piece at node 2, cell 0, sub-node 1 of 4: x = 2 + 0.25·2.
        let place = GridPlace {
            grid: &g,
            i0: 2.0,
            j0: 0.0,
            step: 2.0,
            nu: 4.0,
            nv: 4.0,
        };
        let sub = (1 << 8) | 2;
        assert_eq!(place.albedo(sub).x, 50.0);
        assert_eq!(
            relight(
                Vec3::new(100.0, 0.0, 60.0),
                Vec3::new(200.0, 0.0, 30.0),
                Vec3::splat(100.0)
            ),
            Vec3::new(50.0, 0.0, 200.0)
        );
    }
}
