//! Writes a registered scan set made from a mesh: `SCANS` orthographic range scans, each a
//! square grid of rays from its own direction (spread over the sphere, then turned by a seeded
//! random angle), keeping the first hit of each ray that meets the surface at less than 84°
//! from its normal, with Gaussian depth noise and a small seeded misregistration per scan
//! (a random shift), as `scan_KK.ply` files and a Stanford `scans.conf` listing them with
//! identity poses. It is a scan set of another object than the bunny, and a ~1 M-point
//! multi-scan set, for the figures of docs/algorithms/cloud.md.
//!
//! ```sh
//! cargo run --release -p spatch-scan --example range_scans -- MESH SCANS GRID OUT_DIR [NOISE] [SHIFT]
//! spatch from-cloud OUT_DIR/scans.conf -o x.spatch
//! ```
//!
//! `GRID` rays a side over the mesh's bounding sphere; `NOISE` and `SHIFT` (standard
//! deviations of the depth noise and of each scan's shift, per axis) are fractions of the
//! bounding radius (defaults 0.0005 and 0.0015, as the synthetic 12-scan set of
//! docs/performance.md).

use std::io::Write;
use std::path::Path;

use glam::Vec3;
use rayon::prelude::*;
use spatch_mesh::{load_mesh, Bvh, SplitMix64};

/// Largest angle between a ray and the surface normal at its hit that a scanner records
/// (cosine).
const MIN_COSINE: f32 = 0.1;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        return Err("usage: range_scans MESH SCANS GRID OUT_DIR [NOISE] [SHIFT]".into());
    }
    let mesh = load_mesh(&args[0])?.mesh;
    let scans: usize = args[1].parse()?;
    let grid: usize = args[2].parse()?;
    let dir = Path::new(&args[3]);
    let noise: f32 = args.get(4).map_or(Ok(0.0005), |v| v.parse())?;
    let shift: f32 = args.get(5).map_or(Ok(0.0015), |v| v.parse())?;
    std::fs::create_dir_all(dir)?;
    let bvh = Bvh::new(&mesh);
    let bounds = bvh.bounds();
    let (centre, radius) = (bounds.centre(), bounds.diagonal() / 2.0);
    let mut rng = SplitMix64::new(19);
    let mut gauss = move || {
        let a = 1.0 - rng.next_f64();
        let b = rng.next_f64();
        ((-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()) as f32
    };
    let mut conf = String::new();
    let mut total = 0;
    for k in 0..scans {
        // A Fibonacci direction, turned at random so that no scan lines up with an axis.
        let z = 1.0 - (2.0 * k as f32 + 1.0) / scans as f32;
        let phi = k as f32 * std::f32::consts::PI * (3.0 - 5f32.sqrt()) + gauss();
        let s = (1.0 - z * z).sqrt();
        let view = Vec3::new(s * phi.cos(), s * phi.sin(), z).normalize();
        let u = view.any_orthonormal_vector();
        let w = view.cross(u);
        let offset = Vec3::new(gauss(), gauss(), gauss()) * shift * radius;
        let noises: Vec<f32> = (0..grid * grid).map(|_| gauss() * noise * radius).collect();
        let step = 2.0 * radius / grid as f32;
        let points: Vec<Vec3> = (0..grid * grid)
            .into_par_iter()
            .filter_map(|r| {
                let (a, b) = ((r % grid) as f32 + 0.5, (r / grid) as f32 + 0.5);
                let origin = centre
                    + view * 2.0 * radius
                    + u * (a * step - radius)
                    + w * (b * step - radius);
                let hit = bvh.ray_cast(origin, -view, 0.0, 4.0 * radius)?;
                let normal = mesh.face_normal(hit.face);
                (normal.dot(view).abs() >= MIN_COSINE)
                    .then(|| origin - view * (hit.t + noises[r]) + offset)
            })
            .collect();
        let name = format!("scan_{k:02}.ply");
        write_ply(&dir.join(&name), &points, mesh.origin)?;
        conf.push_str(&format!("bmesh {name} 0 0 0 0 0 0 1\n"));
        total += points.len();
    }
    std::fs::write(dir.join("scans.conf"), conf)?;
    println!("{scans} scans, {total} points in {}", dir.display());
    Ok(())
}

/// Writes `points` (relative to `origin`) as a binary little-endian PLY in world coordinates.
fn write_ply(path: &Path, points: &[Vec3], origin: glam::DVec3) -> std::io::Result<()> {
    let mut file = std::io::BufWriter::new(std::fs::File::create(path)?);
    write!(
        file,
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        points.len()
    )?;
    for p in points {
        for v in (origin + p.as_dvec3()).to_array() {
            file.write_all(&(v as f32).to_le_bytes())?;
        }
    }
    file.flush()
}
