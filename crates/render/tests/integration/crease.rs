//! A patch bent over a crease keeps its front lit (issue 21, item 3).
//!
//! One 9 × 5 patch: a flat half (`d = 0`) and a wall rising at 80° beyond
//! its middle column. Seen from the wall's back side, the wall's cells face
//! away and are culled, the flat half faces the eye, and the patch's normal
//! cone axis (between the two faces' normals) points away from the eye.
//! Lighting the whole patch two-sided from that axis lit the flat half
//! from behind (ambient only): the dark specks along fandisk's creases.
//! The flat half must be shaded as the same flat half alone.

use glam::{DVec3, Vec3};
use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};
use spatch_render::{Camera, Culling, PreparedScene, RenderOptions, RenderedImage, Renderer};

/// Columns of the flat half (nodes `0..=FLAT`); the wall rises beyond.
const FLAT: usize = 4;
/// Height step of the wall per column, in displacement codes of 0.01
/// (tan 80° ≈ 5.67 units per unit of x).
const RISE: u16 = 567;

/// The bent patch (`cols` = 9) or its flat half alone (`cols` = 5).
fn scene(cols: usize) -> Scene {
    let rows = 5;
    let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01).expect("frame");
    let d: Vec<u16> = (0..cols * rows)
        .map(|k| (k % cols).saturating_sub(FLAT) as u16 * RISE)
        .collect();
    let grid = GridSize::new(cols as u32, rows as u32).expect("grid");
    let patch = Patch::new(frame, grid, d, None).expect("patch");
    Scene::new(DVec3::ZERO, ColourChannel::None, vec![patch]).expect("scene")
}

/// The scene drawn with back-face culling from the wall's back side.
fn draw(scene: &Scene) -> RenderedImage {
    // Far enough that every cell is subdivided (cells too large for that,
    // or crossing the view's sides, go to the triangle path, which has no
    // per-cell back-face test).
    let target = DVec3::new(4.0, 2.0, 8.0);
    let eye = target + DVec3::new(1.0, 0.2, 0.5).normalize() * 60.0;
    let camera = Camera::look_at(eye, target, DVec3::Y, 30.0, 256, 256).expect("camera");
    let mut options = RenderOptions::default();
    options.culling = Culling::Back;
    options.threads = 1;
    let prepared = PreparedScene::new(scene);
    Renderer::new(options)
        .expect("renderer")
        .render(&prepared, &camera)
        .expect("frame")
        .image
}

fn grey(p: [u8; 4]) -> i32 {
    (p[0] as i32 + p[1] as i32 + p[2] as i32) / 3
}

#[test]
fn the_front_of_a_patch_bent_over_a_crease_is_lit_as_its_face_alone() {
    let (bent, flat) = (draw(&scene(9)), draw(&scene(FLAT + 1)));
    // The wall's cells face away and are culled: the bent patch covers
    // about what its flat half alone covers.
    let covered = |image: &RenderedImage| image.pixels().iter().filter(|p| p[3] > 0).count();
    let (cb, cf) = (covered(&bent), covered(&flat));
    assert!(
        cb < cf + cf / 4,
        "{cb} pixels against {cf}: the wall was drawn"
    );
    let (w, h) = (flat.width() as usize, flat.height() as usize);
    // Pixels of the flat half, two pixels inside its outline.
    let inside = |x: usize, y: usize| {
        (y.saturating_sub(2)..(y + 3).min(h)).all(|yy| {
            (x.saturating_sub(2)..(x + 3).min(w)).all(|xx| flat.pixels()[yy * w + xx][3] > 0)
        })
    };
    let mut diffs = Vec::new();
    for y in 2..h - 2 {
        for x in 2..w - 2 {
            if inside(x, y) {
                let (a, b) = (bent.pixels()[y * w + x], flat.pixels()[y * w + x]);
                assert!(
                    a[3] > 0,
                    "({x}, {y}): the bent patch leaves the flat half's pixel empty"
                );
                diffs.push((grey(a) - grey(b)).abs());
            }
        }
    }
    assert!(diffs.len() > 100, "{} pixels of the flat half", diffs.len());
    // The flat half alone is lit (not ambient only: 0.15 · 220 = 33).
    let lit = (0..w * h)
        .filter(|&k| flat.pixels()[k][3] > 0)
        .map(|k| grey(flat.pixels()[k]));
    let lit: Vec<i32> = lit.collect();
    let mean = lit.iter().sum::<i32>() / lit.len() as i32;
    assert!(mean > 80, "the flat half's mean grey {mean}");
    // The bent patch's flat half: the same shading, up to the cells next
    // to the crease (whose corner normals lean towards the wall).
    diffs.sort_unstable();
    let median = diffs[diffs.len() / 2];
    assert!(median <= 3, "median grey difference {median}");
}
