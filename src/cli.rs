//! Headless commands, built only on `core` and `io`.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand};

use crate::core::analyze::{AnalyzeOptions, Quality, analyze_with};
use crate::core::design::{Design, Optics, TilingMode};
use crate::core::mask::{MaskRegion, MaskSpec, Tone};
use crate::core::{Analysis, Progress};
use crate::io::mask::{ExportOptions, GdsCells, MaskFormat, PngBits, export_mask};
use crate::io::{design_file, export, pattern, presets, report, spectral};

#[derive(Debug, Parser)]
#[command(
    name = "udc-studio",
    version,
    about = "Design studio for under-display cameras"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Open the studio (the default when no command is given).
    Studio {
        /// A design file to open instead of the last session's design.
        design: Option<PathBuf>,
    },
    /// Analyse a design: PSF, MTF, AUC, LTR and invertibility per channel.
    Analyze(AnalyzeArgs),
    /// List the built-in presets with one-line descriptions.
    Presets,
    /// Write a photolithography mask of the design: GDSII, DXF, SVG or PNG.
    Export(ExportArgs),
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
    #[arg(long)]
    pub optics: Option<String>,
    /// Spectral response CSV (wavelength_nm, r, g, b): channels become weighted sums of
    /// wavelengths sampled every `--spectral-step-nm`.
    #[arg(long)]
    pub spectral: Option<PathBuf>,
    /// Wavelength step for `--spectral`, in nm.
    #[arg(long, default_value_t = 30.0, requires = "spectral")]
    pub spectral_step_nm: f64,
}

#[derive(Debug, Args)]
pub struct AnalyzeArgs {
    #[command(flatten)]
    pub selection: DesignSelection,
    /// Print one JSON object to stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write the PSFs (EXR, 16-bit PNG), log-PSFs (PNG) and mtf.csv into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Interactive preview quality (coarser sampling, same physics).
    #[arg(long)]
    pub preview: bool,
}

#[derive(Debug, Args)]
pub struct ExportArgs {
    #[command(flatten)]
    pub selection: DesignSelection,
    /// File format: gds, dxf, svg or png.
    #[arg(long)]
    pub format: MaskFormat,
    /// Which pixels: `pixel` (the one on the optical axis), `pupil` (every pixel over the lens
    /// pupil, with its outline) or `WxH` (a block of pixels centred on the axis, e.g. 1080x2400).
    #[arg(long)]
    pub region: MaskRegion,
    /// What the polygons are: `open` (drawn = clear) or `chrome` (drawn = dark, gap included).
    #[arg(long, default_value = "open")]
    pub tone: Tone,
    /// Output file; the design is written beside it as `<FILE>.design.json`.
    #[arg(long)]
    pub out: PathBuf,
    /// GDSII layer of the drawn polygons.
    #[arg(long, default_value_t = 1)]
    pub layer: i16,
    /// GDSII datatype of the drawn polygons.
    #[arg(long, default_value_t = 0)]
    pub datatype: i16,
    /// Layer of the pupil outline and the text notes.
    #[arg(long, default_value_t = 2)]
    pub note_layer: i16,
    /// Coordinate grid in nm (the database unit is 1 nm).
    #[arg(long, default_value_t = 1)]
    pub grid_nm: u32,
    /// GDSII top cell name.
    #[arg(long, default_value = "UDC_MASK")]
    pub top_cell: String,
    /// GDSII orientations: `strans` (one cell, reflected/rotated references) or
    /// `per-orientation` (one cell per orientation, plain references).
    #[arg(long, default_value = "strans")]
    pub gds_cells: GdsCells,
    /// PNG pixel size in µm.
    #[arg(long, default_value_t = 1.0)]
    pub um_per_px: f64,
    /// PNG bits per pixel: 1 (black/white) or 8 (grey = covered fraction).
    #[arg(long, default_value = "8")]
    pub png_bits: PngBits,
}

impl DesignSelection {
    /// Resolves the selection into a validated design.
    ///
    /// # Errors
    /// Unreadable or invalid files, unknown presets or recipes, bad override values.
    pub fn resolve(&self) -> Result<Design> {
        let mut design = match (&self.design, &self.preset) {
            (Some(path), _) => design_file::load_design(path)?,
            (None, Some(name)) => presets::load_preset(name)?,
            (None, None) => presets::load_preset(presets::DEFAULT_PRESET)?,
        };
        if let Some(path) = &self.pattern {
            design.opening.cells = pattern::load_pattern_png(path)?;
            design.opening.polygons.clear();
        }
        if let Some(p) = self.pitch_um {
            design.opening.pitch_um = p;
        }
        if let Some(t) = self.tiling {
            design.tiling.mode = t;
        }
        if let Some(s) = self.seed {
            design.tiling.seed = s;
        }
        if let Some(name) = &self.optics {
            design.optics = Optics::recipe_named(name).with_context(|| {
                format!("unknown optics recipe `{name}` (expected iccp21 or phone)")
            })?;
        }
        if let Some(path) = &self.spectral {
            let step = self.spectral_step_nm;
            if !(step.is_finite() && step > 0.0) {
                bail!("--spectral-step-nm must be a positive number of nm (got {step})");
            }
            let resp = spectral::load_response_csv(path)?;
            let lo = resp.wavelengths_nm.first().copied().unwrap_or(0.0);
            let hi = resp.wavelengths_nm.last().copied().unwrap_or(0.0);
            let samples: Vec<f64> = (0..)
                .map(|k| (lo / step).ceil() * step + f64::from(k) * step)
                .take_while(|w| *w <= hi)
                .collect();
            design.channels = spectral::channels_from_response(&resp, &samples)
                .map_err(|e| anyhow::anyhow!("{e} (in {})", path.display()))?;
        }
        design.validate()?;
        Ok(design)
    }
}

/// Runs a headless command.
///
/// # Errors
/// Any failure, as one message for stderr.
pub fn run(command: Command) -> Result<()> {
    match command {
        Command::Presets => {
            for (name, desc) in presets::list() {
                println!("{name:<16} {desc}");
            }
            Ok(())
        }
        Command::Analyze(args) => analyze_cmd(&args),
        Command::Export(args) => export_cmd(&args),
        Command::Studio { .. } => bail!("the studio is not a headless command"),
    }
}

fn analyze_cmd(args: &AnalyzeArgs) -> Result<()> {
    let design = args.selection.resolve()?;
    let options = AnalyzeOptions {
        quality: if args.preview {
            Quality::Preview
        } else {
            Quality::Full
        },
        expected_psf: args.out.is_some(),
    };
    let analysis = analyze_with(&design, &options, &Progress::new())?;
    if let Some(dir) = &args.out {
        export::write_analysis_outputs(dir, &analysis)?;
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string(&report::analysis_json(&analysis))?
        );
    } else {
        print_table(&design, &analysis);
    }
    Ok(())
}

fn export_cmd(args: &ExportArgs) -> Result<()> {
    let design = args.selection.resolve()?;
    let options = ExportOptions {
        format: args.format,
        spec: MaskSpec {
            region: args.region,
            tone: args.tone,
            grid_nm: args.grid_nm,
            ..MaskSpec::default()
        },
        layer: args.layer,
        datatype: args.datatype,
        note_layer: args.note_layer,
        top_cell: args.top_cell.clone(),
        gds_cells: args.gds_cells,
        um_per_px: args.um_per_px,
        png_bits: args.png_bits,
    };
    let report = export_mask(&design, &options, &args.out, &Progress::new())?;
    for line in report.lines() {
        println!("{line}");
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
        println!("warning: {w}");
    }
}
