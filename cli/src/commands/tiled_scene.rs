//! `spatch render INDEX.json`: a tiled scene (docs/scale.md) drawn from only the tiles
//! whose bounds the camera may see; the others are never read.

use std::path::Path;

use anyhow::Context;
use glam::DVec3;
use spatch_format::{ColourChannel, ContainerInfo, Scene};
use spatch_render::Camera;
use spatch_tiling::{SceneIndex, ViewPyramid, WorldBox};

use crate::output::read_spatch;

/// The tiles in view, merged into one scene.
pub(crate) struct VisibleTiles {
    /// Their patches.
    pub(crate) scene: Scene,
    /// The first tile's container, with `file_len` the bytes of every tile read.
    pub(crate) info: Option<ContainerInfo>,
    /// Tiles read.
    pub(crate) loaded: usize,
    /// Tiles in the index.
    pub(crate) total: usize,
}

/// Whether `path` names a tiled scene index rather than a `.spatch` file.
pub(crate) fn is_index(path: &Path) -> bool {
    spatch_tiling::is_index_file(path)
}

/// The index's bounding sphere (centre, radius), or `None` when no tile has a patch.
pub(crate) fn index_sphere(index: &SceneIndex) -> Option<(DVec3, f64)> {
    let b = index.bounds?;
    let (lo, hi) = (DVec3::from_array(b.min), DVec3::from_array(b.max));
    Some(((lo + hi) / 2.0, ((hi - lo) / 2.0).length().max(1e-9)))
}

/// Reads the tiles of `index` (read from `path`) that `camera` may see, cut at `far`.
pub(crate) fn read_visible_tiles(
    path: &Path,
    index: &SceneIndex,
    camera: &Camera,
    far: Option<f64>,
) -> anyhow::Result<VisibleTiles> {
    let view = ViewPyramid::new(
        camera.eye(),
        camera.target(),
        camera.up(),
        camera.fov_y_degrees(),
        (camera.width(), camera.height()),
        far,
    )
    .context("the camera looks nowhere (eye at the target, or up along the view)")?;
    read_tiles(path, index, &|bounds| view.may_see(bounds))
}

/// Reads every tile of the index at `path` that holds patches, joined into one scene
/// (`spatch view INDEX.json`: an orbit sees every side, so every tile is read).
pub(crate) fn read_all_tiles(path: &Path) -> anyhow::Result<Scene> {
    let index = SceneIndex::read(path).map_err(anyhow::Error::msg)?;
    Ok(read_tiles(path, &index, &|_| true)?.scene)
}

/// Reads the tiles of `index` (read from `path`) that hold patches and whose scene bounds
/// `wanted` accepts, joined into one scene.
fn read_tiles(
    path: &Path,
    index: &SceneIndex,
    wanted: &dyn Fn(&WorldBox) -> bool,
) -> anyhow::Result<VisibleTiles> {
    let mut scenes = Vec::new();
    let mut info: Option<ContainerInfo> = None;
    let mut bytes = 0;
    for tile in &index.tiles {
        let Some(bounds) = tile.scene_bounds else {
            continue;
        };
        if tile.patches == 0 || !wanted(&bounds) {
            continue;
        }
        let (scene, tile_info) = read_spatch(&SceneIndex::tile_path(path, tile))?;
        bytes += tile_info.file_len;
        info.get_or_insert(tile_info);
        scenes.push(scene);
    }
    let loaded = scenes.len();
    if let Some(info) = &mut info {
        info.file_len = bytes;
    }
    let scene = if scenes.is_empty() {
        let anchor = WorldBox::new(DVec3::from_array(index.grid.anchor), DVec3::ZERO).min;
        Scene::new(DVec3::from_array(anchor), ColourChannel::None, Vec::new())?
    } else {
        Scene::merge(scenes).with_context(|| format!("{}: joining the tiles", path.display()))?
    };
    Ok(VisibleTiles {
        scene,
        info,
        loaded,
        total: index.tiles.len(),
    })
}
