//! Per-scene preparation, done once and reused for every frame: model-space
//! frames in f64, the mip pyramid of each patch, its normal cone and
//! bounding sphere, and the drawing order.
//!
//! Patches are ordered by their shading ratios (`|az|/|ax|`, `|az|/|ay|`)
//! so that the normal buffer ([`crate::normal_buffer`]) stays valid from
//! one patch to the next; the order is stable, so equal ratios keep file
//! order.
//!
//! Cost: O(nodes) time; about 1.4× the scene's node memory.

use glam::{DMat3, DVec3};
use spatch_format::Scene;

use crate::cull::{compute_normal_cone, NormalCone};
use crate::mip::{build_mip_pyramid, MipLevel};

/// One patch ready to draw.
#[derive(Debug, Clone)]
pub(crate) struct PreparedPatch {
    /// Model-space origin (scene offset included).
    pub(crate) origin: DVec3,
    /// Level-0 axes `ax, ay, az` in model space.
    pub(crate) axes: [DVec3; 3],
    /// Unit axes as columns.
    pub(crate) rotation: DMat3,
    /// `(|az| / |ax|, |az| / |ay|)` at level 0.
    pub(crate) ratios: (f32, f32),
    pub(crate) cone: NormalCone,
    pub(crate) centre: DVec3,
    pub(crate) radius: f64,
    pub(crate) levels: Vec<MipLevel>,
}

impl PreparedPatch {
    /// Shading ratios at mip level `m` (node spacing doubles per level).
    pub(crate) fn ratios_at(&self, m: usize) -> (f32, f32) {
        let s = (1u32 << m) as f32;
        (self.ratios.0 / s, self.ratios.1 / s)
    }
}

/// A scene prepared for rendering (see the module header). Build it once
/// and render it many times.
#[derive(Debug, Clone)]
pub struct PreparedScene {
    pub(crate) patches: Vec<PreparedPatch>,
    pub(crate) bounds: Option<(DVec3, DVec3)>,
    pub(crate) sphere: Option<(DVec3, f64)>,
    skipped: usize,
}

impl PreparedScene {
    /// Prepares `scene`. Patches without a drawable cell are left out.
    pub fn new(scene: &Scene) -> Self {
        let offset = scene.offset();
        let mut patches: Vec<PreparedPatch> = Vec::with_capacity(scene.patches().len());
        let mut skipped = 0;
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        let mut corners: Vec<[DVec3; 8]> = Vec::with_capacity(scene.patches().len());
        for patch in scene.patches() {
            let levels = build_mip_pyramid(patch);
            if levels.is_empty() {
                skipped += 1;
                continue;
            }
            let frame = patch.frame();
            let axes = frame.axes().map(|a| a.as_dvec3());
            let units = frame.unit_axes().map(|a| a.as_dvec3());
            let rotation = DMat3::from_cols(units[0], units[1], units[2]);
            let [lx, ly, lz] = frame.lengths();
            let ratios = (lz / lx, lz / ly);
            let origin = offset + frame.origin().as_dvec3();
            let base = &levels[0];
            let cone = compute_normal_cone(base, ratios, &rotation);
            // Box of the used nodes in model space, via the local box corners.
            let (d0, d1) = base.d_range;
            let (ci, cj) = ((base.cols - 1) as f64, (base.rows - 1) as f64);
            let mut plo = DVec3::splat(f64::INFINITY);
            let mut phi = DVec3::splat(f64::NEG_INFINITY);
            let box_corners: [DVec3; 8] = std::array::from_fn(|k| {
                origin
                    + axes[0] * if k & 1 == 0 { 0.0 } else { ci }
                    + axes[1] * if k & 2 == 0 { 0.0 } else { cj }
                    + axes[2] * if k & 4 == 0 { d0 as f64 } else { d1 as f64 }
            });
            for p in box_corners {
                plo = plo.min(p);
                phi = phi.max(p);
            }
            corners.push(box_corners);
            let centre = (plo + phi) * 0.5;
            let radius = (phi - plo).length() * 0.5;
            lo = lo.min(plo);
            hi = hi.max(phi);
            patches.push(PreparedPatch {
                origin,
                axes,
                rotation,
                ratios,
                cone,
                centre,
                radius,
                levels,
            });
        }
        let bounds = (!patches.is_empty()).then_some((lo, hi));
        // Bounding sphere: the box centre, and the farthest patch-box corner.
        let sphere = bounds.map(|(lo, hi)| {
            let c = (lo + hi) * 0.5;
            let r = corners
                .iter()
                .flatten()
                .map(|p| (*p - c).length())
                .fold(0.0, f64::max);
            (c, r)
        });
        patches.sort_by(|a, b| {
            (a.ratios.0, a.ratios.1)
                .partial_cmp(&(b.ratios.0, b.ratios.1))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        Self {
            patches,
            bounds,
            sphere,
            skipped,
        }
    }

    /// Number of patches that will be considered for drawing.
    pub fn patch_count(&self) -> usize {
        self.patches.len()
    }

    /// Patches left out because they have no drawable cell.
    pub fn skipped_patches(&self) -> usize {
        self.skipped
    }

    /// Model-space box of the scene (loose: built from patch boxes).
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        self.bounds
    }

    /// A bounding sphere `(centre, radius)` of the scene.
    pub fn bounding_sphere(&self) -> Option<(DVec3, f64)> {
        self.sphere
    }
}
