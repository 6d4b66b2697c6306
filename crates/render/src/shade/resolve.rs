//! The per-pixel resolve of a band (deferred shading): every covered
//! pixel is shaded once from what its sample holds, into the image's rows
//! of colour and linear eye depth.
//!
//! A patch sample ([`crate::raster::band`]) names its draw item, cell and
//! sub-node: Gouraud interpolates the colours its corner nodes carry;
//! Phong interpolates the prepared level's normals and albedos
//! ([`PhongItems`]) and shades four neighbouring pixels at a time in
//! lanes (eight with AVX2, [`crate::shade::resolve_wide`]), bit-identical
//! to shading them one by one ([`Material::shade`]);
//! flat does the same with its level's cell normals and every weight on
//! the first corner. A triangle sample carries its colour, or its normal,
//! albedo and frame.
//!
//! So Phong costs one shading per pixel however many samples were drawn
//! over it.
//!
//! Cost: O(pixels) per band.

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::fixed::{attr_from_bits, NodeAttributes, Z_FAR};
#[cfg(target_arch = "x86_64")]
use crate::isa::Isa;
#[cfg(test)]
use crate::lighting::byte_lanes;
#[cfg(doc)]
use crate::lighting::Material;
use crate::lighting::{unpack_normal, unpack_rgb, Lanes, ShadeFrame, ANY_POWER};
use crate::options::Shading;
use crate::plan::work::Item;
#[cfg(test)]
use crate::prepare::patch::PreparedPatch;
use crate::raster::band::{Sample, PATCH_SAMPLE};
use crate::raster::band_box::PixelBox;
use crate::shade::colour_grid::{corner_albedo, grid_place, relight};
#[cfg(test)]
use crate::shade::phong_items::sub_node_place;
use crate::shade::phong_items::{sub_node_weights, Lane, PhongItem, PhongItems, BASE_ALBEDO};
#[cfg(target_arch = "x86_64")]
use crate::shade::resolve_wide::wide_group;
use crate::shade::rgba::{pack_rgba, to_rgba8};

pub(crate) use crate::shade::resolve_inputs::Resolve;

/// [`resolve_band`] for the pixels of `touched` only, the rest of the
/// band `whole` (its rows of the image) taking the background without
/// reading its samples, which are not cleared (see
/// [`crate::raster::band_box`]). Each pixel's colour and depth are those
/// [`resolve_band`] gives it over the whole band: it shades each pixel
/// alone, four lanes at a time.
#[inline(always)]
pub(crate) fn resolve_box(
    r: &Resolve<'_>,
    px: &[Sample],
    whole: PixelBox,
    touched: PixelBox,
    rgba: &mut [[u8; 4]],
    eye_depth: &mut [f32],
) {
    debug_assert!(touched.x0 <= touched.x1 && whole.y0 <= touched.y0 && touched.y0 <= touched.y1);
    let w = whole.x1 as usize;
    let background = |rgba: &mut [[u8; 4]], eye: &mut [f32]| {
        rgba.fill(r.background);
        eye.fill(f32::INFINITY);
    };
    if touched.x0 == whole.x0 && touched.x1 == whole.x1 {
        // Whole rows: one pass over them (no group padded per row).
        let a = (touched.y0 - whole.y0) as usize * w;
        let b = (touched.y1 - whole.y0) as usize * w;
        resolve_band(r, &px[a..b], &mut rgba[a..b], &mut eye_depth[a..b]);
        background(&mut rgba[..a], &mut eye_depth[..a]);
        background(&mut rgba[b..], &mut eye_depth[b..]);
        return;
    }
    let rows = rgba.chunks_exact_mut(w).zip(eye_depth.chunks_exact_mut(w));
    for (k, (rgba, eye)) in rows.enumerate() {
        let y = whole.y0 + k as i32;
        let (x0, x1) = if (touched.y0..touched.y1).contains(&y) {
            (touched.x0 as usize, touched.x1 as usize)
        } else {
            (0, 0)
        };
        let at = k * w;
        resolve_band(
            r,
            &px[at + x0..at + x1],
            &mut rgba[x0..x1],
            &mut eye[x0..x1],
        );
        background(&mut rgba[..x0], &mut eye[..x0]);
        background(&mut rgba[x1..], &mut eye[x1..]);
    }
}

