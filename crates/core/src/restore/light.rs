//! A capture conserves light (conventions.md §5): the PSF it blurs with must hold at least
//! [`MIN_CAPTURE_ENERGY_IN_WINDOW`] of the light that reaches the sensor plane. Every PSF is
//! normalised to sum 1 over its window, so light scattered beyond the window would otherwise be
//! dropped as if it never arrived; on a real sensor it lands as haze, and dropping it flatters the
//! fine pitches that scatter far (a P-OLED at 300 DPI keeps about half its light in a 294-pixel
//! window). The check is one line, with the advice that fixes it.

use crate::analysis::analyze::Analysis;
use crate::psf::warning::WarningKind;

/// The least share of a channel's light that a capture's PSF window must hold. The thesis's
/// own recipe (150 DPI, 294-pixel window) holds 97.9 % in R.
pub const MIN_CAPTURE_ENERGY_IN_WINDOW: f64 = 0.97;

/// The channels of `analysis` whose window holds less than [`MIN_CAPTURE_ENERGY_IN_WINDOW`] of
/// their light, as `(name, share held)`.
pub fn channels_losing_light(analysis: &Analysis) -> Vec<(&str, f64)> {
    analysis
        .channels
        .iter()
        .filter(|c| !(c.energy_in_window >= MIN_CAPTURE_ENERGY_IN_WINDOW))
        .map(|c| (c.name.as_str(), c.energy_in_window))
        .collect()
}

/// One line when a capture through `analysis` would drop more than 3 % of the light reaching
/// the sensor, naming the channels, the share each window holds, and the fix; `None` when every
/// channel's window holds enough.
pub fn capture_light_warning(analysis: &Analysis) -> Option<String> {
    let losing = channels_losing_light(analysis);
    if losing.is_empty() {
        return None;
    }
    let held: Vec<String> = losing
        .iter()
        .map(|(name, share)| format!("{:.1} % in {name}", 100.0 * share))
        .collect();
    // The analysis's own light-outside-window warning carries the computed fix when advice
    // found one; otherwise the general remedy.
    let fix = analysis
        .warnings
        .iter()
        .find(|w| w.kind == WarningKind::LightOutsideWindow)
        .and_then(|w| w.fix.as_ref())
        .map_or_else(
            || {
                "enlarge optics.window_px (and decrease optics.pupil_sample_um with it once the \
                 window fills the FFT grid)"
                    .to_string()
            },
            |f| format!("set {}", f.assignments()),
        );
    Some(format!(
        "capture: the {}-pixel PSF window holds {} of the light reaching the sensor (a capture \
         needs {:.0} %); the rest would land as haze, which this capture leaves out: {fix}",
        analysis.window_px,
        held.join(", "),
        100.0 * MIN_CAPTURE_ENERGY_IN_WINDOW
    ))
}
