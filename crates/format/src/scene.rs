//! A scene: patches in one model space, placed by an `f64` offset.

use glam::DVec3;

use crate::{FormatError, InsideBox, Opening, Patch};

/// What colour each node carries, for the whole scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ColourChannel {
    /// No colour: nothing is stored.
    None,
    /// Red, green, blue bytes (sRGB).
    Rgb8,
    /// Red, green, blue, alpha bytes (sRGB, straight alpha).
    Rgba8,
}

impl ColourChannel {
    /// `"none"`, `"rgb8"` or `"rgba8"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::None => "none",
            Self::Rgb8 => "rgb8",
            Self::Rgba8 => "rgba8",
        }
    }

    /// Bytes per node in the file (0, 3 or 4).
    pub fn bytes_per_node(self) -> usize {
        match self {
            Self::None => 0,
            Self::Rgb8 => 3,
            Self::Rgba8 => 4,
        }
    }
}

/// A set of patches. Node positions are `offset + (patch-relative f32 point)`.
///
/// # Guarantees
/// `offset` is finite; every patch has colours exactly when the channel is
/// not [`ColourChannel::None`]; in an RGB scene every filled node's alpha is 255.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    offset: DVec3,
    channel: ColourChannel,
    patches: Vec<Patch>,
    openings: Vec<Opening>,
    inside_box: Option<InsideBox>,
}

impl Scene {
    /// Builds a scene. RGB scenes get alpha 255 on every filled node.
    pub fn new(
        offset: DVec3,
        channel: ColourChannel,
        mut patches: Vec<Patch>,
    ) -> Result<Self, FormatError> {
        if !offset.is_finite() {
            return Err(FormatError::InvalidOffset);
        }
        for (index, patch) in patches.iter_mut().enumerate() {
            let has = patch.colours().is_some();
            match (channel, has) {
                (ColourChannel::None, true) => {
                    return Err(FormatError::ColourMismatch {
                        patch: index,
                        problem: "has colours but the scene has no colour channel",
                    })
                }
                (ColourChannel::Rgb8 | ColourChannel::Rgba8, false) => {
                    return Err(FormatError::ColourMismatch {
                        patch: index,
                        problem: "has no colours but the scene has a colour channel",
                    })
                }
                _ => {}
            }
            if channel == ColourChannel::Rgb8 {
                if let Some(grid) = patch.colour_grid_mut() {
                    grid.samples_mut().iter_mut().for_each(|c| c[3] = 255);
                }
                let displacements = patch.displacements().to_vec();
                if let Some(colours) = patch.colours_mut() {
                    for (c, d) in colours.iter_mut().zip(displacements) {
                        if d != crate::EMPTY {
                            c[3] = 255;
                        }
                    }
                }
            }
        }
        Ok(Self {
            offset,
            channel,
            patches,
            openings: Vec::new(),
            inside_box: None,
        })
    }

    /// The scene with `openings` (relative to the offset): the boundary loops through which
    /// the back of its [`Sides::ThroughOpenings`](crate::Sides::ThroughOpenings) patches may
    /// be seen.
    #[must_use]
    pub fn with_openings(mut self, openings: Vec<Opening>) -> Self {
        self.openings = openings;
        self
    }

    /// The openings of the surface (see [`Scene::with_openings`]); empty for a closed one.
    pub fn openings(&self) -> &[Opening] {
        &self.openings
    }

    /// The scene with an [`InsideBox`]: the backs of its
    /// [`Sides::Both`](crate::Sides::Both) patches show only to an eye inside it (or through
    /// an opening). `None`: they show from anywhere.
    #[must_use]
    pub fn with_inside_box(mut self, inside_box: Option<InsideBox>) -> Self {
        self.inside_box = inside_box;
        self
    }

    /// The inside box (see [`Scene::with_inside_box`]), if the scene has one.
    pub fn inside_box(&self) -> Option<InsideBox> {
        self.inside_box
    }

    /// Whether a patch of this scene is two-sided ([`Sides::Both`](crate::Sides::Both)).
    pub fn has_two_sided_patches(&self) -> bool {
        self.patches.iter().any(|p| p.sides() == crate::Sides::Both)
    }

    /// The model-space position of the patches' local origin.
    pub fn offset(&self) -> DVec3 {
        self.offset
    }

    /// The colour channel.
    pub fn channel(&self) -> ColourChannel {
        self.channel
    }

    /// The patches.
    pub fn patches(&self) -> &[Patch] {
        &self.patches
    }

    /// Consumes the scene, returning its patches.
    pub fn into_patches(self) -> Vec<Patch> {
        self.patches
    }

    /// All grid nodes, filled or not.
    pub fn node_count(&self) -> usize {
        self.patches.iter().map(|p| p.grid().node_count()).sum()
    }

    /// Non-empty nodes.
    pub fn filled_node_count(&self) -> usize {
        self.patches.iter().map(Patch::filled_count).sum()
    }

    /// The one colour every filled node shares, if the scene has colour and
    /// at least one filled node and all of them are equal.
    pub fn flat_colour(&self) -> Option<[u8; 4]> {
        let mut found: Option<[u8; 4]> = None;
        for patch in &self.patches {
            let colours = patch.colours()?;
            for (c, &d) in colours.iter().zip(patch.displacements()) {
                if d == crate::EMPTY {
                    continue;
                }
                match found {
                    None => found = Some(*c),
                    Some(f) if f != *c => return None,
                    Some(_) => {}
                }
            }
        }
        found
    }

