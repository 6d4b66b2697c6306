//! What a writer chooses from the whole scene before writing it (SCNE's storages, which
//! optional sections exist), gathered patch by patch: the in-memory encoder and the
//! streaming merge writer choose through this one type, so they choose alike.

use super::layout::{ColourStorage, GridStorage, SceneFields, WidthStorage};
use crate::{ColourChannel, DisplacementWidth, FormatError, GridSize, Patch, EMPTY};

/// The one colour of every filled node seen so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Flat {
    /// No filled node yet.
    Nothing,
    /// All filled nodes have this colour.
    One([u8; 4]),
    /// Two filled nodes differ (or a patch has no colour).
    Mixed,
}

/// The scene-wide facts a writer needs, gathered patch by patch ([`SceneShape::add`]).
#[derive(Debug, Clone)]
pub(crate) struct SceneShape {
    patches: u64,
    first_grid: Option<GridSize>,
    same_grid: bool,
    all_8: bool,
    all_16: bool,
    flat: Flat,
    residuals: bool,
    sides: bool,
}

impl SceneShape {
    /// The shape of a scene with no patch.
    pub(crate) fn new() -> Self {
        Self {
            patches: 0,
            first_grid: None,
            same_grid: true,
            all_8: true,
            all_16: true,
            flat: Flat::Nothing,
            residuals: false,
            sides: false,
        }
    }

    /// Takes `patch` into account.
    pub(crate) fn add(&mut self, patch: &Patch) {
        self.patches += 1;
        let grid = patch.grid();
        self.same_grid &= *self.first_grid.get_or_insert(grid) == grid;
        let width = patch.displacement_width();
        self.all_8 &= width == DisplacementWidth::Bits8;
        self.all_16 &= width == DisplacementWidth::Bits16;
        self.residuals |= patch.frame().origin_residual() != glam::Vec3::ZERO;
        self.sides |= patch.sides().code() != 0;
        self.flat = next_flat(self.flat, patch);
    }

    /// How grids are stored.
    pub(crate) fn grid_storage(&self) -> GridStorage {
        match self.first_grid {
            Some(_) if self.same_grid => GridStorage::Shared,
            _ => GridStorage::PerPatch,
        }
    }

    /// How widths are stored.
    pub(crate) fn width_storage(&self) -> WidthStorage {
        match (self.all_8, self.all_16) {
            (true, _) => WidthStorage::All8,
            (false, true) => WidthStorage::All16,
            _ => WidthStorage::PerPatch,
        }
    }

    /// How colours are stored in a scene of `channel`.
    pub(crate) fn colour_storage(&self, channel: ColourChannel) -> ColourStorage {
        match (channel, self.flat) {
            (ColourChannel::None, _) => ColourStorage::None,
            (_, Flat::One(_)) => ColourStorage::Flat,
            _ => ColourStorage::PerNode,
        }
    }

    /// Whether a patch has an origin residual (ORGR is written).
    pub(crate) fn has_residuals(&self) -> bool {
        self.residuals
    }

    /// Whether a patch is not front-only (SIDE is written).
    pub(crate) fn has_sides(&self) -> bool {
        self.sides
    }

    /// The SCNE fields of the scene.
    pub(crate) fn fields(
        &self,
        offset: [f64; 3],
        channel: ColourChannel,
    ) -> Result<SceneFields, FormatError> {
        let patch_count = u32::try_from(self.patches).map_err(|_| FormatError::TooManyPatches {
            count: self.patches,
        })?;
        let grid_storage = self.grid_storage();
        let shared = self
            .first_grid
            .filter(|_| grid_storage == GridStorage::Shared);
        let colour_storage = self.colour_storage(channel);
        let flat_colour = match (colour_storage, self.flat) {
            (ColourStorage::Flat, Flat::One(c)) => c,
            _ => [0; 4],
        };
        Ok(SceneFields {
            offset,
            patch_count,
            channel: match channel {
                ColourChannel::None => 0,
                ColourChannel::Rgb8 => 1,
                ColourChannel::Rgba8 => 2,
            },
            colour_storage,
            grid_storage,
            width_storage: self.width_storage(),
            shared_cols: shared.map_or(0, |g| g.cols()),
            shared_rows: shared.map_or(0, |g| g.rows()),
            flat_colour,
        })
    }
}

/// The flat colour after `patch` (the rule of [`crate::Scene::flat_colour`]).
fn next_flat(flat: Flat, patch: &Patch) -> Flat {
    let Some(colours) = patch.colours() else {
        return Flat::Mixed;
    };
    let mut flat = flat;
    for (c, &d) in colours.iter().zip(patch.displacements()) {
        flat = match flat {
            _ if d == EMPTY => flat,
            Flat::Nothing => Flat::One(*c),
            Flat::One(f) if f != *c => return Flat::Mixed,
            other => other,
        };
    }
    flat
}
