//! Sensor jobs (thesis chapter 5): `sensor` on an HDR scene and the `sensor flat-patch` check.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::{Deserialize, Serialize};
use serde_json::json;

use crate::Report;

use udc_core::Progress;
use udc_core::ValueError;
use udc_core::sensor::{
    AdditiveGain, BinMode, Cfa, Exposure, FlatPatchSpec, Held, PRESET_NAMES, RoiLight, Scene,
    SensorSettings, SensorSpec, Strategy, StrategyResult, check_budget, run_with,
};
use udc_io::numbers::json6 as r;
use udc_io::photo::hdr::{ExrPrecision, load_hdr_with_report, write_scene_exr};
use udc_io::sensor::report::{strategy_json, write_strategy_images, write_truth_images};

/// The parameters of `sensor`: a run on an HDR scene.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct SensorJob {
    /// The HDR scene: a Radiance .hdr or an OpenEXR .exr (linear relative radiance).
    #[arg(long, required = true)]
    pub hdr: Option<PathBuf>,
    /// Sensor preset: table54, nikon-z5, nexus-6p, bfs-u3-200s6c or bfs-u3-16s2m.
    #[arg(long, default_value_t = SensorJob::default().sensor)]
    pub sensor: String,
    /// Exposure: `mean:F` (image mean at fraction F of the full well; Table 5.4: mean:0.05),
    /// `pP:F` (the P-th percentile fills fraction F, e.g. p99.9:0.8) or `abs:E` (radiance 1 gives
    /// E electrons per µm²).
    #[arg(long, default_value_t = SensorJob::default().exposure)]
    pub exposure: String,
    /// ROI side in pixels (gain map, bin map, per-ROI SSIM).
    #[arg(long, default_value_t = SensorJob::default().roi)]
    pub roi: usize,
    /// η of eq. 5.3 for the ROI gains.
    #[arg(long, default_value_t = SensorJob::default().eta)]
    pub eta: f64,
    /// η of eq. 5.3 for the single-shot per-pixel gain (with --all-strategies).
    #[arg(long, default_value_t = SensorJob::default().eta_per_pixel)]
    pub eta_per_pixel: f64,
    /// SNR threshold of the optimal-pitch analysis.
    #[arg(long, default_value_t = SensorJob::default().snr_t)]
    pub snr_t: f64,
    /// Seed of the photon and read noise.
    #[arg(long, default_value_t = SensorJob::default().seed)]
    pub seed: u64,
    /// How the vary-bin strategies combine a bin.
    #[arg(long, value_parser = crate::choice::choice::<BinMode>(), default_value_t = SensorJob::default().bin_mode)]
    #[serde(with = "crate::params::named")]
    pub bin_mode: BinMode,
    /// Amplifier gain of additive bins of N pixels: `scaled` (g/N: no extra saturation, read
    /// noise σ_post²/g²) or `same` (g: least read noise, the sum saturates N× sooner).
    #[arg(long, value_parser = crate::choice::choice::<AdditiveGain>(), default_value_t = SensorJob::default().additive_gain, visible_alias = "gain-policy")]
    #[serde(with = "crate::params::named")]
    pub additive_gain: AdditiveGain,
    /// The light level eq. 5.3 sets an ROI's gain for: its brightest 2×2 snapshot block, the
    /// 99th percentile of its blocks, or its mean.
    #[arg(long, value_parser = crate::choice::choice::<RoiLight>(), default_value_t = SensorJob::default().roi_light)]
    #[serde(with = "crate::params::named")]
    pub roi_light: RoiLight,
    /// Also run the other baselines: maximum gain, alternating rows, per-pixel gain, 2×2 bins.
    #[arg(long)]
    pub all_strategies: bool,
    /// Colour filter array: `none` (monochrome, on the scene's luminance) or `rggb` (a Bayer
    /// mosaic of the RGB scene, same-colour binning, demosaiced; scores on the demosaiced
    /// luminance and per channel).
    #[arg(long, value_parser = crate::choice::choice::<Cfa>(), default_value_t = SensorJob::default().cfa)]
    #[serde(with = "crate::params::named")]
    pub cfa: Cfa,
    /// Scale the scene down (area average) so its longer side has at most this many pixels.
    #[arg(long)]
    pub max_side_px: Option<usize>,
    /// Write the maps and tone-mapped captures (PNG), the captures (float EXR) and the scene as
    /// simulated (half-float EXR) into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Also draw the studio's sensor maps into `--out` as figures with axes and colour bars
    /// (SVG and PNG): the scene, and each strategy's capture, gain and bin maps.
    #[arg(long, requires = "out")]
    #[serde(default)]
    pub figures: bool,
}

