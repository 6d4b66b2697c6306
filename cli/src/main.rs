//! The `spatch` command line: argument parsing, progress and reports.
//! Every algorithm lives in a library crate; this binary only glues them.

mod args;
mod commands;
mod exit_guard;
mod failure;
mod heap;
mod output;
mod overwrite_guard;
mod progress;
mod report;
mod usage_error;

use std::process::ExitCode;

use clap::Parser;

use crate::args::{Cli, Command};
use crate::failure::Failure;

fn run(cli: Cli) -> anyhow::Result<()> {
    progress::set_quiet(cli.quiet);
    cli.command.files().check()?;
    match cli.command {
        Command::Demo(args) => commands::demo::run(&args),
        Command::Convert(args) => commands::convert::run(&args),
        Command::FromCloud(args) => commands::from_cloud::run(&args),
        Command::Plan(args) => commands::plan::run(&args),
        Command::Index(args) => commands::index::run(&args),
        Command::Sphere(args) => commands::sphere::run(&args),
        Command::Stats(args) => commands::stats::run(&args),
        Command::Earth(args) => commands::earth::run(&args),
        Command::Export(args) => commands::export::run(&args),
        Command::Merge(args) => commands::merge::run(&args),
        Command::Render(args) => commands::render::run(&args),
        Command::Eval(args) => commands::eval::run(&args),
        Command::View(args) => commands::view::run(&args),
        Command::Completions(args) => commands::completions::run(&args),
        Command::Man(args) => commands::man::run(&args),
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => return usage_error::report(&err),
    };
    // Before any thread starts: the guard's watcher is one.
    if matches!(cli.command, Command::Render(_) | Command::Eval(_)) {
        heap::pad_heaps();
    }
    exit_guard::install();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            let failure = Failure::classify(&err);
            if failure == Failure::BrokenPipe {
                return ExitCode::SUCCESS;
            }
            eprintln!("spatch: error: {}", failure::one_line(&err));
            failure.exit_code()
        }
    }
}
