//! The viewer's errors.

use spatch_render::RenderError;

/// What can go wrong in the viewer.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// No display to open a window on.
    #[error("no display ({0})")]
    NoDisplay(String),
    /// The window system refused the window.
    #[error("cannot open a window: {0}")]
    Window(String),
    /// The scene has nothing to look at.
    #[error("the scene has no drawable patch")]
    EmptyScene,
    /// The renderer refused the camera or options, or failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A line of an event script is not an event.
    #[error("line {line}: {problem}")]
    Script {
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        problem: String,
    },
    /// The screenshot could not be encoded.
    #[error("cannot encode the screenshot: {0}")]
    Encode(String),
}
