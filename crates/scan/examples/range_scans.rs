//! Writes a registered scan set made from a mesh: `SCANS` orthographic range scans, each a
//! square grid of rays from its own direction (spread over the sphere, then turned by a seeded
//! random angle), keeping the first hit of each ray that meets the surface at less than 84°
//! from its normal, with Gaussian depth noise and a small seeded misregistration per scan
//! (a random shift), as `scan_KK.ply` files and a Stanford `scans.conf` listing them with
//! their poses. Like the Stanford raw scans, each file is in its scanner's frame (image
//! axes x and y, the scanner looking down −z) and holds a `range_grid` element (the ray of
//! each point: `obj_info num_cols / num_rows`, one list of 0 or 1 vertex index per ray,
//! row-major), and its `bmesh` line gives the pose to the mesh's frame. It is a scan set of
//! another object than the bunny, and a ~1 M-point multi-scan set, for the figures of
//! docs/algorithms/cloud.md.
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
//!
//! `--cover` (anywhere among the arguments) plans the directions as a scan campaign would,
//! to see the whole surface instead of spreading them evenly: of [`CANDIDATES`] directions
//! spread over the sphere, each scan takes the one that sees the most surface area no
//! earlier scan saw (greedy set cover, "next best view"). A face is seen from a direction
//! when the ray from outside through its centroid hits it first at less than 60° from its
//! normal (a face seen only at grazing angles gets sparse, noisy samples). Prints the share of the area seen. Evenly spread directions leave concave or
//! shadowed parts unseen (bun_zipper's far ear, the mannequin's neck).

use std::io::Write;
use std::path::{Path, PathBuf};

use glam::{DMat3, DQuat, DVec3, Vec3};
use rayon::prelude::*;
use spatch_mesh::{load_mesh, Bvh, SplitMix64, TriangleMesh};

/// Largest angle between a ray and the surface normal at its hit that a scanner records
/// (cosine).
const MIN_COSINE: f32 = 0.1;

/// Smallest cosine between a face's normal and a direction for `--cover` to count the face
/// as seen from it (60°): a face seen only at grazing angles gets sparse, noisy samples.
const PLAN_COSINE: f32 = 0.5;

/// Directions `--cover` chooses from.
const CANDIDATES: usize = 256;

/// Faces `--cover` tests for visibility (spread evenly over the face list).
const COVER_FACES: usize = 40_000;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let job = Job::from_args()?;
    let mesh = &job.mesh;
    let bvh = Bvh::new(mesh);
    let radius = bvh.bounds().diagonal() / 2.0;
    let mut gauss = gaussian(SplitMix64::new(19));
    let planned = job.cover.then(|| covering_views(mesh, &bvh, job.scans));
    let mut conf = String::new();
    let mut total = 0;
    for k in 0..job.scans {
        let even = spread_direction(k, job.scans, gauss());
        let view = planned.as_ref().map_or(even, |v| v[k]);
        let u = view.any_orthonormal_vector();
        let offset = Vec3::new(gauss(), gauss(), gauss()) * job.shift * radius;
        let pose = ScanPose {
            view,
            u,
            w: view.cross(u),
            offset,
        };
        let cells = job.grid * job.grid;
        let noises: Vec<f32> = (0..cells).map(|_| gauss() * job.noise * radius).collect();
        let rays = cast_scan(mesh, &bvh, &pose, job.grid, &noises);
        conf.push_str(&write_scan(&job, k, &rays, &pose)?);
        total += rays.len();
    }
    std::fs::write(job.dir.join("scans.conf"), conf)?;
    println!(
        "{} scans, {total} points in {}",
        job.scans,
        job.dir.display()
    );
    Ok(())
}

/// What the command line asks for (see the module docs), the mesh loaded and the output
/// folder created.
struct Job {
    mesh: TriangleMesh,
    scans: usize,
    grid: usize,
    dir: PathBuf,
    noise: f32,
    shift: f32,
    cover: bool,
}

