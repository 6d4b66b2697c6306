//! Triangulation of one polygon face (OBJ, PLY, OFF and STL loaders).
//!
//! Input: the polygon's corner positions in order (f64, any plane, any winding). Output:
//! triangles as triples of corner indices, each wound like the polygon.
//!
//! - A convex polygon (every turn the same way, the edge directions going once around) is
//!   fanned from corner 0, `(0, k, k + 1)`: exactly what the loaders did before, so convex
//!   faces (nearly every quad and small n-gon in the field) triangulate as they always have.
//! - Any other polygon is projected onto the plane of its Newell normal and cut by ear
//!   clipping. An ear is a convex corner whose triangle holds no blocking corner (reflex or
//!   flat); only blocking corners can lie in a candidate ear (any boundary that enters the
//!   triangle brings one), and a uniform grid over them answers "is any inside?" by visiting
//!   only the cells under the triangle's bounding box. Corners only ever turn from blocking
//!   to convex as ears are cut (a corner's angle shrinks when a neighbour is removed), so the
//!   grid is built once and entries die lazily.
//! - A polygon with no normal (all corners on a line, or a figure eight whose areas cancel) is
//!   fanned as before. When a full pass finds no ear (the polygon crosses or touches itself),
//!   the next convex corner is cut anyway, so the result still covers the polygon's outline;
//!   such a polygon, and one whose edges go around more than once with no right turn (a
//!   pentagram), is reported as [`PolygonSplit::NotSimple`]. Other self-crossings can go
//!   unnoticed; their triangles then follow the outline's winding.
//!
//! Invariants: every output triangle of a simple polygon has a non-negative signed area in
//! the polygon's plane, and their areas sum to the polygon's area; `n - 2` triangles always.
//!
//! Cost: O(n) for a convex polygon; for other polygons O(n) to build the grid and, in
//! practice, about O(1) cells and corners per ear test on scanned or drawn outlines (the grid
//! holds about one blocking corner per cell), so near-linear overall; adversarial outlines
//! (long ears over dense reflex chains) can cost up to O(n^2). Memory O(n).
//!
//! Based on: G. H. Meisters, *Polygons have ears* (1975); D. Eberly, *Triangulation by Ear
//! Clipping* (2002); M. E. Newell's plane normal (Sutherland, Sproull and Schumacker, *A
//! Characterization of Ten Hidden-Surface Algorithms*, 1974).

use glam::{DVec2, DVec3};

use crate::LoadWarning;

/// How [`triangulate_polygon`] split a polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PolygonSplit {
    /// A fan from corner 0 (triangles, convex polygons, and polygons with no plane).
    Fan,
    /// Ear clipping in the polygon's plane (a simple, non-convex polygon).
    EarClipped,
    /// The polygon crosses or touches itself (ear clipping had to cut a corner whose triangle
    /// holds other corners, or the outline goes around more than once): some triangles
    /// overlap.
    NotSimple,
}

/// Relative size below which a turn counts as straight: `|cross| <= FLAT * |e1| * |e2|`
/// (the sine of the angle between the two edges).
const FLAT: f64 = 1e-12;

/// Appends the triangles of the polygon through `points` (corner indices, in the polygon's
/// winding) to `out`, and says how it was split. Fewer than three points add nothing.
pub fn triangulate_polygon(points: &[DVec3], out: &mut Vec<[u32; 3]>) -> PolygonSplit {
    let n = points.len();
    if n < 3 {
        return PolygonSplit::Fan;
    }
    if n > 3 {
        if let Some(plane) = project_to_plane(points) {
            match classify(&plane) {
                Outline::Convex => {}
                Outline::Concave => return clip_ears(&plane, out),
                Outline::WindsMoreThanOnce => {
                    clip_ears(&plane, out);
                    return PolygonSplit::NotSimple;
                }
            }
        }
    }
    push_fan(0, n, out);
    PolygonSplit::Fan
}

/// The fan `(first, k, k + 1)` over corners `first..first + n` (as before this module).
fn push_fan(first: u32, n: usize, out: &mut Vec<[u32; 3]>) {
    for k in 1..n as u32 - 1 {
        out.push([first, first + k, first + k + 1]);
    }
}

