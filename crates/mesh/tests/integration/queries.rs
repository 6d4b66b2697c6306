//! BVH queries against brute force, on generated shapes, far from the origin and on the bunny.

use glam::Vec3;
use spatch_fixtures::{require_shared, shapes};
use spatch_mesh::{load_mesh, sample_surface, Bvh, FaceId, SplitMix64, TriangleMesh};

use crate::mesh_from_shape;

fn random_unit(rng: &mut SplitMix64) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.next_f64() as f32 * 2.0 - 1.0,
            rng.next_f64() as f32 * 2.0 - 1.0,
            rng.next_f64() as f32 * 2.0 - 1.0,
        );
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v / l;
        }
    }
}

/// Reference ray–triangle test in f64, written independently of the crate's: intersect the
/// plane, then test the point against the three edge half-planes.
fn reference_ray_triangle(t: [Vec3; 3], origin: Vec3, dir: Vec3) -> Option<f64> {
    let [a, b, c] = t.map(Vec3::as_dvec3);
    let (o, d) = (origin.as_dvec3(), dir.as_dvec3());
    let n = (b - a).cross(c - a);
    let denom = n.dot(d);
    if denom.abs() < 1e-300 {
        return None;
    }
    let s = n.dot(a - o) / denom;
    if s < 0.0 {
        return None;
    }
    let p = o + d * s;
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(u, v)| (v - u).cross(p - u).dot(n) >= -1e-9 * n.length_squared());
    inside.then_some(s)
}

fn brute_ray(mesh: &TriangleMesh, origin: Vec3, dir: Vec3) -> Option<(FaceId, f32)> {
    mesh.faces()
        .filter_map(|f| reference_ray_triangle(mesh.face_positions(f), origin, dir).map(|t| (f, t)))
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .map(|(f, t)| (f, t as f32))
}

/// Reference point–triangle distance in f64: the projection if it falls inside, else the
/// nearest of the three edges.
fn reference_distance(t: [Vec3; 3], p: Vec3) -> f64 {
    let [a, b, c] = t.map(Vec3::as_dvec3);
    let p = p.as_dvec3();
    let n = (b - a).cross(c - a);
    if n.length_squared() > 0.0 {
        let q = p - n * (n.dot(p - a) / n.length_squared());
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, v)| (v - u).cross(q - u).dot(n) >= 0.0);
        if inside {
            return (p - q).length();
        }
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(u, v)| {
            let e = v - u;
            let s = if e.length_squared() > 0.0 {
                ((p - u).dot(e) / e.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (u + e * s - p).length()
        })
        .fold(f64::INFINITY, f64::min)
}

fn brute_closest(mesh: &TriangleMesh, p: Vec3) -> f32 {
    mesh.faces()
        .map(|f| reference_distance(mesh.face_positions(f), p))
        .fold(f64::INFINITY, f64::min) as f32
}

fn check_against_brute_force(mesh: &TriangleMesh, queries: usize, seed: u64) {
    let bvh = Bvh::new(mesh);
    let scale = mesh.diagonal();
    let centre = mesh.bounds().centre();
    let mut rng = SplitMix64::new(seed);
    let mut hits = 0;
    for _ in 0..queries {
        let origin = centre + random_unit(&mut rng) * scale * (0.2 + rng.next_f64() as f32);
        let target = centre + random_unit(&mut rng) * scale * 0.3;
        let dir = (target - origin).normalize();
        let fast = bvh.ray_cast(origin, dir, 0.0, f32::INFINITY);
        let slow = brute_ray(mesh, origin, dir);
        match (fast, slow) {
            (Some(a), Some((_, t))) => {
                hits += 1;
                assert!((a.t - t).abs() <= 1e-5 * scale, "t {} vs {t}", a.t);
                let p = mesh.point_at(a.face, a.barycentric);
                assert!((p - (origin + dir * a.t)).length() <= 1e-4 * scale);
            }
            (None, None) => {}
            (a, b) => panic!("BVH {a:?} vs brute force {b:?}"),
        }
        let p = centre + random_unit(&mut rng) * scale * (rng.next_f64() as f32);
        let near = bvh.closest_point(p, f32::INFINITY).unwrap();
        let expected = brute_closest(mesh, p);
        assert!(
            (near.distance - expected).abs() <= 1e-5 * scale,
            "{} vs {expected}",
            near.distance
        );
        assert!((mesh.point_at(near.face, near.barycentric) - near.point).length() <= 1e-4 * scale);
        // A radius just below the true distance finds nothing.
        if expected > 1e-3 * scale {
            assert!(bvh.closest_point(p, expected * 0.99).is_none());
        }
    }
    assert!(
        hits > queries / 10,
        "too few hits ({hits}) to test anything"
    );
}

#[test]
fn generated_shapes_match_brute_force() {
    check_against_brute_force(&mesh_from_shape(&shapes::icosphere(1.0, 3)), 200, 1);
    check_against_brute_force(&mesh_from_shape(&shapes::torus(2.0, 0.4, 24, 12)), 200, 2);
    check_against_brute_force(&mesh_from_shape(&shapes::cylinder(1.0, 3.0, 32)), 200, 3);
}

#[test]
fn far_from_origin_model_keeps_precision() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("far.obj");
    let sphere = shapes::icosphere(0.001, 2);
    std::fs::write(&path, sphere.to_obj([1e6, -2e6, 3e6])).unwrap();
    let mesh = load_mesh(&path).unwrap().mesh;
    assert!((mesh.origin - glam::DVec3::new(1e6, -2e6, 3e6)).length() < 1e-6);
    // f64 text through an f64 origin: positions match the generated ones to f32 precision.
    for (a, b) in mesh.positions.iter().zip(&sphere.positions) {
        assert!((*a - Vec3::from_array(*b)).length() < 1e-9);
    }
    check_against_brute_force(&mesh, 100, 4);
}

#[test]
fn surface_samples_lie_on_the_surface() {
    let mesh = mesh_from_shape(&shapes::torus(2.0, 0.5, 32, 16));
    let bvh = Bvh::new(&mesh);
    for s in sample_surface(&mesh, 2000, 11) {
        let near = bvh
            .closest_point(s.point, 1e-3)
            .expect("sample off the surface");
        assert!(near.distance < 1e-5);
    }
}

#[test]
fn bunny_closest_points_match_brute_force_on_a_few_queries() {
    let mesh = load_mesh(require_shared!("bunny/reconstruction/bun_zipper.ply"))
        .unwrap()
        .mesh;
    let bvh = Bvh::new(&mesh);
    let scale = mesh.diagonal();
    let mut rng = SplitMix64::new(5);
    for _ in 0..20 {
        let p = random_unit(&mut rng) * scale * 0.5 * rng.next_f64() as f32;
        let near = bvh.closest_point(p, f32::INFINITY).unwrap();
        let expected = brute_closest(&mesh, p);
        assert!((near.distance - expected).abs() <= 1e-6 * scale);
    }
    // Every sample of the surface is found at distance ~0 on its own face or a coincident one.
    for s in sample_surface(&mesh, 1000, 3) {
        let near = bvh.closest_point(s.point, f32::INFINITY).unwrap();
        assert!(near.distance <= 1e-6 * scale, "{}", near.distance);
    }
}