impl Job {
    /// Reads the command line, loads the mesh and creates the output folder.
    fn from_args() -> Result<Job, Box<dyn std::error::Error>> {
        let mut args: Vec<String> = std::env::args().skip(1).collect();
        let cover = args.iter().any(|a| a == "--cover");
        args.retain(|a| a != "--cover");
        if args.len() < 4 {
            return Err(
                "usage: range_scans MESH SCANS GRID OUT_DIR [NOISE] [SHIFT] [--cover]".into(),
            );
        }
        let mesh = load_mesh(&args[0])?.mesh;
        let scans: usize = args[1].parse()?;
        let grid: usize = args[2].parse()?;
        let dir = PathBuf::from(&args[3]);
        let noise: f32 = args.get(4).map_or(Ok(0.0005), |v| v.parse())?;
        let shift: f32 = args.get(5).map_or(Ok(0.0015), |v| v.parse())?;
        std::fs::create_dir_all(&dir)?;
        Ok(Job {
            mesh,
            scans,
            grid,
            dir,
            noise,
            shift,
            cover,
        })
    }
}

/// Standard normal samples (Box–Muller) drawn from `rng`.
fn gaussian(mut rng: SplitMix64) -> impl FnMut() -> f32 {
    move || {
        let a = 1.0 - rng.next_f64();
        let b = rng.next_f64();
        ((-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()) as f32
    }
}

/// Direction `k` of `count` spread evenly over the sphere (a Fibonacci direction), turned by
/// `turn` radians about z so that no scan lines up with an axis.
fn spread_direction(k: usize, count: usize, turn: f32) -> Vec3 {
    let z = 1.0 - (2.0 * k as f32 + 1.0) / count as f32;
    let phi = k as f32 * std::f32::consts::PI * (3.0 - 5f32.sqrt()) + turn;
    let s = (1.0 - z * z).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z).normalize()
}

/// One scan's pose: the direction it looks from, its image axes and its misregistration.
struct ScanPose {
    /// From the mesh toward the scanner.
    view: Vec3,
    /// Image axes.
    u: Vec3,
    w: Vec3,
    /// The shift added to every point of the scan.
    offset: Vec3,
}

/// The hits of a `grid × grid` square of rays of the scan `pose` over the mesh's bounding
/// sphere: per ray hitting the surface within about 84° of its normal, the ray's index
/// and the hit moved by its depth noise (`noises`, one per ray) and the scan's offset.
fn cast_scan(
    mesh: &TriangleMesh,
    bvh: &Bvh,
    pose: &ScanPose,
    grid: usize,
    noises: &[f32],
) -> Vec<(usize, Vec3)> {
    let bounds = bvh.bounds();
    let (centre, radius) = (bounds.centre(), bounds.diagonal() / 2.0);
    let ScanPose { view, u, w, offset } = *pose;
    let step = 2.0 * radius / grid as f32;
    (0..grid * grid)
        .into_par_iter()
        .filter_map(|r| {
            let (a, b) = ((r % grid) as f32 + 0.5, (r / grid) as f32 + 0.5);
            let origin =
                centre + view * 2.0 * radius + u * (a * step - radius) + w * (b * step - radius);
            let hit = bvh.ray_cast(origin, -view, 0.0, 4.0 * radius)?;
            let normal = mesh.face_normal(hit.face);
            (normal.dot(view).abs() >= MIN_COSINE)
                .then(|| (r, origin - view * (hit.t + noises[r]) + offset))
        })
        .collect()
}

/// Writes scan `k` of `job` (its `rays`, see [`write_ply`]) as `scan_KK.ply` in the output
/// folder, in the frame of its `pose`; returns its line of `scans.conf`.
fn write_scan(
    job: &Job,
    k: usize,
    rays: &[(usize, Vec3)],
    pose: &ScanPose,
) -> std::io::Result<String> {
    let name = format!("scan_{k:02}.ply");
    // The scanner's frame: image axes u and w, the scanner on the +view side.
    let frame = DMat3::from_cols(pose.u.as_dvec3(), pose.w.as_dvec3(), pose.view.as_dvec3());
    write_ply(&job.dir.join(&name), rays, job.grid, job.mesh.origin, frame)?;
    // The .conf gives the conjugate of the frame's rotation (docs/algorithms/scan.md).
    let q = DQuat::from_mat3(&frame).conjugate();
    Ok(format!(
        "bmesh {name} 0 0 0 {} {} {} {}\n",
        q.x, q.y, q.z, q.w
    ))
}

