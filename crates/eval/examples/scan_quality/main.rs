//! Speck and hole fractions of a scene over the 14 standard views (../shared/MEASURES.md).
//!
//! ```text
//! cargo run --release -p spatch-eval --example scan_quality -- SCENE.spatch REFERENCE_MESH [PNG_DIR] [OPTION...]
//! ```
//!
//! `--cloud INPUT` (a cloud file or a `.conf` scan set, read as `spatch from-cloud` reads it)
//! also says which holes are surface the scans never saw (`coverage.rs`): per view and in
//! total, the reference pixels and the hole pixels with no point of the cloud within two
//! spacings of the surface they show.
//!
//! The other options change how the scene is drawn for the specks (as `spatch render` takes them):
//! `--mode triangles` (its cells as two triangles each), `--projection exact`,
//! `--shading gouraud|flat`, `--no-mip`, `--cull none|back`. Crease artefacts of patch mode
//! show as the ratio of its speck fraction to that of `--mode triangles` (docs/algorithms/render.md).
//!
//! The cameras come from the reference mesh (the views of `spatch_eval::holes`: 6 axes and
//! 8 diagonals, 40° field of view, the bounding sphere filling the image with a 5 % margin,
//! 500²). The scene is drawn with the renderer's defaults (as `spatch render` draws it), or
//! the options below.
//!
//! - **specks**: the scene's covered pixels eroded by 2 px (5 × 5 square); a pixel is a speck
//!   when its grey level (mean of R, G, B) is more than 40 below the median of its 5 × 5
//!   neighbourhood. Fraction = specks / eroded covered pixels.
//! - **holes**: the reference mesh drawn without culling, its coverage eroded by 2 px; a hole
//!   is a pixel of that mask the scene, drawn without culling (nodes projected exactly), leaves
//!   empty or covers only farther than `HOLE_DEPTH_TOLERANCE` of the bounding radius behind
//!   the reference (as `spatch_eval::hole_fraction`). Fraction = holes / eroded reference
//!   pixels.
//!
//! With `PNG_DIR`, each view's render is written there as `view_NN.png`, and its specks as
//! `specks_NN.png` (the render in grey, every speck pixel red, so where they gather shows at a
//! glance), and its holes as `holes_NN.png` (the reference mesh in grey, every hole pixel red). Prints one line per
//! view and a total line; the totals are what docs/algorithms/cloud.md quotes.

use std::path::PathBuf;
use std::process::ExitCode;

use coverage::Coverage;

use glam::DVec3;
use spatch_eval::holes::{
    covers, hole_view_camera, standard_views, HoleOptions, HOLE_DEPTH_TOLERANCE,
};
use spatch_eval::{find_specks, interior_mask, MEASURES_RADIUS};
use spatch_render::{
    Camera, Culling, MeshColours, PreparedScene, Projection, RenderMode, RenderOptions,
    RenderedImage, Renderer, Shading, TriangleMesh as RasterMesh,
};

mod coverage;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let png_dir = args
        .get(2)
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from);
    let flags = &args[(2 + png_dir.is_some() as usize).min(args.len())..];
    let (options, cloud) = match scene_options(flags) {
        Ok(parsed) if args.len() >= 2 => parsed,
        Ok(_) => usage("two arguments needed"),
        Err(message) => usage(&message),
    };
    let coverage = match cloud.map(|path| load_coverage(&path)).transpose() {
        Ok(coverage) => coverage,
        Err(message) => {
            eprintln!("scan_quality: error: {message}");
            return ExitCode::from(2);
        }
    };
    match run(&args[0], &args[1], png_dir, options, coverage.as_ref()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("scan_quality: error: {message}");
            ExitCode::from(2)
        }
    }
}

/// Prints the usage line (after `message`) and exits with status 2.
fn usage(message: &str) -> ! {
    eprintln!("scan_quality: {message}");
    eprintln!("usage: scan_quality SCENE.spatch REFERENCE_MESH [PNG_DIR] [OPTION...]");
    std::process::exit(2)
}

