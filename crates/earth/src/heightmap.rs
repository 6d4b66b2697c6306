//! A height field over longitude and latitude, sampled bilinearly, smoothed
//! by a separable Gaussian.
//!
//! Pixel `(x, y)` of a `w × h` map covers longitude `−180 + 360·x/w ..` and
//! latitude `90 − 180·y/h ..`; its value holds at the pixel centre.
//! Longitude wraps around; latitude clamps at the poles.

/// Heights in model units above sea level (negative below), one per pixel of
/// an equirectangular grid.
///
/// # Guarantees
/// `values.len() == width * height`, both sides at least 2, all values finite.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    width: usize,
    height: usize,
    values: Vec<f32>,
}

impl HeightMap {
    /// A map from values (rows from the north). Non-finite values become 0.
    pub fn new(width: usize, height: usize, mut values: Vec<f32>) -> Option<Self> {
        if width < 2 || height < 2 || values.len() != width * height {
            return None;
        }
        for v in &mut values {
            if !v.is_finite() {
                *v = 0.0;
            }
        }
        Some(Self {
            width,
            height,
            values,
        })
    }

    /// Width in pixels (longitude).
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels (latitude).
    pub fn height(&self) -> usize {
        self.height
    }

    /// The values, rows from the north.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// `(min, max)` of the values.
    pub fn range(&self) -> (f32, f32) {
        self.values
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)))
    }

    /// Multiplies every height by `factor`.
    pub fn scale(&mut self, factor: f32) {
        for v in &mut self.values {
            *v *= factor;
        }
    }

    /// Bilinear height at longitude and latitude in degrees.
    pub fn sample(&self, lon_deg: f64, lat_deg: f64) -> f32 {
        let (w, h) = (self.width as f64, self.height as f64);
        let fx = (lon_deg + 180.0) / 360.0 * w - 0.5;
        let fy = ((90.0 - lat_deg) / 180.0 * h - 0.5).clamp(0.0, h - 1.0);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = ((fx - x0) as f32, (fy - y0) as f32);
        let wrap = |x: f64| (x.rem_euclid(w)) as usize;
        let (xa, xb) = (wrap(x0), wrap(x0 + 1.0));
        let (ya, yb) = (y0 as usize, ((y0 + 1.0) as usize).min(self.height - 1));
        let at = |x: usize, y: usize| self.values[y * self.width + x];
        let top = at(xa, ya) + (at(xb, ya) - at(xa, ya)) * tx;
        let bottom = at(xa, yb) + (at(xb, yb) - at(xa, yb)) * tx;
        top + (bottom - top) * ty
    }

    /// Smooths with a Gaussian of standard deviation `sigma_px` pixels
    /// (separable; wraps in longitude, clamps in latitude). `sigma_px <= 0`
    /// leaves the map as it is. Cost: O(pixels · 6σ).
    pub fn smooth(&mut self, sigma_px: f32) {
        if !(sigma_px > 0.0 && sigma_px.is_finite()) {
            return;
        }
        let radius = (3.0 * sigma_px).ceil() as isize;
        let kernel: Vec<f32> = (-radius..=radius)
            .map(|k| (-(k * k) as f32 / (2.0 * sigma_px * sigma_px)).exp())
            .collect();
        let norm: f32 = kernel.iter().sum();
        let (w, h) = (self.width as isize, self.height as isize);
        let mut row_pass = vec![0.0f32; self.values.len()];
        for y in 0..h {
            for x in 0..w {
                let mut sum = 0.0;
                for (k, weight) in kernel.iter().enumerate() {
                    let xx = (x + k as isize - radius).rem_euclid(w);
                    sum += weight * self.values[(y * w + xx) as usize];
                }
                row_pass[(y * w + x) as usize] = sum / norm;
            }
        }
        for y in 0..h {
            for x in 0..w {
                let mut sum = 0.0;
                for (k, weight) in kernel.iter().enumerate() {
                    let yy = (y + k as isize - radius).clamp(0, h - 1);
                    sum += weight * row_pass[(yy * w + x) as usize];
                }
                self.values[(y * w + x) as usize] = sum / norm;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampling_wraps_in_longitude_and_hits_pixel_centres() {
        let map = HeightMap::new(4, 2, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]).unwrap();
        // Centre of pixel (0, 0): lon −135, lat 45.
        assert!((map.sample(-135.0, 45.0) - 1.0).abs() < 1e-6);
        // Halfway between the last and first column across the seam.
        assert!((map.sample(180.0, 45.0) - 2.5).abs() < 1e-6);
        assert!((map.sample(-180.0, 45.0) - 2.5).abs() < 1e-6);
        // Poles clamp.
        assert!((map.sample(-135.0, 90.0) - 1.0).abs() < 1e-6);
        assert!((map.sample(-135.0, -90.0) - 5.0).abs() < 1e-6);
    }

    #[test]
    fn smoothing_keeps_the_mean_and_flattens_a_spike() {
        let mut values = vec![0.0; 32 * 16];
        values[8 * 32 + 16] = 100.0;
        let mut map = HeightMap::new(32, 16, values).unwrap();
        map.smooth(1.5);
        let sum: f32 = map.values().iter().sum();
        assert!((sum - 100.0).abs() < 0.5, "{sum}");
        assert!(map.range().1 < 10.0);
    }
}
