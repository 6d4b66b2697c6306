//! The viewer's input, independent of any window system.

use crate::orbit::Axis;

/// One input to the frame loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Event {
    /// Orbit by a drag of `dx, dy` pixels (right and down positive).
    Orbit {
        /// Horizontal drag, pixels.
        dx: f64,
        /// Vertical drag, pixels.
        dy: f64,
    },
    /// Pan by a drag of `dx, dy` pixels (right and down positive).
    Pan {
        /// Horizontal drag, pixels.
        dx: f64,
        /// Vertical drag, pixels.
        dy: f64,
    },
    /// Zoom by wheel notches (positive: towards the target).
    Zoom(f64),
    /// Back to the automatic camera.
    Reset,
    /// One of the six axis views.
    View(Axis),
    /// Next shading model: Phong, flat, Gouraud, Phong...
    CycleShading,
    /// Patches or triangles.
    ToggleMode,
    /// Mip pyramid on or off.
    ToggleMip,
    /// Supersampling of still frames on or off.
    ToggleSsaa,
    /// The window's new size in pixels.
    Resize {
        /// Width, pixels.
        width: u32,
        /// Height, pixels.
        height: u32,
    },
}

impl Event {
    /// Whether the event moves the camera (the frame loop then draws the
    /// fast frame first).
    pub fn moves_camera(&self) -> bool {
        matches!(
            self,
            Event::Orbit { .. }
                | Event::Pan { .. }
                | Event::Zoom(_)
                | Event::Reset
                | Event::View(_)
        )
    }
}
