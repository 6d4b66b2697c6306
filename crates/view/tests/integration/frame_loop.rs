//! Scripted events through [`Viewer::apply`] and [`Viewer::frame`]: the
//! camera maths of orbit, axis views and reset, and frames equal to a
//! render of their printed flags.

use glam::DVec3;
use spatch_format::Scene;
use spatch_render::{Camera, RenderMode, RenderOptions, Renderer, Shading};
use spatch_sphere::{build_sphere, SphereOptions};
use spatch_view::{
    parse_script, Axis, Event, Orbit, Quality, Viewer, BACKGROUND, ORBIT_RADIANS_PER_PIXEL,
};

/// A small sphere of radius 10 (200 patches of 9 × 9).
fn sphere() -> Scene {
    let mut options = SphereOptions::default();
    options.radius = 10.0;
    options.patches = 200;
    options.grid = 9;
    options.step = 0.001;
    build_sphere(&options).unwrap().scene
}

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).length() <= tol
}

fn assert_orthonormal(o: &Orbit) {
    assert!((o.up.length() - 1.0).abs() < 1e-12, "{o:?}");
    assert!(o.up.dot(o.forward()).abs() < 1e-12, "{o:?}");
}

#[test]
fn ten_orbit_steps_of_a_tenth_turn_come_back_to_the_start() {
    let mut viewer = Viewer::new(&sphere(), 200, 160, 2).unwrap();
    let start = *viewer.orbit();
    let step = std::f64::consts::TAU / 10.0 / ORBIT_RADIANS_PER_PIXEL;
    let mut eyes = Vec::new();
    for _ in 0..10 {
        viewer.apply(Event::Orbit { dx: step, dy: 0.0 });
        let o = *viewer.orbit();
        assert_orthonormal(&o);
        assert!((o.distance() - start.distance()).abs() < 1e-9);
        assert_eq!(o.target, start.target);
        eyes.push(o.eye);
    }
    // Each step turns by 36° about the up axis; after ten, back home.
    let turned = (eyes[0] - start.target).angle_between(start.eye - start.target);
    assert!((turned.to_degrees() - 36.0).abs() < 1e-9, "{turned}");
    assert!(close(
        viewer.orbit().eye,
        start.eye,
        1e-9 * start.distance()
    ));
    assert!(close(viewer.orbit().up, start.up, 1e-9));
    // Dragging right moves the eye to the left of where it looked from.
    assert!((eyes[0] - start.eye).dot(start.right()) < 0.0);
}

#[test]
fn orbit_over_the_pole_keeps_a_valid_frame() {
    let mut viewer = Viewer::new(&sphere(), 200, 160, 2).unwrap();
    let quarter = std::f64::consts::FRAC_PI_2 / ORBIT_RADIANS_PER_PIXEL;
    viewer.apply(Event::View(Axis::PosZ));
    for _ in 0..3 {
        viewer.apply(Event::Orbit {
            dx: 0.0,
            dy: quarter,
        });
        assert_orthonormal(viewer.orbit());
    }
    // Three quarter turns down from +z: the eye went over -y... to +y.
    let dir = (viewer.orbit().eye - viewer.orbit().target).normalize();
    assert!(
        close(dir, DVec3::NEG_Y, 1e-9) || close(dir, DVec3::Y, 1e-9),
        "{dir}"
    );
    assert!(viewer.frame(Quality::Moving).unwrap().image.covered_count() > 0);
}

#[test]
fn axis_views_look_down_their_axis_with_a_sensible_up() {
    let mut viewer = Viewer::new(&sphere(), 200, 160, 2).unwrap();
    viewer.apply(Event::Zoom(2.0));
    let distance = viewer.orbit().distance();
    let target = viewer.orbit().target;
    let cases = [
        (1, DVec3::NEG_X, DVec3::Y),
        (2, DVec3::X, DVec3::Y),
        (3, DVec3::NEG_Y, DVec3::NEG_Z),
        (4, DVec3::Y, DVec3::Z),
        (5, DVec3::NEG_Z, DVec3::Y),
        (6, DVec3::Z, DVec3::Y),
    ];
    for (key, looking, up) in cases {
        viewer.apply(Event::Orbit {
            dx: 37.0,
            dy: -11.0,
        });
        viewer.apply(Event::View(Axis::of_key(key).unwrap()));
        let o = *viewer.orbit();
        assert!(close(o.forward(), looking, 1e-12), "key {key}: {o:?}");
        assert!(close(o.up, up, 1e-12), "key {key}: {o:?}");
        assert!((o.distance() - distance).abs() < 1e-9 * distance);
        assert_eq!(o.target, target);
        // The rendered camera looks the same way.
        let camera = viewer.camera_line().unwrap().camera;
        let dir = (camera.target() - camera.eye()).normalize();
        assert!(close(dir, looking, 1e-6), "key {key}: {dir}");
    }
    assert_eq!(Axis::of_key(0), None);
    assert_eq!(Axis::of_key(7), None);
}

