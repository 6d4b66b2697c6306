//! Per-node attributes for the shading model, written beside the projected
//! nodes after traversal ([`ChunkWork::node_attributes`]): the shaded
//! colour (flat: the cell's; Gouraud: the node's) or, for Phong, nothing
//! but the normal-buffer lookups the nodes make (the resolve pass reads the
//! prepared level's normals and albedos,
//! [`crate::prepare::level_shading::LevelShading`]).
//!
//! Normals are reconstructed in patch space from displacement differences
//! ([`crate::prepare::normals`]) through the chunk's normal buffer.
//!
//! Cost: one normal-buffer probe and one shading per used node (Gouraud,
//! flat), or one bitset word per 64 slots for a Phong level drawn whole.

use glam::Vec3;

use crate::fixed::{attr_to_bits, EMPTY_NODE, NODE_ATTRIBUTES};
use crate::options::Shading;
use crate::plan::split::NodeRange;
use crate::plan::work::{ChunkWork, PatchContext};
use crate::prepare::mip::MipLevel;
use crate::prepare::normal_buffer::NormalBuffer;
use crate::prepare::normals::{node_differences, reconstruct_normal, OUTSIDE_TABLE};
use crate::prepare::patch::PreparedPatch;
use crate::raster::triangle_raster::TRI_ATTRS;

/// Attributes of node `(i, j)` of `level` for the shading model.
#[inline]
pub(crate) fn node_attributes(
    normals: &mut NormalBuffer,
    ctx: &PatchContext<'_>,
    m: usize,
    level: &MipLevel,
    i: usize,
    j: usize,
) -> [f32; TRI_ATTRS] {
    let (p, frame, setup) = (ctx.patch, ctx.frame, ctx.setup);
    let k = j * level.cols + i;
    let albedo = match &level.colours {
        Some(c) => Vec3::new(c[k][0] as f32, c[k][1] as f32, c[k][2] as f32),
        None => setup.base_colour,
    };
    let ratios = p.ratios_at(m);
    let node_normal = |normals: &mut NormalBuffer| node_normal(normals, ctx, m, level, i, j);
    match setup.options.shading {
        Shading::Phong => {
            let n = node_normal(normals);
            [n.x, n.y, n.z, albedo.x, albedo.y, albedo.z]
        }
        Shading::Gouraud => {
            let c = setup.material.shade(node_normal(normals), frame, albedo);
            [c.x, c.y, c.z, 0.0, 0.0, 0.0]
        }
        Shading::Flat => {
            let (ci, cj) = (i.min(level.cols - 2), j.min(level.rows - 2));
            let n = if level.cell_is_drawable(ci, cj) {
                let d = |a: usize, b: usize| level.displacements[b * level.cols + a] as i32;
                let du = d(ci + 1, cj) + d(ci + 1, cj + 1) - d(ci, cj) - d(ci, cj + 1);
                let dv = d(ci, cj + 1) + d(ci + 1, cj + 1) - d(ci, cj) - d(ci + 1, cj);
                reconstruct_normal(du, dv, ratios.0, ratios.1)
            } else {
                node_normal(normals)
            };
            let c = setup.material.shade(n, frame, albedo);
            [c.x, c.y, c.z, 0.0, 0.0, 0.0]
        }
    }
}

/// The patch-space normal of node `(i, j)` of `level` (level `m` of the
/// patch of `ctx`), through the chunk's normal buffer.
#[inline]
pub(crate) fn node_normal(
    normals: &mut NormalBuffer,
    ctx: &PatchContext<'_>,
    m: usize,
    level: &MipLevel,
    i: usize,
    j: usize,
) -> Vec3 {
    let (gi, gj) = node_differences(
        &level.displacements,
        level.cols,
        level.rows,
        i,
        j,
        spatch_format::EMPTY,
    );
    normals.normal(m, ctx.patch.ratios_at(m), gi, gj)
}

/// Writes the attributes of the used nodes of `range` of level `m`
/// (projected from node `first` on in the chunk's node array) for the
/// shading model: for Phong only the normal-buffer lookups are counted
/// ([`fill_phong_attributes`]).
#[inline(always)]
pub(crate) fn fill_attributes(
    work: &mut ChunkWork,
    ctx: &PatchContext<'_>,
    m: usize,
    range: NodeRange,
    first: usize,
) {
    let (p, setup) = (ctx.patch, ctx.setup);
    if setup.options.shading == Shading::Phong {
        if setup.options.normal_counts {
            fill_phong_attributes(work, p, m, range, first);
        } else {
            // The level's shading inputs are built here on a frame's first
            // use, on the planning threads; nothing is counted.
            p.shading(m);
        }
        return;
    }
    let level = p.level(m);
    // One entry per node from `first` on, as the node array.
    work.node_attributes.truncate(first);
    (work.node_attributes).resize(work.nodes.len(), [0; NODE_ATTRIBUTES]);
    let mut k = first;
    for j in range.j0..=range.j1 {
        for i in range.i0..=range.i1 {
            if work.nodes[k][0] != EMPTY_NODE {
                let a = node_attributes(&mut work.normals, ctx, m, level, i, j);
                work.node_attributes[k] = [a[0], a[1], a[2], a[3]].map(attr_to_bits);
            }
            k += 1;
        }
    }
}

/// The Phong attributes of a piece: none. The resolve pass reads the
/// normals and albedos of the prepared level
/// ([`crate::prepare::level_shading::LevelShading`]); this only counts the normal-buffer
/// lookups the nodes make, when [`crate::RenderOptions::normal_counts`]
/// asks (the statistics keep their meaning; a level drawn whole, whose
/// non-empty nodes are its used nodes, is counted from its slot set,
/// [`PreparedPatch::slot_set`]). Why: copying three normal words (and the albedo)
/// into every node cost ~50 instructions per node, 7.4 M per 500² sphere
/// frame (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn fill_phong_attributes(
    work: &mut ChunkWork,
    p: &PreparedPatch,
    m: usize,
    range: NodeRange,
    first: usize,
) {
    let level = p.level(m);
    // The level's shading inputs are built here on a frame's first use, on
    // the planning threads (with the slot set the count below reads).
    p.counted_shading(m);
    let normals = &mut work.normals;
    normals.select(m, p.ratios_at(m));
    if range.i0 == 0 && range.j0 == 0 && range.i1 + 1 == level.cols && range.j1 + 1 == level.rows {
        // The whole level: its used nodes, whose slots are found once.
        normals.touch_all(m, p.slot_set(m));
        return;
    }
    let width = range.i1 - range.i0 + 1;
    let height = range.j1 - range.j0 + 1;
    let piece = &work.nodes[first..first + width * height];
    for (j, out) in (range.j0..=range.j1).zip(piece.chunks_exact(width)) {
        let row = j * level.cols + range.i0;
        let slots = &level.normal_slots()[row..row + width];
        for (node, &slot) in out.iter().zip(slots) {
            if node[0] == EMPTY_NODE {
                continue;
            }
            if slot != OUTSIDE_TABLE {
                normals.touch_at(m, slot);
            } else {
                normals.touch_outside();
            }
        }
    }
}
