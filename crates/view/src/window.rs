//! The window: minifb (X11, loaded at run time) around the frame loop,
//! mouse and keys turned into [`Event`]s, progressive quality, and the
//! scripted mode that takes a screenshot.

use std::time::{Duration, Instant};

use minifb::{Key, KeyRepeat, MouseButton, MouseMode, Window, WindowOptions};

use crate::error::ViewError;
use crate::event::Event;
use crate::orbit::{Axis, ORBIT_RADIANS_PER_PIXEL};
use crate::overlay::Framebuffer;
use crate::replay::{framebuffer, Replayed};
use crate::settings::Quality;
use crate::viewer::{Frame, Viewer};

/// How long the camera stays still before the refined frame is drawn.
pub const STILL_AFTER: Duration = Duration::from_millis(150);
/// Pixels of orbit per arrow key press (15°).
const ARROW_PIXELS: f64 = std::f64::consts::PI / 12.0 / ORBIT_RADIANS_PER_PIXEL;

/// How the window runs.
#[derive(Debug, Clone, Default)]
pub struct WindowConfig {
    /// Window title.
    pub title: String,
    /// Leave out the overlay line.
    pub no_overlay: bool,
    /// Replay these events instead of reading input, then stop.
    pub script: Option<Vec<Event>>,
}

/// Fails with [`ViewError::NoDisplay`] unless an X display is named.
pub fn check_display() -> Result<(), ViewError> {
    match std::env::var_os("DISPLAY") {
        Some(d) if !d.is_empty() => Ok(()),
        _ => Err(ViewError::NoDisplay(
            "DISPLAY is not set; the viewer draws through X11 (an X server, XWayland or Xvfb); \
             --bench-orbit needs no display"
                .into(),
        )),
    }
}

/// The window and what was last shown in it.
struct Screen {
    window: Window,
    no_overlay: bool,
    shown: Option<(Framebuffer, String)>,
}

impl Screen {
    /// Shows `frame` (with its overlay unless left out).
    fn show(
        &mut self,
        viewer: &mut Viewer,
        frame: Frame,
        quality: Quality,
    ) -> Result<(), ViewError> {
        let fb = framebuffer(&frame, !self.no_overlay);
        self.window
            .update_with_buffer(&fb.words, fb.width, fb.height)
            .map_err(|e| ViewError::Window(e.to_string()))?;
        let flags = frame.render_flags.clone();
        viewer.recycle(frame, quality);
        self.shown = Some((fb, flags));
        Ok(())
    }

    /// Renders and shows the view at `quality`.
    fn draw(&mut self, viewer: &mut Viewer, quality: Quality) -> Result<(), ViewError> {
        let frame = viewer.frame(quality)?;
        self.show(viewer, frame, quality)
    }

    /// A resize event when the window's size differs from the view's.
    fn resize_event(&self, viewer: &Viewer) -> Option<Event> {
        let (w, h) = self.window.get_size();
        let (w, h) = (w.clamp(1, 8192) as u32, h.clamp(1, 8192) as u32);
        (viewer.size() != (w, h)).then_some(Event::Resize {
            width: w,
            height: h,
        })
    }

    fn outcome(self) -> Result<Replayed, ViewError> {
        let (screenshot, render_flags) = self
            .shown
            .ok_or_else(|| ViewError::Window("no frame was shown".into()))?;
        Ok(Replayed {
            render_flags,
            screenshot,
        })
    }
}

/// Opens a window on `viewer` and runs until q, Esc or closing (or, with a
/// script, until its events are replayed and the refined frame is shown,
/// the frames [`crate::replay_offscreen`] renders).
/// `on_print` receives the flags line when p is pressed.
pub fn run_window(
    viewer: &mut Viewer,
    config: &WindowConfig,
    on_print: &mut dyn FnMut(&str),
) -> Result<Replayed, ViewError> {
    check_display()?;
    let (w, h) = viewer.size();
    let options = WindowOptions {
        resize: config.script.is_none(),
        ..WindowOptions::default()
    };
    let mut window = Window::new(&config.title, w as usize, h as usize, options)
        .map_err(|e| ViewError::Window(e.to_string()))?;
    window.set_target_fps(0);
    let mut screen = Screen {
        window,
        no_overlay: config.no_overlay,
        shown: None,
    };
    match &config.script {
        Some(events) => replay(viewer, &mut screen, events)?,
        None => interact(viewer, &mut screen, on_print)?,
    }
    screen.outcome()
}

