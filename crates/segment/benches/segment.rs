//! Criterion bench of the segmenter on the Stanford bunny (bun_zipper.ply, 69,451 triangles):
//! each stage alone and the whole pipeline. Skips (with a message) when ../shared/data is
//! missing. Run with
//! `CARGO_TARGET_DIR=/work/target-segment cargo bench -p spatch-segment --bench segment`.

use criterion::{criterion_group, criterion_main, Criterion};
use spatch_mesh::{build_face_adjacency, load_mesh, prepare_mesh, PrepareOptions};
use spatch_segment::{grow_cones, grow_secondary, merge_regions, segment, SegmentOptions};

fn bench_bunny(c: &mut Criterion) {
    let Some(path) = spatch_fixtures::shared_data("bunny/reconstruction/bun_zipper.ply") else {
        return;
    };
    let loaded = match load_mesh(&path) {
        Ok(loaded) => loaded,
        Err(err) => {
            eprintln!("skipping: {err}");
            return;
        }
    };
    let (mesh, _) = prepare_mesh(&loaded.mesh, &PrepareOptions::default());
    let adjacency = build_face_adjacency(&mesh);
    let options = SegmentOptions::default();
    let Ok(preliminary) = grow_cones(&mesh, &adjacency, &options) else {
        return;
    };
    let Ok(secondary) = grow_secondary(&mesh, &adjacency, &preliminary, &options) else {
        return;
    };

    let mut group = c.benchmark_group("segment_bunny");
    group.sample_size(20);
    group.bench_function("cone_growing", |b| {
        b.iter(|| grow_cones(&mesh, &adjacency, &options))
    });
    group.bench_function("secondary_growth", |b| {
        b.iter(|| grow_secondary(&mesh, &adjacency, &preliminary, &options))
    });
    group.bench_function("merge", |b| {
        b.iter(|| merge_regions(&mesh, &adjacency, &secondary, &options))
    });
    group.bench_function("all_stages", |b| {
        b.iter(|| segment(&mesh, &adjacency, &options))
    });
    group.finish();
}

criterion_group!(benches, bench_bunny);
criterion_main!(benches);
