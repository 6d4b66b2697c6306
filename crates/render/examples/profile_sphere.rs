//! Prints the statistics of a few frames of the perfect sphere (auto camera).
//!
//! `profile_sphere [SIZE=500] [THREADS=2] [FRAMES=20] [patches|triangles|trimmed]`
//! (`trimmed`: patches, prepared with overlaps trimmed);
//! under `valgrind --tool=callgrind`, run it with 1 and with N + 1 frames
//! and take the difference over N for the instructions of one frame.
fn main() {
    let arg = |k: usize| std::env::args().nth(k);
    let size: u32 = arg(1).and_then(|s| s.parse().ok()).unwrap_or(500);
    let threads: usize = arg(2).and_then(|s| s.parse().ok()).unwrap_or(2);
    let frames: usize = arg(3).and_then(|s| s.parse().ok()).unwrap_or(20).max(1);
    let triangles = arg(4).is_some_and(|m| m == "triangles");
    let trimmed = arg(4).is_some_and(|m| m == "trimmed");
    let scene = spatch_sphere::build_sphere(&spatch_sphere::SphereOptions::default())
        .unwrap()
        .scene;
    let prepared = if trimmed {
        spatch_render::PreparedScene::trimming_overlaps(&scene)
    } else {
        spatch_render::PreparedScene::new(&scene)
    };
    let camera = prepared.auto_camera(size, size).unwrap();
    let mut options = spatch_render::RenderOptions::default();
    options.threads = threads;
    if triangles {
        options.mode = spatch_render::RenderMode::Triangles;
    }
    let mut r = spatch_render::Renderer::new(options).unwrap();
    let mut last: Option<spatch_render::RenderOutput> = None;
    for _ in 0..frames {
        if let Some(previous) = last.take() {
            r.recycle(previous.image);
        }
        last = Some(r.render(&prepared, &camera).unwrap());
    }
    let out = last.unwrap();
    let mut s = out.stats.clone();
    s.options = None;
    println!("{}", serde_json::to_string_pretty(&s).unwrap());
    // FNV-1a over colour and depth bits: equal hashes = identical images.
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let bytes = out.image.pixels().iter().flatten().copied();
    let depth = out
        .image
        .depth()
        .iter()
        .flat_map(|d| d.to_bits().to_le_bytes());
    for b in bytes.chain(depth) {
        h = (h ^ b as u64).wrapping_mul(0x100_0000_01b3);
    }
    println!("image hash {h:016x}");
}