/// The merged cloud of `path` (a cloud file or a scan set) indexed for coverage.
fn load_coverage(path: &std::path::Path) -> Result<Coverage, String> {
    let loaded = spatch_scan::load_scans(&[path.to_path_buf()], &Default::default())
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let coverage = Coverage::new(&loaded.cloud).map_err(|e| format!("{}: {e}", path.display()))?;
    println!(
        "cloud {}: {} points, spacing {:.4e}",
        path.display(),
        loaded.cloud.len(),
        coverage.spacing()
    );
    Ok(coverage)
}

/// The render options of the scene's speck images and the `--cloud` input from `flags`
/// (see the header).
fn scene_options(flags: &[String]) -> Result<(RenderOptions, Option<PathBuf>), String> {
    let mut options = RenderOptions::default();
    let mut cloud = None;
    let mut it = flags.iter();
    while let Some(flag) = it.next() {
        let mut value = || {
            it.next()
                .map(String::as_str)
                .ok_or(format!("{flag} needs a value"))
        };
        match flag.as_str() {
            "--mode" => match value()? {
                "triangles" => options.mode = RenderMode::Triangles,
                "patches" => options.mode = RenderMode::Patches,
                v => return Err(format!("--mode {v}: patches or triangles")),
            },
            "--projection" => match value()? {
                "exact" => options.projection = Projection::Exact,
                "trilinear" => options.projection = Projection::Trilinear,
                v => return Err(format!("--projection {v}: exact or trilinear")),
            },
            "--shading" => match value()? {
                "phong" => options.shading = Shading::Phong,
                "gouraud" => options.shading = Shading::Gouraud,
                "flat" => options.shading = Shading::Flat,
                v => return Err(format!("--shading {v}: phong, gouraud or flat")),
            },
            "--cull" => match value()? {
                "auto" => options.culling = Culling::Auto,
                "back" => options.culling = Culling::Back,
                "none" => options.culling = Culling::None,
                v => return Err(format!("--cull {v}: auto, back or none")),
            },
            "--no-mip" => options.mip = false,
            "--cloud" => cloud = Some(PathBuf::from(value()?)),
            other => return Err(format!("unknown option {other}")),
        }
    }
    Ok((options, cloud))
}

/// Measures the scene at `scene_path` against the mesh at `mesh_path` over the standard
/// views, printing a line per view and the totals (see the header).
fn run(
    scene_path: &str,
    mesh_path: &str,
    png_dir: Option<PathBuf>,
    options: RenderOptions,
    coverage: Option<&Coverage>,
) -> Result<(), String> {
    let scene =
        spatch_format::read_scene(scene_path.as_ref()).map_err(|e| format!("{scene_path}: {e}"))?;
    let mesh = spatch_mesh::load_mesh(mesh_path)
        .map_err(|e| format!("{mesh_path}: {e}"))?
        .mesh;
    let raster = RasterMesh::new(
        mesh.origin,
        &mesh.positions,
        &mesh.triangles,
        MeshColours::None,
    )
    .map_err(|e| format!("{mesh_path}: {e}"))?;
    let prepared = PreparedScene::new(&scene);
    let mut renderers = ViewRenderers::new(options)?;
    let radius = raster
        .bounding_sphere()
        .ok_or_else(|| format!("{mesh_path}: nothing to frame"))?
        .1;
    let tolerance = (HOLE_DEPTH_TOLERANCE * radius) as f32;
    let options = HoleOptions::default();
    let mut total = Tally::default();
    for (index, direction) in standard_views().into_iter().enumerate() {
        let camera =
            hole_view_camera(&mesh, direction, &options).map_err(|e| format!("camera: {e}"))?;
        let images = renderers.draw(&prepared, &raster, &camera)?;
        let view = measure_view(&images, tolerance, coverage, &camera);
        print_view(index, direction, &view.tally, coverage.is_some());
        total.add(&view.tally);
        if let Some(dir) = &png_dir {
            write_view_pngs(dir, index, &images, &view)?;
        }
    }
    print_total(&total, coverage.is_some());
    Ok(())
}

/// The three renderers of a view: the scene as asked, the reference mesh without culling,
/// and the scene without culling with nodes projected exactly (for the holes).
struct ViewRenderers {
    scene: Renderer,
    reference: Renderer,
    uncull: Renderer,
}

