//! Heights estimated from colour by hue, as the original work did with no
//! relief data: blue water stays at sea level, green land becomes plateaus,
//! brown land mountains (heights in between follow the hue from green to
//! brown), bright unsaturated ice a plateau; then the field is smoothed.
//!
//! Cost: one pass over the pixels plus the Gaussian.

use crate::{ColourMap, HeightMap};

/// Thresholds and levels of the colour → height rule. Heights are in model
/// units for a globe of radius 128 (the default), before `--exaggeration`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct HueLevels {
    /// Hues (degrees) from this one up to `water_hue_max` are water. Default 170.
    pub water_hue_min: f32,
    /// See `water_hue_min`. Default 270.
    pub water_hue_max: f32,
    /// Pixels darker than this value (0..1) are water whatever their hue
    /// (deep ocean is nearly black). Default 0.08.
    pub dark_water_value: f32,
    /// Land at this hue or greener (degrees) is plateau. Default 100.
    pub green_hue: f32,
    /// Land at this hue or browner (degrees, towards red) is mountain. Default 35.
    pub brown_hue: f32,
    /// Height of green land. Default 0.5.
    pub plateau_height: f32,
    /// Height of brown land. Default 1.5.
    pub mountain_height: f32,
    /// Pixels with saturation below this and value above `ice_value` are ice. Default 0.15.
    pub ice_saturation: f32,
    /// See `ice_saturation`. Default 0.7.
    pub ice_value: f32,
    /// Height of ice. Default 0.5.
    pub ice_height: f32,
    /// Standard deviation of the Gaussian smoothing, in degrees of longitude
    /// (0.7° is 2 pixels of a 1024-wide map). More smoothing: gentler relief,
    /// fewer patches needed for the same error. Default 0.7.
    pub smoothing_deg: f32,
}

impl Default for HueLevels {
    fn default() -> Self {
        Self {
            water_hue_min: 170.0,
            water_hue_max: 270.0,
            dark_water_value: 0.08,
            green_hue: 100.0,
            brown_hue: 35.0,
            plateau_height: 0.5,
            mountain_height: 1.5,
            ice_saturation: 0.15,
            ice_value: 0.7,
            ice_height: 0.5,
            smoothing_deg: 0.7,
        }
    }
}

/// Hue (degrees, 0..360), saturation and value (0..1) of an sRGB pixel.
fn hsv(r: u8, g: u8, b: u8) -> (f32, f32, f32) {
    let (r, g, b) = (
        f32::from(r) / 255.0,
        f32::from(g) / 255.0,
        f32::from(b) / 255.0,
    );
    let max = r.max(g).max(b);
    let min = r.min(g).min(b);
    let delta = max - min;
    let hue = if delta == 0.0 {
        0.0
    } else if max == r {
        60.0 * ((g - b) / delta).rem_euclid(6.0)
    } else if max == g {
        60.0 * ((b - r) / delta + 2.0)
    } else {
        60.0 * ((r - g) / delta + 4.0)
    };
    let saturation = if max == 0.0 { 0.0 } else { delta / max };
    (hue, saturation, max)
}

impl HueLevels {
    /// The unsmoothed height of one pixel.
    pub fn height_of(&self, rgb: [u8; 3]) -> f32 {
        let (hue, saturation, value) = hsv(rgb[0], rgb[1], rgb[2]);
        if saturation < self.ice_saturation && value > self.ice_value {
            return self.ice_height;
        }
        if value < self.dark_water_value || (self.water_hue_min..=self.water_hue_max).contains(&hue)
        {
            return 0.0;
        }
        // Land. Hues past the water range (magenta, red) count as brown.
        let hue = if hue > self.water_hue_max { 0.0 } else { hue };
        let span = (self.green_hue - self.brown_hue).max(1e-3);
        let t = ((self.green_hue - hue) / span).clamp(0.0, 1.0);
        self.plateau_height + t * (self.mountain_height - self.plateau_height)
    }
}

/// The smoothed height field of a colour map.
pub fn heights_from_colour(map: &ColourMap, levels: &HueLevels) -> HeightMap {
    let values = map
        .rgba()
        .chunks_exact(4)
        .map(|p| levels.height_of([p[0], p[1], p[2]]))
        .collect();
    let mut heights = HeightMap::new(map.width() as usize, map.height() as usize, values)
        .unwrap_or_else(|| unreachable!("ColourMap guarantees at least 2x2 pixels"));
    heights.smooth(levels.smoothing_deg * map.width() as f32 / 360.0);
    heights
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn water_green_brown_and_ice_get_their_levels() {
        let l = HueLevels::default();
        assert_eq!(l.height_of([10, 30, 90]), 0.0, "ocean blue");
        assert_eq!(l.height_of([2, 3, 5]), 0.0, "near-black deep water");
        assert_eq!(l.height_of([40, 110, 40]), l.plateau_height, "forest green");
        assert_eq!(l.height_of([120, 80, 40]), l.mountain_height, "brown");
        assert_eq!(l.height_of([240, 240, 245]), l.ice_height, "ice");
        let olive = l.height_of([120, 120, 40]); // hue 60: between green and brown
        assert!(
            olive > l.plateau_height && olive < l.mountain_height,
            "{olive}"
        );
    }
}
