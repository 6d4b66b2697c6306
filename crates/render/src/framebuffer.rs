//! The framebuffer: bands of rows with a depth buffer and a small G-buffer,
//! the per-pixel resolve (deferred Phong), supersampling reduction and the
//! final image with its PNG encodings.
//!
//! Per pixel during rasterization: depth (`i32`, fixed point, initialised
//! to the far plane) and three `u32` payload words.
//!
//! - A **patch sample** (a node or sub-node) is a visibility-buffer entry:
//!   word 2 is the draw item's index with [`PATCH_SAMPLE`] set, word 0 the
//!   cell and the sub-node's position in it (`ci << 24 | cj << 16 | a << 8 | b`).
//!   Placing a sample therefore interpolates only position and depth; the
//!   attributes (normal, albedo or colour) are interpolated bilinearly from
//!   the cell's corner nodes once per visible pixel, in the resolve pass.
//! - A **triangle sample** stores its shading inputs directly — Flat and
//!   Gouraud: the shaded colour in word 0; Phong: the packed normal, the
//!   packed albedo and the shade frame's index in words 0, 1, 2.
//!
//! The resolve pass shades each covered pixel once, so Phong costs one
//! shading per pixel however many samples were drawn over it.
//!
//! Depth test: strictly less, so of two equal depths the first drawn wins;
//! the drawing order within a band is fixed, hence the image does not
//! depend on the thread count.
//!
//! Output depth PNG: 16-bit grey, 0 = no surface, otherwise
//! `1 + round(65534 · (w - near) / (far - near))` with `w` the linear eye
//! depth.
//!
//! Cost: O(pixels) to clear and resolve; 16 bytes per internal pixel.

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::error::RenderError;
use crate::fixed::Z_FAR;
use crate::options::Shading;
use crate::plan::{ChunkWork, Item};
use crate::prepare::PreparedPatch;
use crate::shade::{unpack_normal, unpack_rgb, Lanes, Material, ShadeFrame, ANY_POWER};
use crate::traverse::Node;

/// A band's buffers, borrowed for drawing.
pub(crate) struct BandTarget<'a> {
    pub(crate) width: i32,
    pub(crate) y0: i32,
    pub(crate) rows: i32,
    /// One record per pixel of the band, row-major.
    pub(crate) px: &'a mut [Sample],
}

/// What a pixel holds during rasterization: its depth and three payload
/// words (see the module header). Why one record rather than four arrays:
/// the depth test and the payload stores touch one cache line and one
/// bounds check (callgrind, `profile_sphere 500 1`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Sample {
    pub(crate) depth: i32,
    pub(crate) w0: u32,
    pub(crate) w1: u32,
    pub(crate) w2: u32,
}

impl Sample {
    /// An empty pixel (depth at the far plane).
    pub(crate) const EMPTY: Sample = Sample {
        depth: Z_FAR,
        w0: 0,
        w1: 0,
        w2: 0,
    };
}

/// What a drawn sample stores besides its depth.
pub(crate) trait Payload<const N: usize> {
    /// Stores the payload of a sample that passed the depth test.
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, attrs: &[i32; N]);
}

/// Flag of word 2 marking a patch sample.
pub(crate) const PATCH_SAMPLE: u32 = 1 << 31;

/// Writes a patch sample (see the module header) if it is in the band and
/// passes the depth test.
#[inline(always)]
pub(crate) fn splat_sample(t: &mut BandTarget<'_>, px: i32, py: i32, z: i32, sub: u32, item: u32) {
    let row = py - t.y0;
    // Unsigned compares reject negatives too.
    if (px as u32) < t.width as u32 && (row as u32) < t.rows as u32 {
        let s = &mut t.px[row as usize * t.width as usize + px as usize];
        if z < s.depth {
            s.depth = z;
            s.w0 = sub;
            s.w2 = item;
        }
    }
}

/// Writes a triangle sample with its payload if it is in the band and
/// passes the depth test.
#[inline(always)]
pub(crate) fn splat<const N: usize, P: Payload<N>>(
    t: &mut BandTarget<'_>,
    px: i32,
    py: i32,
    z: i32,
    attrs: &[i32; N],
    payload: &P,
) {
    let row = py - t.y0;
    if (px as u32) < t.width as u32 && (row as u32) < t.rows as u32 {
        let idx = row as usize * t.width as usize + px as usize;
        if z < t.px[idx].depth {
            t.px[idx].depth = z;
            payload.store(t, idx, attrs);
        }
    }
}

/// Flat shading: one colour for the whole cell or triangle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FlatPayload(pub(crate) u32);

impl Payload<0> for FlatPayload {
    #[inline(always)]
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, _: &[i32; 0]) {
        t.px[idx].w0 = self.0;
        t.px[idx].w2 = 0;
    }
}

/// Gouraud: interpolated colour (attributes 0..3, 0..=255 in fixed point).
#[derive(Debug, Clone, Copy)]
pub(crate) struct GouraudPayload;

#[inline(always)]
fn channel(v: i32) -> u32 {
    (v >> crate::fixed::ATTR_FRAC_BITS).clamp(0, 255) as u32
}

impl Payload<3> for GouraudPayload {
    #[inline(always)]
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, a: &[i32; 3]) {
        t.px[idx].w0 = channel(a[0]) | channel(a[1]) << 8 | channel(a[2]) << 16 | 0xff00_0000;
        t.px[idx].w2 = 0;
    }
}

/// Phong: interpolated normal and albedo, and the shade frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PhongPayload(pub(crate) u32);

impl Payload<6> for PhongPayload {
    #[inline(always)]
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, a: &[i32; 6]) {
        let s = &mut t.px[idx];
        s.w0 = crate::shade::pack_fixed_normal(a[0], a[1], a[2]);
        s.w1 = channel(a[3]) | channel(a[4]) << 8 | channel(a[5]) << 16;
        s.w2 = self.0;
    }
}

/// Time spent in one band, nanoseconds.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct BandTimes {
    pub(crate) cells: u64,
    pub(crate) triangles: u64,
    pub(crate) resolve: u64,
}

/// The buffers of one band of rows.
#[derive(Debug, Default)]
pub(crate) struct Band {
    pub(crate) y0: i32,
    pub(crate) rows: i32,
    pub(crate) width: i32,
    px: Vec<Sample>,
    pub(crate) times: BandTimes,
}

