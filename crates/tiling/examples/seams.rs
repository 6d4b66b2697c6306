//! Seams of a tiled scene: the hole fraction of a render near the tiles' borders against
//! the hole fraction inside the tiles, from above and from a street-level view.
//!
//! ```text
//! cargo run --release -p spatch-tiling --example seams -- INDEX.json [--size N] [--band W] [--street EX,EY,TX,TY]
//! ```
//!
//! For scenes whose ground covers their bounds' footprint (a city, a terrain). Every tile of
//! the index is read and joined (`Scene::merge`) and drawn as the hole measure draws scenes
//! (`spatch_eval::holes`: no culling, exact projection, flat shading), `N`² pixels
//! (default 1000):
//!
//! - **top**: straight down from above the bounds' centre, 20° field of view, the footprint
//!   filling the view;
//! - **street**: from `(EX, EY)` at 1.7 m above the bounds' floor towards `(TX, TY)` at 1 m,
//!   60° field of view (default: a quarter of the way along the lowest `x` edge's street,
//!   looking along `+y`: the cityscape's first street).
//!
//! A pixel is a **reference** pixel when its ray meets the plane of the bounds' lowest `z`
//! inside the footprint shrunk by 1 m: the ground is there, so something must be drawn. It
//! is a **hole** when nothing is drawn. It lies at the point its depth gives (at that plane
//! for a hole), and is in the **band** when that point is within `W` (default: the grid's
//! buffer) of an inner tile border in `x` or `y`, else **inside**. Prints, per view and in
//! total, the reference pixels and hole fractions of the band and of the inside, and the
//! same for a band of `W / 8`; a seam shows as a band fraction above the inside one.

use std::path::PathBuf;
use std::process::ExitCode;

use glam::{DVec2, DVec3};
use spatch_format::{read_scene, Scene};
use spatch_render::{Camera, Culling, PreparedScene, Projection, RenderOptions, Renderer, Shading};
use spatch_tiling::SceneIndex;

/// Margin by which the footprint is shrunk for reference pixels (model units).
const MARGIN: f64 = 1.0;

/// Hole counts of one class of pixels.
#[derive(Clone, Copy, Default)]
struct Holes {
    reference: u64,
    holes: u64,
}

impl Holes {
    fn add(&mut self, hole: bool) {
        self.reference += 1;
        self.holes += u64::from(hole);
    }

    fn merge(&mut self, other: Holes) {
        self.reference += other.reference;
        self.holes += other.holes;
    }

    fn text(&self) -> String {
        let fraction = self.holes as f64 / self.reference.max(1) as f64;
        format!("{:.4} % of {}", 100.0 * fraction, self.reference)
    }
}

/// Band (wide, narrow) and inside counts of one view.
#[derive(Clone, Copy, Default)]
struct ViewHoles {
    band: Holes,
    inside: Holes,
    narrow_band: Holes,
    narrow_inside: Holes,
}

impl ViewHoles {
    fn merge(&mut self, other: &ViewHoles) {
        self.band.merge(other.band);
        self.inside.merge(other.inside);
        self.narrow_band.merge(other.narrow_band);
        self.narrow_inside.merge(other.narrow_inside);
    }

    fn print(&self, name: &str, band: f64) {
        println!(
            "{name:>6}: band ±{band:.3}: {} | inside: {} || band ±{:.3}: {} | inside: {}",
            self.band.text(),
            self.inside.text(),
            band / 8.0,
            self.narrow_band.text(),
            self.narrow_inside.text()
        );
    }
}

/// What the measure needs of the tiled scene.
struct Layout {
    lo: DVec3,
    hi: DVec3,
    /// Inner tile borders along x and along y.
    borders: [Vec<f64>; 2],
}

impl Layout {
    fn new(index: &SceneIndex) -> Option<Layout> {
        let b = index.bounds?;
        let (lo, hi) = (DVec3::from_array(b.min), DVec3::from_array(b.max));
        let g = &index.grid;
        let borders = [0, 1].map(|k| {
            let first = ((lo[k] - g.anchor[k]) / g.size).ceil() as i64;
            (first..)
                .map(|i| g.anchor[k] + i as f64 * g.size)
                .take_while(|&x| x < hi[k])
                .filter(|&x| x > lo[k] + MARGIN && x < hi[k] - MARGIN)
                .collect()
        });
        Some(Layout { lo, hi, borders })
    }

    /// Distance in the plane from `p` to the nearest inner border.
    fn border_distance(&self, p: DVec3) -> f64 {
        (0..2)
            .flat_map(|k| self.borders[k].iter().map(move |&b| (p[k] - b).abs()))
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether `p` lies in the footprint shrunk by the margin.
    fn in_footprint(&self, p: DVec3) -> bool {
        (0..2).all(|k| p[k] > self.lo[k] + MARGIN && p[k] < self.hi[k] - MARGIN)
    }
}

fn main() -> ExitCode {
    match run(std::env::args().skip(1).collect()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("seams: error: {message}");
            ExitCode::from(2)
        }
    }
}

/// The usage line, printed when the index is missing.
const USAGE: &str = "usage: seams INDEX.json [--size N] [--band W] [--street EX,EY,TX,TY]";

