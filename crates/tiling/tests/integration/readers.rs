//! The streamed readers agree with each other and with what was written.

use glam::DVec3;
use spatch_fixtures::Cityscape;
use spatch_tiling::{make_plan, stream_points, PlanOptions, TilingError};

use crate::write_city_ply;

fn read_all(path: &std::path::Path) -> (Vec<DVec3>, Vec<[u8; 4]>) {
    let (mut p, mut c) = (Vec::new(), Vec::new());
    stream_points(path, &mut |chunk| {
        p.extend_from_slice(&chunk.positions);
        c.extend_from_slice(chunk.colours.as_deref().unwrap_or_default());
        Ok(())
    })
    .unwrap();
    (p, c)
}

#[test]
fn binary_ascii_ply_and_xyz_give_the_same_points_over_several_chunks() {
    let dir = tempfile::tempdir().unwrap();
    // More than one chunk (65 536 points).
    let city = Cityscape::new(70_000, 3);
    let binary = dir.path().join("c.ply");
    write_city_ply(&city, &binary);
    let (p, c) = read_all(&binary);
    assert_eq!(p.len(), 70_000);
    assert_eq!(c.len(), 70_000);
    let mut ascii = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n",
        p.len()
    );
    let mut xyz = String::new();
    for (p, c) in p.iter().zip(&c) {
        ascii.push_str(&format!(
            "{} {} {} {} {} {}\n",
            p.x as f32, p.y as f32, p.z as f32, c[0], c[1], c[2]
        ));
        xyz.push_str(&format!(
            "{} {} {} {} {} {}\n",
            p.x as f32, p.y as f32, p.z as f32, c[0], c[1], c[2]
        ));
    }
    std::fs::write(dir.path().join("a.ply"), ascii).unwrap();
    std::fs::write(dir.path().join("a.xyz"), xyz).unwrap();
    // Printed as f32: equal as f32.
    let single = |v: &[DVec3]| v.iter().map(|p| p.as_vec3()).collect::<Vec<_>>();
    for name in ["a.ply", "a.xyz"] {
        let (q, d) = read_all(&dir.path().join(name));
        assert!(single(&q) == single(&p), "{name}: positions differ");
        assert!(d == c, "{name}: colours differ");
    }
}

#[test]
fn truncated_ply_and_unknown_formats_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    write_city_ply(&Cityscape::new(1000, 1), &path);
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() - 100]).unwrap();
    let err = stream_points(&path, &mut |_| Ok(())).unwrap_err();
    assert!(
        matches!(err, TilingError::Truncated { declared: 1000, .. }),
        "{err}"
    );
    let other = dir.path().join("c.obj");
    std::fs::write(&other, "v 0 0 0\n").unwrap();
    assert!(matches!(
        stream_points(&other, &mut |_| Ok(())),
        Err(TilingError::UnsupportedFormat { .. })
    ));
}

#[test]
fn a_plan_counts_every_point_once_and_estimates_the_density() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    let city = Cityscape::new(80_000, 5);
    write_city_ply(&city, &path);
    let options = PlanOptions {
        tile: city.side() / 2.0 + 0.01,
        buffer: None,
        spacing: None,
        pixel_factor: 2.0,
    };
    let plan = make_plan(&path, &options).unwrap();
    assert_eq!(plan.points, 80_000);
    assert_eq!(plan.tiles.iter().map(|t| t.points).sum::<u64>(), 80_000);
    assert!(plan.tiles.len() >= 4, "{}", plan.tiles.len());
    // 100 points per square metre: about 0.1 m apart.
    assert!((0.05..0.2).contains(&plan.spacing), "{}", plan.spacing);
    assert!((plan.grid.buffer - 16.0 * 2.0 * f64::from(plan.spacing)).abs() < 1e-6);
    for (k, tile) in plan.tiles.iter().enumerate() {
        assert_eq!(tile.index, k);
        assert!(tile.buffered.min[0] < tile.bounds.min[0]);
    }
}

#[test]
fn a_tile_too_small_for_the_default_buffer_is_refused_naming_the_default() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    let city = Cityscape::new(20_000, 5);
    write_city_ply(&city, &path);
    let options = PlanOptions {
        tile: 0.5,
        buffer: None,
        spacing: None,
        pixel_factor: 2.0,
    };
    let Err(TilingError::InvalidOption { option, reason }) = make_plan(&path, &options) else {
        panic!("a tile of 0.5 with a buffer of 16 pixels of about 0.1 m must be refused");
    };
    assert_eq!(option, "tile size");
    assert!(reason.contains("default buffer"), "{reason}");
    // The size it names is enough.
    let least: f64 = reason
        .split("more than about ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|v| v.parse().ok())
        .expect("the least tile size");
    let options = PlanOptions {
        tile: least * 1.2,
        ..options
    };
    make_plan(&path, &options).expect("a tile just above the size the message names");
    // A buffer given keeps the plain message.
    let options = PlanOptions {
        tile: 0.5,
        buffer: Some(0.3),
        ..options
    };
    let Err(TilingError::InvalidOption { option, .. }) = make_plan(&path, &options) else {
        panic!("a buffer over half a tile must be refused");
    };
    assert_eq!(option, "buffer");
}
