#![warn(missing_docs)]
//! Headless commands, built only on `core` and `io`.

pub mod analysis_cache;
pub mod appearance;
mod choice;
pub mod denoise;
pub mod denoise_flags;
pub mod drc;
mod export_cmd;
pub mod field_depth;
pub mod flags;
pub mod saturation;
pub use export_cmd::ExportArgs;
pub mod import;
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

use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with};
use udc_core::design::{Design, OpticsRecipe, TilingMode};
use udc_core::{Analysis, Progress};
use udc_io::design::presets;
use udc_io::display::{export, report};

pub use udc_io::TOOL_VERSION;

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
    /// (a container's, a Slurm job's `--mem`) and 60 % of what `RLIMIT_AS` leaves (`ulimit -v`,
    /// `prlimit --as`), or `RLIMIT_DATA`.
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
    Analyze(AnalyzeArgs),
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
    Restore(RestoreArgs),
    /// Denoise an image with BM3D (grey) or CBM3D (colour) at a known noise variance σ² on the
    /// [0, 1] scale; writes the same kind of file (PNG, TIFF or EXR) and, with `--reference`,
    /// prints the PSNR before and after.
    Denoise(denoise::DenoiseArgs),
    /// Optimize the opening of one display pixel (thesis §3.4.2) and save the new design.
    Optimize(optimize::OptimizeArgs),
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

/// How a command picks its design: a file, or a preset, then overrides.
#[derive(Debug, Args)]
pub struct DesignSelection {
    /// Design file (JSON). Without it, `--preset` or the default T-OLED preset is used.
    pub design: Option<PathBuf>,
    /// Built-in preset name (see `udc-studio presets`).
    #[arg(long, conflicts_with = "design")]
    pub preset: Option<String>,
    /// PNG opening that replaces the design's (grey > 127 = open; one pixel = one cell).
    #[arg(long)]
    pub pattern: Option<PathBuf>,
    /// Display pixel pitch in µm.
    #[arg(long)]
    pub pitch_um: Option<f64>,
    /// Tiling: repeat, random-d4 or random-4.
    #[arg(long)]
    pub tiling: Option<TilingMode>,
    /// Seed of the random tiling.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Optics recipe: iccp21 (the thesis) or phone.
    #[arg(long, value_parser = crate::choice::choice_of(&OpticsRecipe::NAMED))]
    pub optics: Option<OpticsRecipe>,
    /// Spectral response CSV (wavelength_nm, r, g, b): channels become weighted sums of
    /// wavelengths sampled every `--spectral-step-nm`.
    #[arg(long)]
    pub spectral: Option<PathBuf>,
    /// Wavelength step for `--spectral`, in nm.
    #[arg(long, default_value_t = 30.0, requires = "spectral")]
    pub spectral_step_nm: f64,
}

/// Arguments of `udc-studio analyze`.
#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    /// The design to analyse.
    #[command(flatten)]
    pub selection: DesignSelection,
    /// Print one JSON object to stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write the PSFs (EXR, 16-bit PNG), log-PSFs (PNG) and mtf.csv into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Interactive preview quality: twice the fine PSF spacing where the f-number oversamples
    /// the PSF enough for the AUC to stay within 3 % (about 4× faster), full quality otherwise
    /// (the thesis recipe at f/2.5).
    #[arg(long)]
    pub preview: bool,
    /// Also look for a fix for each note (a documented property of the thesis recipe), not
    /// only for each warning; every fix is checked by a further analysis.
    #[arg(long)]
    pub advice: bool,
}

impl DesignSelection {
    /// The files this selection reads (design, pattern, spectral response).
    pub fn input_files(&self) -> Vec<&std::path::Path> {
        [&self.design, &self.pattern, &self.spectral]
            .into_iter()
            .flatten()
            .map(PathBuf::as_path)
            .collect()
    }

    /// Resolves the selection into a validated design.
    ///
    /// # Errors
    /// Unreadable or invalid files, unknown presets or recipes, bad override values.
    pub fn resolve(&self) -> Result<Design> {
        // A core error stays one, so `name_flags` can name the flag behind its field.
        self.choice().resolve().map_err(|e| match e {
            udc_io::error::IoError::Invalid(sim) => anyhow::Error::from(sim),
            other => other.into(),
        })
    }

