//! One module per subcommand: arguments → library options → library call →
//! report.

pub(crate) mod cloud_progress;
pub(crate) mod cloud_scanners;
pub(crate) mod completions;
pub(crate) mod convert;
pub(crate) mod convert_plan;
pub(crate) mod demo;
pub(crate) mod earth;
pub(crate) mod eval;
pub(crate) mod eval_args;
pub(crate) mod export;
pub(crate) mod frame_bench;
pub(crate) mod from_cloud;
pub(crate) mod index;
pub(crate) mod man;
pub(crate) mod merge;
pub(crate) mod pipeline_args;
pub(crate) mod plan;
pub(crate) mod render;
pub(crate) mod render_output;
pub(crate) mod render_values;
pub(crate) mod sphere;
pub(crate) mod stats;
pub(crate) mod tiled;
pub(crate) mod tiled_scene;
pub(crate) mod view;

use spatch_format::Compression;

/// The container compression for a `--compress` flag.
pub(crate) fn compression(compress: bool) -> Compression {
    if compress {
        Compression::Predictive
    } else {
        Compression::None
    }
}

/// `--threads N`, the same on every command that does work.
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub(crate) struct ThreadsArg {
    /// Worker threads, 0..=1024 (0 = all cores) [default: all cores]. The output does not
    /// depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=1024))]
    pub(crate) threads: Option<u32>,
}

impl ThreadsArg {
    /// The thread count asked for, 0 meaning all cores.
    pub(crate) fn count(self) -> usize {
        self.threads.map_or(0, |n| n as usize)
    }

    /// Sets up the worker threads of the parallel stages (once per process; 0
    /// or no flag: one per core).
    pub(crate) fn init(self) -> anyhow::Result<()> {
        if let Some(n) = self.threads {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n as usize)
                .build_global()
                .map_err(|e| {
                    crate::failure::InternalFailure(format!("cannot start {n} worker threads: {e}"))
                })?;
        }
        Ok(())
    }
}
