//! The analysis as JSON: the `udc-studio analyze --json` contract other tools depend on.
//! Field names are fixed; new fields may be added, none renamed.

use serde_json::{Value, json};

use udc_core::Analysis;
use udc_core::analysis::analyze::Quality;
use udc_core::psf::warning::{OpticsField, SamplingWarning};

/// Analysis reports keep 9 significant digits.
fn r(v: f64) -> f64 {
    crate::numbers::round_sig(v, 9)
}

fn rs(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| r(*x)).collect()
}

/// The `warnings` array of a report: each warning's message, a plain string.
pub fn warning_messages(warnings: &[SamplingWarning]) -> Vec<&str> {
    warnings.iter().map(|w| w.message.as_str()).collect()
}

/// The `advice` array of a report, parallel to `warnings`: per warning its `kind`
/// (`light-outside-window`, …), `severity` (`note` or `warning`), `message`, and `fix`: `null`,
/// or `{"summary": "δ1 8 → 4 µm, window 294 → 588 px", "set": {"optics.pupil_sample_um": 4.0,
/// "optics.window_px": 588}}`, the design-file values to set.
pub fn advice_json(warnings: &[SamplingWarning]) -> Value {
    let each = warnings.iter().map(|w| {
        let fix = w.fix.as_ref().map(|f| {
            let set: serde_json::Map<String, Value> = f
                .changes
                .iter()
                .map(|c| {
                    let v = match c.field {
                        OpticsField::Window => json!(c.to.round() as u64),
                        OpticsField::PupilSample | OpticsField::FineSample => json!(c.to),
                    };
                    (c.field.path().to_string(), v)
                })
                .collect();
            json!({ "summary": f.summary(), "set": set })
        });
        json!({
            "kind": w.kind.as_str(),
            "severity": w.severity.as_str(),
            "message": w.message,
            "fix": fix,
        })
    });
    Value::Array(each.collect())
}

/// The JSON object printed by `analyze --json`.
pub fn analysis_json(a: &Analysis) -> Value {
    let channels: Vec<Value> = a
        .channels
        .iter()
        .map(|c| {
            json!({
                "name": c.name,
                "wavelength_nm": r(c.wavelength_nm),
                "wavelengths_nm": c.wavelengths_nm,
                "fft_size": c.fft_sizes.first().copied().unwrap_or(0),
                "fft_sizes": c.fft_sizes,
                "fine_sample_um": r(c.fine_um),
                "auc_radial_min": r(c.mtf.auc_radial_min),
                "auc_radial_min_normalised": r(c.mtf.auc_normalised()),
                "auc_radial_mean": r(c.mtf.auc_radial_mean),
                "freq_cyc_per_px": rs(&c.mtf.freqs_cyc_per_px()),
                "radial_min": rs(&c.mtf.radial_min),
                "radial_mean": rs(&c.mtf.radial_mean),
                "mtf_horizontal": rs(&c.mtf.horizontal),
                "mtf_vertical": rs(&c.mtf.vertical),
                "energy_in_window": r(c.energy_in_window),
                "invertibility": r(c.invertibility),
            })
        })
        .collect();
    json!({
        "open_fraction": r(a.open_fraction),
        "ltr": r(a.ltr),
        "invertibility_loss": r(a.invertibility_loss),
        "auc_radial_min_mean": r(a.channels.iter().map(|c| c.mtf.auc_radial_min).sum::<f64>()
            / a.channels.len().max(1) as f64),
        "warnings": warning_messages(&a.warnings),
        "advice": advice_json(&a.warnings),
        "elapsed_ms": (a.elapsed_ms * 1000.0).round() / 1000.0,
        "quality": match a.quality { Quality::Full => "full", Quality::Preview => "preview" },
        "window_px": a.window_px,
        "sensor_pixel_um": a.sensor_pixel_um,
        "pupil_diameter_um": r(a.pupil_diameter_um),
        "tiles_in_pupil": r(a.tiles_in_pupil),
        "channels": channels,
    })
}
