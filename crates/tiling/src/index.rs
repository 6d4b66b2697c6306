//! Tiled scenes: an index (JSON) listing a plan's tile files with their bounds and counts,
//! so a viewer loads only the tiles it needs (the schema is in `docs/scale.md`).
//!
//! The index is made from the plan and the tile files alone, in plan order, so every run of
//! the same plan (local, GNU parallel, Dask, any worker count) writes the same bytes; so is
//! its coarse level ([`crate::coarse`], `coarse.spatch` beside it).

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::{Deserialize, Serialize};
use spatch_format::{read_scene, write_scene, Scene, WriteOptions};

use crate::coarse::{coarse_scene, COARSE_FILE, COARSE_STEP};
use crate::plan::{Plan, PlanGrid, WorldBox};
use crate::TilingError;

/// The index format's version (the `version` field).
pub const INDEX_VERSION: u32 = 1;

/// The file name of tile `index`'s scene in a run's directory.
pub fn tile_file_name(index: usize) -> String {
    format!("tile_{index:05}.spatch")
}

/// One tile of a tiled scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IndexTile {
    /// Its index in the plan.
    pub index: usize,
    /// Its grid key.
    pub key: [i64; 3],
    /// Its scene file, relative to the index's directory.
    pub file: String,
    /// The box it owns (every patch's anchor is inside).
    pub bounds: WorldBox,
    /// The bounds of its filled nodes (`null` for a tile with no patch); they may reach a
    /// little past `bounds` (a patch covers the points it was cut for and its border cells).
    pub scene_bounds: Option<WorldBox>,
    /// Its patches.
    pub patches: usize,
    /// Its grid nodes.
    pub nodes: usize,
    /// Its filled nodes.
    pub filled_nodes: usize,
    /// Its file's size in bytes.
    pub bytes: u64,
}

/// A tiled scene (see the module documentation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneIndex {
    /// [`INDEX_VERSION`].
    pub version: u32,
    /// The plan's input.
    pub input: String,
    /// The plan's grid.
    pub grid: PlanGrid,
    /// The union of the tiles' scene bounds (`null` when no tile has a patch).
    pub bounds: Option<WorldBox>,
    /// The tiles in plan order.
    pub tiles: Vec<IndexTile>,
    /// The coarse level (absent from indexes written before it existed, and when no tile
    /// has a patch).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coarse: Option<CoarseLevel>,
}

/// The coarse level of a tiled scene: every tile's patches with one node in `step` kept
/// along each axis, in one file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CoarseLevel {
    /// Its scene file, relative to the index's directory.
    pub file: String,
    /// One node in this many kept along each grid axis.
    pub step: usize,
    /// Its patches.
    pub patches: usize,
    /// Its grid nodes.
    pub nodes: usize,
    /// Its file's size in bytes.
    pub bytes: u64,
    /// The largest node spacing of its patches (model units): its cells are at most this
    /// wide (0 when unknown: never picked automatically).
    #[serde(default)]
    pub cell: f64,
}

impl CoarseLevel {
    /// Whether the level looks the same as the tiles from `eye` for a view of
    /// `fov_y_degrees` over `pixels` rows, the scene within `bounds`: its cells, at the
    /// scene's nearest point, project to less than one pixel.
    pub fn fine_enough(
        &self,
        bounds: &WorldBox,
        eye: DVec3,
        fov_y_degrees: f64,
        pixels: u32,
    ) -> bool {
        let (lo, hi) = (DVec3::from_array(bounds.min), DVec3::from_array(bounds.max));
        let distance = (eye.clamp(lo, hi) - eye).length();
        let pixel =
            distance * 2.0 * (fov_y_degrees.to_radians() / 2.0).tan() / f64::from(pixels.max(1));
        self.cell > 0.0 && self.cell < pixel
    }
}

/// The index of `plan`'s tiles written in `dir` (as [`tile_file_name`]); writes its coarse
/// level, [`COARSE_FILE`], in `dir` too (reading one tile at a time).
///
/// Errors: [`TilingError::Io`] / [`TilingError::BadJson`] for a missing or unreadable tile
/// file, [`TilingError::Io`] when the coarse level cannot be written.
pub fn build_index(plan: &Plan, dir: &Path) -> Result<SceneIndex, TilingError> {
    let mut tiles = Vec::with_capacity(plan.tiles.len());
    let mut coarse = Vec::new();
    let mut bounds: Option<WorldBox> = None;
    for tile in &plan.tiles {
        let file = tile_file_name(tile.index);
        let path = dir.join(&file);
        let bytes = std::fs::metadata(&path)
            .map_err(|e| TilingError::io(&path, e))?
            .len();
        let scene = read_scene(&path).map_err(|e| TilingError::BadJson {
            path: path.clone(),
            reason: format!("not a readable tile: {e}"),
        })?;
        let scene_bounds = scene.bounds().map(|(lo, hi)| WorldBox::new(lo, hi));
        if !scene.patches().is_empty() {
            coarse.push(
                coarse_scene(&scene, COARSE_STEP).map_err(|e| TilingError::BadJson {
                    path: path.clone(),
                    reason: format!("cannot make its coarse level: {e}"),
                })?,
            );
        }
        if let Some(b) = scene_bounds {
            bounds = Some(match bounds {
                None => b,
                Some(u) => union(&u, &b),
            });
        }
        tiles.push(IndexTile {
            index: tile.index,
            key: tile.key,
            file,
            bounds: tile.bounds,
            scene_bounds,
            patches: scene.patches().len(),
            nodes: scene.node_count(),
            filled_nodes: scene.filled_node_count(),
            bytes,
        });
    }
    Ok(SceneIndex {
        version: INDEX_VERSION,
        input: plan.input.clone(),
        grid: plan.grid,
        bounds,
        tiles,
        coarse: write_coarse(coarse, dir)?,
    })
}