    /// The selection as the io layer's [`DesignChoice`](udc_io::design::choice::DesignChoice).
    pub fn choice(&self) -> udc_io::design::choice::DesignChoice {
        udc_io::design::choice::DesignChoice {
            design: self.design.clone(),
            preset: self.preset.clone(),
            pattern: self.pattern.clone(),
            pitch_um: self.pitch_um,
            tiling: self.tiling,
            seed: self.seed,
            optics: self.optics,
            spectral: self.spectral.clone(),
            spectral_step_nm: self.spectral_step_nm,
        }
    }
}

thread_local! {
    /// Where a command's `--json` output goes when a sweep runs it in-process: the sweep's
    /// point, not stdout.
    static JSON_SINK: std::cell::RefCell<Option<Option<serde_json::Value>>> =
        const { std::cell::RefCell::new(None) };
}

/// Prints a command's `--json` object, or hands it to the sweep running the command.
///
/// # Errors
/// When the object cannot be serialised.
pub(crate) fn emit_json(v: &serde_json::Value) -> Result<()> {
    let captured = JSON_SINK.with(|s| {
        let mut slot = s.borrow_mut();
        match slot.as_mut() {
            Some(out) => {
                *out = Some(v.clone());
                true
            }
            None => false,
        }
    });
    if !captured {
        // Printed objects name the build that made them; a sweep's captured ones do not (its
        // rows carry `tool_version` in their own column).
        let mut v = v.clone();
        if let Some(obj) = v.as_object_mut() {
            obj.entry("tool_version")
                .or_insert_with(|| TOOL_VERSION.into());
        }
        println!("{}", serde_json::to_string(&v)?);
    }
    Ok(())
}

/// Whether a sweep is running the current command (progress reports stay quiet).
pub(crate) fn in_sweep() -> bool {
    JSON_SINK.with(|s| s.borrow().is_some())
}

/// Runs a command on this thread and returns the object its `--json` output would print.
///
/// # Errors
/// The command's error, or a command that printed no object.
pub(crate) fn capture_json(run: impl FnOnce() -> Result<()>) -> Result<serde_json::Value> {
    JSON_SINK.with(|s| *s.borrow_mut() = Some(None));
    let result = run();
    let value = JSON_SINK.with(|s| s.borrow_mut().take()).flatten();
    result?;
    value.ok_or_else(|| anyhow::anyhow!("the command printed no JSON"))
}

/// Runs one headless command given as its words (`["phase", "psf", "--mask", "double-mla"]`),
/// as `udc-studio WORDS --json` would, and returns the object it prints. The Python package's
/// `phase` and `sensor` calls go through here, so they take the command's parameters, give its
/// messages and return its JSON.
///
/// # Errors
/// A usage error (one line, as the command line prints it), or the command's own error.
pub fn run_json(words: &[String], progress: &udc_core::Progress) -> Result<serde_json::Value> {
    let argv: Vec<String> = std::iter::once("udc-studio".to_string())
        .chain(words.iter().cloned())
        .chain(std::iter::once("--json".to_string()))
        .collect();
    let cli = parse::parse_from(&argv).map_err(|e| match e {
        parse::CliParseError::Display(help) => anyhow::anyhow!("{help}"),
        parse::CliParseError::Usage(line) => anyhow::anyhow!(line),
    })?;
    match cli.command {
        Some(Command::Studio { .. }) | None => bail!("the studio is not a headless command"),
        Some(command) => capture_json(|| run_with(command, progress)),
    }
}

/// Runs a headless command.
///
/// # Errors
/// Any failure, as one message for stderr.
pub fn run(command: Command) -> Result<()> {
    run_with(command, &udc_core::Progress::new())
}