/// Shows a fast frame after each event, then the refined one.
fn replay(viewer: &mut Viewer, screen: &mut Screen, events: &[Event]) -> Result<(), ViewError> {
    screen.draw(viewer, Quality::Moving)?;
    for event in events {
        viewer.apply(*event);
        screen.draw(viewer, Quality::Moving)?;
    }
    screen.draw(viewer, Quality::Still)
}

/// The interactive loop: fast frames while input comes, the refined one
/// after [`STILL_AFTER`] without.
fn interact(
    viewer: &mut Viewer,
    screen: &mut Screen,
    on_print: &mut dyn FnMut(&str),
) -> Result<(), ViewError> {
    let mut mouse = MouseState::default();
    let mut last_input = Instant::now();
    let mut refined = false;
    screen.draw(viewer, Quality::Moving)?;
    while screen.window.is_open() {
        let keys = screen.window.get_keys_pressed(KeyRepeat::Yes);
        if keys.iter().any(|k| matches!(k, Key::Q | Key::Escape)) {
            break;
        }
        if keys.contains(&Key::P) {
            if let Some((_, flags)) = &screen.shown {
                on_print(flags);
            }
        }
        let mut events: Vec<Event> = keys.iter().filter_map(|k| key_event(*k)).collect();
        events.extend(mouse.events(&screen.window));
        events.extend(screen.resize_event(viewer));
        if !events.is_empty() {
            events.into_iter().for_each(|e| viewer.apply(e));
            screen.draw(viewer, Quality::Moving)?;
            last_input = Instant::now();
            refined = false;
        } else if !refined && last_input.elapsed() >= STILL_AFTER {
            screen.draw(viewer, Quality::Still)?;
            refined = true;
        } else {
            // Nothing to draw: let the window take its events, and rest.
            screen.window.update();
            std::thread::sleep(Duration::from_millis(5));
        }
    }
    Ok(())
}

/// The event of a key press, if it has one.
fn key_event(key: Key) -> Option<Event> {
    let number = |k: u8| Axis::of_key(k).map(Event::View);
    match key {
        Key::R => Some(Event::Reset),
        Key::S => Some(Event::CycleShading),
        Key::T => Some(Event::ToggleMode),
        Key::M => Some(Event::ToggleMip),
        Key::A => Some(Event::ToggleSsaa),
        Key::Key1 | Key::NumPad1 => number(1),
        Key::Key2 | Key::NumPad2 => number(2),
        Key::Key3 | Key::NumPad3 => number(3),
        Key::Key4 | Key::NumPad4 => number(4),
        Key::Key5 | Key::NumPad5 => number(5),
        Key::Key6 | Key::NumPad6 => number(6),
        Key::Left => Some(Event::Orbit {
            dx: -ARROW_PIXELS,
            dy: 0.0,
        }),
        Key::Right => Some(Event::Orbit {
            dx: ARROW_PIXELS,
            dy: 0.0,
        }),
        Key::Up => Some(Event::Orbit {
            dx: 0.0,
            dy: -ARROW_PIXELS,
        }),
        Key::Down => Some(Event::Orbit {
            dx: 0.0,
            dy: ARROW_PIXELS,
        }),
        Key::Equal | Key::NumPadPlus => Some(Event::Zoom(1.0)),
        Key::Minus | Key::NumPadMinus => Some(Event::Zoom(-1.0)),
        _ => None,
    }
}

/// The mouse position of the previous poll, for drags.
#[derive(Debug, Default)]
struct MouseState {
    last: Option<(f32, f32)>,
}

impl MouseState {
    /// Drag and wheel events since the previous poll.
    fn events(&mut self, window: &Window) -> Vec<Event> {
        let mut events = Vec::new();
        let now = window.get_mouse_pos(MouseMode::Pass);
        if let (Some((x0, y0)), Some((x1, y1))) = (self.last, now) {
            let (dx, dy) = (f64::from(x1 - x0), f64::from(y1 - y0));
            if dx != 0.0 || dy != 0.0 {
                if window.get_mouse_down(MouseButton::Left) {
                    events.push(Event::Orbit { dx, dy });
                } else if window.get_mouse_down(MouseButton::Right)
                    || window.get_mouse_down(MouseButton::Middle)
                {
                    events.push(Event::Pan { dx, dy });
                }
            }
        }
        self.last = now;
        if let Some((_, wheel)) = window.get_scroll_wheel() {
            if wheel != 0.0 {
                events.push(Event::Zoom(f64::from(wheel.signum())));
            }
        }
        events
    }
}
