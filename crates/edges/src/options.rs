//! The generator's options, with documented defaults and what each trades.

use spatch_fit::FitOptions;

use crate::EdgeError;

/// Default [`EdgeOptions::crease_angle_deg`]: 25°.
///
/// Below the 30° rim of the crease-angle sweep test, and well above the facet-to-facet angle
/// of tessellated curved CAD faces (a 64-sided cylinder turns 5.6° per facet).
pub const DEFAULT_CREASE_ANGLE_DEG: f32 = 25.0;
/// Default [`EdgeOptions::resolution`]: edge patches have the surface patches' node spacing.
/// What closes a crease is the edge patch's view from the bisector and its row along the
/// crease, not density: on the shared CAD parts and the sweep frustums 1.5 closed no more
/// holes than 1.0 and cost about 1.6 times the bytes (docs/algorithms/edges.md).
pub const DEFAULT_RESOLUTION: f32 = 1.0;
/// Default [`EdgeOptions::strip_width`]: 0.8 surface node spacings on each face. The gap a
/// surface patch leaves at a crease is under one cell, and the edge patch's outer rows
/// run on to the first row past the strip; 1.2 closed no more holes and cost 1.2 times the
/// bytes.
pub const DEFAULT_STRIP_WIDTH: f32 = 0.8;
/// Default [`EdgeOptions::max_cols`]: 33 nodes (32 cells) along the edge per patch.
pub const DEFAULT_MAX_COLS: u32 = 33;
/// Default [`EdgeOptions::max_turn_deg`]: 10°. The faces' bisector may turn this far within a
/// piece (and a run may turn this far through a corner); how far the crease strays from the
/// piece's row is limited separately by [`EdgeOptions::max_stray`]. On fandisk 8° made 157
/// edge + corner patches, 10° 147, 12° 142; but beyond 10° the sweep's rims, whose steep
/// faces are seen at up to 75° from the bisector, open (30° rim: 0.009 % holes at 10°,
/// 0.058 % at 11° and 12°; docs/algorithms/edges.md).
pub const DEFAULT_MAX_TURN_DEG: f32 = 10.0;
/// Default [`EdgeOptions::max_stray`]: 0.75 edge spacings. On fandisk (at 12° of turn) 0.5
/// made 142 edge + corner patches at 0.0004 % holes, 0.75 136 at 0.0006 %; the sweep is
/// limited by the turn, not by this.
pub const DEFAULT_MAX_STRAY: f32 = 0.75;

/// Default [`EdgeOptions::soft_crease_deg`]: 50°. Below it a crease the surface patches reach
/// over counts as covered within the corner cut of their cells (`coverage`): on Duck.glb this
/// left 145 edge + corner patches where 201 were made with no soft creases, fuze.obj 76
/// where 102, at the same holes on Duck's 14 views to within 0.0001 % of the pixels; fandisk's
/// uncovered creases are sharper (80–90°) and unchanged.
pub const DEFAULT_SOFT_CREASE_DEG: f32 = 50.0;

