//! The Phong resolve of the AVX2 copy of the band kernels ([`crate::isa`]):
//! eight neighbouring pixels at a time in eight-lane registers ([`F8`])
//! where they are eight covered patch samples of items without colours,
//! or of items with their own albedos and no colour grid (the two fast
//! paths of `resolve::resolve_group`; the caller resolves any other group
//! of eight as two groups of four). Every lane performs the operations of
//! the four-lane path, so the image is the same bit for bit (tested).
//!
//! Cost: O(pixels) per band, as the four-lane resolve.

use glam::Vec4;
use pulp::x86::V3;

use crate::lighting::Lanes8;
#[cfg(doc)]
use crate::lighting::Material;
use crate::raster::band::{Sample, PATCH_SAMPLE};
use crate::shade::phong_items::{PhongItem, BASE_ALBEDO};
use crate::shade::resolve_inputs::Resolve;
use crate::wide::{pack_rgba8, transpose8_xyz, F8};

/// Resolves eight neighbouring pixels if they take one of the fast paths
/// of `resolve_group` (the same choices, for all eight): eight covered
/// patch samples of items without colours (or of a frame without any),
/// or of items with their own albedos and no colour grid. False, and
/// nothing written, for any other group.
#[inline(always)]
pub(crate) fn wide_group<const SQUARINGS: u32, const SHIFTED: bool>(
    simd: V3,
    r: &Resolve<'_>,
    s: &[Sample; 8],
    rgba: &mut [[u8; 4]; 8],
    eye: &mut [f32; 8],
) -> bool {
    // Only a sample that passed the depth test holds a patch sample's
    // flag, so eight patch samples are eight covered pixels.
    let w2 = |k: usize| s[k].w2() & s[k + 4].w2();
    if w2(0) & w2(1) & w2(2) & w2(3) & PATCH_SAMPLE == 0 {
        return false;
    }
    let items = &r.phong.items[..];
    let id = |k: usize| (s[k].w2() & !PATCH_SAMPLE) as usize;
    let most = |k: usize| id(k).max(id(k + 4));
    let last = most(0).max(most(1)).max(most(2).max(most(3)));
    assert!(last < items.len(), "item index");
    let it = [
        &items[id(0)],
        &items[id(1)],
        &items[id(2)],
        &items[id(3)],
        &items[id(4)],
        &items[id(5)],
        &items[id(6)],
        &items[id(7)],
    ];
    let both = |k: usize| it[k].frame & it[k + 4].frame;
    if r.phong.uncoloured || both(0) & both(1) & both(2) & both(3) & BASE_ALBEDO != 0 {
        shade_group::<SQUARINGS, SHIFTED, false>(simd, r, s, &it, rgba, eye);
        return true;
    }
    let either = |k: usize| it[k].frame | it[k + 4].frame;
    let own = either(0) | either(1) | either(2) | either(3);
    if own & BASE_ALBEDO == 0 && r.phong.grids.is_empty() {
        shade_group::<SQUARINGS, SHIFTED, true>(simd, r, s, &it, rgba, eye);
        return true;
    }
    false
}

/// Shades eight covered patch samples of the items `it`: their normals
/// (and with `COLOURED` their albedos, else the base albedo) interpolated
/// per pixel as the four-lane path does ([`interpolate8`]), transposed
/// into lanes, with their items' shade frames
/// ([`Material::shade8_with`]). Why a copy for eight pixels of one item
/// (within a patch, away from overlaps): the item's fields are read once
/// and its frame splat, where eight items take three transposes.
#[inline(always)]
fn shade_group<const SQUARINGS: u32, const SHIFTED: bool, const COLOURED: bool>(
    simd: V3,
    r: &Resolve<'_>,
    s: &[Sample; 8],
    it: &[&PhongItem<'_>; 8],
    rgba: &mut [[u8; 4]; 8],
    eye: &mut [f32; 8],
) {
    *eye = eye_depths8(simd, r, s);
    let other = |k: usize| s[k].w2() ^ s[0].w2();
    let same = other(1) | other(2) | other(3) | other(4) | other(5) | other(6) | other(7) == 0;
    let ((normals, colours), [light, half, view]) = if same {
        let one = it[0];
        let splat = |v: Vec4| [v.x, v.y, v.z].map(|c| F8::splat(simd, c));
        let frame = [splat(one.light), splat(one.half), splat(one.view)];
        (interpolate8::<SHIFTED, COLOURED>(r, s, &[one; 8]), frame)
    } else {
        // The items' frame vectors, one lane per pixel.
        macro_rules! lanes {
            ($v:ident) => {
                transpose8_xyz(
                    simd,
                    &[
                        it[0].$v, it[1].$v, it[2].$v, it[3].$v, it[4].$v, it[5].$v, it[6].$v,
                        it[7].$v,
                    ],
                )
            };
        }
        let frame = [lanes!(light), lanes!(half), lanes!(view)];
        (interpolate8::<SHIFTED, COLOURED>(r, s, it), frame)
    };
    let albedo = if COLOURED {
        transpose8_xyz(simd, &colours)
    } else {
        let a = r.base_albedo;
        [
            F8::splat(simd, a.x),
            F8::splat(simd, a.y),
            F8::splat(simd, a.z),
        ]
    };
    let lanes = Lanes8 {
        simd,
        normal: transpose8_xyz(simd, &normals),
        light,
        half,
        view,
        albedo,
    };
    *rgba = pack_rgba8(simd, r.material.shade8_with::<SQUARINGS>(&lanes));
}

/// The normals and (with `COLOURED`, else zero) albedos of eight patch
/// samples of the items `it`, each interpolated alone.
#[inline(always)]
fn interpolate8<const SHIFTED: bool, const COLOURED: bool>(
    r: &Resolve<'_>,
    s: &[Sample; 8],
    it: &[&PhongItem<'_>; 8],
) -> ([Vec4; 8], [Vec4; 8]) {
    let (weights, offsets) = (&r.phong.weights[..], &r.phong.offsets[..]);
    let (mut normals, mut colours) = ([Vec4::ZERO; 8], [Vec4::ZERO; 8]);
    // Why spelled out rather than a loop or a closure per lane: the loop
    // stayed a loop (its counter and a round trip through memory per
    // pixel), and a closure became an out-of-line call compiled without
    // the band's instruction set.
    macro_rules! pixels {
        ($($k:literal)*) => {
            $(if COLOURED {
                (normals[$k], colours[$k]) =
                    it[$k].normal_colour::<SHIFTED>(s[$k].w0(), weights, offsets);
            } else {
                normals[$k] = it[$k].normal::<SHIFTED>(s[$k].w0(), weights, offsets);
            })*
        };
    }
    pixels!(0 1 2 3 4 5 6 7);
    (normals, colours)
}

/// The linear eye depths of eight covered pixels, in lanes (the same
/// operations per lane as `eye_depths`).
#[inline(always)]
fn eye_depths8(simd: V3, r: &Resolve<'_>, s: &[Sample; 8]) -> [f32; 8] {
    let scale = (r.far - r.near) / crate::fixed::Z_FAR as f32;
    let d = |k: usize| s[k].depth;
    let depth = F8::from_ints(simd, [d(0), d(1), d(2), d(3), d(4), d(5), d(6), d(7)]);
    (F8::splat(simd, r.near) + depth * F8::splat(simd, scale)).to_array()
}
