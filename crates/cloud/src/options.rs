//! The options of [`cloud_to_scene`](crate::cloud_to_scene), with their defaults and what each
//! one trades.

use spatch_format::WriteOptions;

/// Edge-preserving smoothing of the range images (a bilateral filter, see `smooth.rs`).
///
/// Smoothing lowers noise on scans at the cost of rounding fine detail (features smaller than
/// the filter radius) and a little time (one pass over the pixels of every view per
/// iteration).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct SmoothOptions {
    /// Filter radius in pixels, 1..=8. Default [`SmoothOptions::DEFAULT_RADIUS`] (2, a 5×5
    /// window). A larger radius removes more noise and more detail.
    pub radius: u32,
    /// Passes of the filter, 1..=8. Default [`SmoothOptions::DEFAULT_ITERATIONS`] (2).
    pub iterations: u32,
    /// Cut-off of the range weight, in multiples of the noise estimated in each range image
    /// (positive). Default [`SmoothOptions::DEFAULT_RANGE`] (3.0). Depth differences near it get
    /// little weight and beyond it none (edges and curved detail are kept); larger values
    /// average more but flatten curved surface.
    pub range: f32,
}

impl SmoothOptions {
    /// Default [`SmoothOptions::radius`].
    pub const DEFAULT_RADIUS: u32 = 2;
    /// Default [`SmoothOptions::iterations`].
    pub const DEFAULT_ITERATIONS: u32 = 2;
    /// Default [`SmoothOptions::range`].
    pub const DEFAULT_RANGE: f32 = 3.0;
}

impl Default for SmoothOptions {
    fn default() -> Self {
        SmoothOptions {
            radius: Self::DEFAULT_RADIUS,
            iterations: Self::DEFAULT_ITERATIONS,
            range: Self::DEFAULT_RANGE,
        }
    }
}

