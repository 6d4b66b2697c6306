//! The displaced globe: a geodesic icosphere with equirectangular texture
//! coordinates and vertices moved along their normals by the height field.
//!
//! - **Triangles of similar size**: each face of an icosahedron (with a
//!   vertex on each pole) is split into `f²` triangles by a barycentric
//!   lattice projected onto the sphere, `20·f²` triangles in all, with no
//!   slivers at the poles (unlike a latitude–longitude sphere).
//! - **Texture coordinates per corner**: `u = (lon + 180°) / 360°`,
//!   `v = (lat + 90°) / 180°` (v up). A triangle that straddles the seam at
//!   ±180° gets `u + 1` on its corners west of the seam, so its texture span
//!   stays small (the texture repeats); a pole corner takes the mean `u` of
//!   its two other corners, so the pole's five triangles each sample their
//!   own meridians.
//! - **Heights**: every vertex is displaced by the bilinear height at its
//!   own direction, so vertices shared across the seam or at the poles get
//!   exactly one position: no cracks.
//!
//! The polar axis is +Y and longitude 0 faces +Z, so the default camera
//! sees the globe upright. Cost: O(f²) vertices and triangles.

use std::collections::HashMap;

use glam::{DVec3, Vec2};
use spatch_mesh::{Material, MaterialId, Texture, TriangleMesh};

use crate::{ColourMap, EarthError, HeightMap};

/// Options of [`build_globe`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct GlobeOptions {
    /// Sphere radius in model units. Default 128.
    pub radius: f64,
    /// Wanted number of triangles; the icosphere frequency is the nearest
    /// `f` with `20·f² ≈ triangles`. Default 40,000 (the original's), giving
    /// 40,500. More triangles follow the height field more closely and cost
    /// conversion time, not file size (patch count is set by the spacing).
    pub triangles: usize,
    /// Multiplies every height. Default 1.
    pub exaggeration: f64,
}

impl Default for GlobeOptions {
    fn default() -> Self {
        Self {
            radius: 128.0,
            triangles: 40_000,
            exaggeration: 1.0,
        }
    }
}

/// A built globe.
#[derive(Debug, Clone)]
pub struct Globe {
    /// The displaced, textured mesh.
    pub mesh: TriangleMesh,
    /// The icosphere frequency `f` (`20·f²` triangles).
    pub frequency: usize,
    /// Largest over smallest triangle area of the undisplaced sphere.
    pub area_ratio: f64,
}

/// Texture coordinates of a unit direction (polar axis +Y, longitude 0 at +Z).
pub fn equirectangular_uv(d: DVec3) -> (f64, f64) {
    let lat = d.y.clamp(-1.0, 1.0).asin();
    let lon = d.x.atan2(d.z);
    (
        (lon + std::f64::consts::PI) / std::f64::consts::TAU,
        (lat + std::f64::consts::FRAC_PI_2) / std::f64::consts::PI,
    )
}

/// The 12 vertices and 20 faces of an icosahedron with vertices on ±Y.
fn icosahedron() -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let h = 1.0 / 5f64.sqrt();
    let r = 2.0 / 5f64.sqrt();
    let mut v = vec![DVec3::Y, DVec3::NEG_Y];
    for k in 0..5 {
        let a = std::f64::consts::TAU * k as f64 / 5.0;
        v.push(DVec3::new(r * a.sin(), h, r * a.cos()));
    }
    for k in 0..5 {
        let a = std::f64::consts::TAU * (k as f64 + 0.5) / 5.0;
        v.push(DVec3::new(r * a.sin(), -h, r * a.cos()));
    }
    let (upper, lower) = (|k: usize| 2 + k % 5, |k: usize| 7 + k % 5);
    let mut faces = Vec::new();
    for k in 0..5 {
        faces.push([0, upper(k), upper(k + 1)]);
        faces.push([upper(k), lower(k), upper(k + 1)]);
        faces.push([upper(k + 1), lower(k), lower(k + 1)]);
        faces.push([1, lower(k + 1), lower(k)]);
    }
    // Make every face counter-clockwise seen from outside.
    for f in &mut faces {
        let (a, b, c) = (v[f[0]], v[f[1]], v[f[2]]);
        if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
            f.swap(1, 2);
        }
    }
    (v, faces)
}

/// Refuses an exaggeration that makes the relief taller (or deeper) than the
/// globe's radius: a valley deeper than the radius turns the sphere inside
/// out, and relief of 1e20 makes every later size overflow.
fn check_relief(samples: &[f64], options: &GlobeOptions) -> Result<(), EarthError> {
    let highest = samples.iter().fold(0.0f64, |m, h| m.max(h.abs()));
    let relief = highest * options.exaggeration.abs();
    if relief > options.radius {
        return Err(EarthError::ReliefTooLarge {
            exaggeration: options.exaggeration,
            relief,
            radius: options.radius,
            largest: options.radius / highest,
        });
    }
    Ok(())
}

/// Builds the displaced globe with the colour map as its texture.
pub fn build_globe(
    map: &ColourMap,
    heights: &HeightMap,
    options: &GlobeOptions,
) -> Result<Globe, EarthError> {
    check_options(options)?;
    let frequency = ((options.triangles as f64 / 20.0).sqrt().round() as usize).max(2);
    let (directions, triangles) = geodesic_lattice(frequency);
    let area_ratio = area_ratio(&directions, &triangles);
    let world = displaced_positions(&directions, heights, options)?;
    let face_uvs: Vec<[Vec2; 3]> = triangles
        .iter()
        .map(|t| corner_uvs(t.map(|k| directions[k as usize])))
        .collect();
    let mesh = textured_mesh(&world, triangles, face_uvs, map)?;
    Ok(Globe {
        mesh,
        frequency,
        area_ratio,
    })
}