/// The corners in 2D, counter-clockwise: coordinates relative to corner 0 in an orthonormal
/// basis `(u, v)` with `u x v` the polygon's Newell normal. `None` when the normal is zero or
/// not finite.
fn project_to_plane(points: &[DVec3]) -> Option<Vec<DVec2>> {
    let origin = points[0];
    let mut normal = DVec3::ZERO;
    let mut a = points[points.len() - 1] - origin;
    for &p in points {
        let b = p - origin;
        normal += a.cross(b);
        a = b;
    }
    let normal = normal.try_normalize()?;
    let (u, _) = normal.any_orthonormal_pair();
    let v = normal.cross(u);
    Some(
        points
            .iter()
            .map(|&p| {
                let d = p - origin;
                DVec2::new(d.dot(u), d.dot(v))
            })
            .collect(),
    )
}

/// Twice the signed area of `(a, b, c)`: positive for a left turn at `b`.
#[inline]
fn cross(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    (b - a).perp_dot(c - b)
}

/// How corner `b` between `a` and `c` turns, with straight turns (within [`FLAT`]) apart.
fn turn(a: DVec2, b: DVec2, c: DVec2) -> Turn {
    let area = cross(a, b, c);
    let scale = (b - a).length() * (c - b).length();
    if area.abs() <= FLAT * scale {
        Turn::Flat
    } else if area > 0.0 {
        Turn::Convex
    } else {
        Turn::Reflex
    }
}

/// The turn at a polygon corner.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Turn {
    Convex,
    Flat,
    Reflex,
}

/// What the corners' turns and the edges' directions say about a counter-clockwise polygon.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Outline {
    /// No corner turns right and the edges go once around.
    Convex,
    /// No corner turns right but the edges go around more than once (a pentagram).
    WindsMoreThanOnce,
    /// Some corner turns right.
    Concave,
}

/// Classifies `q`: no right turn, and the signs of the edges' x and y components each
/// changing at most twice around the polygon, means convex.
fn classify(q: &[DVec2]) -> Outline {
    let n = q.len();
    let mut changes = [0u32; 2];
    let mut last_sign = [0i8; 2];
    for i in 0..n {
        let (a, b, c) = (q[(i + n - 1) % n], q[i], q[(i + 1) % n]);
        if turn(a, b, c) == Turn::Reflex {
            return Outline::Concave;
        }
        let edge = c - b;
        for (axis, value) in [edge.x, edge.y].into_iter().enumerate() {
            let sign = if value > 0.0 {
                1
            } else if value < 0.0 {
                -1
            } else {
                0
            };
            if sign != 0 {
                if last_sign[axis] != 0 && sign != last_sign[axis] {
                    changes[axis] += 1;
                }
                last_sign[axis] = sign;
            }
        }
    }
    // The loop does not compare the last edge with the first; going once around ends where
    // it started, so the closing comparison would add one change at most.
    if changes[0] <= 2 && changes[1] <= 2 {
        Outline::Convex
    } else {
        Outline::WindsMoreThanOnce
    }
}

