//! The settings the simulation names when it refuses a value: a closed set with one spelling
//! each. A design file's fields are named by their path in the file (`optics.window_px`); the
//! settings a command's flag or a studio control sets by the name the settings structs and their
//! JSON use (`light_e`). The CLI maps a setting to its flag and the studio to the label of its
//! control, each with an exhaustive `match`, so a new setting cannot be left out of either.
//!
//! Paths with an index (`opening.cells[3]`) stay text: the setting there is the array, and
//! [`Setting::of_path`] finds it.

use std::fmt;

/// A setting the core validates, named by its path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Setting {
    // The display design file.
    /// `optics.window_px`: the PSF window.
    OpticsWindowPx,
    /// `optics.pupil_sample_um`: δ1.
    OpticsPupilSampleUm,
    /// `optics.fine_sample_um`: δ2.
    OpticsFineSampleUm,
    /// `optics.sensor_pixel_um`.
    OpticsSensorPixelUm,
    /// `optics.focal_length_mm`.
    OpticsFocalLengthMm,
    /// `optics.f_number`.
    OpticsFNumber,
    /// `optics.axis_in_pixel_um`: where the optical axis sits in the pixel.
    OpticsAxisInPixelUm,
    /// `opening.pitch_um`: the display pixel pitch.
    OpeningPitchUm,
    /// `opening.cell_um`: the pitch over the opening grid.
    OpeningCellUm,
    /// `opening.cells`: the opening as a grid.
    OpeningCells,
    /// `opening.polygons`: the opening as polygons.
    OpeningPolygons,
    /// `tiling.wiring_gap_um`.
    TilingWiringGapUm,
    /// `tiling.origin_offset_cells`.
    TilingOriginOffsetCells,
    /// `tiling.mode`.
    TilingMode,
    /// `tiling.seed`: the random tiling's seed.
    TilingSeed,
    // Restoration and capture (display workspace, `restore`).
    /// `capture.light.snr_db`.
    CaptureSnrDb,
    /// `capture.light.electrons_at_peak`.
    CaptureElectronsAtPeak,
    /// `capture.adc_bits`.
    CaptureAdcBits,
    /// `method.nsr`: the Wiener filter's noise-to-signal ratio.
    MethodNsr,
    /// `method.lambda`: the gradient prior's weight.
    MethodLambda,
    // The opening optimizer.
    /// `epochs`.
    Epochs,
    /// `target_open_fraction`.
    TargetOpenFraction,
    /// `weights.area`.
    WeightArea,
    /// `weights.inv`.
    WeightInv,
    /// `weights.data`.
    WeightData,
    // The sensor (chapter 5).
    /// `eta`: the sensor's quantum efficiency.
    Eta,
    /// `eta_per_pixel`.
    EtaPerPixel,
    /// `roi_px`: the region of interest.
    RoiPx,
    /// `snr_t`: the SNR threshold of the gain map.
    SnrT,
    /// `light_e`: electrons at the brightest pixel.
    LightE,
    /// `bin_px`.
    BinPx,
    /// `side_px`.
    SidePx,
    /// `gain`.
    Gain,
    /// `clip_percent`.
    ClipPercent,
    /// `brackets`: the exposure brackets.
    Brackets,
    /// `step_ev`: the exposure step between brackets.
    StepEv,
    // Field-of-view, depth and appearance studies.
    /// `photo`: the photo a study captures.
    Photo,
    /// `display_distance_mm`.
    DisplayDistanceMm,
    /// `max_field_deg`.
    MaxFieldDeg,
    /// `grid`: the field grid's side.
    Grid,
    /// `nsr`: a study's Wiener noise-to-signal ratio.
    Nsr,
    /// `object_distance_mm`.
    ObjectDistanceMm,
    /// `focal_mm`.
    FocalMm,
    /// `dpi`.
    Dpi,
    /// `viewing_distance_mm`.
    ViewingDistanceMm,
    /// `region_mm`.
    RegionMm,
    /// `acuity_arcmin`.
    AcuityArcmin,
}

impl Setting {
    /// Every setting.
    pub const ALL: [Setting; 47] = [
        Setting::OpticsWindowPx,
        Setting::OpticsPupilSampleUm,
        Setting::OpticsFineSampleUm,
        Setting::OpticsSensorPixelUm,
        Setting::OpticsFocalLengthMm,
        Setting::OpticsFNumber,
        Setting::OpticsAxisInPixelUm,
        Setting::OpeningPitchUm,
        Setting::OpeningCellUm,
        Setting::OpeningCells,
        Setting::OpeningPolygons,
        Setting::TilingWiringGapUm,
        Setting::TilingOriginOffsetCells,
        Setting::TilingMode,
        Setting::TilingSeed,
        Setting::CaptureSnrDb,
        Setting::CaptureElectronsAtPeak,
        Setting::CaptureAdcBits,
        Setting::MethodNsr,
        Setting::MethodLambda,
        Setting::Epochs,
        Setting::TargetOpenFraction,
        Setting::WeightArea,
        Setting::WeightInv,
        Setting::WeightData,
        Setting::Eta,
        Setting::EtaPerPixel,
        Setting::RoiPx,
        Setting::SnrT,
        Setting::LightE,
        Setting::BinPx,
        Setting::SidePx,
        Setting::Gain,
        Setting::ClipPercent,
        Setting::Brackets,
        Setting::StepEv,
        Setting::Photo,
        Setting::DisplayDistanceMm,
        Setting::MaxFieldDeg,
        Setting::Grid,
        Setting::Nsr,
        Setting::ObjectDistanceMm,
        Setting::FocalMm,
        Setting::Dpi,
        Setting::ViewingDistanceMm,
        Setting::RegionMm,
        Setting::AcuityArcmin,
    ];