/// How the resolve pass turns payloads into colours.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Resolve<'a> {
    pub(crate) shading: Shading,
    /// Draw items by index: `(chunk, item)`.
    pub(crate) items: &'a [(u32, u32)],
    pub(crate) chunks: &'a [ChunkWork],
    /// The draw items as the Phong resolve pass reads them.
    pub(crate) phong: &'a PhongItems<'a>,
    pub(crate) material: Material,
    /// The albedo of nodes without colours, as stored in nodes (rounded to
    /// the attribute grid).
    pub(crate) base_albedo: Vec3,
    pub(crate) background: [u8; 4],
    pub(crate) near: f32,
    pub(crate) far: f32,
}

impl Band {
    /// Sizes and clears the buffers for rows `y0..y0 + rows` of `width`.
    /// Why a clear pass right before drawing rather than clearing in the
    /// resolve pass: the pass brings the band into the cache for the
    /// cells; clearing in the resolve pass saved ~0.45 M instructions per
    /// 500² sphere frame but cost ~1.5 ms of `cells_cpu` in cache misses
    /// (`--bench 50 --threads 1`, alternated runs). Why `fill`: stores of
    /// whole samples, a third of `resize`'s instructions (callgrind,
    /// `profile_sphere 500 1`).
    pub(crate) fn reset(&mut self, y0: i32, rows: i32, width: i32) {
        let n = (rows * width) as usize;
        self.y0 = y0;
        self.rows = rows;
        self.width = width;
        if self.px.len() == n {
            self.px.fill(Sample::EMPTY);
        } else {
            self.px.clear();
            self.px.resize(n, Sample::EMPTY);
        }
        self.times = BandTimes::default();
    }

    /// The buffers for drawing.
    pub(crate) fn target(&mut self) -> BandTarget<'_> {
        BandTarget {
            width: self.width,
            y0: self.y0,
            rows: self.rows,
            px: &mut self.px,
        }
    }

    /// Shades every pixel of the band into its rows of the image: colour
    /// into `rgba`, linear eye depth into `eye_depth` (`f32::INFINITY`
    /// where empty). Why the image's own rows: no band copy to gather, and
    /// the image's first touch happens on the pool (callgrind and
    /// `--bench`: the serial gather was ~1.3 ms of a 13.5 ms frame).
    pub(crate) fn resolve(&mut self, r: &Resolve<'_>, rgba: &mut [[u8; 4]], eye_depth: &mut [f32]) {
        debug_assert!(rgba.len() == self.px.len() && eye_depth.len() == self.px.len());
        if r.shading == Shading::Phong {
            self.resolve_phong(r, rgba, eye_depth);
            return;
        }
        let scale = (r.far - r.near) / Z_FAR as f32;
        // Why zipped slices: one length check per band instead of five
        // bounds checks per pixel (callgrind, `profile_sphere 500 1`).
        let pixels = self
            .px
            .iter()
            .zip(rgba.iter_mut().zip(eye_depth.iter_mut()));
        for (
            &Sample {
                depth: z,
                w0,
                w1: _,
                w2,
            },
            (rgba, eye),
        ) in pixels
        {
            if z >= Z_FAR {
                *rgba = r.background;
                *eye = f32::INFINITY;
                continue;
            }
            *eye = r.near + z as f32 * scale;
            *rgba = if w2 & PATCH_SAMPLE != 0 {
                resolve_patch_sample(r, w2 & !PATCH_SAMPLE, w0)
            } else {
                w0.to_le_bytes()
            };
        }
    }

    /// [`Self::resolve`] for Phong: the band in groups of four pixels
    /// ([`resolve_phong_pixels`]).
    fn resolve_phong(&mut self, r: &Resolve<'_>, rgba: &mut [[u8; 4]], eye_depth: &mut [f32]) {
        // The default shininess, 32, is five squarings (see
        // [`Material::shade4_with`]).
        if r.material.squarings() == 5 {
            resolve_phong_pixels::<5>(r, &self.px, rgba, eye_depth);
        } else {
            resolve_phong_pixels::<ANY_POWER>(r, &self.px, rgba, eye_depth);
        }
    }
}

/// Resolves the Phong pixels `px` into `rgba` and `eye_depth`, four
/// neighbours at a time: their eye depths, their normals and albedos
/// interpolated straight into lanes ([`phong_lane`]), shaded together
/// ([`Material::shade4_with`], bit-identical to shading them one by one; tested
/// against [`phong_reference`]), the background where a lane is empty.
/// Why groups of neighbours rather than a queue of covered pixels: the
/// queue's round trip through memory, its indices and scattered stores
/// were ~50 of the ~150 instructions per covered pixel, and groups only
/// waste lanes on silhouette edges (callgrind, `profile_sphere 500 1`).
/// Not inlined: inlined into [`Band::resolve`] the queued pass cost 2.5 M
/// instructions more per frame (register allocation).
#[inline(never)]
fn resolve_phong_pixels<const SQUARINGS: u32>(
    r: &Resolve<'_>,
    px: &[Sample],
    rgba: &mut [[u8; 4]],
    eye_depth: &mut [f32],
) {
    let groups = px
        .chunks_exact(4)
        .zip(rgba.chunks_exact_mut(4).zip(eye_depth.chunks_exact_mut(4)));
    for (s, (rgba, eye)) in groups {
        let s: &[Sample; 4] = s.try_into().expect("groups of four");
        let rgba: &mut [[u8; 4]; 4] = rgba.try_into().expect("groups of four");
        let eye: &mut [f32; 4] = eye.try_into().expect("groups of four");
        resolve_group::<SQUARINGS>(r, s, rgba, eye);
    }
    // The last pixels of a band whose size is not a multiple of four,
    // padded with empty pixels.
    let done = px.len() / 4 * 4;
    if done < px.len() {
        let n = px.len() - done;
        let mut s = [Sample::EMPTY; 4];
        s[..n].copy_from_slice(&px[done..]);
        let (mut c, mut e) = ([[0u8; 4]; 4], [0f32; 4]);
        resolve_group::<SQUARINGS>(r, &s, &mut c, &mut e);
        rgba[done..].copy_from_slice(&c[..n]);
        eye_depth[done..].copy_from_slice(&e[..n]);
    }
}

