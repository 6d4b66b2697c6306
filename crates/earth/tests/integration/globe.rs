use glam::DVec3;
use spatch_earth::{build_globe, equirectangular_uv, ColourMap, GlobeOptions, HeightMap};

fn flat_map() -> ColourMap {
    ColourMap::from_rgba(8, 4, [30, 60, 150, 255].repeat(32)).unwrap()
}

#[test]
fn about_forty_thousand_triangles_of_similar_size_on_a_closed_sphere() {
    let heights = HeightMap::new(8, 4, vec![0.0; 32]).unwrap();
    let globe = build_globe(&flat_map(), &heights, &GlobeOptions::default()).unwrap();
    let mesh = &globe.mesh;
    assert_eq!(globe.frequency, 45);
    assert_eq!(mesh.triangles.len(), 40_500);
    assert!(globe.area_ratio < 2.0, "area ratio {}", globe.area_ratio);
    // Closed: Euler characteristic 2, every edge shared by exactly two faces.
    assert_eq!(mesh.positions.len() as i64 - 3 * 40_500 / 2 + 40_500, 2);
    let adjacency = spatch_mesh::build_face_adjacency(mesh);
    assert_eq!(adjacency.boundary_edge_count(), 0);
    assert_eq!(adjacency.non_manifold_edge_count(), 0);
    for face in mesh.faces() {
        let centre = mesh.face_centroid(face).as_dvec3() + mesh.origin;
        assert!(
            mesh.face_normal(face).as_dvec3().dot(centre) > 0.0,
            "inward face {face:?}"
        );
    }
    for k in 0..mesh.positions.len() {
        let r = mesh
            .world_position(spatch_mesh::VertexId(k as u32))
            .length();
        assert!((r - 128.0).abs() < 1e-3, "{r}");
    }
}

#[test]
fn texture_coordinates_stay_continuous_across_the_seam_and_poles() {
    let heights = HeightMap::new(8, 4, vec![0.0; 32]).unwrap();
    let globe = build_globe(&flat_map(), &heights, &GlobeOptions::default()).unwrap();
    let uvs = globe.mesh.face_uvs.as_ref().unwrap();
    for corners in uvs {
        let us: Vec<f32> = corners.iter().map(|c| c.x).collect();
        let span = us.iter().cloned().fold(f32::MIN, f32::max)
            - us.iter().cloned().fold(f32::MAX, f32::min);
        let at_pole = corners.iter().any(|c| c.y > 0.9999 || c.y < 0.0001);
        if at_pole {
            // Around a pole the five icosahedron edges fan out 72° apart.
            assert!(
                span <= 0.2 + 1e-5,
                "a polar triangle spans {span} of the texture width"
            );
        } else {
            // A triangle is about 1.3° across; in longitude that widens by 1/cos(latitude).
            let widest_lat = corners
                .iter()
                .map(|c| ((c.y - 0.5) * std::f32::consts::PI).abs())
                .fold(0.0, f32::max);
            assert!(
                span * widest_lat.cos() < 0.01,
                "a triangle spans {span} of the texture width"
            );
        }
    }
}

#[test]
fn heights_displace_along_the_normal_without_cracks() {
    // A map whose height depends on longitude only, with a jump at the seam
    // that a crack-prone builder would tear open.
    let values: Vec<f32> = (0..4).flat_map(|_| (0..8).map(|x| x as f32)).collect();
    let heights = HeightMap::new(8, 4, values).unwrap();
    let globe = build_globe(&flat_map(), &heights, &GlobeOptions::default()).unwrap();
    let adjacency = spatch_mesh::build_face_adjacency(&globe.mesh);
    assert_eq!(
        adjacency.boundary_edge_count(),
        0,
        "the seam or a pole cracked open"
    );
    // The vertex facing +Z (lon 0, lat 0) carries the height sampled there.
    let front = (0..globe.mesh.positions.len())
        .map(|k| globe.mesh.world_position(spatch_mesh::VertexId(k as u32)))
        .max_by(|a, b| {
            a.normalize()
                .dot(DVec3::Z)
                .total_cmp(&b.normalize().dot(DVec3::Z))
        })
        .unwrap();
    let (u, v) = equirectangular_uv(front.normalize());
    let expected = 128.0 + f64::from(heights.sample(u * 360.0 - 180.0, v * 180.0 - 90.0));
    assert!((front.length() - expected).abs() < 1e-3);
}

#[test]
fn bad_options_are_refused() {
    let heights = HeightMap::new(8, 4, vec![0.0; 32]).unwrap();
    let mut options = GlobeOptions::default();
    options.triangles = 3;
    assert!(build_globe(&flat_map(), &heights, &options).is_err());
    let mut options = GlobeOptions::default();
    options.radius = f64::NAN;
    assert!(build_globe(&flat_map(), &heights, &options).is_err());
}

#[test]
fn issue_20_relief_larger_than_the_radius_is_refused() {
    let heights = HeightMap::new(8, 4, vec![1.5; 32]).unwrap();
    let mut options = GlobeOptions::default();
    options.triangles = 80;
    for exaggeration in [1e20, -1e20, 86.0] {
        options.exaggeration = exaggeration;
        let err = build_globe(&flat_map(), &heights, &options).unwrap_err();
        assert!(
            matches!(err, spatch_earth::EarthError::ReliefTooLarge { .. }),
            "{err}"
        );
        assert!(err.to_string().contains("at most 85.3333"), "{err}");
    }
    options.exaggeration = 85.0;
    assert!(build_globe(&flat_map(), &heights, &options).is_ok());
}
