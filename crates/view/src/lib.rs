//! `spatch view`: an interactive viewer of spatial patches on the CPU.
//!
//! The frame loop is a library, independent of any window: a [`Viewer`]
//! holds the camera ([`Orbit`]) and the toggles ([`Settings`]), takes
//! input as [`Event`]s through [`Viewer::apply`] (or a text script,
//! [`parse_script`]) and renders with spatch-render in [`Viewer::frame`],
//! which returns the image, the overlay line (frame time, patches drawn,
//! the camera as `--eye/--target/--up/--fov`) and the `spatch render`
//! flags that draw the same image pixel for pixel ([`camera_line`] rounds
//! the camera and renders with the rounded one). [`bench_orbit`] times an
//! orbit without a window.
//!
//! The window ([`run_window`]) is minifb on X11, loaded at run time: it
//! maps mouse and keys to events, draws fast frames while the camera
//! moves and a supersampled one after [`STILL_AFTER`] without input, and
//! draws the overlay with its own 5 × 7 bitmap font ([`font`]). See
//! docs/viewer.md.
//!
//! Modules, in use order: `error`, `orbit`, `event`, `script`, `settings`,
//! `camera_line`, `viewer`, `bench`, `font`, `overlay`, `replay`, `window`.
#![forbid(unsafe_code)]

mod bench;
pub mod camera_line;
mod error;
mod event;
pub mod font;
mod orbit;
mod overlay;
mod replay;
mod script;
mod settings;
mod viewer;
mod window;

pub use bench::{bench_orbit, OrbitBench};
pub use camera_line::CameraLine;
pub use error::ViewError;
pub use event::Event;
pub use orbit::{Axis, Orbit, ORBIT_RADIANS_PER_PIXEL, ZOOM_PER_STEP};
pub use overlay::Framebuffer;
pub use replay::{replay_offscreen, Replayed};
pub use script::parse_script;
pub use settings::{Quality, Settings, ViewShading, MAX_MOVING_SCALE, STILL_SSAA};
pub use viewer::{Frame, Viewer, BACKGROUND};
pub use window::{check_display, run_window, WindowConfig, STILL_AFTER};
