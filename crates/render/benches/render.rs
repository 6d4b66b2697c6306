//! Frame time of the perfect sphere (radius 128, 1362 patches of 17×17).
//!
//! Machine, thread counts and figures: docs/performance.md. Run with
//! `CARGO_TARGET_DIR=... cargo bench -p spatch-render --bench render`.
//!
//! - `sphere_500/patches_phong_2t`: the target (≤ 5 ms), auto camera;
//! - `sphere_500/triangles_phong_2t`: the same view in triangle mode;
//! - `sphere_1000/patches_phong_{1,2}t`: thread scaling.

use criterion::{criterion_group, criterion_main, Criterion};
use spatch_render::{PreparedScene, RenderMode, RenderOptions, Renderer};

fn sphere() -> PreparedScene {
    let scene = spatch_sphere::build_sphere(&spatch_sphere::SphereOptions::default())
        .expect("sphere")
        .scene;
    PreparedScene::new(&scene)
}

fn bench(c: &mut Criterion) {
    let scene = sphere();
    for (size, cases) in [
        (
            500u32,
            vec![
                ("patches_phong_2t", RenderMode::Patches, 2),
                ("triangles_phong_2t", RenderMode::Triangles, 2),
            ],
        ),
        (
            1000,
            vec![
                ("patches_phong_1t", RenderMode::Patches, 1),
                ("patches_phong_2t", RenderMode::Patches, 2),
            ],
        ),
    ] {
        let camera = scene.auto_camera(size, size).expect("camera");
        let mut group = c.benchmark_group(format!("sphere_{size}"));
        for (name, mode, threads) in cases {
            let mut options = RenderOptions::default();
            options.mode = mode;
            options.threads = threads;
            let mut renderer = Renderer::new(options).expect("renderer");
            group.bench_function(name, |b| {
                b.iter(|| {
                    let out = renderer.render(&scene, &camera).expect("frame");
                    renderer.recycle(out.image);
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
