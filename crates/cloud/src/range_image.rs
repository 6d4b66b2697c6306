//! Orthographic range images: the points of the cloud flushed into a z-buffer seen from one
//! view direction.
//!
//! Input: positions (relative to the cloud origin), unoriented unit normals (zero where
//! unknown), optional colours, a [`ViewBasis`] and an [`ImageGeometry`] (pixel size and
//! extent). Output: a [`RangeImage`]: per pixel the height `h = p · direction` of the
//! surface nearest the viewer at the pixel centre (larger is nearer), or empty; per pixel the
//! mean colour of the points that made it.
//!
//! Method, per view, in three passes (pass 1's projection is `range_image/projector.rs`,
//! pass 3 `range_image/see_through.rs`):
//! 1. Every point is projected to its nearest pixel centre. Its height is carried from the
//!    point to the pixel centre along the point's tangent plane (its normal gives the depth
//!    gradient, clamped to [`MAX_GRADIENT`]), so a point that is off-centre on a slope does
//!    not bias the pixel. Points seen at a grazing angle (`|n · direction|` below
//!    [`MIN_POINT_COSINE`]) are not drawn. The buffer keeps the largest height per pixel.
//!    This pass runs once per view over every point, so it is split in two loops: the
//!    first computes each point's pixel and carried height without branches over the
//!    coordinate arrays of a [`PointColumns`] (so it compiles to SIMD); the second, scalar,
//!    updates the z-buffer.
//!    Blocks of consecutive points whose normals all face away from the view (their
//!    normal cones, `normal_cones.rs`) are skipped in this pass and the next.
//! 2. Every drawn point whose height at the pixel centre lies within `band` of the pixel's
//!    front-most height is averaged into the pixel (depth and colour). This averages the
//!    front surface layer (noise drops by √count) and ignores surfaces behind it.
//! 3. See-through pixels are removed: where the front surface has a sampling hole, a point of
//!    a farther surface can land in the hole. A pixel with at least [`SEE_THROUGH_NEIGHBOURS`]
//!    of its 8 neighbours nearer by more than the discontinuity threshold is emptied (gap
//!    filling then closes it from the front surface).
//!
//! Invariants: filled heights are finite; empty pixels hold [`EMPTY_DEPTH`]; the result does
//! not depend on thread count (each view is built by one thread, points in input order).
//!
//! Cost: one projection and two passes over the points (O(n)), one over the pixels
//! (O(w·h)); memory: 4 bytes per pixel for the heights (plus 4 for colours), and a
//! transient 12 bytes per pixel, and 8 bytes per projected point up to [`KEPT_POINTS`] (its
//! pixel and height, kept from pass 1 for pass 2 in a [`FlushScratch`] reused from view to
//! view, one per worker; beyond, one chunk's, projected again in pass 2) while building; the coordinate arrays take 24 bytes per point for all views.
//! (Projecting every point again for pass 2 instead cost 0.50 G of the 6.47 G worker
//! instructions of the covering 1 M scan set; the kept projections add less than the
//! normals stage's peak.)
//!
//! Based on: the range-image sampling of point clouds of the spatial-patch paper (a z-buffer
//! flush per view direction); surface splatting's use of the tangent plane to place a sample
//! at a pixel (M. Zwicker, H. Pfister, J. van Baar, M. Gross, "Surface splatting",
//! SIGGRAPH 2001).

use glam::Vec3;
use spatch_mesh::Aabb;

use crate::directions::ViewBasis;
use crate::normal_cones::NormalCones;

mod projector;
mod see_through;

use projector::{Projector, NOT_DRAWN};
use see_through::remove_see_through;

/// The height of an empty pixel.
pub(crate) const EMPTY_DEPTH: f32 = f32::NEG_INFINITY;

/// Points whose normal makes an angle above about 84° with the view are not drawn.
pub(crate) const MIN_POINT_COSINE: f32 = 0.1;

/// Largest depth gradient (height per unit image distance) used to carry a point's height to
/// the pixel centre.
pub(crate) const MAX_GRADIENT: f32 = 4.0;

/// Nearer 8-neighbours that mark a pixel as seen through a hole.
pub(crate) const SEE_THROUGH_NEIGHBOURS: usize = 6;

