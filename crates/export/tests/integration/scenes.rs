//! Scenes shared by the tests.

use glam::{DVec3, Vec3};
use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene, EMPTY};
use spatch_sphere::{build_sphere, SphereOptions};

/// A 200-patch sphere of radius 128 (no colour).
pub(crate) fn sphere() -> Scene {
    let mut options = SphereOptions::default();
    options.patches = 200;
    options.grid = 9;
    build_sphere(&options).unwrap().scene
}

/// Two coloured 4 × 3 patches, one node empty, offset `offset`; `alpha`
/// sets the alpha of every node (RGBA when below 255).
pub(crate) fn coloured(offset: DVec3, alpha: u8) -> Scene {
    let patches = (0..2)
        .map(|k| {
            let frame = Frame::new(
                Vec3::new(k as f32 * 5.0, 0.0, 0.0),
                Vec3::X,
                Vec3::Y,
                Vec3::Z * 0.01,
            )
            .unwrap();
            let grid = GridSize::new(4, 3).unwrap();
            let mut d: Vec<u16> = (0..12).map(|i| i * 10).collect();
            d[11] = EMPTY;
            let colours = (0..12u8)
                .map(|i| [i * 20, 255 - i * 20, 128, alpha])
                .collect();
            Patch::new(frame, grid, d, Some(colours)).unwrap()
        })
        .collect();
    let channel = if alpha == 255 {
        ColourChannel::Rgb8
    } else {
        ColourChannel::Rgba8
    };
    Scene::new(offset, channel, patches).unwrap()
}

/// Model-space positions of every filled node, in scene order, in f64.
pub(crate) fn node_positions(scene: &Scene) -> Vec<DVec3> {
    scene
        .patches()
        .iter()
        .flat_map(|p| {
            p.filled_nodes()
                .map(move |(i, j, _)| scene.offset() + p.precise_node_position(i, j).unwrap())
        })
        .collect()
}

/// Diagonal of the box of `points`.
pub(crate) fn extent(points: &[DVec3]) -> f64 {
    let (lo, hi) = points
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    (hi - lo).length()
}
