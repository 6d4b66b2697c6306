//! The same input and options give byte-identical files whatever the thread count.

use glam::DVec3;
use spatch_cloud::{cloud_to_scene, CloudOptions, SmoothOptions};

use crate::clouds::{cloud, sphere, Gaussian};

#[test]
fn one_and_two_threads_give_the_same_bytes() {
    let mut noise = Gaussian::new(11);
    let points = sphere(30_000, 1.0)
        .into_iter()
        .map(|p| p + noise.vector() * 0.003)
        .collect();
    let c = cloud(DVec3::new(3.0, 4.0, 5.0), points);
    let mut options = CloudOptions::default();
    options.smooth = Some(SmoothOptions::default());
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| cloud_to_scene(&c, &options).unwrap().bytes)
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(2));
}