/// How sharp edges are found and covered.
///
/// Build with `EdgeOptions::default()` and change the fields you need.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct EdgeOptions {
    /// An edge shared by two faces is sharp when the angle between their normals is at least
    /// this, in degrees (0° = flat, 90° = a cube's edge). Range `(0, 180)`, default
    /// [`DEFAULT_CREASE_ANGLE_DEG`]. Lower: more edges covered (more bytes, fewer holes at
    /// shallow creases, where holes are narrow anyway); higher: only the sharpest edges.
    pub crease_angle_deg: f32,
    /// Edge patch node density relative to the surface patches: edge spacing = surface
    /// spacing / `resolution`. Range `[1, 16]`, default [`DEFAULT_RESOLUTION`]. Higher:
    /// edge cells cut the crease's corner less and cover narrower gaps, at
    /// `resolution²` times the nodes per unit of strip area.
    pub resolution: f32,
    /// Width of the strip covered on each face, measured on the face perpendicular to the
    /// edge, in surface node spacings. Range `[0.5, 16]`, default [`DEFAULT_STRIP_WIDTH`].
    /// The gap left by surface patches at a crease is under one surface cell wide, and the
    /// patch's rows run on to the first row past the strip, so values near 1 overlap the
    /// surface patches; wider costs bytes linearly.
    pub strip_width: f32,
    /// Largest number of nodes along the edge in one edge patch, `3..=257`. Default
    /// [`DEFAULT_MAX_COLS`]. Longer patches: fewer frames (40 bytes each) but wider rows
    /// where the edge curves.
    pub max_cols: u32,
    /// Largest turn of the faces' bisector within one edge patch, in degrees. Range
    /// `(0, 90]`, default [`DEFAULT_MAX_TURN_DEG`]. Smaller: more, shorter patches, each
    /// seeing its faces more squarely; larger: fewer patches (a face is never taken into a
    /// piece whose first bisector it is more than about 78° from).
    pub max_turn_deg: f32,
    /// Largest distance of the crease from a piece's chord, in edge spacings. Range
    /// `[0, 4]`, default [`DEFAULT_MAX_STRAY`]. The patch has a row of nodes along the
    /// chord's mean offset, which lands on a straight crease; a crease that strays from it
    /// is crossed by cells that cut its fold's tip (a rim's silhouette shrinks by up to the
    /// stray). Pieces with a face more than about 50° from their view keep a fifth of it
    /// (their tips show more on screen). Smaller: more, shorter pieces on curved creases;
    /// larger: fewer, longer ones.
    pub max_stray: f32,
    /// Creases under this angle (degrees) are soft: with [`EdgeOptions::only_gaps`], a
    /// surface patch that reaches over one with drawable cells covers it within the corner
    /// cut of its cells (`tan φ / 4` of a cell at most, under 0.35 cells up to 54°) instead
    /// of the usual 0.2 cells. Range `[0, 180)`, default [`DEFAULT_SOFT_CREASE_DEG`]; 0 (or
    /// anything at most `crease_angle_deg`) turns it off. Higher: fewer edge patches on
    /// coarse tessellations, whose shallow facet creases are not features, at a rim that may
    /// lose up to a third of a cell at its tip.
    pub soft_crease_deg: f32,
    /// Whether to add a corner patch where three or more sharp edges meet, seen along the
    /// mean normal of the faces around the corner. Default `true`. A corner patch costs about
    /// one edge patch per corner.
    pub corners: bool,
    /// Largest displacement reconstruction error (half a step) as a fraction of the edge
    /// spacing before a patch gets 16-bit codes (as
    /// [`FitOptions::max_step_error`](spatch_fit::FitOptions::max_step_error)). Default
    /// [`FitOptions::DEFAULT_STEP_ERROR`].
    pub max_step_error: f32,
    /// Whether to sample colour when the source has any. Default `true`.
    pub colour: bool,
    /// Whether to leave out creases the surface patches already cover (probed as the
    /// `coverage` module describes). Default `true`. Off: every crease gets a patch, which
    /// costs bytes and closes no more holes; useful only to compare.
    pub only_gaps: bool,
    /// With [`EdgeOptions::only_gaps`], whether to drop the edge patches of pieces that the
    /// surface patches and the other edge patches already cover (probed as the creases are;
    /// shortest pieces first, every dropped piece still covered by what is kept). Default
    /// `true`. Off: one patch per piece, as before (more patches, the same probed coverage).
    pub drop_covered_pieces: bool,
    /// With [`EdgeOptions::only_gaps`], whether to join pieces that meet at a crease vertex
    /// into one patch wherever that patch, with the others, covers every probe of the pieces
    /// (`joined_pieces`: seen along their mean bisector, at most twice the nodes of the two
    /// patches it replaces). Default `true`: fewer patches (a frame and per-patch work each)
    /// for a few more nodes. Off: one patch per piece.
    pub join_pieces: bool,
}

impl Default for EdgeOptions {
    fn default() -> Self {
        Self {
            crease_angle_deg: DEFAULT_CREASE_ANGLE_DEG,
            resolution: DEFAULT_RESOLUTION,
            strip_width: DEFAULT_STRIP_WIDTH,
            max_cols: DEFAULT_MAX_COLS,
            max_turn_deg: DEFAULT_MAX_TURN_DEG,
            max_stray: DEFAULT_MAX_STRAY,
            soft_crease_deg: DEFAULT_SOFT_CREASE_DEG,
            corners: true,
            max_step_error: FitOptions::DEFAULT_STEP_ERROR,
            colour: true,
            only_gaps: true,
            drop_covered_pieces: true,
            join_pieces: true,
        }
    }
}

impl EdgeOptions {
    /// Checks the ranges documented on each field.
    pub fn validate(&self) -> Result<(), EdgeError> {
        let bad = |name, reason| Err(EdgeError::InvalidOption { name, reason });
        let a = self.crease_angle_deg;
        if !(a.is_finite() && a > 0.0 && a < 180.0) {
            return bad("crease_angle_deg", "must be in (0, 180) degrees");
        }
        if !(self.resolution.is_finite() && (1.0..=16.0).contains(&self.resolution)) {
            return bad("resolution", "must be in [1, 16]");
        }
        if !(self.strip_width.is_finite() && (0.5..=16.0).contains(&self.strip_width)) {
            return bad("strip_width", "must be in [0.5, 16] surface spacings");
        }
        if !(3..=257).contains(&self.max_cols) {
            return bad("max_cols", "must be in 3..=257");
        }
        let t = self.max_turn_deg;
        if !(t.is_finite() && t > 0.0 && t <= 90.0) {
            return bad("max_turn_deg", "must be in (0, 90] degrees");
        }
        if !(self.max_stray.is_finite() && (0.0..=4.0).contains(&self.max_stray)) {
            return bad("max_stray", "must be in [0, 4] edge spacings");
        }
        let soft = self.soft_crease_deg;
        if !(soft.is_finite() && (0.0..180.0).contains(&soft)) {
            return bad("soft_crease_deg", "must be in [0, 180) degrees");
        }
        let e = self.max_step_error;
        if !(e.is_finite() && e > 0.0) {
            return bad("max_step_error", "must be positive and finite");
        }
        Ok(())
    }
}
