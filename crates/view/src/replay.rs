//! A script replayed without a window: the frames the window would show,
//! and the last (refined) one as its framebuffer.

use crate::error::ViewError;
use crate::event::Event;
use crate::overlay::Framebuffer;
use crate::settings::Quality;
use crate::viewer::{Frame, Viewer};

/// The end of a replay: the flags of the last frame and its framebuffer.
#[derive(Debug, Clone)]
pub struct Replayed {
    /// The `spatch render` flags of the last frame shown.
    pub render_flags: String,
    /// The last framebuffer shown (overlay included unless left out).
    pub screenshot: Framebuffer,
}

/// Applies `events` in order, then renders the still frame as a window
/// shows it once input stops; `overlay` draws its line.
pub fn replay_offscreen(
    viewer: &mut Viewer,
    events: &[Event],
    overlay: bool,
) -> Result<Replayed, ViewError> {
    events.iter().for_each(|e| viewer.apply(*e));
    let frame = viewer.frame(Quality::Still)?;
    Ok(Replayed {
        screenshot: framebuffer(&frame, overlay),
        render_flags: frame.render_flags,
    })
}

/// The framebuffer of a frame at the view's size, with its overlay line
/// when `overlay` (the font doubles from 1600 px wide).
pub(crate) fn framebuffer(frame: &Frame, overlay: bool) -> Framebuffer {
    let (width, height) = frame.view;
    let mut fb = Framebuffer::of_image(&frame.image).enlarged(frame.scale, width, height);
    if overlay {
        fb.draw_overlay(&frame.overlay, 1 + fb.width / 1600);
    }
    fb
}
