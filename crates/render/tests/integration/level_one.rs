//! Level 1 past the mip limit (`RenderOptions::level_one_limit`): a patch
//! with an irregular outline drawn at level 1 keeps the outline level 0
//! draws, because level 1 draws its outline cells by the level-0 cells
//! they hold; off by default. Which patches lift: the geometric bounds
//! and the shading.

use glam::{DVec3, Vec3};
use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene, EMPTY};
use spatch_render::{PreparedScene, RenderOptions, RenderOutput, Renderer, Shading};

use crate::common::{known_camera, known_eye_direction};

/// Nodes per side of the test patch.
const SIDE: u32 = 33;

/// One patch of `side × side` nodes `spacing` apart facing the known
/// camera, centred on the origin, node `(x, y)` (from the centre) at
/// displacement `d(x, y)`.
fn facing_patch(side: u32, spacing: f32, d: impl Fn(f32, f32) -> u16) -> Scene {
    facing_patch_coloured(side, spacing, d, None)
}

/// [`facing_patch`] with node colours `colour(i)` by node column `i`.
fn facing_patch_coloured(
    side: u32,
    spacing: f32,
    d: impl Fn(f32, f32) -> u16,
    colour: Option<fn(u32) -> [u8; 4]>,
) -> Scene {
    let (view, ax) = view_axes();
    let ay = view.cross(ax);
    let c = (side - 1) as f32 / 2.0;
    let origin = -(ax + ay) * c * spacing;
    let d = (0..side * side)
        .map(|k| d((k % side) as f32 - c, (k / side) as f32 - c))
        .collect();
    let colours = colour.map(|c| (0..side * side).map(|k| c(k % side)).collect());
    let axes = [ax * spacing, ay * spacing, view * 0.01];
    one_patch(origin, axes, side, d, colours)
}

/// A flat patch of `side × side` nodes `spacing` apart turned 45° from
/// the known camera about its rows, so that displacements move its nodes
/// on screen, at displacement `d(i, j)` for node column `i` and row `j`
/// (0.01 units a code; the origin sits 2000 codes behind the centre).
fn slanted_patch(side: u32, spacing: f32, d: impl Fn(u32, u32) -> u16) -> Scene {
    let (view, side_axis) = view_axes();
    let (u, v) = ((side_axis - view).normalize(), view.cross(side_axis));
    let normal = (view + side_axis).normalize();
    let c = (side - 1) as f32 / 2.0;
    let origin = -(u + v) * c * spacing - normal * 20.0;
    let d = (0..side * side).map(|k| d(k % side, k / side)).collect();
    let axes = [u * spacing, v * spacing, normal * 0.01];
    one_patch(origin, axes, side, d, None)
}

/// The known camera's direction from the origin to the eye, and a unit
/// axis across it (level, at right angles to it and to `Y`).
fn view_axes() -> (Vec3, Vec3) {
    let view = known_eye_direction().as_vec3();
    (view, view.cross(Vec3::Y).normalize())
}

/// A scene of one `side × side` patch with frame `origin` and `axes`,
/// displacements `d` and node `colours` (RGB when given).
fn one_patch(
    origin: Vec3,
    axes: [Vec3; 3],
    side: u32,
    d: Vec<u16>,
    colours: Option<Vec<[u8; 4]>>,
) -> Scene {
    let frame = Frame::new(origin, axes[0], axes[1], axes[2]).unwrap();
    let channel = match colours {
        Some(_) => ColourChannel::Rgb8,
        None => ColourChannel::None,
    };
    let grid = GridSize::new(side, side).unwrap();
    let patch = Patch::new(frame, grid, d, colours).unwrap();
    Scene::new(DVec3::ZERO, channel, vec![patch]).unwrap()
}

/// A shallow bowl of `SIDE × SIDE` nodes `spacing` apart, filled inside a
/// wavy disc (radius 12 ± 3 nodes, five lobes), so that its outline
/// crosses level-1 cells in every way.
fn wavy_disc(spacing: f32) -> Scene {
    facing_patch(SIDE, spacing, |x, y| {
        let r = x.hypot(y);
        let edge = 12.0 + 3.0 * (5.0 * y.atan2(x)).sin();
        if r <= edge {
            (2000.0 + 3.0 * r * r) as u16
        } else {
            EMPTY
        }
    })
}

/// Pixels covered by `a` and not `b`.
fn covered_only_by(a: &RenderOutput, b: &RenderOutput) -> usize {
    let (w, h) = (a.image.width(), a.image.height());
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| a.image.is_covered(x, y) && !b.image.is_covered(x, y))
        .count()
}

fn draw(prepared: &PreparedScene, level_one_limit: f32) -> RenderOutput {
    draw_shaded(prepared, level_one_limit, Shading::Phong)
}

fn draw_shaded(prepared: &PreparedScene, level_one_limit: f32, shading: Shading) -> RenderOutput {
    let mut o = RenderOptions::default();
    o.level_one_limit = level_one_limit;
    o.shading = shading;
    Renderer::new(o)
        .unwrap()
        .render(prepared, &known_camera(600.0, 500))
        .unwrap()
}

