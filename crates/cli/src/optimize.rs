//! `udc-studio optimize`: the opening optimizer of §3.4.2 from the command line.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use serde_json::json;

use super::DesignSelection;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use udc_core::optimize::{DataSet, LossWeights, OptimizeSettings, Relaxation, Start, optimize};
use udc_core::{Analysis, Progress};
use udc_io::design::file as design_file;
use udc_io::photo;
use udc_jobs::backend::BackendFlag;

/// `--start`: the cells' state before the first epoch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StartArg {
    /// Every cell half-way open (logit +1), as the thesis.
    AllOpen,
    /// The design's own opening.
    Current,
}

/// Arguments of `udc-studio optimize`.
#[derive(Debug, Args)]
pub struct OptimizeArgs {
    /// The design whose opening is optimized (its optics, tiling and channels are kept).
    #[command(flatten)]
    pub selection: DesignSelection,
    /// Number of epochs (Adam steps).
    #[arg(long, default_value_t = 150)]
    pub epochs: usize,
    /// Target open fraction of the pixel, 0–1 (the thesis: 0.2).
    #[arg(long, default_value_t = 0.2)]
    pub area: f64,
    /// Folder of PNG/JPEG photos: adds the top-10 % L2 loss through the Wiener pipeline.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Side of the square training patch cut from each photo, in pixels.
    #[arg(long, default_value_t = 256)]
    pub data_patch_px: usize,
    /// Weight of L_inv.
    #[arg(long, default_value_t = 0.01)]
    pub weight_inv: f64,
    /// Weight of the area term.
    #[arg(long, default_value_t = 10.0)]
    pub weight_area: f64,
    /// Weight of the data loss (with --data).
    #[arg(long, default_value_t = 10.0)]
    pub weight_data: f64,
    /// Evaluate the loss on the grey sigmoid mask instead of the binarised one (straight-through,
    /// the default); the grey optimum is a dimmed open aperture that thresholding ruins.
    #[arg(long)]
    pub sigmoid_relaxation: bool,
    /// Where the cells start.
    #[arg(long, value_enum, default_value_t = StartArg::AllOpen)]
    pub start: StartArg,
    /// Optimize on the preview sampling (twice the fine spacing, about 4× faster, where that
    /// agrees with full quality; full quality otherwise).
    #[arg(long)]
    pub preview: bool,
    /// Reserve room for three equal R, G, B emitters of at least this many µm² each in the
    /// opaque area (0 = off); the saved design carries their placement.
    #[arg(long, default_value_t = 0.0)]
    pub reserve_subpixels_um2: f64,
    /// Where every epoch's window transforms and their adjoints (and the PSFs of the before and
    /// after analyses) are computed: cpu, gpu or auto (as `analyze --backend`).
    #[command(flatten)]
    pub backend: BackendFlag,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Where to write the optimized design (JSON).
    #[arg(long)]
    pub out: PathBuf,
}

/// Loads every PNG/JPEG in `dir` (sorted by name, at most 1024 px a side).
fn load_photos(dir: &Path) -> Result<Vec<Vec<ndarray::Array2<f64>>>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("cannot read the data folder {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| matches!(e.to_ascii_lowercase().as_str(), "png" | "jpg" | "jpeg"))
        })
        .collect();
    paths.sort();
    if paths.is_empty() {
        bail!("no PNG or JPEG photo in {}", dir.display());
    }
    paths
        .iter()
        .map(|p| photo::load_photo(p, Some(1024)).map_err(anyhow::Error::from))
        .collect()
}

fn aucs(a: &Analysis) -> Vec<f64> {
    a.channels.iter().map(|c| c.mtf.auc_radial_min).collect()
}

