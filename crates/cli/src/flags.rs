//! The flag behind a setting. The core names a bad setting by its field (`SimError::InvalidField`,
//! the path in the design or settings file); a setting that only a flag sets is reported to a
//! command-line user by that flag instead, as they typed it. One table for every command, applied
//! once, where [`crate::run`] returns.

use udc_core::SimError;

/// Settings that only a flag sets, by the field name the core reports, and their flag.
const FLAG_OF_FIELD: [(&str, &str); 32] = [
    ("eta", "--eta"),
    ("eta_per_pixel", "--eta-per-pixel"),
    ("capture.light.snr_db", "--snr-db"),
    ("capture.light.electrons_at_peak", "--light"),
    ("capture.adc_bits", "--adc-bits"),
    ("method.nsr", "--nsr"),
    ("method.lambda", "--lambda"),
    ("epochs", "--epochs"),
    ("target_open_fraction", "--area"),
    ("weights.area", "--weight-area"),
    ("weights.inv", "--weight-inv"),
    ("weights.data", "--weight-data"),
    ("roi_px", "--roi"),
    ("snr_t", "--snr-t"),
    ("photo", "--image"),
    ("display_distance_mm", "--display-distance-mm"),
    ("max_field_deg", "--max-field-deg"),
    ("grid", "--grid"),
    ("nsr", "--nsr"),
    ("object_distance_mm", "--object-distance-mm"),
    ("focal_mm", "--focal-mm"),
    ("light_e", "--light"),
    ("bin_px", "--bin"),
    ("side_px", "--side-px"),
    ("gain", "--gain"),
    ("clip_percent", "--clip-percent"),
    ("brackets", "--brackets"),
    ("step_ev", "--step-ev"),
    ("dpi", "--dpi"),
    ("viewing_distance_mm", "--viewing-distance-mm"),
    ("region_mm", "--region-mm"),
    ("acuity_arcmin", "--acuity-arcmin"),
];

/// The flag that sets `field`, if only a flag does.
pub fn flag_of(field: &str) -> Option<&'static str> {
    FLAG_OF_FIELD
        .iter()
        .find(|(f, _)| *f == field)
        .map(|(_, flag)| *flag)
}

/// A core error about a setting that only a flag sets names the flag; every other error is
/// returned as it is.
pub(crate) fn name_flags(e: anyhow::Error) -> anyhow::Error {
    match e.downcast::<SimError>() {
        Ok(SimError::InvalidField { field, message }) => match flag_of(&field) {
            Some(flag) => anyhow::anyhow!("{flag}: {message}"),
            None => SimError::InvalidField { field, message }.into(),
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
        let e = name_flags(SimError::field("viewing_distance_mm", "must be above 0").into());
        assert_eq!(e.to_string(), "--viewing-distance-mm: must be above 0");
        let e = name_flags(SimError::field("opening.cells", "too many").into());
        assert_eq!(e.to_string(), "field `opening.cells`: too many");
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
        for (field, flag) in FLAG_OF_FIELD {
            assert!(
                all.iter().any(|l| l == flag),
                "{field} → {flag}: no such flag"
            );
        }
    }
}
