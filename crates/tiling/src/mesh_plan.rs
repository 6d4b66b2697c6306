//! Mesh plans: the faces each tile counts, from a loaded mesh or streamed from a PLY or
//! plain OBJ file.
//!
//! A tile counts every face whose bounding box touches its box, and the one tile that
//! owns the face's centroid (`[min, max)` per axis, the rule of [`crate::TileOwner`]) is
//! always listed, so every face of the input has an owner task. Each plan uses the
//! coordinates its tasks will use: a loaded mesh its own origin and f32 offsets, a
//! streamed file the plan's anchor and f32 offsets from it (as `read_mesh_tile` gives
//! them), so the plan and the tasks compute every centroid bit for bit alike.
//!
//! A streamed plan keeps one position per vertex (24 B) and the per-tile counts, and reads
//! the file three times (vertices, polygons for the lowest corner, polygons again).
//! Polygons are split as the tasks split them; faces the mesh loader drops (two equal
//! corners, zero area) are not counted.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DVec3, Vec3};
use spatch_cloud::TileGrid;
use spatch_mesh::{triangulate_polygon, TriangleMesh};

use crate::mesh_stream::{each_polygon, each_vertex, format_of};
use crate::mesh_tiles::owns;
use crate::plan::{
    buffer_fits, given_buffer_too_wide, tiles_of_counts, Plan, PlanGrid, WorldBox, PLAN_VERSION,
};
use crate::TilingError;

/// What a mesh plan needs from its faces: their bounds, their mean area (for a default
/// spacing) and the faces each tile counts.
#[derive(Debug, Clone)]
pub struct MeshCensus {
    grid: TileGrid,
    bounds: Option<(DVec3, DVec3)>,
    faces: u64,
    area: f64,
    area_faces: u64,
    counts: BTreeMap<(i64, i64, i64), u64>,
}

/// A positive, finite tile size, or an error.
fn checked_tile(tile: f64) -> Result<f64, TilingError> {
    if tile.is_finite() && tile > 0.0 {
        Ok(tile)
    } else {
        Err(TilingError::InvalidOption {
            option: "tile size",
            reason: "must be a positive number".to_string(),
        })
    }
}

impl MeshCensus {
    /// An empty census of tiles of side `tile` on the grid anchored at `anchor`.
    fn new(anchor: DVec3, tile: f64) -> Result<MeshCensus, TilingError> {
        let grid = TileGrid::new(anchor, checked_tile(tile)?, 0.0).ok_or_else(|| {
            TilingError::InvalidOption {
                option: "tile size",
                reason: "out of range".to_string(),
            }
        })?;
        Ok(MeshCensus {
            grid,
            bounds: None,
            faces: 0,
            area: 0.0,
            area_faces: 0,
            counts: BTreeMap::new(),
        })
    }

    /// Counts the face with world corners `corners` and f32 area `area`.
    fn add(&mut self, corners: [DVec3; 3], area: f32) {
        let [a, b, c] = corners;
        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
        self.bounds = Some(match self.bounds {
            Some((l, h)) => (l.min(lo), h.max(hi)),
            None => (lo, hi),
        });
        self.faces += 1;
        if area > 0.0 && area.is_finite() {
            self.area += f64::from(area);
            self.area_faces += 1;
        }
        let (ka, kb) = (self.grid.key_of(lo), self.grid.key_of(hi));
        let owner = self.owner_key((a + b + c) / 3.0);
        let touched = (0..3).all(|k| (ka[k]..=kb[k]).contains(&owner[k]));
        if !touched {
            *self
                .counts
                .entry((owner[2], owner[1], owner[0]))
                .or_insert(0) += 1;
        }
        for z in ka[2]..=kb[2] {
            for y in ka[1]..=kb[1] {
                for x in ka[0]..=kb[0] {
                    *self.counts.entry((z, y, x)).or_insert(0) += 1;
                }
            }
        }
    }

    /// The key of the tile whose bounds own `centroid` (the grid's key, moved by one where
    /// rounding puts the centroid on the other side of a tile face).
    fn owner_key(&self, centroid: DVec3) -> [i64; 3] {
        let mut key = self.grid.key_of(centroid);
        for k in 0..3 {
            let (min, max) = self.grid.bounds_of(key);
            if centroid[k] < min[k] {
                key[k] -= 1;
            } else if centroid[k] >= max[k] {
                key[k] += 1;
            }
        }
        debug_assert!({
            let (min, max) = self.grid.bounds_of(key);
            owns(&WorldBox::new(min, max), centroid)
        });
        key
    }

    /// The mean area of the faces of positive area, or `None` without one.
    pub fn mean_face_area(&self) -> Option<f64> {
        (self.area_faces > 0).then(|| self.area / self.area_faces as f64)
    }