impl Default for SensorJob {
    fn default() -> Self {
        SensorJob {
            hdr: None,
            sensor: DEFAULT_SENSOR.to_string(),
            exposure: "mean:0.05".to_string(),
            roi: 128,
            eta: 2.0,
            eta_per_pixel: 4.0,
            snr_t: 4.0,
            seed: 0,
            bin_mode: BinMode::Digital,
            additive_gain: AdditiveGain::Scaled,
            roi_light: RoiLight::Brightest,
            all_strategies: false,
            cfa: Cfa::None,
            max_side_px: None,
            out: None,
            figures: false,
        }
    }
}

/// The parameters of `sensor flat-patch`.
#[derive(Debug, Clone, Args, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub struct FlatPatchJob {
    /// Light level of the patch, electrons per unit pixel (also the l̂ of eq. 5.3).
    #[arg(long, value_name = "E")]
    pub light: f64,
    /// η of eq. 5.3.
    #[arg(long, value_name = "H", default_value_t = FlatPatchJob::default().eta)]
    pub eta: f64,
    /// Sensor preset: table54, nikon-z5, nexus-6p, bfs-u3-200s6c or bfs-u3-16s2m.
    #[arg(long, default_value_t = FlatPatchJob::default().sensor)]
    pub sensor: String,
    /// Bin side in unit pixels: 1, 2, 4 or 8.
    #[arg(long, default_value_t = FlatPatchJob::default().bin)]
    pub bin: usize,
    /// How a bin's pixels are combined.
    #[arg(long, value_parser = crate::choice::choice::<BinMode>(), default_value_t = FlatPatchJob::default().bin_mode)]
    #[serde(with = "crate::params::named")]
    pub bin_mode: BinMode,
    /// Amplifier gain of additive bins: `scaled` (g/N) or `same` (g).
    #[arg(long, value_parser = crate::choice::choice::<AdditiveGain>(), default_value_t = FlatPatchJob::default().additive_gain, visible_alias = "gain-policy")]
    #[serde(with = "crate::params::named")]
    pub additive_gain: AdditiveGain,
    /// Side of the square patch, pixels.
    #[arg(long, default_value_t = FlatPatchJob::default().side_px)]
    pub side_px: usize,
    /// Seed of the photon and read noise.
    #[arg(long, default_value_t = FlatPatchJob::default().seed)]
    pub seed: u64,
    /// Read at this pixel gain instead of eq. 5.3's gain for the light and η.
    #[arg(long, value_name = "G")]
    pub gain: Option<f64>,
}

impl Default for FlatPatchJob {
    fn default() -> Self {
        FlatPatchJob {
            light: 0.0,
            eta: 2.0,
            sensor: DEFAULT_SENSOR.to_string(),
            bin: 1,
            bin_mode: BinMode::Digital,
            additive_gain: AdditiveGain::Scaled,
            side_px: 512,
            seed: 0,
            gain: None,
        }
    }
}

/// The sensor unless named: Table 5.4's.
const DEFAULT_SENSOR: &str = "table54";

fn named_sensor(name: &str) -> Result<SensorSpec> {
    SensorSpec::named(name).with_context(|| {
        format!(
            "unknown sensor `{name}` (expected one of: {})",
            PRESET_NAMES.join(", ")
        )
    })
}