/// Refuses a radius, triangle count or exaggeration outside its range.
fn check_options(options: &GlobeOptions) -> Result<(), EarthError> {
    let radius_ok = options.radius.is_finite() && options.radius > 0.0;
    if !radius_ok {
        return Err(EarthError::InvalidOption {
            name: "radius",
            reason: "must be a positive finite number",
        });
    }
    if !(80..=20_000_000).contains(&options.triangles) {
        return Err(EarthError::InvalidOption {
            name: "triangles",
            reason: "must be in 80..=20000000",
        });
    }
    if !options.exaggeration.is_finite() {
        return Err(EarthError::InvalidOption {
            name: "exaggeration",
            reason: "must be finite",
        });
    }
    Ok(())
}

/// Unit directions and triangles of the icosphere of the given frequency:
/// each icosahedron face split into `f²` triangles by a barycentric lattice.
fn geodesic_lattice(frequency: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let (corners, faces) = icosahedron();

    // Lattice points keyed by their exact barycentric combination of
    // icosahedron vertices, so points on shared edges are created once.
    let mut index_of: HashMap<Vec<(usize, usize)>, u32> = HashMap::new();
    let mut directions: Vec<DVec3> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut lattice = |weights: [(usize, usize); 3]| -> u32 {
        let mut key: Vec<(usize, usize)> =
            weights.iter().copied().filter(|&(_, w)| w > 0).collect();
        key.sort_unstable();
        *index_of.entry(key).or_insert_with(|| {
            let p: DVec3 = weights.iter().map(|&(c, w)| corners[c] * w as f64).sum();
            directions.push(p.normalize());
            (directions.len() - 1) as u32
        })
    };
    let f = frequency;
    for face in &faces {
        let point = |i: usize, j: usize| [(face[0], f - i - j), (face[1], i), (face[2], j)];
        for i in 0..f {
            for j in 0..f - i {
                let a = lattice(point(i, j));
                let b = lattice(point(i + 1, j));
                let c = lattice(point(i, j + 1));
                triangles.push([a, b, c]);
                if i + j + 1 < f {
                    let d = lattice(point(i + 1, j + 1));
                    triangles.push([b, d, c]);
                }
            }
        }
    }
    (directions, triangles)
}

/// Largest over smallest triangle area of the undisplaced sphere.
fn area_ratio(directions: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    let areas: Vec<f64> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| directions[k as usize]);
            (b - a).cross(c - a).length()
        })
        .collect();
    areas.iter().cloned().fold(0.0, f64::max) / areas.iter().cloned().fold(f64::MAX, f64::min)
}

/// World positions: every direction moved out by the radius plus its
/// exaggerated height, after checking the relief fits inside the radius.
fn displaced_positions(
    directions: &[DVec3],
    heights: &HeightMap,
    options: &GlobeOptions,
) -> Result<Vec<DVec3>, EarthError> {
    let samples: Vec<f64> = directions
        .iter()
        .map(|&d| {
            let (u, v) = equirectangular_uv(d);
            f64::from(heights.sample(u * 360.0 - 180.0, v * 180.0 - 90.0))
        })
        .collect();
    check_relief(&samples, options)?;
    Ok(directions
        .iter()
        .zip(&samples)
        .map(|(&d, &h)| d * (options.radius + h * options.exaggeration))
        .collect())
}

/// The validated mesh with the colour map as its one textured material.
fn textured_mesh(
    world: &[DVec3],
    triangles: Vec<[u32; 3]>,
    face_uvs: Vec<[Vec2; 3]>,
    map: &ColourMap,
) -> Result<TriangleMesh, EarthError> {
    let mut mesh = TriangleMesh::from_world_positions(world, triangles)?;
    let texture = Texture::new(map.width(), map.height(), map.rgba().to_vec())?;
    mesh.materials = vec![Material {
        name: "earth".to_owned(),
        base_colour: [1.0; 4],
        texture: Some(texture),
    }];
    mesh.face_materials = vec![MaterialId(0); mesh.triangles.len()];
    mesh.face_uvs = Some(face_uvs);
    mesh.validate()?;
    Ok(mesh)
}

/// Texture coordinates of one triangle's corners, seam and poles handled.
fn corner_uvs(d: [DVec3; 3]) -> [Vec2; 3] {
    let is_pole = |p: DVec3| p.y.abs() > 1.0 - 1e-12;
    let mut uv: Vec<(f64, f64)> = d.iter().map(|&p| equirectangular_uv(p)).collect();
    let ordinary: Vec<usize> = (0..3).filter(|&k| !is_pole(d[k])).collect();
    let (lo, hi) = ordinary.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &k| {
        (lo.min(uv[k].0), hi.max(uv[k].0))
    });
    if hi - lo > 0.5 {
        for &k in &ordinary {
            if uv[k].0 < 0.5 {
                uv[k].0 += 1.0;
            }
        }
    }
    let mean_u = ordinary.iter().map(|&k| uv[k].0).sum::<f64>() / ordinary.len().max(1) as f64;
    for k in 0..3 {
        if is_pole(d[k]) {
            uv[k].0 = mean_u;
        }
    }
    [0, 1, 2].map(|k| Vec2::new(uv[k].0 as f32, uv[k].1 as f32))
}
