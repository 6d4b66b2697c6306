//! Clouds generated for the tests, and the checks every conversion must pass.

use glam::{DVec3, Vec3};
use spatch_cloud::{
    cloud_to_scene, measure_cloud_error, CloudConversion, CloudErrorReport, CloudOptions,
};
use spatch_mesh::{PointCloud, SplitMix64};

/// A cloud from positions alone.
pub(crate) fn cloud(origin: DVec3, positions: Vec<Vec3>) -> PointCloud {
    PointCloud {
        origin,
        positions,
        colours: None,
        normals: None,
    }
}

/// Standard normal samples from a seeded generator (Box–Muller).
pub(crate) struct Gaussian(SplitMix64);

impl Gaussian {
    pub(crate) fn new(seed: u64) -> Gaussian {
        Gaussian(SplitMix64::new(seed))
    }

    pub(crate) fn sample(&mut self) -> f32 {
        let a = 1.0 - self.0.next_f64();
        let b = self.0.next_f64();
        ((-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()) as f32
    }

    pub(crate) fn vector(&mut self) -> Vec3 {
        Vec3::new(self.sample(), self.sample(), self.sample())
    }
}

/// A jittered `n × n` grid of step `step` on the plane `z = slope · x`.
pub(crate) fn tilted_plane(n: usize, step: f32, slope: f32, seed: u64) -> Vec<Vec3> {
    let mut rng = SplitMix64::new(seed);
    (0..n * n)
        .map(|k| {
            let x = ((k % n) as f64 + rng.next_f64() * 0.5 - 0.25) as f32 * step;
            let y = ((k / n) as f64 + rng.next_f64() * 0.5 - 0.25) as f32 * step;
            Vec3::new(x, y, slope * x)
        })
        .collect()
}

/// `n` points spread evenly on a sphere of radius `r` around the origin.
pub(crate) fn sphere(n: usize, r: f32) -> Vec<Vec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|k| {
            let z = 1.0 - (2.0 * k as f64 + 1.0) / n as f64;
            let s = (1.0 - z * z).sqrt();
            let phi = golden * k as f64;
            Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, z as f32) * r
        })
        .collect()
}

/// Converts with `options` and measures the error.
pub(crate) fn convert_and_measure(
    cloud: &PointCloud,
    options: &CloudOptions,
) -> (CloudConversion, CloudErrorReport) {
    let conversion = cloud_to_scene(cloud, options).expect("conversion succeeds");
    let error = measure_cloud_error(cloud, &conversion.scene, conversion.report.spacing)
        .expect("error is measurable");
    (conversion, error)
}

/// The targets: fewer nodes than points, `cloud_to_patch` RMS at most half the
/// spacing, at least 99 % of the points within twice the spacing.
pub(crate) fn assert_targets(
    name: &str,
    cloud: &PointCloud,
    c: &CloudConversion,
    e: &CloudErrorReport,
) {
    let r = &c.report;
    eprintln!(
        "{name}: {} points, {} patches, {} nodes ({} filled), spacing {:.3e}; cloud_to_patch rms {:.3e} ({:.3} s), max {:.3e}, beyond 2s {:.4} %; node_to_cloud rms {:.3e}",
        cloud.len(),
        r.counts.patches,
        r.counts.nodes,
        r.counts.filled_nodes,
        r.spacing,
        e.cloud_to_patch.distance.rms,
        e.cloud_to_patch.distance.rms / e.spacing,
        e.cloud_to_patch.distance.max,
        e.cloud_to_patch.share_beyond_2x_spacing * 100.0,
        e.node_to_cloud.rms,
    );
    assert!(
        r.counts.nodes < cloud.len(),
        "{name}: {} nodes for {} points",
        r.counts.nodes,
        cloud.len()
    );
    assert!(
        e.cloud_to_patch.distance.rms <= 0.5 * e.spacing,
        "{name}: rms {} vs spacing {}",
        e.cloud_to_patch.distance.rms,
        e.spacing
    );
    assert!(
        e.cloud_to_patch.share_beyond_2x_spacing <= 0.01,
        "{name}: {} beyond 2 spacings",
        e.cloud_to_patch.share_beyond_2x_spacing
    );
}
