//! Whether a capture through an analysed design keeps its light (conventions.md §5): each
//! channel's PSF window must hold at least
//! [`crate::restore::light::MIN_CAPTURE_ENERGY_IN_WINDOW`] of the
//! light reaching the sensor; when it does not, one line says which channels hold how much and
//! what fixes it. `restore` (CLI, studio, Python) says it before capturing.

use crate::analysis::analyze::Analysis;
use crate::psf::warning::WarningKind;
use crate::restore::light::MIN_CAPTURE_ENERGY_IN_WINDOW;

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
