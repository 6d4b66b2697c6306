//! Per-node attributes for the shading model, written beside the projected
//! nodes after traversal ([`ChunkWork::node_attributes`]): Gouraud, the
//! node's shaded colour; Phong, nothing but the normal-buffer lookups the
//! nodes make (the resolve pass reads the prepared level's normals and
//! albedos, [`crate::prepare::level_shading::LevelShading`]); flat,
//! nothing (the resolve pass reads the level's prepared cell normals,
//! [`PreparedPatch::flat_shading`]). The attributes of a vertex of cells
//! drawn as triangles ([`node_attributes`]) carry the shaded colour for
//! flat too.
//!
//! Normals are reconstructed in patch space from displacement differences
//! ([`crate::prepare::normals`]) through the chunk's normal buffer.
//!
//! Cost: Gouraud, one shading per used node, four at a time, from the
//! level's kept normals; Phong, one bitset word per 64 slots for a level
//! drawn whole.

use glam::{Mat4, Vec3, Vec4};

use crate::fixed::{attr_to_bits, NodeAttributes, EMPTY_NODE, NODE_ATTRIBUTES};
use crate::lighting::{byte_lanes, Lanes, ShadeFrame, ANY_POWER};
use crate::options::Shading;
use crate::plan::split::NodeRange;
use crate::plan::work::{ChunkWork, FrameSetup, PatchContext};
use crate::prepare::level_shading::{flat_node_normal, LevelShading};
use crate::prepare::mip::MipLevel;
use crate::prepare::normal_buffer::NormalBuffer;
use crate::prepare::normals::{node_differences, OUTSIDE_TABLE};
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
    let (frame, setup) = (ctx.frame, ctx.setup);
    let albedo = node_albedo(level, j * level.cols + i, setup.base_colour);
    let shaded = |n: Vec3| {
        let c = setup.material.shade(n, frame, albedo);
        [c.x, c.y, c.z, 0.0, 0.0, 0.0]
    };
    match setup.options.shading {
        Shading::Phong => {
            let n = node_normal(normals, ctx, m, level, i, j);
            [n.x, n.y, n.z, albedo.x, albedo.y, albedo.z]
        }
        Shading::Gouraud => shaded(node_normal(normals, ctx, m, level, i, j)),
        Shading::Flat => shaded(flat_node_normal(level, ctx.patch.ratios_at(m), i, j)),
    }
}

/// The albedo of node `at` (row-major) of `level`: its colour, or `base`.
#[inline]
fn node_albedo(level: &MipLevel, at: usize, base: Vec3) -> Vec3 {
    match &level.colours {
        Some(c) => Vec3::new(c[at][0] as f32, c[at][1] as f32, c[at][2] as f32),
        None => base,
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
/// ([`fill_phong_attributes`]), for flat nothing (see the module header).
#[inline(always)]
pub(crate) fn fill_attributes(
    work: &mut ChunkWork,
    ctx: &PatchContext<'_>,
    m: usize,
    range: NodeRange,
    first: usize,
) {
    let (p, setup) = (ctx.patch, ctx.setup);
    if setup.options.shading == Shading::Flat {
        // The resolve pass reads the level's cell normals
        // ([`PreparedPatch::flat_shading`]), built here on a frame's first
        // use, on the planning threads.
        p.flat_shading(m);
        return;
    }
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
    if setup.options.normal_counts {
        // The normal lookups counted as for Phong (Gouraud reads the same normals).
        fill_phong_attributes(work, p, m, range, first);
    }
    // Why Gouraud reads the normals the prepared level keeps for the Phong
    // resolve ([`crate::prepare::level_shading::LevelShading`]) rather than
    // the chunk's normal buffer: a probe and a reconstruction per node took
    // a third of its planning (perf, bunny 1000²).
    let kept = p.shading(m);
    let level = p.level(m);
    // One entry per node from `first` on, as the node array.
    work.node_attributes.truncate(first);
    (work.node_attributes).resize(work.nodes.len(), [0; NODE_ATTRIBUTES]);
    work.to_shade.clear();
    let mut k = first;
    for j in range.j0..=range.j1 {
        for i in range.i0..=range.i1 {
            if work.nodes[k][0] != EMPTY_NODE {
                work.to_shade.push((k as u32, (j * level.cols + i) as u32));
            }
            k += 1;
        }
    }
    let nodes = (kept, &work.to_shade[..]);
    // The default shininess, 32, is five squarings (see
    // [`crate::lighting::Material::shade4_with`]).
    match setup.material.squarings() {
        5 => shade_nodes::<5>(setup, ctx.frame, nodes, &mut work.node_attributes),
        _ => shade_nodes::<ANY_POWER>(setup, ctx.frame, nodes, &mut work.node_attributes),
    }
}

/// Shades the nodes of `kept` (a level's shading inputs) that `nodes`
/// names (index into `out`, index into the level) into their entries of
/// `out`, four at a time ([`crate::lighting::Material::shade4_with`],
/// bit-identical to [`crate::lighting::Material::shade`] one by one), the
/// four normals and albedos gathered by transposes. Why lanes and
/// transposes: the scalar shading of each node was a fifth of a Gouraud
/// frame (perf, bunny 1000²), and gathering each lane's components one by
/// one cost the shading's time again (1.5 ms of a one-thread 500² bunny
/// frame for 72 k nodes, where Phong's resolve shades 69 k pixels in 0.9).
#[inline(always)]
fn shade_nodes<const SQUARINGS: u32>(
    setup: &FrameSetup<'_>,
    frame: &ShadeFrame,
    (kept, nodes): (&LevelShading, &[(u32, u32)]),
    out: &mut [NodeAttributes],
) {
    let splat = |v: Vec3| [Vec4::splat(v.x), Vec4::splat(v.y), Vec4::splat(v.z)];
    let (light, half, view) = (splat(frame.light), splat(frame.half), splat(frame.view));
    let base = splat(setup.base_colour);
    let rows = |v: [Vec4; 4]| {
        let t = Mat4::from_cols(v[0], v[1], v[2], v[3]).transpose();
        [t.x_axis, t.y_axis, t.z_axis]
    };
    for group in nodes.chunks(4) {
        // Lanes past the group's end shade zeros, written nowhere.
        let mut at = [None; 4];
        for (lane, &(_, a)) in at.iter_mut().zip(group) {
            *lane = Some(a as usize);
        }
        let normal = at.map(|a| a.map_or(Vec4::ZERO, |a| kept.normals[a]));
        let albedo = match kept.colours.is_empty() {
            true => base,
            false => rows(at.map(|a| a.map_or(Vec4::ZERO, |a| byte_lanes(kept.colours[a])))),
        };
        let rgb = setup.material.shade4_with::<SQUARINGS>(&Lanes {
            normal: rows(normal),
            light,
            half,
            view,
            albedo,
        });
        for (lane, &(k, _)) in group.iter().enumerate() {
            let colour = [rgb[0][lane], rgb[1][lane], rgb[2][lane], 0.0];
            out[k as usize] = colour.map(attr_to_bits);
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
    let (width, height) = range.size();
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
