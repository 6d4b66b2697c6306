//! Mesh builders for the fitter's tests.

use glam::Vec3;
use spatch_fit::{fit_regions, FitOptions, FitOutput, FitRegion};
use spatch_mesh::{build_face_adjacency, FaceId, TriangleMesh};

/// A mesh from a fixtures shape.
pub(crate) fn mesh_of(shape: &spatch_fixtures::Shape) -> TriangleMesh {
    TriangleMesh::new(
        shape.positions.iter().map(|&p| Vec3::from(p)).collect(),
        shape.triangles.clone(),
    )
    .unwrap()
}

/// Adds a grid of `n × n` quads spanning `corner + [0,1]·u + [0,1]·v`, two triangles each,
/// wound so that their normal points along `facing`.
pub(crate) fn add_sheet(
    positions: &mut Vec<Vec3>,
    triangles: &mut Vec<[u32; 3]>,
    corner: Vec3,
    (u, v): (Vec3, Vec3),
    n: u32,
    facing: Vec3,
) {
    let base = positions.len() as u32;
    for j in 0..=n {
        for i in 0..=n {
            let (a, b) = (i as f32 / n as f32, j as f32 / n as f32);
            positions.push(corner + u * a + v * b);
        }
    }
    let flip = u.cross(v).dot(facing) < 0.0;
    let at = |i: u32, j: u32| base + j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            let (p00, p10, p01, p11) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
            for t in [[p00, p10, p11], [p00, p11, p01]] {
                triangles.push(if flip { [t[0], t[2], t[1]] } else { t });
            }
        }
    }
}

/// A horizontal unit square at height `z`, `n × n` quads, facing +z.
pub(crate) fn square(n: u32, z: f32) -> TriangleMesh {
    let (mut p, mut t) = (Vec::new(), Vec::new());
    add_sheet(
        &mut p,
        &mut t,
        Vec3::new(0.0, 0.0, z),
        (Vec3::X, Vec3::Y),
        n,
        Vec3::Z,
    );
    TriangleMesh::new(p, t).unwrap()
}

/// All faces of `mesh` whose normal satisfies `keep`.
pub(crate) fn faces_where(mesh: &TriangleMesh, keep: impl Fn(Vec3) -> bool) -> Vec<FaceId> {
    mesh.faces()
        .filter(|&f| keep(mesh.face_normal(f)))
        .collect()
}

/// Fits one region with the given spacing (other options default unless `tune` changes them).
pub(crate) fn fit_one(
    mesh: &TriangleMesh,
    faces: &[FaceId],
    axis: Vec3,
    spacing: f32,
    tune: impl FnOnce(&mut FitOptions),
) -> FitOutput {
    let adjacency = build_face_adjacency(mesh);
    let mut options = FitOptions::default();
    options.spacing = Some(spacing);
    tune(&mut options);
    fit_regions(mesh, &adjacency, &[FitRegion { faces, axis }], &options).unwrap()
}

/// Every filled node of the output, in mesh coordinates.
pub(crate) fn nodes(out: &FitOutput) -> Vec<Vec3> {
    out.patches
        .iter()
        .flat_map(|p| p.filled_nodes().map(|(_, _, q)| q).collect::<Vec<_>>())
        .collect()
}
