//! Prints the statistics of a few frames of the perfect sphere (auto camera).
fn main() {
    let size: u32 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(500);
    let threads: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(2);
    let scene = spatch_sphere::build_sphere(&spatch_sphere::SphereOptions::default())
        .unwrap()
        .scene;
    let prepared = spatch_render::PreparedScene::new(&scene);
    let camera = prepared.auto_camera(size, size).unwrap();
    let mut options = spatch_render::RenderOptions::default();
    options.threads = threads;
    let mut r = spatch_render::Renderer::new(options).unwrap();
    let mut last = None;
    for _ in 0..20 {
        last = Some(r.render(&prepared, &camera).unwrap());
    }
    let out = last.unwrap();
    let mut s = out.stats.clone();
    s.options = None;
    println!("{}", serde_json::to_string_pretty(&s).unwrap());
}