    /// Model-space bounds `(min, max)` of the filled nodes (offset and
    /// each patch's [`crate::Frame::precise_origin`] applied in f64), or
    /// `None` for a scene with no filled node.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        self.patches
            .iter()
            .filter_map(|p| {
                let origin = self.offset + p.frame().precise_origin();
                let (lo, hi) = p.bounds()?;
                let shift = p.frame().origin();
                Some((
                    origin + (lo - shift).as_dvec3(),
                    origin + (hi - shift).as_dvec3(),
                ))
            })
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    }

    /// Concatenates scenes into one (see `spatch merge`).
    ///
    /// The result's offset is the first scene's. Every other scene's patch
    /// origins are moved by the difference of offsets in f64 and stored as
    /// an f32 origin plus its residual ([`crate::Frame::with_precise_origin`]),
    /// so each part keeps the precision it had alone: node positions from
    /// [`Patch::precise_node_position`] differ from the scene alone's by
    /// f32 rounding of the patch-local frame only, however far apart the
    /// scenes are (tested at 1e7). All scenes must have the same colour
    /// channel.
    pub fn merge(scenes: Vec<Scene>) -> Result<Scene, MergeError> {
        let Some(first) = scenes.first() else {
            return Err(MergeError::Empty);
        };
        let (offset, channel) = (first.offset, first.channel);
        let mut patches = Vec::new();
        let mut openings = Vec::new();
        let mut inside = InsideBoxes::default();
        for (index, scene) in scenes.into_iter().enumerate() {
            if scene.channel != channel {
                return Err(MergeError::ChannelMismatch {
                    index,
                    expected: channel,
                    found: scene.channel,
                });
            }
            let shift = scene.offset - offset;
            inside.add(&scene, shift)?;
            for o in &scene.openings {
                openings.push(rebase_opening(o, shift).map_err(MergeError::Format)?);
            }
            for patch in scene.patches {
                patches.push(rebase_patch(patch, shift).map_err(MergeError::Format)?);
            }
        }
        Ok(Scene::new(offset, channel, patches)
            .map_err(MergeError::Format)?
            .with_openings(openings)
            .with_inside_box(inside.merged()))
    }

    /// The same scene moved by `shift` (model units, f64): only the offset
    /// changes, so nothing is rounded (`spatch merge --translate`).
    pub fn translated(mut self, shift: DVec3) -> Result<Scene, FormatError> {
        let offset = self.offset + shift;
        if !offset.is_finite() {
            return Err(FormatError::InvalidOffset);
        }
        self.offset = offset;
        Ok(self)
    }
}

/// A patch of a scene whose offset is `shift` from the merged scene's, moved into the
/// merged scene: its origin in f64, stored as an f32 origin and its residual.
pub(crate) fn rebase_patch(mut patch: Patch, shift: DVec3) -> Result<Patch, FormatError> {
    if shift == DVec3::ZERO {
        return Ok(patch);
    }
    let origin = patch.frame().precise_origin() + shift;
    let frame = patch.frame().with_precise_origin(origin)?;
    patch.set_frame(frame);
    Ok(patch)
}

/// An opening of a scene whose offset is `shift` from the merged scene's, moved into it.
pub(crate) fn rebase_opening(opening: &Opening, shift: DVec3) -> Result<Opening, FormatError> {
    let centre = (opening.centre().as_dvec3() + shift).as_vec3();
    Opening::new(
        centre,
        opening.radius(),
        opening.normal(),
        opening.half_thickness(),
    )
}

/// The inside box of merged scenes: the union of their boxes when every scene with a
/// two-sided patch has one (a two-sided patch of a scene without one shows its back from
/// anywhere, which no box can say), else none.
#[derive(Debug, Default)]
pub(crate) struct InsideBoxes {
    union: Option<InsideBox>,
    unbounded: bool,
}

impl InsideBoxes {
    /// Takes in `scene`, placed `shift` from the merged scene's offset.
    pub(crate) fn add(&mut self, scene: &Scene, shift: DVec3) -> Result<(), MergeError> {
        match scene.inside_box {
            Some(b) => {
                let b = rebase_inside_box(&b, shift).map_err(MergeError::Format)?;
                self.union = Some(self.union.map_or(b, |u| u.union(&b)));
            }
            None => self.unbounded |= scene.has_two_sided_patches(),
        }
        Ok(())
    }

    /// The merged scene's inside box.
    pub(crate) fn merged(&self) -> Option<InsideBox> {
        self.union.filter(|_| !self.unbounded)
    }
}

/// `b` moved by `shift`, each corner rounded outward so the box still holds what it held.
pub(crate) fn rebase_inside_box(b: &InsideBox, shift: DVec3) -> Result<InsideBox, FormatError> {
    let outward = |v: DVec3, down: bool| {
        v.to_array().map(|x| {
            let r = x as f32;
            match (down, f64::from(r).partial_cmp(&x)) {
                (true, Some(std::cmp::Ordering::Greater)) => r.next_down(),
                (false, Some(std::cmp::Ordering::Less)) => r.next_up(),
                _ => r,
            }
        })
    };
    let min = outward(b.min().as_dvec3() + shift, true);
    let max = outward(b.max().as_dvec3() + shift, false);
    InsideBox::new(min.into(), max.into())
}

/// Why scenes could not be merged.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MergeError {
    /// No scene was given.
    #[error("nothing to merge")]
    Empty,
    /// Scenes disagree on colour.
    #[error("scene {index} has colour channel {}, the first has {}: convert them with the same colour options", found.name(), expected.name())]
    ChannelMismatch {
        /// Index of the offending scene in the input list.
        index: usize,
        /// The first scene's channel.
        expected: ColourChannel,
        /// This scene's channel.
        found: ColourChannel,
    },
    /// A moved frame became invalid (an offset so large the origin overflows f32).
    #[error("{0}")]
    Format(FormatError),
}
