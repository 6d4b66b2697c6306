//! Writes a synthetic cityscape (`spatch_fixtures::Cityscape`: ground, buildings, trees, at
//! 100 points per m²) as LAS (1.2, point format 2, 1 mm steps) and binary little-endian
//! PLY (float x y z, uchar red green blue), streamed a chunk at a time.
//!
//! `cargo run --release -p spatch-tiling --example cityscape -- POINTS OUT [SEED]` writes
//! `OUT.las` and `OUT.ply` (`bench/cityscape.sh` wraps it). The two hold the same points
//! in the same order (positions rounded to the millimetre in both).

use std::path::PathBuf;

use spatch_fixtures::cityscape::millimetre;
use spatch_fixtures::Cityscape;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(points), Some(out)) = (args.first(), args.get(1)) else {
        return Err("usage: cityscape POINTS OUT [SEED] (writes OUT.las and OUT.ply)".into());
    };
    let points: u64 = points.parse()?;
    let seed: u64 = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1);
    let city = Cityscape::new(points, seed);
    let base = PathBuf::from(out);
    write_las(&city, &base.with_extension("las"))?;
    city.write_binary_ply(&base.with_extension("ply"), true)?;
    eprintln!(
        "cityscape: {} points over {:.0} m x {:.0} m -> {}.las, {}.ply",
        city.len(),
        city.side(),
        city.side(),
        base.display(),
        base.display()
    );
    Ok(())
}

fn write_las(city: &Cityscape, path: &std::path::Path) -> Result<(), Box<dyn std::error::Error>> {
    let mut builder = las::Builder::from((1, 2));
    builder.point_format = las::point::Format::new(2)?;
    let mm = las::Transform {
        scale: 0.001,
        offset: 0.0,
    };
    builder.transforms = las::Vector {
        x: mm,
        y: mm,
        z: mm,
    };
    let mut writer = las::Writer::from_path(path, builder.into_header()?)?;
    let mut failure = None;
    city.for_each_chunk(1 << 16, &mut |positions, colours| {
        for (p, c) in positions.iter().zip(colours) {
            let wide = |v: u8| u16::from(v) * 257;
            let point = las::Point {
                x: millimetre(p[0]),
                y: millimetre(p[1]),
                z: millimetre(p[2]),
                color: Some(las::Color::new(wide(c[0]), wide(c[1]), wide(c[2]))),
                ..las::Point::default()
            };
            if let Err(e) = writer.write_point(point) {
                failure.get_or_insert(e);
            }
        }
    });
    if let Some(e) = failure {
        return Err(e.into());
    }
    writer.close()?;
    Ok(())
}