/// Joins the tiles' coarse scenes and writes them as [`COARSE_FILE`] in `dir` (none
/// without a scene; a stale file is then removed).
fn write_coarse(scenes: Vec<Scene>, dir: &Path) -> Result<Option<CoarseLevel>, TilingError> {
    let path = dir.join(COARSE_FILE);
    let failed = |reason: String| TilingError::BadJson {
        path: path.clone(),
        reason,
    };
    if scenes.is_empty() {
        return match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(TilingError::io(&path, e)),
            _ => Ok(None),
        };
    }
    let scene = Scene::merge(scenes).map_err(|e| failed(format!("cannot join the tiles: {e}")))?;
    write_scene(&path, &scene, &WriteOptions::default())
        .map_err(|e| failed(format!("cannot write: {e}")))?;
    let bytes = std::fs::metadata(&path)
        .map_err(|e| TilingError::io(&path, e))?
        .len();
    let cell = scene
        .patches()
        .iter()
        .map(|p| {
            let [x, y, _] = p.frame().lengths();
            f64::from(x.max(y))
        })
        .fold(0.0, f64::max);
    Ok(Some(CoarseLevel {
        file: COARSE_FILE.to_string(),
        step: COARSE_STEP,
        patches: scene.patches().len(),
        nodes: scene.node_count(),
        bytes,
        cell,
    }))
}

fn union(a: &WorldBox, b: &WorldBox) -> WorldBox {
    WorldBox {
        min: [0, 1, 2].map(|k| a.min[k].min(b.min[k])),
        max: [0, 1, 2].map(|k| a.max[k].max(b.max[k])),
    }
}

impl SceneIndex {
    /// The index as pretty JSON with a final newline.
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text
    }

    /// Reads an index; tile files are then relative to `path`'s directory.
    ///
    /// Errors: [`TilingError::Io`], [`TilingError::BadJson`].
    pub fn read(path: &Path) -> Result<SceneIndex, TilingError> {
        let text = std::fs::read_to_string(path).map_err(|e| TilingError::io(path, e))?;
        let index: SceneIndex = serde_json::from_str(&text).map_err(|e| TilingError::BadJson {
            path: path.to_path_buf(),
            reason: format!("not a tiled scene index: {e}"),
        })?;
        if index.version != INDEX_VERSION {
            return Err(TilingError::BadJson {
                path: path.to_path_buf(),
                reason: format!(
                    "index version {} (this spatch reads {INDEX_VERSION})",
                    index.version
                ),
            });
        }
        Ok(index)
    }

    /// The coarse level's file for an index read from `index_path`, if it has one.
    pub fn coarse_path(&self, index_path: &Path) -> Option<PathBuf> {
        let coarse = self.coarse.as_ref()?;
        Some(
            index_path
                .parent()
                .unwrap_or_else(|| Path::new("."))
                .join(&coarse.file),
        )
    }

    /// Tile `tile`'s file for an index read from `index_path`.
    pub fn tile_path(index_path: &Path, tile: &IndexTile) -> PathBuf {
        index_path
            .parent()
            .unwrap_or_else(|| Path::new("."))
            .join(&tile.file)
    }
}

/// Whether a JSON file looks like a tiled scene index (its `version` and `tiles` fields),
/// read cheaply enough to decide how to open a file.
pub fn is_index_file(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coarse_level_is_fine_enough_only_where_its_cells_are_under_a_pixel() {
        let level = |cell| CoarseLevel {
            file: COARSE_FILE.to_string(),
            step: COARSE_STEP,
            patches: 1,
            nodes: 4,
            bytes: 0,
            cell,
        };
        let bounds = WorldBox::new(DVec3::ZERO, DVec3::splat(100.0));
        // 90° over 1000 rows: a pixel is 2·distance/1000; the nearest point is 900 away.
        let eye = DVec3::new(50.0, 50.0, 1000.0);
        assert!(level(1.7).fine_enough(&bounds, eye, 90.0, 1000));
        assert!(!level(1.9).fine_enough(&bounds, eye, 90.0, 1000));
        // More pixels, or an eye inside the bounds: too coarse; unknown cells: never.
        assert!(!level(1.7).fine_enough(&bounds, eye, 90.0, 2000));
        assert!(!level(1e-9).fine_enough(&bounds, DVec3::splat(50.0), 90.0, 1000));
        assert!(!level(0.0).fine_enough(&bounds, eye, 90.0, 1000));
    }
}
