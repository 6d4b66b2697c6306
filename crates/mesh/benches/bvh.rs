//! BVH build and query cost on the Stanford bunny (69,451 triangles).
//!
//! Skips (prints a note, measures nothing) when `../shared/data` is missing.
//! Run: `cargo bench -p spatch-mesh --bench bvh`.

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use spatch_mesh::{load_mesh, sample_surface, Bvh, SplitMix64};

fn bunny_bvh(c: &mut Criterion) {
    let Some(path) = spatch_fixtures::shared_data("bunny/reconstruction/bun_zipper.ply") else {
        return;
    };
    let mesh = load_mesh(&path).expect("the bunny loads").mesh;
    let scale = mesh.diagonal();
    let bvh = Bvh::new(&mesh);

    // 100k queries like the evaluator's: surface samples pushed off the surface by up to 2 %
    // of the diagonal in random directions.
    let mut rng = SplitMix64::new(42);
    let queries: Vec<Vec3> = sample_surface(&mesh, 100_000, 7)
        .into_iter()
        .map(|s| {
            let offset = Vec3::new(
                rng.next_f64() as f32 - 0.5,
                rng.next_f64() as f32 - 0.5,
                rng.next_f64() as f32 - 0.5,
            );
            s.point + offset * (0.04 * scale)
        })
        .collect();
    let rays: Vec<(Vec3, Vec3)> = queries
        .iter()
        .take(100_000)
        .map(|&q| (q * 3.0, (-q).normalize_or_zero()))
        .collect();

    let mut group = c.benchmark_group("bunny");
    group.sample_size(10);
    group.bench_function("build", |b| b.iter(|| Bvh::new(&mesh)));
    group.bench_function("closest_point_100k", |b| {
        b.iter(|| {
            queries
                .iter()
                .filter_map(|&q| bvh.closest_point(q, f32::INFINITY))
                .map(|c| c.distance)
                .sum::<f32>()
        })
    });
    group.bench_function("ray_cast_100k", |b| {
        b.iter(|| {
            rays.iter()
                .filter_map(|&(o, d)| bvh.ray_cast(o, d, 0.0, f32::INFINITY))
                .count()
        })
    });
    group.finish();
}

criterion_group!(benches, bunny_bvh);
criterion_main!(benches);
