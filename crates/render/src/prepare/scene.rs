//! A scene prepared for rendering, done once and reused for every frame:
//! its patches prepared ([`crate::prepare::patch`]), optionally with their
//! overlaps trimmed ([`crate::prepare::overlap`]), in drawing order, its
//! openings as portals ([`crate::prepare::portals`]), its bounds.
//!
//! Patches are ordered by their shading ratios (`|az|/|ax|`, `|az|/|ay|`)
//! so that the normal buffer ([`crate::prepare::normal_buffer`]) stays
//! valid from one patch to the next; the order is stable, so equal ratios
//! keep file order.
//!
//! Cost: O(nodes), in parallel over patches.

use glam::DVec3;
use rayon::prelude::*;
use spatch_format::{InsideBox, Opening, Scene};

use crate::camera::Camera;
use crate::error::CameraProblem;
use crate::isa::Isa;
use crate::prepare::overlap::trim_overlaps;
use crate::prepare::patch::PreparedPatch;
use crate::prepare::portals::Portals;

/// A scene prepared for rendering (see the module header). Build it once
/// and render it many times.
#[derive(Debug, Clone)]
pub struct PreparedScene {
    pub(crate) patches: Vec<PreparedPatch>,
    /// The scene's openings in model space, grouped.
    pub(crate) portals: Portals,
    /// The scene's inside box in model space ([`spatch_format::InsideBox`]):
    /// outside it, two-sided patches show their backs only through
    /// openings.
    pub(crate) inside_box: Option<(DVec3, DVec3)>,
    pub(crate) bounds: Option<(DVec3, DVec3)>,
    pub(crate) sphere: Option<(DVec3, f64)>,
    skipped: usize,
    trimmed_cells: u64,
}

impl PreparedScene {
    /// Prepares `scene`. Patches without a drawable cell are left out.
    pub fn new(scene: &Scene) -> Self {
        Self::prepare(scene, false, Isa::detect(true))
    }

    /// Prepares `scene` and trims the level-0 cells that an earlier patch
    /// already draws (docs/algorithms/overlap.md): frames of scenes whose patches
    /// overlap draw fewer cells, for a one-off cost here (the perfect
    /// sphere: 98,559 of 348,672 cells, 13 % of the instructions of a 500²
    /// frame, for about 40 ms more with 2 threads).
    pub fn trimming_overlaps(scene: &Scene) -> Self {
        Self::prepare(scene, true, Isa::detect(true))
    }

    /// Prepares with the lanes of `isa` (the renderer's, so `--no-simd`
    /// keeps preparation portable too); the lazily built levels use it.
    ///
    /// Why in parallel: every patch is prepared on its own (its pyramid,
    /// cone and box), and preparation was most of a one-frame render (the
    /// perfect sphere: ≈ 320 M instructions against ≈ 80 M for a 500²
    /// frame, before the shading inputs moved to first use). It runs on the
    /// current rayon pool
    /// ([`crate::Renderer::prepare`] uses the renderer's); the result does
    /// not depend on the number of threads.
    pub(crate) fn prepare(scene: &Scene, trim: bool, isa: Isa) -> Self {
        let offset = scene.offset();
        let built: Vec<Option<PreparedPatch>> = scene
            .patches()
            .par_iter()
            .map(|patch| PreparedPatch::new(patch, offset, isa))
            .collect();
        Self::assemble(built, offset, (scene.openings(), scene.inside_box()), trim)
    }

    /// [`Self::prepare`] taking the scene's nodes instead of copying them
    /// ([`PreparedPatch::from_owned`]).
    pub(crate) fn prepare_owned(scene: Scene, trim: bool, isa: Isa) -> Self {
        let offset = scene.offset();
        let openings = scene.openings().to_vec();
        let inside_box = scene.inside_box();
        let built: Vec<Option<PreparedPatch>> = scene
            .into_patches()
            .into_par_iter()
            .map(|patch| PreparedPatch::from_owned(patch, offset, isa))
            .collect();
        Self::assemble(built, offset, (&openings, inside_box), trim)
    }