fn run(args: Vec<String>) -> Result<(), String> {
    let index_path = PathBuf::from(args.first().ok_or(USAGE)?);
    let size: u32 = parsed_option(&args, "--size", 1000)?;
    let index = SceneIndex::read(&index_path).map_err(|e| e.to_string())?;
    let layout = Layout::new(&index).ok_or("the index has no patch")?;
    let band: f64 = parsed_option(&args, "--band", index.grid.buffer)?;
    let street = street_ends(&args, &layout)?;
    let scene = read_tiles(&index_path, &index)?;
    let prepared = PreparedScene::new(&scene);
    let mut renderer = hole_renderer()?;
    let views = [
        ("top", top_camera(&layout, size)?),
        ("street", street_camera(&layout, street, size)?),
    ];
    let mut total = ViewHoles::default();
    for (name, camera) in views {
        let depth = renderer
            .render(&prepared, &camera)
            .map_err(|e| e.to_string())?
            .image
            .depth()
            .to_vec();
        let holes = count_holes(&camera, &depth, &layout, band);
        holes.print(name, band);
        total.merge(&holes);
    }
    total.print("total", band);
    Ok(())
}

/// The argument after `name`, if `name` is given with one.
fn option<'a>(args: &'a [String], name: &str) -> Option<&'a String> {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
}

/// The value of option `name` parsed, or `default` when it is not given.
fn parsed_option<T>(args: &[String], name: &str, default: T) -> Result<T, String>
where
    T: std::str::FromStr,
    T::Err: std::fmt::Display,
{
    option(args, name)
        .map_or(Ok(default), |s| s.parse())
        .map_err(|e| format!("{name}: {e}"))
}

/// The street view's eye and target in the plane: `--street`, else the first street.
fn street_ends(args: &[String], layout: &Layout) -> Result<(DVec2, DVec2), String> {
    match option(args, "--street") {
        Some(s) => {
            let v: Vec<f64> = s
                .split(',')
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|e| format!("--street: {e}"))?;
            let [ex, ey, tx, ty] = v[..] else {
                return Err("--street takes EX,EY,TX,TY".into());
            };
            Ok((DVec2::new(ex, ey), DVec2::new(tx, ty)))
        }
        None => {
            let x = layout.lo.x + 2.0 * MARGIN;
            Ok((
                DVec2::new(x, layout.lo.y + 2.0 * MARGIN),
                DVec2::new(x, layout.hi.y),
            ))
        }
    }
}

/// A renderer drawing as the hole measure does: flat, no culling, exact projection.
fn hole_renderer() -> Result<Renderer, String> {
    let mut options = RenderOptions::default();
    options.shading = Shading::Flat;
    options.culling = Culling::None;
    options.projection = Projection::Exact;
    options.threads = 2;
    Renderer::new(options).map_err(|e| e.to_string())
}

/// Straight down from above the bounds' centre, the footprint filling the 20° view.
fn top_camera(layout: &Layout, size: u32) -> Result<Camera, String> {
    let floor = layout.lo.z;
    let centre = (layout.lo + layout.hi) / 2.0;
    let half = (layout.hi - layout.lo).truncate().max_element() / 2.0;
    Camera::look_at(
        DVec3::new(
            centre.x,
            centre.y,
            layout.hi.z + half / 10f64.to_radians().tan() * 1.02,
        ),
        DVec3::new(centre.x, centre.y, floor),
        DVec3::Y,
        20.0,
        size,
        size,
    )
    .map_err(|e| e.to_string())
}

/// From 1.7 m above the floor at the street's eye towards its target at 1 m, 60° view.
fn street_camera(layout: &Layout, street: (DVec2, DVec2), size: u32) -> Result<Camera, String> {
    let floor = layout.lo.z;
    Camera::look_at(
        street.0.extend(floor + 1.7),
        street.1.extend(floor + 1.0),
        DVec3::Z,
        60.0,
        size,
        size,
    )
    .map_err(|e| e.to_string())
}

/// Every tile of the index with patches, joined.
fn read_tiles(index_path: &std::path::Path, index: &SceneIndex) -> Result<Scene, String> {
    let scenes = index
        .tiles
        .iter()
        .filter(|t| t.patches > 0)
        .map(|t| read_scene(&SceneIndex::tile_path(index_path, t)).map_err(|e| e.to_string()))
        .collect::<Result<Vec<_>, _>>()?;
    Scene::merge(scenes).map_err(|e| e.to_string())
}

/// The band and inside hole counts of a render's `depth` seen by `camera`.
fn count_holes(camera: &Camera, depth: &[f32], layout: &Layout, band: f64) -> ViewHoles {
    let (w, h) = (camera.width() as usize, camera.height() as usize);
    let forward = (camera.target() - camera.eye()).normalize();
    let right = forward.cross(camera.up()).normalize();
    let up = right.cross(forward);
    let f = 1.0 / (camera.fov_y_degrees().to_radians() / 2.0).tan();
    let aspect = w as f64 / h as f64;
    let floor = layout.lo.z;
    let mut holes = ViewHoles::default();
    for (i, &d) in depth.iter().enumerate() {
        let (px, py) = ((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
        let x = (2.0 * px / w as f64 - 1.0) * aspect / f;
        let y = (1.0 - 2.0 * py / h as f64) / f;
        // A ray with unit eye depth per unit of parameter.
        let ray = forward + right * x + up * y;
        if ray.z >= 0.0 {
            continue;
        }
        let ground = camera.eye() + ray * ((floor - camera.eye().z) / ray.z);
        if !layout.in_footprint(ground) {
            continue;
        }
        let hole = !d.is_finite();
        let at = if hole {
            ground
        } else {
            camera.eye() + ray * f64::from(d)
        };
        let distance = layout.border_distance(at);
        if distance < band {
            &mut holes.band
        } else {
            &mut holes.inside
        }
        .add(hole);
        if distance < band / 8.0 {
            &mut holes.narrow_band
        } else {
            &mut holes.narrow_inside
        }
        .add(hole);
    }
    holes
}