/// Shades every pixel `px` of a band into its rows of the image: colour
/// into `rgba`, linear eye depth into `eye_depth` (`f32::INFINITY`
/// where empty). Why the image's own rows: no band copy to gather, and
/// the image's first touch happens on the pool (callgrind and
/// `--bench`: the serial gather was ~1.3 ms of a 13.5 ms frame).
#[inline(always)]
pub(crate) fn resolve_band(
    r: &Resolve<'_>,
    px: &[Sample],
    rgba: &mut [[u8; 4]],
    eye_depth: &mut [f32],
) {
    debug_assert!(rgba.len() == px.len() && eye_depth.len() == px.len());
    if r.shading != Shading::Gouraud {
        resolve_phong(r, px, rgba, eye_depth);
        return;
    }
    let scale = (r.far - r.near) / Z_FAR as f32;
    // Why zipped slices: one length check per band instead of five
    // bounds checks per pixel (callgrind, `profile_sphere 500 1`).
    let pixels = px.iter().zip(rgba.iter_mut().zip(eye_depth.iter_mut()));
    for (s, (rgba, eye)) in pixels {
        let (z, w0, w2) = (s.depth, s.w0(), s.w2());
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

/// [`resolve_band`] for Phong and flat: the band in groups of four pixels,
/// or eight with AVX2 ([`resolve_phong_pixels`]).
#[inline(always)]
fn resolve_phong(r: &Resolve<'_>, px: &[Sample], rgba: &mut [[u8; 4]], eye_depth: &mut [f32]) {
    // The default shininess, 32, is five squarings (see
    // [`Material::shade4_with`]).
    // And the mapping of coarse-geometry items only when the frame has
    // some (see `PhongItem::corner`; never flat).
    // Why calls rather than a function pointer: inlined, they run with the
    // caller's instruction set (`crate::isa`).
    let flat = r.shading == Shading::Flat;
    match (r.material.squarings() == 5, r.phong.shifted, flat) {
        (true, false, false) => resolve_phong_pixels::<5, false, false>(r, px, rgba, eye_depth),
        (true, true, _) => resolve_phong_pixels::<5, true, false>(r, px, rgba, eye_depth),
        (false, false, false) => {
            resolve_phong_pixels::<ANY_POWER, false, false>(r, px, rgba, eye_depth)
        }
        (false, true, _) => resolve_phong_pixels::<ANY_POWER, true, false>(r, px, rgba, eye_depth),
        (true, false, true) => resolve_phong_pixels::<5, false, true>(r, px, rgba, eye_depth),
        (false, false, true) => {
            resolve_phong_pixels::<ANY_POWER, false, true>(r, px, rgba, eye_depth)
        }
    }
}

/// Resolves the Phong pixels `px` into `rgba` and `eye_depth`, four
/// neighbours at a time: their eye depths, their normals and albedos
/// interpolated straight into lanes ([`phong_lane`]), shaded together
/// ([`Material::shade4_with`], bit-identical to shading them one by one; tested
/// against `phong_reference`), the background where a lane is empty.
/// Why groups of neighbours rather than a queue of covered pixels: the
/// queue's round trip through memory, its indices and scattered stores
/// were ~50 of the ~150 instructions per covered pixel, and groups only
/// waste lanes on silhouette edges (callgrind, `profile_sphere 500 1`).
/// Inlined so that it runs with the band's instruction set
/// ([`crate::isa`]).
/// With `FLAT`, a group that is not four patch samples is resolved pixel
/// by pixel ([`resolve_flat_group`]). With AVX2 (`r.isa`), groups of
/// eight ([`resolve_phong_wide`]).
#[inline(always)]
fn resolve_phong_pixels<const SQUARINGS: u32, const SHIFTED: bool, const FLAT: bool>(
    r: &Resolve<'_>,
    px: &[Sample],
    rgba: &mut [[u8; 4]],
    eye_depth: &mut [f32],
) {
    #[cfg(target_arch = "x86_64")]
    if let Isa::V3(simd) = r.isa {
        return resolve_phong_wide::<SQUARINGS, SHIFTED, FLAT>(simd, r, px, rgba, eye_depth);
    }
    resolve_phong_fours::<SQUARINGS, SHIFTED, FLAT>(r, px, rgba, eye_depth);
}

/// [`resolve_phong_pixels`] four pixels at a time.
#[inline(always)]
fn resolve_phong_fours<const SQUARINGS: u32, const SHIFTED: bool, const FLAT: bool>(
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
        resolve_any_group::<SQUARINGS, SHIFTED, FLAT>(r, s, rgba, eye);
    }
    // The last pixels of a band whose size is not a multiple of four,
    // padded with empty pixels.
    let done = px.len() / 4 * 4;
    if done < px.len() {
        let n = px.len() - done;
        let mut s = [Sample::EMPTY; 4];
        s[..n].copy_from_slice(&px[done..]);
        let (mut c, mut e) = ([[0u8; 4]; 4], [0f32; 4]);
        resolve_any_group::<SQUARINGS, SHIFTED, FLAT>(r, &s, &mut c, &mut e);
        rgba[done..].copy_from_slice(&c[..n]);
        eye_depth[done..].copy_from_slice(&e[..n]);
    }
}

/// [`resolve_phong_pixels`] with AVX2: eight neighbours at a time where
/// they take a fast path ([`wide_group`]), any other group of eight as
/// two of four, the pixels after the last whole group of eight four at a
/// time ([`resolve_phong_fours`]).
/// Why eight: the shading, packing and transposes take one AVX
/// instruction for eight lanes where the four-lane path takes one for
/// four. Inlined so that it runs with the band's instruction set.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn resolve_phong_wide<const SQUARINGS: u32, const SHIFTED: bool, const FLAT: bool>(
    simd: pulp::x86::V3,
    r: &Resolve<'_>,
    px: &[Sample],
    rgba: &mut [[u8; 4]],
    eye_depth: &mut [f32],
) {
    let groups = px
        .chunks_exact(8)
        .zip(rgba.chunks_exact_mut(8).zip(eye_depth.chunks_exact_mut(8)));
    for (s, (rgba, eye)) in groups {
        let s: &[Sample; 8] = s.try_into().expect("groups of eight");
        let rgba: &mut [[u8; 4]; 8] = rgba.try_into().expect("groups of eight");
        let eye: &mut [f32; 8] = eye.try_into().expect("groups of eight");
        // A flat frame's patch samples take Phong's unshifted path (see
        // `resolve_flat_group`).
        let wide = match FLAT {
            true => wide_group::<SQUARINGS, false>(simd, r, s, rgba, eye),
            false => wide_group::<SQUARINGS, SHIFTED>(simd, r, s, rgba, eye),
        };
        if !wide {
            let (s0, s1) = s.split_at(4);
            let (c0, c1) = rgba.split_at_mut(4);
            let (e0, e1) = eye.split_at_mut(4);
            let four = "halves of four";
            let (s0, c0, e0) = (s0.try_into().expect(four), c0.try_into(), e0.try_into());
            resolve_any_group::<SQUARINGS, SHIFTED, FLAT>(r, s0, c0.expect(four), e0.expect(four));
            let (s1, c1, e1) = (s1.try_into().expect(four), c1.try_into(), e1.try_into());
            resolve_any_group::<SQUARINGS, SHIFTED, FLAT>(r, s1, c1.expect(four), e1.expect(four));
        }
    }
    let done = px.len() / 8 * 8;
    resolve_phong_fours::<SQUARINGS, SHIFTED, FLAT>(
        r,
        &px[done..],
        &mut rgba[done..],
        &mut eye_depth[done..],
    );
}

