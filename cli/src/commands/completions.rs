//! `spatch completions SHELL`: the shell completion script, on standard
//! output.

use clap::CommandFactory;
use clap_complete::Shell;

use crate::args::Cli;

/// Arguments of `spatch completions`.
#[derive(Debug, clap::Args)]
pub(crate) struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    shell: Shell,
}

/// Prints the completion script for the chosen shell.
pub(crate) fn run(args: &CompletionsArgs) -> anyhow::Result<()> {
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut Cli::command(), "spatch", &mut script);
    crate::output::write_stdout(&script)
}
