//! Polygon triangulation: one 200,000-corner concave face (a star whose inner corners are all
//! reflex), triangulated directly and loaded from an OBJ file (parse + triangulate + build).
//!
//! Issue 22's target: the OBJ face loads in under a second (the old fan took 21.6 s for
//! 20,000 corners downstream, because its triangles overlapped).
//! Run: `cargo bench -p spatch-mesh --bench triangulate`.

use std::fmt::Write as _;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::DVec3;
use spatch_mesh::{load_mesh, triangulate_polygon};

/// A star with `n` corners alternating between radius 1 and 0.5, tilted out of the axis planes.
fn star(n: usize) -> Vec<DVec3> {
    let q = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.7, -0.4, 1.9);
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            let r = if k % 2 == 0 { 1.0 } else { 0.5 };
            q * DVec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect()
}

fn big_face(c: &mut Criterion) {
    let points = star(200_000);
    let dir = tempfile::tempdir().expect("a temporary folder");
    let path = dir.path().join("star.obj");
    let mut text = String::new();
    for p in &points {
        writeln!(text, "v {} {} {}", p.x, p.y, p.z).expect("writing to a string");
    }
    text.push('f');
    for k in 1..=points.len() {
        write!(text, " {k}").expect("writing to a string");
    }
    text.push('\n');
    std::fs::write(&path, text).expect("the OBJ is written");

    let mut group = c.benchmark_group("star_200k");
    group.sample_size(10);
    group.bench_function("triangulate_polygon", |b| {
        let mut out = Vec::with_capacity(points.len());
        b.iter(|| {
            out.clear();
            triangulate_polygon(&points, &mut out)
        })
    });
    group.bench_function("load_obj", |b| {
        b.iter(|| load_mesh(&path).expect("the star loads"))
    });
    group.finish();
}

criterion_group!(benches, big_face);
criterion_main!(benches);
