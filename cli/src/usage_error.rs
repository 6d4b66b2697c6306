//! Command-line mistakes (an unknown option, a bad value, a missing
//! argument) reported like every other error: one line
//! `spatch: error: <problem>`, exit code 2.

use std::process::ExitCode;

use clap::error::ErrorKind;

/// Prints a parse error and gives the exit code: help and version go to
/// standard output with 0, as clap prints them; mistakes are one line.
pub(crate) fn report(err: &clap::Error) -> ExitCode {
    match err.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = err.print();
            return ExitCode::SUCCESS;
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = err.print();
            return ExitCode::from(2);
        }
        _ => {}
    }
    eprintln!("spatch: error: {}", one_line(&err.render().to_string()));
    ExitCode::from(2)
}

/// clap's message up to its first blank line (what follows is a tip and the
/// usage), on one line and without its own `error: ` prefix.
fn one_line(text: &str) -> String {
    let message = text.split("\n\n").next().unwrap_or(text);
    let message = message.strip_prefix("error: ").unwrap_or(message);
    message
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::one_line;

    #[test]
    fn clap_messages_become_one_line() {
        let text = "error: the following required arguments were not provided:\n  --output <FILE>\n\nUsage: spatch sphere --output <FILE>\n\nFor more information, try '--help'.\n";
        assert_eq!(
            one_line(text),
            "the following required arguments were not provided: --output <FILE>"
        );
        let text = "error: invalid value 'x' for '--grid <GRID>': invalid digit found in string\n\nFor more information, try '--help'.\n";
        assert_eq!(
            one_line(text),
            "invalid value 'x' for '--grid <GRID>': invalid digit found in string"
        );
    }
}