/// Ear clipping of a counter-clockwise polygon `q`; appends `q.len() - 2` triangles.
fn clip_ears(q: &[DVec2], out: &mut Vec<[u32; 3]>) -> PolygonSplit {
    let n = q.len();
    let mut prev: Vec<u32> = (0..n as u32)
        .map(|i| (i + n as u32 - 1) % n as u32)
        .collect();
    let mut next: Vec<u32> = (0..n as u32).map(|i| (i + 1) % n as u32).collect();
    let mut blocking: Vec<bool> = (0..n)
        .map(|i| turn(q[prev[i] as usize], q[i], q[next[i] as usize]) != Turn::Convex)
        .collect();
    let mut grid = BlockingGrid::new(q, &blocking);
    let mut split = PolygonSplit::EarClipped;
    let mut remaining = n;
    let mut cursor = 0u32;
    let mut misses = 0usize;
    while remaining > 3 {
        let (p, c, x) = (prev[cursor as usize], cursor, next[cursor as usize]);
        let ear = match turn(q[p as usize], q[c as usize], q[x as usize]) {
            // A straight corner cuts off nothing: its zero-area triangle keeps it in the mesh.
            Turn::Flat => true,
            Turn::Convex => {
                misses >= remaining
                    || !grid.any_inside(q, [p, c, x], |k| k != p && k != c && k != x)
            }
            Turn::Reflex => false,
        };
        if !ear {
            misses += 1;
            // Two full passes without an ear: no corner is convex (a degenerate outline).
            if misses >= 2 * remaining {
                push_rest_as_fan(cursor, remaining, &next, out);
                return PolygonSplit::NotSimple;
            }
            cursor = x;
            continue;
        }
        if misses >= remaining {
            split = PolygonSplit::NotSimple;
        }
        out.push([p, c, x]);
        next[p as usize] = x;
        prev[x as usize] = p;
        remaining -= 1;
        // The cut corner (straight ones block) leaves the outline; its neighbours' angles
        // shrink, and those that turn convex stop blocking.
        blocking[c as usize] = false;
        grid.remove(c);
        for k in [p, x] {
            let k = k as usize;
            if blocking[k] && turn(q[prev[k] as usize], q[k], q[next[k] as usize]) == Turn::Convex {
                blocking[k] = false;
                grid.remove(k as u32);
            }
        }
        misses = 0;
        cursor = x;
    }
    let c = cursor as usize;
    out.push([prev[c], cursor, next[c]]);
    split
}

/// Fans the `remaining` corners of the ring through `next`, starting at `start`.
fn push_rest_as_fan(start: u32, remaining: usize, next: &[u32], out: &mut Vec<[u32; 3]>) {
    let mut b = next[start as usize];
    for _ in 0..remaining - 2 {
        let c = next[b as usize];
        out.push([start, b, c]);
        b = c;
    }
}

/// The blocking corners, bucketed into a uniform grid over the polygon's bounding box (about
/// two cells per corner), in CSR form. Each cell keeps its live corners first: a corner that
/// stops blocking is swapped behind them, so tests never visit it again.
struct BlockingGrid {
    min: DVec2,
    inv_cell: DVec2,
    side: [usize; 2],
    starts: Vec<u32>,
    /// Live corners per cell (a prefix of the cell's range).
    live: Vec<u32>,
    corners: Vec<u32>,
    /// Per polygon corner: its cell (`u32::MAX` when never blocking) and its slot in `corners`.
    cell: Vec<u32>,
    slot: Vec<u32>,
}

impl BlockingGrid {
    /// Buckets the corners flagged in `blocking`.
    fn new(q: &[DVec2], blocking: &[bool]) -> BlockingGrid {
        let (mut min, mut max) = (q[0], q[0]);
        for &p in q {
            min = min.min(p);
            max = max.max(p);
        }
        let count = 2 * blocking.iter().filter(|&&b| b).count().max(1);
        let extent = (max - min).max(DVec2::splat(f64::MIN_POSITIVE));
        // Cells about square, about `count` of them (corners lie on curves, so a cell whose
        // side is the mean corner spacing would be mostly empty; twice as many cells as
        // corners halves each cell's load on a curve at little memory).
        let aspect = (extent.x / extent.y).clamp(1e-6, 1e6);
        let nx = ((count as f64 * aspect).sqrt().ceil() as usize).clamp(1, count);
        let ny = count.div_ceil(nx).max(1);
        let side = [nx, ny];
        let inv_cell = DVec2::new(nx as f64 / extent.x, ny as f64 / extent.y);
        let mut grid = BlockingGrid {
            min,
            inv_cell,
            side,
            starts: vec![0; nx * ny + 1],
            live: vec![0; nx * ny],
            corners: Vec::new(),
            cell: Vec::new(),
            slot: vec![0; q.len()],
        };
        grid.cell = (0..q.len())
            .map(|i| {
                if blocking[i] {
                    grid.cell_of(q[i]) as u32
                } else {
                    u32::MAX
                }
            })
            .collect();
        for &cell in grid.cell.iter().filter(|&&c| c != u32::MAX) {
            grid.starts[cell as usize + 1] += 1;
            grid.live[cell as usize] += 1;
        }
        for k in 1..grid.starts.len() {
            grid.starts[k] += grid.starts[k - 1];
        }
        let mut fill = grid.starts.clone();
        grid.corners = vec![0; grid.starts[nx * ny] as usize];
        for (i, &cell) in grid.cell.iter().enumerate() {
            if cell != u32::MAX {
                let at = &mut fill[cell as usize];
                grid.corners[*at as usize] = i as u32;
                grid.slot[i] = *at;
                *at += 1;
            }
        }
        grid
    }

