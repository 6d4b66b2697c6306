//! Deferred shading: the resolve pass that shades each covered pixel of a
//! band once, after every sample has been drawn. In use order:
//! splatted samples placed at their pixel centres, the draw items as Phong
//! reads them, the resolve pass.

pub(crate) mod phong_items;
pub(crate) mod resolve;
pub(crate) mod splat_centre;
#[cfg(test)]
mod resolve_tests;
