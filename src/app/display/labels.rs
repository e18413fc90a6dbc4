//! The design's fields as the studio shows them: the simulation's messages name fields
//! (`optics.window_px`), the user knows the label and the tab it sits on.

/// Each design field the simulation's messages name, and where the user finds it.
const FIELDS: &[(&str, &str)] = &[
    ("optics.window_px", "Optics > Window"),
    ("optics.pupil_sample_um", "Optics > Pupil sampling δ1"),
    ("optics.fine_sample_um", "Optics > Fine PSF spacing δ2"),
    ("optics.sensor_pixel_um", "Optics > Sensor pixel"),
    ("optics.focal_length_mm", "Optics > Focal length"),
    ("optics.f_number", "Optics > f-number"),
    ("optics.axis_in_pixel_um", "Optics > Axis in pixel"),
    ("opening.pitch_um", "the pixel pitch"),
    ("opening.cell_um", "the cell size (pitch / Opening > grid)"),
    ("opening.cells", "the opening"),
    ("opening.polygons", "the opening's polygons"),
    ("tiling.wiring_gap_um", "Tiling > Wiring gap"),
    ("tiling.origin_offset_cells", "Tiling > Axis on cell"),
    ("tiling.mode", "Tiling > mode"),
];

/// `message` with every design field it names replaced by the label the studio shows, and its
/// arrows in words the studio's font can draw.
pub fn in_ui_words(message: &str) -> String {
    let mut out = message.to_string();
    for (field, label) in FIELDS {
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
