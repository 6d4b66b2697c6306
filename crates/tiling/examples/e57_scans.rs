//! Writes a point file as an E57 scan set: `SCANS` scans, each holding every `SCANS`-th
//! point (so every scan covers the whole area, as overlapping scanner stations do) in its
//! own frame, with a pose (a turn about z by `k × 37°` and a shift of `k × (3, 2, 0.5)` m
//! from the input's lowest corner) that puts it back where it was.
//!
//! `cargo run --release -p spatch-tiling --example e57_scans -- INPUT SCANS OUT.e57`, e.g.
//! `INPUT` the 2 M-point `bench/cityscape.sh` city: the E57 tile figures of
//! `docs/scale.md`. The input is streamed once per scan (the `e57` writer takes one scan
//! at a time); colours are written as 8-bit channels when the input has them. Positions
//! are f64, so a point read back and posed lies within about 1e-9 m of the input's.

use std::path::Path;

use e57::{E57Writer, Quaternion, Record, RecordValue, Transform, Translation};
use glam::{DQuat, DVec3};
use spatch_tiling::{stream_points, PointChunk};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, scans, out] = args.as_slice() else {
        return Err("usage: e57_scans INPUT SCANS OUT.e57".into());
    };
    let input = Path::new(input);
    let scans: usize = scans.parse()?;
    if scans == 0 {
        return Err("SCANS must be at least 1".into());
    }
    let (corner, colour) = survey(input)?;
    let mut writer = E57Writer::from_file(out, "spatch-e57-scans")?;
    let mut written = 0u64;
    for k in 0..scans {
        let turn = DQuat::from_rotation_z((37.0 * k as f64).to_radians());
        let shift = corner + DVec3::new(3.0, 2.0, 0.5) * k as f64;
        let mut prototype = vec![
            Record::CARTESIAN_X_F64,
            Record::CARTESIAN_Y_F64,
            Record::CARTESIAN_Z_F64,
        ];
        if colour {
            prototype.extend([
                Record::COLOR_RED_U8,
                Record::COLOR_GREEN_U8,
                Record::COLOR_BLUE_U8,
            ]);
        }
        let mut pc = writer.add_pointcloud(&format!("scan-{k}"), prototype)?;
        pc.set_transform(Some(Transform {
            rotation: Quaternion {
                w: turn.w,
                x: turn.x,
                y: turn.y,
                z: turn.z,
            },
            translation: Translation {
                x: shift.x,
                y: shift.y,
                z: shift.z,
            },
        }));
        let inverse = turn.inverse();
        let mut index = 0usize;
        let mut failure: Option<e57::Error> = None;
        stream_points(input, &mut |chunk: &PointChunk| {
            for (i, p) in chunk.positions.iter().enumerate() {
                index += 1;
                if (index - 1) % scans != k || failure.is_some() {
                    continue;
                }
                let local = inverse * (*p - shift);
                let mut values: Vec<RecordValue> = local
                    .to_array()
                    .iter()
                    .map(|&v| RecordValue::Double(v))
                    .collect();
                if let Some(c) = &chunk.colours {
                    values.extend(c[i][..3].iter().map(|&v| RecordValue::Integer(v.into())));
                }
                match pc.add_point(values) {
                    Ok(()) => written += 1,
                    Err(e) => failure = Some(e),
                }
            }
            Ok(())
        })?;
        if let Some(e) = failure {
            return Err(e.into());
        }
        pc.finalize()?;
    }
    writer.finalize()?;
    eprintln!("e57_scans: {written} points in {scans} scans -> {out}");
    Ok(())
}

/// The input's lowest corner and whether it has colours (one streamed pass).
fn survey(input: &Path) -> Result<(DVec3, bool), Box<dyn std::error::Error>> {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut colour = false;
    stream_points(input, &mut |chunk: &PointChunk| {
        colour |= chunk.colours.is_some();
        for p in &chunk.positions {
            lo = lo.min(*p);
        }
        Ok(())
    })?;
    Ok((lo, colour))
}
