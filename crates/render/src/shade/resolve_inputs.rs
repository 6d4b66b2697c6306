//! What the resolve pass reads ([`crate::shade::resolve`]): the frame's
//! draw items as the shading reads them, its material and depth range,
//! and the instruction set of its kernels. Its own module so that the
//! four- and eight-pixel kernels ([`crate::shade::resolve_wide`]) share
//! it without importing each other.
//!
//! Cost: none (plain data, built once per frame).

use glam::Vec3;

use crate::isa::Isa;
use crate::lighting::Material;
use crate::options::Shading;
use crate::plan::work::ChunkWork;
use crate::prepare::patch::PreparedPatch;
use crate::shade::phong_items::PhongItems;

/// How the resolve pass turns payloads into colours.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Resolve<'a> {
    pub(crate) shading: Shading,
    /// Draw items by index: `(chunk, item)`.
    pub(crate) items: &'a [(u32, u32)],
    pub(crate) chunks: &'a [ChunkWork],
    /// The draw items as the Phong resolve pass reads them.
    pub(crate) phong: &'a PhongItems<'a>,
    /// The prepared patches the items draw (for their colour grids; empty
    /// for a mesh).
    pub(crate) patches: &'a [PreparedPatch],
    pub(crate) material: Material,
    /// The albedo of nodes without colours, as stored in nodes (rounded to
    /// the attribute grid).
    pub(crate) base_albedo: Vec3,
    pub(crate) background: [u8; 4],
    pub(crate) near: f32,
    pub(crate) far: f32,
    /// The instruction set the resolve runs with: eight pixels at a time
    /// with AVX2 ([`crate::shade::resolve_wide`]), else four (read only
    /// on x86-64).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    pub(crate) isa: Isa,
}