/// Runs a headless command whose long steps report to and are cancelled by `progress` (a
/// sweep's point, a Python call).
///
/// # Errors
/// Any failure, as one message for stderr; `progress` cancelled stops the command at its next
/// check.
pub fn run_with(command: Command, progress: &udc_core::Progress) -> Result<()> {
    run_command(command, progress).map_err(flags::name_flags)
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
        Command::Analyze(args) => analyze_cmd(&args),
        Command::Export(args) => export_cmd::export_cmd(&args),
        Command::Drc(args) => drc::drc_cmd(&args),
        Command::Import(args) => import::import_cmd(&args),
        Command::Restore(args) => restore_cmd(&args, progress),
        Command::Denoise(args) => denoise::denoise_cmd(&args),
        Command::Optimize(args) => optimize::optimize_cmd(&args),
        Command::Sensor(args) => sensor::sensor_cmd(&args, progress),
        Command::Phase(cmd) => phase::phase_cmd(&cmd, progress),
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

fn analyze_cmd(args: &AnalyzeArgs) -> Result<()> {
    use udc_core::analysis::advice::AdviceScope;

    let design = args.selection.resolve()?;
    let options = AnalyzeOptions {
        quality: if args.preview {
            Quality::Preview
        } else {
            Quality::Full
        },
        expected_psf: args.out.is_some(),
    };
    let progress = Progress::new();
    let mut analysis = analyze_with(&design, &options, &progress)?;
    // A fix is checked by a further analysis: the CLI pays for it where the numbers are off
    // (warnings), and for the notes only when asked.
    let scope = if args.advice {
        AdviceScope::All
    } else {
        AdviceScope::Warnings
    };
    udc_core::analysis::advice::advise_in(&design, &mut analysis.warnings, scope, &progress)?;
    if let Some(dir) = &args.out {
        export::write_analysis_outputs(dir, &analysis)?;
    }
    if args.json {
        emit_json(&report::analysis_json(&analysis))?;
    } else {
        print_table(&design, &analysis);
    }
    Ok(())
}

fn print_table(design: &Design, a: &Analysis) {
    println!(
        "{}: {} cells of {:.2} µm, pitch {:.1} µm ({:.0} DPI), tiling {}",
        if design.name.is_empty() {
            "design"
        } else {
            &design.name
        },
        design.opening.n(),
        design.opening.cell_um(),
        design.opening.pitch_um,
        design.opening.dpi(),
        design.tiling.mode.as_str()
    );
    println!(
        "open fraction {:.4}   LTR {:.4}   L_inv {:.4}   {:.1} ms",
        a.open_fraction, a.ltr, a.invertibility_loss, a.elapsed_ms
    );
    println!("channel  λ (nm)   FFT    AUC(min)  AUC/0.5   AUC(mean)  in window");
    for c in &a.channels {
        println!(
            "{:<8} {:>6.1}  {:>5}   {:.5}   {:.5}   {:.5}    {:.4}",
            c.name,
            c.wavelength_nm,
            c.fft_sizes.first().copied().unwrap_or(0),
            c.mtf.auc_radial_min,
            c.mtf.auc_normalised(),
            c.mtf.auc_radial_mean,
            c.energy_in_window
        );
    }
    for w in &a.warnings {
        println!("{}: {w}", w.severity.as_str());
        if let Some(fix) = &w.fix {
            println!("  advice: set {} ({})", fix.assignments(), fix.summary());
        }
    }
}

/// The restoration algorithm of `restore`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RestoreMethod {
    /// Wiener deconvolution with `--nsr` (the thesis).
    Wiener,
    /// Gradient-regularised least squares by conjugate gradients (`--lambda`, `--iterations`).
    Cg,
}

