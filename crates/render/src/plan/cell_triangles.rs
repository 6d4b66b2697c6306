//! Cells as triangles: every drawable cell of a node range as two
//! triangles, clipped against the near plane and projected
//! ([`crate::raster::triangle_raster`]). The path of `--mode triangles`, of
//! single cells crossing the near plane after splitting, and of pieces
//! whose cells are too large to subdivide (of those, only the cells their
//! measurement draws: not the ones facing away).
//!
//! Cost: one attribute evaluation per used node, one clip and projection
//! per triangle.

use glam::Vec3;

use crate::grid::CELL_DRAW;
use crate::lighting::pack_colour;
use crate::options::Shading;
use crate::plan::attributes::{node_attributes, node_normal};
use crate::plan::project::level_map;
use crate::plan::split::NodeRange;
use crate::plan::work::{ChunkWork, PatchContext};
use crate::prepare::mip::MipLevel;
use crate::prepare::normal_buffer::NormalBuffer;
use crate::prepare::patch::grid_level;
use crate::raster::triangle_raster::{clip_and_project, ClipOutcome, ClipVertex, TRI_ATTRS};

/// Emits every drawable cell of `range` (level `m`) as two triangles,
/// clipped against the near plane. With `measured`, the index in
/// `work.cell_flags` of the range's measured flags
/// ([`crate::plan::measure::measure_cells`]), only the cells they draw:
/// cells facing away are left out as the sub-node path leaves them out.
/// Returns the triangles emitted.
pub(crate) fn emit_cell_triangles(
    work: &mut ChunkWork,
    ctx: &PatchContext<'_>,
    m: usize,
    range: NodeRange,
    measured: Option<usize>,
) -> u64 {
    let (setup, index) = (ctx.setup, ctx.index);
    let level = ctx.patch.level(m);
    let (cols, rows) = range.size();
    // Why grid attributes: a triangle sample has no patch position for
    // the resolve pass to read a colour grid at, so the cell's triangles
    // carry it (perspective-correct) and the band reads the grid as it
    // stores the sample (`crate::frame::tiles`). Flat keeps one colour.
    let grid = ctx.patch.colour_grid.is_some() && setup.options.shading != Shading::Flat;
    let first_triangle = work.triangles.len();
    let mut vertices = std::mem::take(&mut work.vertices);
    vertices.clear();
    let used = clip_vertices(work, ctx, (m, range), grid, &mut vertices);
    work.counters.patch_nodes += used;
    let near = setup.view.near as f32;
    let size = (setup.view.width as f32, setup.view.height as f32);
    let mut emitted = 0;
    for cj in 0..rows - 1 {
        for ci in 0..cols - 1 {
            let drawn = match measured {
                Some(first) => work.cell_flags[first + cj * (cols - 1) + ci] & CELL_DRAW != 0,
                None => level.cell_is_drawable(range.i0 + ci, range.j0 + cj),
            };
            if !drawn {
                continue;
            }
            let k = cj * cols + ci;
            let (v00, v10, v01, v11) = (
                vertices[k],
                vertices[k + 1],
                vertices[k + cols],
                vertices[k + cols + 1],
            );
            let a = v00.attrs;
            let flat = pack_colour(Vec3::new(a[0], a[1], a[2]));
            for tri in [[v00, v10, v11], [v00, v11, v01]] {
                match clip_and_project(&tri, near, size, index, flat, &mut work.triangles) {
                    ClipOutcome::Dropped => {}
                    ClipOutcome::Whole => emitted += 1,
                    ClipOutcome::Clipped(c) => {
                        emitted += c as u64;
                        work.counters.triangles_clipped += 1;
                    }
                }
            }
        }
    }
    if grid {
        for t in &mut work.triangles[first_triangle..] {
            t.grid = true;
        }
    }
    work.counters.triangles += emitted;
    work.vertices = vertices;
    emitted
}

/// Appends to `vertices` the clip-space vertex of every node of `range` of
/// level `m` (row by row; a zero vertex for unused nodes) with its
/// attributes (`grid`: those of a cell triangle reading a colour grid);
/// returns how many nodes are used.
fn clip_vertices(
    work: &mut ChunkWork,
    ctx: &PatchContext<'_>,
    (m, range): (usize, NodeRange),
    grid: bool,
    vertices: &mut Vec<ClipVertex>,
) -> u64 {
    let level = ctx.patch.level(m);
    let lmap = level_map(&ctx.map, m);
    let mut used = 0;
    for j in range.j0..=range.j1 {
        for i in range.i0..=range.i1 {
            let k = j * level.cols + i;
            let d = level.displacements[k];
            let v = if level.used[k] {
                used += 1;
                let attrs = if grid {
                    grid_attributes(&mut work.normals, ctx, m, level, i, j)
                } else {
                    node_attributes(&mut work.normals, ctx, m, level, i, j)
                };
                ClipVertex {
                    clip: lmap * Vec3::new(i as f32, j as f32, d as f32) + ctx.t0,
                    attrs,
                }
            } else {
                ClipVertex {
                    clip: Vec3::ZERO,
                    attrs: [0.0; TRI_ATTRS],
                }
            };
            vertices.push(v);
        }
    }
    used
}

/// The attributes of node `(i, j)` of `level` (level `m`) on a cell
/// triangle of a patch with a colour grid: Phong, the normal; Gouraud, the
/// light's factor (the node shaded white, over 255, so that the band
/// multiplies it by the grid's albedo as [`crate::shade::colour_grid::relight`]
/// does); then the node's position in level-0 grid units, where the grid is
/// read.
fn grid_attributes(
    normals: &mut NormalBuffer,
    ctx: &PatchContext<'_>,
    m: usize,
    level: &MipLevel,
    i: usize,
    j: usize,
) -> [f32; TRI_ATTRS] {
    let n = node_normal(normals, ctx, m, level, i, j);
    let light = match ctx.setup.options.shading {
        Shading::Phong => n,
        _ => ctx.setup.material.shade(n, ctx.frame, Vec3::splat(255.0)) / 255.0,
    };
    let step = (1u32 << grid_level(m)) as f32;
    [
        light.x,
        light.y,
        light.z,
        i as f32 * step,
        j as f32 * step,
        0.0,
    ]
}
