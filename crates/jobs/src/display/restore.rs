//! `restore`: a photo captured through a display and restored (thesis §3.5, conventions §5).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use serde::{Deserialize, Serialize};

use udc_core::Progress;
use udc_core::analysis::analyze::{AnalyzeOptions, Quality};
use udc_core::psf::route::Backend;

use super::DesignSelection;
use crate::Report;
use crate::denoise::DenoiseFlags;

pub use udc_core::restore::RestoreMethod;

/// The parameters of `restore`: a photo captured through a display at each `--light` or
/// `--snr-db` and restored; or, with `--psf`, a real capture (`--image`) restored with a
/// measured PSF.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[command(group(
    clap::ArgGroup::new("light_level").required(true).args(["light", "snr_db", "psf"])
))]
pub struct RestoreJob {
    /// The display design the photo is captured through.
    #[command(flatten)]
    #[serde(flatten)]
    pub selection: DesignSelection,
    /// The photo (PNG, JPEG, TIFF, HDR or EXR), read as linear intensities in [0, 1]; with
    /// `--psf`, the capture to restore (also a linear .npy or MATLAB .mat array).
    #[arg(long)]
    pub image: PathBuf,
    /// Restore `--image` as a real capture with this PSF set (`psf import`'s .npy with its
    /// sidecar): no capture is simulated, so no `--light`; one PSF for every colour, or one
    /// per channel.
    #[arg(long, value_name = "PSF.npy", conflicts_with_all = ["light", "snr_db"])]
    #[serde(default)]
    pub psf: Option<PathBuf>,
    /// With `--psf`: the scene as it should look (same size), to score the restoration (PSNR,
    /// SSIM).
    #[arg(long, value_name = "CLEAN", requires = "psf")]
    #[serde(default)]
    pub truth: Option<PathBuf>,
    /// Electrons at a pixel of value 1 behind the reference display (T-OLED 150 DPI); give it
    /// several times for several runs.
    #[arg(long, value_name = "E")]
    #[serde(with = "crate::params::list")]
    pub light: Vec<f64>,
    /// The same light level as an SNR in dB (24/28/32/36/40 ↔ 273/654/1608/4005/10024 e⁻); give
    /// it several times for several runs.
    #[arg(long, value_name = "S")]
    #[serde(with = "crate::params::list")]
    pub snr_db: Vec<f64>,
    /// Restoration method.
    #[arg(long, value_parser = crate::choice::choice::<RestoreMethod>(), default_value_t = RestoreMethod::Wiener)]
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
    #[serde(flatten)]
    pub denoise: DenoiseFlags,
    /// Write captured, denoised, restored and difference PNGs (and float EXRs) per run into
    /// this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also draw the Restore view's pictures into `--out` as figures with pixel axes (SVG and
    /// PNG): the capture, the denoised capture, the restoration and its difference.
    #[arg(long, requires = "out")]
    #[serde(default)]
    pub figures: bool,
    /// Where the design's PSFs are computed: cpu, gpu or auto (as `analyze --backend`).
    #[arg(long, value_parser = crate::choice::choice::<Backend>(), default_value_t = Backend::Cpu)]
    #[serde(default)]
    pub backend: Backend,
}

impl Default for RestoreJob {
    fn default() -> Self {
        let cg = udc_core::restore::CgSettings::default();
        RestoreJob {
            selection: DesignSelection::default(),
            image: PathBuf::new(),
            psf: None,
            truth: None,
            light: Vec::new(),
            snr_db: Vec::new(),
            method: RestoreMethod::Wiener,
            nsr: udc_core::restore::THESIS_NSR,
            lambda: cg.lambda,
            iterations: cg.iterations,
            noise_seed: 0,
            adc_bits: None,
            max_side_px: None,
            pad_linear: false,
            denoise: DenoiseFlags::default(),
            out: None,
            figures: false,
            backend: Backend::Cpu,
        }
    }
}

impl RestoreJob {
    /// What the command line's argument rules check (a photo, at least one light level), for
    /// callers that build the job from parameters.
    ///
    /// # Errors
    /// The first rule broken, naming the flag.
    pub fn check(&self) -> Result<()> {
        if self.image.as_os_str().is_empty() {
            bail!("--image is required: the photo to capture and restore");
        }
        match (&self.psf, self.light.is_empty() && self.snr_db.is_empty()) {
            (None, true) => bail!("at least one --light or --snr-db is required"),
            (Some(_), false) => {
                bail!("--psf restores --image as a real capture: --light and --snr-db simulate one")
            }
            (None, false) if self.truth.is_some() => {
                bail!("--truth scores a real capture restored with --psf")
            }
            _ => {}
        }
        Ok(())
    }
}

