//! The frame loop without a window: the state, [`Viewer::apply`] for an
//! input event and [`Viewer::frame`] for an image and its overlay line.

use spatch_format::Scene;
use spatch_render::{Camera, PreparedScene, RenderOptions, RenderStats, RenderedImage, Renderer};

use crate::camera_line::{position_decimals, CameraLine};
use crate::error::ViewError;
use crate::event::Event;
use crate::orbit::Orbit;
use crate::settings::{Quality, Settings, MAX_MOVING_SCALE};

/// Background of the viewer (opaque, so the window shows what a PNG of the
/// printed flags shows).
pub const BACKGROUND: [u8; 4] = [40, 44, 52, 255];

/// One rendered frame.
#[derive(Debug)]
pub struct Frame {
    /// The image, as `spatch render` with [`Frame::render_flags`] draws it
    /// (`scale` times smaller than the view per side).
    pub image: RenderedImage,
    /// The on-screen line: frame time, patches drawn, settings, camera.
    pub overlay: String,
    /// The `spatch render` flags that make the same image.
    pub render_flags: String,
    /// The camera used (the rounded one the flags give).
    pub camera: Camera,
    /// The renderer's statistics.
    pub stats: RenderStats,
    /// The image is this many times smaller per side than the view.
    pub scale: u32,
    /// The view's size in pixels (the window's).
    pub view: (u32, u32),
}

impl Frame {
    /// Patches drawn: those neither outside the view nor facing away.
    pub fn patches_drawn(&self) -> u64 {
        let s = &self.stats;
        s.patches - s.patches_culled_frustum - s.patches_culled_backface
    }
}

/// The viewer's state and renderers.
#[derive(Debug)]
pub struct Viewer {
    scene: PreparedScene,
    auto: Orbit,
    orbit: Orbit,
    settings: Settings,
    base: RenderOptions,
    width: u32,
    height: u32,
    decimals: usize,
    /// The renderer of each quality, with the options it was made for.
    renderers: [Option<Renderer>; 2],
}

impl Viewer {
    /// A viewer of `scene` in a `width × height` view rendering on
    /// `threads` threads (0: all cores), at the automatic camera.
    pub fn new(scene: &Scene, width: u32, height: u32, threads: usize) -> Result<Self, ViewError> {
        let mut base = RenderOptions::default();
        base.threads = threads;
        base.background = BACKGROUND;
        // The viewer shows whole frames' times only: no clock reads per patch.
        base.stage_times = false;
        let renderer = Renderer::new(base)?;
        let scene = renderer.prepare(scene);
        let (_, radius) = scene.bounding_sphere().ok_or(ViewError::EmptyScene)?;
        let auto_camera = scene
            .auto_camera(width, height)
            .map_err(spatch_render::RenderError::InvalidCamera)?;
        let auto = Orbit::of_camera(&auto_camera);
        Ok(Viewer {
            scene,
            auto,
            orbit: auto,
            settings: Settings::default(),
            base,
            width,
            height,
            decimals: position_decimals(radius),
            renderers: [Some(renderer), None],
        })
    }

    /// The current camera state.
    pub fn orbit(&self) -> &Orbit {
        &self.orbit
    }

    /// The automatic camera's state (what reset returns to).
    pub fn auto_orbit(&self) -> &Orbit {
        &self.auto
    }

    /// The toggles.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The view's size in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Worker threads of the renderers.
    pub fn threads(&self) -> usize {
        self.renderers
            .iter()
            .flatten()
            .map(Renderer::threads)
            .next()
            .unwrap_or(0)
    }

    /// Patches in the prepared scene.
    pub fn patch_count(&self) -> usize {
        self.scene.patch_count()
    }

    /// Applies one input event to the state.
    pub fn apply(&mut self, event: Event) {
        match event {
            Event::Orbit { dx, dy } => self.orbit.orbit(dx, dy),
            Event::Pan { dx, dy } => self.orbit.pan(dx, dy, self.height),
            Event::Zoom(steps) => self.orbit.zoom(steps),
            Event::Reset => self.orbit = self.auto,
            Event::View(axis) => self.orbit.axis_view(axis),
            Event::CycleShading => self.settings.cycle_shading(),
            Event::ToggleMode => self.settings.triangles = !self.settings.triangles,
            Event::ToggleMip => self.settings.mip = !self.settings.mip,
            Event::ToggleSsaa => self.settings.ssaa = !self.settings.ssaa,
            Event::Resize { width, height } => {
                self.width = width;
                self.height = height;
            }
        }
    }

    /// Renders moving frames `k` times smaller per side (1..=4, clamped),
    /// enlarged to the view: fewer pixels while the camera moves.
    pub fn set_moving_scale(&mut self, k: u32) {
        self.settings.moving_scale = k.clamp(1, MAX_MOVING_SCALE);
    }

    /// The camera of a still frame, with its flags.
    pub fn camera_line(&self) -> Result<CameraLine, ViewError> {
        self.camera_line_at(self.width, self.height)
    }

    /// The camera at `width × height`, with its flags.
    fn camera_line_at(&self, width: u32, height: u32) -> Result<CameraLine, ViewError> {
        CameraLine::new(&self.orbit, self.decimals, width, height)
            .map_err(|p| ViewError::Render(spatch_render::RenderError::InvalidCamera(p)))
    }

    /// Renders the current view at `quality`.
    pub fn frame(&mut self, quality: Quality) -> Result<Frame, ViewError> {
        let (width, height) = self.settings.render_size(quality, self.width, self.height);
        let line = self.camera_line_at(width, height)?;
        let options = self.settings.options(&self.base, quality);
        let renderer = renderer_for(&mut self.renderers[quality as usize], options)?;
        let out = renderer.render(&self.scene, &line.camera)?;
        let s = &out.stats;
        let drawn = s.patches - s.patches_culled_frustum - s.patches_culled_backface;
        let overlay = format!(
            "{:.1} ms  {drawn}/{} patches  {}  {}",
            s.times_ms.total_wall,
            s.patches,
            self.settings.describe(quality),
            line.flags
        );
        let render_flags = format!(
            "{} --width {} --height {} --background {},{},{}{}",
            line.flags,
            width,
            height,
            BACKGROUND[0],
            BACKGROUND[1],
            BACKGROUND[2],
            self.settings.render_flags(quality)
        );
        Ok(Frame {
            image: out.image,
            overlay,
            render_flags,
            camera: line.camera,
            stats: out.stats,
            scale: self.settings.scale(quality),
            view: (self.width, self.height),
        })
    }

    /// Hands a frame's buffers back for the next frame of its quality.
    pub fn recycle(&mut self, frame: Frame, quality: Quality) {
        if let Some(r) = self.renderers[quality as usize].as_mut() {
            r.recycle(frame.image);
        }
    }
}

/// The renderer in `slot`, made anew when its options are not `options`.
fn renderer_for(
    slot: &mut Option<Renderer>,
    options: RenderOptions,
) -> Result<&mut Renderer, ViewError> {
    if !matches!(slot, Some(r) if *r.options() == options) {
        *slot = Some(Renderer::new(options)?);
    }
    slot.as_mut()
        .ok_or(ViewError::Render(spatch_render::RenderError::Bug(
            "renderer slot",
        )))
}
