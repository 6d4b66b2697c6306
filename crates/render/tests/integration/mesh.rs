//! The public triangle rasterizer on plain meshes.

use glam::{DVec3, Vec3};
use spatch_render::{
    rasterize_triangles, Camera, Culling, MeshColours, RenderError, RenderOptions, TriangleMesh,
};

/// A unit square at z = 0 in the xy plane (counter-clockwise seen from +z).
fn square() -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let p = vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];
    (p, vec![[0, 1, 2], [0, 2, 3]])
}

#[test]
fn a_square_covers_exactly_the_pixel_centres_inside_its_projection() {
    let (p, t) = square();
    let origin = DVec3::new(1e6, -2e6, 5e5); // far from the origin: f64 offset keeps precision
    let mesh = TriangleMesh::new(origin, &p, &t, MeshColours::None).unwrap();
    // 90° fov at distance 2: the square spans half the image.
    let camera = Camera::look_at(origin + DVec3::Z * 2.0, origin, DVec3::Y, 90.0, 64, 64).unwrap();
    let out = rasterize_triangles(&mesh, &camera, &RenderOptions::default()).unwrap();
    let img = &out.image;
    for y in 0..64 {
        for x in 0..64 {
            let inside = (16..48).contains(&x) && (16..48).contains(&y);
            assert_eq!(img.is_covered(x, y), inside, "pixel {x},{y}");
        }
    }
    let d = img.depth()[32 * 64 + 32];
    assert!((d - 2.0).abs() < 1e-3, "{d}");
}

#[test]
fn back_faces_are_culled_or_lit_from_behind() {
    let (p, t) = square();
    let mesh = TriangleMesh::new(DVec3::ZERO, &p, &t, MeshColours::None).unwrap();
    let behind = Camera::look_at(DVec3::Z * -2.0, DVec3::ZERO, DVec3::Y, 90.0, 32, 32).unwrap();
    let mut back = RenderOptions::default();
    back.culling = Culling::Back;
    let culled = rasterize_triangles(&mesh, &behind, &back).unwrap();
    assert_eq!(culled.image.covered_count(), 0);
    assert_eq!(culled.stats.triangles_culled, 2);
    // The square is open: automatic culling (the default) draws its back.
    assert!(!mesh.is_closed());
    let auto = rasterize_triangles(&mesh, &behind, &RenderOptions::default()).unwrap();
    assert_eq!(auto.image.covered_count(), 16 * 16);
    let mut o = RenderOptions::default();
    o.culling = Culling::None;
    let two_sided = rasterize_triangles(&mesh, &behind, &o).unwrap();
    assert_eq!(two_sided.image.covered_count(), 16 * 16);
}

#[test]
fn per_corner_colours_reach_the_image_and_bad_meshes_are_refused() {
    let (p, t) = square();
    let red = [[255, 0, 0, 255]; 6];
    let mesh = TriangleMesh::new(DVec3::ZERO, &p, &t, MeshColours::PerCorner(&red)).unwrap();
    let camera = Camera::look_at(DVec3::Z * 2.0, DVec3::ZERO, DVec3::Y, 90.0, 32, 32).unwrap();
    let out = rasterize_triangles(&mesh, &camera, &RenderOptions::default()).unwrap();
    let c = out.image.pixels()[16 * 32 + 16];
    assert!(c[0] > 100 && c[1] < 60 && c[2] < 60, "{c:?}");
    assert!(matches!(
        TriangleMesh::new(DVec3::ZERO, &p, &[[0, 1, 4]], MeshColours::None),
        Err(RenderError::TriangleIndexOutOfRange { vertex: 4, .. })
    ));
    assert!(matches!(
        TriangleMesh::new(DVec3::ZERO, &[Vec3::NAN], &[], MeshColours::None),
        Err(RenderError::NonFiniteVertex { vertex: 0 })
    ));
    assert!(TriangleMesh::new(DVec3::ZERO, &p, &t, MeshColours::PerVertex(&red)).is_err());
}
