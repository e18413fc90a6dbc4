//! The command line into a [`Cli`]: negative numbers are values, usage errors one line.

use super::Cli;

/// Every command, and every subcommand below it, takes negative numbers as values.
fn negative_numbers(cmd: clap::Command) -> clap::Command {
    cmd.allow_negative_numbers(true)
        .mut_subcommands(negative_numbers)
}

/// The command tree the command line is parsed with, and that `completions` and `manpages`
/// describe.
pub(crate) fn command() -> clap::Command {
    use clap::CommandFactory;
    negative_numbers(Cli::command())
}

/// Parses the command line. Negative numbers are values, so `--snr-db -1000` reaches the check
/// that says what is wrong with it; a usage error is one line (`--help` prints the rest).
///
/// # Errors
/// Help and version requests as clap's own "errors" (print them and exit 0); anything else as
/// one line for stderr.
pub fn parse() -> Result<Cli, CliParseError> {
    use clap::FromArgMatches;
    let matches = command().try_get_matches().map_err(CliParseError::from)?;
    Cli::from_arg_matches(&matches).map_err(CliParseError::from)
}

/// What [`parse`] refuses.
pub enum CliParseError {
    /// `--help` or `--version`: clap prints it.
    Display(clap::Error),
    /// A usage error in one line, without "error: ".
    Usage(String),
}

impl From<clap::Error> for CliParseError {
    fn from(e: clap::Error) -> Self {
        use clap::error::ErrorKind;
        match e.kind() {
            ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => CliParseError::Display(e),
            _ => {
                // clap's message is a headline, then indented details (the missing arguments,
                // the possible values, tips), then a usage block: keep the headline and the
                // details that say what is allowed, on one line.
                let text = e.render().to_string();
                let mut lines = text.lines().filter(|l| !l.trim().is_empty());
                let mut first = lines
                    .next()
                    .unwrap_or("invalid arguments")
                    .trim_start_matches("error: ")
                    .to_string();
                let details: Vec<&str> = lines
                    .take_while(|l| l.starts_with(' '))
                    .map(str::trim)
                    .filter(|l| !l.starts_with("tip:"))
                    .collect();
                if !details.is_empty() {
                    first = format!("{first} {}", details.join(", "));
                }
                CliParseError::Usage(format!("{first} (see --help)"))
            }
        }
    }
}