    /// Its path in a design or settings file, as messages name it.
    pub fn path(self) -> &'static str {
        match self {
            Setting::OpticsWindowPx => "optics.window_px",
            Setting::OpticsPupilSampleUm => "optics.pupil_sample_um",
            Setting::OpticsFineSampleUm => "optics.fine_sample_um",
            Setting::OpticsSensorPixelUm => "optics.sensor_pixel_um",
            Setting::OpticsFocalLengthMm => "optics.focal_length_mm",
            Setting::OpticsFNumber => "optics.f_number",
            Setting::OpticsAxisInPixelUm => "optics.axis_in_pixel_um",
            Setting::OpeningPitchUm => "opening.pitch_um",
            Setting::OpeningCellUm => "opening.cell_um",
            Setting::OpeningCells => "opening.cells",
            Setting::OpeningPolygons => "opening.polygons",
            Setting::TilingWiringGapUm => "tiling.wiring_gap_um",
            Setting::TilingOriginOffsetCells => "tiling.origin_offset_cells",
            Setting::TilingMode => "tiling.mode",
            Setting::TilingSeed => "tiling.seed",
            Setting::CaptureSnrDb => "capture.light.snr_db",
            Setting::CaptureElectronsAtPeak => "capture.light.electrons_at_peak",
            Setting::CaptureAdcBits => "capture.adc_bits",
            Setting::MethodNsr => "method.nsr",
            Setting::MethodLambda => "method.lambda",
            Setting::Epochs => "epochs",
            Setting::TargetOpenFraction => "target_open_fraction",
            Setting::WeightArea => "weights.area",
            Setting::WeightInv => "weights.inv",
            Setting::WeightData => "weights.data",
            Setting::Eta => "eta",
            Setting::EtaPerPixel => "eta_per_pixel",
            Setting::RoiPx => "roi_px",
            Setting::SnrT => "snr_t",
            Setting::LightE => "light_e",
            Setting::BinPx => "bin_px",
            Setting::SidePx => "side_px",
            Setting::Gain => "gain",
            Setting::ClipPercent => "clip_percent",
            Setting::Brackets => "brackets",
            Setting::StepEv => "step_ev",
            Setting::Photo => "photo",
            Setting::DisplayDistanceMm => "display_distance_mm",
            Setting::MaxFieldDeg => "max_field_deg",
            Setting::Grid => "grid",
            Setting::Nsr => "nsr",
            Setting::ObjectDistanceMm => "object_distance_mm",
            Setting::FocalMm => "focal_mm",
            Setting::Dpi => "dpi",
            Setting::ViewingDistanceMm => "viewing_distance_mm",
            Setting::RegionMm => "region_mm",
            Setting::AcuityArcmin => "acuity_arcmin",
        }
    }

    /// The setting a path names, an indexed path (`opening.cells[3][4]`) included.
    pub fn of_path(path: &str) -> Option<Setting> {
        let base = path.split('[').next().unwrap_or(path);
        Setting::ALL.into_iter().find(|s| s.path() == base)
    }
}

impl fmt::Display for Setting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.path())
    }
}

/// What an [`crate::SimError::InvalidSetting`] names: a setting, or a path inside one (an array
/// element, a sweep axis) written out.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SettingPath {
    /// A setting as a whole.
    Setting(Setting),
    /// A path the closed set does not hold: an element (`opening.cells[3]`), a sweep spec's
    /// own fields (`axis[1].range.step`), a study's inputs.
    Path(String),
}

impl SettingPath {
    /// The path as messages print it.
    pub fn path(&self) -> &str {
        match self {
            SettingPath::Setting(s) => s.path(),
            SettingPath::Path(p) => p,
        }
    }

    /// The setting this field is or is inside of, if any.
    pub fn setting(&self) -> Option<Setting> {
        match self {
            SettingPath::Setting(s) => Some(*s),
            SettingPath::Path(p) => Setting::of_path(p),
        }
    }
}

impl fmt::Display for SettingPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.path())
    }
}

impl From<Setting> for SettingPath {
    fn from(s: Setting) -> Self {
        SettingPath::Setting(s)
    }
}

impl From<&str> for SettingPath {
    fn from(p: &str) -> Self {
        SettingPath::Path(p.to_string())
    }
}

impl From<String> for SettingPath {
    fn from(p: String) -> Self {
        SettingPath::Path(p)
    }
}

impl PartialEq<str> for SettingPath {
    fn eq(&self, other: &str) -> bool {
        self.path() == other
    }
}

impl PartialEq<&str> for SettingPath {
    fn eq(&self, other: &&str) -> bool {
        self.path() == *other
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_setting_is_listed_once_with_its_own_path() {
        let mut paths: Vec<&str> = Setting::ALL.iter().map(|s| s.path()).collect();
        paths.sort_unstable();
        paths.dedup();
        assert_eq!(paths.len(), Setting::ALL.len());
        for s in Setting::ALL {
            assert_eq!(Setting::of_path(s.path()), Some(s));
        }
    }

    #[test]
    fn an_indexed_path_is_inside_its_setting() {
        assert_eq!(
            Setting::of_path("opening.cells[3][4]"),
            Some(Setting::OpeningCells)
        );
        assert_eq!(
            SettingPath::from("optics.axis_in_pixel_um[1]").setting(),
            Some(Setting::OpticsAxisInPixelUm)
        );
        assert_eq!(SettingPath::from("axis[1].range.step").setting(), None);
        assert_eq!(SettingPath::from(Setting::LightE).to_string(), "light_e");
    }
}
