//! Colour grids: a textured quad keeps a checkerboard finer than its nodes.

use glam::{Vec2, Vec3};
use spatch_fit::{fit_regions, FitOptions, FitRegion};
use spatch_mesh::{build_face_adjacency, FaceId, Material, MaterialId, Texture, TriangleMesh};

/// Texels per side of the checkerboard texture, and texels per square (an odd number of
/// squares, so the pattern is the same whichever way the texture's rows run).
const TEXELS: u32 = 72;
const SQUARE: u32 = 8;

fn checker(u: f32, v: f32) -> [u8; 3] {
    let (i, j) = ((u * TEXELS as f32) as u32, (v * TEXELS as f32) as u32);
    if (i / SQUARE + j / SQUARE).is_multiple_of(2) {
        [230, 40, 20]
    } else {
        [20, 60, 240]
    }
}

/// The unit square `z = 0` of two triangles, UVs = `(x, y)` with `v` down the texture (its
/// rows run from the top), textured with the checkerboard.
fn checker_quad() -> TriangleMesh {
    let mut mesh = TriangleMesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
        vec![[0, 1, 2], [2, 1, 3]],
    )
    .unwrap();
    let mut rgba = Vec::new();
    for row in 0..TEXELS {
        for col in 0..TEXELS {
            let [r, g, b] = checker(
                (col as f32 + 0.5) / TEXELS as f32,
                (row as f32 + 0.5) / TEXELS as f32,
            );
            rgba.extend_from_slice(&[r, g, b, 255]);
        }
    }
    let mut material = Material::white("checker");
    material.texture = Some(Texture::new(TEXELS, TEXELS, rgba).unwrap());
    mesh.materials = vec![material];
    mesh.face_materials = vec![MaterialId(0); 2];
    let uv = |p: Vec3| Vec2::new(p.x, p.y);
    mesh.face_uvs = Some(
        mesh.faces()
            .map(|f| mesh.face_positions(f).map(uv))
            .collect(),
    );
    mesh
}

/// The albedo at patch position `(x, y)` (grid units) as a renderer reads it: the colour
/// grid's bilinear sample, or the corner nodes' colours interpolated bilinearly.
fn albedo(patch: &spatch_format::Patch, x: f32, y: f32) -> [f32; 3] {
    if let Some(g) = patch.colour_grid() {
        return g.albedo_at(x, y);
    }
    let cols = usize::from(patch.grid().cols());
    let (i, j) = (
        (x as usize).min(cols - 2),
        (y as usize).min(usize::from(patch.grid().rows()) - 2),
    );
    let (a, b) = (x - i as f32, y - j as f32);
    let c = patch.colours().unwrap();
    let at = |i: usize, j: usize, k: usize| f32::from(c[j * cols + i][k]);
    std::array::from_fn(|k| {
        let top = at(i, j, k) * (1.0 - a) + at(i + 1, j, k) * a;
        let bottom = at(i, j + 1, k) * (1.0 - a) + at(i + 1, j + 1, k) * a;
        top * (1.0 - b) + bottom * b
    })
}

/// PSNR (dB) of the fitted patch's albedo against the checkerboard, over a 300 × 300
/// lattice of points of the quad, and the patch's colour grid factor.
fn albedo_psnr(options: &FitOptions) -> (f64, Option<u8>) {
    let mesh = checker_quad();
    let adjacency = build_face_adjacency(&mesh);
    let faces = [FaceId(0), FaceId(1)];
    let region = FitRegion {
        faces: &faces,
        axis: Vec3::Z,
    };
    let out = fit_regions(&mesh, &adjacency, &[region], options).unwrap();
    assert_eq!(out.patches.len(), 1);
    let patch = &out.patches[0];
    let frame = patch.frame();
    let [ax, ay, _] = frame.axes();
    let (cols, rows) = (
        patch.grid().cols() as f32 - 1.0,
        patch.grid().rows() as f32 - 1.0,
    );
    let (mut squared, mut count) = (0.0f64, 0usize);
    let n = 300;
    for sj in 0..=n {
        for si in 0..=n {
            let (x, y) = (cols * si as f32 / n as f32, rows * sj as f32 / n as f32);
            let p = frame.origin() + ax * x + ay * y;
            if !((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y)) {
                continue;
            }
            let want = checker(p.x, p.y);
            let got = albedo(patch, x, y);
            for k in 0..3 {
                squared += (f64::from(got[k]) - f64::from(want[k])).powi(2);
            }
            count += 3;
        }
    }
    assert!(count > 0);
    let mse = squared / count as f64;
    (
        10.0 * (255.0f64 * 255.0 / mse).log10(),
        patch.colour_grid().map(|g| g.factor()),
    )
}

#[test]
fn a_colour_grid_keeps_a_checkerboard_the_nodes_cannot() {
    let mut options = FitOptions::default();
    options.spacing = Some(0.25);
    options.texels_per_node = 0.0;
    options.colour_grid_texels = 1.0;
    let (with_grid, factor) = albedo_psnr(&options);
    assert_eq!(factor, Some(18));
    options.colour_grid_texels = 0.0;
    let (nodes, factor) = albedo_psnr(&options);
    assert_eq!(factor, None);
    // Nodes every 18 texels on 8-texel squares alias; the grid's samples, one per texel,
    // miss only the squares' borders.
    assert!(
        with_grid > 15.0 && nodes < 10.0,
        "grid {with_grid:.2} dB, nodes {nodes:.2} dB"
    );
}
