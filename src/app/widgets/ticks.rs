//! Axis ticks at 1-2-5 steps, about five labelled per axis whatever the range, so an axis never
//! shows only its "0" (egui_plot's default powers of ten label one tick on a ±600 µm axis).

use std::ops::RangeInclusive;

use egui_plot::{GridInput, GridMark, uniform_grid_spacer};

/// The 1-2-5 step nearest above `x` (> 0).
pub fn nice_step(x: f64) -> f64 {
    if !(x > 0.0) || !x.is_finite() {
        return 1.0;
    }
    let e = 10f64.powf(x.log10().floor());
    let m = x / e;
    let k = if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    };
    k * e
}

/// The three nested step sizes for the visible range: about six major ticks across it, the
/// middle step a round number too (0.5 → 0.1, never 0.025).
fn steps(input: GridInput) -> [f64; 3] {
    let range = (input.bounds.1 - input.bounds.0).abs();
    let major = nice_step(range / 6.0).max(input.base_step_size);
    let mantissa = major / 10f64.powf(major.log10().floor());
    let medium = if (mantissa - 5.0).abs() < 1e-9 {
        major / 5.0
    } else {
        major / 2.0
    };
    [major / 10.0, medium, major]
}

/// A tick's label with as many decimals as its step needs (0.05 → "0.05", 200 → "200").
pub fn tick_label(mark: GridMark, _range: &RangeInclusive<f64>) -> String {
    let decimals = (-mark.step_size.log10().floor()).clamp(0.0, 12.0) as usize;
    let v = if mark.value.abs() < mark.step_size * 1e-9 {
        0.0
    } else {
        mark.value
    };
    format!("{v:.decimals$}")
}

/// A grid spacer with labelled ticks at 1-2-5 steps.
pub fn ticks_125() -> impl Fn(GridInput) -> Vec<GridMark> {
    uniform_grid_spacer(steps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_one_two_five() {
        assert_eq!(nice_step(240.0), 500.0);
        assert_eq!(nice_step(160.0), 200.0);
        assert_eq!(nice_step(0.09), 0.1);
        assert_eq!(nice_step(1.0), 1.0);
        assert_eq!(nice_step(f64::NAN), 1.0);
        // A ±600 µm axis gets ticks 200 µm apart: five labels, not one.
        let s = steps(GridInput {
            bounds: (-600.0, 600.0),
            base_step_size: 1.0,
        });
        assert_eq!(s, [20.0, 100.0, 200.0]);
        let s = steps(GridInput {
            bounds: (0.0, 0.21),
            base_step_size: 1e-4,
        });
        assert_eq!(s, [0.005, 0.01, 0.05]);
        let mark = |value, step_size| GridMark { value, step_size };
        assert_eq!(tick_label(mark(0.15, 0.05), &(0.0..=1.0)), "0.15");
        assert_eq!(tick_label(mark(-400.0, 200.0), &(0.0..=1.0)), "-400");
        assert_eq!(tick_label(mark(-1e-17, 0.1), &(0.0..=1.0)), "0.0");
    }
}
