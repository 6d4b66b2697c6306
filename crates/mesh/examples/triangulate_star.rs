//! Times the triangulation of one concave polygon face: a star of N corners (default
//! 200,000) alternating between radius 1 and 0.5, written as an OBJ face and loaded.
//!
//! Run: `cargo run --release -p spatch-mesh --example triangulate_star -- 200000`
//! (prints the load time and the triangle count; wrap in `/usr/bin/time` for CPU time on a
//! shared machine).

use std::fmt::Write as _;
use std::time::Instant;

use spatch_mesh::load_mesh;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: usize = match std::env::args().nth(1) {
        Some(a) => a.parse()?,
        None => 200_000,
    };
    let mut text = String::new();
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let r = if k % 2 == 0 { 1.0 } else { 0.5 };
        writeln!(text, "v {} {} 0", r * a.cos(), r * a.sin())?;
    }
    text.push('f');
    for k in 1..=n {
        write!(text, " {k}")?;
    }
    text.push('\n');
    let dir = std::env::temp_dir().join(format!("spatch-star-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let path = dir.join("star.obj");
    std::fs::write(&path, text)?;
    let start = Instant::now();
    let loaded = load_mesh(&path);
    let seconds = start.elapsed().as_secs_f64();
    std::fs::remove_dir_all(&dir)?;
    let loaded = loaded?;
    println!(
        "{n} corners: {} triangles, loaded in {seconds:.3} s",
        loaded.mesh.triangles.len()
    );
    Ok(())
}
