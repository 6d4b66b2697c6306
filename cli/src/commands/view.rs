//! `spatch view`: an interactive window on one or more scenes (merged), a
//! scripted replay with a screenshot, or an orbit benchmark.

use std::path::{Path, PathBuf};

use anyhow::Context;
use spatch_format::Scene;
use spatch_view::{
    bench_orbit, parse_script, replay_offscreen, run_window, Replayed, ViewError, Viewer,
    WindowConfig,
};

use super::ThreadsArg;
use crate::failure::InternalFailure;
use crate::output::{print_summary, read_spatch, write_output};

/// Arguments of `spatch view`.
#[derive(Debug, clap::Args)]
pub(crate) struct ViewArgs {
    /// Input .spatch files; several are shown together (as `spatch merge`
    /// would join them). A tiled scene index (`index.json` of `from-cloud
    /// --plan`) is shown whole, on its own.
    #[arg(required = true, value_name = "FILE")]
    inputs: Vec<PathBuf>,
    /// Window width in pixels.
    #[arg(long, value_name = "PX", default_value_t = 1000, value_parser = clap::value_parser!(u32).range(1..=8192))]
    width: u32,
    /// Window height in pixels.
    #[arg(long, value_name = "PX", default_value_t = 800, value_parser = clap::value_parser!(u32).range(1..=8192))]
    height: u32,
    #[command(flatten)]
    threads: ThreadsArg,
    /// Render N frames of one orbit around the scene without a window and
    /// print the median and worst frame times.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100_000), conflicts_with_all = ["script", "screenshot"])]
    bench_orbit: Option<u32>,
    /// Replay the events of FILE (one a line: orbit DX DY, pan DX DY, zoom
    /// N, view K, reset, shading, mode, mip, ssaa, resize W H; see
    /// docs/viewer.md), show the refined frame, print its `spatch render`
    /// command and exit.
    #[arg(long, value_name = "FILE")]
    script: Option<PathBuf>,
    /// With --script: write the last frame shown as a PNG.
    #[arg(long, value_name = "FILE", requires = "script")]
    screenshot: Option<PathBuf>,
    /// Render moving frames K times smaller per side (1..=4) and enlarge
    /// them to the window: about K² fewer pixels while the camera moves;
    /// still frames are always full size.
    #[arg(long, value_name = "K", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=4))]
    moving_scale: u32,
    /// Leave the overlay line out of the window (and the screenshot).
    #[arg(long)]
    no_overlay: bool,
    /// With --script: render the frames without opening a window (no
    /// display needed).
    #[arg(long, requires = "script")]
    no_window: bool,
}

/// Reads and merges the inputs; a tiled scene index (docs/scale.md) is read whole and
/// viewed on its own.
fn read_scenes(inputs: &[PathBuf]) -> anyhow::Result<Scene> {
    if let Some(index) = inputs.iter().find(|p| super::tiled_scene::is_index(p)) {
        if inputs.len() > 1 {
            anyhow::bail!(
                "{}: a tiled scene index is viewed on its own",
                index.display()
            );
        }
        return super::tiled_scene::read_all_tiles(index);
    }
    let mut scenes = Vec::with_capacity(inputs.len());
    for path in inputs {
        scenes.push(read_spatch(path)?.0);
    }
    if scenes.len() == 1 {
        return Ok(scenes.remove(0));
    }
    Scene::merge(scenes).with_context(|| format!("{}", inputs[1].display()))
}

/// A viewer error as an exit-code-aware error, naming `file` for input
/// problems.
fn classify(err: ViewError, file: &Path) -> anyhow::Error {
    match err {
        ViewError::Render(e) => crate::failure::render_failure(e),
        ViewError::Encode(_) => anyhow::Error::new(InternalFailure(err.to_string())),
        ViewError::Script { .. } | ViewError::EmptyScene => {
            anyhow::anyhow!("{}: {err}", file.display())
        }
        ViewError::NoDisplay(_) | ViewError::Window(_) => anyhow::Error::new(err),
    }
}

/// The command that renders the same image as `spatch render`.
fn render_command(inputs: &[PathBuf], flags: &str) -> String {
    let names: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
    if names.len() == 1 {
        format!("spatch render {} -o view.png {flags}", names[0])
    } else {
        format!(
            "spatch merge {} -o view.spatch && spatch render view.spatch -o view.png {flags}",
            names.join(" ")
        )
    }
}

/// Runs the viewer, the replay or the benchmark.
pub(crate) fn run(args: &ViewArgs) -> anyhow::Result<()> {
    if args.bench_orbit.is_none() && !args.no_window {
        // Before reading anything: no window can open.
        spatch_view::check_display().map_err(anyhow::Error::new)?;
    }
    let events = match &args.script {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("{}: cannot read the script", path.display()))?;
            Some(parse_script(&text).map_err(|e| classify(e, path))?)
        }
        None => None,
    };
    let scene = read_scenes(&args.inputs)?;
    let first = &args.inputs[0];
    let mut viewer = Viewer::new(&scene, args.width, args.height, args.threads.count())
        .map_err(|e| classify(e, first))?;
    viewer.set_moving_scale(args.moving_scale);
    if let Some(frames) = args.bench_orbit {
        return bench(&mut viewer, frames as usize, first);
    }
    let outcome = match &events {
        Some(events) if args.no_window => replay_offscreen(&mut viewer, events, !args.no_overlay),
        _ => {
            let config = WindowConfig {
                title: format!("spatch view {}", first.display()),
                no_overlay: args.no_overlay,
                script: events.clone(),
            };
            let inputs = &args.inputs;
            run_window(&mut viewer, &config, &mut |flags| {
                // A closed standard output must not end the session: the line is a convenience.
                let _ =
                    crate::output::print_stdout(&format!("{}\n", render_command(inputs, flags)));
            })
        }
    }
    .map_err(|e| classify(e, first))?;
    finish(args, &outcome)
}

/// Writes the screenshot and prints the render command of the last frame.
fn finish(args: &ViewArgs, outcome: &Replayed) -> anyhow::Result<()> {
    if let Some(path) = &args.screenshot {
        let png = outcome
            .screenshot
            .encode_png()
            .map_err(|e| InternalFailure(e.to_string()))?;
        write_output(path, &png)?;
    }
    print_summary(
        &format!("{}\n", render_command(&args.inputs, &outcome.render_flags)),
        false,
    )
}

/// `--bench-orbit`: the table of frame times.
fn bench(viewer: &mut Viewer, frames: usize, file: &Path) -> anyhow::Result<()> {
    let b = bench_orbit(viewer, frames).map_err(|e| classify(e, file))?;
    let (w, h) = viewer.size();
    let (rw, rh) = viewer
        .settings()
        .render_size(spatch_view::Quality::Moving, w, h);
    let rendered = if (rw, rh) == (w, h) {
        String::new()
    } else {
        format!(" (rendered at {rw}x{rh})")
    };
    let threads = viewer.threads();
    print_summary(
        &format!(
            "orbit of {} frames at {w}x{h}{rendered}, {threads} threads: median {:.2} ms ({:.0} fps), worst {:.2} ms; {} of {} patches drawn (median)\n",
            b.frames,
            b.median_ms,
            1e3 / b.median_ms,
            b.worst_ms,
            b.median_patches_drawn,
            viewer.patch_count()
        ),
        false,
    )
}

impl ViewArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        let mut files = crate::overwrite_guard::Files::default()
            .input(self.script.as_deref())
            .output_as(self.screenshot.as_deref(), Written::Png);
        files
            .inputs
            .extend(self.inputs.iter().map(PathBuf::as_path));
        files
    }
}