/// Runs `restore`.
///
/// # Errors
/// A design or photo that does not load, a bad value (naming its flag), a refused size,
/// unwritable outputs, cancellation.
pub fn restore(args: &RestoreJob, progress: &Progress) -> Result<Report> {
    use udc_core::restore::capture::REFERENCE_LTR;
    use udc_core::restore::figures::difference_planes;
    use udc_core::restore::{
        CaptureSettings, CgSettings, Intermediate, Light, Method, Padding, RestoreSettings,
        simulate_with,
    };
    use udc_io::display::restore_report;
    use udc_io::photo;

    args.check()?;
    let method = match args.method {
        RestoreMethod::Wiener => Method::Wiener { nsr: args.nsr },
        RestoreMethod::Cg => Method::Cg(CgSettings {
            lambda: args.lambda,
            iterations: args.iterations,
            ..CgSettings::default()
        }),
    };
    if let Some(psf) = &args.psf {
        let padding = if args.pad_linear || args.method == RestoreMethod::Cg {
            Padding::Linear
        } else {
            Padding::Double
        };
        let name = args.method.name();
        let run = super::restore_measured::MeasuredRun {
            image: &args.image,
            psf,
            truth: args.truth.as_deref(),
            method: (method, name),
            padding,
            denoise: &args.denoise,
            out: args.out.as_deref(),
            figures: args.figures,
        };
        return super::restore_measured::restore_measured(&run, progress);
    }
    let design = args.selection.resolve()?;
    // f32 planes: a 16-megapixel photo's stages then fit in well under a gigabyte.
    let photo = photo::load_photo::<f32>(&args.image, args.max_side_px)?;
    // The display openings are chapter 3's: its σ² table.
    let denoise = args.denoise.resolve(udc_core::restore::Recipe::Iccp21)?;
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
    let route = crate::backend::route(args.backend)?;
    let analysis = super::analyze_shared(&design, &options, &route)?;
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
    let mut out = Report::default();
    {
        outln!(
            out,
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
            outln!(out, "{}: {w}", w.severity.as_str());
        }
        if let Some(w) = &light_warning {
            outln!(out, "warning: {w}");
        }
        outln!(
            out,
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
                    if args.figures {
                        let name = match stage {
                            Intermediate::Captured => "captured",
                            Intermediate::Denoised => "denoised",
                        };
                        outputs.extend(restore_report::write_stage_figure(
                            dir, &stem, name, planes,
                        )?);
                    }
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
            if args.figures {
                outputs.extend(restore_report::write_stage_figure(
                    dir,
                    &stem,
                    "restored",
                    &result.restored,
                )?);
                let difference = difference_planes(&result.restored, &photo);
                outputs.extend(restore_report::write_stage_figure(
                    dir,
                    &stem,
                    "difference",
                    &difference,
                )?);
            }
        }
        runs.push(restore_report::run_json(&result, &names, &outputs));
        {
            let per: Vec<String> = names
                .iter()
                .zip(&result.channels)
                .map(|(n, c)| format!("{n} {:.2}/{:.4}", c.psnr_db, c.ssim))
                .collect();
            let denoised = result
                .denoised_psnr_db
                .map_or_else(|| "-".to_string(), |p| format!("{p:.2}"));
            outln!(
                out,
                "{:>10.0}  {:>8.2}  {:>9.2}  {:.4}   {:>10.2}    {denoised:>11}    {}    ({})",
                result.light_e,
                result.snr_db,
                result.psnr_db,
                result.ssim,
                result.captured_psnr_db,
                per.join("  "),
                crate::denoise::denoise_text(&result.denoise)
            );
            let saturated = result
                .channels
                .iter()
                .map(|c| c.saturated_fraction)
                .fold(0.0, f64::max);
            if saturated > 0.0 {
                outln!(
                    out,
                    "warning: {:.2} % of the pixels reached the full well",
                    100.0 * saturated
                );
            }
            for p in &outputs {
                outln!(out, "wrote {}", p.display());
            }
        }
    }
    {
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
        out.json = serde_json::json!({
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
    }
    if args.out.is_some() {
        outln!(
            out,
            "difference images show |restored − truth| × {}",
            photo::DIFFERENCE_GAIN
        );
    }
    crate::backend::report(&mut out, args.backend, &route);
    Ok(out)
}