/// The `count` directions of `--cover` (see the module docs), in the order chosen.
fn covering_views(mesh: &TriangleMesh, bvh: &Bvh, count: usize) -> Vec<Vec3> {
    let bounds = bvh.bounds();
    let radius = bounds.diagonal() / 2.0;
    let stride = mesh.face_count().div_ceil(COVER_FACES).max(1);
    let faces: Vec<_> = mesh.faces().step_by(stride).collect();
    let areas: Vec<f32> = faces.iter().map(|&f| mesh.face_area(f)).collect();
    let candidates: Vec<Vec3> = (0..CANDIDATES)
        .map(|k| {
            let z = 1.0 - (2.0 * k as f32 + 1.0) / CANDIDATES as f32;
            let phi = k as f32 * std::f32::consts::PI * (3.0 - 5f32.sqrt());
            let s = (1.0 - z * z).sqrt();
            Vec3::new(s * phi.cos(), s * phi.sin(), z)
        })
        .collect();
    let seen: Vec<Vec<bool>> = candidates
        .par_iter()
        .map(|&view| {
            faces
                .iter()
                .map(|&f| {
                    let at = mesh.face_centroid(f);
                    let origin = at + view * 4.0 * radius;
                    let first = bvh.ray_cast(origin, -view, 0.0, 8.0 * radius);
                    first.is_some_and(|h| h.face == f)
                        && mesh.face_normal(f).dot(view).abs() >= PLAN_COSINE
                })
                .collect()
        })
        .collect();
    let mut covered = vec![false; faces.len()];
    let mut chosen = Vec::with_capacity(count);
    for _ in 0..count {
        let gain = |c: usize| -> f32 {
            (0..faces.len())
                .filter(|&f| seen[c][f] && !covered[f])
                .map(|f| areas[f])
                .sum()
        };
        let best = (0..candidates.len())
            .max_by(|&a, &b| gain(a).total_cmp(&gain(b)))
            .unwrap_or(0);
        for (c, s) in covered.iter_mut().zip(&seen[best]) {
            *c |= s;
        }
        chosen.push(candidates[best]);
    }
    let total: f32 = areas.iter().sum();
    let seen_area: f32 = (0..faces.len())
        .filter(|&f| covered[f])
        .map(|f| areas[f])
        .sum();
    let ever: f32 = (0..faces.len())
        .filter(|&f| seen.iter().any(|s| s[f]))
        .map(|f| areas[f])
        .sum();
    println!(
        "--cover: the {count} scans see {:.2} % of the area ({} faces tested); all {CANDIDATES} candidates {:.2} %",
        100.0 * seen_area / total,
        faces.len(),
        100.0 * ever / total
    );
    chosen
}

/// Writes the hits of `rays` (ray index in a `grid × grid` image, point relative to
/// `origin`) as a binary little-endian PLY in the scanner's `frame` (world = frame · local),
/// with their `range_grid`.
fn write_ply(
    path: &Path,
    rays: &[(usize, Vec3)],
    grid: usize,
    origin: DVec3,
    frame: DMat3,
) -> std::io::Result<()> {
    let mut file = std::io::BufWriter::new(std::fs::File::create(path)?);
    write!(
        file,
        "ply\nformat binary_little_endian 1.0\nobj_info num_cols {grid}\nobj_info num_rows {grid}\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element range_grid {}\nproperty list uchar int vertex_indices\nend_header\n",
        rays.len(),
        grid * grid
    )?;
    let to_local = frame.transpose();
    for (_, p) in rays {
        for v in (to_local * (origin + p.as_dvec3())).to_array() {
            file.write_all(&(v as f32).to_le_bytes())?;
        }
    }
    let mut cells = vec![None; grid * grid];
    for (k, &(r, _)) in rays.iter().enumerate() {
        cells[r] = Some(k as i32);
    }
    for cell in cells {
        match cell {
            Some(k) => {
                file.write_all(&[1])?;
                file.write_all(&k.to_le_bytes())?;
            }
            None => file.write_all(&[0])?,
        }
    }
    file.flush()
}
