//! Scan sets streamed for a plan: a `.conf` of XYZ scans and an E57 of two scans give,
//! point for point, the posed points of `spatch_scan::load_scans` (the untiled loader).

use std::path::{Path, PathBuf};

use e57::{E57Writer, Quaternion, Record, RecordValue, Transform, Translation};
use glam::DVec3;
use spatch_tiling::{make_plan, stream_points, PlanOptions};

/// `n` points of a wavy 2 m sheet at `offset`.
fn sheet(n: usize, offset: f64) -> Vec<[f64; 3]> {
    (0..n)
        .map(|k| {
            let (x, y) = ((k % 40) as f64 * 0.05, (k / 40) as f64 * 0.05);
            [x + offset, y, 0.1 * (3.0 * x).sin() * (2.0 * y).cos()]
        })
        .collect()
}

/// One E57 scan: its points, its rotation (`w x y z`) and its translation.
type Scan = (Vec<[f64; 3]>, [f64; 4], [f64; 3]);

/// Writes an E57 file of `scans`, each with its pose.
fn write_e57(path: &Path, scans: &[Scan]) {
    let mut writer = E57Writer::from_file(path, "file-guid").unwrap();
    for (index, (points, [w, x, y, z], [tx, ty, tz])) in scans.iter().enumerate() {
        let prototype = vec![
            Record::CARTESIAN_X_F64,
            Record::CARTESIAN_Y_F64,
            Record::CARTESIAN_Z_F64,
        ];
        let mut pc = writer
            .add_pointcloud(&format!("scan-{index}"), prototype)
            .unwrap();
        pc.set_transform(Some(Transform {
            rotation: Quaternion {
                w: *w,
                x: *x,
                y: *y,
                z: *z,
            },
            translation: Translation {
                x: *tx,
                y: *ty,
                z: *tz,
            },
        }));
        for p in points {
            pc.add_point(p.iter().map(|&v| RecordValue::Double(v)).collect())
                .unwrap();
        }
        pc.finalize().unwrap();
    }
    writer.finalize().unwrap();
}

/// Every streamed point of `path`, in order.
fn streamed(path: &Path) -> Vec<DVec3> {
    let mut all = Vec::new();
    stream_points(path, &mut |chunk| {
        all.extend_from_slice(&chunk.positions);
        Ok(())
    })
    .unwrap();
    all
}

/// The untiled loader's world positions of `path`, in order.
fn loaded(path: &Path) -> Vec<DVec3> {
    let scans = spatch_scan::load_scans(&[path.to_path_buf()], &Default::default()).unwrap();
    let cloud = scans.cloud;
    cloud
        .positions
        .iter()
        .map(|p| cloud.origin + p.as_dvec3())
        .collect()
}

fn check(path: &Path, points: usize) {
    let (a, b) = (streamed(path), loaded(path));
    assert_eq!(a.len(), points);
    assert_eq!(a.len(), b.len());
    let worst = a
        .iter()
        .zip(&b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, f64::max);
    assert!(worst < 1e-4, "{}: {worst}", path.display());
    let options = PlanOptions {
        tile: 1.0,
        buffer: Some(0.2),
        spacing: None,
        pixel_factor: spatch_cloud::CloudOptions::DEFAULT_PIXEL_FACTOR,
    };
    let plan = make_plan(path, &options).unwrap();
    assert_eq!(plan.points, points as u64);
    assert!(plan.tiles.len() >= 4, "{} tiles", plan.tiles.len());
}