#[test]
fn reset_returns_exactly_to_the_automatic_camera() {
    let scene = sphere();
    let mut viewer = Viewer::new(&scene, 300, 200, 2).unwrap();
    let script = "orbit 40 25\npan 12 -7\nzoom 3\nview 4\norbit -5 80\nreset\n";
    for event in parse_script(script).unwrap() {
        viewer.apply(event);
    }
    let prepared = spatch_render::PreparedScene::new(&scene);
    let auto = prepared.auto_camera(300, 200).unwrap();
    assert_eq!(viewer.orbit(), viewer.auto_orbit());
    assert_eq!(viewer.orbit().eye, auto.eye());
    assert_eq!(viewer.orbit().target, auto.target());
    assert_eq!(viewer.orbit().fov_y_degrees, auto.fov_y_degrees());
    // The automatic camera's up is +y, already orthogonal-free of the
    // view: the viewer's unit up is +y made orthogonal to the view.
    let forward = (auto.target() - auto.eye()).normalize();
    assert!(viewer.orbit().up.dot(forward).abs() < 1e-12);
    assert!(viewer.orbit().up.dot(DVec3::Y) > 0.9);
    // Its rounded camera stays within the rounding step of the automatic one.
    let camera = viewer.camera_line().unwrap().camera;
    assert!(close(camera.eye(), auto.eye(), 1e-5));
}

#[test]
fn pan_moves_eye_and_target_together_in_the_image_plane() {
    let mut viewer = Viewer::new(&sphere(), 200, 200, 2).unwrap();
    let before = *viewer.orbit();
    viewer.apply(Event::Pan { dx: 100.0, dy: 0.0 });
    let after = *viewer.orbit();
    let shift = after.target - before.target;
    assert!(close(after.eye - before.eye, shift, 1e-12));
    // Half the image width at the target's depth: tan(20°) · distance.
    let expected = (20f64).to_radians().tan() * before.distance();
    assert!((shift.length() - expected).abs() < 1e-9 * expected);
    // Dragging right moves the scene right: the camera moves left.
    assert!(shift.dot(before.right()) < 0.0);
    viewer.apply(Event::Zoom(1.0));
    assert!((viewer.orbit().distance() - 0.9 * before.distance()).abs() < 1e-9);
}

/// The options and camera `spatch render` makes of the viewer's flags (the
/// flags it prints; the CLI test renders them with the real command).
fn render_from_flags(flags: &str) -> (RenderOptions, Camera) {
    let words: Vec<&str> = flags.split_whitespace().collect();
    let value = |name: &str| {
        let i = words.iter().position(|w| *w == name)?;
        words.get(i + 1).copied()
    };
    let vec3 = |name: &str| {
        let v: Vec<f64> = value(name)
            .unwrap()
            .split(',')
            .map(|c| c.parse().unwrap())
            .collect();
        DVec3::new(v[0], v[1], v[2])
    };
    let number = |name: &str| value(name).unwrap().parse::<f64>().unwrap();
    let camera = Camera::look_at(
        vec3("--eye"),
        vec3("--target"),
        vec3("--up"),
        number("--fov"),
        number("--width") as u32,
        number("--height") as u32,
    )
    .unwrap();
    let mut options = RenderOptions::default();
    options.background = BACKGROUND;
    options.ssaa = value("--ssaa").map_or(1, |k| k.parse().unwrap());
    options.mip = !words.contains(&"--no-mip");
    if words.contains(&"triangles") {
        options.mode = RenderMode::Triangles;
    }
    options.shading = match value("--shading") {
        Some("flat") => Shading::Flat,
        Some("gouraud") => Shading::Gouraud,
        _ => Shading::Phong,
    };
    (options, camera)
}