/// Where a view's pixels lie.
///
/// # Guarantees
/// `pixel > 0`, `width ≥ 2`, `height ≥ 2`; every point of the bounds used to build it
/// projects to a pixel inside the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ImageGeometry {
    /// The view.
    pub(crate) basis: ViewBasis,
    /// Image coordinate (`p · u`) of the centre of pixel column 0.
    pub(crate) x0: f32,
    /// Image coordinate (`p · w`) of the centre of pixel row 0.
    pub(crate) y0: f32,
    /// Pixel size (model units).
    pub(crate) pixel: f32,
    /// Pixel columns.
    pub(crate) width: usize,
    /// Pixel rows.
    pub(crate) height: usize,
}

impl ImageGeometry {
    /// The smallest image with pixel size `pixel` that holds `bounds` seen from `basis`.
    pub(crate) fn covering(basis: ViewBasis, bounds: &Aabb, pixel: f32) -> ImageGeometry {
        let (mut lo, mut hi) = (
            glam::Vec2::splat(f32::INFINITY),
            glam::Vec2::splat(-f32::INFINITY),
        );
        for k in 0..8 {
            let corner = Vec3::new(
                if k & 1 == 0 {
                    bounds.min.x
                } else {
                    bounds.max.x
                },
                if k & 2 == 0 {
                    bounds.min.y
                } else {
                    bounds.max.y
                },
                if k & 4 == 0 {
                    bounds.min.z
                } else {
                    bounds.max.z
                },
            );
            let q = glam::Vec2::new(corner.dot(basis.u), corner.dot(basis.w));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let size = |extent: f32| (extent / pixel).floor().max(0.0) as usize + 2;
        ImageGeometry {
            basis,
            x0: lo.x,
            y0: lo.y,
            pixel,
            width: size(hi.x - lo.x),
            height: size(hi.y - lo.y),
        }
    }

    /// Number of pixels.
    pub(crate) fn pixel_count(&self) -> usize {
        self.width * self.height
    }

    /// Image coordinates of `p` in pixel units and its height: `(fx, fy, h)`.
    pub(crate) fn project(&self, p: Vec3) -> (f32, f32, f32) {
        let inv = 1.0 / self.pixel;
        (
            (p.dot(self.basis.u) - self.x0) * inv,
            (p.dot(self.basis.w) - self.y0) * inv,
            p.dot(self.basis.direction),
        )
    }

    /// The model-space point (relative to the cloud origin) of pixel `(i, j)` at height `h`.
    pub(crate) fn point_at(&self, i: usize, j: usize, h: f32) -> Vec3 {
        self.basis.u * (self.x0 + i as f32 * self.pixel)
            + self.basis.w * (self.y0 + j as f32 * self.pixel)
            + self.basis.direction * h
    }
}

/// One view's range image.
#[derive(Clone, Debug)]
pub(crate) struct RangeImage {
    /// Where the pixels lie.
    pub(crate) geometry: ImageGeometry,
    /// Height per pixel, row-major (`j * width + i`); [`EMPTY_DEPTH`] when empty.
    pub(crate) depth: Vec<f32>,
    /// Mean RGBA colour per pixel when the cloud has colour.
    pub(crate) colour: Option<Vec<[u8; 4]>>,
}

#[cfg(test)]
impl RangeImage {
    /// A `w × h` image seen along +z with unit pixels at the origin, `depth(i, j)` per pixel
    /// and no colour (for the tests of the image filters).
    pub(crate) fn from_fn(w: usize, h: usize, depth: impl Fn(usize, usize) -> f32) -> Self {
        RangeImage {
            geometry: ImageGeometry {
                basis: ViewBasis::new(Vec3::Z),
                x0: 0.0,
                y0: 0.0,
                pixel: 1.0,
                width: w,
                height: h,
            },
            depth: (0..w * h).map(|k| depth(k % w, k / w)).collect(),
            colour: None,
        }
    }
}

/// Positions and normals as one array per coordinate (structure of arrays), so that the
/// projection loop of [`flush_points`], which runs once per view over every point, compiles
/// to SIMD instructions; and the normals' cones, so that it skips the blocks of points
/// facing away from a view.
#[derive(Clone, Debug, Default)]
pub(crate) struct PointColumns {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    nx: Vec<f32>,
    ny: Vec<f32>,
    nz: Vec<f32>,
    cones: NormalCones,
}

impl PointColumns {
    /// The columns of `positions` and their `normals` (one per position).
    pub(crate) fn new(positions: &[Vec3], normals: &[Vec3]) -> PointColumns {
        debug_assert_eq!(positions.len(), normals.len());
        PointColumns {
            x: positions.iter().map(|p| p.x).collect(),
            y: positions.iter().map(|p| p.y).collect(),
            z: positions.iter().map(|p| p.z).collect(),
            nx: normals.iter().map(|n| n.x).collect(),
            ny: normals.iter().map(|n| n.y).collect(),
            nz: normals.iter().map(|n| n.z).collect(),
            cones: NormalCones::new(normals),
        }
    }