/// Arguments of `udc-studio restore`; at least one `--light` or `--snr-db` is required.
#[derive(Debug, Args)]
#[command(group(
    clap::ArgGroup::new("light_level").required(true).args(["light", "snr_db"])
))]
pub struct RestoreArgs {
    /// The display design the photo is captured through.
    #[command(flatten)]
    pub selection: DesignSelection,
    /// The photo (PNG, JPEG, TIFF, HDR or EXR), read as linear intensities in [0, 1].
    #[arg(long)]
    pub image: PathBuf,
    /// Electrons at a pixel of value 1 behind the reference display (T-OLED 150 DPI); give it
    /// several times for several runs.
    #[arg(long, value_name = "E")]
    pub light: Vec<f64>,
    /// The same light level as an SNR in dB (24/28/32/36/40 ↔ 273/654/1608/4005/10024 e⁻); give
    /// it several times for several runs.
    #[arg(long, value_name = "S")]
    pub snr_db: Vec<f64>,
    /// Restoration method.
    #[arg(long, value_enum, default_value = "wiener")]
    pub method: RestoreMethod,
    /// Noise-to-signal ratio of the Wiener filter.
    #[arg(long, default_value_t = udc_core::restore::THESIS_NSR)]
    pub nsr: f64,
    /// Weight of the gradient penalty of `--method cg`.
    #[arg(long, default_value_t = udc_core::restore::CgSettings::default().lambda)]
    pub lambda: f64,
    /// Iterations of `--method cg`.
    #[arg(long, default_value_t = udc_core::restore::CgSettings::default().iterations)]
    pub iterations: usize,
    /// Seed of the photon and read noise (`--seed` is the tiling's, as in `analyze`).
    #[arg(long, default_value_t = 0)]
    pub noise_seed: u64,
    /// ADC bits over the full well (default: whole electrons, no ADC).
    #[arg(long)]
    pub adc_bits: Option<u32>,
    /// Scale the photo down so its longer side has at most this many pixels.
    #[arg(long)]
    pub max_side_px: Option<u32>,
    /// Wiener on the smallest linear FFT grid instead of conventions.md §5's 2× zero padding
    /// (faster; changes only the borders). Conjugate gradients always use it: their result does
    /// not depend on the padding.
    #[arg(long)]
    pub pad_linear: bool,
    /// The denoiser before the deblurring (`--denoise`, `--denoise-sigma2`).
    #[command(flatten)]
    pub denoise: denoise_flags::DenoiseFlags,
    /// Print one JSON object to stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write captured, denoised, restored and difference PNGs (and float EXRs) per run into
    /// this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

fn restore_cmd(args: &RestoreArgs, progress: &udc_core::Progress) -> Result<()> {
    use udc_core::restore::capture::REFERENCE_LTR;
    use udc_core::restore::{
        CaptureSettings, CgSettings, Light, Method, Padding, RestoreSettings, simulate_with,
    };
    use udc_io::display::restore_report;
    use udc_io::photo;

    let design = args.selection.resolve()?;
    // f32 planes: a 16-megapixel photo's stages then fit in well under a gigabyte.
    let photo = photo::load_photo::<f32>(&args.image, args.max_side_px)?;
    // The display openings are chapter 3's: its σ² table.
    let denoise = args.denoise.resolve(udc_core::restore::Recipe::Iccp21)?;
    let method = match args.method {
        RestoreMethod::Wiener => Method::Wiener { nsr: args.nsr },
        RestoreMethod::Cg => Method::Cg(CgSettings {
            lambda: args.lambda,
            iterations: args.iterations,
            ..CgSettings::default()
        }),
    };
    let lights: Vec<(Light, String)> = args
        .light
        .iter()
        .map(|e| (Light::ElectronsAtPeak(*e), format!("light-{e}e")))
        .chain(
            args.snr_db
                .iter()
                .map(|s| (Light::SnrDb(*s), format!("snr-{s}db"))),
        )
        .collect();
    let settings_for = |light: Light, ltr_relative: f64| RestoreSettings {
        capture: CaptureSettings {
            light,
            adc_bits: args.adc_bits,
            ltr_relative,
            seed: args.noise_seed,
            ..CaptureSettings::default()
        },
        method,
        padding: if args.pad_linear || args.method == RestoreMethod::Cg {
            Padding::Linear
        } else {
            Padding::Double
        },
        denoise,
    };
    // Every light level and the photo are checked before the analysis, which is the slow part.
    for (light, _) in &lights {
        udc_core::restore::check(&photo, &settings_for(*light, 1.0))?;
    }
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    // Shared with the sweep's other points on this design (every light level and photo).
    let analysis = analysis_cache::analyze_shared(&design, &options)?;
    let psfs: Vec<&ndarray::Array2<f64>> = analysis.channels.iter().map(|c| &c.psf).collect();
    let names: Vec<String> = analysis.channels.iter().map(|c| c.name.clone()).collect();
    if photo.len() != psfs.len() {
        bail!(
            "the design has {} channels but a photo has 3 (R, G, B); restore needs an RGB design",
            psfs.len()
        );
    }
    let ltr_relative = analysis.ltr / REFERENCE_LTR;
    let (rows, cols) = photo.first().map_or((0, 0), ndarray::Array2::dim);
    // Light the window drops is not physical: said in one line, with the fix (conventions §5).
    let light_warning = udc_core::analysis::light::capture_light_warning(&analysis);
    if !args.json {
        println!(
            "{}: LTR {:.4} ({:.3}× the reference T-OLED's {REFERENCE_LTR:.4}); photo {} ({cols}×{rows})",
            if design.name.is_empty() {
                "design"
            } else {
                &design.name
            },
            analysis.ltr,
            ltr_relative,
            args.image.display(),
        );
        for w in &analysis.warnings {
            println!("{}: {w}", w.severity.as_str());
        }
        if let Some(w) = &light_warning {
            println!("warning: {w}");
        }
        println!(
            "light (e⁻)  SNR (dB)  PSNR (dB)  SSIM     capture PSNR  denoised PSNR  per channel \
             PSNR / SSIM"
        );
    }
    let mut runs = Vec::new();
    for (light, stem) in lights {
        let settings = settings_for(light, ltr_relative);
        // The capture and the denoised capture are written the moment they are done, and let go.
        let mut outputs = Vec::new();
        let result = simulate_with(
            &photo,
            &psfs,
            &settings,
            progress,
            |stage, planes| -> Result<()> {
                if let Some(dir) = &args.out {
                    outputs.extend(restore_report::write_stage_images(
                        dir, &stem, stage, planes,
                    )?);
                }
                Ok(())
            },
        )?;
        if let Some(dir) = &args.out {
            outputs.extend(restore_report::write_restored_images(
                dir,
                &stem,
                &photo,
                &result.restored,
            )?);
        }
        if args.json {
            runs.push(restore_report::run_json(&result, &names, &outputs));
        } else {
            let per: Vec<String> = names
                .iter()
                .zip(&result.channels)
                .map(|(n, c)| format!("{n} {:.2}/{:.4}", c.psnr_db, c.ssim))
                .collect();
            let denoised = result
                .denoised_psnr_db
                .map_or_else(|| "-".to_string(), |p| format!("{p:.2}"));
            println!(
                "{:>10.0}  {:>8.2}  {:>9.2}  {:.4}   {:>10.2}    {denoised:>11}    {}    ({})",
                result.light_e,
                result.snr_db,
                result.psnr_db,
                result.ssim,
                result.captured_psnr_db,
                per.join("  "),
                denoise_flags::denoise_text(&result.denoise)
            );
            let saturated = result
                .channels
                .iter()
                .map(|c| c.saturated_fraction)
                .fold(0.0, f64::max);
            if saturated > 0.0 {
                println!(
                    "warning: {:.2} % of the pixels reached the full well",
                    100.0 * saturated
                );
            }
            for p in &outputs {
                println!("wrote {}", p.display());
            }
        }
    }
    if args.json {
        let method_json = match method {
            Method::Wiener { nsr } => serde_json::json!({ "name": "wiener", "nsr": nsr }),
            Method::Cg(cg) => serde_json::json!({
                "name": "cg", "lambda": cg.lambda, "iterations": cg.iterations,
                "tolerance": cg.tolerance
            }),
        };
        // The share of each channel's light its PSF window holds (conventions §5).
        let held: Vec<f64> = analysis
            .channels
            .iter()
            .map(|c| udc_io::numbers::round_sig(c.energy_in_window, 9))
            .collect();
        let warnings: Vec<&str> = udc_io::display::report::warning_messages(&analysis.warnings)
            .into_iter()
            .chain(light_warning.as_deref())
            .collect();
        let out = serde_json::json!({
            "design": design.name,
            "image": args.image.display().to_string(),
            "image_size_px": [cols, rows],
            "ltr": analysis.ltr,
            "ltr_relative": ltr_relative,
            "method": method_json,
            "denoise": {"method": denoise.method_name()},
            "noise_seed": args.noise_seed,
            "energy_in_window": held,
            "energy_in_window_min": held.iter().copied().fold(f64::INFINITY, f64::min),
            "psf_share_in_frame_min": udc_io::numbers::round_sig(
                udc_core::restore::light::least_share_in_frame(&psfs, (rows, cols)),
                9
            ),
            "auc_radial_min_mean": udc_io::numbers::round_sig(
                analysis.channels.iter().map(|c| c.mtf.auc_radial_min).sum::<f64>()
                    / analysis.channels.len().max(1) as f64,
                9
            ),
            "warnings": warnings,
            "runs": runs,
        });
        emit_json(&out)?;
    } else if args.out.is_some() {
        println!(
            "difference images show |restored − truth| × {}",
            photo::DIFFERENCE_GAIN
        );
    }
    Ok(())
}
