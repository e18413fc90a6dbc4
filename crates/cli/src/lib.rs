#![warn(missing_docs)]
//! Headless commands: the command line over the typed jobs of `udc-jobs` (and the commands
//! that are not jobs: export, import, drc, optimize, sweep, reproduce, …), built only on
//! `core`, `io` and `jobs`.

pub mod appearance;
pub mod denoise;
pub mod drc;
mod export_cmd;
pub mod field_depth;
mod progress_bar;
pub mod saturation;
pub use export_cmd::ExportArgs;
pub mod import;
pub mod lesson;
pub mod optimize;
pub mod packaging;
pub mod phase;
pub mod sensor;

mod parse;
pub use parse::{CliParseError, parse};
pub mod reproduce;
pub mod sweep;

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::{Args, Parser, Subcommand};

use udc_io::design::presets;
use udc_jobs::display::{AnalyzeJob, RestoreJob};
use udc_jobs::{JobSpec, evaluate};

pub use udc_io::TOOL_VERSION;
pub use udc_jobs::display::DesignSelection;
pub use udc_jobs::{choice, flags};

/// The command line: an optional headless command and the global options.
#[derive(Debug, Parser)]
#[command(
    name = "udc-studio",
    version = TOOL_VERSION,
    about = "Design studio for under-display cameras"
)]
pub struct Cli {
    /// The command to run; `None` opens the studio.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Memory budget: jobs estimated to need more are refused before they start (e.g. 2G,
    /// 512M). Default: the smallest of half the physical memory, the process's cgroup limit
    /// (a container's, a Slurm job's `--mem`) and 60 % of what the process can still map under
    /// `RLIMIT_AS` (`ulimit -v`, `prlimit --as`; measured at start), or `RLIMIT_DATA`.
    #[arg(long, global = true, value_name = "SIZE", value_parser = udc_core::budget::parse_size)]
    pub max_memory: Option<u64>,
}

/// `udc-studio presets`.
#[derive(Debug, clap::Args)]
pub struct PresetsArgs {
    /// Print one JSON object, `{"presets": [{"name", "group", "description"}]}` (`group`:
    /// `thesis` or `fourier-optics`), the stable form for scripts.
    #[arg(long)]
    pub json: bool,
}

