//! Writes synthetic scanner files for the reading-throughput measurement of
//! docs/algorithms/scan.md: `N` points of a wavy terrain with RGB and intensity, as
//! `terrain.las` (LAS 1.4, format 7), `terrain.laz`, `terrain.e57` and `terrain.pts`.
//!
//! ```sh
//! cargo run --release -p spatch-scan --example make_scans -- 1000000 /tmp/scans
//! ```

use std::io::Write;
use std::path::Path;

use e57::{E57Writer, Record, RecordValue};

/// The synthetic terrain: `n` points on a square grid of 5 cm.
struct Terrain {
    n: usize,
    /// Points along a row of the grid.
    side: usize,
}

impl Terrain {
    /// Point `k`: its position, its RGB (8-bit values) and its intensity.
    fn point(&self, k: usize) -> ([f64; 3], [u16; 3], u16) {
        let side = self.side;
        let (x, y) = ((k % side) as f64 * 0.05, (k / side) as f64 * 0.05);
        let z = 2.0 * (x * 0.1).sin() * (y * 0.07).cos();
        let rgb = [(k % 251) as u16, ((k / side) % 256) as u16, 128];
        (
            [x + 500_000.0, y + 4_000_000.0, z + 100.0],
            rgb,
            (k % 4000) as u16,
        )
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().unwrap_or_else(|| "1000000".into()).parse()?;
    let dir = args.next().unwrap_or_else(|| ".".into());
    let dir = Path::new(&dir);
    std::fs::create_dir_all(dir)?;
    let side = (n as f64).sqrt().ceil() as usize;
    let terrain = Terrain { n, side };
    for name in ["terrain.las", "terrain.laz"] {
        write_las(&dir.join(name), &terrain)?;
    }
    write_e57(&dir.join("terrain.e57"), &terrain)?;
    write_pts(&dir.join("terrain.pts"), &terrain)?;
    Ok(())
}

/// Writes the terrain as LAS 1.4 point format 7 at 1 mm (compressed when `path` ends in
/// `.laz`).
fn write_las(path: &Path, terrain: &Terrain) -> Result<(), Box<dyn std::error::Error>> {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(7)?;
    let near = |offset: f64| las::Transform {
        scale: 0.001,
        offset,
    };
    builder.transforms = las::Vector {
        x: near(500_000.0),
        y: near(4_000_000.0),
        z: near(0.0),
    };
    let mut writer = las::Writer::from_path(path, builder.into_header()?)?;
    for k in 0..terrain.n {
        let ([x, y, z], [r, g, b], intensity) = terrain.point(k);
        writer.write_point(las::Point {
            x,
            y,
            z,
            intensity,
            color: Some(las::Color::new(r * 257, g * 257, b * 257)),
            gps_time: Some(0.0),
            ..las::Point::default()
        })?;
    }
    writer.close()?;
    Ok(())
}

/// Writes the terrain as one E57 scan of f64 positions and 8-bit colours.
fn write_e57(path: &Path, terrain: &Terrain) -> Result<(), Box<dyn std::error::Error>> {
    let mut e57 = E57Writer::from_file(path, "terrain")?;
    let prototype = vec![
        Record::CARTESIAN_X_F64,
        Record::CARTESIAN_Y_F64,
        Record::CARTESIAN_Z_F64,
        Record::COLOR_RED_U8,
        Record::COLOR_GREEN_U8,
        Record::COLOR_BLUE_U8,
    ];
    let mut pc = e57.add_pointcloud("scan-0", prototype)?;
    for k in 0..terrain.n {
        let (p, rgb, _) = terrain.point(k);
        let mut values: Vec<RecordValue> = p.iter().map(|&v| RecordValue::Double(v)).collect();
        values.extend(rgb.map(|c| RecordValue::Integer(i64::from(c))));
        pc.add_point(values)?;
    }
    pc.finalize()?;
    e57.finalize()?;
    Ok(())
}

/// Writes the terrain as a PTS text file: the count, then `x y z intensity r g b` lines
/// (the intensity less 2048).
fn write_pts(path: &Path, terrain: &Terrain) -> Result<(), Box<dyn std::error::Error>> {
    let n = terrain.n;
    let mut pts = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(pts, "{n}")?;
    for k in 0..n {
        let ([x, y, z], [r, g, b], intensity) = terrain.point(k);
        writeln!(
            pts,
            "{x:.3} {y:.3} {z:.3} {} {r} {g} {b}",
            i32::from(intensity) - 2048
        )?;
    }
    pts.flush()?;
    Ok(())
}