    /// Number of points.
    pub(crate) fn len(&self) -> usize {
        self.x.len()
    }

    /// The columns `[x, y, z, nx, ny, nz]` of the points in `range`.
    #[inline(always)] // Sets up the vectorised loop of `Projector::project`.
    fn columns(&self, range: std::ops::Range<usize>) -> [&[f32]; 6] {
        [
            &self.x[range.clone()],
            &self.y[range.clone()],
            &self.z[range.clone()],
            &self.nx[range.clone()],
            &self.ny[range.clone()],
            &self.nz[range],
        ]
    }

    /// The normals as vectors.
    pub(crate) fn normals(&self) -> Vec<Vec3> {
        (0..self.len())
            .map(|i| Vec3::new(self.nx[i], self.ny[i], self.nz[i]))
            .collect()
    }
}

/// Inputs of [`flush_points`] shared by every view.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FlushInput<'a> {
    /// Positions relative to the cloud origin, and unoriented unit normals (zero where
    /// unknown).
    pub(crate) points: &'a PointColumns,
    /// Colours, when the cloud has them.
    pub(crate) colours: Option<&'a [[u8; 4]]>,
    /// Heights within this distance of the front-most one are averaged (model units).
    pub(crate) band: f32,
    /// The discontinuity threshold between neighbouring pixels (model units).
    pub(crate) jump: f32,
    /// The normals face the side each point was seen from: a point is drawn only in views
    /// it faces (`n · direction ≥` [`MIN_POINT_COSINE`]), not in views of its back.
    pub(crate) oriented: bool,
}

/// Per-point buffers of [`flush_points`], kept from one view to the next: the pixel (or
/// [`NOT_DRAWN`]) and height of every point the view's normal cones do not skip (8 bytes a
/// point), written by pass 1 and read again by pass 2.
#[derive(Clone, Debug, Default)]
pub(crate) struct FlushScratch {
    pixel_of: Vec<u32>,
    height_of: Vec<f32>,
}

impl FlushScratch {
    /// Scratch with room for `points` points, reserved by the caller's thread: the pages are
    /// touched only as points are projected, and the memory returns to the caller's heap
    /// afterwards (grown on a worker thread it stayed resident in that thread's arena: 10 MB
    /// more peak on the evenly spread 1 M scan set).
    pub(crate) fn with_capacity(points: usize) -> FlushScratch {
        let points = points.clamp(FLUSH_CHUNK, KEPT_POINTS);
        FlushScratch {
            pixel_of: Vec::with_capacity(points),
            height_of: Vec::with_capacity(points),
        }
    }

    /// The pixels and heights of the points in `slots`.
    fn slots(&mut self, slots: std::ops::Range<usize>) -> (&mut [u32], &mut [f32]) {
        (
            &mut self.pixel_of[slots.clone()],
            &mut self.height_of[slots],
        )
    }

    /// Room for `n` points (grown, never shrunk: resizing to each view's count re-zeroed it).
    fn ensure(&mut self, n: usize) {
        if self.pixel_of.len() < n {
            self.pixel_of.resize(n, 0);
            self.height_of.resize(n, 0.0);
        }
    }
}

/// Most projected points a view keeps from pass 1 for pass 2 (8 bytes each, per worker):
/// beyond, pass 2 projects each chunk again. Keeping every point cost a 4 M-point terrain
/// 70 MB more peak (97 instead of 80 bytes a point) on 2 threads.
const KEPT_POINTS: usize = 1 << 20;

/// Points projected at a time: a chunk's pixels and heights are still in the cache when
/// the z-buffer reads them.
const FLUSH_CHUNK: usize = 16_384;