/// A command of `udc-studio`: the studio or one of the headless commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Open the studio (the default when no command is given).
    Studio {
        /// A design file to open instead of the last session's design.
        design: Option<PathBuf>,
    },
    /// Analyse a design: PSF, MTF, AUC, LTR and invertibility per channel.
    Analyze(JobArgs<AnalyzeJob>),
    /// Lessons for teaching Fourier optics in the studio: `lesson check FILE...` validates
    /// lesson files.
    #[command(subcommand)]
    Lesson(lesson::LessonCommand),
    /// Save a display view as a figure (SVG or PNG at a chosen size) with its axes, units,
    /// colour bar, legend and a caption naming the design: the studio's Save figure, from a
    /// script.
    Figure(JobArgs<udc_jobs::display::FigureJob>),
    /// List the built-in presets with one-line descriptions: a listing for people, grouped
    /// under headings that may change; scripts use `--json`.
    Presets(PresetsArgs),
    /// Write a photolithography mask of the design: GDSII, OASIS, DXF, SVG or PNG.
    Export(ExportArgs),
    /// Check a display mask against a fab's design rules: smallest opening and gap, corner
    /// contacts, acute angles.
    Drc(drc::DrcArgs),
    /// Read a mask (GDSII, DXF or PNG) back into a design file: its pixel on the optical axis.
    Import(import::ImportArgs),
    /// Capture a photo through the display (blur, photon and read noise) and restore it; prints
    /// PSNR and SSIM per run (thesis §3.5).
    Restore(JobArgs<RestoreJob>),
    /// Denoise an image with BM3D (grey) or CBM3D (colour) at a known noise variance σ² on the
    /// [0, 1] scale; writes the same kind of file (PNG, TIFF or EXR) and, with `--reference`,
    /// prints the PSNR before and after.
    Denoise(denoise::DenoiseArgs),
    /// Optimize the opening of one display pixel (thesis §3.4.2) and save the new design.
    Optimize(optimize::OptimizeArgs),
    /// Measured PSFs: `psf import` merges a prototype's frames (a bracket of exposures, dark
    /// frames) into a PSF set (.npy with a .json sidecar); `psf compare` sets it beside the
    /// design.
    #[command(subcommand)]
    Psf(PsfCommand),
    /// Simulate spatially-varying gain and binning on an HDR scene (thesis chapter 5): the four
    /// strategies of Table 5.4 with worst-ROI SSIM, PSNR and saturation; `sensor flat-patch`
    /// checks eq. 5.3's η on a flat patch.
    Sensor(sensor::SensorArgs),
    /// Phase masks (thesis chapter 4): double microlens arrays around a T-OLED, folded plates
    /// and the allocation of folding wavelengths.
    #[command(subcommand)]
    Phase(phase::PhaseCommand),
    /// PSFs over the field of view through a display in front of the lens, and their residual
    /// after deblurring with the centre PSF (thesis §3.7, Fig. 3.29).
    Field(field_depth::FieldArgs),
    /// PSFs of a point at a finite depth, focused on it and focused at infinity, and their
    /// residual after deblurring with the infinity PSF (thesis §3.7, Fig. 3.31).
    Depth(field_depth::DepthArgs),
    /// A capture that clips specular highlights against an exposure-bracketed HDR capture, both
    /// restored by Wiener deconvolution (thesis §3.7, Fig. 3.30).
    Saturation(saturation::SaturationArgs),
    /// Show an image on the design's layout as the eye sees it (subpixels, DPI, viewing
    /// distance) with display-quality numbers beside the camera's AUC (thesis §3.7).
    Appearance(appearance::AppearanceArgs),
    /// Run a sweep of many designs in-process (`sweep SPEC --out DIR`), merge shard folders
    /// (`sweep merge`), or write Slurm scripts for a cluster (`sweep slurm`).
    Sweep(sweep::SweepArgs),
    /// Reproduce a thesis result in one command (`reproduce --list` names them): its sweep
    /// specs in presets/reproduce/ run in-process, then report.md, results.csv and plots with
    /// the thesis's numbers beside ours and its claims checked (`--quick`: ≈ 2 min each).
    Reproduce(reproduce::ReproduceArgs),
    /// Print the shell completion script for bash, zsh or fish to stdout.
    ///
    /// Install it where the shell looks for completions (the package installs them already),
    /// then open a new shell:
    ///
    /// bash: `udc-studio completions bash > ~/.local/share/bash-completion/completions/udc-studio`
    ///
    /// zsh: `udc-studio completions zsh > ~/.zfunc/_udc-studio`, with `fpath+=~/.zfunc` before
    /// `compinit` in ~/.zshrc
    ///
    /// fish: `udc-studio completions fish > ~/.config/fish/completions/udc-studio.fish`
    Completions(packaging::CompletionsArgs),
    /// Write the man pages (packaging): `udc-studio.1` and one page per subcommand,
    /// `udc-studio-phase-psf.1`, into a directory.
    #[command(hide = true)]
    Manpages(packaging::ManpagesArgs),
}

/// The `psf` commands.
#[derive(Debug, Subcommand)]
pub enum PsfCommand {
    /// Merge a measured PSF's frames into a PSF set: dark subtraction, hot pixels, saturation
    /// masks, an HDR merge weighted by exposure, background, sub-pixel centring, crop and
    /// normalisation, each reported (and each with a `--no-…` switch).
    Import(JobArgs<udc_jobs::measured::ImportJob>),
    /// Compare a measured PSF set with a design simulated at its pixel pitch: each channel
    /// aligned to a sub-pixel, the residual, both MTFs and their AUC; figures with `--out`.
    Compare(JobArgs<udc_jobs::measured::CompareJob>),
    /// Fit the display to a measured PSF set, starting from a design: the pitch, the open
    /// fraction (the openings' edges moved out or in), the display's turn and the lens's
    /// defocus, each with its uncertainty; the fitted design with `--out`.
    Fit(JobArgs<udc_jobs::measured::FitJob>),
}

