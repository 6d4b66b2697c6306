use glam::DVec3;
use rayon::prelude::*;
use spatch_format::{encode_scene, Patch, Scene, WriteOptions};
use spatch_sphere::{build_sphere, SphereOptions};

/// Upper bound of the distance from `p` to the bilinear surface of `patch`
/// (cells as bilinear quads): the gap along the patch normal between `p` and
/// the surface point with the same grid coordinates. `None` when `p` does not
/// project onto a drawable cell.
fn distance_along_normal(patch: &Patch, p: DVec3) -> Option<f64> {
    let frame = patch.frame();
    let [ux, uy, uz] = frame.unit_axes().map(|a| a.as_dvec3());
    let [lx, ly, lz] = frame.lengths().map(f64::from);
    let rel = p - frame.origin().as_dvec3();
    if rel.dot(uz) <= 0.0 {
        return None;
    }
    let (s, t) = (rel.dot(ux) / lx, rel.dot(uy) / ly);
    let (cols, rows) = (patch.grid().cols() as f64, patch.grid().rows() as f64);
    if !(0.0..=cols - 1.0).contains(&s) || !(0.0..=rows - 1.0).contains(&t) {
        return None;
    }
    let (i, j) = (
        (s as usize).min(cols as usize - 2),
        (t as usize).min(rows as usize - 2),
    );
    if !patch.cell_is_drawable(i, j) {
        return None;
    }
    let (fs, ft) = (s - i as f64, t - j as f64);
    let d = |a, b| f64::from(patch.displacement(a, b).unwrap_or(0));
    let h = (d(i, j) * (1.0 - fs) + d(i + 1, j) * fs) * (1.0 - ft)
        + (d(i, j + 1) * (1.0 - fs) + d(i + 1, j + 1) * fs) * ft;
    Some((rel.dot(uz) - h * lz).abs())
}

fn random_unit_vectors(count: usize, mut seed: u64) -> Vec<DVec3> {
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..count)
        .map(|_| {
            let z = 2.0 * next() - 1.0;
            let phi = 2.0 * std::f64::consts::PI * next();
            let r = (1.0 - z * z).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

fn worst_gap(scene: &Scene, radius: f64, samples: usize) -> f64 {
    let centres: Vec<DVec3> = scene
        .patches()
        .iter()
        .map(|p| {
            let [ux, uy, _] = p.frame().unit_axes().map(|a| a.as_dvec3());
            let [lx, ly, _] = p.frame().lengths().map(f64::from);
            let half = (p.grid().cols() - 1) as f64 / 2.0;
            (p.frame().origin().as_dvec3() + ux * lx * half + uy * ly * half).normalize()
        })
        .collect();
    random_unit_vectors(samples, 0x9E37_79B9_7F4A_7C15)
        .into_par_iter()
        .map(|dir| {
            let p = dir * radius;
            scene
                .patches()
                .iter()
                .zip(&centres)
                .filter(|(_, c)| c.dot(dir) > 0.95)
                .filter_map(|(patch, _)| distance_along_normal(patch, p))
                .fold(f64::INFINITY, f64::min)
        })
        .reduce(|| 0.0, f64::max)
}

#[test]
fn default_sphere_has_no_gaps_and_fits_the_original_budget() {
    let scene = build_sphere(&SphereOptions::default()).unwrap().scene;
    let gap = worst_gap(&scene, 128.0, 200_000);
    assert!(
        gap <= 0.01,
        "a point on the sphere is {gap} from every patch"
    );
    let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    assert!(bytes.len() < 450_560, "file is {} bytes", bytes.len());
}

#[test]
fn other_radii_and_grids_stay_covered() {
    let mut options = SphereOptions::default();
    options.radius = 40.0;
    options.patches = 700;
    options.grid = 9;
    options.step = 0.002;
    let scene = build_sphere(&options).unwrap().scene;
    assert!(worst_gap(&scene, 40.0, 20_000) <= 0.01);
}
