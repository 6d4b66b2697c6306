//! The shading inputs of one mip level's nodes ([`LevelShading`]): unit
//! patch-space normals rounded as projected nodes carry them, and albedos
//! as bytes, built once per scene the first time a Phong frame draws the
//! level ([`crate::prepare::patch::PreparedPatch::shading`]), eight nodes
//! at a time in lanes; for flat shading, each node's normal is that of
//! the cell it is the first corner of ([`LevelShading::flat`],
//! [`crate::prepare::patch::PreparedPatch::flat_shading`]).

use std::sync::OnceLock;

use glam::{Vec3, Vec4};
use spatch_format::EMPTY;

use crate::fixed::ATTR_ONE;
use crate::isa::Isa;
use crate::prepare::mip::MipLevel;
use crate::prepare::normal_buffer::{SlotSet, SlotSetBuilder};
use crate::prepare::normals::{
    grid_differences, node_differences, reconstruct_normal, unit_normals,
};
use crate::prepare::wide::{Portable, Wide, LANES};

/// The shading inputs of one mip level's nodes, row-major like its grid.
#[derive(Debug, Clone)]
pub(crate) struct LevelShading {
    /// Unit patch-space normal (`xyz`, `w` = 0) exactly as a projected node
    /// would carry it ([`crate::fixed::attr_to_bits`] rounding), zero for
    /// empty nodes.
    pub(crate) normals: Vec<Vec4>,
    /// Albedo (RGB bytes and a zero byte, [`crate::lighting::byte_lanes`] as floats) when
    /// the level has colours, else empty. Why bytes: the resolve pass reads
    /// four corners' albedos per pixel, and at four bytes rather than a
    /// sixteen-byte vector a coloured scan's shading inputs take 20 bytes
    /// per node instead of 32.
    pub(crate) colours: Vec<[u8; 4]>,
}

impl LevelShading {
    /// The inputs of a mip level with shading ratios `ratios` (at that
    /// level), with the lanes of `w`. Why each node's normal computed from
    /// its differences, eight nodes in lanes, rather than through a normal
    /// buffer: a scan's patches nearly all have ratios of their own, so the
    /// buffer's table was cleared for each and every distinct normal
    /// computed anyway, behind a slot lookup per node (the Phong inputs
    /// were 45.5 M of a one-frame bunny render's 226.5 M instructions;
    /// callgrind, `spatch render bunny.spatch -o out.png --threads 1`). The
    /// normals are the buffer's bit for bit (the same operations in the
    /// same order).
    /// With `slots` (a frame that counts its normal lookups), also sets
    /// the level's slot set there from the same differences, unless it is
    /// set already.
    #[inline(always)]
    fn new<W: Wide>(
        w: W,
        level: &MipLevel,
        ratios: (f32, f32),
        scratch: &mut NodeScratch,
        slots: Option<&OnceLock<Box<SlotSet>>>,
    ) -> Self {
        let (cols, rows) = (level.cols, level.rows);
        let d = &level.displacements;
        let (gi, gj) = (&mut scratch.gi, &mut scratch.gj);
        grid_differences(d, cols, rows, EMPTY, (&mut *gi, &mut *gj));
        if let Some(cell) = slots.filter(|c| c.get().is_none()) {
            // `set`, not `get_or_init`: a closure would be compiled without
            // the lanes' instruction set.
            let _ = cell.set(Box::new(used_slots(level, gi, gj)));
        }
        Self {
            normals: rounded_unit_normals(w, scratch, d, ratios),
            colours: level_colours(level),
        }
    }

    /// [`Self::new`] with the lanes of `isa`.
    pub(crate) fn with_isa(
        isa: Isa,
        level: &MipLevel,
        ratios: (f32, f32),
        slots: Option<&OnceLock<Box<SlotSet>>>,
    ) -> Self {
        // The scratch is borrowed outside the lanes' function: a closure
        // inside it is compiled without its instruction set.
        SCRATCH.with_borrow_mut(|scratch| match isa {
            Isa::Base => Self::new(Portable, level, ratios, scratch, slots),
            #[cfg(target_arch = "x86_64")]
            Isa::V3(v3) => v3.vectorize(
                #[inline(always)]
                || Self::new(v3, level, ratios, scratch, slots),
            ),
        })
    }