#[test]
fn conf_and_e57_scan_sets_stream_their_posed_points() {
    let dir = tempfile::tempdir().unwrap();
    let xyz = |name: &str, points: &[[f64; 3]]| -> PathBuf {
        let text: String = points
            .iter()
            .map(|p| format!("{} {} {}\n", p[0], p[1], p[2]))
            .collect();
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    xyz("a.xyz", &sheet(1600, 0.0));
    xyz("b.xyz", &sheet(1600, 0.0));
    // b is turned a quarter about z and moved 3 along x.
    let half = std::f64::consts::FRAC_1_SQRT_2;
    let conf = dir.path().join("set.conf");
    let text = format!("bmesh a.xyz 0 0 0 0 0 0 1\nbmesh b.xyz 3 0 0 0 0 {half} {half}\n");
    std::fs::write(&conf, text).unwrap();
    check(&conf, 3200);

    let e57 = dir.path().join("set.e57");
    let scans = [
        (sheet(1200, 0.0), [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        (sheet(1200, 0.0), [half, 0.0, 0.0, half], [3.0, 0.5, 0.0]),
    ];
    write_e57(&e57, &scans);
    check(&e57, 2400);
}

/// The points of every scan of the E57 at `path` read whole by `spatch_scan::read_e57`,
/// each moved by its pose: what E57 tiles read before they streamed.
fn whole_e57(path: &Path) -> Vec<DVec3> {
    let (scans, _) = spatch_scan::read_e57(path).unwrap();
    scans
        .iter()
        .flat_map(|s| s.positions.iter().map(|&p| s.pose.apply_point(p)))
        .collect()
}

#[test]
fn an_e57_tile_streams_the_points_the_whole_read_gives() {
    let dir = tempfile::tempdir().unwrap();
    let e57 = dir.path().join("three.e57");
    let (h, c) = (std::f64::consts::FRAC_1_SQRT_2, 0.8f64);
    // 70 000 points in the first scan: more than one chunk.
    let scans = [
        (sheet(70_000, 0.0), [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        (sheet(2400, 0.5), [h, 0.0, 0.0, h], [3.0, 0.5, 0.0]),
        (sheet(2400, 0.0), [c, 0.6, 0.0, 0.0], [1.0, -2.0, 0.25]),
    ];
    write_e57(&e57, &scans);
    let whole = whole_e57(&e57);
    let bits = |v: &[DVec3]| -> Vec<[u64; 3]> {
        v.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
    };
    assert_eq!(bits(&streamed(&e57)), bits(&whole), "bit for bit, in order");

    let options = PlanOptions {
        tile: 2.0,
        buffer: Some(0.2),
        spacing: Some(0.05),
        pixel_factor: spatch_cloud::CloudOptions::DEFAULT_PIXEL_FACTOR,
    };
    let plan = make_plan(&e57, &options).unwrap();
    assert!(plan.tiles.len() >= 4, "{} tiles", plan.tiles.len());
    let grid = plan.grid.tile_grid().unwrap();
    for tile in &plan.tiles {
        let (cloud, own) = spatch_tiling::read_tile_points(&e57, &grid, tile.key).unwrap();
        let expected: Vec<glam::Vec3> = whole
            .iter()
            .filter(|&&p| spatch_tiling::is_member(&grid, tile.key, p))
            .map(|&p| (p - cloud.origin).as_vec3())
            .collect();
        assert_eq!(cloud.positions, expected, "tile {}", tile.index);
        assert_eq!(own, tile.points, "tile {}", tile.index);
    }
}

#[test]
fn a_conf_listing_an_e57_numbers_every_scan_and_poses_it_once() {
    let dir = tempfile::tempdir().unwrap();
    let text: String = sheet(1600, 0.0)
        .iter()
        .map(|p| format!("{} {} {}\n", p[0], p[1], p[2]))
        .collect();
    std::fs::write(dir.path().join("a.xyz"), text).unwrap();
    let half = std::f64::consts::FRAC_1_SQRT_2;
    let scans = [
        (sheet(1200, 0.0), [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        (sheet(1200, 0.0), [half, 0.0, 0.0, half], [0.0, 2.5, 0.0]),
    ];
    write_e57(&dir.path().join("b.e57"), &scans);
    // The E57's scans are moved by their own poses, then by the entry's (3 along x).
    let conf = dir.path().join("set.conf");
    let text = "bmesh a.xyz 0 0 0 0 0 0 1\nbmesh b.e57 3 0 0 0 0 0 1\n";
    std::fs::write(&conf, text).unwrap();
    // The same points as the untiled loader gives (posed once), in order.
    check(&conf, 4000);
    let mut per_scan = Vec::new();
    stream_points(&conf, &mut |chunk| {
        if per_scan.len() <= chunk.scan {
            per_scan.resize(chunk.scan + 1, 0);
        }
        per_scan[chunk.scan] += chunk.len();
        Ok(())
    })
    .unwrap();
    assert_eq!(per_scan, [1600, 1200, 1200]);

    // Each tile's points are runs of their scans, counted alike by the spill and by a
    // tile read alone.
    let options = PlanOptions {
        tile: 1.0,
        buffer: Some(0.2),
        spacing: Some(0.05),
        pixel_factor: spatch_cloud::CloudOptions::DEFAULT_PIXEL_FACTOR,
    };
    let plan = make_plan(&conf, &options).unwrap();
    let grid = plan.grid.tile_grid().unwrap();
    let keys: Vec<_> = plan.tiles.iter().map(|t| t.key).collect();
    let spill_dir = tempfile::tempdir().unwrap();
    let spill = spatch_tiling::spill_tiles(&conf, &grid, &keys, spill_dir.path(), 1 << 20).unwrap();
    let mut total = vec![0u64; 3];
    for (i, tile) in plan.tiles.iter().enumerate() {
        let alone = spatch_tiling::read_tile(&conf, &grid, tile.key).unwrap();
        assert_eq!(spill.tiles[i].scan_points, alone.scan_points, "tile {i}");
        let sum: u64 = alone.scan_points.iter().sum();
        assert_eq!(sum, alone.cloud.len() as u64, "tile {i}");
        for (t, n) in total.iter_mut().zip(&alone.scan_points) {
            *t += n;
        }
    }
    // Buffer points count in every tile that reads them: at least each scan's points.
    assert!(
        total[0] >= 1600 && total[1] >= 1200 && total[2] >= 1200,
        "{total:?}"
    );
}
