//! Small scenes shared by the tests.

use glam::{DVec3, Quat, Vec3};
use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene, EMPTY};

/// The scene of `testdata/format/v1_minimal.spatch` (see docs/format.md).
pub(crate) fn minimal_scene() -> Scene {
    let frame = Frame::new(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(0.0, 0.0, 0.25),
    )
    .unwrap();
    let grid = GridSize::new(3, 2).unwrap();
    let displacements = vec![0, 1, 2, 3, EMPTY, 5];
    let colours = vec![
        [255, 0, 0, 255],
        [0, 255, 0, 255],
        [0, 0, 255, 255],
        [255, 255, 255, 255],
        [0, 0, 0, 0],
        [16, 32, 48, 255],
    ];
    let patch = Patch::new(frame, grid, displacements, Some(colours)).unwrap();
    Scene::new(DVec3::new(10.0, 0.0, 0.0), ColourChannel::Rgb8, vec![patch]).unwrap()
}

/// A scene with several patches, grids, widths and a far offset, with or
/// without colour.
pub(crate) fn mixed_scene(channel: ColourChannel) -> Scene {
    let mut patches = Vec::new();
    for k in 0..5u16 {
        let rotation = Quat::from_rotation_y(0.3 * f32::from(k)) * Quat::from_rotation_x(0.7);
        let frame = Frame::new(
            Vec3::splat(f32::from(k)),
            rotation * Vec3::X * 0.1,
            rotation * Vec3::Y * 0.1,
            rotation * Vec3::Z * 0.001,
        )
        .unwrap();
        let grid = GridSize::new(2 + u32::from(k) * 3, 17).unwrap();
        let n = grid.node_count();
        let displacements: Vec<u16> = (0..n)
            .map(|i| {
                let i = i as u16;
                if i % 7 == 3 {
                    EMPTY
                } else if k == 2 {
                    i * 300 // 16-bit patch
                } else {
                    (i * 5) % 255
                }
            })
            .collect();
        let colours = (channel != ColourChannel::None).then(|| {
            (0..n)
                .map(|i| [i as u8, (i * 3) as u8, k as u8, (i * 7) as u8])
                .collect()
        });
        patches.push(Patch::new(frame, grid, displacements, colours).unwrap());
    }
    Scene::new(DVec3::new(1e6, -2e6, 0.5), channel, patches).unwrap()
}
