//! Light transmittance and the invertibility score (conventions.md §3, thesis eq. 3.9).

use ndarray::Array2;

/// ε of eq. 3.9.
pub const INVERTIBILITY_EPSILON: f64 = 0.015;
/// Fraction of the lowest `H` values averaged by `L_inv`.
pub const INVERTIBILITY_FRACTION: f64 = 0.3;

/// `H = |K|² / (|K|² + ε)` for every frequency of one channel (`power = |K|²`).
pub fn wiener_response(power: &Array2<f64>) -> impl Iterator<Item = f64> + '_ {
    power.iter().map(|p| p / (p + INVERTIBILITY_EPSILON))
}

/// Mean of the lowest 30 % of the `H` values pooled over all given channels.
pub fn mean_lowest_h<'a>(powers: impl IntoIterator<Item = &'a Array2<f64>>) -> f64 {
    let mut h: Vec<f64> = powers.into_iter().flat_map(wiener_response).collect();
    if h.is_empty() {
        return 0.0;
    }
    let k = ((INVERTIBILITY_FRACTION * h.len() as f64).floor() as usize).max(1);
    h.select_nth_unstable_by(k - 1, f64::total_cmp);
    h[..k].iter().sum::<f64>() / k as f64
}

/// `L_inv = −mean(lowest 30 % of H, pooled over the channels)`; more negative is better.
pub fn invertibility_loss<'a>(powers: impl IntoIterator<Item = &'a Array2<f64>>) -> f64 {
    -mean_lowest_h(powers)
}

/// LTR: `Σ|a|² / Σ|p|²` over the pupil.
pub fn ltr(field_energy: f64, pupil_samples: f64) -> f64 {
    if pupil_samples > 0.0 {
        field_energy / pupil_samples
    } else {
        0.0
    }
}

/// Intensity transmittance of one tile (the open fraction for binary cells), defined with the
/// opening it measures.
pub use crate::display::opening_ops::open_fraction;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perfect_blur_scores_almost_one() {
        let power = Array2::from_elem((4, 4), 1.0);
        let want = 1.0 / (1.0 + INVERTIBILITY_EPSILON);
        assert!((invertibility_loss([&power]) + want).abs() < 1e-12);
    }

    #[test]
    fn loss_averages_the_lowest_30_percent_pooled() {
        // 10 values per channel, 2 channels: the lowest 6 of 20.
        let a = Array2::from_shape_fn((2, 5), |(y, x)| (y * 5 + x) as f64);
        let b = Array2::from_elem((2, 5), 100.0);
        let mut h: Vec<f64> = (0..10)
            .map(|v| v as f64 / (v as f64 + INVERTIBILITY_EPSILON))
            .collect();
        h.sort_by(f64::total_cmp);
        let want = -h[..6].iter().sum::<f64>() / 6.0;
        assert!((invertibility_loss([&a, &b]) - want).abs() < 1e-12);
    }
}
