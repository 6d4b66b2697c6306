//! Writes a point cloud sampled from the Stanford bunny (`bun_zipper.ply` of the shared data),
//! optionally with Gaussian noise, as a binary little-endian PLY: the 1 M-point clouds of the
//! throughput and memory figures in docs/algorithms/cloud.md and docs/performance.md.
//!
//! ```sh
//! cargo run --release -p spatch-cloud --example bunny_cloud -- 1000000 bunny1m.ply [NOISE]
//! ```
//!
//! `NOISE` is the standard deviation per axis in model units (metres; the bench's noisy cloud
//! uses 1e-4). The samples are uniform over the surface area (seed 2001) and the noise is
//! seeded (7), so the same arguments give the same file; the points are those of the
//! `from_cloud` bench (`benches/from_cloud.rs`) for 1 M points.

use glam::Vec3;
use spatch_mesh::{load_mesh, sample_surface, SplitMix64};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        return Err("usage: bunny_cloud POINTS OUT.ply [NOISE]".into());
    }
    let count: usize = args[0].parse()?;
    let noise: f32 = args.get(2).map_or(Ok(0.0), |v| v.parse())?;
    let path = spatch_fixtures::shared_data("bunny/reconstruction/bun_zipper.ply")
        .ok_or("../shared/data/bunny/reconstruction/bun_zipper.ply not found")?;
    let mesh = load_mesh(&path)?.mesh;
    let mut rng = SplitMix64::new(7);
    let mut gauss = || {
        // Box-Muller from two uniforms in (0, 1].
        let a = 1.0 - rng.next_f64();
        let b = rng.next_f64();
        ((-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()) as f32
    };
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\ncomment {count} points sampled from bun_zipper.ply\n\
         element vertex {count}\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
    )
    .into_bytes();
    for sample in sample_surface(&mesh, count, 2001) {
        let p = sample.point + Vec3::new(gauss(), gauss(), gauss()) * noise;
        for v in (mesh.origin + p.as_dvec3()).to_array() {
            bytes.extend_from_slice(&(v as f32).to_le_bytes());
        }
    }
    std::fs::write(&args[1], bytes)?;
    Ok(())
}
