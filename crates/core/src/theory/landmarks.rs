//! The landmarks a figure draws over the simulation to read it by, in the units the figures
//! use: the Airy disc's first dark ring, the diffraction orders of a period, and the period of
//! the MTF's repeating structure (units as conventions.md §0 gives them: λ in nm, f in mm,
//! lengths on the sensor in µm).

/// Spacing of the display's diffraction orders on the sensor, `λ f / T`, in µm
/// (λ in µm × f in µm / T in µm).
pub fn order_spacing_um(wavelength_nm: f64, focal_length_mm: f64, period_um: f64) -> f64 {
    (wavelength_nm * 1e-3) * (focal_length_mm * 1e3) / period_um
}

/// The light a double microlens array brings through a T-OLED over the bare display's,
/// `P / a = 1 / open_ratio`: the first array focuses a whole pixel's light through the slit
/// that passes only the open share otherwise (thesis §4.2, before the polariser).
pub fn mla_light_gain(open_ratio: f64) -> f64 {
    1.0 / open_ratio
}

/// Airy radius (first dark ring) `1.22 λ F#`, in µm.
pub fn airy_radius_um(wavelength_nm: f64, f_number: f64) -> f64 {
    1.22 * wavelength_nm * 1e-3 * f_number
}

/// Period of the MTF's repeating structure, `ν = T p / (λ f)` cycles/pixel: the display's
/// autocorrelation repeats every `T` in the pupil, i.e. every `T/(λf)` cycles/µm on the sensor.
pub fn mtf_repeat_cyc_per_px(
    period_um: f64,
    sensor_pixel_um: f64,
    wavelength_nm: f64,
    focal_length_mm: f64,
) -> f64 {
    period_um * sensor_pixel_um / ((wavelength_nm * 1e-3) * (focal_length_mm * 1e3))
}

/// `step, 2·step, …` up to and including `max`, at most `limit` of them (an empty list for a
/// non-positive or non-finite step).
pub fn multiples_up_to(step: f64, max: f64, limit: usize) -> Vec<f64> {
    if !(step > 0.0) || !step.is_finite() {
        return Vec::new();
    }
    (1..=limit)
        .map(|k| k as f64 * step)
        .take_while(|v| *v <= max * (1.0 + 1e-12))
        .collect()
}

/// The lattice of diffraction orders `(m·s, n·s)` within `±half_extent` in x and y, at most
/// `max_per_side` orders each way (so a tiny spacing cannot flood the plot).
pub fn order_lattice(spacing: f64, half_extent: f64, max_per_side: usize) -> Vec<[f64; 2]> {
    let pos = multiples_up_to(spacing, half_extent, max_per_side);
    let axis: Vec<f64> = pos
        .iter()
        .rev()
        .map(|v| -v)
        .chain(std::iter::once(0.0))
        .chain(pos.iter().copied())
        .collect();
    axis.iter()
        .flat_map(|y| axis.iter().map(move |x| [*x, *y]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diffraction_lattice_sits_at_multiples_of_lambda_f_over_t() {
        // iccp21 red: 610 nm, f = 10 mm, T = 168 µm → 36.31 µm.
        let s = order_spacing_um(610.0, 10.0, 168.0);
        assert!((s - 6100.0 / 168.0).abs() < 1e-9);
        let lattice = order_lattice(10.0, 25.0, 64);
        assert_eq!(lattice.len(), 25);
        assert!(lattice.contains(&[0.0, 0.0]));
        assert!(lattice.contains(&[-20.0, 10.0]));
        assert!(
            lattice
                .iter()
                .all(|p| p[0].abs() <= 25.0 && p[1].abs() <= 25.0)
        );
        assert_eq!(order_lattice(0.001, 1e6, 3).len(), 49);
        assert_eq!(order_lattice(0.0, 10.0, 3), vec![[0.0, 0.0]]);
        assert!((airy_radius_um(610.0, 2.5) - 1.8605).abs() < 1e-9);
    }

    #[test]
    fn mtf_repeat_period_and_its_multiples() {
        // T = 168 µm, p = 2 µm, λ = 610 nm, f = 10 mm → 336 / 6100 cycles/pixel.
        let nu = mtf_repeat_cyc_per_px(168.0, 2.0, 610.0, 10.0);
        assert!((nu - 336.0 / 6100.0).abs() < 1e-12);
        let m = multiples_up_to(0.2, 0.5, 100);
        assert_eq!(m.len(), 2);
        assert!((m[1] - 0.4).abs() < 1e-12);
        assert_eq!(multiples_up_to(0.25, 0.5, 100).len(), 2);
        assert!(multiples_up_to(f64::NAN, 0.5, 100).is_empty());
    }
}
