//! Frame time of the perfect sphere (radius 128, 1362 patches of 17×17).
//!
//! Machine, thread counts and figures: docs/performance.md. Run with
//! `CARGO_TARGET_DIR=... cargo bench -p spatch-render --bench render`.
//!
//! - `sphere_500/patches_phong_2t`: the target (≤ 5 ms), auto camera;
//! - `sphere_500/triangles_phong_2t`: the same view in triangle mode;
//! - `sphere_500/patches_phong_2t_trimmed`: the target view, the scene
//!   prepared with overlaps trimmed (`--trim-overlaps`);
//! - `sphere_1000/patches_phong_{1,2}t`: thread scaling;
//! - `prepare/sphere_{kept,trimmed}`: the one-off preparation, without and
//!   with the overlap trimming.

use criterion::{criterion_group, criterion_main, Criterion};
use spatch_format::Scene;
use spatch_render::{PreparedScene, RenderMode, RenderOptions, Renderer};

fn sphere() -> Scene {
    spatch_sphere::build_sphere(&spatch_sphere::SphereOptions::default())
        .expect("sphere")
        .scene
}

fn bench(c: &mut Criterion) {
    let source = sphere();
    let (kept, trimmed) = (
        PreparedScene::new(&source),
        PreparedScene::trimming_overlaps(&source),
    );
    for (size, cases) in [
        (
            500u32,
            vec![
                ("patches_phong_2t", RenderMode::Patches, 2, &kept),
                ("triangles_phong_2t", RenderMode::Triangles, 2, &kept),
                ("patches_phong_2t_trimmed", RenderMode::Patches, 2, &trimmed),
            ],
        ),
        (
            1000,
            vec![
                ("patches_phong_1t", RenderMode::Patches, 1, &kept),
                ("patches_phong_2t", RenderMode::Patches, 2, &kept),
            ],
        ),
    ] {
        let camera = kept.auto_camera(size, size).expect("camera");
        let mut group = c.benchmark_group(format!("sphere_{size}"));
        for (name, mode, threads, scene) in cases {
            let mut options = RenderOptions::default();
            options.mode = mode;
            options.threads = threads;
            let mut renderer = Renderer::new(options).expect("renderer");
            group.bench_function(name, |b| {
                b.iter(|| {
                    let out = renderer.render(scene, &camera).expect("frame");
                    renderer.recycle(out.image);
                })
            });
        }
        group.finish();
    }
    let mut group = c.benchmark_group("prepare");
    group.sample_size(20);
    group.bench_function("sphere_kept", |b| b.iter(|| PreparedScene::new(&source)));
    group.bench_function("sphere_trimmed", |b| {
        b.iter(|| PreparedScene::trimming_overlaps(&source))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