/// Resolves four neighbouring Phong pixels (see [`resolve_phong_pixels`]).
/// Why a fast path: nearly every group of the sphere is four covered patch
/// samples of items without colours, which need only their normals
/// interpolated (no albedo lanes, no per-lane choices); empty groups are
/// next, and the rest (silhouette edges, triangles, colours) goes through
/// [`resolve_general_group`] (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn resolve_group<const SQUARINGS: u32>(
    r: &Resolve<'_>,
    s: &[Sample; 4],
    rgba: &mut [[u8; 4]; 4],
    eye: &mut [f32; 4],
) {
    // Only a sample that passed the depth test holds a patch sample's
    // flag, so four patch samples are four covered pixels.
    let patches = s[0].w2 & s[1].w2 & s[2].w2 & s[3].w2;
    if patches & PATCH_SAMPLE != 0 {
        debug_assert!(s.iter().all(|s| s.depth < Z_FAR));
        let items = &r.phong.items[..];
        let id = |k: usize| (s[k].w2 & !PATCH_SAMPLE) as usize;
        let last = id(0).max(id(1)).max(id(2).max(id(3)));
        assert!(last < items.len(), "item index");
        let it = [&items[id(0)], &items[id(1)], &items[id(2)], &items[id(3)]];
        let uncoloured =
            || it[0].frame & it[1].frame & it[2].frame & it[3].frame & BASE_ALBEDO != 0;
        if r.phong.uncoloured || uncoloured() {
            let depth = [s[0].depth, s[1].depth, s[2].depth, s[3].depth];
            let sub = [s[0].w0, s[1].w0, s[2].w0, s[3].w0];
            let scale = (r.far - r.near) / Z_FAR as f32;
            let depth = Vec4::new(
                depth[0] as f32,
                depth[1] as f32,
                depth[2] as f32,
                depth[3] as f32,
            );
            *eye = (Vec4::splat(r.near) + depth * scale).to_array();
            let weights = &r.phong.weights[..];
            let normal = |k: usize| it[k].normal(sub[k], weights);
            let normals = [normal(0), normal(1), normal(2), normal(3)];
            // Why transposes even when the four share a frame: comparing
            // frames and choosing cost more than the shuffles (callgrind,
            // `profile_sphere 500 1`).
            let rows = |v: [Vec4; 4]| {
                let t = Mat4::from_cols(v[0], v[1], v[2], v[3]).transpose();
                [t.x_axis, t.y_axis, t.z_axis]
            };
            let light = rows([it[0].light, it[1].light, it[2].light, it[3].light]);
            let half = rows([it[0].half, it[1].half, it[2].half, it[3].half]);
            let albedo = r.base_albedo.extend(0.0);
            let albedo = [albedo.x, albedo.y, albedo.z].map(Vec4::splat);
            let words = shade_lanes::<SQUARINGS>(r, normals, light, half, |_| albedo);
            *rgba = words.map(u32::to_le_bytes);
            return;
        }
    }
    let near = s[0].depth.min(s[1].depth).min(s[2].depth.min(s[3].depth));
    if near >= Z_FAR {
        *rgba = [r.background; 4];
        *eye = [f32::INFINITY; 4];
        return;
    }
    resolve_general_group(r, s, rgba, eye);
}

/// [`resolve_group`] for any group with a covered pixel: lanes with their
/// own albedos, triangle samples, empty pixels (which take the inputs of a
/// covered one, then the background).
#[inline(never)]
fn resolve_general_group(
    r: &Resolve<'_>,
    s: &[Sample; 4],
    rgba: &mut [[u8; 4]; 4],
    eye: &mut [f32; 4],
) {
    let scale = (r.far - r.near) / Z_FAR as f32;
    let is = |k: usize| s[k].depth < Z_FAR;
    let some = &s[(0..4).find(|&k| is(k)).expect("a covered pixel")];
    let pick = |k: usize| if is(k) { &s[k] } else { some };
    // Why spelled out rather than a closure per lane or `array::map`: they
    // became out-of-line calls (~45 instructions per pixel of triangles;
    // callgrind, `profile_sphere 500 1 1 triangles`).
    let g = [
        phong_lane(r.phong, pick(0)),
        phong_lane(r.phong, pick(1)),
        phong_lane(r.phong, pick(2)),
        phong_lane(r.phong, pick(3)),
    ];
    let frame = |k: usize| (g[k].frame & !BASE_ALBEDO) as usize;
    let normals = [
        g[0].normal_red,
        g[1].normal_red,
        g[2].normal_red,
        g[3].normal_red,
    ];
    let frames = [frame(0), frame(1), frame(2), frame(3)];
    let words = shade_normals(r, normals, frames, |red| own_albedo(r, &g, red));
    for k in 0..4 {
        (rgba[k], eye[k]) = if is(k) {
            (words[k].to_le_bytes(), r.near + s[k].depth as f32 * scale)
        } else {
            (r.background, f32::INFINITY)
        };
    }
}

/// The shading inputs of a covered pixel: a patch sample's interpolated
/// normal and albedo, or a triangle sample's stored ones.
#[inline(always)]
fn phong_lane(t: &PhongItems<'_>, s: &Sample) -> Lane {
    if s.w2 & PATCH_SAMPLE != 0 {
        let i = (s.w2 & !PATCH_SAMPLE) as usize;
        return t.items[i].interpolate(s.w0, t.colours[i], &t.weights);
    }
    let albedo = unpack_rgb(s.w1);
    Lane {
        normal_red: unpack_normal(s.w0).extend(albedo.x),
        green_blue: Vec2::new(albedo.y, albedo.z),
        frame: s.w2,
    }
}

/// Flag of [`Lane::frame`]: the pixel takes the base albedo.
const BASE_ALBEDO: u32 = 1 << 31;

/// The shading inputs of one pixel of a group of four.
#[derive(Debug, Clone, Copy, Default)]
struct Lane {
    /// Normal (`xyz`, not unit) and albedo red (`w`, unless the base albedo).
    normal_red: Vec4,
    /// Albedo green and blue (unless the base albedo).
    green_blue: Vec2,
    /// Shade frame index, with [`BASE_ALBEDO`] for the base albedo.
    frame: u32,
}

/// Shades four pixels into RGBA8 words: their normals (`xyz`, not unit;
/// `w` passed to `albedo`), shade frames and albedo lanes. Why splats: the
/// four often share their shade frame, so only the normals need
/// transposing (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn shade_normals(
    r: &Resolve<'_>,
    normals: [Vec4; 4],
    f: [usize; 4],
    albedo: impl FnOnce(Vec4) -> [Vec4; 3],
) -> [u32; 4] {
    let frames = &r.phong.frames;
    let splat = |v: Vec4| [v.x, v.y, v.z].map(Vec4::splat);
    let (light, half) = if f[1] == f[0] && f[2] == f[0] && f[3] == f[0] {
        let [light, half] = frames[f[0]];
        (splat(light), splat(half))
    } else {
        // Where patches overlap (60 % of the sphere's groups): transposes.
        let e = f.map(|i| frames[i]);
        let rows = |k: usize| {
            let t = Mat4::from_cols(e[0][k], e[1][k], e[2][k], e[3][k]).transpose();
            [t.x_axis, t.y_axis, t.z_axis]
        };
        (rows(0), rows(1))
    };
    shade_lanes::<ANY_POWER>(r, normals, light, half, albedo)
}

