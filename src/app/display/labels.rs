//! The settings as the studio shows them: the simulation's messages name a setting by its path
//! (`optics.window_px`), the user knows the label and the tab it sits on.

use crate::core::Setting;

/// Where the user finds `setting` in the studio, for the settings the Display workspace edits
/// (one exhaustive `match`, as the CLI's flags: a new setting must say whether it has a label).
pub fn label(setting: Setting) -> Option<&'static str> {
    Some(match setting {
        Setting::OpticsWindowPx => "Optics > Window",
        Setting::OpticsPupilSampleUm => "Optics > Pupil sampling δ1",
        Setting::OpticsFineSampleUm => "Optics > Fine PSF spacing δ2",
        Setting::OpticsSensorPixelUm => "Optics > Sensor pixel",
        Setting::OpticsFocalLengthMm => "Optics > Focal length",
        Setting::OpticsFNumber => "Optics > f-number",
        Setting::OpticsAxisInPixelUm => "Optics > Axis in pixel",
        Setting::OpeningPitchUm => "the pixel pitch",
        Setting::OpeningCellUm => "the cell size (pitch / Opening > grid)",
        Setting::OpeningCells => "the opening",
        Setting::OpeningPolygons => "the opening's polygons",
        Setting::TilingWiringGapUm => "Tiling > Wiring gap",
        Setting::TilingOriginOffsetCells => "Tiling > Axis on cell",
        Setting::TilingMode => "Tiling > mode",
        // Set by the other workspaces' own controls, whose messages name the setting as the
        // settings files do.
        Setting::TilingSeed
        | Setting::CaptureSnrDb
        | Setting::CaptureElectronsAtPeak
        | Setting::CaptureAdcBits
        | Setting::MethodNsr
        | Setting::MethodLambda
        | Setting::Epochs
        | Setting::TargetOpenFraction
        | Setting::WeightArea
        | Setting::WeightInv
        | Setting::WeightData
        | Setting::Eta
        | Setting::EtaPerPixel
        | Setting::RoiPx
        | Setting::SnrT
        | Setting::LightE
        | Setting::BinPx
        | Setting::SidePx
        | Setting::Gain
        | Setting::ClipPercent
        | Setting::Brackets
        | Setting::StepEv
        | Setting::Photo
        | Setting::DisplayDistanceMm
        | Setting::MaxFieldDeg
        | Setting::Grid
        | Setting::Nsr
        | Setting::ObjectDistanceMm
        | Setting::FocalMm
        | Setting::Dpi
        | Setting::ViewingDistanceMm
        | Setting::RegionMm
        | Setting::AcuityArcmin => return None,
    })
}

/// `message` with every design field it names replaced by the label the studio shows, and its
/// arrows in words the studio's font can draw.
pub fn in_ui_words(message: &str) -> String {
    // Longest paths first, so that no path is replaced inside a longer one; built once, since
    // messages are put into words while drawing.
    static LABELLED: std::sync::LazyLock<Vec<(&str, &str)>> = std::sync::LazyLock::new(|| {
        let mut labelled: Vec<(&str, &str)> = Setting::ALL
            .into_iter()
            .filter_map(|s| label(s).map(|l| (s.path(), l)))
            .collect();
        labelled.sort_by_key(|(path, _)| std::cmp::Reverse(path.len()));
        labelled
    });
    let mut out = message.to_string();
    for &(field, label) in LABELLED.iter() {
        // Backquoted first, so `optics.window_px` does not keep its quotes around the label.
        out = out
            .replace(&format!("`{field}`"), label)
            .replace(field, label);
    }
    // The studio's proportional font (Ubuntu Light) has no arrow: "δ1 8 → 4 µm" reads
    // "δ1 8 to 4 µm".
    out.replace(" → ", " to ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_become_the_labels_the_user_sees() {
        assert_eq!(
            in_ui_words("the window is small; enlarge optics.window_px"),
            "the window is small; enlarge Optics > Window"
        );
        assert_eq!(
            in_ui_words("`optics.pupil_sample_um` must be positive"),
            "Optics > Pupil sampling δ1 must be positive"
        );
        assert_eq!(in_ui_words("no field here"), "no field here");
        assert_eq!(
            in_ui_words("optics.window_px: 294 → 588 px"),
            "Optics > Window: 294 to 588 px"
        );
    }
}
