//! How the sharp-edge patches of a tiled box cover its twelve edges, against one
//! conversion of the whole box: the figures of `docs/scale.md` ("Meshes", sharp edges).
//!
//! `cargo run --release -p spatch-tiling --example edge_cover -- BOX.obj SPACING WHOLE.spatch
//! TILE.spatch...` reads the source box (an axis-aligned box; its edges are those of its
//! bounding box), the node spacing the files were converted at, the whole conversion and
//! the tile files, and prints for the whole file and for the tiles joined:
//!
//! - patches, and of them **edge-like** ones: every filled node within 1.2 spacings of one
//!   box edge (the edge patches' strips reach 0.8 spacings onto each face; surface patches
//!   span many cells), and **corner-like** ones: every node within 1.5 spacings of a box
//!   corner;
//! - along the box edges (sampled every 1/8 spacing, leaving out 2 spacings at each end,
//!   where corner patches take over), the length covered by **no** edge-like patch, by
//!   **one**, and by **two or more**. Each patch covers the stretch its filled nodes span
//!   along the edge, less 1.5 spacings at each end (an edge piece's lattice reaches
//!   1.4 spacings past its piece, with the default strip, so that consecutive pieces
//!   overlap; the 0.1 more keeps a node's rounding from counting as a duplicate). A
//!   stretch covered twice is a crease made twice (by two tiles); a stretch covered by none
//!   is closed by the surface patches or left open, which the hole fraction tells;
//! - the hole fraction over the 14 standard views (`spatch_eval::hole_fraction`).
//!
//! `edge_cover --box OUT.obj` writes the box measured there: `spatch_fixtures::grid_box`
//! of 48 × 36 × 24 cells of 1/12 (4 × 3 × 2, 14 976 faces).

use std::path::Path;

use glam::DVec3;
use spatch_eval::{hole_fraction, HoleOptions};
use spatch_format::{read_scene, Patch, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, out] = args.as_slice() {
        if flag == "--box" {
            let shape = spatch_fixtures::grid_box([48, 36, 24], 1.0 / 12.0);
            std::fs::write(out, shape.to_obj([0.0; 3]))?;
            return Ok(());
        }
    }
    let [source, spacing, whole, tiles @ ..] = args.as_slice() else {
        return Err("usage: edge_cover BOX.obj SPACING WHOLE.spatch TILE.spatch...".into());
    };
    let spacing: f64 = spacing.parse()?;
    let mesh = spatch_mesh::load_mesh(Path::new(source))?.mesh;
    let (lo, hi) = mesh_bounds(&mesh);
    let edges = box_edges(lo, hi);
    let whole = read_scene(Path::new(whole))?;
    let tiles: Vec<Scene> = tiles
        .iter()
        .map(|t| read_scene(Path::new(t)))
        .collect::<Result<_, _>>()?;
    let joined = Scene::merge(
        tiles
            .into_iter()
            .filter(|s| !s.patches().is_empty())
            .collect(),
    )?;
    println!("scene   patches  edge-like  corner-like  none m  once m  twice+ m  holes");
    for (name, scene) in [("whole", &whole), ("tiles", &joined)] {
        let cover = edge_cover(scene, &edges, spacing);
        let holes = hole_fraction(scene, &mesh, &HoleOptions::default())?;
        println!(
            "{name:<7} {:>7}  {:>9}  {:>11}  {:>6.3}  {:>6.3}  {:>8.3}  {:.5} %",
            scene.patches().len(),
            cover.edge_like,
            cover.corner_like,
            cover.lengths[0],
            cover.lengths[1],
            cover.lengths[2],
            holes.fraction * 100.0
        );
    }
    Ok(())
}

/// The lowest and highest world corners of `mesh`'s vertices.
fn mesh_bounds(mesh: &spatch_mesh::TriangleMesh) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for p in &mesh.positions {
        let w = mesh.origin + p.as_dvec3();
        (lo, hi) = (lo.min(w), hi.max(w));
    }
    (lo, hi)
}

/// The twelve edges of the box `lo..hi`, as (start, end).
fn box_edges(lo: DVec3, hi: DVec3) -> Vec<(DVec3, DVec3)> {
    let corner = |bits: usize| {
        DVec3::new(
            if bits & 1 == 1 { hi.x } else { lo.x },
            if bits & 2 == 2 { hi.y } else { lo.y },
            if bits & 4 == 4 { hi.z } else { lo.z },
        )
    };
    let mut edges = Vec::new();
    for bits in 0..8 {
        for axis in [1, 2, 4] {
            if bits & axis == 0 {
                edges.push((corner(bits), corner(bits | axis)));
            }
        }
    }
    edges
}

/// What [`edge_cover`] measured.
struct Cover {
    edge_like: usize,
    corner_like: usize,
    /// Edge length covered by none, one, two or more edge-like patches.
    lengths: [f64; 3],
}

/// See the module docs.
fn edge_cover(scene: &Scene, edges: &[(DVec3, DVec3)], spacing: f64) -> Cover {
    let mut spans: Vec<Vec<(f64, f64)>> = vec![Vec::new(); edges.len()];
    let (mut edge_like, mut corner_like) = (0, 0);
    let corners: Vec<DVec3> = edges.iter().flat_map(|&(a, b)| [a, b]).collect();
    for patch in scene.patches() {
        let nodes = filled_positions(patch, scene.offset());
        if nodes.is_empty() {
            continue;
        }
        let near_corner = corners
            .iter()
            .any(|&c| nodes.iter().all(|n| n.distance(c) <= 1.5 * spacing));
        if near_corner {
            corner_like += 1;
            continue;
        }
        for (k, &(a, b)) in edges.iter().enumerate() {
            let dir = (b - a).normalize();
            let along = |n: &DVec3| (*n - a).dot(dir);
            let off = |n: &DVec3| (*n - a - dir * along(n)).length();
            if nodes.iter().all(|n| off(n) <= 1.2 * spacing) {
                edge_like += 1;
                let (t0, t1) = nodes
                    .iter()
                    .map(along)
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), t| {
                        (l.min(t), h.max(t))
                    });
                spans[k].push((t0 + 1.5 * spacing, t1 - 1.5 * spacing));
                break;
            }
        }
    }
    let mut lengths = [0.0; 3];
    let step = spacing / 8.0;
    for (&(a, b), spans) in edges.iter().zip(&spans) {
        let length = a.distance(b);
        let mut t = 2.0 * spacing;
        while t <= length - 2.0 * spacing {
            let n = spans.iter().filter(|&&(l, h)| l <= t && t <= h).count();
            lengths[n.min(2)] += step;
            t += step;
        }
    }
    Cover {
        edge_like,
        corner_like,
        lengths,
    }
}

/// World positions of `patch`'s filled nodes in a scene at `offset`.
fn filled_positions(patch: &Patch, offset: DVec3) -> Vec<DVec3> {
    patch
        .filled_nodes()
        .filter_map(|(i, j, _)| patch.model_position(offset, i, j))
        .collect()
}