/// Shades four pixels into RGBA8 words: their normals (`xyz`, not unit;
/// `w` passed to `albedo`), the lanes of their light and half vectors,
/// and their albedo lanes.
#[inline(always)]
fn shade_lanes<const SQUARINGS: u32>(
    r: &Resolve<'_>,
    normals: [Vec4; 4],
    light: [Vec4; 3],
    half: [Vec4; 3],
    albedo: impl FnOnce(Vec4) -> [Vec4; 3],
) -> [u32; 4] {
    let t = Mat4::from_cols(normals[0], normals[1], normals[2], normals[3]).transpose();
    let lanes = Lanes {
        normal: [t.x_axis, t.y_axis, t.z_axis],
        light,
        half,
        albedo: albedo(t.w_axis),
    };
    pack_rgba(r.material.shade4_with::<SQUARINGS>(&lanes))
}

/// The albedo lanes of four pixels, some of which may have their own
/// (red in `red`, green and blue in [`Lane::green_blue`]).
#[inline(always)]
fn own_albedo(r: &Resolve<'_>, g: &[Lane; 4], red: Vec4) -> [Vec4; 3] {
    let base = r.base_albedo;
    let lane = |k: usize| {
        if g[k].frame & BASE_ALBEDO != 0 {
            base
        } else {
            Vec3::new(red[k], g[k].green_blue.x, g[k].green_blue.y)
        }
    };
    let v = [lane(0), lane(1), lane(2), lane(3)];
    [0, 1, 2].map(|i| Vec4::new(v[0][i], v[1][i], v[2][i], v[3][i]))
}

/// What the Phong resolve pass needs of every draw item of a frame, by
/// index (as [`Resolve::items`]), and the bilinear weights of the
/// sub-nodes of every subdivision the frame uses. Built once per frame.
/// Why a flat table: where patches overlap, a third of the sphere's pixels
/// change item, and the item → chunk → item → patch → level lookups cost
/// ~70 instructions each (callgrind, `profile_sphere 500 1`).
#[derive(Debug, Default)]
pub(crate) struct PhongItems<'a> {
    items: Vec<PhongItem<'a>>,
    /// Per item, its level's prepared albedos from the piece's first node
    /// on; empty for the base albedo. Why apart from [`PhongItem`]: 32-byte
    /// items index with a shift (callgrind, `profile_sphere 500 1`).
    colours: Vec<&'a [Vec4]>,
    /// True when no item has colours (all take the base albedo).
    uncoloured: bool,
    /// The shade frames' light and half vectors (`w` = 0), by frame index.
    /// Why vectors: lanes of different frames are gathered by transposes
    /// (callgrind, `profile_sphere 500 1`: 60 % of the sphere's groups of
    /// four mix frames where patches overlap).
    frames: Vec<[Vec4; 2]>,
    /// Per subdivision `nu × nv`, the weights of sub-node `(a, b)` at
    /// `a * (nv + 1) + b`, each splat over four lanes.
    weights: Vec<[Vec4; 4]>,
}

impl<'a> PhongItems<'a> {
    /// The table for the draw items `items` (`(chunk, item)`) of `chunks`,
    /// which refer to `patches` and `frames`; empty unless `shading` is
    /// Phong.
    pub(crate) fn new(
        shading: Shading,
        items: &[(u32, u32)],
        chunks: &[ChunkWork],
        patches: &'a [PreparedPatch],
        frames: &[ShadeFrame],
    ) -> Self {
        let mut table = Self::default();
        if shading != Shading::Phong {
            return table;
        }
        table.frames = frames
            .iter()
            .map(|f| [f.light.extend(0.0), f.half.extend(0.0)])
            .collect();
        let mut built: Vec<(u16, u16, u32)> = Vec::new();
        table.items.reserve(items.len());
        table.colours.reserve(items.len());
        for &(c, i) in items {
            let item = &chunks[c as usize].items[i as usize];
            let (nu, nv) = (item.nu, item.nv);
            let start = match built.iter().find(|&&(u, v, _)| (u, v) == (nu, nv)) {
                Some(&(_, _, start)) => start,
                None => {
                    let start = table.weights.len() as u32;
                    for a in 0..=nu as u32 {
                        for b in 0..=nv as u32 {
                            let w = sub_node_weights(a, b, nu as u32, nv as u32);
                            table.weights.push(w.map(Vec4::splat));
                        }
                    }
                    built.push((nu, nv, start));
                    start
                }
            };
            let (entry, colours) = PhongItem::new(item, patches, &table.frames, start);
            table.items.push(entry);
            table.colours.push(colours);
        }
        table.uncoloured = table.colours.iter().all(|c| c.is_empty());
        table
    }
}

/// A draw item as the Phong resolve pass reads it: its level's prepared
/// normals from the piece's first node on (its albedos are in
/// [`PhongItems::colours`]).
#[derive(Debug, Clone, Copy)]
struct PhongItem<'a> {
    /// The light vector of the item's shade frame (`w` = 0).
    light: Vec4,
    /// The half vector of the item's shade frame (`w` = 0).
    half: Vec4,
    normals: &'a [Vec4],
    /// Nodes per row of the level (`u16`: index sums cannot overflow, no
    /// checks).
    cols: u16,
    /// Weights per row of the item's weight table (`nv + 1`).
    stride: u16,
    /// Where the item's weights start in [`PhongItems::weights`].
    weights: u32,
    /// The item's shade frame, with [`BASE_ALBEDO`] for an item without
    /// colours.
    frame: u32,
}

