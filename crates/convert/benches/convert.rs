//! Benchmark of the whole conversion of the Stanford bunny (`bun_zipper.ply`, 69,451
//! triangles) from file to encoded bytes, with 2 worker threads.
//!
//! Run: `cargo bench -p spatch-convert --bench convert`. Skips (prints a note) when
//! `../shared/data` is missing. Figures are recorded in `benches/README.md`.

use criterion::{criterion_group, criterion_main, Criterion};
use spatch_convert::{convert, ConvertInput, ConvertOptions};

fn bunny(c: &mut Criterion) {
    let Some(path) = spatch_fixtures::shared_data("bunny/reconstruction/bun_zipper.ply") else {
        return;
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a thread pool of 2");
    let options = ConvertOptions::default();
    let mut group = c.benchmark_group("convert");
    group.sample_size(10);
    group.bench_function("bun_zipper_2_threads", |b| {
        b.iter(|| {
            pool.install(|| convert(ConvertInput::Path(&path), &options))
                .expect("the bunny converts")
        })
    });
    group.finish();
}

criterion_group!(benches, bunny);
criterion_main!(benches);