/// A job's command line: its parameters (the job's own struct) and how to print its result.
#[derive(Debug, Args)]
pub struct JobArgs<J: Args> {
    /// The job's parameters.
    #[command(flatten)]
    pub job: J,
    /// Print one JSON object to stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// Prints a command's `--json` object with the build that made it (`tool_version`).
///
/// # Errors
/// When the object cannot be serialised.
pub(crate) fn emit_json(v: &serde_json::Value) -> Result<()> {
    println!(
        "{}",
        serde_json::to_string(&udc_jobs::with_tool_version(v.clone()))?
    );
    Ok(())
}

/// Evaluates a job with a progress bar on a terminal, then prints its JSON object or its table.
///
/// # Errors
/// The job's own error.
pub(crate) fn run_job(job: JobSpec, json: bool, progress: &udc_core::Progress) -> Result<()> {
    let report = progress_bar::with_bar(progress, true, job.kind().as_str(), || {
        evaluate(&job, progress)
    })?;
    if json {
        emit_json(&report.json)
    } else {
        print!("{}", report.text);
        Ok(())
    }
}

/// Runs a headless command.
///
/// # Errors
/// Any failure, as one message for stderr.
pub fn run(command: Command) -> Result<()> {
    run_with(command, &udc_core::Progress::new())
}

/// Runs a headless command whose long steps report to and are cancelled by `progress`.
///
/// # Errors
/// Any failure, as one message for stderr; `progress` cancelled stops the command at its next
/// check.
pub fn run_with(command: Command, progress: &udc_core::Progress) -> Result<()> {
    run_command(command, progress).map_err(udc_jobs::flags::name_flags)
}

fn run_command(command: Command, progress: &udc_core::Progress) -> Result<()> {
    match command {
        Command::Presets(args) => {
            let list = presets::list();
            if args.json {
                let rows: Vec<_> = list
                    .iter()
                    .map(|(name, group, description)| {
                        serde_json::json!({"name": name, "group": group, "description": description})
                    })
                    .collect();
                return emit_json(&serde_json::json!({ "presets": rows }));
            }
            for group in presets::PresetGroup::ALL {
                println!("{}:", group.label());
                for (name, _, desc) in list.iter().filter(|p| p.1 == group) {
                    println!("  {name:<20} {desc}");
                }
            }
            Ok(())
        }
        Command::Analyze(args) => run_job(JobSpec::Analyze(args.job), args.json, progress),
        Command::Figure(args) => {
            let report = udc_jobs::display::figure(&args.job, progress)?;
            if args.json {
                emit_json(&report.json)
            } else {
                print!("{}", report.text);
                Ok(())
            }
        }
        Command::Lesson(cmd) => lesson::lesson_cmd(&cmd),
        Command::Export(args) => export_cmd::export_cmd(&args),
        Command::Drc(args) => drc::drc_cmd(&args),
        Command::Import(args) => import::import_cmd(&args),
        Command::Restore(args) => run_job(JobSpec::Restore(args.job), args.json, progress),
        Command::Denoise(args) => denoise::denoise_cmd(&args),
        Command::Optimize(args) => optimize::optimize_cmd(&args),
        Command::Psf(cmd) => {
            let (report, json) = match cmd {
                PsfCommand::Import(args) => {
                    (udc_jobs::measured::import(&args.job, progress)?, args.json)
                }
                PsfCommand::Compare(args) => {
                    (udc_jobs::measured::compare(&args.job, progress)?, args.json)
                }
                PsfCommand::Fit(args) => (udc_jobs::measured::fit(&args.job, progress)?, args.json),
            };
            if json {
                emit_json(&report.json)
            } else {
                print!("{}", report.text);
                Ok(())
            }
        }
        Command::Sensor(args) => sensor::sensor_cmd(args, progress),
        Command::Phase(cmd) => phase::phase_cmd(cmd, progress),
        Command::Field(args) => field_depth::field_cmd(&args),
        Command::Depth(args) => field_depth::depth_cmd(&args),
        Command::Saturation(args) => saturation::saturation_cmd(&args),
        Command::Appearance(args) => appearance::appearance_cmd(&args),
        Command::Sweep(args) => sweep::sweep_cmd(&args),
        Command::Reproduce(args) => reproduce::reproduce_cmd(&args),
        Command::Completions(args) => packaging::completions_cmd(&args),
        Command::Manpages(args) => packaging::manpages_cmd(&args),
        Command::Studio { .. } => bail!("the studio is not a headless command"),
    }
}
