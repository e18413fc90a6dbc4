//! The bin-size study as CSV: one row per capture, the sweep (Fig. 5.4a) then the mode
//! comparison (Fig. 5.4b), with the predicted and the best bin of the capture's light level.

use udc_core::sensor::BinMode;
use udc_core::sensor::study::BinStudy;

/// The header of [`bin_study_csv`].
pub const HEADER: &str = "part,light_e_per_um2,bin_px,mode,additive_gain,gain,ssim,psnr_db,saturated_fraction,predicted_bin_px,best_bin_px";

/// The study's CSV text (comma-separated, `.` decimals, one header line). The mode comparison's
/// predicted and best bins are left empty: they belong to the sweep's mode and gain.
pub fn bin_study_csv(study: &BinStudy) -> String {
    let mut out = String::from(HEADER);
    out.push('\n');
    let parts = [("sweep", &study.sweep), ("modes", &study.modes)];
    for (part, captures) in parts {
        for c in captures {
            let choice = (part == "sweep")
                .then(|| {
                    study
                        .choices
                        .iter()
                        .find(|k| k.light_e_per_um2 == c.light_e_per_um2)
                })
                .flatten();
            // The amplifier-gain policy only means something for additive bins.
            let additive = if c.mode == BinMode::AnalogAdditive {
                c.additive_gain.label()
            } else {
                ""
            };
            let (predicted, best) = choice.map_or((String::new(), String::new()), |k| {
                (k.predicted_bin.to_string(), k.best_bin.to_string())
            });
            out.push_str(&format!(
                "{part},{},{},{},{},{},{:.6},{:.4},{:.6},{predicted},{best}\n",
                c.light_e_per_um2,
                c.bin,
                c.mode.label(),
                additive,
                c.gain,
                c.ssim,
                c.psnr_db,
                c.saturated_fraction,
            ));
        }
    }
    out
}
