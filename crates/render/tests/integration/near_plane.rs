//! Near-plane handling: the camera inside the sphere, and the near plane
//! cutting patches, never draw geometry behind the eye and never panic.

use glam::DVec3;
use spatch_render::{Camera, Culling, RenderMode, RenderOptions, Renderer};

use crate::common::{prepared_sphere, RADIUS};

fn options(culling: Culling, mode: RenderMode) -> RenderOptions {
    let mut o = RenderOptions::default();
    o.culling = culling;
    o.mode = mode;
    o
}

#[test]
fn camera_at_the_centre_sees_the_inside_everywhere_at_the_right_depth() {
    let camera = Camera::look_at(
        DVec3::ZERO,
        DVec3::new(1.0, 0.2, 0.1),
        DVec3::Y,
        60.0,
        200,
        150,
    )
    .unwrap();
    for mode in [RenderMode::Patches, RenderMode::Triangles] {
        let out = Renderer::new(options(Culling::None, mode))
            .unwrap()
            .render(prepared_sphere(), &camera)
            .unwrap();
        let image = &out.image;
        assert_eq!(
            image.covered_count(),
            200 * 150,
            "{mode:?}: every pixel sees the sphere"
        );
        // Every surface seen is at the radius along its ray, so its eye depth
        // (along the view axis) is at most R and at least R·cos(half diagonal fov).
        for &d in image.depth() {
            assert!(
                d > 0.0 && (d as f64) <= RADIUS * 1.01,
                "{mode:?}: depth {d}"
            );
        }
    }
    // With back-face culling the whole sphere faces away: nothing is drawn.
    let out = Renderer::new(RenderOptions::default())
        .unwrap()
        .render(prepared_sphere(), &camera)
        .unwrap();
    assert_eq!(out.image.covered_count(), 0);
}

#[test]
fn near_plane_cutting_patches_splits_them_and_draws_only_what_is_in_front() {
    // The eye just outside the surface, looking along it: the near plane
    // cuts the patches under the eye.
    let eye = DVec3::new(0.0, RADIUS + 0.5, 0.0);
    let camera = Camera::look_at(
        eye,
        DVec3::new(60.0, RADIUS - 20.0, 0.0),
        DVec3::Y,
        70.0,
        240,
        180,
    )
    .unwrap()
    .with_clip_planes(Some(0.2), Some(400.0))
    .unwrap();
    for mode in [RenderMode::Patches, RenderMode::Triangles] {
        let out = Renderer::new(options(Culling::Back, mode))
            .unwrap()
            .render(prepared_sphere(), &camera)
            .unwrap();
        let s = &out.stats;
        if mode == RenderMode::Patches {
            assert!(s.patches_split > 0 && s.clipped_cells > 0, "{s:?}");
        }
        assert!(s.triangles_clipped > 0, "{mode:?}: {s:?}");
        let image = &out.image;
        assert!(image.covered_count() > 240 * 180 / 4);
        for &d in image.depth() {
            if d.is_finite() {
                assert!(
                    (0.2 * 0.999..=400.0 * 1.001).contains(&d),
                    "{mode:?}: depth {d} outside [near, far]"
                );
            }
        }
        // Looking down-forward from just above the surface: the bottom row
        // is ground, close by.
        assert!(
            (0..240).all(|x| image.is_covered(x, 179)),
            "{mode:?}: hole at the bottom"
        );
    }
}

#[test]
fn looking_away_from_the_sphere_draws_nothing() {
    let eye = DVec3::new(0.0, 0.0, 300.0);
    let camera = Camera::look_at(eye, DVec3::new(0.0, 0.0, 400.0), DVec3::Y, 90.0, 64, 64).unwrap();
    for mode in [RenderMode::Patches, RenderMode::Triangles] {
        let out = Renderer::new(options(Culling::None, mode))
            .unwrap()
            .render(prepared_sphere(), &camera)
            .unwrap();
        assert_eq!(out.image.covered_count(), 0, "{mode:?}");
    }
}
