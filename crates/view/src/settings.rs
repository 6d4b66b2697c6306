//! The toggles of the viewer and the render options and flags they make.

use spatch_render::{RenderMode, RenderOptions, Shading};

/// Supersampling factor of still frames when supersampling is on.
pub const STILL_SSAA: u32 = 2;

/// How good a frame is: the fast one while the camera moves, or the
/// refined one once it is still.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quality {
    /// No supersampling: the fastest settings.
    Moving,
    /// Supersampled by [`STILL_SSAA`] when the toggle is on.
    Still,
}

/// The shading models the viewer cycles through (key s).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViewShading {
    /// Deferred per-pixel shading (the default of `spatch render`).
    Phong,
    /// One colour per cell.
    Flat,
    /// Colours at nodes, interpolated.
    Gouraud,
}

impl ViewShading {
    /// The renderer's model.
    pub fn shading(self) -> Shading {
        match self {
            ViewShading::Phong => Shading::Phong,
            ViewShading::Flat => Shading::Flat,
            ViewShading::Gouraud => Shading::Gouraud,
        }
    }

    /// The name `spatch render --shading` takes.
    pub fn name(self) -> &'static str {
        match self {
            ViewShading::Phong => "phong",
            ViewShading::Flat => "flat",
            ViewShading::Gouraud => "gouraud",
        }
    }
}

/// The user's toggles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Settings {
    /// Shading model (key s cycles).
    pub shading: ViewShading,
    /// Each cell as two triangles instead of patches (key t).
    pub triangles: bool,
    /// Mip pyramid (key m).
    pub mip: bool,
    /// Supersampling of still frames (key a).
    pub ssaa: bool,
    /// Moving frames are rendered this many times smaller per side,
    /// 1..=[`MAX_MOVING_SCALE`], and enlarged to the window (1: full size).
    pub moving_scale: u32,
}

/// The largest [`Settings::moving_scale`].
pub const MAX_MOVING_SCALE: u32 = 4;

impl Default for Settings {
    fn default() -> Self {
        Settings {
            shading: ViewShading::Phong,
            triangles: false,
            mip: true,
            ssaa: true,
            moving_scale: 1,
        }
    }
}

impl Settings {
    /// The next shading model: Phong → flat → Gouraud → Phong.
    pub fn cycle_shading(&mut self) {
        self.shading = match self.shading {
            ViewShading::Phong => ViewShading::Flat,
            ViewShading::Flat => ViewShading::Gouraud,
            ViewShading::Gouraud => ViewShading::Phong,
        };
    }

    /// The supersampling factor of a frame of `quality`.
    pub fn ssaa_factor(&self, quality: Quality) -> u32 {
        match quality {
            Quality::Still if self.ssaa => STILL_SSAA,
            _ => 1,
        }
    }

    /// How many times smaller per side a frame of `quality` is rendered.
    pub fn scale(&self, quality: Quality) -> u32 {
        match quality {
            Quality::Moving => self.moving_scale.clamp(1, MAX_MOVING_SCALE),
            Quality::Still => 1,
        }
    }

    /// The rendered size of a `width × height` view at `quality`.
    pub fn render_size(&self, quality: Quality, width: u32, height: u32) -> (u32, u32) {
        let k = self.scale(quality);
        (width.div_ceil(k), height.div_ceil(k))
    }

    /// `base` with these toggles at `quality`.
    pub fn options(&self, base: &RenderOptions, quality: Quality) -> RenderOptions {
        let mut o = *base;
        o.shading = self.shading.shading();
        o.mode = if self.triangles {
            RenderMode::Triangles
        } else {
            RenderMode::Patches
        };
        o.mip = self.mip;
        o.ssaa = self.ssaa_factor(quality);
        o
    }

    /// The `spatch render` flags of the toggles that differ from its
    /// defaults, each with a leading space.
    pub fn render_flags(&self, quality: Quality) -> String {
        let mut flags = String::new();
        if self.shading != ViewShading::Phong {
            flags += &format!(" --shading {}", self.shading.name());
        }
        if self.triangles {
            flags += " --mode triangles";
        }
        if !self.mip {
            flags += " --no-mip";
        }
        let k = self.ssaa_factor(quality);
        if k != 1 {
            flags += &format!(" --ssaa {k}");
        }
        flags
    }

    /// A few words for the overlay.
    pub fn describe(&self, quality: Quality) -> String {
        let shading = self.shading.name();
        let mode = if self.triangles {
            "triangles"
        } else {
            "patches"
        };
        let mip = if self.mip { "mip" } else { "no mip" };
        let scale = match self.scale(quality) {
            1 => String::new(),
            k => format!(" 1/{k} size"),
        };
        format!(
            "{mode} {shading} {mip} ssaa {}{scale}",
            self.ssaa_factor(quality)
        )
    }
}
