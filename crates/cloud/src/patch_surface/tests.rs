//! Tests of the patch surface index: every query path against a linear scan.

use super::*;
use spatch_mesh::SplitMix64;

/// A wavy sheet of `n × n` cells, in patches of `per` cells a side, with a gap.
fn sheet(n: usize, per: usize) -> (Vec<Quad>, Vec<u32>) {
    let h = |x: f32, y: f32| (x * 3.0).sin() * 0.1 + y * y * 0.2;
    let step = 1.0 / n as f32;
    let at = |i: usize, j: usize| {
        let (x, y) = (i as f32 * step, j as f32 * step);
        Vec3::new(x, y, h(x, y))
    };
    let (mut quads, mut owners) = (Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..n {
            if (n / 3..n / 2).contains(&i) && (n / 3..n / 2).contains(&j) {
                continue;
            }
            quads.push([at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]);
            owners.push(((j / per) * n.div_ceil(per) + i / per) as u32);
        }
    }
    (quads, owners)
}

fn linear_scan(p: Vec3, quads: &[Quad], owners: &[u32]) -> (f32, u32) {
    let (mut best, mut owner) = (f32::INFINITY, NO_PATCH);
    for (q, &o) in quads.iter().zip(owners) {
        let d = distance_to_quad(p, q);
        if d < best || (d == best && o < owner) {
            (best, owner) = (d, o);
        }
    }
    (best, owner)
}

#[test]
fn morton_interleaves_bits() {
    assert_eq!(spread(0b1011), 0b001_000_001_001);
    let b = Node {
        lo: Vec3::ZERO,
        hi: Vec3::ONE,
    };
    assert_eq!(morton(Vec3::ZERO, &b), 0);
    assert_eq!(morton(Vec3::ONE, &b), (1u64 << 63) - 1);
    assert_eq!(morton(Vec3::splat(-5.0), &b), 0);
}

#[test]
fn nearest_equals_a_linear_scan() {
    let (quads, owners) = sheet(40, 7);
    let surface = PatchSurface::from_quads(&quads, &owners).unwrap();
    assert_eq!(surface.cell_count(), quads.len());
    let mut rng = SplitMix64::new(3);
    let mut r = |lo: f32, hi: f32| lo + (hi - lo) * rng.next_f64() as f32;
    // Near the sheet, in the gap, off its rim, and far away.
    let points: Vec<Vec3> = (0..3000)
        .map(|k| {
            let spread = [0.01, 0.2, 3.0, 1e4][k % 4];
            Vec3::new(
                r(-spread, 1.0 + spread),
                r(-spread, 1.0 + spread),
                r(-spread, spread),
            )
        })
        .collect();
    let (all_d, all_o) = surface.nearest_all(&points);
    for (k, &p) in points.iter().enumerate() {
        let expected = linear_scan(p, &quads, &owners);
        assert_eq!(surface.nearest(p), expected, "{p}");
        assert_eq!((all_d[k], all_o[k]), expected, "{p}");
    }
}

/// Random twisted quads of sizes spread over three decades, a few of them long slivers
/// (the grid's extras), in a unit cube.
fn quad_soup(n: usize, seed: u64) -> (Vec<Quad>, Vec<u32>) {
    let mut rng = SplitMix64::new(seed);
    let mut r = move || rng.next_f64() as f32;
    let (mut quads, mut owners) = (Vec::new(), Vec::new());
    for k in 0..n {
        let size = 10f32.powf(-3.0 + 2.0 * r()) * if k % 50 == 0 { 40.0 } else { 1.0 };
        let o = Vec3::new(r(), r(), r());
        let (u, v) = (
            Vec3::new(r(), r(), r()) - 0.5,
            Vec3::new(r(), r(), r()) - 0.5,
        );
        let twist = (Vec3::new(r(), r(), r()) - 0.5) * 0.3;
        let (u, v) = (u * size, v * size);
        quads.push([o, o + u, o + v, o + u + v + twist * size]);
        owners.push((k % 17) as u32);
    }
    (quads, owners)
}