/// Runs `sensor flat-patch`.
///
/// # Errors
/// Unknown sensors and bad values, naming the flag.
pub fn flat_patch(args: &FlatPatchJob, progress: &Progress) -> Result<Report> {
    let mut out = Report::default();
    let sensor = named_sensor(&args.sensor)?;
    let spec = FlatPatchSpec {
        light_e: args.light,
        eta: args.eta,
        bin_px: args.bin,
        bin_mode: args.bin_mode,
        additive_gain: args.additive_gain,
        side_px: args.side_px,
        seed: args.seed,
        gain: args.gain,
    };
    let res = udc_core::sensor::flat_patch(&spec, &sensor, progress)?;
    let mode = if spec.bin_px == 1 {
        "none".to_string()
    } else if spec.bin_mode == BinMode::AnalogAdditive {
        format!(
            "{0}×{0} additive ({1} gain)",
            spec.bin_px,
            spec.additive_gain.label()
        )
    } else {
        format!("{0}×{0} {1}", spec.bin_px, spec.bin_mode.label())
    };
    {
        out.json = json!({
            "saturated_fraction": r(res.saturated_fraction),
            "predicted": r(res.predicted),
            "gaussian_tail": r(res.gaussian_tail),
            "standard_error": r(res.standard_error),
            "readouts": res.readouts,
            "gain": r(res.gain),
            "amplifier_gain": r(res.amplifier_gain),
            "light_e": spec.light_e,
            "eta": spec.eta,
            "sensor": sensor.name,
            "bin_px": spec.bin_px,
            "bin_mode": spec.bin_mode.label(),
            "additive_gain": spec.additive_gain.label(),
            "side_px": spec.side_px,
            "seed": spec.seed,
            "gain_from": if spec.gain.is_some() { "--gain" } else { "eq. 5.3" },
            "variance_e2": r(res.variance_e2),
            "table51_variance_e2": r(res.table51_variance_e2),
            "variance_standard_error_e2": r(res.variance_standard_error_e2),
        });
    }
    outln!(
        out,
        "flat patch {0}×{0} px at {1} e⁻ on {2}, η {3}: gain {4:.4} ({5}), binning {mode}",
        spec.side_px,
        spec.light_e,
        sensor.name,
        spec.eta,
        res.gain,
        if spec.gain.is_some() {
            "--gain"
        } else {
            "eq. 5.3"
        }
    );
    outln!(
        out,
        "saturated {:.3} % of pixels (± {:.3} % standard error, {} readouts); predicted {:.3} % \
         (Poisson photons, Gaussian read noise, ADC top code); eq. 5.3's Gaussian 1 − Φ(η) = {:.3} %",
        100.0 * res.saturated_fraction,
        100.0 * res.standard_error,
        res.readouts,
        100.0 * res.predicted,
        100.0 * res.gaussian_tail
    );
    outln!(
        out,
        "variance of the estimate {:.4} e⁻² (± {:.4}); Table 5.1: {:.4} e⁻²",
        res.variance_e2,
        res.variance_standard_error_e2,
        res.table51_variance_e2
    );
    Ok(out)
}