#[test]
fn scripted_frames_equal_a_render_of_their_printed_flags() {
    let scene = sphere();
    let mut viewer = Viewer::new(&scene, 240, 180, 2).unwrap();
    let script = "orbit 30 12\nzoom 4\npan 9 4\n";
    for event in parse_script(script).unwrap() {
        viewer.apply(event);
    }
    let cases = [
        ("", Quality::Still, "--ssaa 2"),
        ("shading\n", Quality::Moving, "--shading flat"),
        (
            "mode\nmip\n",
            Quality::Still,
            "--mode triangles --no-mip --ssaa 2",
        ),
        (
            "ssaa\n",
            Quality::Still,
            "--shading flat --mode triangles --no-mip",
        ),
    ];
    for (toggles, quality, expected_flags) in cases {
        for event in parse_script(toggles).unwrap() {
            viewer.apply(event);
        }
        let frame = viewer.frame(quality).unwrap();
        assert!(
            frame.render_flags.ends_with(expected_flags),
            "{}",
            frame.render_flags
        );
        assert!(frame
            .overlay
            .contains(frame.render_flags.split(" --width").next().unwrap()));
        assert!(frame.overlay.contains(" ms "), "{}", frame.overlay);
        let (options, camera) = render_from_flags(&frame.render_flags);
        assert_eq!(camera, frame.camera);
        let mut renderer = Renderer::new(options).unwrap();
        let reference = renderer.render(&renderer.prepare(&scene), &camera).unwrap();
        assert!(frame.image.covered_count() > 1000);
        assert!(
            reference.image.pixels() == frame.image.pixels(),
            "{expected_flags}: frame differs from its flags' render"
        );
    }
}

#[test]
fn the_refined_frame_differs_from_the_fast_one_only_by_supersampling() {
    let mut viewer = Viewer::new(&sphere(), 160, 120, 2).unwrap();
    let fast = viewer.frame(Quality::Moving).unwrap();
    let still = viewer.frame(Quality::Still).unwrap();
    assert_eq!(fast.camera, still.camera);
    assert_eq!(fast.stats.internal, [160, 120]);
    assert_eq!(still.stats.internal, [320, 240]);
    assert_ne!(fast.image.pixels(), still.image.pixels());
    viewer.apply(Event::ToggleSsaa);
    let unrefined = viewer.frame(Quality::Still).unwrap();
    assert_eq!(unrefined.image.pixels(), fast.image.pixels());
}

#[test]
fn an_orbit_benchmark_times_every_frame() {
    let mut viewer = Viewer::new(&sphere(), 120, 100, 2).unwrap();
    let start = *viewer.orbit();
    let bench = spatch_view::bench_orbit(&mut viewer, 8).unwrap();
    assert_eq!(bench.frames, 8);
    assert!(bench.median_ms > 0.0 && bench.median_ms <= bench.worst_ms);
    assert!(bench.median_patches_drawn > 0);
    assert!(bench.median_patches_drawn <= viewer.patch_count() as u64);
    // A whole turn: the camera is back where it started.
    assert!(close(
        viewer.orbit().eye,
        start.eye,
        1e-9 * start.distance()
    ));
}

#[test]
fn moving_frames_at_a_smaller_scale_print_their_own_size() {
    let mut viewer = Viewer::new(&sphere(), 201, 150, 2).unwrap();
    viewer.set_moving_scale(2);
    let moving = viewer.frame(Quality::Moving).unwrap();
    assert_eq!((moving.image.width(), moving.image.height()), (101, 75));
    assert_eq!((moving.scale, moving.view), (2, (201, 150)));
    assert!(
        moving.render_flags.contains("--width 101 --height 75"),
        "{}",
        moving.render_flags
    );
    assert!(moving.overlay.contains("1/2 size"), "{}", moving.overlay);
    let still = viewer.frame(Quality::Still).unwrap();
    assert_eq!((still.image.width(), still.scale), (201, 1));
    let (options, camera) = render_from_flags(&moving.render_flags);
    let mut renderer = Renderer::new(options).unwrap();
    let reference = renderer
        .render(&renderer.prepare(&sphere()), &camera)
        .unwrap();
    assert!(reference.image.pixels() == moving.image.pixels());
    viewer.set_moving_scale(9);
    assert_eq!(viewer.settings().moving_scale, 4);
}
