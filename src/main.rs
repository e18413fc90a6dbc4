//! Parse arguments; run a headless command or open the studio. Nothing else.

use udc_studio::cli::{CliParseError, Command, parse};

/// Keeps freed grids for the next design instead of returning them to the kernel (see the
/// `mimalloc` line in Cargo.toml).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    let cli = match parse() {
        Ok(c) => c,
        Err(CliParseError::Display(e)) => e.exit(),
        Err(CliParseError::Usage(line)) => {
            eprintln!("error: {line}");
            return std::process::ExitCode::from(2);
        }
    };
    udc_studio::core::budget::set_max_memory_bytes(
        cli.max_memory
            .unwrap_or_else(udc_studio::io::system::default_max_memory_bytes),
    );
    let result = match cli.command {
        None => studio(None),
        Some(Command::Studio { design }) => studio(design),
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

/// Opens the studio window, optionally on a design file.
#[cfg(feature = "gui")]
fn studio(design: Option<std::path::PathBuf>) -> anyhow::Result<()> {
    udc_studio::app::run_studio(design)
}

/// A headless build (`--no-default-features`) has no window to open.
#[cfg(not(feature = "gui"))]
fn studio(_design: Option<std::path::PathBuf>) -> anyhow::Result<()> {
    anyhow::bail!(
        "this udc-studio was built without the studio window (feature `gui`); \
         run a command (see `udc-studio --help`) or build it with default features"
    )
}