impl<'a> PhongItem<'a> {
    /// The entry of `item` (of a patch of `patches`, shaded in one of
    /// `frames`) whose weights start at `weights`, and its albedos (empty
    /// for the base albedo).
    fn new(
        item: &Item,
        patches: &'a [PreparedPatch],
        frames: &[[Vec4; 2]],
        weights: u32,
    ) -> (Self, &'a [Vec4]) {
        let patch = &patches[item.frame as usize];
        let m = item.level as usize;
        let cols = patch.level(m).cols;
        let shading = patch.shading(m);
        let start = item.j0 as usize * cols + item.i0 as usize;
        let uniform = item.uniform_albedo || shading.colours.is_empty();
        let [light, half] = frames[item.frame as usize];
        let entry = Self {
            light,
            half,
            normals: &shading.normals[start..],
            cols: cols as u16,
            stride: item.nv + 1,
            weights,
            frame: item.frame | if uniform { BASE_ALBEDO } else { 0 },
        };
        let colours: &[Vec4] = if uniform {
            &[]
        } else {
            &shading.colours[start..]
        };
        (entry, colours)
    }

    /// The normal interpolated at sample `sub` (`w` unused): the same
    /// operations in the same order as [`phong_reference`].
    #[inline(always)]
    fn normal(&self, sub: u32, weights: &[[Vec4; 4]]) -> Vec4 {
        let cols = self.cols as usize;
        let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
        let k = cj * cols + ci;
        let (a, b) = (((sub >> 8) & 0xff) as usize, (sub & 0xff) as usize);
        let w = &weights[self.weights as usize + a * self.stride as usize + b];
        // One slice for the four corners: a single bounds check.
        let quad = &self.normals[k..k + cols + 2];
        quad[0] * w[0] + quad[1] * w[1] + quad[cols] * w[2] + quad[cols + 1] * w[3]
    }

    /// The normal and albedo (from `colours`, the item's) interpolated at
    /// sample `sub`: the same operations in the same order as
    /// [`phong_reference`].
    #[inline(always)]
    fn interpolate(&self, sub: u32, colours: &[Vec4], weights: &[[Vec4; 4]]) -> Lane {
        let cols = self.cols as usize;
        let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
        let k = cj * cols + ci;
        let (a, b) = (((sub >> 8) & 0xff) as usize, (sub & 0xff) as usize);
        let w = &weights[self.weights as usize + a * self.stride as usize + b];
        // One slice for the four corners: a single bounds check.
        let lerp = |v: &[Vec4]| {
            let quad = &v[k..k + cols + 2];
            quad[0] * w[0] + quad[1] * w[1] + quad[cols] * w[2] + quad[cols + 1] * w[3]
        };
        let mut lane = Lane {
            normal_red: lerp(self.normals),
            green_blue: Vec2::ZERO,
            frame: self.frame,
        };
        if self.frame & BASE_ALBEDO == 0 {
            let c = lerp(colours);
            lane.normal_red.w = c.x;
            lane.green_blue = Vec2::new(c.y, c.z);
        }
        lane
    }
}

/// The bilinear weights of the corners `(0, 0), (1, 0), (0, 1), (1, 1)` at
/// sub-node `(a, b)` of a cell cut `nu × nv`.
#[inline(always)]
fn sub_node_weights(a: u32, b: u32, nu: u32, nv: u32) -> [f32; 4] {
    let s = a as f32 / nu as f32;
    let t = b as f32 / nv as f32;
    [(1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t]
}

/// Red, green and blue lanes in 0..=255 (as [`Material::shade4_with`] returns
/// them) truncated to bytes and packed as RGBA8 words (alpha 255), as
/// [`truncate_to_bytes`] gives them.
#[inline(always)]
fn pack_rgba(c: [Vec4; 3]) -> [u32; 4] {
    // Why spelled out: `array::map` here became an out-of-line call per
    // channel (~40 instructions per pixel group; callgrind,
    // `profile_sphere 500 1`).
    let bits = |v: Vec4| {
        let a = truncated_bits(v).to_array();
        [
            a[0].to_bits(),
            a[1].to_bits(),
            a[2].to_bits(),
            a[3].to_bits(),
        ]
    };
    let (r, g, b) = (bits(c[0]), bits(c[1]), bits(c[2]));
    // No masks: each lane's bits are `0x4b00_00vv` (`2^23 + v`, v < 256),
    // so the shifts push the exponent out of the word and the alpha byte
    // covers red's.
    let word = |k: usize| r[k] | g[k] << 8 | b[k] << 16 | 0xff00_0000;
    [word(0), word(1), word(2), word(3)]
}

/// RGB floats in 0..=255 (as [`Material::shade`] returns them) to RGBA8.
/// Why through `i32`: the values are already in range, and the saturating
/// float-to-`u8` conversion costs about twice as many instructions; the
/// result is the same (truncation).
#[inline(always)]
fn to_rgba8(c: Vec3) -> [u8; 4] {
    [c.x as i32 as u8, c.y as i32 as u8, c.z as i32 as u8, 255]
}

/// Four colour values in 0..=255 truncated to bytes, as `c as i32 as u8`
/// does one at a time. Why: the scalar conversions with their saturation
/// checks were ~18 instructions per pixel (callgrind, `profile_sphere 500
/// 1`). Adding `2^23` rounds to an integer (kept in the low mantissa bits);
/// subtracting one where that rounded up gives the truncation.
#[inline(always)]
#[cfg(test)]
fn truncate_to_bytes(c: Vec4) -> [u8; 4] {
    truncated_bits(c).to_array().map(|v| v.to_bits() as u8)
}

/// `2^23 + trunc(c)` per lane: the truncated value sits in the low
/// mantissa bits (see [`truncate_to_bytes`]).
#[inline(always)]
fn truncated_bits(c: Vec4) -> Vec4 {
    const SHIFT: f32 = 8_388_608.0; // 2^23: the unit of the last mantissa bit is 1.
    let shifted = c + Vec4::splat(SHIFT);
    let nearest = shifted - Vec4::splat(SHIFT);
    // Exact: `shifted` is an integer in 2^23..2^23 + 256.
    shifted - Vec4::select(nearest.cmpgt(c), Vec4::ONE, Vec4::ZERO)
}

/// The four attribute words `[from, from + 4)` of a node as floats.
#[inline(always)]
fn attr4(n: &Node, from: usize) -> Vec4 {
    Vec4::new(
        attr_to_f32f(n[from]),
        attr_to_f32f(n[from + 1]),
        attr_to_f32f(n[from + 2]),
        attr_to_f32f(n[from + 3]),
    )
}

/// The cell of a patch sample: its item, its four corner nodes and the
/// bilinear weights of its sub-node.
#[inline(always)]
fn sample_cell<'r>(r: &Resolve<'r>, item: u32, sub: u32) -> (&'r Item, [&'r Node; 4], [f32; 4]) {
    let (c, i) = r.items[item as usize];
    let chunk = &r.chunks[c as usize];
    let item = &chunk.items[i as usize];
    let cols = item.cols as usize;
    let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
    let k = item.first as usize + cj * cols + ci;
    // One slice for the four corners: a single bounds check.
    let quad = &chunk.nodes[k..k + cols + 2];
    let w = sub_node_weights(
        (sub >> 8) & 0xff,
        sub & 0xff,
        item.nu as u32,
        item.nv as u32,
    );
    (item, [&quad[0], &quad[1], &quad[cols], &quad[cols + 1]], w)
}