#[test]
fn random_quad_soups_match_a_linear_scan() {
    for seed in 0..4 {
        let (quads, owners) = quad_soup(3000, seed);
        let surface = PatchSurface::from_quads(&quads, &owners).unwrap();
        assert!(surface.grid.is_some());
        let mut rng = SplitMix64::new(100 + seed);
        let mut r = move || rng.next_f64() as f32;
        let points: Vec<Vec3> = (0..4000)
            .map(|k| match k % 3 {
                // On a quad, near one, anywhere in the cube and around it.
                0 => {
                    let q = &quads[(r() * quads.len() as f32) as usize % quads.len()];
                    crate::quad_distance::bilinear(q, r(), r())
                }
                1 => {
                    let q = &quads[(r() * quads.len() as f32) as usize % quads.len()];
                    q[0] + (Vec3::new(r(), r(), r()) - 0.5) * 0.01
                }
                _ => Vec3::new(r(), r(), r()) * 3.0 - 1.0,
            })
            .collect();
        let (all_d, all_o) = surface.nearest_all(&points);
        for (k, &p) in points.iter().enumerate() {
            let expected = linear_scan(p, &quads, &owners);
            assert_eq!(surface.nearest(p), expected, "seed {seed}: {p}");
            assert_eq!((all_d[k], all_o[k]), expected, "seed {seed}: {p}");
        }
    }
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let (quads, owners) = sheet(30, 5);
    let surface = PatchSurface::from_quads(&quads, &owners).unwrap();
    let points: Vec<Vec3> = (0..5000)
        .map(|k| Vec3::new((k % 71) as f32 / 70.0, (k / 71) as f32 / 70.0, 0.05))
        .collect();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| surface.nearest_all(&points));
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| surface.nearest_all(&points));
    assert_eq!(one, two);
}

/// Two tilted, overlapping patches with empty nodes, in a scene far from the origin.
fn small_scene() -> Scene {
    use spatch_format::{ColourChannel, Frame, GridSize, Patch, EMPTY};
    let patch = |origin: Vec3, ax: Vec3, ay: Vec3, seed: u64| {
        let mut rng = SplitMix64::new(seed);
        let d: Vec<u16> = (0..81)
            .map(|k| {
                if k % 13 == 5 {
                    EMPTY
                } else {
                    (rng.next_u64() % 40) as u16
                }
            })
            .collect();
        let az = ax.cross(ay).normalize() * 0.01;
        Patch::new(
            Frame::new(origin, ax, ay, az).unwrap(),
            GridSize::new(9, 9).unwrap(),
            d,
            None,
        )
        .unwrap()
    };
    let patches = vec![
        patch(Vec3::ZERO, Vec3::X * 0.1, Vec3::Y * 0.1, 1),
        patch(
            Vec3::new(0.5, 0.2, 0.1),
            Vec3::new(0.06, 0.08, 0.0),
            Vec3::new(0.0, 0.0, 0.1),
            2,
        ),
    ];
    Scene::new(glam::DVec3::splat(1e5), ColourChannel::None, patches).unwrap()
}

/// The drawable cells of `scene` (moved by `shift`) and their patches, for a linear scan.
fn scene_quads(scene: &Scene, shift: Vec3) -> (Vec<Quad>, Vec<u32>) {
    let (mut quads, mut owners) = (Vec::new(), Vec::new());
    for (k, patch) in scene.patches().iter().enumerate() {
        let (cols, rows) = (
            usize::from(patch.grid().cols()),
            usize::from(patch.grid().rows()),
        );
        for j in 0..rows - 1 {
            for i in 0..cols - 1 {
                if patch.cell_is_drawable(i, j) {
                    let at = |a, b| patch.node_position(a, b).unwrap() + shift;
                    quads.push([at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]);
                    owners.push(k as u32);
                }
            }
        }
    }
    (quads, owners)
}

#[test]
fn scene_cells_match_a_brute_force_over_drawable_cells() {
    let scene = small_scene();
    let shift = Vec3::new(1.0, -2.0, 0.5);
    let (quads, owners) = scene_quads(&scene, shift);
    let surface = PatchSurface::new(&scene, shift).unwrap();
    assert_eq!(surface.cell_count(), quads.len());
    let mut rng = SplitMix64::new(9);
    for _ in 0..2000 {
        let mut r = || rng.next_f64() as f32 * 1.4 - 0.2;
        let p = Vec3::new(r(), r(), r() * 0.5) + shift;
        assert_eq!(surface.nearest(p), linear_scan(p, &quads, &owners), "{p}");
    }
}

#[test]
fn no_quads_no_surface() {
    assert!(PatchSurface::from_quads(&[], &[]).is_none());
}

