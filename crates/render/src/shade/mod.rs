//! Deferred shading: the resolve pass that shades each covered pixel of a
//! band once, after every sample has been drawn. In use order:
//! shaded colours as RGBA8, the draw items as Phong reads them, the resolve
//! pass.

pub(crate) mod colour_grid;
pub(crate) mod phong_items;
pub(crate) mod resolve;
pub(crate) mod resolve_inputs;
#[cfg(test)]
mod resolve_tests;
#[cfg(target_arch = "x86_64")]
pub(crate) mod resolve_wide;
pub(crate) mod rgba;
