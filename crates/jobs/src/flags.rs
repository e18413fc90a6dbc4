//! The flag behind a setting. The core names a bad setting by its [`Setting`]
//! (`SimError::InvalidSetting`); a setting that only a flag sets is reported to a command-line user
//! by that flag instead, as they typed it. One exhaustive `match`, applied once, where
//! [`crate::run`] returns: a new setting does not compile until it says whether a flag sets it.

use udc_core::{Setting, SettingPath, SimError};

/// The flag that sets `setting`, if only a flag does (a design file's fields are named by their
/// path in the file).
pub fn flag_of(setting: Setting) -> Option<&'static str> {
    Some(match setting {
        Setting::Eta => "--eta",
        Setting::EtaPerPixel => "--eta-per-pixel",
        Setting::CaptureSnrDb => "--snr-db",
        Setting::CaptureElectronsAtPeak | Setting::LightE => "--light",
        Setting::CaptureAdcBits => "--adc-bits",
        Setting::MethodNsr | Setting::Nsr => "--nsr",
        Setting::MethodLambda => "--lambda",
        Setting::Epochs => "--epochs",
        Setting::TargetOpenFraction => "--area",
        Setting::WeightArea => "--weight-area",
        Setting::WeightInv => "--weight-inv",
        Setting::WeightData => "--weight-data",
        Setting::RoiPx => "--roi",
        Setting::SnrT => "--snr-t",
        Setting::Photo => "--image",
        Setting::DisplayDistanceMm => "--display-distance-mm",
        Setting::MaxFieldDeg => "--max-field-deg",
        Setting::Grid => "--grid",
        Setting::ObjectDistanceMm => "--object-distance-mm",
        Setting::FocalMm => "--focal-mm",
        Setting::BinPx => "--bin",
        Setting::SidePx => "--side-px",
        Setting::Gain => "--gain",
        Setting::ClipPercent => "--clip-percent",
        Setting::Brackets => "--brackets",
        Setting::StepEv => "--step-ev",
        Setting::Dpi => "--dpi",
        Setting::ViewingDistanceMm => "--viewing-distance-mm",
        Setting::RegionMm => "--region-mm",
        Setting::AcuityArcmin => "--acuity-arcmin",
        Setting::OpticsWindowPx
        | Setting::OpticsPupilSampleUm
        | Setting::OpticsFineSampleUm
        | Setting::OpticsSensorPixelUm
        | Setting::OpticsFocalLengthMm
        | Setting::OpticsFNumber
        | Setting::OpticsAxisInPixelUm
        | Setting::OpeningPitchUm
        | Setting::OpeningCellUm
        | Setting::OpeningCells
        | Setting::OpeningPolygons
        | Setting::TilingWiringGapUm
        | Setting::TilingOriginOffsetCells
        | Setting::TilingMode
        | Setting::TilingSeed => return None,
    })
}

/// A core error about a setting that only a flag sets names the flag; every other error is
/// returned as it is.
pub fn name_flags(e: anyhow::Error) -> anyhow::Error {
    match e.downcast::<SimError>() {
        Ok(SimError::InvalidSetting {
            path: SettingPath::Setting(setting),
            message,
        }) => match flag_of(setting) {
            Some(flag) => anyhow::anyhow!("{flag}: {message}"),
            None => SimError::invalid(setting, message).into(),
        },
        Ok(other) => other.into(),
        Err(e) => e,
    }
}