#[test]
fn point_cells_are_searched_without_a_grid() {
    // Every quad collapsed to a point: no grid, so nearest_all queries in Morton order.
    let quads: Vec<Quad> = (0..500)
        .map(|k| [Vec3::new(k as f32 * 0.01, (k % 7) as f32 * 0.1, (k % 3) as f32); 4])
        .collect();
    let owners: Vec<u32> = (0..500).map(|k| k % 13).collect();
    let surface = PatchSurface::from_quads(&quads, &owners).unwrap();
    assert!(surface.grid.is_none());
    let points: Vec<Vec3> = (0..2000)
        .map(|k| {
            Vec3::new(
                (k % 97) as f32 * 0.06,
                (k % 11) as f32 * 0.07,
                (k % 5) as f32,
            )
        })
        .collect();
    let (all_d, all_o) = surface.nearest_all(&points);
    for (k, &p) in points.iter().enumerate() {
        assert_eq!((all_d[k], all_o[k]), linear_scan(p, &quads, &owners), "{p}");
    }
}

/// A sheet whose every fourth row of cells is stretched 12 times across it (steep cells of a
/// scan set: the grid's reach exceeds its side, so runs gather more than `MAX_GRID_CELLS`
/// grid cells), queried by points off it by up to a few cell sizes (noisy, misregistered
/// scans: beyond the first gather's margin, answered by the second).
#[test]
fn long_cells_and_points_off_the_surface_match_a_linear_scan() {
    let n = 30;
    let step = 1.0 / n as f32;
    let (mut quads, mut owners) = (Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (i as f32 * step, j as f32 * step);
            let long = if j % 4 == 0 { 12.0 * step } else { step };
            let z = |x: f32| (x * 5.0).sin() * 0.05;
            quads.push([
                Vec3::new(x, y, z(x)),
                Vec3::new(x + long, y, z(x + long)),
                Vec3::new(x, y + step, z(x)),
                Vec3::new(x + long, y + step, z(x + long)),
            ]);
            owners.push((j / 4) as u32);
        }
    }
    let surface = PatchSurface::from_quads(&quads, &owners).unwrap();
    let mut rng = SplitMix64::new(7);
    let mut r = move || rng.next_f64() as f32;
    let points: Vec<Vec3> = (0..6000)
        .map(|k| {
            let off = [0.1, 1.0, 3.0][k % 3] * step;
            Vec3::new(r(), r(), (r() - 0.5) * 2.0 * off)
        })
        .collect();
    let (all_d, all_o) = surface.nearest_all(&points);
    for (k, &p) in points.iter().enumerate() {
        assert_eq!((all_d[k], all_o[k]), linear_scan(p, &quads, &owners), "{p}");
    }
}

/// Six 17 × 17-node patches side by side on a gently waved sheet (256 cells a patch).
fn sheet_scene() -> Scene {
    use spatch_format::{ColourChannel, Frame, GridSize, Patch};
    let patches = (0..6)
        .map(|k| {
            let origin = Vec3::new((k % 3) as f32 * 1.6, (k / 3) as f32 * 1.6, 0.0);
            let d: Vec<u16> = (0..289)
                .map(|n| (20.0 + 10.0 * ((n % 17 + k) as f32 * 0.7).sin()) as u16)
                .collect();
            let frame = Frame::new(origin, Vec3::X * 0.1, Vec3::Y * 0.1, Vec3::Z * 0.01).unwrap();
            Patch::new(frame, GridSize::new(17, 17).unwrap(), d, None).unwrap()
        })
        .collect();
    Scene::new(glam::DVec3::ZERO, ColourChannel::None, patches).unwrap()
}

/// Points far from a scene of patches (beyond the grid's neighbourhood) are searched through
/// the patches' boxes (`blocks.rs`), one by one and in a batch, exactly as a linear scan.
#[test]
fn far_points_match_a_linear_scan_through_the_patches_boxes() {
    let scene = sheet_scene();
    let shift = Vec3::new(-3.0, 1.0, 2.0);
    let (quads, owners) = scene_quads(&scene, shift);
    let surface = PatchSurface::new(&scene, shift).unwrap();
    assert_eq!(surface.cell_count(), 6 * 256);
    let mut rng = SplitMix64::new(21);
    let mut r = move || rng.next_f64() as f32 * 200.0 - 100.0;
    let points: Vec<Vec3> = (0..1500)
        .map(|_| Vec3::new(r(), r(), r()) + shift)
        .collect();
    let (all_d, all_o) = surface.nearest_all(&points);
    for (k, &p) in points.iter().enumerate() {
        let expected = linear_scan(p, &quads, &owners);
        assert_eq!(surface.nearest(p), expected, "{p}");
        assert_eq!((all_d[k], all_o[k]), expected, "{p}");
    }
    assert!(surface.block_index.get().is_some() && surface.tree.get().is_none());
}
