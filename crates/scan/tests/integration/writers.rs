//! Small files of every format, written with the formats' own crates (las/laz, e57) or as
//! text, for the round-trip tests.

use std::path::Path;

use e57::{E57Writer, Quaternion, Record, RecordValue, Transform, Translation};

/// A test point: position, colour, intensity.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TestPoint {
    pub(crate) position: [f64; 3],
    pub(crate) colour: [u8; 3],
    pub(crate) intensity: u16,
}

/// `n` points on a wavy 2 m sheet far from the origin (georeferenced-like), with colours
/// and intensities that vary per point. Coordinates are multiples of 1 mm (LAS's scale).
pub(crate) fn test_points(n: usize, offset: [f64; 3]) -> Vec<TestPoint> {
    let side = (n as f64).sqrt().ceil() as usize;
    (0..n)
        .map(|k| {
            let (i, j) = ((k % side) as f64, (k / side) as f64);
            let (x, y) = (i * 2.0 / side as f64, j * 2.0 / side as f64);
            let z = 0.1 * (x * 3.0).sin() * (y * 2.0).cos();
            let mm = |v: f64| (v * 1000.0).round() / 1000.0;
            TestPoint {
                position: [mm(x + offset[0]), mm(y + offset[1]), mm(z + offset[2])],
                colour: [
                    (k % 256) as u8,
                    ((k * 7) % 256) as u8,
                    ((k * 13) % 256) as u8,
                ],
                intensity: (k % 4096) as u16,
            }
        })
        .collect()
}

/// Writes a LAS (or, by the `.laz` extension, LAZ) file of `version` with point format
/// `format` (2/3/7 have RGB; 0/1/6 do not). Colours are written as 16-bit (`c * 257`).
pub(crate) fn write_las(path: &Path, points: &[TestPoint], version: (u8, u8), format: u8) {
    let mut builder = las::Builder::from(version);
    builder.point_format = las::point::Format::new(format).unwrap();
    // 1 mm steps from an offset near the points (as lidar writers do for UTM coordinates).
    let near = |axis: usize| las::Transform {
        scale: 0.001,
        offset: points.first().map_or(0.0, |p| p.position[axis].round()),
    };
    builder.transforms = las::Vector {
        x: near(0),
        y: near(1),
        z: near(2),
    };
    let header = builder.into_header().unwrap();
    let mut writer = las::Writer::from_path(path, header).unwrap();
    for p in points {
        let [x, y, z] = p.position;
        let colour = builder_has_rgb(format).then(|| {
            let [r, g, b] = p.colour.map(|c| u16::from(c) * 257);
            las::Color::new(r, g, b)
        });
        writer
            .write_point(las::Point {
                x,
                y,
                z,
                intensity: p.intensity,
                color: colour,
                gps_time: matches!(format, 1 | 3 | 6 | 7).then_some(0.0),
                ..las::Point::default()
            })
            .unwrap();
    }
    writer.close().unwrap();
}

/// Whether LAS point format `format` carries RGB.
fn builder_has_rgb(format: u8) -> bool {
    matches!(format, 2 | 3 | 5 | 7 | 8 | 10)
}

/// One E57 scan to write: points in its local frame and its pose.
pub(crate) struct E57Scan<'a> {
    pub(crate) points: &'a [TestPoint],
    pub(crate) rotation: [f64; 4],
    pub(crate) translation: [f64; 3],
    pub(crate) colour: bool,
}

/// Writes an E57 file holding `scans`, each with its pose (`rotation` as `w x y z`).
pub(crate) fn write_e57(path: &Path, scans: &[E57Scan<'_>]) {
    let mut writer = E57Writer::from_file(path, "file-guid").unwrap();
    for (index, scan) in scans.iter().enumerate() {
        let mut prototype = vec![
            Record::CARTESIAN_X_F64,
            Record::CARTESIAN_Y_F64,
            Record::CARTESIAN_Z_F64,
        ];
        if scan.colour {
            prototype.extend([
                Record::COLOR_RED_U8,
                Record::COLOR_GREEN_U8,
                Record::COLOR_BLUE_U8,
            ]);
        } else {
            prototype.push(Record::INTENSITY_U16);
        }
        let guid = format!("scan-{index}");
        let mut pc = writer.add_pointcloud(&guid, prototype).unwrap();
        let [w, x, y, z] = scan.rotation;
        let [tx, ty, tz] = scan.translation;
        pc.set_transform(Some(Transform {
            rotation: Quaternion { w, x, y, z },
            translation: Translation {
                x: tx,
                y: ty,
                z: tz,
            },
        }));
        for p in scan.points {
            let mut values: Vec<RecordValue> =
                p.position.iter().map(|&v| RecordValue::Double(v)).collect();
            if scan.colour {
                values.extend(p.colour.map(|c| RecordValue::Integer(i64::from(c))));
            } else {
                values.push(RecordValue::Integer(i64::from(p.intensity)));
            }
            pc.add_point(values).unwrap();
        }
        pc.finalize().unwrap();
    }
    writer.finalize().unwrap();
}