    /// Gives every filled node `(i, j)` of `coarse` (the level these
    /// inputs are for, one above `fine`) whose node `(2i, 2j)` of `fine` is
    /// filled the normal `fine_normals` holds for that node (`fine`'s
    /// prepared normals). Why: level 1 drawn past the mip limit
    /// ([`crate::RenderOptions::level_one_limit`]) with its own normals,
    /// which average a scan's noise over twice the span, showed blocks of
    /// flatter shading with steps at the seams to level-0 neighbours; with
    /// level 0's normals at the nodes the two levels share it keeps level
    /// 0's shading there, at level 1's memory (the resolve's cost).
    pub(crate) fn take_finer_normals(
        &mut self,
        coarse: &MipLevel,
        fine: &MipLevel,
        fine_normals: &[Vec4],
    ) {
        for j in 0..coarse.rows.min(fine.rows.div_ceil(2)) {
            for i in 0..coarse.cols.min(fine.cols.div_ceil(2)) {
                let (k, f) = (j * coarse.cols + i, 2 * j * fine.cols + 2 * i);
                if coarse.displacements[k] != EMPTY && fine.displacements[f] != EMPTY {
                    self.normals[k] = fine_normals[f];
                }
            }
        }
    }

    /// The flat-shading inputs of a level with shading ratios `ratios`:
    /// per filled node, the normal flat shading gives it (the normal of
    /// the cell it is the first corner of, the last column's and row's
    /// nodes that of the cell before them; the node's own unit normal
    /// where that cell is not drawable, as the normal buffer gives it),
    /// zero for empty nodes; the albedos as [`Self::new`] keeps them. Read
    /// with every weight on a sample's first corner, they give each pixel
    /// the colour flat shading gives its cell's first corner.
    pub(crate) fn flat(level: &MipLevel, ratios: (f32, f32)) -> Self {
        let (cols, rows) = (level.cols, level.rows);
        let mut normals = vec![Vec4::ZERO; cols * rows];
        for j in 0..rows {
            for i in 0..cols {
                if level.displacements[j * cols + i] != EMPTY {
                    normals[j * cols + i] = flat_node_normal(level, ratios, i, j).extend(0.0);
                }
            }
        }
        Self {
            normals,
            colours: level_colours(level),
        }
    }
}

/// The normal flat shading gives filled node `(i, j)` of `level` (see
/// [`LevelShading::flat`]); not unit when it is a cell's.
pub(crate) fn flat_node_normal(level: &MipLevel, ratios: (f32, f32), i: usize, j: usize) -> Vec3 {
    let (ci, cj) = (i.min(level.cols - 2), j.min(level.rows - 2));
    if level.cell_is_drawable(ci, cj) {
        return cell_normal(level, ratios, ci, cj);
    }
    let d = &level.displacements;
    let (gi, gj) = node_differences(d, level.cols, level.rows, i, j, EMPTY);
    reconstruct_normal(gi, gj, ratios.0, ratios.1).normalize()
}

/// The flat-shading normal of cell `(ci, cj)` of `level` (shading ratios
/// `ratios`), from its four corners' displacements; not unit.
fn cell_normal(level: &MipLevel, ratios: (f32, f32), ci: usize, cj: usize) -> Vec3 {
    let d = |a: usize, b: usize| level.displacements[b * level.cols + a] as i32;
    let du = d(ci + 1, cj) + d(ci + 1, cj + 1) - d(ci, cj) - d(ci, cj + 1);
    let dv = d(ci, cj + 1) + d(ci + 1, cj + 1) - d(ci, cj) - d(ci + 1, cj);
    reconstruct_normal(du, dv, ratios.0, ratios.1)
}

/// Per-node lanes inputs of one level's shading, their room reused.
struct NodeScratch {
    /// Displacement differences across rows and columns
    /// ([`grid_differences`]).
    gi: Vec<i32>,
    gj: Vec<i32>,
    /// 1 for a filled node, 0 for an empty node or padding.
    filled: Vec<i32>,
}

thread_local! {
    /// The room for a level's [`NodeScratch`], kept per thread. Why: fresh
    /// vectors per level were allocated and freed (the shading inputs of
    /// 1,988 levels in a one-frame bunny render).
    static SCRATCH: std::cell::RefCell<NodeScratch> = const {
        std::cell::RefCell::new(NodeScratch {
            gi: Vec::new(),
            gj: Vec::new(),
            filled: Vec::new(),
        })
    };
}