/// Runs `optimize`.
///
/// # Errors
/// Bad arguments, unreadable inputs, simulation errors, an unwritable output.
pub fn optimize_cmd(args: &OptimizeArgs) -> Result<()> {
    // Refused before the (long) run, not after it.
    udc_io::safe_file::check_not_an_input(&args.out, &args.selection.input_files())?;
    let design = args.selection.resolve()?;
    let settings = OptimizeSettings {
        epochs: args.epochs,
        target_open_fraction: args.area,
        weights: LossWeights {
            area: args.weight_area,
            inv: args.weight_inv,
            data: args.weight_data,
        },
        relaxation: if args.sigmoid_relaxation {
            Relaxation::Sigmoid
        } else {
            Relaxation::StraightThrough
        },
        start: match args.start {
            StartArg::AllOpen => Start::AllOpen,
            StartArg::Current => Start::Current,
        },
        quality: if args.preview {
            Quality::Preview
        } else {
            Quality::Full
        },
        reserve_subpixels_um2: args.reserve_subpixels_um2,
        ..OptimizeSettings::default()
    };
    settings.validate()?;
    let data = match &args.data {
        Some(dir) => Some(DataSet::new(
            &load_photos(dir)?,
            design.channels.len(),
            args.data_patch_px,
        )?),
        None => None,
    };
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let route = args.backend.route()?;
    let before = analyze_with_route(&design, &options, &route, &Progress::new())?;
    let json = args.json;
    let result = optimize(
        &design,
        &settings,
        data.as_ref(),
        &route,
        &Progress::new(),
        |r| {
            if !json && (r.epoch % 10 == 0 || r.epoch + 1 == r.epochs) {
                eprintln!(
                    "epoch {:>4}/{}  loss {:>10.6}  L_inv {:>8.5}  area {:.3} (target {:.2}){}",
                    r.epoch + 1,
                    r.epochs,
                    r.loss_total,
                    r.loss_inv,
                    r.open_fraction,
                    r.area_target,
                    r.loss_data
                        .map(|d| format!("  L_data {d:.3e}"))
                        .unwrap_or_default()
                );
            }
            ControlFlow::Continue(())
        },
    )?;
    let after = analyze_with_route(&result.design, &options, &route, &Progress::new())?;
    design_file::save_design(&args.out, &result.design)?;
    if json {
        let history: Vec<_> = result
            .history
            .iter()
            .map(|r| {
                json!({
                    "epoch": r.epoch,
                    "area_target": r.area_target,
                    "open_fraction": r.open_fraction,
                    "loss_total": r.loss_total,
                    "loss_inv": r.loss_inv,
                    "loss_area": r.loss_area,
                    "loss_data": r.loss_data,
                })
            })
            .collect();
        let channels: Vec<&str> = before.channels.iter().map(|c| c.name.as_str()).collect();
        let mut out = json!({
            "design": design.name,
            "out": args.out.display().to_string(),
            "epochs": result.history.len(),
            "channels": channels,
            "auc_before": aucs(&before),
            "auc_after": aucs(&after),
            "open_fraction_before": before.open_fraction,
            "open_fraction_after": after.open_fraction,
            "ltr_before": before.ltr,
            "ltr_after": after.ltr,
            "invertibility_loss_before": before.invertibility_loss,
            "invertibility_loss_after": after.invertibility_loss,
            "elapsed_ms": result.elapsed_ms,
            "history": history,
        });
        args.backend.note(&route, &mut out);
        crate::emit_json(&out)?;
    } else {
        println!(
            "optimized {} epoch{} in {:.1} s -> {}",
            result.history.len(),
            if result.history.len() == 1 { "" } else { "s" },
            result.elapsed_ms / 1e3,
            args.out.display()
        );
        println!("{:<10} {:>12} {:>12}", "", "before", "after");
        println!(
            "{:<10} {:>12.4} {:>12.4}",
            "open", before.open_fraction, after.open_fraction
        );
        println!("{:<10} {:>12.4} {:>12.4}", "LTR", before.ltr, after.ltr);
        println!(
            "{:<10} {:>12.5} {:>12.5}",
            "L_inv", before.invertibility_loss, after.invertibility_loss
        );
        for (b, a) in before.channels.iter().zip(&after.channels) {
            println!(
                "{:<10} {:>12.5} {:>12.5}",
                format!("AUC {}", b.name),
                b.mtf.auc_radial_min,
                a.mtf.auc_radial_min
            );
        }
        if let Some(line) = args.backend.line(&route) {
            println!("{line}");
        }
    }
    Ok(())
}
