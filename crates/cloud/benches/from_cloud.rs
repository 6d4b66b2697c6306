//! Criterion bench of `cloud_to_scene` on 1M points sampled from the Stanford bunny
//! (`bun_zipper.ply`), clean and with Gaussian noise. Skips when ../shared/data is missing.

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use spatch_cloud::{cloud_to_scene, CloudOptions, SmoothOptions};
use spatch_mesh::{load_mesh, sample_surface, PointCloud, SplitMix64};

const POINTS: usize = 1_000_000;

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

fn bench(c: &mut Criterion) {
    let Some(clean) = bunny_cloud(0.0) else {
        return;
    };
    let mut group = c.benchmark_group("from_cloud");
    group.sample_size(10);
    group.bench_function("bunny_1m_clean", |b| {
        b.iter(|| cloud_to_scene(&clean, &CloudOptions::default()).map(|c| c.bytes.len()))
    });
    drop(clean);
    if let Some(noisy) = bunny_cloud(1e-4) {
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