/// Options of the point cloud → patches pipeline.
///
/// Lengths are given in multiples of the point spacing `s` (estimated from the cloud, see
/// [`CloudOptions::spacing`]) so that one set of defaults serves clouds of any scale.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct CloudOptions {
    /// Number of view directions, 1..=1000. Default [`CloudOptions::DEFAULT_VIEWS`] (20,
    /// every surface normal within about 27° of a view). More views cost time (one range
    /// image each) and let more surface be seen nearly head-on (denser nodes on steep parts);
    /// fewer views leave occluded or steep parts to the relaxed second pass.
    pub views: usize,
    /// Pixel (node) spacing in multiples of the point spacing, 0.25..=16. Default
    /// [`CloudOptions::DEFAULT_PIXEL_FACTOR`] (2.0: about four points per pixel on a surface
    /// facing the view, so sampling gaps are rare and at most one or two pixels wide, and a
    /// scene has about half as many nodes as the cloud has points). Smaller pixels keep more
    /// detail but leave more gaps and cost more nodes (1.4 doubles them on the bunny scans
    /// without lowering `cloud_to_patch`, which scanner noise dominates); larger pixels cost
    /// fewer nodes and smooth detail away.
    pub pixel_factor: f32,
    /// Widest gap (in pixels, 0..=8) that is filled by interpolating the depths on both
    /// sides. Default [`CloudOptions::DEFAULT_MAX_GAP`] (2). Wider fills close more holes but
    /// may bridge real openings narrower than the fill.
    pub max_gap: u32,
    /// Depth discontinuity threshold between neighbouring pixels, in pixels, > 0. Default
    /// [`CloudOptions::DEFAULT_JUMP_FACTOR`] (3: a step of more than 3 pixel widths in depth
    /// between neighbours separates two surfaces). Lower values split steep surfaces; higher
    /// values join layers (the two sides of a thin sheet) into one patch.
    pub jump_factor: f32,
    /// Steepest surface accepted in the first pass over the views, in degrees between the
    /// surface normal and the view direction, 1..=89. Default
    /// [`CloudOptions::DEFAULT_PREFERRED_SLOPE`] (40). Every surface is first given to a view
    /// that sees it nearly head-on (dense, accurate nodes).
    pub preferred_slope_degrees: f32,
    /// Steepest surface accepted in the second pass, which covers what the first pass left
    /// (occluded from the good views), in degrees, ≥ the preferred slope, ≤ 89. Default
    /// [`CloudOptions::DEFAULT_MAX_SLOPE`] (70). Steeper patches have nodes farther apart on
    /// the surface (`pixel / cos(angle)`), so they are less accurate.
    pub max_slope_degrees: f32,
    /// How far a point may be from a patch surface and still count as covered by it, in
    /// multiples of the spacing, > 0. Default [`CloudOptions::DEFAULT_COVER_TOLERANCE`]
    /// (1.5). Points farther away stay uncovered and are offered to later views. Raise it for
    /// noisy scans whose noise exceeds the spacing.
    pub cover_tolerance: f32,
    /// Edge-preserving smoothing of the range images, off by default (`None`). Use it for
    /// noisy scans.
    pub smooth: Option<SmoothOptions>,
    /// Most nodes per patch side, 2..=257. Default [`CloudOptions::DEFAULT_GRID`] (33). Each
    /// region of a view's range image becomes one patch when it fits, else it is halved
    /// until the pieces do (`patch_cut.rs`). Larger patches cost fewer frames (bytes) and
    /// fewer repeated border nodes but more 16-bit codes (a wider depth range) and coarser
    /// culling (on the ten bunny scans 33 gives 156 filled nodes a patch, 17 gave 92).
    pub grid: u32,
    /// Voxel side for the PCA normals, in multiples of the spacing, 0.5..=8. Default
    /// [`CloudOptions::DEFAULT_NORMAL_VOXEL`] (2.0: each normal fits the points of a
    /// 3×3×3-voxel block, about 35–70 points, about 6 spacings wide; the same blocks give
    /// the consensus planes). Larger voxels give smoother normals and a smoother consensus
    /// surface on noisy scans and blur them at creases (on the ten registered bunny scans,
    /// 1.0 / 1.5 / 2.0 / 3.0 gave 2.97 / 0.72 / 0.41 / 0.67 % dark specks; 1.5 was the
    /// default before the consensus stage).
    pub normal_voxel: f32,
    /// Move every point onto the least-squares plane of its normal-voxel block before the
    /// range images are drawn (`consensus.rs`), so that overlapping scans offset from each
    /// other give one surface. Default off: on a single clean cloud it pulls nodes off curved
    /// surfaces (the sampled bunny's node error rises past 0.15 spacings); `spatch
    /// from-cloud` turns it on when its inputs hold several scans. Points whose block spreads more than
    /// [`CloudOptions::CONSENSUS_MAX_SPREAD`] spacings from its plane (creases, thin parts)
    /// or that lie more than [`CloudOptions::CONSENSUS_MAX_MOVE`] spacings from it stay put.
    /// Off: each view averages whichever scans fall in its pixels (specks and z-fighting
    /// where views overlap on registered scan sets).
    pub consensus: bool,
    /// Point spacing `s` in model units; `None` (default) estimates it from the 12 nearest
    /// neighbours of up to 20,000 sample points (see `spacing.rs`).
    pub spacing: Option<f32>,
    /// Target quantization step of the 8-bit displacements, in multiples of the spacing, > 0.
    /// Default [`CloudOptions::DEFAULT_DISPLACEMENT_STEP`] (0.01). Patches whose depth range
    /// needs a coarser step than [`CloudOptions::DEFAULT_MAX_DISPLACEMENT_STEP`] × spacing
    /// are stored with 16-bit codes.
    pub displacement_step: f32,
    /// Container options (compression of node data). Default: uncompressed.
    pub write: WriteOptions,
    /// Side of the spatial tiles (model units, positive), each converted with its own range
    /// images; `None` (default) makes one tile of a cloud whose images fit
    /// [`PIXEL_BUDGET`](crate::PIXEL_BUDGET) and, for larger extents, tiles sized to that
    /// budget (`tiles.rs`). Smaller tiles need less memory and cost a little overlap at
    /// their borders; tiles too large for the budget fail (or coarsen, below).
    pub tile_size: Option<f32>,
    /// When a tile's range images would exceed the pixel budget anyway (a `tile_size` too
    /// large for the spacing), enlarge that tile's pixel with a warning instead of failing
    /// with [`CloudError::PixelBudgetExceeded`](crate::CloudError::PixelBudgetExceeded).
    /// Default off: the resolution never drops silently.
    pub allow_coarsening: bool,
    /// A grid every run shares (a scale-out plan's: anchor, tile side, buffer), used
    /// instead of one anchored at the cloud's lowest corner; overrides
    /// [`CloudOptions::tile_size`]. Default `None`.
    pub tile_grid: Option<crate::TileGrid>,
    /// Convert only this tile of the grid (its key, see [`crate::TileGrid::key_of`]): its
    /// own points and its buffer's, keeping the patches cut for its own points, so runs of
    /// each tile of a cloud join with no duplicate. Needs [`CloudOptions::tile_grid`].
    /// Default `None` (every tile).
    pub only_tile: Option<[i64; 3]>,
    /// Where the scanners of a scan set were and which points each saw (structured scans,
    /// `spatch_scan::Viewpoint`), for a cloud without normals of its own. Each point then
    /// takes the PCA normal of its voxel block turned to its scanner's side (zero where the
    /// block has no plane), and a view draws only the points whose normal faces it, so the
    /// two sides of a thin part seen by different scans (an ear) are never averaged into one
    /// pixel, back-facing points never win a pixel, and a view's cells cover only the points
    /// facing it. Default `None`: normals are used up to sign and every view draws every
    /// point not seen at a grazing angle. Ignored when the cloud has normals. On the ten
    /// bunny scans: specks 0.366 → 0.336 %, holes 0.055 → 0.021 %
    /// (docs/algorithms/cloud.md, "Range grids").
    pub scanners: Option<crate::Scanners>,
    /// With [`CloudOptions::scanners`] and the consensus on, move each scan by the
    /// translation that best puts its points on the voxel blocks' planes before the
    /// consensus (`scan_shifts.rs`): removes the rigid part of the scans' misregistration.
    /// Default on.
    pub align_scans: bool,
    /// With [`CloudOptions::align_scans`] (and the scanners and the consensus), the
    /// translation of each scan of [`CloudOptions::scanners`] (in their order), used instead
    /// of computing it from this cloud: a tiled run's, computed once over every tile with
    /// [`scan_shift_sums`](crate::scan_shift_sums) so that the tiles agree at their seams.
    /// Default `None` (computed).
    pub scan_shifts: Option<Vec<glam::DVec3>>,
}

