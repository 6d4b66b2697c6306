//! `spatch man`: the manual page (roff), on standard output or into a
//! file; one page covers every subcommand.

use std::path::PathBuf;

use clap::CommandFactory;

use crate::args::Cli;

/// Arguments of `spatch man`.
#[derive(Debug, clap::Args)]
pub(crate) struct ManArgs {
    /// Write the page to FILE (e.g. spatch.1) instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
}

/// Renders the manual page: the top-level page, then each subcommand's.
pub(crate) fn run(args: &ManArgs) -> anyhow::Result<()> {
    let command = Cli::command();
    let mut page = Vec::new();
    clap_mangen::Man::new(command.clone()).render(&mut page)?;
    for sub in command.get_subcommands().filter(|s| !s.is_hide_set()) {
        let sub = sub
            .clone()
            .display_name(format!("spatch-{}", sub.get_name()))
            .bin_name(format!("spatch {}", sub.get_name()));
        clap_mangen::Man::new(sub).render(&mut page)?;
    }
    match &args.output {
        Some(path) => crate::output::write_output(path, &page),
        None => crate::output::write_stdout(&page),
    }
}

impl ManArgs {
    /// The files this run writes.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        crate::overwrite_guard::Files::default().output(self.output.as_deref())
    }
}
