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

use std::error::Error;
use std::fs::File;
use std::path::Path;

use e57::{E57Writer, PointCloudWriter, Quaternion, Record, RecordValue, Transform, Translation};
use glam::{DQuat, DVec3};
use spatch_tiling::{stream_points, PointChunk};

/// What every scan of the set shares: the input and how it is dealt out and posed.
struct ScanSet<'a> {
    input: &'a Path,
    scans: usize,
    /// The input's lowest corner, the first scan's origin.
    corner: DVec3,
    /// Whether the input has colours.
    colour: bool,
}

fn main() -> Result<(), Box<dyn Error>> {
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
    let set = ScanSet {
        input,
        scans,
        corner,
        colour,
    };
    let mut writer = E57Writer::from_file(out, "spatch-e57-scans")?;
    let mut written = 0u64;
    for k in 0..scans {
        written += write_scan(&mut writer, &set, k)?;
    }
    writer.finalize()?;
    eprintln!("e57_scans: {written} points in {scans} scans -> {out}");
    Ok(())
}

/// Writes scan `k` (every `scans`-th point from the `k`-th, in its own frame, with its
/// pose) and returns how many points it holds.
fn write_scan(
    writer: &mut E57Writer<File>,
    set: &ScanSet,
    k: usize,
) -> Result<u64, Box<dyn Error>> {
    let turn = DQuat::from_rotation_z((37.0 * k as f64).to_radians());
    let shift = set.corner + DVec3::new(3.0, 2.0, 0.5) * k as f64;
    let mut pc = writer.add_pointcloud(&format!("scan-{k}"), prototype(set.colour))?;
    pc.set_transform(Some(pose(turn, shift)));
    let written = add_scan_points(&mut pc, set, k, (turn, shift))?;
    pc.finalize()?;
    Ok(written)
}

/// The records of a scan's points: f64 positions, and 8-bit colours when the input has them.
fn prototype(colour: bool) -> Vec<Record> {
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
    prototype
}

/// The E57 pose of a scan turned by `turn` and shifted by `shift`.
fn pose(turn: DQuat, shift: DVec3) -> Transform {
    Transform {
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
    }
}

/// Streams the input and adds scan `k`'s points to `pc` in the scan's frame (the inverse
/// of its pose `(turn, shift)`); returns how many were added.
fn add_scan_points(
    pc: &mut PointCloudWriter<File>,
    set: &ScanSet,
    k: usize,
    (turn, shift): (DQuat, DVec3),
) -> Result<u64, Box<dyn Error>> {
    let inverse = turn.inverse();
    let mut written = 0u64;
    let mut index = 0usize;
    let mut failure: Option<e57::Error> = None;
    stream_points(set.input, &mut |chunk: &PointChunk| {
        for (i, p) in chunk.positions.iter().enumerate() {
            index += 1;
            if (index - 1) % set.scans != k || failure.is_some() {
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
    Ok(written)
}

/// The input's lowest corner and whether it has colours (one streamed pass).
fn survey(input: &Path) -> Result<(DVec3, bool), Box<dyn Error>> {
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
