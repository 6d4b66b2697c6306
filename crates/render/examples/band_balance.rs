//! How evenly a scene's frame shares out over the threads: per band, the
//! median time to draw and resolve it, and per thread, the median time
//! spent in bands (the raster stage's critical path is the busiest
//! thread's).
//!
//! `band_balance FILE.spatch [SIZE=500] [THREADS=2] [FRAMES=40]` (the
//! automatic camera of `spatch render`).
use spatch_render::{Camera, PreparedScene, RenderOptions, Renderer};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let arg = |k: usize| std::env::args().nth(k);
    let path = arg(1).expect("usage: band_balance FILE.spatch [SIZE] [THREADS] [FRAMES]");
    let size: u32 = arg(2).and_then(|s| s.parse().ok()).unwrap_or(500);
    let threads: usize = arg(3).and_then(|s| s.parse().ok()).unwrap_or(2);
    let frames: usize = arg(4).and_then(|s| s.parse().ok()).unwrap_or(40).max(1);
    let scene = spatch_format::read_scene(std::path::Path::new(&path)).expect("scene");
    let prepared = PreparedScene::new(&scene);
    let (centre, radius) = prepared.bounding_sphere().expect("a patch");
    let eye = Camera::framing(centre, radius, 40.0, size, size)
        .expect("camera")
        .eye();
    let camera = Camera::look_at(eye, centre, glam::DVec3::Y, 40.0, size, size).expect("camera");
    let mut options = RenderOptions::default();
    options.threads = threads;
    let mut r = Renderer::new(options).expect("renderer");
    let mut all = Vec::new();
    for k in 0..frames + 2 {
        let out = r.render(&prepared, &camera).expect("frame");
        if k >= 2 {
            all.push(out.stats);
        }
        r.recycle(out.image);
    }
    let bands = all[0].bands.len();
    println!("band  y0 rows items  median_ms");
    for b in 0..bands {
        let s = all[0].bands[b];
        let ms = median(all.iter().map(|f| f.bands[b].ms).collect());
        println!("{b:4} {:4} {:4} {:5} {ms:10.3}", s.y0, s.rows, s.items);
    }
    let busy = |f: &spatch_render::RenderStats, t: usize| -> f64 {
        f.bands.iter().filter(|b| b.thread == t).map(|b| b.ms).sum()
    };
    let per_thread: Vec<f64> = (0..threads)
        .map(|t| median(all.iter().map(|f| busy(f, t)).collect()))
        .collect();
    let max_share = median(
        all.iter()
            .map(|f| {
                let total: f64 = f.bands.iter().map(|b| b.ms).sum();
                let max = (0..threads).map(|t| busy(f, t)).fold(0.0, f64::max);
                max / total
            })
            .collect(),
    );
    println!("busiest thread's share of band time (median over frames): {max_share:.3}");
    println!("per thread, median ms in bands: {per_thread:.3?}");
    let pick = |f: fn(&spatch_render::RenderStats) -> f64| median(all.iter().map(f).collect());
    println!(
        "median ms: frame {:.3}, plan_wall {:.3}, raster_wall {:.3}",
        pick(|s| s.times_ms.total_wall),
        pick(|s| s.times_ms.plan_wall),
        pick(|s| s.times_ms.raster_wall)
    );
}
