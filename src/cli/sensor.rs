//! `udc-studio sensor`: the sensor previewer of thesis chapter 5 from the command line.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use serde_json::json;

use crate::core::Progress;
use crate::core::sensor::{
    BinMode, Cfa, Exposure, PRESET_NAMES, SensorSettings, SensorSpec, Strategy, run,
};
use crate::io::hdr::{ExrPrecision, load_hdr_with_report, write_scene_exr};
use crate::io::numbers::json6 as r;
use crate::io::sensor_report::{run_json, write_run_images};

/// Arguments of `udc-studio sensor`.
#[derive(Debug, Args)]
pub struct SensorArgs {
    /// The HDR scene: a Radiance .hdr or an OpenEXR .exr (linear relative radiance).
    #[arg(long)]
    pub hdr: PathBuf,
    /// Sensor preset: table54, nikon-z5, nexus-6p, bfs-u3-200s6c or bfs-u3-16s2m.
    #[arg(long, default_value = "table54")]
    pub sensor: String,
    /// Exposure: `mean:F` (image mean at fraction F of the full well; Table 5.4: mean:0.05),
    /// `pP:F` (the P-th percentile fills fraction F, e.g. p99.9:0.8) or `abs:E` (radiance 1 gives
    /// E electrons per µm²).
    #[arg(long, default_value = "mean:0.05")]
    pub exposure: String,
    /// ROI side in pixels (gain map, bin map, per-ROI SSIM).
    #[arg(long, default_value_t = 128)]
    pub roi: usize,
    /// η of eq. 5.3 for the ROI gains.
    #[arg(long, default_value_t = 2.0)]
    pub eta: f64,
    /// η of eq. 5.3 for the single-shot per-pixel gain (with --all-strategies).
    #[arg(long, default_value_t = 4.0)]
    pub eta_per_pixel: f64,
    /// SNR threshold of the optimal-pitch analysis.
    #[arg(long, default_value_t = 4.0)]
    pub snr_t: f64,
    /// Seed of the photon and read noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// How the vary-bin strategies combine a bin.
    #[arg(long, value_enum, default_value_t = BinMode::Digital)]
    pub bin_mode: BinMode,
    /// Also run the other baselines: maximum gain, alternating rows, per-pixel gain, 2×2 bins.
    #[arg(long)]
    pub all_strategies: bool,
    /// Colour filter array: `none` (monochrome, on the scene's luminance) or `rggb` (a Bayer
    /// mosaic of the RGB scene, same-colour binning, demosaiced; scores on the demosaiced
    /// luminance and per channel).
    #[arg(long, value_enum, default_value_t = Cfa::None)]
    pub cfa: Cfa,
    /// Scale the scene down (area average) so its longer side has at most this many pixels.
    #[arg(long)]
    pub max_side_px: Option<usize>,
    /// Print one JSON object to stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write the maps and tone-mapped captures (PNG), the captures (float EXR) and the scene as
    /// simulated (half-float EXR) into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Parses `mean:F`, `pP:F` or `abs:E` (see [`SensorArgs::exposure`]).
///
/// # Errors
/// A message naming what is wrong.
pub fn parse_exposure(s: &str) -> Result<Exposure, String> {
    let (kind, value) = s
        .split_once(':')
        .ok_or_else(|| format!("`{s}`: expected mean:F, pP:F or abs:E (e.g. mean:0.05)"))?;
    let number = |t: &str| {
        t.trim()
            .parse::<f64>()
            .map_err(|_| format!("`{s}`: `{t}` is not a number"))
    };
    let kind = kind.trim().to_ascii_lowercase();
    let e = match kind.as_str() {
        "mean" => Exposure::MeanFraction(number(value)?),
        "abs" => Exposure::ElectronsPerUm2(number(value)?),
        k if k.starts_with('p') => Exposure::PercentileFill {
            percentile: number(&k[1..])?,
            fill: number(value)?,
        },
        _ => return Err(format!("`{s}`: expected mean:F, pP:F or abs:E")),
    };
    e.validate().map_err(|err| format!("`{s}`: {err}"))?;
    Ok(e)
}

fn exposure_json(e: &Exposure) -> serde_json::Value {
    match *e {
        Exposure::MeanFraction(f) => json!({ "mean_fraction": f }),
        Exposure::PercentileFill { percentile, fill } => {
            json!({ "percentile": percentile, "fill": fill })
        }
        Exposure::ElectronsPerUm2(x) => json!({ "electrons_per_um2": x }),
    }
}

fn exposure_text(e: &Exposure) -> String {
    match *e {
        Exposure::MeanFraction(f) => format!("mean at {} % of the full well", 100.0 * f),
        Exposure::PercentileFill { percentile, fill } => {
            format!(
                "{percentile}th percentile at {} % of the full well",
                100.0 * fill
            )
        }
        Exposure::ElectronsPerUm2(x) => format!("{x} e⁻/µm² at radiance 1"),
    }
}

/// Runs `udc-studio sensor`.
///
/// # Errors
/// Unknown sensors, unreadable scenes, invalid settings, unwritable outputs.
pub fn sensor_cmd(args: &SensorArgs) -> Result<()> {
    let sensor = SensorSpec::named(&args.sensor).with_context(|| {
        format!(
            "unknown sensor `{}` (expected one of: {})",
            args.sensor,
            PRESET_NAMES.join(", ")
        )
    })?;
    if args.max_side_px == Some(0) {
        bail!("--max-side-px must be at least 1");
    }
    let exposure = parse_exposure(&args.exposure).map_err(|e| anyhow::anyhow!("--exposure {e}"))?;
    let (mut scene, report) = load_hdr_with_report(&args.hdr)?;
    let full = scene.dim();
    let settings = SensorSettings {
        sensor,
        exposure,
        roi_px: args.roi,
        eta: args.eta,
        eta_per_pixel: args.eta_per_pixel,
        snr_t: args.snr_t,
        seed: args.seed,
        bin_mode: args.bin_mode,
        strategies: if args.all_strategies {
            Strategy::all()
        } else {
            Strategy::table54()
        },
        cfa: args.cfa,
        ..SensorSettings::default()
    };
    if let Some(m) = args.max_side_px {
        scene = scene.downscaled(m);
    }
    let result = run(&scene, &settings, &Progress::new())?;
    let mut outputs = Vec::new();
    if let Some(dir) = &args.out {
        outputs = write_run_images(dir, &result, settings.sensor.max_gain)?;
        let p = dir.join("scene.exr");
        write_scene_exr(&p, &scene, ExrPrecision::Half)?;
        outputs.push(p);
    }
    let notes = report.notes();
    let (rows, cols) = scene.dim();
    if args.json {
        let mut v = run_json(&result);
        if let Some(obj) = v.as_object_mut() {
            let s = &settings.sensor;
            obj.insert("hdr".into(), json!(args.hdr.display().to_string()));
            obj.insert("source_size_px".into(), json!([full.1, full.0]));
            obj.insert(
                "sensor".into(),
                json!({
                    "name": s.name, "unit_pixel_um": s.unit_pixel_um,
                    "full_well_e": s.full_well_e, "sigma_pre_e": s.sigma_pre_e,
                    "sigma_post_e": s.sigma_post_e, "max_gain": r(s.max_gain),
                    "adc_bits": s.adc_bits, "black_level_fraction": s.black_level_fraction,
                }),
            );
            obj.insert("exposure".into(), exposure_json(&settings.exposure));
            obj.insert("eta".into(), json!(settings.eta));
            obj.insert("snr_t".into(), json!(settings.snr_t));
            obj.insert("seed".into(), json!(settings.seed));
            obj.insert("gamma".into(), r(settings.gamma));
            obj.insert("bin_mode".into(), json!(settings.bin_mode.label()));
            obj.insert("notes".into(), json!(notes));
            obj.insert(
                "outputs".into(),
                json!(
                    outputs
                        .iter()
                        .map(|p| p.display().to_string())
                        .collect::<Vec<_>>()
                ),
            );
        }
        println!("{}", serde_json::to_string(&v)?);
        return Ok(());
    }
    let s = &settings.sensor;
    println!(
        "{} ({cols}×{rows}{}): sensor {} ({} µm, full well {} e⁻, σ_pre {} e⁻, σ_post {} e⁻, \
         gain ≤ {:.1}, {}-bit)",
        args.hdr.display(),
        if (rows, cols) == full {
            String::new()
        } else {
            format!(", from {}×{}", full.1, full.0)
        },
        s.name,
        s.unit_pixel_um,
        s.full_well_e,
        s.sigma_pre_e,
        s.sigma_post_e,
        s.max_gain,
        s.adc_bits
    );
    if settings.cfa != Cfa::None {
        println!(
            "colour: {} Bayer mosaic, same-colour binning, Malvar-He-Cutler demosaic; scores on \
             the demosaiced luminance",
            settings.cfa.label().to_uppercase()
        );
    }
    println!(
        "exposure: {} ({:.4} e⁻ per unit radiance); ROI {} px ({}×{}); η {:?}; SNR_t {:?}; {} binning; \
         {:.0} ms",
        exposure_text(&settings.exposure),
        result.electrons_per_radiance,
        settings.roi_px,
        result.grid.cols,
        result.grid.rows,
        settings.eta,
        settings.snr_t,
        settings.bin_mode.label(),
        result.elapsed_ms
    );
    for n in &notes {
        println!("note: {n}");
    }
    println!(
        "{:<22} {:>10} {:>9} {:>9} {:>10} {:>8} {:>13} {:>10}",
        "strategy",
        "worst SSIM",
        "mean SSIM",
        "PSNR (dB)",
        "saturated",
        "DR (dB)",
        "gain",
        "mean bin"
    );
    for st in &result.strategies {
        let (lo, hi) = st
            .gain_map
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), g| (a.min(*g), b.max(*g)));
        println!(
            "{:<22} {:>10.4} {:>9.4} {:>9.2} {:>9.2}% {:>8.1} {:>13} {:>10.2}",
            st.name,
            st.worst_roi_ssim,
            st.mean_ssim,
            st.psnr_db,
            100.0 * st.saturated_fraction,
            st.dynamic_range_db,
            format!("{lo:.1}–{hi:.1}"),
            st.bin_map.mean().unwrap_or(1.0)
        );
    }
    print_channels(&result);
    for p in &outputs {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// With a colour filter array, the per-channel scores under the table.
fn print_channels(result: &crate::core::sensor::SensorRun) {
    use crate::core::sensor::colour::CHANNEL_NAMES;
    if result.colour_truth.is_none() {
        return;
    }
    println!("per channel (worst ROI SSIM / PSNR dB):");
    print!("{:<22}", "strategy");
    for c in CHANNEL_NAMES {
        print!(" {:>17}", c);
    }
    println!();
    for st in &result.strategies {
        let Some(colour) = &st.colour else { continue };
        print!("{:<22}", st.name);
        for ch in &colour.channels {
            print!(
                " {:>17}",
                format!("{:.4} / {:.2}", ch.worst_roi_ssim, ch.psnr_db)
            );
        }
        println!();
    }
}