/// The three images of one view (see [`ViewRenderers`]).
struct ViewImages {
    image: RenderedImage,
    reference: RenderedImage,
    uncull: RenderedImage,
}

impl ViewRenderers {
    /// The renderers, the scene's with `options`.
    fn new(options: RenderOptions) -> Result<Self, String> {
        let mut reference_options = RenderOptions::default();
        reference_options.culling = Culling::None;
        let mut uncull_options = RenderOptions::default();
        uncull_options.culling = Culling::None;
        uncull_options.projection = Projection::Exact;
        let renderer = |o| Renderer::new(o).map_err(|e| e.to_string());
        Ok(ViewRenderers {
            scene: renderer(options)?,
            reference: renderer(reference_options)?,
            uncull: renderer(uncull_options)?,
        })
    }

    /// Draws the view of `camera`.
    fn draw(
        &mut self,
        prepared: &PreparedScene,
        raster: &RasterMesh<'_>,
        camera: &Camera,
    ) -> Result<ViewImages, String> {
        let image = self.scene.render(prepared, camera);
        let image = image.map_err(|e| e.to_string())?.image;
        let reference = self.reference.rasterize(raster, camera);
        let reference = reference.map_err(|e| e.to_string())?.image;
        let uncull = self.uncull.render(prepared, camera);
        let uncull = uncull.map_err(|e| e.to_string())?.image;
        Ok(ViewImages {
            image,
            reference,
            uncull,
        })
    }
}

/// What one view measured, and which pixels are its specks and holes.
struct ViewMeasure {
    tally: Tally,
    speck_pixels: Vec<usize>,
    hole_pixels: Vec<usize>,
}

/// The specks and holes of one view (and with `coverage`, what the cloud did not see).
fn measure_view(
    images: &ViewImages,
    tolerance: f32,
    coverage: Option<&Coverage>,
    camera: &Camera,
) -> ViewMeasure {
    let (image, reference) = (&images.image, &images.reference);
    let (width, height) = (image.width() as usize, image.height() as usize);
    let covered: Vec<bool> = image.pixels().iter().map(|p| p[3] > 0).collect();
    let reference_covered: Vec<bool> = reference.depth().iter().map(|d| d.is_finite()).collect();
    let reached: Vec<bool> = reference
        .depth()
        .iter()
        .zip(images.uncull.depth())
        .map(|(&s, &p)| covers(s, p, tolerance))
        .collect();
    let found = find_specks(image.pixels(), &covered, width, height);
    let speck_pixels = found.pixels;
    let mut hole_pixels = Vec::new();
    let mut counted = Vec::new();
    let mut tally = Tally {
        specks: Share {
            part: speck_pixels.len(),
            whole: found.counted,
        },
        holes: count_holes(&reference_covered, &reached, width, height, &mut counted),
        ..Tally::default()
    };
    hole_pixels.extend(counted.iter().copied().filter(|&k| !reached[k]));
    if let Some(coverage) = coverage {
        let depth = reference.depth();
        let unseen = |pixels: &[usize]| Share {
            part: coverage
                .unseen(camera, depth, pixels)
                .into_iter()
                .filter(|&u| u)
                .count(),
            whole: pixels.len(),
        };
        tally.unseen = unseen(&counted);
        tally.unseen_holes = unseen(&hole_pixels);
    }
    ViewMeasure {
        tally,
        speck_pixels,
        hole_pixels,
    }
}

/// Prints view `index`'s line (and with a cloud, what it did not see).
fn print_view(index: usize, direction: DVec3, view: &Tally, with_cloud: bool) {
    println!(
        "view {index:2} ({:+.2},{:+.2},{:+.2}): specks {:.3} % of {}, holes {:.3} % of {}",
        direction.x,
        direction.y,
        direction.z,
        view.specks.percent(),
        view.specks.whole,
        view.holes.percent(),
        view.holes.whole
    );
    if with_cloud {
        println!(
            "  unseen by the cloud: {} of {} reference pixels, {} of {} hole pixels",
            view.unseen.part, view.unseen.whole, view.unseen_holes.part, view.unseen_holes.whole
        );
    }
}