    /// The plan of the counted faces (read from `input`), with a buffer `buffer` and the
    /// node spacing `spacing` every tile converts with (`pixel_factor` is 1).
    ///
    /// Errors: [`TilingError::NoPoints`] (no face), [`TilingError::InvalidOption`].
    pub fn plan(&self, input: &Path, buffer: f64, spacing: f32) -> Result<Plan, TilingError> {
        let size = self.grid.size;
        if !buffer_fits(buffer, size) {
            return Err(given_buffer_too_wide());
        }
        let (lo, hi) = self.bounds.ok_or_else(|| TilingError::NoPoints {
            path: input.to_path_buf(),
        })?;
        Ok(Plan {
            version: PLAN_VERSION,
            input: input.display().to_string(),
            points: self.faces,
            skipped_non_finite: 0,
            bounds: WorldBox::new(lo, hi),
            spacing,
            pixel_factor: 1.0,
            grid: PlanGrid {
                anchor: self.grid.anchor.to_array(),
                size,
                buffer,
            },
            tiles: tiles_of_counts(&self.counts, &self.grid, buffer),
            scan_shifts: None,
        })
    }
}

/// The census of a loaded `mesh`'s faces, on the grid of tiles of side `tile` anchored at
/// the lowest corner of its faces. Errors: [`TilingError::InvalidOption`].
pub fn census_mesh(mesh: &TriangleMesh, tile: f64) -> Result<MeshCensus, TilingError> {
    let world = |v: u32| mesh.origin + mesh.positions[v as usize].as_dvec3();
    let anchor = mesh
        .triangles
        .iter()
        .flatten()
        .map(|&v| world(v))
        .reduce(DVec3::min)
        .unwrap_or(DVec3::ZERO);
    let mut census = MeshCensus::new(anchor, tile)?;
    for face in mesh.faces() {
        let corners = mesh.triangles[face.index()].map(world);
        census.add(corners, mesh.face_area(face));
    }
    Ok(census)
}

/// Plans the tiles of `mesh` (read from `input`): [`census_mesh`], then
/// [`MeshCensus::plan`].
///
/// Errors: [`TilingError::NoPoints`] (no face), [`TilingError::InvalidOption`].
pub fn make_mesh_plan(
    mesh: &TriangleMesh,
    input: &Path,
    tile: f64,
    buffer: f64,
    spacing: f32,
) -> Result<Plan, TilingError> {
    census_mesh(mesh, tile)?.plan(input, buffer, spacing)
}

/// The census of the mesh in the PLY or plain OBJ file at `path` (see the module docs),
/// streamed: the grid is anchored at the lowest corner of its polygons, and every face is
/// taken at the anchor plus an f32 offset, as `read_mesh_tile` takes it.
///
/// Errors: [`TilingError::UnsupportedFormat`], the readers' I/O and format errors, a
/// corner naming no vertex.
pub fn census_mesh_file(path: &Path, tile: f64) -> Result<MeshCensus, TilingError> {
    let format = format_of(path).ok_or_else(|| TilingError::UnsupportedFormat {
        path: path.to_path_buf(),
    })?;
    let mut positions: Vec<DVec3> = Vec::new();
    each_vertex(path, format, &mut |p, _, _| {
        positions.push(p);
        Ok(())
    })?;
    let mut lowest: Option<DVec3> = None;
    each_polygon(path, format, &mut |polygon| {
        for &v in polygon {
            let p = corner(path, &positions, v)?;
            lowest = Some(lowest.map_or(p, |l| l.min(p)));
        }
        Ok(())
    })?;
    let anchor = lowest.unwrap_or(DVec3::ZERO);
    for p in &mut positions {
        *p = anchor + (*p - anchor).as_vec3().as_dvec3();
    }
    let mut census = MeshCensus::new(anchor, tile)?;
    let (mut split, mut points) = (Vec::new(), Vec::new());
    each_polygon(path, format, &mut |polygon| {
        points.clear();
        for &v in polygon {
            points.push(corner(path, &positions, v)?);
        }
        split.clear();
        if points.len() == 3 {
            split.push([0, 1, 2]);
        } else if points.len() > 3 {
            triangulate_polygon(&points, &mut split);
        }
        for t in &split {
            let corners = t.map(|k| points[k as usize]);
            if let Some(area) = kept_area(corners, anchor) {
                census.add(corners, area);
            }
        }
        Ok(())
    })?;
    Ok(census)
}

/// The position of vertex `v`, or an error naming it.
fn corner(path: &Path, positions: &[DVec3], v: u32) -> Result<DVec3, TilingError> {
    positions.get(v as usize).copied().ok_or_else(|| {
        let n = positions.len();
        TilingError::malformed(path, format!("a face names vertex {v} (from 0) of {n}"))
    })
}

/// The f32 area of a face at `anchor`, as the loaded mesh computes it, or `None` for a
/// face the mesh loader drops (two equal corners, or exactly zero area).
fn kept_area(corners: [DVec3; 3], anchor: DVec3) -> Option<f32> {
    let [a, b, c] = corners;
    if a == b || b == c || a == c || (b - a).cross(c - a) == DVec3::ZERO {
        return None;
    }
    let [a, b, c]: [Vec3; 3] = corners.map(|p| (p - anchor).as_vec3());
    let area = 0.5 * (b - a).cross(c - a).length();
    Some(if area.is_finite() {
        area
    } else {
        (0.5 * (b - a).as_dvec3().cross((c - a).as_dvec3()).length()) as f32
    })
}
