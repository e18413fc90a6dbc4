//! Parse arguments; run a headless command or open the studio. Nothing else.

use clap::Parser;
use udc_studio::cli::{Cli, Command};

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => udc_studio::app::run_studio(None),
        Some(Command::Studio { design }) => udc_studio::app::run_studio(design),
        Some(command) => udc_studio::cli::run(command),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