/// Builds the range image of one view (see the module documentation).
pub(crate) fn flush_points(
    input: &FlushInput<'_>,
    geometry: ImageGeometry,
    scratch: &mut FlushScratch,
) -> RangeImage {
    let flush = ViewFlush::new(input, &geometry);
    let front = flush.front_heights(scratch, geometry.pixel_count());
    let sums = flush.sum_front_layer(scratch, &front);
    drop(front);
    let mut image = sums.into_image(geometry);
    remove_see_through(&mut image, input.jump);
    image
}

/// One view's flush of the points: the projection, the blocks of points drawn (the normal
/// cones skip the rest) and whether pass 1 keeps their projections for pass 2.
struct ViewFlush<'a> {
    /// The points and the flush settings.
    input: &'a FlushInput<'a>,
    /// The projection onto the view's pixels.
    projector: Projector,
    /// Only the blocks of points that may face the view.
    runs: Vec<std::ops::Range<usize>>,
    /// Points in `runs`.
    projected: usize,
    /// Whether the projections of pass 1 are kept for pass 2 (up to [`KEPT_POINTS`]).
    keep: bool,
}

impl<'a> ViewFlush<'a> {
    /// The flush of `input`'s points into the view of `geometry`.
    fn new(input: &'a FlushInput<'a>, geometry: &ImageGeometry) -> ViewFlush<'a> {
        let n = input.points.len();
        let runs = input
            .points
            .cones
            .drawn_runs(geometry.basis.direction, input.oriented, n);
        let projected: usize = runs.iter().map(ExactSizeIterator::len).sum();
        ViewFlush {
            input,
            projector: Projector::new(geometry),
            runs,
            projected,
            keep: projected <= KEPT_POINTS,
        }
    }

    /// The drawn points, at most a chunk at a time.
    fn chunks(&self) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
        self.runs.iter().flat_map(|run| {
            let end = run.end;
            run.clone()
                .step_by(FLUSH_CHUNK)
                .map(move |a| a..(a + FLUSH_CHUNK).min(end))
        })
    }

    /// Where a chunk of `n` projections lies in the scratch: after the earlier ones (`at`
    /// of them) when kept.
    fn window(&self, at: usize, n: usize) -> std::ops::Range<usize> {
        if self.keep {
            at..at + n
        } else {
            0..n
        }
    }

    /// Pass 1: the front-most height of each of the `pixels` pixels, a chunk of points at a
    /// time (its pixels and heights are still in the cache for the z-buffer). Up to
    /// KEPT_POINTS they are kept for pass 2: projecting every chunk again cost 0.50 G of the
    /// covering 1 M scan set's 6.47 G worker instructions (callgrind). Beyond, each chunk is
    /// projected again.
    fn front_heights(&self, scratch: &mut FlushScratch, pixels: usize) -> Vec<f32> {
        let input = self.input;
        let mut front = vec![EMPTY_DEPTH; pixels];
        scratch.ensure(if self.keep {
            self.projected
        } else {
            FLUSH_CHUNK
        });
        let mut at = 0;
        for range in self.chunks() {
            let slots = self.window(at, range.len());
            at += range.len();
            let (pixel_of, height_of) = scratch.slots(slots);
            self.projector
                .project(input.points, range, input.oriented, (pixel_of, height_of));
            for (&k, &hc) in pixel_of.iter().zip(height_of.iter()) {
                if k != NOT_DRAWN {
                    // A comparison, not `f32::max`, whose NaN handling cost 62 M of the
                    // covering 1 M scan set's worker instructions. Neither keeps a NaN
                    // height; a zero's sign may differ, which `hc ≥ front − band` below does
                    // not see.
                    let f = &mut front[k as usize];
                    if hc > *f {
                        *f = hc;
                    }
                }
            }
        }
        front
    }

    /// Pass 2: the sums of the heights (and colours) of the points within the band of each
    /// pixel's `front` height, in the points' order.
    fn sum_front_layer(&self, scratch: &mut FlushScratch, front: &[f32]) -> FrontSums {
        let input = self.input;
        let pixels = front.len();
        let mut sum = vec![(0.0f32, 0u32); pixels];
        let mut colour_sum = input.colours.map(|_| vec![[0u32; 4]; pixels]);
        let mut at = 0;
        for range in self.chunks() {
            let (first, slots) = (range.start, self.window(at, range.len()));
            at += range.len();
            let (pixel_of, height_of) = scratch.slots(slots);
            if !self.keep {
                self.projector
                    .project(input.points, range, input.oriented, (pixel_of, height_of));
            }
            for (offset, (&k, &hc)) in pixel_of.iter().zip(height_of.iter()).enumerate() {
                if k != NOT_DRAWN && hc >= front[k as usize] - input.band {
                    let k = k as usize;
                    sum[k].0 += hc;
                    sum[k].1 += 1;
                    if let (Some(acc), Some(colours)) = (colour_sum.as_mut(), input.colours) {
                        for (a, v) in acc[k].iter_mut().zip(colours[first + offset]) {
                            *a += u32::from(v);
                        }
                    }
                }
            }
        }
        FrontSums { sum, colour_sum }
    }
}

