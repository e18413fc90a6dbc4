//! The analysis as JSON: the `udc-studio analyze --json` contract other tools depend on.
//! Field names are fixed; new fields may be added, none renamed.

use serde_json::{Value, json};

use crate::core::Analysis;
use crate::core::analyze::Quality;

/// Analysis reports keep 9 significant digits.
fn r(v: f64) -> f64 {
    super::numbers::round_sig(v, 9)
}

fn rs(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| r(*x)).collect()
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
        "warnings": a.warnings,
        "elapsed_ms": (a.elapsed_ms * 1000.0).round() / 1000.0,
        "quality": match a.quality { Quality::Full => "full", Quality::Preview => "preview" },
        "window_px": a.window_px,
        "sensor_pixel_um": a.sensor_pixel_um,
        "pupil_diameter_um": r(a.pupil_diameter_um),
        "tiles_in_pupil": r(a.tiles_in_pupil),
        "channels": channels,
    })
}