/// [`resolve_flat_group`] when `FLAT`, else [`resolve_group`].
#[inline(always)]
fn resolve_any_group<const SQUARINGS: u32, const SHIFTED: bool, const FLAT: bool>(
    r: &Resolve<'_>,
    s: &[Sample; 4],
    rgba: &mut [[u8; 4]; 4],
    eye: &mut [f32; 4],
) {
    match FLAT {
        true => resolve_flat_group::<SQUARINGS>(r, s, rgba, eye),
        false => resolve_group::<SQUARINGS, SHIFTED>(r, s, rgba, eye),
    }
}

/// Resolves four neighbouring Phong pixels (see [`resolve_phong_pixels`]).
/// Why a fast path: nearly every group of the sphere is four covered patch
/// samples of items without colours, which need only their normals
/// interpolated (no albedo lanes, no per-lane choices); empty groups are
/// next, and the rest (silhouette edges, triangles, colours) goes through
/// [`resolve_general_group`] (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn resolve_group<const SQUARINGS: u32, const SHIFTED: bool>(
    r: &Resolve<'_>,
    s: &[Sample; 4],
    rgba: &mut [[u8; 4]; 4],
    eye: &mut [f32; 4],
) {
    // Only a sample that passed the depth test holds a patch sample's
    // flag, so four patch samples are four covered pixels.
    let patches = s[0].w2() & s[1].w2() & s[2].w2() & s[3].w2();
    if patches & PATCH_SAMPLE != 0 {
        debug_assert!(s.iter().all(|s| s.depth < Z_FAR));
        let items = &r.phong.items[..];
        let id = |k: usize| (s[k].w2() & !PATCH_SAMPLE) as usize;
        let last = id(0).max(id(1)).max(id(2).max(id(3)));
        assert!(last < items.len(), "item index");
        let it = [&items[id(0)], &items[id(1)], &items[id(2)], &items[id(3)]];
        let uncoloured =
            || it[0].frame & it[1].frame & it[2].frame & it[3].frame & BASE_ALBEDO != 0;
        if r.phong.uncoloured || uncoloured() {
            let sub = [s[0].w0(), s[1].w0(), s[2].w0(), s[3].w0()];
            *eye = eye_depths(r, s);
            let (weights, offsets) = (&r.phong.weights[..], &r.phong.offsets[..]);
            let normal = |k: usize| it[k].normal::<SHIFTED>(sub[k], weights, offsets);
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
            let view = rows([it[0].view, it[1].view, it[2].view, it[3].view]);
            let albedo = r.base_albedo.extend(0.0);
            let albedo = [albedo.x, albedo.y, albedo.z].map(Vec4::splat);
            let words = shade_lanes::<SQUARINGS>(r, normals, [light, half, view], |_| albedo);
            *rgba = words.map(u32::to_le_bytes);
            return;
        }
        let own = it[0].frame | it[1].frame | it[2].frame | it[3].frame;
        if own & BASE_ALBEDO == 0 && r.phong.grids.is_empty() {
            return resolve_coloured_group::<SQUARINGS, SHIFTED>(r, s, it, rgba, eye);
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

/// [`resolve_group`] for a flat frame: four patch samples as Phong's (the
/// items read their cells' normals with every weight on the first corner,
/// [`crate::shade::phong_items`]); any other group pixel by pixel, a patch
/// sample shaded alone (the same operations as a lane,
/// [`Material::shade`]), a triangle sample taking the colour it carries.
#[inline(always)]
fn resolve_flat_group<const SQUARINGS: u32>(
    r: &Resolve<'_>,
    s: &[Sample; 4],
    rgba: &mut [[u8; 4]; 4],
    eye: &mut [f32; 4],
) {
    if s[0].w2() & s[1].w2() & s[2].w2() & s[3].w2() & PATCH_SAMPLE != 0 {
        return resolve_group::<SQUARINGS, false>(r, s, rgba, eye);
    }
    let depths = eye_depths(r, s);
    for k in 0..4 {
        (rgba[k], eye[k]) = match (s[k].depth < Z_FAR, s[k].w2() & PATCH_SAMPLE != 0) {
            (false, _) => (r.background, f32::INFINITY),
            (true, true) => (flat_patch_sample(r, &s[k]), depths[k]),
            (true, false) => (s[k].w0().to_le_bytes(), depths[k]),
        };
    }
}

/// The flat colour of one patch sample: its cell's normal and first
/// corner's albedo ([`phong_lane`]) shaded in its item's frame.
#[inline(always)]
fn flat_patch_sample(r: &Resolve<'_>, s: &Sample) -> [u8; 4] {
    let lane = phong_lane(r.phong, s);
    let albedo = match lane.frame & BASE_ALBEDO {
        0 => Vec3::new(lane.normal_red.w, lane.green_blue.x, lane.green_blue.y),
        _ => r.base_albedo,
    };
    let [light, half, view] = r.phong.frames[(lane.frame & !BASE_ALBEDO) as usize];
    let frame = ShadeFrame {
        light: light.truncate(),
        half: half.truncate(),
        view: view.truncate(),
    };
    to_rgba8(r.material.shade(lane.normal_red.truncate(), &frame, albedo))
}

/// [`resolve_group`] for four covered patch samples whose items all have
/// their own albedos and no colour grid (a coloured scan's groups): the
/// general path's values without its per-lane choices. Why: the mannequin's
/// groups took [`resolve_general_group`], whose empty-lane picks, grid
/// lookups and per-lane albedo choices cost about as much as the shading.
#[inline(always)]
fn resolve_coloured_group<const SQUARINGS: u32, const SHIFTED: bool>(
    r: &Resolve<'_>,
    s: &[Sample; 4],
    it: [&PhongItem<'_>; 4],
    rgba: &mut [[u8; 4]; 4],
    eye: &mut [f32; 4],
) {
    *eye = eye_depths(r, s);
    let (weights, offsets) = (&r.phong.weights[..], &r.phong.offsets[..]);
    // Why spelled out: a closure per lane became an out-of-line call,
    // compiled without the band's instruction set (`crate::isa`).
    let g = [
        it[0].interpolate::<SHIFTED>(s[0].w0(), weights, offsets),
        it[1].interpolate::<SHIFTED>(s[1].w0(), weights, offsets),
        it[2].interpolate::<SHIFTED>(s[2].w0(), weights, offsets),
        it[3].interpolate::<SHIFTED>(s[3].w0(), weights, offsets),
    ];
    let normals = [
        g[0].normal_red,
        g[1].normal_red,
        g[2].normal_red,
        g[3].normal_red,
    ];
    let frames = [
        g[0].frame as usize,
        g[1].frame as usize,
        g[2].frame as usize,
        g[3].frame as usize,
    ];
    let green = Vec4::new(
        g[0].green_blue.x,
        g[1].green_blue.x,
        g[2].green_blue.x,
        g[3].green_blue.x,
    );
    let blue = Vec4::new(
        g[0].green_blue.y,
        g[1].green_blue.y,
        g[2].green_blue.y,
        g[3].green_blue.y,
    );
    let words = shade_normals::<SQUARINGS>(r, normals, frames, |red| [red, green, blue]);
    *rgba = words.map(u32::to_le_bytes);
}

/// The linear eye depths of four covered pixels, in lanes (the same
/// operations per lane as one at a time).
#[inline(always)]
fn eye_depths(r: &Resolve<'_>, s: &[Sample; 4]) -> [f32; 4] {
    let scale = (r.far - r.near) / Z_FAR as f32;
    let depth = Vec4::new(
        s[0].depth as f32,
        s[1].depth as f32,
        s[2].depth as f32,
        s[3].depth as f32,
    );
    (Vec4::splat(r.near) + depth * scale).to_array()
}

/// [`resolve_group`] for any group with a covered pixel: lanes with their
/// own albedos, triangle samples, empty pixels (which take the inputs of a
/// covered one, then the background).
#[inline(always)]
fn resolve_general_group(
    r: &Resolve<'_>,
    s: &[Sample; 4],
    rgba: &mut [[u8; 4]; 4],
    eye: &mut [f32; 4],
) {
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
    let words = shade_normals::<ANY_POWER>(r, normals, frames, |red| own_albedo(r, &g, red));
    let depths = eye_depths(r, s);
    for k in 0..4 {
        (rgba[k], eye[k]) = if is(k) {
            (words[k].to_le_bytes(), depths[k])
        } else {
            (r.background, f32::INFINITY)
        };
    }
}

/// The shading inputs of a covered pixel: a patch sample's interpolated
/// normal and albedo, or a triangle sample's stored ones.
#[inline(always)]
fn phong_lane(t: &PhongItems<'_>, s: &Sample) -> Lane {
    if s.w2() & PATCH_SAMPLE != 0 {
        let i = (s.w2() & !PATCH_SAMPLE) as usize;
        let mut lane = t.items[i].interpolate::<true>(s.w0(), &t.weights, &t.offsets);
        if let Some(place) = t.grids.get(i).copied().flatten() {
            let a = place.albedo(s.w0());
            lane.normal_red.w = a.x;
            lane.green_blue = Vec2::new(a.y, a.z);
            lane.frame &= !BASE_ALBEDO;
        }
        return lane;
    }
    let albedo = unpack_rgb(s.w1);
    Lane {
        normal_red: unpack_normal(s.w0()).extend(albedo.x),
        green_blue: Vec2::new(albedo.y, albedo.z),
        frame: s.w2(),
    }
}

/// Shades four pixels into RGBA8 words: their normals (`xyz`, not unit;
/// `w` passed to `albedo`), shade frames and albedo lanes. Why splats: the
/// four often share their shade frame, so only the normals need
/// transposing (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn shade_normals<const SQUARINGS: u32>(
    r: &Resolve<'_>,
    normals: [Vec4; 4],
    f: [usize; 4],
    albedo: impl FnOnce(Vec4) -> [Vec4; 3],
) -> [u32; 4] {
    let frames = &r.phong.frames;
    let splat = |v: Vec4| [v.x, v.y, v.z].map(Vec4::splat);
    let vectors = if f[1] == f[0] && f[2] == f[0] && f[3] == f[0] {
        frames[f[0]].map(splat)
    } else {
        // Where patches overlap (60 % of the sphere's groups): transposes.
        let e = f.map(|i| frames[i]);
        let rows = |k: usize| {
            let t = Mat4::from_cols(e[0][k], e[1][k], e[2][k], e[3][k]).transpose();
            [t.x_axis, t.y_axis, t.z_axis]
        };
        [rows(0), rows(1), rows(2)]
    };
    shade_lanes::<SQUARINGS>(r, normals, vectors, albedo)
}

/// Shades four pixels into RGBA8 words: their normals (`xyz`, not unit;
/// `w` passed to `albedo`), the lanes of their light and half vectors
/// and directions to the eye, and their albedo lanes.
#[inline(always)]
fn shade_lanes<const SQUARINGS: u32>(
    r: &Resolve<'_>,
    normals: [Vec4; 4],
    [light, half, view]: [[Vec4; 3]; 3],
    albedo: impl FnOnce(Vec4) -> [Vec4; 3],
) -> [u32; 4] {
    let t = Mat4::from_cols(normals[0], normals[1], normals[2], normals[3]).transpose();
    let lanes = Lanes {
        normal: [t.x_axis, t.y_axis, t.z_axis],
        light,
        half,
        view,
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

/// The first four attribute words of a node as floats.
#[inline(always)]
fn attr4(n: &NodeAttributes) -> Vec4 {
    Vec4::new(
        attr_to_f32f(n[0]),
        attr_to_f32f(n[1]),
        attr_to_f32f(n[2]),
        attr_to_f32f(n[3]),
    )
}

/// The cell of a patch sample: its item, its four corner nodes'
/// attributes and the bilinear weights of its sub-node.
#[inline(always)]
fn sample_cell<'r>(
    r: &Resolve<'r>,
    item: u32,
    sub: u32,
) -> (&'r Item, [&'r NodeAttributes; 4], [f32; 4]) {
    let (c, i) = r.items[item as usize];
    let chunk = &r.chunks[c as usize];
    let item = &chunk.items[i as usize];
    let cols = item.cols as usize;
    let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
    let k = item.first as usize + cj * cols + ci;
    // One slice for the four corners: a single bounds check.
    let quad = &chunk.node_attributes[k..k + cols + 2];
    let w = sub_node_weights(
        (sub >> 8) & 0xff,
        sub & 0xff,
        item.nu as u32,
        item.nv as u32,
    );
    (item, [&quad[0], &quad[1], &quad[cols], &quad[cols + 1]], w)
}

/// The first four attribute words interpolated bilinearly. Why four
/// lanes at a time: the same products and sums in the same order as one
/// channel at a time (identical images), a quarter of the instructions
/// (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn lerp4(n: [&NodeAttributes; 4], w: [f32; 4]) -> Vec4 {
    attr4(n[0]) * w[0] + attr4(n[1]) * w[1] + attr4(n[2]) * w[2] + attr4(n[3]) * w[3]
}

/// Shades a patch sample with Gouraud colours: the colours of its cell's
/// corners interpolated at its sub-node (relit by the patch's colour grid
/// where it has one).
#[inline]
fn resolve_patch_sample(r: &Resolve<'_>, item: u32, sub: u32) -> [u8; 4] {
    let (item, n, w) = sample_cell(r, item, sub);
    let lit = lerp4(n, w).truncate();
    let colour = match grid_place(r.patches, item) {
        Some(place) => relight(
            lit,
            corner_albedo(&r.patches[item.frame as usize], item, sub, w),
            place.albedo(sub),
        ),
        None => lit,
    };
    to_rgba8(colour)
}

/// The Phong colour of a patch sample shaded alone, straight from the
/// prepared level: the bilinear weights of its sub-node, the corners'
/// normals and albedos (`base_albedo` for an item without colours) summed
/// in corner order, [`Material::shade`]. The reference the grouped resolve
/// pass is tested against.
#[cfg(test)]
pub(crate) fn phong_reference(
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
    let shift = item.shade_shift as usize;
    let (cols, shading) = if shift == 0 {
        (patch.level(m).cols, patch.shading(m))
    } else {
        ((patch.level(m).cols - 1) * 2 + 1, patch.fine_shading(m))
    };
    let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
    let (w, offset) = sub_node_place(
        (sub >> 8) & 0xff,
        sub & 0xff,
        item.nu as u32,
        item.nv as u32,
        shift as u32,
    );
    let (di, dj) = ((offset & 0xffff) as usize, (offset >> 16) as usize);
    let k =
        (((item.j0 as usize + cj) << shift) + dj) * cols + ((item.i0 as usize + ci) << shift) + di;
    let lerp = |at: &dyn Fn(usize) -> Vec4| {
        let corners = [k, k + 1, k + cols, k + cols + 1];
        let mut sum = at(corners[0]).truncate() * w[0];
        for (corner, weight) in corners.into_iter().zip(w).skip(1) {
            sum += at(corner).truncate() * weight;
        }
        sum
    };
    let albedo = if item.uniform_albedo {
        r.base_albedo
    } else {
        lerp(&|k| byte_lanes(shading.colours[k]))
    };
    let normal = lerp(&|k| shading.normals[k]);
    let c = r
        .material
        .shade(normal, &frames[item.frame as usize], albedo);
    to_rgba8(c)
}

#[inline(always)]
fn attr_to_f32f(v: i32) -> f32 {
    attr_from_bits(v)
}
