//! `udc-studio lesson check FILE...`: validates lesson files as the studio reads them, one
//! line per file; the exit code says whether every file passed.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::{Args, Subcommand};

/// The `lesson` commands.
#[derive(Debug, Subcommand)]
pub enum LessonCommand {
    /// Check lesson files (TOML): the format, every step's fields, the presets they load and
    /// the quantities their questions measure; one line per file, naming the step and the
    /// field of the first problem.
    Check(CheckArgs),
}

/// The files to check.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Lesson files.
    #[arg(required = true, value_name = "FILE")]
    pub files: Vec<PathBuf>,
}

/// Runs a `lesson` command.
///
/// # Errors
/// Any file that fails its check (each already reported on its line).
pub fn lesson_cmd(cmd: &LessonCommand) -> Result<()> {
    match cmd {
        LessonCommand::Check(args) => {
            let mut failed = 0;
            for f in &args.files {
                match udc_io::lesson::read_lesson(f) {
                    Ok(l) => println!(
                        "{}: ok, \"{}\", {} step{}",
                        f.display(),
                        l.title,
                        l.steps.len(),
                        if l.steps.len() == 1 { "" } else { "s" }
                    ),
                    Err(e) => {
                        failed += 1;
                        eprintln!("{}: {e}", f.display());
                    }
                }
            }
            if failed > 0 {
                bail!("{failed} of {} lesson files failed", args.files.len());
            }
            Ok(())
        }
    }
}