impl CloudOptions {
    /// Default [`CloudOptions::views`].
    pub const DEFAULT_VIEWS: usize = 20;
    /// Default [`CloudOptions::pixel_factor`].
    pub const DEFAULT_PIXEL_FACTOR: f32 = 2.0;
    /// Default [`CloudOptions::max_gap`].
    pub const DEFAULT_MAX_GAP: u32 = 2;
    /// Default [`CloudOptions::jump_factor`].
    pub const DEFAULT_JUMP_FACTOR: f32 = 3.0;
    /// Default [`CloudOptions::preferred_slope_degrees`].
    pub const DEFAULT_PREFERRED_SLOPE: f32 = 40.0;
    /// Default [`CloudOptions::max_slope_degrees`].
    pub const DEFAULT_MAX_SLOPE: f32 = 70.0;
    /// Default [`CloudOptions::cover_tolerance`].
    pub const DEFAULT_COVER_TOLERANCE: f32 = 1.5;
    /// Default [`CloudOptions::grid`].
    pub const DEFAULT_GRID: u32 = 33;
    /// Default [`CloudOptions::normal_voxel`].
    pub const DEFAULT_NORMAL_VOXEL: f32 = 2.0;
    /// Default [`CloudOptions::displacement_step`].
    pub const DEFAULT_DISPLACEMENT_STEP: f32 = 0.01;
    /// Largest RMS distance (in spacings) of a block's points from its plane for the block to
    /// move points onto it ([`CloudOptions::consensus`]).
    pub const CONSENSUS_MAX_SPREAD: f32 = 1.0;
    /// Largest distance (in spacings) a point moves onto its block's plane.
    pub const CONSENSUS_MAX_MOVE: f32 = 2.0;
    /// Coarsest 8-bit step (in spacings) before a patch is stored with 16-bit codes (0.1
    /// made the ten bunny scans' file 24 % smaller with the same specks, but put the 95th
    /// percentile of a clean tilted plane's cloud error at 0.026 s, over its 0.02 s test).
    pub const DEFAULT_MAX_DISPLACEMENT_STEP: f32 = 0.05;

    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<(), crate::CloudError> {
        self.validate_images()?;
        self.validate_extraction()?;
        self.validate_scales()?;
        if let Some(smooth) = self.smooth {
            smooth.validate()?;
        }
        Ok(())
    }