/// Parses `mean:F`, `pP:F` or `abs:E` (see [`SensorJob::exposure`]).
///
/// # Errors
/// A message naming what is wrong.
pub fn parse_exposure(s: &str) -> Result<Exposure, ValueError> {
    let bad = |problem: String| ValueError::Unusable {
        value: s.to_string(),
        problem,
    };
    let (kind, value) = s
        .split_once(':')
        .ok_or_else(|| bad("expected mean:F, pP:F or abs:E (e.g. mean:0.05)".into()))?;
    let number = |t: &str| {
        t.trim()
            .parse::<f64>()
            .map_err(|_| bad(format!("`{t}` is not a number")))
    };
    let kind = kind.trim().to_ascii_lowercase();
    let e = match kind.as_str() {
        "mean" => Exposure::MeanFraction(number(value)?),
        "abs" => Exposure::ElectronsPerUm2(number(value)?),
        k if k.starts_with('p') => Exposure::PercentileFill {
            percentile: number(&k[1..])?,
            fill: number(value)?,
        },
        _ => return Err(bad("expected mean:F, pP:F or abs:E".into())),
    };
    e.validate().map_err(|err| bad(err.to_string()))?;
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

/// Runs `sensor`.
///
/// # Errors
/// Unknown sensors, unreadable scenes, invalid settings, unwritable outputs.
pub fn sensor(args: &SensorJob, progress: &Progress) -> Result<Report> {
    let mut out = Report::default();
    let Some(hdr) = &args.hdr else {
        bail!("--hdr is required (or a check such as `sensor flat-patch`)");
    };
    let sensor = named_sensor(&args.sensor)?;
    if args.max_side_px == Some(0) {
        bail!("--max-side-px must be at least 1");
    }
    let exposure = parse_exposure(&args.exposure).map_err(|e| anyhow::anyhow!("--exposure {e}"))?;
    let (mut scene, report) = load_hdr_with_report(hdr)?;
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
        additive_gain: args.additive_gain,
        roi_light: args.roi_light,
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
    let (rows, cols) = scene.dim();
    let mut outputs = Vec::new();
    if let Some(dir) = &args.out {
        // The budget first, so a refused run writes nothing.
        let planes_beside = match settings.cfa {
            Cfa::None => 0,
            Cfa::Rggb => scene.planes.len(),
        };
        check_budget((rows, cols), planes_beside, &settings, Held::HandedOver)?;
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create the output folder {}", dir.display()))?;
        let p = dir.join("scene.exr");
        write_scene_exr(&p, &scene, ExrPrecision::Half)?;
        outputs.push(p);
    }
    // A monochrome run needs only the luminance: hand the run that plane and let the RGB go.
    if settings.cfa == Cfa::None && scene.planes.len() != 1 {
        scene = Scene {
            planes: vec![scene.luminance()],
        };
    }
    let max_gain = settings.sensor.max_gain;
    // Each strategy's images are written as it finishes, and only its numbers are kept.
    let keep = |s: StrategyResult| -> Result<Kept> {
        if let Some(dir) = &args.out {
            outputs.extend(write_strategy_images(dir, &s, max_gain)?);
            if args.figures {
                outputs.extend(write_strategy_figures(dir, &s, max_gain)?);
            }
        }
        Ok(Kept::of(&s))
    };
    let result = run_with(scene, &settings, progress, Held::HandedOver, keep)?;
    if let Some(dir) = &args.out {
        outputs.extend(write_truth_images(dir, &result)?);
        if args.figures {
            let panel = udc_core::sensor::maps::scene_panel(&result);
            outputs.extend(udc_io::figure::write_panel(dir, "scene-figure", &panel)?);
        }
    }
    let notes = report.notes();
    {
        let mut v = udc_io::sensor::report::run_json(&result, |k: &Kept| k.json.clone());
        if let Some(obj) = v.as_object_mut() {
            let s = &settings.sensor;
            obj.insert("hdr".into(), json!(hdr.display().to_string()));
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
            obj.insert(
                "additive_gain".into(),
                json!(settings.additive_gain.label()),
            );
            obj.insert("roi_light".into(), json!(settings.roi_light.label()));
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
        out.json = v;
    }
    let s = &settings.sensor;
    outln!(
        out,
        "{} ({cols}×{rows}{}): sensor {} ({} µm, full well {} e⁻, σ_pre {} e⁻, σ_post {} e⁻, \
         gain ≤ {:.1}, {}-bit)",
        hdr.display(),
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
        outln!(
            out,
            "colour: {} Bayer mosaic, same-colour binning, Malvar-He-Cutler demosaic; scores on \
             the demosaiced luminance",
            settings.cfa.label().to_uppercase()
        );
    }
    let binning = match settings.bin_mode {
        BinMode::AnalogAdditive => format!("additive ({} gain)", settings.additive_gain.label()),
        m => m.label().to_string(),
    };
    outln!(
        out,
        "exposure: {} ({:.4} e⁻ per unit radiance); ROI {} px ({}×{}), gain from its {} light; \
         η {:?}; SNR_t {:?}; {binning} binning; {:.0} ms",
        exposure_text(&settings.exposure),
        result.electrons_per_radiance,
        settings.roi_px,
        result.grid.cols,
        result.grid.rows,
        settings.roi_light.label(),
        settings.eta,
        settings.snr_t,
        result.elapsed_ms
    );
    for n in &notes {
        outln!(out, "note: {n}");
    }
    outln!(
        out,
        "{:<22} {:>10} {:>9} {:>9} {:>10} {:>10} {:>8} {:>13} {:>10}",
        "strategy",
        "worst SSIM",
        "mean SSIM",
        "PSNR (dB)",
        "saturated",
        "sat. ROIs",
        "DR (dB)",
        "gain",
        "mean bin"
    );
    for st in &result.strategies {
        outln!(out, "{}", st.line);
    }
    print_channels(&mut out, &result);
    for p in &outputs {
        outln!(out, "wrote {}", p.display());
    }
    Ok(out)
}

/// What the command keeps of a strategy once its images are written: its JSON and its lines of
/// the text table.
struct Kept {
    json: serde_json::Value,
    line: String,
    channels: Option<String>,
}

impl Kept {
    fn of(st: &StrategyResult) -> Kept {
        let (lo, hi) = st
            .gain_map
            .iter()
            .fold((f32::INFINITY, 0.0f32), |(a, b), g| (a.min(*g), b.max(*g)));
        let mean_bin =
            st.bin_map.iter().map(|b| f64::from(*b)).sum::<f64>() / st.bin_map.len().max(1) as f64;
        let line = format!(
            "{:<22} {:>10.4} {:>9.4} {:>9.2} {:>9.2}% {:>9.1}% {:>8.1} {:>13} {:>10.2}",
            st.name,
            st.worst_roi_ssim,
            st.mean_ssim,
            st.psnr_db,
            100.0 * st.saturated_fraction,
            100.0 * st.saturated_roi_fraction,
            st.dynamic_range_db,
            format!("{lo:.1}–{hi:.1}"),
            mean_bin
        );
        let channels = st.colour.as_ref().map(|colour| {
            let mut text = format!("{:<22}", st.name);
            for ch in &colour.channels {
                text += &format!(
                    " {:>17}",
                    format!("{:.4} / {:.2}", ch.worst_roi_ssim, ch.psnr_db)
                );
            }
            text
        });
        Kept {
            json: strategy_json(st),
            line,
            channels,
        }
    }
}

/// With a colour filter array, the per-channel scores under the table.
fn print_channels(out: &mut Report, result: &udc_core::sensor::SensorRun<Kept>) {
    use udc_core::sensor::colour::CHANNEL_NAMES;
    if result.colour_truth.is_none() {
        return;
    }
    outln!(out, "per channel (worst ROI SSIM / PSNR dB):");
    out!(out, "{:<22}", "strategy");
    for c in CHANNEL_NAMES {
        out!(out, " {:>17}", c);
    }
    outln!(out);
    for line in result.strategies.iter().filter_map(|k| k.channels.as_ref()) {
        outln!(out, "{line}");
    }
}

/// A strategy's capture, gain and bin maps as the studio draws them, as figures (SVG and PNG)
/// named `<strategy>_<map>-figure`; `max_gain` tops the gain maps' shared scale.
fn write_strategy_figures(dir: &Path, s: &StrategyResult, max_gain: f64) -> Result<Vec<PathBuf>> {
    use udc_core::sensor::maps;
    let stem = udc_io::sensor::report::strategy_stem(&s.name);
    let mut written = Vec::new();
    for (map, panel) in [
        ("capture", maps::capture_panel(s)),
        ("gain", maps::gain_panel(s, max_gain)),
        ("bins", maps::bin_panel(s)),
    ] {
        written.extend(udc_io::figure::write_panel(
            dir,
            &format!("{stem}_{map}-figure"),
            &panel,
        )?);
    }
    Ok(written)
}
