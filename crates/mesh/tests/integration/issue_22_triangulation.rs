//! Issue 22 item 7: polygon faces. Convex faces triangulate exactly as before (a fan from the
//! first corner); concave faces are ear clipped: their triangles cover the polygon's area
//! exactly, none is inverted, and a 20,000-corner face loads (the fan took 21.6 s downstream
//! and overlapped itself).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use spatch_mesh::{
    load_mesh, triangulate_polygon, LoadWarning, PolygonSplit, SplitMix64, TriangleMesh,
};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// An OBJ with the given vertices and faces (0-based corner lists).
fn obj_text(points: &[DVec3], faces: &[Vec<u32>]) -> String {
    let mut text = String::new();
    for p in points {
        writeln!(text, "v {} {} {}", p.x, p.y, p.z).unwrap();
    }
    for f in faces {
        text.push('f');
        for v in f {
            write!(text, " {}", v + 1).unwrap();
        }
        text.push('\n');
    }
    text
}

/// A rotation taking +z to a tilted direction, so the polygons do not lie in an axis plane.
fn tilt(p: DVec3) -> DVec3 {
    let q = glam::DQuat::from_euler(glam::EulerRot::XYZ, 0.7, -0.4, 1.9);
    q * p + DVec3::new(3.0, -2.0, 5.0)
}

/// A star with `n` corners alternating between radius 1 and 0.5 (every inner corner reflex).
fn star(n: usize) -> Vec<DVec3> {
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            let r = if k % 2 == 0 { 1.0 } else { 0.5 };
            DVec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect()
}

/// A comb: a spine along the bottom and `teeth` teeth pointing up (counter-clockwise).
fn comb(teeth: usize) -> Vec<DVec3> {
    let mut p = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(teeth as f64, 0.0, 0.0),
    ];
    for k in (0..teeth).rev() {
        let x = k as f64;
        p.push(DVec3::new(x + 1.0, 1.0, 0.0));
        p.push(DVec3::new(x + 0.75, 5.0, 0.0));
        p.push(DVec3::new(x + 0.25, 5.0, 0.0));
        p.push(DVec3::new(x + 0.25, 1.0, 0.0));
    }
    p.pop();
    p.push(DVec3::new(0.0, 5.0, 0.0));
    p
}

/// The polygon's vector area (half the Newell normal).
fn vector_area(points: &[DVec3]) -> DVec3 {
    let o = points[0];
    let mut sum = DVec3::ZERO;
    for k in 1..points.len() - 1 {
        sum += (points[k] - o).cross(points[k + 1] - o);
    }
    sum * 0.5
}

/// Checks that `mesh` (one polygon) covers `polygon`'s area with no inverted triangle.
fn assert_covers(mesh: &TriangleMesh, polygon: &[DVec3]) {
    let area = vector_area(polygon);
    let normal = area.normalize();
    // Positions are f32 relative to the mesh's centre: a zero-area triangle (a straight
    // corner) may come back a few f32 steps negative.
    let slack = 8.0 * f64::from(f32::EPSILON) * f64::from(mesh.diagonal());
    assert_eq!(mesh.triangles.len(), polygon.len() - 2);
    let mut sum = 0.0;
    let mut total = 0.0;
    // What f32 rounding can add to each triangle's area.
    let mut noise = 0.0;
    for (f, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|k| mesh.positions[k as usize].as_dvec3());
        let signed = (b - a).cross(c - a).dot(normal) * 0.5;
        let size = (b - a).length().max((c - a).length());
        assert!(
            signed >= -slack * size,
            "triangle {f} {t:?} is inverted (signed area {signed})"
        );
        sum += signed;
        total += signed.abs();
        noise += slack * size;
    }
    let expected = area.length();
    let tolerance = 1e-6 * expected + noise;
    assert!(
        (sum - expected).abs() <= tolerance,
        "areas sum to {sum}, the polygon's is {expected}"
    );
    assert!(
        (total - expected).abs() <= tolerance,
        "unsigned areas sum to {total}: triangles overlap"
    );
}

fn load_one_face(dir: &Path, name: &str, polygon: &[DVec3]) -> spatch_mesh::LoadedMesh {
    let face: Vec<u32> = (0..polygon.len() as u32).collect();
    load_mesh(write(dir, name, &obj_text(polygon, &[face]))).unwrap()
}

#[test]
fn small_convex_faces_triangulate_exactly_as_before() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = SplitMix64::new(22);
    let mut points = Vec::new();
    let mut faces = Vec::new();
    for face in 0..400 {
        let n = 4 + face % 5;
        // Convex: corners at sorted random angles on a circle, then tilted; quads get a
        // little non-planar lift; half the faces wind the other way.
        let mut angles: Vec<f64> = (0..n)
            .map(|_| rng.next_f64() * std::f64::consts::TAU)
            .collect();
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
        if angles.len() < 4 {
            continue;
        }
        let first = points.len() as u32;
        for (k, a) in angles.iter().enumerate() {
            let lift = if angles.len() == 4 && k == 2 {
                0.05
            } else {
                0.0
            };
            points.push(tilt(DVec3::new(a.cos() + face as f64 * 3.0, a.sin(), lift)));
        }
        let mut corners: Vec<u32> = (first..points.len() as u32).collect();
        if face % 2 == 1 {
            corners.reverse();
        }
        faces.push(corners);
    }
    let loaded = load_mesh(write(dir.path(), "convex.obj", &obj_text(&points, &faces))).unwrap();
    let fans: Vec<[u32; 3]> = faces
        .iter()
        .flat_map(|f| (1..f.len() - 1).map(move |k| [f[0], f[k], f[k + 1]]))
        .collect();
    assert_eq!(loaded.mesh.triangles, fans);
    assert_eq!(
        loaded.warnings,
        vec![LoadWarning::PolygonsTriangulated {
            count: faces.len() as u64
        }]
    );
}