    /// Checks the options of the range images: views, pixel, gaps and discontinuities.
    fn validate_images(&self) -> Result<(), crate::CloudError> {
        check(
            (1..=1000).contains(&self.views),
            "views",
            "must be 1..=1000",
        )?;
        check(
            (0.25..=16.0).contains(&self.pixel_factor),
            "pixel_factor",
            "must be 0.25..=16",
        )?;
        check(self.max_gap <= 8, "max_gap", "must be 0..=8 pixels")?;
        check(
            self.jump_factor.is_finite() && self.jump_factor > 0.0,
            "jump_factor",
            "must be a positive number",
        )
    }

    /// Checks the options of the region extraction: slopes, cover tolerance and grid.
    fn validate_extraction(&self) -> Result<(), crate::CloudError> {
        check(
            (1.0..=89.0).contains(&self.preferred_slope_degrees),
            "preferred_slope_degrees",
            "must be 1..=89",
        )?;
        check(
            self.max_slope_degrees >= self.preferred_slope_degrees
                && self.max_slope_degrees <= 89.0,
            "max_slope_degrees",
            "must be between the preferred slope and 89",
        )?;
        check(
            self.cover_tolerance.is_finite() && self.cover_tolerance > 0.0,
            "cover_tolerance",
            "must be a positive number",
        )?;
        check((2..=257).contains(&self.grid), "grid", "must be 2..=257")
    }

    /// Checks the lengths (normal voxel, spacing, displacement step, tile size) and the tile
    /// choice.
    fn validate_scales(&self) -> Result<(), crate::CloudError> {
        check(
            (0.5..=8.0).contains(&self.normal_voxel),
            "normal_voxel",
            "must be 0.5..=8",
        )?;
        check(
            self.spacing.is_none_or(|s| s.is_finite() && s > 0.0),
            "spacing",
            "must be a positive number",
        )?;
        check(
            self.displacement_step.is_finite() && self.displacement_step > 0.0,
            "displacement_step",
            "must be a positive number",
        )?;
        check(
            self.tile_size.is_none_or(|s| s.is_finite() && s > 0.0),
            "tile_size",
            "must be a positive number",
        )?;
        check(
            self.only_tile.is_none() || self.tile_grid.is_some(),
            "only_tile",
            "needs tile_grid",
        )
    }
}

impl SmoothOptions {
    /// Checks every field against its documented range (the errors name them `smooth.*`).
    fn validate(&self) -> Result<(), crate::CloudError> {
        check(
            (1..=8).contains(&self.radius),
            "smooth.radius",
            "must be 1..=8",
        )?;
        check(
            (1..=8).contains(&self.iterations),
            "smooth.iterations",
            "must be 1..=8",
        )?;
        check(
            self.range.is_finite() && self.range > 0.0,
            "smooth.range",
            "must be a positive number",
        )
    }
}

/// `Ok` when `ok`, else the invalid `option` with its `reason`.
fn check(ok: bool, option: &'static str, reason: &'static str) -> Result<(), crate::CloudError> {
    if ok {
        Ok(())
    } else {
        Err(crate::CloudError::InvalidOption { option, reason })
    }
}

