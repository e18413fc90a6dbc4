//! Fig. 5.3 as figure panels (`crate::figure`): (a) the contrast of a sinusoid through pixels
//! of one pitch against the noise times the SNR threshold, with the cutoff and Nyquist marked;
//! (b) the optimal pitch against the light, continuous and among the bin sizes. The studio draws
//! them; the numbers are [`super::pitch`]'s.

use super::pitch::{contrast_noise, cutoff_cyc_per_um, nyquist_cyc_per_um, optimal_pitch_curve};
use super::{BIN_SIZES, SensorSpec};
use crate::figure::{Annotation, Axis, Mark, Panel, Series, palette};

/// Frequencies sampled on panel (a), from 0 to the larger of `2/p` and 1 cycle/µm.
const FREQUENCY_SAMPLES: usize = 400;
/// Light levels sampled on panel (b), from 0.1 to 1000 e⁻/µm², even in log10.
const LIGHT_SAMPLES: usize = 80;
/// Candidate pitches of the continuous curve, 0.25 to 8 µm, even in log2.
const PITCH_CANDIDATES: usize = 48;

/// Fig. 5.3(a) at `light_e_per_um2` and `pitch_um` (gain 1): `|c(f)|` and `SNR_t σ` against the
/// frequency in cycles/µm, the cutoff and Nyquist `1/(2p)` marked.
pub fn contrast_panel(
    light_e_per_um2: f64,
    pitch_um: f64,
    sensor: &SensorSpec,
    snr_t: f64,
) -> Panel {
    let nyquist = nyquist_cyc_per_um(pitch_um);
    let f_max = (2.0 / pitch_um).max(1.0);
    let freqs: Vec<f64> = (0..=FREQUENCY_SAMPLES)
        .map(|k| f_max * k as f64 / FREQUENCY_SAMPLES as f64)
        .collect();
    let (contrast, noise) = contrast_noise(light_e_per_um2, pitch_um, sensor, 1.0, &freqs);
    let cutoff = cutoff_cyc_per_um(light_e_per_um2, pitch_um, sensor, 1.0, snr_t);
    let line = |name: String, i: usize, ys: Vec<f64>| Series {
        name,
        colour: palette::series(i),
        mark: Mark::Line,
        points: freqs.iter().zip(ys).map(|(f, y)| [*f, y.abs()]).collect(),
        band: None,
    };
    Panel {
        title: format!(
            "(a) contrast and noise at {light_e_per_um2:.1} e-/µm², pitch {pitch_um:.2} µm \
             (gain 1): cutoff {cutoff:.3} cycles/µm, Nyquist {nyquist:.3}"
        ),
        x: Axis::new("frequency", Some("cycles/µm")),
        y: Axis::new("electrons", None),
        series: vec![
            line("contrast |c|".into(), 0, contrast),
            line(
                format!("SNR_t x noise ({snr_t})"),
                1,
                noise.iter().map(|s| s * snr_t).collect(),
            ),
        ],
        annotations: vec![
            Annotation::VLine {
                x: nyquist,
                label: "Nyquist 1/(2p)".into(),
            },
            Annotation::VLine {
                x: cutoff,
                label: "cutoff".into(),
            },
        ],
        ..Panel::default()
    }
}

/// Fig. 5.3(b) for `sensor` (gain 1): the pitch with the highest cutoff against log10 of the
/// light, among continuous pitches and among the bin sizes (1, 2, 4, 8 unit pixels).
pub fn optimal_pitch_panel(sensor: &SensorSpec, snr_t: f64) -> Panel {
    let lights: Vec<f64> = (0..=LIGHT_SAMPLES)
        .map(|k| 10f64.powf(-1.0 + 4.0 * k as f64 / LIGHT_SAMPLES as f64))
        .collect();
    let candidates: Vec<f64> = (0..=PITCH_CANDIDATES)
        .map(|k| 0.25 * 2f64.powf(5.0 * k as f64 / PITCH_CANDIDATES as f64))
        .collect();
    let bins: Vec<f64> = BIN_SIZES
        .iter()
        .map(|b| *b as f64 * sensor.unit_pixel_um)
        .collect();
    let curve = |name: &str, i: usize, pitches: &[f64]| Series {
        name: name.into(),
        colour: palette::series(i),
        mark: Mark::Line,
        points: lights
            .iter()
            .zip(optimal_pitch_curve(&lights, pitches, sensor, 1.0, snr_t))
            .map(|(l, p)| [l.log10(), p])
            .collect(),
        band: None,
    };
    Panel {
        title: format!(
            "(b) optimal pitch vs light for {} (gain 1, SNR_t {snr_t}); x is log10(e-/µm²)",
            sensor.name
        ),
        x: Axis::new("log10 light", Some("e-/µm²")),
        y: Axis::new("pitch", Some("µm")),
        series: vec![
            curve("optimal pitch (continuous)", 0, &candidates),
            curve("optimal bin (1, 2, 4, 8 unit pixels)", 1, &bins),
        ],
        annotations: Vec::new(),
        ..Panel::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table54() -> SensorSpec {
        SensorSpec::named("table54").expect("the Table 5.4 sensor")
    }

    /// The cutoff marked on (a) is where the contrast meets the threshold line, and Nyquist is
    /// 1/(2p).
    #[test]
    fn the_contrast_panel_marks_where_contrast_meets_the_threshold() {
        let p = contrast_panel(50.0, 1.0, &table54(), 4.0);
        let [contrast, threshold] = &p.series[..] else {
            panic!("two series")
        };
        let Annotation::VLine { x: nyquist, .. } = p.annotations[0] else {
            panic!("Nyquist first")
        };
        let Annotation::VLine { x: cutoff, .. } = p.annotations[1] else {
            panic!("the cutoff second")
        };
        assert_eq!(nyquist, 0.5);
        assert!(cutoff > 0.0 && cutoff < 1.0, "{cutoff}");
        // Below the cutoff the contrast is above the threshold, just above it below.
        let at = |s: &Series, f: f64| {
            s.points
                .iter()
                .min_by(|a, b| (a[0] - f).abs().total_cmp(&(b[0] - f).abs()))
                .map_or(f64::NAN, |q| q[1])
        };
        assert!(at(contrast, 0.9 * cutoff) > at(threshold, 0.9 * cutoff));
        assert!(at(contrast, 1.1 * cutoff) < at(threshold, 1.1 * cutoff));
        assert_eq!(p.x.unit.as_deref(), Some("cycles/µm"));
    }

    /// More light, finer optimal pitch (Fig. 5.3b falls from left to right), and the bin curve
    /// only takes the bin sizes.
    #[test]
    fn the_optimal_pitch_falls_with_light_and_bins_are_the_bin_sizes() {
        let s = table54();
        let p = optimal_pitch_panel(&s, 4.0);
        let continuous = &p.series[0].points;
        let first = continuous.first().map_or(f64::NAN, |q| q[1]);
        let last = continuous.last().map_or(f64::NAN, |q| q[1]);
        assert!(first > last, "{first} → {last}");
        for q in &p.series[1].points {
            let in_px = q[1] / s.unit_pixel_um;
            assert!(
                BIN_SIZES.iter().any(|b| (*b as f64 - in_px).abs() < 1e-9),
                "{in_px}"
            );
        }
    }
}
