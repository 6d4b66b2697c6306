//! The options of the segmenter, with their defaults and what each trades.

use crate::{SegmentError, SegmentOption};

/// Default [`SegmentOptions::cone_angle_deg`]: 30°.
pub const DEFAULT_CONE_ANGLE_DEG: f32 = 30.0;
/// Default [`SegmentOptions::merge_angle_deg`]: 40°.
pub const DEFAULT_MERGE_ANGLE_DEG: f32 = 40.0;
/// Default [`SegmentOptions::max_extent`]: unlimited.
pub const DEFAULT_MAX_EXTENT: f32 = f32::INFINITY;
/// Default [`SegmentOptions::min_region_faces`]: 128 faces.
pub const DEFAULT_MIN_REGION_FACES: usize = 128;

/// Largest cone or merge angle accepted, in degrees. A region whose normals span a cone of
/// half-angle below 90° is a height field over the plane normal to the cone's axis, which is
/// what a patch needs; at 90° that no longer holds.
pub const MAX_ANGLE_DEG: f32 = 89.0;

/// Parameters of [`segment`](crate::segment) and of each stage.
///
/// Every field has a named default constant (`DEFAULT_*`); [`SegmentOptions::default`] uses
/// them. See `docs/algorithms/segmenter.md` for measurements of what each trades.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SegmentOptions {
    /// θ1: half-angle, in degrees, of the normal cone every region of the cone-growing and
    /// secondary-growth stages must fit in. Range `(0, 89]`, default 30°
    /// ([`DEFAULT_CONE_ANGLE_DEG`]).
    ///
    /// Trades patch count against sampling quality: a patch samples the surface on a regular
    /// grid in the plane normal to the axis, so where the surface tilts by `θ` the nodes
    /// spread `1 / cos θ` further apart on the surface and the displacement range grows.
    /// At 30° the spread is at most 15 % and a patch stays well conditioned; larger angles
    /// give fewer, larger regions (fewer patches and bytes) but coarser sampling on the
    /// slopes and larger displacements to quantize; smaller angles give many small regions.
    pub cone_angle_deg: f32,
    /// θ3: half-angle, in degrees, the normal cone of a merged region may reach in the merge
    /// stage. Range `(0, 89]`, default 40° ([`DEFAULT_MERGE_ANGLE_DEG`]).
    ///
    /// Larger than θ1 so that the small leftovers of the first two stages (crease strips,
    /// noise) can join a neighbour: each merge removes a patch that would hold few nodes.
    /// Raising it removes more small regions at the price of steeper patches.
    pub merge_angle_deg: f32,
    /// Largest extent, in model units, a merged region may span in its axis plane and still
    /// "fit a patch". The convert pipeline sets it to `(grid - 1) × spacing`; default
    /// `f32::INFINITY` ([`DEFAULT_MAX_EXTENT`]): unlimited. Must be positive (or infinite).
    ///
    /// Tested conservatively (see [`merge_regions`](crate::merge_regions)): two regions that
    /// each fit a patch merge only when a sphere enclosing the union has a diameter within
    /// `max_extent`, so the union fits a square patch of that side whatever in-plane
    /// orientation the fitter picks; a small region may still join a region that is already
    /// wider than a patch (the fitter tiles that one anyway). Only the merge stage uses it;
    /// larger regions of the first two stages are split by the fitter.
    pub max_extent: f32,
    /// A region with fewer faces than this is "small": secondary growth does not seed from a
    /// preliminary region this small, and the merge stage tries to merge it into a neighbour.
    /// Default 128 ([`DEFAULT_MIN_REGION_FACES`]): on the bunny, 32 gave 4 % more patches and
    /// 256 no fewer; `0` turns merging off and seeds from every preliminary region.
    ///
    /// Raising it merges more regions (fewer, fuller patches) and lets steeper normals in;
    /// lowering it keeps tiny regions that the fitter turns into nearly empty patches.
    pub min_region_faces: usize,
}

impl Default for SegmentOptions {
    fn default() -> Self {
        SegmentOptions {
            cone_angle_deg: DEFAULT_CONE_ANGLE_DEG,
            merge_angle_deg: DEFAULT_MERGE_ANGLE_DEG,
            max_extent: DEFAULT_MAX_EXTENT,
            min_region_faces: DEFAULT_MIN_REGION_FACES,
        }
    }
}

impl SegmentOptions {
    /// The defaults with θ1 set to `degrees`.
    pub fn with_cone_angle_deg(mut self, degrees: f32) -> Self {
        self.cone_angle_deg = degrees;
        self
    }

    /// The options with θ3 set to `degrees`.
    pub fn with_merge_angle_deg(mut self, degrees: f32) -> Self {
        self.merge_angle_deg = degrees;
        self
    }

    /// The options with [`SegmentOptions::max_extent`] set.
    pub fn with_max_extent(mut self, extent: f32) -> Self {
        self.max_extent = extent;
        self
    }

    /// The options with [`SegmentOptions::min_region_faces`] set.
    pub fn with_min_region_faces(mut self, faces: usize) -> Self {
        self.min_region_faces = faces;
        self
    }

    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<(), SegmentError> {
        let angle = |option, value: f32| {
            if value > 0.0 && value <= MAX_ANGLE_DEG {
                Ok(())
            } else {
                Err(SegmentError::InvalidOption {
                    option,
                    value,
                    expected: "an angle in degrees above 0 and at most 89",
                })
            }
        };
        angle(SegmentOption::ConeAngle, self.cone_angle_deg)?;
        angle(SegmentOption::MergeAngle, self.merge_angle_deg)?;
        // NaN fails `> 0.0` too.
        if self.max_extent.is_nan() || self.max_extent <= 0.0 {
            return Err(SegmentError::InvalidOption {
                option: SegmentOption::MaxExtent,
                value: self.max_extent,
                expected: "a positive length or infinity",
            });
        }
        Ok(())
    }

    /// θ1 in radians.
    pub(crate) fn cone_angle(&self) -> f32 {
        self.cone_angle_deg.to_radians()
    }

    /// θ3 in radians.
    pub(crate) fn merge_angle(&self) -> f32 {
        self.merge_angle_deg.to_radians()
    }
}
