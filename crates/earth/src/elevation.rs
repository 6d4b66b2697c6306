//! Heights from a greyscale elevation map (8- or 16-bit PNG).
//!
//! A raw sample `s` is read as unsigned (`0..=255` or `0..=65535`) or, for
//! 16-bit maps, as signed two's complement (`−32768..=32767`, as SRTM-style
//! files store metres). Its elevation is `s − sea_level` (in the map's own
//! units, metres for real DEMs). Heights are then scaled so that the largest
//! elevation magnitude in the map becomes `peak_height` model units; land is
//! positive, sea floor negative. Void samples (the `void` value; −32768 by
//! default for signed maps) are filled from their neighbours by repeated
//! averaging, so they never show as pits or spikes.
//!
//! Cost: one pass, plus a few passes over voids.

use std::path::Path;

use crate::{EarthError, HeightMap};

/// How 16-bit samples are read. 8-bit samples are always unsigned.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ElevationEncoding {
    /// 0..=65535.
    #[default]
    Unsigned,
    /// Two's complement −32768..=32767 (metres in SRTM-style files).
    Signed,
}

/// Options of [`heights_from_elevation`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct ElevationOptions {
    /// How 16-bit samples are read. Default unsigned.
    pub encoding: ElevationEncoding,
    /// The raw sample value of sea level. Default 0.
    pub sea_level: f64,
    /// A raw sample value meaning "no data", if any. Default: −32768 for
    /// signed maps, none for unsigned ones.
    pub void: Option<f64>,
    /// Model units the largest elevation magnitude maps to (before
    /// `--exaggeration`). Default 1.5, the colour rule's mountain height.
    pub peak_height: f32,
}

impl Default for ElevationOptions {
    fn default() -> Self {
        Self {
            encoding: ElevationEncoding::Unsigned,
            sea_level: 0.0,
            void: None,
            peak_height: 1.5,
        }
    }
}

/// Passes of neighbour averaging used to fill voids (after which any still
/// unfilled sample is set to sea level).
const VOID_FILL_PASSES: usize = 64;

/// Reads an elevation map and turns it into heights.
pub fn heights_from_elevation(
    path: &Path,
    options: &ElevationOptions,
) -> Result<HeightMap, EarthError> {
    let image = image::open(path).map_err(|source| EarthError::Image {
        path: path.to_path_buf(),
        source,
    })?;
    let unusable = |problem: String| EarthError::UnusableImage {
        path: path.to_path_buf(),
        problem,
    };
    let (width, height) = (image.width() as usize, image.height() as usize);
    let samples: Vec<f64> = match &image {
        image::DynamicImage::ImageLuma8(grey) => {
            grey.as_raw().iter().map(|&v| f64::from(v)).collect()
        }
        image::DynamicImage::ImageLuma16(grey) => match options.encoding {
            ElevationEncoding::Unsigned => grey.as_raw().iter().map(|&v| f64::from(v)).collect(),
            ElevationEncoding::Signed => {
                grey.as_raw().iter().map(|&v| f64::from(v as i16)).collect()
            }
        },
        other => {
            return Err(unusable(format!(
                "an elevation map must be 8- or 16-bit greyscale, this one is {:?}",
                other.color()
            )))
        }
    };
    let void = options.void.or(match (options.encoding, &image) {
        (ElevationEncoding::Signed, image::DynamicImage::ImageLuma16(_)) => Some(-32768.0),
        _ => None,
    });
    let mut elevations: Vec<Option<f64>> = samples
        .iter()
        .map(|&s| (Some(s) != void).then_some(s - options.sea_level))
        .collect();
    fill_voids(&mut elevations, width, height);
    let peak = elevations
        .iter()
        .flatten()
        .fold(0.0f64, |m, e| m.max(e.abs()));
    let scale = if peak > 0.0 {
        f64::from(options.peak_height) / peak
    } else {
        0.0
    };
    let values = elevations
        .iter()
        .map(|e| (e.unwrap_or(0.0) * scale) as f32)
        .collect();
    HeightMap::new(width, height, values).ok_or_else(|| {
        unusable(format!(
            "a {width}x{height} elevation map is too small (needs at least 2x2)"
        ))
    })
}

/// Replaces voids by the mean of their known 4-neighbours, pass after pass
/// (longitude wraps), so holes fill from their rims inwards.
fn fill_voids(values: &mut [Option<f64>], width: usize, height: usize) {
    for _ in 0..VOID_FILL_PASSES {
        let mut changed = false;
        let snapshot = values.to_vec();
        for y in 0..height {
            for x in 0..width {
                if snapshot[y * width + x].is_some() {
                    continue;
                }
                let mut neighbours = vec![
                    snapshot[y * width + (x + 1) % width],
                    snapshot[y * width + (x + width - 1) % width],
                ];
                if y > 0 {
                    neighbours.push(snapshot[(y - 1) * width + x]);
                }
                if y + 1 < height {
                    neighbours.push(snapshot[(y + 1) * width + x]);
                }
                let known: Vec<f64> = neighbours.into_iter().flatten().collect();
                if !known.is_empty() {
                    values[y * width + x] = Some(known.iter().sum::<f64>() / known.len() as f64);
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn voids_fill_from_their_rims() {
        let mut v = vec![Some(10.0), None, None, Some(20.0)];
        fill_voids(&mut v, 4, 1);
        assert!(v.iter().all(Option::is_some));
        let filled = v[1].unwrap();
        assert!((10.0..=20.0).contains(&filled), "{filled}");
    }
}