    /// Takes corner `k` (which has stopped blocking) out of its cell's live corners.
    fn remove(&mut self, k: u32) {
        let cell = self.cell[k as usize];
        if cell == u32::MAX {
            return;
        }
        let cell = cell as usize;
        let last = self.starts[cell] + self.live[cell] - 1;
        let at = self.slot[k as usize];
        let moved = self.corners[last as usize];
        self.corners.swap(at as usize, last as usize);
        self.slot[moved as usize] = at;
        self.slot[k as usize] = last;
        self.live[cell] -= 1;
        self.cell[k as usize] = u32::MAX;
    }

    /// The cell column and row of `p`, clamped to the grid.
    fn cell_xy(&self, p: DVec2) -> [usize; 2] {
        let t = (p - self.min) * self.inv_cell;
        [
            (t.x.max(0.0) as usize).min(self.side[0] - 1),
            (t.y.max(0.0) as usize).min(self.side[1] - 1),
        ]
    }

    /// The flat cell index of `p`.
    fn cell_of(&self, p: DVec2) -> usize {
        let [x, y] = self.cell_xy(p);
        y * self.side[0] + x
    }

    /// Whether a live (still blocking) corner accepted by `other` lies in or on the
    /// counter-clockwise triangle `tri` (corners at the same position as one of its three
    /// corners do not count: they are where the outline touches itself).
    fn any_inside(&self, q: &[DVec2], tri: [u32; 3], other: impl Fn(u32) -> bool) -> bool {
        let [a, b, c] = tri.map(|k| q[k as usize]);
        let lo = self.cell_xy(a.min(b).min(c));
        let hi = self.cell_xy(a.max(b).max(c));
        let cell_height = 1.0 / self.inv_cell.y;
        for y in lo[1]..=hi[1] {
            // Only the cells of this row that the triangle reaches (a long thin ear crosses
            // few cells of its bounding box), widened by one cell against rounding.
            let y0 = self.min.y + y as f64 * cell_height;
            let margin = 1e-9 * cell_height;
            let band = (y0 - margin, y0 + cell_height + margin);
            let Some((x0, x1)) = x_range_in_band([a, b, c], band.0, band.1) else {
                continue;
            };
            let first = self.cell_xy(DVec2::new(x0, y0))[0]
                .saturating_sub(1)
                .max(lo[0]);
            let last = (self.cell_xy(DVec2::new(x1, y0))[0] + 1).min(hi[0]);
            let row = y * self.side[0];
            for cell in row + first..=row + last {
                let start = self.starts[cell] as usize;
                for &k in &self.corners[start..start + self.live[cell] as usize] {
                    if !other(k) {
                        continue;
                    }
                    let p = q[k as usize];
                    if p == a || p == b || p == c {
                        continue;
                    }
                    if cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0 {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// The x extent of the part of triangle `tri` inside the horizontal band `y0..=y1`, or `None`
/// when it misses the band. The part is convex, so its extent is that of the triangle's
/// edges clipped to the band.
fn x_range_in_band(tri: [DVec2; 3], y0: f64, y1: f64) -> Option<(f64, f64)> {
    let (mut x_min, mut x_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..3 {
        let (p, r) = (tri[k], tri[(k + 1) % 3]);
        let (lo, hi) = if p.y <= r.y { (p, r) } else { (r, p) };
        if hi.y < y0 || lo.y > y1 {
            continue;
        }
        let dy = hi.y - lo.y;
        let (xa, xb) = if dy > 0.0 {
            let at = |y: f64| lo.x + (hi.x - lo.x) * ((y - lo.y) / dy).clamp(0.0, 1.0);
            (at(y0.max(lo.y)), at(y1.min(hi.y)))
        } else {
            (lo.x, hi.x)
        };
        x_min = x_min.min(xa.min(xb));
        x_max = x_max.max(xa.max(xb));
    }
    (x_min <= x_max).then_some((x_min, x_max))
}

/// Triangulates polygons given as vertex indices into one position list, for the loaders,
/// and counts what the loaders report ([`LoadWarning::PolygonsTriangulated`],
/// [`LoadWarning::PolygonsNotSimple`]).
#[derive(Default)]
pub(crate) struct PolygonTriangulator {
    corners: Vec<DVec3>,
    local: Vec<[u32; 3]>,
    triangulated: u64,
    not_simple: u64,
}

impl PolygonTriangulator {
    /// The triangles of `polygon` (indices into `positions`, all in range) as corner numbers
    /// `0..polygon.len()`, valid until the next call.
    pub(crate) fn split(&mut self, positions: &[DVec3], polygon: &[u32]) -> &[[u32; 3]] {
        self.corners.clear();
        self.corners
            .extend(polygon.iter().map(|&v| positions[v as usize]));
        self.local.clear();
        let split = triangulate_polygon(&self.corners, &mut self.local);
        self.triangulated += u64::from(polygon.len() > 3);
        self.not_simple += u64::from(split == PolygonSplit::NotSimple);
        &self.local
    }

    /// Appends the triangles of `polygon` as vertex indices to `out`.
    pub(crate) fn push(&mut self, positions: &[DVec3], polygon: &[u32], out: &mut Vec<[u32; 3]>) {
        let local = self.split(positions, polygon);
        out.extend(local.iter().map(|t| t.map(|k| polygon[k as usize])));
    }

    /// The warnings for what was counted.
    pub(crate) fn warnings(&self) -> impl Iterator<Item = LoadWarning> {
        let triangulated = (self.triangulated > 0).then_some(LoadWarning::PolygonsTriangulated {
            count: self.triangulated,
        });
        let not_simple = (self.not_simple > 0).then_some(LoadWarning::PolygonsNotSimple {
            count: self.not_simple,
        });
        triangulated.into_iter().chain(not_simple)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(points: &[[f64; 2]]) -> Vec<DVec3> {
        points.iter().map(|p| DVec3::new(p[0], p[1], 0.0)).collect()
    }

    #[test]
    fn convex_polygons_are_fanned_from_corner_zero() {
        let square = flat(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        let mut out = Vec::new();
        assert_eq!(triangulate_polygon(&square, &mut out), PolygonSplit::Fan);
        assert_eq!(out, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn a_pentagram_is_not_convex() {
        let star: Vec<[f64; 2]> = (0..5)
            .map(|k| {
                let a = std::f64::consts::TAU * (2 * k) as f64 / 5.0;
                [a.cos(), a.sin()]
            })
            .collect();
        let plane = project_to_plane(&flat(&star)).unwrap();
        assert_eq!(classify(&plane), Outline::WindsMoreThanOnce);
    }

    #[test]
    fn a_concave_quad_is_cut_at_its_reflex_corner() {
        // The reflex corner is 1; a fan from 0 would make the triangle (0, 1, 2) inverted.
        let arrow = flat(&[[2.0, -1.0], [1.0, 0.0], [2.0, 1.0], [0.0, 0.0]]);
        let mut out = Vec::new();
        assert_eq!(
            triangulate_polygon(&arrow, &mut out),
            PolygonSplit::EarClipped
        );
        assert_eq!(out.len(), 2);
        for t in &out {
            let [a, b, c] = t.map(|k| arrow[k as usize].truncate());
            assert!(cross(a, b, c) > 0.0, "{t:?}");
        }
    }
}
