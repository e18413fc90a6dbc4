//! Parse arguments; run a headless command or open the studio. Nothing else.

use clap::Parser;
use udc_studio::cli::{Cli, Command};

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => udc_studio::app::run_studio(None),
        Some(Command::Studio { design }) => udc_studio::app::run_studio(design),
        Some(command) => {
            // Ctrl-C or SIGTERM during a long export leaves no `.part` file behind.
            udc_studio::io::safe_file::remove_temp_files_on_signal();
            udc_studio::cli::run(command)
        }
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