impl Default for CloudOptions {
    fn default() -> Self {
        CloudOptions {
            views: Self::DEFAULT_VIEWS,
            pixel_factor: Self::DEFAULT_PIXEL_FACTOR,
            max_gap: Self::DEFAULT_MAX_GAP,
            jump_factor: Self::DEFAULT_JUMP_FACTOR,
            preferred_slope_degrees: Self::DEFAULT_PREFERRED_SLOPE,
            max_slope_degrees: Self::DEFAULT_MAX_SLOPE,
            cover_tolerance: Self::DEFAULT_COVER_TOLERANCE,
            smooth: None,
            grid: Self::DEFAULT_GRID,
            normal_voxel: Self::DEFAULT_NORMAL_VOXEL,
            consensus: false,
            spacing: None,
            displacement_step: Self::DEFAULT_DISPLACEMENT_STEP,
            write: WriteOptions::default(),
            tile_size: None,
            tile_grid: None,
            only_tile: None,
            allow_coarsening: false,
            scanners: None,
            align_scans: true,
            scan_shifts: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CloudError;

    /// The option and reason `validate` refuses the default options changed by `change`
    /// with, or `None` when it accepts them.
    fn refusal(change: impl FnOnce(&mut CloudOptions)) -> Option<(&'static str, &'static str)> {
        let mut options = CloudOptions::default();
        change(&mut options);
        match options.validate() {
            Ok(()) => None,
            Err(CloudError::InvalidOption { option, reason }) => Some((option, reason)),
            Err(other) => panic!("not an invalid option: {other}"),
        }
    }

    /// A change of the default options, the option it makes invalid and the reason given.
    type Case = (fn(&mut CloudOptions), &'static str, &'static str);

    /// The default smoothing changed by `change`.
    fn smooth(change: fn(&mut SmoothOptions)) -> Option<SmoothOptions> {
        let mut options = SmoothOptions::default();
        change(&mut options);
        Some(options)
    }

    #[test]
    fn every_field_out_of_range_is_named_with_its_range() {
        let positive = "must be a positive number";
        assert_eq!(refusal(|_| {}), None);
        assert_eq!(refusal(|o| o.smooth = smooth(|_| {})), None);
        let cases: [Case; 17] = [
            (|o| o.views = 0, "views", "must be 1..=1000"),
            (
                |o| o.pixel_factor = 17.0,
                "pixel_factor",
                "must be 0.25..=16",
            ),
            (|o| o.max_gap = 9, "max_gap", "must be 0..=8 pixels"),
            (|o| o.jump_factor = 0.0, "jump_factor", positive),
            (
                |o| o.preferred_slope_degrees = 0.5,
                "preferred_slope_degrees",
                "must be 1..=89",
            ),
            (
                |o| o.max_slope_degrees = 30.0,
                "max_slope_degrees",
                "must be between the preferred slope and 89",
            ),
            (
                |o| o.cover_tolerance = f32::NAN,
                "cover_tolerance",
                positive,
            ),
            (|o| o.grid = 258, "grid", "must be 2..=257"),
            (|o| o.normal_voxel = 0.25, "normal_voxel", "must be 0.5..=8"),
            (|o| o.spacing = Some(0.0), "spacing", positive),
            (
                |o| o.displacement_step = -1.0,
                "displacement_step",
                positive,
            ),
            (|o| o.tile_size = Some(f32::INFINITY), "tile_size", positive),
            (
                |o| o.only_tile = Some([0; 3]),
                "only_tile",
                "needs tile_grid",
            ),
            (
                |o| o.smooth = smooth(|s| s.radius = 0),
                "smooth.radius",
                "must be 1..=8",
            ),
            (
                |o| o.smooth = smooth(|s| s.iterations = 9),
                "smooth.iterations",
                "must be 1..=8",
            ),
            (
                |o| o.smooth = smooth(|s| s.range = 0.0),
                "smooth.range",
                positive,
            ),
            // Several fields out of range: the first checked is named.
            (
                |o| {
                    o.smooth = smooth(|s| s.range = 0.0);
                    o.only_tile = Some([1; 3]);
                    o.grid = 1;
                    o.max_gap = 9;
                },
                "max_gap",
                "must be 0..=8 pixels",
            ),
        ];
        for (change, option, reason) in cases {
            assert_eq!(refusal(change), Some((option, reason)));
        }
    }
}
