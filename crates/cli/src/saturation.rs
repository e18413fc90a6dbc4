//! `udc-studio saturation`: a capture that clips specular highlights against an exposure-
//! bracketed HDR capture, both restored by Wiener deconvolution (thesis §3.7, Fig. 3.30).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;

use super::DesignSelection;
use udc_core::Progress;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality, analyze_with_route};
use udc_core::camera::saturation::{SaturationSettings, saturation_study};
use udc_io::photo::hdr;
use udc_io::photo::write_photo_png;
use udc_jobs::backend::BackendFlag;

/// Arguments of `udc-studio saturation`.
#[derive(Debug, Args)]
pub struct SaturationArgs {
    /// The display design the scene is captured through.
    #[command(flatten)]
    pub selection: DesignSelection,
    /// HDR scene (EXR or Radiance HDR, linear RGB); default: the built-in StillLife.
    #[arg(long)]
    pub hdr: Option<PathBuf>,
    /// Scale the scene down so its longer side has at most this many pixels.
    #[arg(long)]
    pub max_side_px: Option<usize>,
    /// Share of pixels (%) clipped at the full well in the base exposure.
    #[arg(long, default_value_t = 2.0)]
    pub clip_percent: f64,
    /// Number of bracketed exposures.
    #[arg(long, default_value_t = 3)]
    pub brackets: usize,
    /// Spacing of the bracketed exposures, in stops (EV).
    #[arg(long, default_value_t = 2.0)]
    pub step_ev: f64,
    /// Noise-to-signal ratio of the Wiener filter.
    #[arg(long, default_value_t = udc_core::restore::THESIS_NSR)]
    pub nsr: f64,
    /// Seed of the photon and read noise.
    #[arg(long, default_value_t = 0)]
    pub noise_seed: u64,
    /// Print one JSON object to stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write truth, captures and restorations (PNG, clipped to the base exposure) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Where the PSFs are computed.
    #[command(flatten)]
    pub backend: BackendFlag,
}

/// Runs `udc-studio saturation`.
///
/// # Errors
/// Bad arguments, unreadable scenes, sampling errors, unwritable output.
pub fn saturation_cmd(args: &SaturationArgs) -> Result<()> {
    let settings = SaturationSettings {
        clip_percent: args.clip_percent,
        brackets: args.brackets,
        step_ev: args.step_ev,
        nsr: args.nsr,
        seed: args.noise_seed,
    };
    settings.validate()?;
    if args.max_side_px == Some(0) {
        bail!("--max-side-px: must be at least 1");
    }
    let design = args.selection.resolve()?;
    let mut scene = match &args.hdr {
        Some(path) => hdr::load_hdr(path)?,
        None => hdr::sample_scene()?,
    };
    if let Some(m) = args.max_side_px {
        scene = scene.downscaled(m);
    }
    let options = AnalyzeOptions {
        quality: Quality::Full,
        expected_psf: false,
    };
    let route = args.backend.route()?;
    let analysis = analyze_with_route(&design, &options, &route, &Progress::new())?;
    let psfs: Vec<&ndarray::Array2<f64>> = analysis.channels.iter().map(|c| &c.psf).collect();
    if psfs.len() != scene.planes.len() {
        bail!(
            "the design has {} channels and the scene {} planes; saturation needs them equal",
            psfs.len(),
            scene.planes.len()
        );
    }
    let r = saturation_study(&scene.planes, &psfs, &settings)?;
    let mut written = Vec::new();
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir)?;
        for (name, planes) in [
            ("truth.png", &r.truth),
            ("clipped_captured.png", &r.clipped.captured),
            ("clipped_restored.png", &r.clipped.restored),
            ("bracketed_captured.png", &r.bracketed.captured),
            ("bracketed_restored.png", &r.bracketed.restored),
        ] {
            let path = dir.join(name);
            let refs: Vec<_> = planes.iter().collect();
            write_photo_png(&path, &refs)?;
            written.push(path.display().to_string());
        }
    }
    let run_json = |run: &udc_core::camera::saturation::SaturationRun| {
        serde_json::json!({
            "psnr_db": run.psnr_db,
            "ssim": run.ssim,
            "clipped_fraction": run.clipped_fraction,
        })
    };
    if args.json {
        let (rows, cols) = scene.dim();
        let mut out = serde_json::json!({
            "design": design.name,
            "scene": args.hdr.as_ref().map_or(hdr::SAMPLE_SCENE_NAME.to_string(), |p| p.display().to_string()),
            "scene_size_px": [cols, rows],
            "clip_percent": settings.clip_percent,
            "exposure_factors": r.factors,
            "nsr": settings.nsr,
            "clipped": run_json(&r.clipped),
            "bracketed": run_json(&r.bracketed),
            "psnr_gain_db": r.bracketed.psnr_db - r.clipped.psnr_db,
            "outputs": written,
        });
        args.backend.note(&route, &mut out);
        crate::emit_json(&out)?;
        return Ok(());
    }
    println!(
        "{}: {} % of the pixels clip in the base exposure; {} exposures {} EV apart",
        design.name, settings.clip_percent, settings.brackets, settings.step_ev
    );
    println!("capture              PSNR (dB)  SSIM     still clipped");
    for (name, run) in [
        ("one exposure", &r.clipped),
        ("bracketed HDR", &r.bracketed),
    ] {
        println!(
            "{name:<20} {:>9.2}  {:.4}   {:.2} %",
            run.psnr_db,
            run.ssim,
            100.0 * run.clipped_fraction
        );
    }
    println!("scores on the base exposure's range: truth and restoration clipped to [0, 1]");
    for w in &written {
        println!("wrote {w}");
    }
    if let Some(line) = args.backend.line(&route) {
        println!("{line}");
    }
    Ok(())
}