#[test]
fn triangles_and_convex_polygons_report_a_fan() {
    let square = [DVec3::ZERO, DVec3::X, DVec3::ONE.with_z(0.0), DVec3::Y];
    let mut out = Vec::new();
    assert_eq!(triangulate_polygon(&square, &mut out), PolygonSplit::Fan);
    assert_eq!(out, vec![[0, 1, 2], [0, 2, 3]]);
    out.clear();
    assert_eq!(
        triangulate_polygon(&square[..3], &mut out),
        PolygonSplit::Fan
    );
    assert_eq!(out, vec![[0, 1, 2]]);
}

#[test]
fn a_big_concave_star_covers_its_area_with_no_inverted_triangle() {
    let dir = tempfile::tempdir().unwrap();
    let polygon: Vec<DVec3> = star(20_000).into_iter().map(tilt).collect();
    let loaded = load_one_face(dir.path(), "star.obj", &polygon);
    assert_covers(&loaded.mesh, &polygon);
    assert_eq!(
        loaded.warnings,
        vec![LoadWarning::PolygonsTriangulated { count: 1 }]
    );
}

#[test]
fn a_clockwise_comb_keeps_its_winding() {
    let dir = tempfile::tempdir().unwrap();
    let mut polygon: Vec<DVec3> = comb(500).into_iter().map(tilt).collect();
    polygon.reverse();
    let loaded = load_one_face(dir.path(), "comb.obj", &polygon);
    assert_covers(&loaded.mesh, &polygon);
    // Every triangle with an area (the straight corners' have none) faces where the
    // polygon faces.
    let normal = vector_area(&polygon).normalize().as_vec3();
    let mut facing = 0;
    for (f, t) in loaded.mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|k| loaded.mesh.positions[k as usize]);
        if (b - a).cross(c - a).length() < 1e-3 * (b - a).length_squared() {
            continue;
        }
        let n: Vec3 = loaded.mesh.face_normal(spatch_mesh::FaceId(f as u32));
        assert!(n.dot(normal) > 0.99, "face {f}: {n}");
        facing += 1;
    }
    assert!(facing > loaded.mesh.triangles.len() / 2);
}

#[test]
fn collinear_and_duplicate_corners_keep_the_area() {
    // An L shape with extra corners on its edges and one corner written twice.
    let polygon: Vec<DVec3> = [
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
        [0.0, 1.0],
    ]
    .iter()
    .map(|p| DVec3::new(p[0], p[1], 0.0))
    .collect();
    let dir = tempfile::tempdir().unwrap();
    let loaded = load_one_face(dir.path(), "l.obj", &polygon);
    assert_covers(&loaded.mesh, &polygon);
}

#[test]
fn a_self_crossing_polygon_is_reported_and_still_gives_n_minus_2_triangles() {
    let pentagram: Vec<DVec3> = (0..5)
        .map(|k| {
            let a = std::f64::consts::TAU * (2 * k) as f64 / 5.0;
            DVec3::new(a.cos(), a.sin(), 0.0)
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let loaded = load_one_face(dir.path(), "pentagram.obj", &pentagram);
    assert_eq!(loaded.mesh.triangles.len(), 3);
    assert!(loaded
        .warnings
        .contains(&LoadWarning::PolygonsNotSimple { count: 1 }));
    // A figure eight whose halves cancel has no plane: fanned as before, no panic.
    let eight = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ];
    let mut out = Vec::new();
    assert_eq!(triangulate_polygon(&eight, &mut out), PolygonSplit::Fan);
    assert_eq!(out.len(), 2);
    // Random corners cross themselves everywhere: n - 2 triangles, every corner used.
    let mut rng = SplitMix64::new(7);
    for n in [5usize, 17, 200] {
        let points: Vec<DVec3> = (0..n)
            .map(|_| DVec3::new(rng.next_f64(), rng.next_f64(), 0.0))
            .collect();
        out.clear();
        triangulate_polygon(&points, &mut out);
        assert_eq!(out.len(), n - 2);
        let mut used = vec![false; n];
        out.iter().flatten().for_each(|&k| used[k as usize] = true);
        assert!(used.iter().all(|&u| u), "n = {n}");
    }
}

#[test]
fn ply_and_off_faces_are_ear_clipped_too() {
    let dir = tempfile::tempdir().unwrap();
    let polygon = comb(20);
    let n = polygon.len();
    let mut off = format!("OFF\n{n} 1 0\n");
    for p in &polygon {
        writeln!(off, "{} {} {}", p.x, p.y, p.z).unwrap();
    }
    off.push_str(&n.to_string());
    for k in 0..n {
        write!(off, " {k}").unwrap();
    }
    off.push('\n');
    let loaded = load_mesh(write(dir.path(), "comb.off", &off)).unwrap();
    assert_covers(&loaded.mesh, &polygon);

    let mut ply = format!(
        "ply\nformat ascii 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
    );
    for p in &polygon {
        writeln!(ply, "{} {} {}", p.x, p.y, p.z).unwrap();
    }
    ply.push_str(&n.to_string());
    for k in 0..n {
        write!(ply, " {k}").unwrap();
    }
    ply.push('\n');
    let loaded = load_mesh(write(dir.path(), "comb.ply", &ply)).unwrap();
    assert_covers(&loaded.mesh, &polygon);
}
