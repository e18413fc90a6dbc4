//! The flag behind a setting. The core names a bad setting by its [`Setting`]
//! (`SimError::InvalidField`); a setting that only a flag sets is reported to a command-line user
//! by that flag instead, as they typed it. One exhaustive `match`, applied once, where
//! [`crate::run`] returns: a new setting does not compile until it says whether a flag sets it.

use udc_core::{Field, Setting, SimError};

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
pub(crate) fn name_flags(e: anyhow::Error) -> anyhow::Error {
    match e.downcast::<SimError>() {
        Ok(SimError::InvalidField {
            field: Field::Setting(setting),
            message,
        }) => match flag_of(setting) {
            Some(flag) => anyhow::anyhow!("{flag}: {message}"),
            None => SimError::field(setting, message).into(),
        },
        Ok(other) => other.into(),
        Err(e) => e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_field_only_a_flag_sets_is_reported_by_its_flag() {
        let e = name_flags(SimError::field(Setting::ViewingDistanceMm, "must be above 0").into());
        assert_eq!(e.to_string(), "--viewing-distance-mm: must be above 0");
        let e = name_flags(SimError::field(Setting::OpeningCells, "too many").into());
        assert_eq!(e.to_string(), "field `opening.cells`: too many");
        // A path is not a setting, even where it spells one: only the core's typed key counts.
        let e = name_flags(SimError::field("nsr", "must be ≥ 0").into());
        assert_eq!(e.to_string(), "field `nsr`: must be ≥ 0");
        let e = name_flags(anyhow::anyhow!("not a core error"));
        assert_eq!(e.to_string(), "not a core error");
    }

    #[test]
    fn every_flag_in_the_table_exists_on_some_command() {
        use clap::CommandFactory;
        fn longs(c: &clap::Command, out: &mut Vec<String>) {
            out.extend(
                c.get_arguments()
                    .filter_map(|a| a.get_long())
                    .map(|l| format!("--{l}")),
            );
            for sub in c.get_subcommands() {
                longs(sub, out);
            }
        }
        let mut all = Vec::new();
        longs(&crate::Cli::command(), &mut all);
        for setting in Setting::ALL {
            if let Some(flag) = flag_of(setting) {
                assert!(
                    all.iter().any(|l| l == flag),
                    "{setting} → {flag}: no such flag"
                );
            }
        }
    }
}
