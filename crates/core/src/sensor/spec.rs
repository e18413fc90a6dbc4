//! Sensors: the noise parameters of eq. 5.1 and the presets of thesis Tables 5.4 and 5.2.

use crate::SimError;

/// One image sensor as eq. 5.1 sees it. Electrons are photo-electrons of one unit pixel; read
/// noise is referred to the pixel at base gain (`σ_post` is divided by the gain, `σ_pre` is not).
#[derive(Debug, Clone, PartialEq)]
pub struct SensorSpec {
    /// Short name, as the CLI's `--sensor` takes it.
    pub name: String,
    /// One line for menus and reports.
    pub description: String,
    /// Pitch of one unit (unbinned) pixel, µm.
    pub unit_pixel_um: f64,
    /// Well capacity `l_wc`: the electrons that fill the ADC's range at base gain.
    pub full_well_e: f64,
    /// Pre-amplifier read noise, electrons RMS.
    pub sigma_pre_e: f64,
    /// Post-amplifier read noise at base gain, electrons RMS.
    pub sigma_post_e: f64,
    /// Largest analog gain, as a multiple of the base gain (1).
    pub max_gain: f64,
    /// ADC resolution: codes `0 … 2^bits − 1`.
    pub adc_bits: u32,
    /// Black level `i0` as a fraction of the ADC's range (0.05: code 205 of 4095).
    pub black_level_fraction: f64,
}

/// The names of [`SensorSpec::presets`], in order.
pub const PRESET_NAMES: [&str; 5] = [
    "table54",
    "nikon-z5",
    "nexus-6p",
    "bfs-u3-200s6c",
    "bfs-u3-16s2m",
];

/// A gain in dB (20 log10) as a factor.
fn db(gain_db: f64) -> f64 {
    10f64.powf(gain_db / 20.0)
}

/// A camera of Table 5.2. Its σ are in ADU at base gain; read as electrons (1 e⁻/ADU), and with
/// a 5 % black level, the full well is the ADC's range above the black level.
fn table52(
    name: &str,
    description: &str,
    unit_pixel_um: f64,
    adc_bits: u32,
    (sigma_pre_e, sigma_post_e): (f64, f64),
    max_gain: f64,
) -> SensorSpec {
    let black = 0.05;
    let codes = f64::from((1u32 << adc_bits) - 1);
    SensorSpec {
        name: name.into(),
        description: description.into(),
        unit_pixel_um,
        full_well_e: (codes - (black * codes).round()).round(),
        sigma_pre_e,
        sigma_post_e,
        max_gain,
        adc_bits,
        black_level_fraction: black,
    }
}

impl SensorSpec {
    /// The simulated sensor of Table 5.4 (§5.7): 0.5 µm pixels, 1000 e⁻ full well,
    /// σ_pre 0.33 e⁻, σ_post 3.31 e⁻, 12 bits, 5 % black level. The thesis does not state its
    /// maximum gain; 64× (36 dB) is used, where σ_post/g is a tenth of σ_pre.
    pub fn table54() -> SensorSpec {
        SensorSpec {
            name: "table54".into(),
            description: "Table 5.4's simulated sensor: 0.5 µm, 1000 e⁻, σ 0.33/3.31 e⁻".into(),
            unit_pixel_um: 0.5,
            full_well_e: 1000.0,
            sigma_pre_e: 0.33,
            sigma_post_e: 3.31,
            max_gain: 64.0,
            adc_bits: 12,
            black_level_fraction: 0.05,
        }
    }

    /// Table 5.4's sensor and the four cameras of Table 5.2, with their maximum gains (ISO
    /// 51200 / 100, ISO 7656 / 60, 27 dB, 48 dB). For the cameras, σ_pre and σ_post are
    /// Table 5.2's; pixel pitch and ADC depth come from the public spec sheets (Nikon Z5: 5.97 µm,
    /// 14 bit; Nexus 6P, Sony IMX377: 1.55 µm, 10 bit; BFS-U3-200S6C, Sony IMX183: 2.4 µm, 12 bit;
    /// BFS-U3-16S2M, Sony IMX273: 3.45 µm, 12 bit). Table 5.2 gives σ in ADU at base gain and
    /// no conversion gain, so the presets assume 1 e⁻/ADU: the full well is the ADC's range
    /// above a 5 % black level (e.g. 15 564 e⁻ for 14 bits). That is an assumption, not a
    /// measurement.
    pub fn presets() -> Vec<SensorSpec> {
        vec![
            SensorSpec::table54(),
            table52(
                "nikon-z5",
                "Nikon Z5 (mirrorless), Table 5.2: σ 0.11/3.53, ISO 100–51200",
                5.97,
                14,
                (0.11, 3.53),
                512.0,
            ),
            table52(
                "nexus-6p",
                "Nexus 6P (smartphone), Table 5.2: σ 1.17/7.39, ISO 60–7656",
                1.55,
                10,
                (1.17, 7.39),
                7656.0 / 60.0,
            ),
            table52(
                "bfs-u3-200s6c",
                "FLIR BFS-U3-200S6C (machine vision), Table 5.2: σ 0.46/2.27, 0–27 dB",
                2.4,
                12,
                (0.46, 2.27),
                db(27.0),
            ),
            table52(
                "bfs-u3-16s2m",
                "FLIR BFS-U3-16S2M (machine vision, mono), Table 5.2: σ 0.52/4.55, 0–48 dB",
                3.45,
                12,
                (0.52, 4.55),
                db(48.0),
            ),
        ]
    }

    /// The preset called `name` (see [`PRESET_NAMES`]), case-insensitive.
    pub fn named(name: &str) -> Option<SensorSpec> {
        SensorSpec::presets()
            .into_iter()
            .find(|s| s.name.eq_ignore_ascii_case(name.trim()))
    }

    /// Area of one unit pixel, µm².
    pub fn unit_pixel_area_um2(&self) -> f64 {
        self.unit_pixel_um * self.unit_pixel_um
    }

    /// Checks every field; errors name it as `sensor.<field>`.
    ///
    /// # Errors
    /// [`SimError::InvalidSetting`] for the first bad field.
    pub fn validate(&self) -> Result<(), SimError> {
        let positive = |field: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(SimError::invalid(
                    format!("sensor.{field}"),
                    format!("must be a positive number (got {v:?})"),
                ))
            }
        };
        let non_negative = |field: &str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(SimError::invalid(
                    format!("sensor.{field}"),
                    format!("must be a finite number ≥ 0 (got {v:?})"),
                ))
            }
        };
        positive("unit_pixel_um", self.unit_pixel_um)?;
        positive("full_well_e", self.full_well_e)?;
        non_negative("sigma_pre_e", self.sigma_pre_e)?;
        non_negative("sigma_post_e", self.sigma_post_e)?;
        if !(self.max_gain.is_finite() && self.max_gain >= 1.0) {
            return Err(SimError::invalid(
                "sensor.max_gain",
                format!("must be ≥ 1, the base gain (got {:?})", self.max_gain),
            ));
        }
        if !(2..=24).contains(&self.adc_bits) {
            return Err(SimError::invalid(
                "sensor.adc_bits",
                format!("must be 2 … 24 bits (got {:?})", self.adc_bits),
            ));
        }
        if !(self.black_level_fraction.is_finite()
            && (0.0..0.5).contains(&self.black_level_fraction))
        {
            return Err(SimError::invalid(
                "sensor.black_level_fraction",
                format!(
                    "must be in [0, 0.5) of the ADC range (got {:?})",
                    self.black_level_fraction
                ),
            ));
        }
        Ok(())
    }
}