/// Attribute words `[from, from + 4)` interpolated bilinearly. Why four
/// lanes at a time: the same products and sums in the same order as one
/// channel at a time (identical images), a quarter of the instructions
/// (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn lerp4(n: [&Node; 4], w: [f32; 4], from: usize) -> Vec4 {
    attr4(n[0], from) * w[0]
        + attr4(n[1], from) * w[1]
        + attr4(n[2], from) * w[2]
        + attr4(n[3], from) * w[3]
}

/// Shades a patch sample with flat or Gouraud colours: the cell's colour,
/// or the colours of its corners interpolated at its sub-node.
#[inline]
fn resolve_patch_sample(r: &Resolve<'_>, item: u32, sub: u32) -> [u8; 4] {
    let (_, n, w) = sample_cell(r, item, sub);
    let colour = match r.shading {
        Shading::Flat => Vec3::new(
            attr_to_f32f(n[0][3]),
            attr_to_f32f(n[0][4]),
            attr_to_f32f(n[0][5]),
        ),
        Shading::Gouraud | Shading::Phong => lerp4(n, w, 3).truncate(),
    };
    to_rgba8(colour)
}

/// The Phong colour of a patch sample shaded alone, straight from the
/// prepared level: the bilinear weights of its sub-node, the corners'
/// normals and albedos (`base_albedo` for an item without colours) summed
/// in corner order, [`Material::shade`]. The reference the grouped resolve
/// pass is tested against.
#[cfg(test)]
fn phong_reference(
    r: &Resolve<'_>,
    patches: &[PreparedPatch],
    frames: &[ShadeFrame],
    item: u32,
    sub: u32,
) -> [u8; 4] {
    let (c, i) = r.items[item as usize];
    let item = &r.chunks[c as usize].items[i as usize];
    let patch = &patches[item.frame as usize];
    let m = item.level as usize;
    let cols = patch.level(m).cols;
    let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
    let k = (item.j0 as usize + cj) * cols + item.i0 as usize + ci;
    let w = sub_node_weights(
        (sub >> 8) & 0xff,
        sub & 0xff,
        item.nu as u32,
        item.nv as u32,
    );
    let lerp = |v: &[Vec4]| {
        let corners = [k, k + 1, k + cols, k + cols + 1];
        let mut sum = v[corners[0]].truncate() * w[0];
        for (corner, weight) in corners.into_iter().zip(w).skip(1) {
            sum += v[corner].truncate() * weight;
        }
        sum
    };
    let shading = patch.shading(m);
    let albedo = if item.uniform_albedo {
        r.base_albedo
    } else {
        lerp(&shading.colours)
    };
    let c = r
        .material
        .shade(lerp(&shading.normals), &frames[item.frame as usize], albedo);
    to_rgba8(c)
}

#[inline(always)]
fn attr_to_f32f(v: i32) -> f32 {
    crate::fixed::attr_from_bits(v)
}

/// A rendered image: RGBA8 colour and linear eye depth per pixel, row 0 at
/// the top.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderedImage {
    width: u32,
    height: u32,
    rgba: Vec<[u8; 4]>,
    depth: Vec<f32>,
    near: f64,
    far: f64,
}

