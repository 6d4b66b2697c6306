//! Mesh tiles own every face exactly once: the tile whose box holds the face's centroid, and
//! that tile reads the face.

use glam::{DVec3, Vec3};
use spatch_convert::{world_centroid, PartOwner};
use spatch_mesh::TriangleMesh;
use spatch_tiling::{make_mesh_plan, mesh_tile, TileOwner};

#[test]
fn every_face_has_exactly_one_owner_tile_which_reads_it() {
    let torus = spatch_fixtures::shapes::torus(2.0, 0.7, 48, 24);
    let positions = torus.positions.iter().map(|&p| Vec3::from(p)).collect();
    let mut mesh = TriangleMesh::new(positions, torus.triangles.clone()).unwrap();
    // Far from the world origin, as a survey's coordinates are.
    mesh.origin = DVec3::new(512_000.25, 6_400_000.5, 120.0);
    let plan = make_mesh_plan(&mesh, "torus.obj".as_ref(), 1.3, 0.1, 0.05).unwrap();
    assert!(plan.tiles.len() >= 9, "{} tiles", plan.tiles.len());
    let mut owners = vec![0u32; mesh.triangles.len()];
    for tile in &plan.tiles {
        let part = mesh_tile(&mesh, &tile.buffered);
        let owner = TileOwner {
            bounds: &tile.bounds,
        };
        let mut owned_here = 0;
        for f in part.faces() {
            if owner.owns_point(world_centroid(&part, f)) {
                owned_here += 1;
            }
        }
        for f in mesh.faces() {
            if owner.owns_point(world_centroid(&mesh, f)) {
                owners[f.index()] += 1;
            }
        }
        // The part holds every face the tile owns, at the same world centroid.
        let owned_whole = mesh
            .faces()
            .filter(|&f| owner.owns_point(world_centroid(&mesh, f)))
            .count();
        assert_eq!(owned_here, owned_whole, "tile {}", tile.index);
    }
    let wrong: Vec<(usize, u32)> = owners
        .iter()
        .enumerate()
        .filter(|&(_, &n)| n != 1)
        .map(|(f, &n)| (f, n))
        .collect();
    assert!(wrong.is_empty(), "faces not owned once: {wrong:?}");
}
