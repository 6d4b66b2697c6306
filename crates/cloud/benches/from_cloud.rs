//! Criterion bench of `cloud_to_scene` on 1M points sampled from the Stanford bunny
//! (`bun_zipper.ply`), clean and with Gaussian noise (σ = 0.1 mm per axis, smoothed). Skips
//! when ../shared/data is missing.
//!
//! With `SPATCH_CLOUD_BENCH_PLY=<prefix>` it also writes both clouds as binary PLY files
//! (`<prefix>_clean.ply`, `<prefix>_noisy.ply`) for end-to-end runs of `spatch from-cloud`
//! (see docs/algorithms/cloud.md for the commands and figures).

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use spatch_cloud::{cloud_to_scene, CloudOptions, SmoothOptions};
use spatch_mesh::{load_mesh, sample_surface, PointCloud, SplitMix64};

const POINTS: usize = 1_000_000;

/// Standard deviation of the Gaussian noise per axis (model units: metres).
const NOISE: f32 = 1.0e-4;

fn bunny_cloud(noise: f32) -> Option<PointCloud> {
    let path = spatch_fixtures::shared_data("bunny/reconstruction/bun_zipper.ply")?;
    let mesh = load_mesh(&path).ok()?.mesh;
    let samples = sample_surface(&mesh, POINTS, 2001);
    let mut rng = SplitMix64::new(7);
    let mut gauss = || {
        // Box-Muller from two uniforms in (0, 1].
        let a = 1.0 - rng.next_f64();
        let b = rng.next_f64();
        ((-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()) as f32
    };
    let positions = samples
        .iter()
        .map(|s| s.point + Vec3::new(gauss(), gauss(), gauss()) * noise)
        .collect();
    Some(PointCloud {
        origin: mesh.origin,
        positions,
        colours: None,
        normals: None,
    })
}

/// Writes `cloud` as a binary little-endian PLY (world coordinates as f32).
fn write_ply(cloud: &PointCloud, path: &str) -> std::io::Result<()> {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\ncomment {} points sampled from bun_zipper.ply\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        cloud.len(),
        cloud.len()
    )
    .into_bytes();
    for i in 0..cloud.len() {
        for v in cloud.world_position(i).to_array() {
            bytes.extend_from_slice(&(v as f32).to_le_bytes());
        }
    }
    std::fs::write(path, bytes)
}

fn bench(c: &mut Criterion) {
    let Some(clean) = bunny_cloud(0.0) else {
        return;
    };
    if let Ok(prefix) = std::env::var("SPATCH_CLOUD_BENCH_PLY") {
        let written = write_ply(&clean, &format!("{prefix}_clean.ply")).and_then(|()| {
            bunny_cloud(NOISE).map_or(Ok(()), |noisy| {
                write_ply(&noisy, &format!("{prefix}_noisy.ply"))
            })
        });
        if let Err(e) = written {
            eprintln!("cannot write the PLY files: {e}");
        }
    }
    let mut group = c.benchmark_group("from_cloud");
    group.sample_size(10);
    group.bench_function("bunny_1m_clean", |b| {
        b.iter(|| cloud_to_scene(&clean, &CloudOptions::default()).map(|c| c.bytes.len()))
    });
    drop(clean);
    if let Some(noisy) = bunny_cloud(NOISE) {
        let mut options = CloudOptions::default();
        options.smooth = Some(SmoothOptions::default());
        group.bench_function("bunny_1m_noisy_smooth", |b| {
            b.iter(|| cloud_to_scene(&noisy, &options).map(|c| c.bytes.len()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