/// Writes view `index`'s render, speck map and hole map into `dir` (see the header).
fn write_view_pngs(
    dir: &std::path::Path,
    index: usize,
    images: &ViewImages,
    view: &ViewMeasure,
) -> Result<(), String> {
    let image = &images.image;
    let (width, height) = (image.width() as usize, image.height() as usize);
    let png = image.encode_png().map_err(|e| e.to_string())?;
    let path = dir.join(format!("view_{index:02}.png"));
    std::fs::write(&path, png).map_err(|e| format!("{}: {e}", path.display()))?;
    let path = dir.join(format!("specks_{index:02}.png"));
    write_speck_mask(&path, image.pixels(), &view.speck_pixels, width, height)?;
    let path = dir.join(format!("holes_{index:02}.png"));
    let reference = images.reference.pixels();
    write_speck_mask(&path, reference, &view.hole_pixels, width, height)
}

/// Prints the totals over the views.
fn print_total(total: &Tally, with_cloud: bool) {
    println!(
        "total: specks {:.3} % ({} of {} covered pixels), holes {:.3} % ({} of {} reference pixels)",
        total.specks.percent(),
        total.specks.part,
        total.specks.whole,
        total.holes.percent(),
        total.holes.part,
        total.holes.whole
    );
    if with_cloud {
        println!(
            "unseen by the cloud: {:.3} % of reference pixels ({} of {}), {} of {} hole pixels",
            total.unseen.percent(),
            total.unseen.part,
            total.unseen.whole,
            total.unseen_holes.part,
            total.unseen_holes.whole
        );
    }
}

/// A count out of a whole.
#[derive(Default, Clone, Copy)]
struct Share {
    part: usize,
    whole: usize,
}

impl Share {
    fn percent(&self) -> f64 {
        if self.whole == 0 {
            0.0
        } else {
            100.0 * self.part as f64 / self.whole as f64
        }
    }
}

/// Specks and holes of one view or of all, and with `--cloud` the reference and hole pixels
/// the cloud did not see.
#[derive(Default)]
struct Tally {
    specks: Share,
    holes: Share,
    unseen: Share,
    unseen_holes: Share,
}

impl Share {
    fn add(&mut self, other: Share) {
        self.part += other.part;
        self.whole += other.whole;
    }
}

impl Tally {
    fn add(&mut self, other: &Tally) {
        self.specks.add(other.specks);
        self.holes.add(other.holes);
        self.unseen.add(other.unseen);
        self.unseen_holes.add(other.unseen_holes);
    }
}

fn grey(pixel: [u8; 4]) -> i32 {
    (i32::from(pixel[0]) + i32::from(pixel[1]) + i32::from(pixel[2])) / 3
}

/// Writes the render in grey (light, so the marks stand out; background white) with every
/// pixel of `specks` red, as a PNG at `path`.
fn write_speck_mask(
    path: &std::path::Path,
    pixels: &[[u8; 4]],
    specks: &[usize],
    width: usize,
    height: usize,
) -> Result<(), String> {
    let mut rgb: Vec<u8> = pixels
        .iter()
        .flat_map(|&p| {
            let level = if p[3] == 0 { 255 } else { 128 + grey(p) / 2 } as u8;
            [level; 3]
        })
        .collect();
    for &k in specks {
        rgb[3 * k..3 * k + 3].copy_from_slice(&[255, 0, 0]);
    }
    image::RgbImage::from_raw(width as u32, height as u32, rgb)
        .ok_or("speck mask: wrong buffer size")?
        .save(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The holes of one view: the eroded reference pixels (their indices go to `counted`) that
/// `covered` leaves out.
fn count_holes(
    reference: &[bool],
    covered: &[bool],
    width: usize,
    height: usize,
    counted: &mut Vec<usize>,
) -> Share {
    let mut share = Share::default();
    let interior = interior_mask(reference, width, height, MEASURES_RADIUS);
    for y in 0..height {
        for x in 0..width {
            if interior[y * width + x] {
                share.whole += 1;
                counted.push(y * width + x);
                if !covered[y * width + x] {
                    share.part += 1;
                }
            }
        }
    }
    share
}
