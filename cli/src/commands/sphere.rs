//! `spatch sphere`: the perfect sphere.

use std::path::PathBuf;
use std::time::Instant;

use spatch_format::{encode_scene, WriteOptions};
use spatch_sphere::{build_sphere, SphereOptions};

use crate::output::{print_stdout, write_output};

/// Arguments of `spatch sphere`.
#[derive(Debug, clap::Args)]
pub(crate) struct SphereArgs {
    /// Output .spatch file.
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Sphere radius in model units.
    #[arg(long, default_value_t = SphereOptions::DEFAULT_RADIUS)]
    radius: f64,
    /// Number of patches (centres spread almost evenly over the sphere).
    #[arg(long, default_value_t = SphereOptions::DEFAULT_PATCHES)]
    patches: usize,
    /// Nodes per patch side (2..=257).
    #[arg(long, default_value_t = SphereOptions::DEFAULT_GRID)]
    grid: u32,
    /// Node spacing |ax| = |ay| in model units.
    #[arg(long, default_value_t = SphereOptions::DEFAULT_SPACING)]
    spacing: f64,
    /// Displacement step |az|: the radial error is at most half of it.
    #[arg(long, default_value_t = SphereOptions::DEFAULT_STEP)]
    step: f64,
    /// Compress node data (grid prediction + range coding).
    #[arg(long)]
    compress: bool,
}

impl SphereArgs {
    fn options(&self) -> SphereOptions {
        let mut options = SphereOptions::default();
        options.radius = self.radius;
        options.patches = self.patches;
        options.grid = self.grid;
        options.spacing = self.spacing;
        options.step = self.step;
        options
    }
}

/// Builds the sphere, measures its radial error, writes it.
pub(crate) fn run(args: &SphereArgs) -> anyhow::Result<()> {
    let options = args.options();
    let started = Instant::now();
    let sphere = build_sphere(&options)?;
    let build_seconds = started.elapsed().as_secs_f64();
    let scene = &sphere.scene;
    let worst = scene
        .patches()
        .iter()
        .flat_map(|p| {
            p.filled_nodes()
                .map(|(_, _, q)| (q.as_dvec3().length() - options.radius).abs())
        })
        .fold(0.0f64, f64::max);
    let write_started = Instant::now();
    let bytes = encode_scene(
        scene,
        &WriteOptions::with_compression(super::compression(args.compress)),
    )?;
    write_output(&args.output, &bytes)?;
    let write_seconds = write_started.elapsed().as_secs_f64();
    let mut text = format!(
        "{}: {} patches, {} nodes, {} bytes\n  radial error max {:.6} (bound: step/2 = {:.6})\n",
        args.output.display(),
        scene.patches().len(),
        scene.filled_node_count(),
        bytes.len(),
        worst,
        options.step / 2.0,
    );
    if sphere.coverage_margin >= 0.0 {
        text.push_str(&format!(
            "  coverage: no gaps (margin {:.3} units)\n",
            sphere.coverage_margin
        ));
    } else {
        text.push_str(&format!(
            "  coverage: GAPS up to {:.3} units wide: use more --patches or a larger --grid\n",
            -sphere.coverage_margin
        ));
    }
    text.push_str(&format!(
        "  time: build {:.1} ms, encode+write {:.1} ms\n",
        build_seconds * 1e3,
        write_seconds * 1e3
    ));
    print_stdout(&text)
}

impl SphereArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default().output_as(Some(&self.output), Written::Spatch)
    }
}