#[test]
fn level_one_past_the_limit_keeps_level_zeros_outline() {
    // Level-0 cells of about 2 px: the mip limit (3 px) keeps level 0,
    // a level-one limit of 6 px takes level 1.
    let prepared = PreparedScene::new(&wavy_disc(1.3));
    let (zero, one) = (draw(&prepared, 0.0), draw(&prepared, 6.0));
    assert_eq!(zero.stats.mip_levels, vec![1]);
    assert_eq!(one.stats.mip_levels, vec![0, 1]);
    let (lost, gained) = (covered_only_by(&zero, &one), covered_only_by(&one, &zero));
    let covered = zero.image.covered_count();
    assert!(covered > 1000, "{covered} pixels covered");
    // The outline is about 2π · 12 nodes · 2 px ≈ 150 px long. Without
    // the cells by quarters level 1 loses 134 pixels along it; with them
    // none, and it reaches past it by under half a pixel on average (62
    // pixels: a quarter's sub-nodes reach half a sub-cell past it).
    assert!(
        lost <= 4 && gained <= 80,
        "lost {lost}, gained {gained} of {covered}"
    );
}

#[test]
fn a_patch_drawn_by_quarters_alone_is_drawn() {
    // 3 × 3 nodes with an edge's middle node empty: level 0 draws two of
    // its four cells, level 1 its one cell by those two quarters only.
    let scene = facing_patch(
        3,
        1.3,
        |x, y| if (x, y) == (0.0, -1.0) { EMPTY } else { 2000 },
    );
    let prepared = PreparedScene::new(&scene);
    let (zero, one) = (draw(&prepared, 0.0), draw(&prepared, 6.0));
    assert_eq!(one.stats.mip_levels, vec![0, 1]);
    let covered = zero.image.covered_count();
    assert!(covered >= 4, "{covered}");
    assert!(
        covered_only_by(&zero, &one) <= 1,
        "level 1 lost level 0's pixels"
    );
    assert!(
        covered_only_by(&one, &zero) <= covered,
        "level 1 drew past them"
    );
}

#[test]
fn a_lifted_patch_with_colours_keeps_level_zeros_colours() {
    // Node columns alternately red and blue: level 1's colours, averaged
    // over twice the span, would be purple; the lifted patch is shaded from
    // level 0, so its pixels keep level 0's colours.
    let stripes: fn(u32) -> [u8; 4] = |i| match i % 2 {
        0 => [255, 0, 0, 255],
        _ => [0, 0, 255, 255],
    };
    let scene = facing_patch_coloured(SIDE, 1.3, |_, _| 2000, Some(stripes));
    let prepared = PreparedScene::new(&scene);
    let (zero, one) = (draw(&prepared, 0.0), draw(&prepared, 6.0));
    assert_eq!(one.stats.mip_levels, vec![0, 1]);
    let redness = |o: &RenderOutput| {
        let p = o.image.pixels();
        let covered = p.iter().filter(|c| c[3] > 0);
        covered
            .map(|c| (c[0] as i32 - c[2] as i32).abs())
            .sum::<i32>() as f64
            / o.image.covered_count() as f64
    };
    let (a, b) = (redness(&zero), redness(&one));
    assert!(
        a > 60.0 && (a - b).abs() < 0.1 * a,
        "level 0 {a}, lifted {b}"
    );
    // Flat and Gouraud shading interpolate the drawn level's colours, so
    // under them the patch keeps level 0 and its image.
    for shading in [Shading::Flat, Shading::Gouraud] {
        let (zero, six) = (
            draw_shaded(&prepared, 0.0, shading),
            draw_shaded(&prepared, 6.0, shading),
        );
        assert_eq!(six.stats.mip_levels, vec![1], "{shading:?}");
        assert!(six.image.pixels() == zero.image.pixels(), "{shading:?}");
    }
}

#[test]
fn a_ridge_level_one_cuts_off_keeps_level_zero_and_a_spike_does_not() {
    // One node column (6 % of the nodes) raised by 75 codes, about 0.7 px
    // on screen: level 1, which skips that column, would cut the ridge
    // off, so the patch keeps level 0, although the root mean square move
    // (about 0.17 px) is within bounds. One raised node moves the surface
    // as far but is scan noise to the test (under 2 % of the nodes): the
    // patch lifts.
    // (A corner node empty, as along a scan's outline: a full grid's levels
    // would go past the limit by the mip tolerance first.)
    let with_corner = |d: u16, i: u32, j: u32| if (i, j) == (0, 0) { EMPTY } else { d };
    let ridge = move |i: u32, j| with_corner(if i == 7 { 2075 } else { 2000 }, i, j);
    let spike = move |i: u32, j: u32| with_corner(if (i, j) == (7, 7) { 2075 } else { 2000 }, i, j);
    let flat = move |i, j| with_corner(2000, i, j);
    let levels = |scene: Scene| draw(&PreparedScene::new(&scene), 6.0).stats.mip_levels;
    assert_eq!(levels(slanted_patch(17, 1.2, flat)), vec![0, 1]);
    assert_eq!(levels(slanted_patch(17, 1.2, spike)), vec![0, 1]);
    assert_eq!(levels(slanted_patch(17, 1.2, ridge)), vec![1]);
}

#[test]
fn a_level_one_limit_out_of_range_is_refused() {
    for bad in [-1.0, 0.05, 17.0, f32::NAN] {
        let mut o = RenderOptions::default();
        o.level_one_limit = bad;
        assert!(Renderer::new(o).is_err(), "{bad}");
    }
}
