//! Turning each patch about its normal so that its square contains its
//! Voronoi cell.
//!
//! With all patches the same size, the sphere is covered exactly when every
//! patch's square (in the patch plane) contains the orthographic image of its
//! spherical Voronoi cell. The cell is found in the gnomonic projection at the
//! centre, where the great-circle bisectors to the neighbours are straight
//! lines: clip a large square by one half-plane per neighbour. Its boundary is
//! then sampled, mapped back to the sphere and projected orthographically, and
//! the rotation (searched in 0.5° steps over a quarter turn) that leaves the
//! largest margin to the square's edge is kept.
//!
//! Cost: O(patches × neighbours²) for the clipping, O(patches × 180 × samples)
//! for the search; a few ms for the default sphere.

use glam::{DVec2, DVec3};

/// Boundary samples per Voronoi edge (the orthographic image of an edge is an
/// ellipse arc, which bulges slightly beyond its chord).
const SAMPLES_PER_EDGE: usize = 6;
/// Rotations tried over a quarter turn.
const ROTATION_STEPS: usize = 180;

/// The chosen rotation and how much room it leaves.
pub(crate) struct Orientation {
    /// Unit x axis of the patch (tangent to the sphere at the centre).
    pub(crate) x: DVec3,
    /// Distance (model units, in the patch plane) from the cell's farthest
    /// boundary point to the square's edge; negative when the cell sticks out.
    pub(crate) margin: f64,
}

/// The Voronoi cell of `centre` among `neighbours` in gnomonic coordinates of
/// the basis `(x0, y0)`.
fn voronoi_cell(centre: DVec3, x0: DVec3, y0: DVec3, neighbours: &[DVec3]) -> Vec<DVec2> {
    let far = 4.0;
    let mut polygon = vec![
        DVec2::new(-far, -far),
        DVec2::new(far, -far),
        DVec2::new(far, far),
        DVec2::new(-far, far),
    ];
    for &q in neighbours {
        // Keep points p = c + u x0 + v y0 with p·(c − q) >= 0.
        let n = centre - q;
        let (a, b, c) = (x0.dot(n), y0.dot(n), centre.dot(n));
        let side = |p: DVec2| a * p.x + b * p.y + c;
        let mut clipped = Vec::with_capacity(polygon.len() + 1);
        for k in 0..polygon.len() {
            let (p, r) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            let (sp, sr) = (side(p), side(r));
            if sp >= 0.0 {
                clipped.push(p);
            }
            if (sp >= 0.0) != (sr >= 0.0) {
                clipped.push(p + (r - p) * (sp / (sp - sr)));
            }
        }
        polygon = clipped;
    }
    polygon
}

/// Picks the rotation of a patch of half-width `half` centred on `centre`
/// (unit) on a sphere of `radius`.
pub(crate) fn orient_patch(
    centre: DVec3,
    x0: DVec3,
    y0: DVec3,
    neighbours: &[DVec3],
    radius: f64,
    half: f64,
) -> Orientation {
    let cell = voronoi_cell(centre, x0, y0, neighbours);
    let mut boundary = Vec::with_capacity(cell.len() * SAMPLES_PER_EDGE);
    for k in 0..cell.len() {
        let (p, r) = (cell[k], cell[(k + 1) % cell.len()]);
        for s in 0..SAMPLES_PER_EDGE {
            let g = p + (r - p) * (s as f64 / SAMPLES_PER_EDGE as f64);
            let d = (centre + x0 * g.x + y0 * g.y).normalize();
            boundary.push(DVec2::new(d.dot(x0), d.dot(y0)) * radius);
        }
    }
    let mut best = Orientation {
        x: x0,
        margin: f64::NEG_INFINITY,
    };
    for step in 0..ROTATION_STEPS {
        let angle = step as f64 / ROTATION_STEPS as f64 * std::f64::consts::FRAC_PI_2;
        let (sin, cos) = angle.sin_cos();
        let reach = boundary
            .iter()
            .map(|p| {
                let (u, v) = (p.x * cos + p.y * sin, -p.x * sin + p.y * cos);
                u.abs().max(v.abs())
            })
            .fold(0.0, f64::max);
        if half - reach > best.margin {
            best = Orientation {
                x: x0 * cos + y0 * sin,
                margin: half - reach,
            };
        }
    }
    best
}