/// Per pixel, the sum and count of the front layer's heights, and the sums of their colours
/// when the cloud has colour.
struct FrontSums {
    /// Height sum and point count per pixel.
    sum: Vec<(f32, u32)>,
    /// RGBA sums per pixel.
    colour_sum: Option<Vec<[u32; 4]>>,
}

impl FrontSums {
    /// The image of the pixels' mean heights and colours (empty where no point counted).
    fn into_image(self, geometry: ImageGeometry) -> RangeImage {
        let FrontSums { sum, colour_sum } = self;
        let depth: Vec<f32> = sum
            .iter()
            .map(|&(s, c)| if c == 0 { EMPTY_DEPTH } else { s / c as f32 })
            .collect();
        let colour = colour_sum.map(|acc| {
            acc.iter()
                .zip(&sum)
                .map(|(a, &(_, c))| {
                    if c == 0 {
                        [0; 4]
                    } else {
                        a.map(|v| ((v + c / 2) / c).min(255) as u8)
                    }
                })
                .collect()
        });
        RangeImage {
            geometry,
            depth,
            colour,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane_points(n: usize, tilt: f32) -> (Vec<Vec3>, Vec<Vec3>) {
        // z = tilt * x over [0, 1]², on a jittered grid.
        let normal = Vec3::new(-tilt, 0.0, 1.0).normalize();
        let positions = (0..n * n)
            .map(|k| {
                let (a, b) = ((k % n) as f32, (k / n) as f32);
                let jitter = ((k * 7919 % 101) as f32 / 101.0 - 0.5) * 0.6;
                let x = (a + jitter) / n as f32;
                let y = (b - jitter) / n as f32;
                Vec3::new(x, y, tilt * x)
            })
            .collect();
        (positions, vec![normal; n * n])
    }

    #[test]
    fn tilted_plane_heights_are_exact_at_pixel_centres() {
        let (positions, normals) = plane_points(60, 0.8);
        let bounds = Aabb::from_points(positions.iter().copied());
        let basis = ViewBasis::new(Vec3::Z);
        let geometry = ImageGeometry::covering(basis, &bounds, 1.0 / 40.0);
        let points = PointColumns::new(&positions, &normals);
        let input = FlushInput {
            points: &points,
            colours: None,
            band: 0.02,
            jump: 0.1,
            oriented: false,
        };
        let image = flush_points(&input, geometry, &mut FlushScratch::default());
        assert!(image.depth.iter().filter(|d| d.is_finite()).count() > 1000);
        for j in 0..geometry.height {
            for i in 0..geometry.width {
                let d = image.depth[j * geometry.width + i];
                if d.is_finite() {
                    let p = geometry.point_at(i, j, d);
                    assert!((p.z - 0.8 * p.x).abs() < 1e-5, "pixel {i},{j}: {p}");
                }
            }
        }
    }

    #[test]
    fn oriented_normals_keep_the_two_sides_of_a_sheet_apart() {
        // A sheet 0.05 thick (under the averaging band): its top points face +z, its bottom
        // points −z. Unoriented, each view averages both sides; oriented, each view sees
        // only the side that faces it.
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        for j in 0..20 {
            for i in 0..20 {
                let p = Vec3::new(i as f32, j as f32, 0.0);
                positions.extend([p, p + 0.05 * Vec3::Z]);
                normals.extend([-Vec3::Z, Vec3::Z]);
            }
        }
        let bounds = Aabb::from_points(positions.iter().copied());
        let points = PointColumns::new(&positions, &normals);
        let mean_height = |direction: Vec3, oriented: bool| {
            let geometry = ImageGeometry::covering(ViewBasis::new(direction), &bounds, 1.0);
            let input = FlushInput {
                points: &points,
                colours: None,
                band: 0.1,
                jump: 0.5,
                oriented,
            };
            let image = flush_points(&input, geometry, &mut FlushScratch::default());
            let filled: Vec<f32> = image.depth.into_iter().filter(|d| d.is_finite()).collect();
            assert_eq!(filled.len(), 400);
            filled.iter().sum::<f32>() / filled.len() as f32
        };
        assert!((mean_height(Vec3::Z, false) - 0.025).abs() < 1e-4);
        assert!((mean_height(Vec3::Z, true) - 0.05).abs() < 1e-4);
        assert!((mean_height(-Vec3::Z, false) + 0.025).abs() < 1e-4);
        assert!(mean_height(-Vec3::Z, true).abs() < 1e-4);
    }

    #[test]
    fn farther_points_in_a_hole_are_removed() {
        // A front plane at z = 1 with a one-pixel hole, and a back plane at z = 0.
        let mut positions = Vec::new();
        for j in 0..20 {
            for i in 0..20 {
                let p = Vec3::new(i as f32, j as f32, 0.0);
                positions.push(p);
                if (i, j) != (10, 10) {
                    positions.push(p + Vec3::Z);
                }
            }
        }
        let normals = vec![Vec3::Z; positions.len()];
        let bounds = Aabb::from_points(positions.iter().copied());
        let geometry = ImageGeometry::covering(ViewBasis::new(Vec3::Z), &bounds, 1.0);
        let points = PointColumns::new(&positions, &normals);
        let input = FlushInput {
            points: &points,
            colours: None,
            band: 0.1,
            jump: 0.5,
            oriented: false,
        };
        let image = flush_points(&input, geometry, &mut FlushScratch::default());
        let (fx, fy, _) = geometry.project(Vec3::new(10.0, 10.0, 0.0));
        let k = fy.round() as usize * geometry.width + fx.round() as usize;
        assert_eq!(image.depth[k], EMPTY_DEPTH);
        let (fx, fy, _) = geometry.project(Vec3::new(5.0, 5.0, 0.0));
        assert!(image.depth[fy.round() as usize * geometry.width + fx.round() as usize] > 0.9);
    }

    #[test]
    fn every_chunk_of_points_reaches_its_pixel_with_its_own_colour() {
        // One point per pixel centre of a 200 × 200 grid (more than two chunks), each with
        // its own height and colour: a lost chunk tail or a colour taken from the wrong
        // point shows in its pixel.
        let side = 200;
        assert!(side * side > 2 * FLUSH_CHUNK + 1);
        let positions: Vec<Vec3> = (0..side * side)
            .map(|k| Vec3::new((k % side) as f32, (k / side) as f32, (k % 7) as f32 * 0.01))
            .collect();
        let colours: Vec<[u8; 4]> = (0..side * side)
            .map(|k| [(k % 251) as u8, (k / 251 % 256) as u8, (k % 13) as u8, 255])
            .collect();
        let normals = vec![Vec3::Z; positions.len()];
        let bounds = Aabb::from_points(positions.iter().copied());
        let geometry = ImageGeometry::covering(ViewBasis::new(Vec3::Z), &bounds, 1.0);
        let points = PointColumns::new(&positions, &normals);
        let input = FlushInput {
            points: &points,
            colours: Some(&colours),
            band: 0.001,
            jump: 10.0,
            oriented: false,
        };
        let image = flush_points(&input, geometry, &mut FlushScratch::default());
        let colour = image.colour.as_ref().expect("colours kept");
        for (k, p) in positions.iter().enumerate() {
            let (fx, fy, _) = geometry.project(*p);
            let pixel = fy.round() as usize * geometry.width + fx.round() as usize;
            assert!((image.depth[pixel] - p.z).abs() < 1e-6, "point {k}");
            assert_eq!(colour[pixel], colours[k], "point {k}");
        }
    }
}