/// The albedos of `level`'s nodes as [`LevelShading::colours`] keeps them
/// (empty without colours).
fn level_colours(level: &MipLevel) -> Vec<[u8; 4]> {
    level.colours.as_ref().map_or_else(Vec::new, |c| {
        c.iter().map(|&[r, g, b, _]| [r, g, b, 0]).collect()
    })
}

/// The unit normals of nodes with differences `scratch.gi`, `scratch.gj`
/// and displacements `d`, rounded as projected nodes carry them
/// ([`crate::fixed::attr_to_bits`]); empty nodes get zero. Why eight nodes
/// at a time in lanes ([`unit_normals`], the rounding by [`Wide::trunc`],
/// which truncates as `as i32` does for these values, and a transpose to
/// node order): one by one, the three saturating conversions per node
/// were most of the cost. Why collected by whole groups of eight (the
/// differences padded), then cut to length: appending four at a time
/// checked the vector's room at each append (3.8 M of a one-frame bunny
/// render; callgrind). Why empty nodes zeroed by a lane select on a
/// filled flag: a test per node after the lanes cost 0.75 M of that
/// render (callgrind, `spatch render bunny.spatch -o out.png --threads 1`).
#[inline(always)]
fn rounded_unit_normals<W: Wide>(
    w: W,
    scratch: &mut NodeScratch,
    d: &[u16],
    ratios: (f32, f32),
) -> Vec<Vec4> {
    let (n, room) = (d.len(), d.len().next_multiple_of(LANES));
    let NodeScratch { gi, gj, filled } = scratch;
    gi.resize(room, 0);
    gj.resize(room, 0);
    filled.clear();
    filled.extend(d.iter().map(|&v| i32::from(v != EMPTY)));
    filled.resize(room, 0);
    let negated = (w.splat(-ratios.0), w.splat(-ratios.1));
    let (scale, unscale) = (w.splat(ATTR_ONE), w.splat(1.0 / ATTR_ONE));
    let round = |v| w.mul(w.trunc(w.mul(v, scale)), unscale);
    let (zero, half) = (w.splat(0.0), w.splat(0.5));
    // An empty node's lanes (`filled` 0) are zero.
    let keep = |v, filled| w.select_lt(filled, half, zero, v);
    // A loop, not an iterator's `collect`: the fold it called was left out
    // of line, without the caller's instruction set.
    let mut nodes: Vec<[Vec4; LANES]> = Vec::with_capacity(room / LANES);
    let groups = gi.chunks_exact(LANES).zip(gj.chunks_exact(LANES));
    for ((gi, gj), filled) in groups.zip(filled.chunks_exact(LANES)) {
        let [x, y, z] = unit_normals(w, w.load_i32(gi), w.load_i32(gj), negated);
        let f = w.load_i32(filled);
        nodes.push(w.columns([keep(round(x), f), keep(round(y), f), keep(round(z), f)]));
    }
    let mut nodes = nodes.into_flattened();
    nodes.truncate(n);
    nodes
}

/// The normal-buffer slots of `level`'s used nodes
/// ([`crate::prepare::patch::PreparedPatch::slot_set`]), with the lanes of
/// `isa`.
pub(crate) fn level_slot_set(isa: Isa, level: &MipLevel) -> SlotSet {
    // The scratch is borrowed outside the lanes' function (as in
    // `LevelShading::with_isa`); inside it the differences run in lanes
    // and the AVX2 copy counts a word with `popcnt`.
    SCRATCH.with_borrow_mut(|scratch| {
        let (gi, gj) = (&mut scratch.gi, &mut scratch.gj);
        let (d, cols, rows) = (&level.displacements, level.cols, level.rows);
        isa.run(
            #[inline(always)]
            || {
                grid_differences(d, cols, rows, EMPTY, (&mut *gi, &mut *gj));
                used_slots(level, gi, gj)
            },
        )
    })
}

/// The slot set of `level`'s used nodes from their displacement
/// differences `gi`, `gj` ([`grid_differences`]).
#[inline(always)]
fn used_slots(level: &MipLevel, gi: &[i32], gj: &[i32]) -> SlotSet {
    let mut slots = SlotSetBuilder::default();
    slots.add_used(&level.used, gi, gj);
    slots.finish()
}
