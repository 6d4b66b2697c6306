//! Command-line arguments: one `Args` struct per subcommand.

use clap::{Parser, Subcommand};

use crate::commands;

/// spatch turns 3D models into spatial patches (small range images of
/// surface) and renders them on the CPU.
#[derive(Debug, Parser)]
#[command(name = "spatch", version, about, long_about = None, propagate_version = true)]
pub(crate) struct Cli {
    /// No progress bar and no summary (errors are still printed; --json and
    /// --report still write their reports).
    #[arg(short, long, global = true)]
    pub(crate) quiet: bool,
    /// What to do.
    #[command(subcommand)]
    pub(crate) command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Convert the built-in model (a textured cow) into a folder: source, scene and report.
    #[command(after_help = "Example:\n  spatch demo\n  spatch demo -o my-demo --grid 9")]
    Demo(commands::demo::DemoArgs),
    /// Convert a mesh (.obj, .gltf, .glb, .ply, .off, .stl) into spatial patches.
    #[command(
        after_help = "Example:\n  spatch convert bunny.ply -o bunny.spatch\n  spatch convert duck.glb -o duck.spatch --report report.json --grid 9 --threads 2"
    )]
    Convert(commands::convert::ConvertArgs),
    /// Convert point clouds and scan sets (.ply, .xyz, .pts, .las, .laz, .e57, .conf) into
    /// spatial patches through range images.
    #[command(
        name = "from-cloud",
        after_help = "Example:\n  spatch from-cloud bun000.ply -o bun000.spatch\n  spatch from-cloud bun.conf -o bunny.spatch        # a registered scan set (poses)\n  spatch from-cloud a.ply b.ply c.xyz -o abc.spatch  # several clouds, one frame\n  spatch from-cloud site.laz -o site.spatch\n  spatch from-cloud scan.txt --columns x,y,z,nx,ny,nz,r,g,b -o scan.spatch\n  spatch from-cloud scan.ply -o scan.spatch --smooth --report report.json"
    )]
    FromCloud(commands::from_cloud::FromCloudArgs),
    /// Stream a point cloud (or tile a mesh by face) and write a tile plan (JSON): the grid,
    /// the occupied tiles with their bounds and counts, and the spacing every tile converts with.
    #[command(
        after_help = "Example:\n  spatch plan city.las --tile 50 -o plan.json\n  spatch from-cloud city.las --plan plan.json --tile 3 -o 3.spatch   # one tile\n  spatch from-cloud city.las --plan plan.json -o out/                # every tile + out/index.json\n  spatch plan city.obj --tile 50 -o mplan.json\n  spatch convert city.obj --plan mplan.json --tile 3 -o 3.spatch     # one tile of a mesh"
    )]
    Plan(commands::plan::PlanArgs),
    /// Write the tiled scene index (DIR/index.json) of a plan's tile files converted
    /// elsewhere (GNU parallel, Dask).
    #[command(
        after_help = "Example:\n  spatch index plan.json out/\n  spatch render out/index.json -o city.png"
    )]
    Index(commands::index::IndexArgs),
    /// Build the perfect sphere of the original work as patches.
    #[command(
        after_help = "Example:\n  spatch sphere -o sphere.spatch\n  spatch sphere --radius 10 --patches 500 --grid 9 --step 0.001 -o small.spatch"
    )]
    Sphere(commands::sphere::SphereArgs),
    /// Build the Earth model from a colour map (and an elevation map) and convert it to patches.
    #[command(
        after_help = "Example:\n  spatch earth -o earth.spatch\n  spatch earth --colour map.jpg --level high --report r.json -o earth.spatch\n  spatch earth --elevation relief.png --sea-level 92 -o relief.spatch"
    )]
    Earth(commands::earth::EarthArgs),
    /// Report what a .spatch file holds: counts, bytes per section, precision, bounds, and
    /// which sides of its patches may show (openings, inside box).
    #[command(
        after_help = "Example:\n  spatch stats sphere.spatch\n  spatch stats sphere.spatch --json"
    )]
    Stats(commands::stats::StatsArgs),
    /// Write the nodes (or the cells, one welded mesh per patch) of a .spatch
    /// file as PLY, OBJ, glTF or GLB.
    #[command(
        after_help = "Example:\n  spatch export sphere.spatch -o nodes.ply\n  spatch export sphere.spatch --cells -o cells.glb\n  spatch export utm.spatch --cells -o utm.obj --origin 500000,4000000,0"
    )]
    Export(commands::export::ExportArgs),
    /// Concatenate scenes into one file, each kept at full precision however
    /// far apart, reading one input at a time.
    #[command(
        after_help = "Example:\n  spatch merge a.spatch b.spatch -o ab.spatch\n  spatch merge a.spatch a.spatch --translate 0,0,0 --translate 1e7,0,0 -o aa.spatch\n  spatch merge out/index.json -o city.spatch   # every tile of a tiled scene"
    )]
    Merge(commands::merge::MergeArgs),
    /// Render a .spatch file to a PNG on the CPU (patches or triangles).
    #[command(
        after_help = "Example:\n  spatch render sphere.spatch -o sphere.png\n  spatch render sphere.spatch -o near.png --eye 0,0,400 --target 0,0,0 --fov 30 --width 1000 --height 1000 --depth depth.png --stats stats.json\n  spatch render sphere.spatch --bench 50 --threads 2"
    )]
    Render(commands::render::RenderArgs),
    /// Measure a scene against its source (geometric and image error, timing), or sweep
    /// conversion and render settings and plot error against time.
    #[command(
        after_help = "Example:\n  spatch eval bunny.spatch --source bun_zipper.ply\n  spatch eval bunny.spatch --source bun_zipper.ply --views 6 --json --per-patch patches.csv\n  spatch eval scan.spatch --source bun000.ply        # a point cloud: cloud error, no image error\n  spatch eval --sweep bun_zipper.ply --out sweep --threads 2"
    )]
    Eval(commands::eval_args::EvalArgs),
    /// Look around scenes in a window on the CPU: drag to orbit, right/middle drag to pan,
    /// wheel to zoom; keys r reset, 1-6 axis views, s shading, t patches/triangles, m mip,
    /// a supersampling, p print the `spatch render` command, q/Esc quit.
    #[command(after_help = "Example:
  spatch view bunny.spatch
  spatch view a.spatch b.spatch --width 1280 --height 720
  spatch view bunny.spatch --bench-orbit 100 --threads 2
  spatch view bunny.spatch --script events.txt --screenshot out.png --no-overlay")]
    View(commands::view::ViewArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    #[command(
        after_help = "Example:\n  spatch completions bash > /etc/bash_completion.d/spatch\n  spatch completions zsh > ~/.zfunc/_spatch"
    )]
    Completions(commands::completions::CompletionsArgs),
    /// Print the manual page (roff) of spatch and every subcommand.
    #[command(after_help = "Example:\n  spatch man | man -l -\n  spatch man -o spatch.1")]
    Man(commands::man::ManArgs),
}

impl Command {
    /// The files the run reads and writes, checked before any work
    /// (see [`crate::overwrite_guard`]).
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        match self {
            Command::Convert(args) => args.files(),
            Command::FromCloud(args) => args.files(),
            Command::Plan(args) => args.files(),
            Command::Index(args) => args.files(),
            Command::Sphere(args) => args.files(),
            Command::Stats(args) => args.files(),
            Command::Earth(args) => args.files(),
            Command::Export(args) => args.files(),
            Command::Merge(args) => args.files(),
            Command::Render(args) => args.files(),
            Command::Eval(args) => args.files(),
            Command::View(args) => args.files(),
            Command::Man(args) => args.files(),
            // demo writes its own fresh names into a folder; completions
            // only prints.
            Command::Demo(_) | Command::Completions(_) => Default::default(),
        }
    }
}