impl RenderedImage {
    /// The `width × height` image from the internal image (`ssaa` times
    /// larger per axis) as the bands resolved it: kept as is for `ssaa = 1`,
    /// else reduced (box filter for colour, nearest surface for depth).
    pub(crate) fn from_internal(
        internal_rgba: Vec<[u8; 4]>,
        internal_depth: Vec<f32>,
        width: u32,
        height: u32,
        ssaa: u32,
        near: f64,
        far: f64,
    ) -> Self {
        let (w, h) = (width as usize, height as usize);
        let k = ssaa as usize;
        let iw = w * k;
        debug_assert_eq!(internal_rgba.len(), iw * h * k);
        if k == 1 {
            return Self {
                width,
                height,
                rgba: internal_rgba,
                depth: internal_depth,
                near,
                far,
            };
        }
        let mut rgba = vec![[0u8; 4]; w * h];
        let mut depth = vec![f32::INFINITY; w * h];
        let samples = (k * k) as u32;
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 4];
                let mut nearest = f32::INFINITY;
                for sy in 0..k {
                    let row = (y * k + sy) * iw + x * k;
                    for s in row..row + k {
                        for (acc, c) in sum.iter_mut().zip(internal_rgba[s]) {
                            *acc += c as u32;
                        }
                        nearest = nearest.min(internal_depth[s]);
                    }
                }
                rgba[y * w + x] = sum.map(|v| ((v + samples / 2) / samples) as u8);
                depth[y * w + x] = nearest;
            }
        }
        Self {
            width,
            height,
            rgba,
            depth,
            near,
            far,
        }
    }

    /// The colour and depth buffers, for [`crate::Renderer::recycle`].
    pub(crate) fn into_buffers(self) -> (Vec<[u8; 4]>, Vec<f32>) {
        (self.rgba, self.depth)
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Pixels, row-major from the top-left, RGBA8.
    pub fn pixels(&self) -> &[[u8; 4]] {
        &self.rgba
    }
    /// Linear eye depth per pixel; `f32::INFINITY` where no surface.
    pub fn depth(&self) -> &[f32] {
        &self.depth
    }
    /// The near plane used.
    pub fn near(&self) -> f64 {
        self.near
    }
    /// The far plane used.
    pub fn far(&self) -> f64 {
        self.far
    }
    /// True when pixel `(x, y)` shows a surface.
    pub fn is_covered(&self, x: u32, y: u32) -> bool {
        self.depth[(y * self.width + x) as usize].is_finite()
    }
    /// Number of pixels showing a surface.
    pub fn covered_count(&self) -> usize {
        self.depth.iter().filter(|d| d.is_finite()).count()
    }

    /// PSNR (dB) of the RGB channels against `other` (same size), or `None`
    /// when the images are identical or differ in size.
    pub fn psnr(&self, other: &RenderedImage) -> Option<f64> {
        if self.width != other.width || self.height != other.height {
            return None;
        }
        let mut sum = 0u64;
        for (a, b) in self.rgba.iter().zip(&other.rgba) {
            for c in 0..3 {
                let d = a[c] as i64 - b[c] as i64;
                sum += (d * d) as u64;
            }
        }
        if sum == 0 {
            return None;
        }
        let mse = sum as f64 / (self.rgba.len() * 3) as f64;
        Some(10.0 * (255.0 * 255.0 / mse).log10())
    }

    /// The colour image as PNG bytes (RGBA8).
    pub fn encode_png(&self) -> Result<Vec<u8>, RenderError> {
        let bytes: Vec<u8> = self.rgba.iter().flatten().copied().collect();
        let buffer = image::RgbaImage::from_raw(self.width, self.height, bytes)
            .ok_or(RenderError::Bug("colour buffer size"))?;
        let mut out = std::io::Cursor::new(Vec::new());
        buffer
            .write_to(&mut out, image::ImageFormat::Png)
            .map_err(|source| RenderError::Encode {
                what: "colour",
                source,
            })?;
        Ok(out.into_inner())
    }

    /// The depth image as 16-bit greyscale PNG bytes (see the module header).
    pub fn encode_depth_png(&self) -> Result<Vec<u8>, RenderError> {
        let span = self.far - self.near;
        let values: Vec<u16> = self
            .depth
            .iter()
            .map(|&d| {
                if d.is_finite() {
                    let t = ((d as f64 - self.near) / span).clamp(0.0, 1.0);
                    1 + (t * 65534.0).round() as u16
                } else {
                    0
                }
            })
            .collect();
        let buffer = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(
            self.width,
            self.height,
            values,
        )
        .ok_or(RenderError::Bug("depth buffer size"))?;
        let mut out = std::io::Cursor::new(Vec::new());
        buffer
            .write_to(&mut out, image::ImageFormat::Png)
            .map_err(|source| RenderError::Encode {
                what: "depth",
                source,
            })?;
        Ok(out.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// Two 9 × 9 patches with colours, bumpy, with a few empty nodes.
    fn coloured_scene(rng: &mut XorShift) -> crate::PreparedScene {
        use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};
        let patches = (0..2)
            .map(|p| {
                let frame = Frame::new(
                    glam::Vec3::new(p as f32 * 9.0, 0.0, 0.0),
                    glam::Vec3::X,
                    glam::Vec3::Y * (1.0 + p as f32),
                    glam::Vec3::Z * 0.01,
                )
                .unwrap();
                let d = (0..81)
                    .map(|k| {
                        if k % 23 == 7 {
                            spatch_format::EMPTY
                        } else {
                            rng.below(3000) as u16
                        }
                    })
                    .collect();
                let c = (0..81)
                    .map(|_| [0, 1, 2, 3].map(|_| rng.below(256) as u8))
                    .collect();
                Patch::new(frame, GridSize::new(9, 9).unwrap(), d, Some(c)).unwrap()
            })
            .collect();
        let scene = Scene::new(glam::DVec3::ZERO, ColourChannel::Rgba8, patches).unwrap();
        crate::PreparedScene::new(&scene)
    }

    /// Which pixels [`check_phong_resolve`] draws.
    #[derive(Clone, Copy)]
    enum Mix {
        /// Every kind of pixel: empty, triangle samples, patch samples of
        /// items with and without colours.
        Everything,
        /// Nearly all patch samples of items without colours, of both
        /// shade frames (the fast path of [`resolve_group`]).
        Uncoloured,
        /// Items without colours only (a frame without colours: the fast
        /// path does not look at the items' albedos), patch samples of
        /// both shade frames and a few triangle samples.
        NoColours,
    }

    #[test]
    fn phong_resolve_matches_scalar_shading_per_pixel() {
        // Shininess 32 takes the five squarings of `resolve_phong_pixels`.
        check_phong_resolve(Mix::Everything, 61, 7);
        check_phong_resolve(Mix::Everything, 62, 32);
        check_phong_resolve(Mix::Uncoloured, 64, 32);
        check_phong_resolve(Mix::Uncoloured, 63, 7);
        check_phong_resolve(Mix::NoColours, 64, 32);
        check_phong_resolve(Mix::NoColours, 65, 7);
    }

    /// Resolves a band of `width × 6` random pixels of `mix`, lit with
    /// `shininess`, and checks every pixel against [`phong_reference`] or
    /// [`Material::shade`].
    fn check_phong_resolve(mix: Mix, width: i32, shininess: u32) {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        let prepared = coloured_scene(&mut rng);
        let patches = &prepared.patches;
        assert_eq!(patches.len(), 2);
        assert!(patches.iter().all(|p| p.level_count() >= 2));
        // Pieces at levels 0 and 1, cut in several ways, with and without
        // their colours.
        let mut chunk = ChunkWork::default();
        for k in 0..8u32 {
            let (frame, level) = ((k % 2) as usize, (k / 2 % 2) as usize);
            let lc = patches[frame].level(level).cols;
            let (i0, j0) = if level == 0 {
                (k as usize % 3, 1)
            } else {
                (0, 0)
            };
            chunk.items.push(Item {
                first: 0,
                cols: (lc - i0) as u16,
                rows: (lc - j0) as u16,
                nu: [1, 2, 3, 5][k as usize % 4],
                nv: [1, 4, 2, 3][k as usize / 2 % 4],
                frame: frame as u32,
                flags: 0,
                spans: 0,
                uniform_albedo: k >= 4 || matches!(mix, Mix::NoColours),
                level: level as u8,
                i0: i0 as u16,
                j0: j0 as u16,
                y0: 0,
                y1: 0,
                inside_columns: false,
                splat: [0, 0],
            });
        }
        let items: Vec<(u32, u32)> = (0..8).map(|i| (0, i)).collect();
        let chunks = [chunk];
        let lighting = crate::Lighting {
            shininess,
            ..Default::default()
        };
        let light = crate::shade::WorldLight::new(
            &lighting,
            [glam::DVec3::X, glam::DVec3::Y, glam::DVec3::Z],
        );
        let frames: Vec<ShadeFrame> = patches
            .iter()
            .enumerate()
            .map(|(k, p)| light.frame_in(&p.rotation, k == 1))
            .collect();
        let phong = PhongItems::new(Shading::Phong, &items, &chunks, patches, &frames);
        assert_eq!(phong.uncoloured, matches!(mix, Mix::NoColours));
        let r = Resolve {
            shading: Shading::Phong,
            items: &items,
            chunks: &chunks,
            phong: &phong,
            material: Material::new(&lighting),
            base_albedo: Vec3::new(200.0, 120.0, 40.0),
            background: [1, 2, 3, 4],
            near: 0.5,
            far: 10.0,
        };
        let rows = 6;
        let mut band = Band::default();
        band.reset(0, rows, width);
        let mut expected = Vec::new();
        for px in band.px.iter_mut() {
            let choice = match mix {
                Mix::Everything => rng.below(10),
                Mix::Uncoloured => {
                    [0, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9][rng.below(16) as usize]
                }
                Mix::NoColours => {
                    [0, 1, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9, 9][rng.below(16) as usize]
                }
            };
            if choice == 0 {
                expected.push(r.background);
                continue;
            }
            px.depth = rng.below(Z_FAR as u32) as i32;
            if choice == 1 {
                // A triangle sample with its own normal, albedo and frame.
                let n = Vec3::new(rng.below(200) as f32, rng.below(200) as f32, 100.0);
                px.w0 = crate::shade::pack_normal((n - Vec3::new(100.0, 100.0, 0.0)) / 200.0);
                px.w1 = rng.next_u32() & 0xff_ffff;
                px.w2 = rng.below(2);
                let c = r.material.shade(
                    unpack_normal(px.w0),
                    &frames[px.w2 as usize],
                    unpack_rgb(px.w1),
                );
                expected.push(to_rgba8(c));
                continue;
            }
            // Runs of one item, as drawn patches leave them, or any item
            // (`Mix::Uncoloured`: an item without colours, runs of one).
            let id = match mix {
                Mix::Everything if choice < 6 => 3,
                Mix::Everything => rng.below(8),
                Mix::Uncoloured if rng.below(3) == 0 => 4 + rng.below(4),
                Mix::Uncoloured => 5,
                Mix::NoColours if rng.below(3) == 0 => rng.below(8),
                Mix::NoColours => 2,
            };
            let item = &chunks[0].items[id as usize];
            let ci = rng.below(item.cols as u32 - 1);
            let cj = rng.below(item.rows as u32 - 1);
            let a = rng.below(item.nu as u32 + 1);
            let b = rng.below(item.nv as u32 + 1);
            px.w0 = ci << 24 | cj << 16 | a << 8 | b;
            px.w2 = id | PATCH_SAMPLE;
            expected.push(phong_reference(&r, patches, &frames, id, px.w0));
        }
        let samples = band.px.clone();
        let mut rgba = vec![[0u8; 4]; band.px.len()];
        let mut eye = vec![0f32; band.px.len()];
        band.resolve(&r, &mut rgba, &mut eye);
        for (k, (got, want)) in rgba.iter().zip(&expected).enumerate() {
            assert_eq!(got, want, "pixel {k}: {:?}", samples[k]);
        }
        let covered = samples.iter().filter(|s| s.depth < Z_FAR).count();
        assert!(covered > 300, "{covered}");
        if let Mix::Everything = mix {
            assert!(covered % 4 != 0, "{covered}");
        }
        assert_eq!(eye.iter().filter(|e| e.is_finite()).count(), covered);
        for (e, s) in eye.iter().zip(&samples) {
            if s.depth < Z_FAR {
                assert_eq!(
                    *e,
                    r.near + s.depth as f32 * ((r.far - r.near) / Z_FAR as f32)
                );
            }
        }
        // How many groups took the fast path: four covered patch samples
        // of items without colours, of one shade frame or of several.
        let fast = |mixed: bool| {
            samples
                .chunks_exact(4)
                .filter(|g| {
                    let uncoloured = |s: &Sample| {
                        s.depth < Z_FAR
                            && s.w2 & PATCH_SAMPLE != 0
                            && chunks[0].items[(s.w2 & !PATCH_SAMPLE) as usize].uniform_albedo
                    };
                    let frame = |s: &Sample| chunks[0].items[(s.w2 & !PATCH_SAMPLE) as usize].frame;
                    g.iter().all(uncoloured) && g.iter().any(|s| frame(s) != frame(&g[0])) == mixed
                })
                .count()
        };
        if let Mix::Uncoloured | Mix::NoColours = mix {
            assert!(
                fast(false) > 10 && fast(true) > 10,
                "{} {}",
                fast(false),
                fast(true)
            );
        }
    }

    #[test]
    fn packed_words_hold_the_truncated_channels() {
        let mut rng = XorShift(0x5151_a5a5_0f0f_7777);
        for round in 0..5000 {
            let v = |rng: &mut XorShift| match round % 3 {
                // Integers and their neighbours (the rounding step's edges).
                0 => {
                    let k = rng.below(256) as f32;
                    let up = f32::from_bits(k.to_bits() + 1);
                    [k, up, k - 0.5, k + 0.5][rng.below(4) as usize].clamp(0.0, 255.0)
                }
                _ => rng.below(1 << 24) as f32 / (1 << 24) as f32 * 255.0,
            };
            let c =
                [0, 1, 2].map(|_| Vec4::new(v(&mut rng), v(&mut rng), v(&mut rng), v(&mut rng)));
            let want: [u32; 4] = std::array::from_fn(|k| {
                u32::from_le_bytes([
                    c[0][k] as i32 as u8,
                    c[1][k] as i32 as u8,
                    c[2][k] as i32 as u8,
                    255,
                ])
            });
            assert_eq!(pack_rgba(c), want, "{c:?}");
        }
    }

    #[test]
    fn bytes_are_truncated_like_a_scalar_conversion() {
        let mut v = 0.0f32;
        while v <= 255.0 {
            let next = f32::from_bits(v.to_bits() + 1).min(255.0);
            let c = Vec4::new(v, (v * 0.37).min(255.0), 255.0 - v, next);
            let expected = c.to_array().map(|x| x as i32 as u8);
            assert_eq!(truncate_to_bytes(c), expected, "{c:?}");
            v += 0.023_437_5;
        }
        // Exact integers and halves (ties of the rounding step).
        for k in 0..=255 {
            let c = Vec4::new(
                k as f32,
                k as f32 + 0.5,
                (k as f32 - 0.5).max(0.0),
                k as f32,
            );
            assert_eq!(truncate_to_bytes(c), c.to_array().map(|x| x as i32 as u8));
        }
    }
}
