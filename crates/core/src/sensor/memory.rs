//! What a sensor run holds at once, and the budget check it makes before it starts
//! ([`super::run_with`]; the Limits chapter has the measured peaks).

use super::{SensorSettings, colour};
use crate::SimError;

/// How much of a run [`peak_bytes`] counts on being held at once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Held {
    /// Every strategy's capture and maps, to the end ([`super::run`]).
    Kept,
    /// One strategy at a time, handed over and let go ([`super::run_with`] with a hand-over that
    /// keeps only numbers), with room for the hand-over to write its images.
    HandedOver,
}

/// Working bytes per scene pixel of a run, without its strategies and its scene: the exposed
/// scene (8), one exposure's draws (8, two `f32` planes) and a second exposure's or a
/// readout's working rows (8).
pub const FIXED_BYTES_PER_PIXEL: u64 = 24;

/// Bytes per scene pixel of one strategy's capture and maps: estimate (8), gain (4), bin (1)
/// and saturation (1).
pub const STRATEGY_BYTES_PER_PIXEL: u64 = 14;

/// What a hand-over may use per scene pixel while it writes a strategy's images (an 8-bit
/// grey picture and the encoders' buffers; the EXR is encoded as it is read).
pub const HANDOVER_BYTES_PER_PIXEL: u64 = 6;

/// The estimated peak working memory of a run on a scene of `dim`, bytes: `scene_planes`
/// planes of the scene held beside the run (none when the run takes over a monochrome scene),
/// [`FIXED_BYTES_PER_PIXEL`], and the strategies held (all of them, or one and
/// [`HANDOVER_BYTES_PER_PIXEL`]), with a colour sensor's extra planes.
pub fn peak_bytes(
    dim: (usize, usize),
    scene_planes: usize,
    settings: &SensorSettings,
    held: Held,
) -> u64 {
    let colour = colour::is_colour(settings.cfa);
    let strategy = STRATEGY_BYTES_PER_PIXEL
        + if colour {
            colour::KEPT_BYTES_PER_PIXEL
        } else {
            0
        };
    let strategies = match held {
        Held::Kept => settings.strategies.len() as u64 * strategy,
        Held::HandedOver => strategy + HANDOVER_BYTES_PER_PIXEL,
    };
    let per_pixel = 8 * scene_planes as u64
        + FIXED_BYTES_PER_PIXEL
        + strategies
        + if colour {
            colour::EXTRA_BYTES_PER_PIXEL
        } else {
            0
        };
    ((dim.0 * dim.1) as u64).saturating_mul(per_pixel)
}

/// Refuses a run whose [`peak_bytes`] the memory budget cannot hold, with the one-line budget
/// message; [`super::run_with`] calls it first, and a caller that writes files before the run can too.
///
/// # Errors
/// [`SimError::TooLarge`] above the budget.
pub fn check_budget(
    dim: (usize, usize),
    scene_planes: usize,
    settings: &SensorSettings,
    held: Held,
) -> Result<(), SimError> {
    let (rows, cols) = dim;
    crate::budget::check(
        &format!("simulating the sensor on a {cols}×{rows} scene"),
        peak_bytes(dim, scene_planes, settings, held),
        "use a smaller scene or crop it",
    )
}