    /// The scene of the patches `built` (`None`: no drawable cell, left
    /// out) with its openings and inside box, trimmed when `trim` says, in
    /// drawing order.
    fn assemble(
        built: Vec<Option<PreparedPatch>>,
        offset: DVec3,
        (openings, inside_box): (&[Opening], Option<InsideBox>),
        trim: bool,
    ) -> Self {
        let skipped = built.iter().filter(|b| b.is_none()).count();
        // The kept patches collected where `built` lies (an in-place
        // collect, which `filter_map` takes and `flatten` does not). Why:
        // each copy of the prepared patches into a new vector touched
        // fresh memory (the collect into a new vector: 126 page faults of
        // a one-image bunny render).
        #[allow(clippy::filter_map_identity)]
        let mut patches: Vec<PreparedPatch> = built.into_iter().filter_map(|b| b).collect();
        let trimmed_cells = if trim { trim_overlaps(&mut patches) } else { 0 };
        // Drawing order (after trimming, which relies on scene order).
        put_in_drawing_order(&mut patches);
        let corners = || patches.iter().flat_map(PreparedPatch::box_corners);
        let bounds = corners().fold(None, |b, p| {
            let (lo, hi) = b.unwrap_or((p, p));
            Some((p.min(lo), p.max(hi)))
        });
        // Bounding sphere: the box centre, and the farthest patch-box corner.
        let sphere = bounds.map(|(lo, hi): (DVec3, DVec3)| {
            let c = (lo + hi) * 0.5;
            let r = corners().map(|p| (p - c).length()).fold(0.0, f64::max);
            (c, r)
        });
        let portals = Portals::new(openings, offset);
        let inside_box =
            inside_box.map(|b| (offset + b.min().as_dvec3(), offset + b.max().as_dvec3()));
        Self {
            patches,
            portals,
            inside_box,
            bounds,
            sphere,
            skipped,
            trimmed_cells,
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

    /// Level-0 cells left out because an earlier patch draws them (0 unless
    /// prepared with [`Self::trimming_overlaps`]).
    pub fn trimmed_cells(&self) -> u64 {
        self.trimmed_cells
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

/// Sorts `patches` by their shading ratios (stable: equal ratios keep
/// their order). Why through an index sort and swaps in place: a prepared
/// patch is a few hundred bytes; the stable sort moved whole patches (9.3 M
/// of the 265 M instructions of a one-frame bunny render, mostly `memcpy`;
/// callgrind, `spatch render bunny.spatch -o out.png --threads 1`), and
/// gathering them into a new vector touched as much fresh memory as the
/// patches take. The keys and the resulting order are the same.
fn put_in_drawing_order(patches: &mut [PreparedPatch]) {
    let mut order: Vec<(f32, f32, u32)> = patches
        .iter()
        .enumerate()
        .map(|(k, p)| (p.ratios.0, p.ratios.1, k as u32))
        .collect();
    order.sort_by(|a, b| {
        (a.0, a.1)
            .partial_cmp(&(b.0, b.1))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let source: Vec<u32> = order.iter().map(|&(_, _, k)| k).collect();
    permute(patches, &source);
}

/// Puts `items[source[k]]` at `k` for every `k` (`source` a permutation),
/// following each cycle with swaps.
fn permute<T>(items: &mut [T], source: &[u32]) {
    let mut placed = vec![false; items.len()];
    for start in 0..items.len() {
        let mut at = start;
        while !placed[at] {
            placed[at] = true;
            let from = source[at] as usize;
            if from == start {
                break;
            }
            items.swap(at, from);
            at = from;
        }
    }
}

impl PreparedScene {
    /// The automatic camera for this scene (see [`Camera::framing`]).
    pub fn auto_camera(&self, width: u32, height: u32) -> Result<Camera, CameraProblem> {
        let (centre, radius) = self
            .bounding_sphere()
            .ok_or(CameraProblem::NothingToFrame)?;
        Camera::framing(centre, radius, Camera::DEFAULT_FOV_Y_DEGREES, width, height)
    }
}

#[cfg(test)]
impl PreparedScene {
    /// The default perfect sphere (`spatch sphere`), prepared: the scene
    /// the frame tests draw.
    pub(crate) fn default_sphere() -> Self {
        let sphere = spatch_sphere::build_sphere(&spatch_sphere::SphereOptions::default())
            .expect("the default sphere builds");
        Self::new(&sphere.scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use spatch_format::{ColourChannel, Frame, GridSize, Patch, EMPTY};

    /// A 5 × 5 patch at `x` whose codes are `codes` (a code may be EMPTY).
    fn patch_at(x: f32, codes: [u16; 25]) -> Patch {
        let frame = Frame::new(Vec3::new(x, 0.0, 0.0), Vec3::X, Vec3::Y, Vec3::Z * 0.01).unwrap();
        Patch::new(frame, GridSize::new(5, 5).unwrap(), codes.to_vec(), None).unwrap()
    }

    #[test]
    fn permute_places_each_item_where_the_order_says() {
        let mut rng = crate::test_rng::XorShift(7);
        for n in [0usize, 1, 2, 5, 64, 257] {
            let mut source: Vec<u32> = (0..n as u32).collect();
            for k in (1..n).rev() {
                source.swap(k, rng.below(k as u32 + 1) as usize);
            }
            let mut items: Vec<u32> = (0..n as u32).map(|k| k * 10).collect();
            permute(&mut items, &source);
            let expected: Vec<u32> = source.iter().map(|&k| k * 10).collect();
            assert_eq!(items, expected, "n = {n}");
        }
    }

    #[test]
    fn patches_without_a_drawable_cell_are_left_out_in_order() {
        // Patch 1 has no cell with four filled corners (a checkerboard of
        // empty nodes); the others keep their order and their boxes.
        let full = [3; 25];
        let sparse: [u16; 25] = std::array::from_fn(|k| if k % 2 == 0 { 3 } else { EMPTY });
        let patches = vec![
            patch_at(0.0, full),
            patch_at(10.0, sparse),
            patch_at(20.0, full),
        ];
        let scene = Scene::new(DVec3::ZERO, ColourChannel::None, patches).unwrap();
        let prepared = PreparedScene::new(&scene);
        assert_eq!((prepared.patch_count(), prepared.skipped_patches()), (2, 1));
        let origins: Vec<f64> = prepared.patches.iter().map(|p| p.origin.x).collect();
        assert_eq!(origins, [0.0, 20.0]);
        let (lo, hi) = prepared.bounds().unwrap();
        assert_eq!((lo.x, hi.x), (0.0, 24.0));
        let empty = Scene::new(DVec3::ZERO, ColourChannel::None, Vec::new()).unwrap();
        let none = PreparedScene::new(&empty);
        assert_eq!(none.patch_count(), 0);
        assert!(none.bounds().is_none() && none.bounding_sphere().is_none());
    }
}
