//! `udc-studio appearance`: an image shown on the design's layout as the eye sees it, the
//! display-quality numbers and the camera's AUC side by side (thesis §3.7, Fig. 3.27).

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use ndarray::Array2;

use super::DesignSelection;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use udc_core::display::appearance::{AppearanceSettings, appearance, periodic_and_random};
use udc_core::{Analysis, Progress};
use udc_io::photo;
use udc_jobs::backend::BackendFlag;

/// The display resolution `appearance` shows a layout at without `--dpi` (Fig. 3.27's), DPI.
pub const DEFAULT_DPI: f64 = 300.0;

/// Arguments of `udc-studio appearance`.
#[derive(Debug, Args)]
pub struct AppearanceArgs {
    /// The design to show (its emitter layer, or an automatic placement); its `--dpi` is the
    /// display resolution the layout is shown at ([`DEFAULT_DPI`] when not given: Fig. 3.27).
    #[command(flatten)]
    pub selection: DesignSelection,
    /// The image to show (PNG, JPEG, ...); without it, the built-in photo.
    #[arg(long)]
    pub image: Option<PathBuf>,
    /// Distance from the eye to the display, mm.
    #[arg(long, default_value_t = 300.0)]
    pub viewing_distance_mm: f64,
    /// Side of the square display region rendered, mm (Fig. 3.27: 8.4).
    #[arg(long, default_value_t = 8.4)]
    pub region_mm: f64,
    /// FWHM of the eye's Gaussian blur, arcminutes (1 = 20/20 acuity).
    #[arg(long, default_value_t = 1.0)]
    pub acuity_arcmin: f64,
    /// Print one JSON object to stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write the eye-blurred rendering (appearance.png) into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Camera AUC at preview quality (twice the fine PSF spacing where that keeps the AUC within
    /// 3 %, full quality otherwise).
    #[arg(long)]
    pub preview: bool,
    /// Where the camera's PSFs are computed.
    #[command(flatten)]
    pub backend: BackendFlag,
}

/// The camera's AUC: the radially-minimum AUC averaged over the colour channels.
pub fn camera_auc(analysis: &Analysis) -> f64 {
    let n = analysis.channels.len().max(1) as f64;
    analysis
        .channels
        .iter()
        .map(|c| c.mtf.auc_radial_min)
        .sum::<f64>()
        / n
}

/// Runs `appearance`.
///
/// # Errors
/// Bad values (named by their flag), unreadable files, designs whose emitters do not fit.
pub fn appearance_cmd(args: &AppearanceArgs) -> Result<()> {
    let settings = AppearanceSettings {
        dpi: args.selection.dpi.unwrap_or(DEFAULT_DPI),
        viewing_distance_mm: args.viewing_distance_mm,
        region_mm: args.region_mm,
        acuity_arcmin: args.acuity_arcmin,
    };
    let design = args.selection.resolve()?;
    settings.validate(design.opening.n())?;
    let image: Vec<Array2<f64>> = match &args.image {
        Some(path) => photo::load_photo(path, Some(4096))?,
        None => photo::built_in_photo()?,
    };
    let progress = Progress::new();
    let (quality, rendering) = appearance(&design, &image, &settings, &progress)?;
    let options = AnalyzeOptions {
        quality: if args.preview {
            Quality::Preview
        } else {
            Quality::Full
        },
        expected_psf: false,
    };
    let route = args.backend.route()?;
    let analysis = analyze_with_route(&design, &options, &route, &progress)?;
    let auc = camera_auc(&analysis);
    let mut outputs = Vec::new();
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir)
            .map_err(|e| anyhow!("cannot create the directory {}: {e}", dir.display()))?;
        let path = dir.join("appearance.png");
        let [r, g, b] = &rendering.planes;
        photo::write_photo_png(&path, &[r, g, b])?;
        outputs.push(path.display().to_string());
    }
    // Fig. 3.27's pair: the same opening tiled periodically and randomly, rendered alike.
    let mut pair = Vec::new();
    for (label, d) in periodic_and_random(&design) {
        let (q, rendering) = appearance(&d, &image, &settings, &progress)?;
        if let Some(dir) = &args.out {
            let kind = if d.tiling.mode.is_random() {
                "random"
            } else {
                "periodic"
            };
            let path = dir.join(format!("appearance-{kind}.png"));
            let [r, g, b] = &rendering.planes;
            photo::write_photo_png(&path, &[r, g, b])?;
            outputs.push(path.display().to_string());
        }
        pair.push((label, q));
    }
    let r = |v: f64| (v * 1e6).round() / 1e6;
    if args.json {
        let mut out = serde_json::json!({
            "design": design.name,
            "display_quality": {
                "nonuniformity": r(quality.nonuniformity),
                "aliasing": r(quality.aliasing),
                "harmonic_fraction": r(quality.harmonic_fraction),
                "image_error": r(quality.image_error),
                "eye_fwhm_um": r(quality.eye_fwhm_um),
                "pixels_per_side": quality.pixels_per_side,
            },
            "camera_auc": r(auc),
            "camera_auc_per_channel": analysis.channels.iter()
                .map(|c| r(c.mtf.auc_radial_min)).collect::<Vec<_>>(),
            "settings": {
                "dpi": settings.dpi,
                "viewing_distance_mm": settings.viewing_distance_mm,
                "region_mm": settings.region_mm,
                "acuity_arcmin": settings.acuity_arcmin,
            },
            "sample_um": r(rendering.sample_um),
            "tilings": pair.iter().map(|(label, q)| serde_json::json!({
                "tiling": label,
                "nonuniformity": r(q.nonuniformity),
                "aliasing": r(q.aliasing),
                "image_error": r(q.image_error),
            })).collect::<Vec<_>>(),
            "outputs": outputs,
        });
        args.backend.note(&route, &mut out);
        crate::emit_json(&out)?;
    } else {
        println!(
            "{}: {} display pixels per side at {} DPI, seen from {} mm (eye FWHM {:.1} µm)",
            design.name,
            quality.pixels_per_side,
            settings.dpi,
            settings.viewing_distance_mm,
            quality.eye_fwhm_um
        );
        println!(
            "nonuniformity {:.5}   aliasing {:.5}   harmonic fraction {:.4}   image error {:.5}",
            quality.nonuniformity, quality.aliasing, quality.harmonic_fraction, quality.image_error
        );
        println!("camera AUC (radial min, mean of channels) {auc:.5}");
        for (label, q) in &pair {
            println!(
                "{label}: nonuniformity {:.5}   aliasing {:.5}   image error {:.5}",
                q.nonuniformity, q.aliasing, q.image_error
            );
        }
        for o in &outputs {
            println!("wrote {o}");
        }
        if let Some(line) = args.backend.line(&route) {
            println!("{line}");
        }
    }
    Ok(())
}
